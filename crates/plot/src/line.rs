//! Line charts: curves and markers on axes, phase planes at equal scales, sweep charts.

use super::*;

mod sweep;

pub use sweep::{Gap, cycle_gaps, missing_values, sweep_chart};

/// Line plot with axes (tick values), axis labels, title and legend.
///
/// Used for friction curves (F/mg vs velocity); phase planes use [`phase_plot`] and sweeps
/// [`sweep_chart`]. `log_x` gives a logarithmic x axis; points with `x <= 0` are then
/// skipped. Axis ranges are the extent of all drawable points and markers plus a 5%
/// margin. Non-finite points are skipped (polylines are broken there); a curve with no drawable
/// point is an error, as is a call with neither curves nor drawable markers. The title may
/// have several lines (`\n`). Size 900x700.
pub fn line_plot(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    curves: &[Curve],
    markers: &[Marker],
    log_x: bool,
) -> Result<(), PlotError> {
    line_chart(
        path,
        LineOpts {
            title,
            x_label,
            y_label,
            curves,
            markers,
            log_x,
            aspect: None,
            gaps: None,
        },
    )
}

/// The unstable limit cycle `(xs, vs)` (one revolution; closed here) in its phase plane,
/// with the fixed point `fp` and the state at rest marked, titled with the model `p`; in
/// metres and m/s for a physical system (`si`: its units and its line of the title,
/// [`phase_plot_si`]).
pub fn cycle_plot(
    path: &Path,
    (xs, vs): (&[f64], &[f64]),
    fp: (f64, f64),
    p: &ModelParams,
    (scale, si): (StateScale, Option<(SiState, &str)>),
) -> Result<(), PlotError> {
    let close = |a: &[f64]| a.iter().chain(a.first()).copied().collect::<Vec<_>>();
    let curve = Curve {
        label: "unstable limit cycle".into(),
        xs: close(xs),
        ys: close(vs),
        color: CYCLE,
        points_only: false,
    };
    let marks = [
        Marker {
            label: "fixed point".into(),
            x: fp.0,
            y: fp.1,
            color: FIXED_POINT,
        },
        Marker {
            label: "rest (0, 0)".into(),
            x: 0.0,
            y: 0.0,
            color: STICK,
        },
    ];
    let title = phase_title("Unstable limit cycle", p);
    match si {
        Some((si, system)) => phase_plot_si(path, &(title + system), si, &[curve], &marks),
        None => phase_plot(path, &title, scale, &[curve], &marks),
    }
}

/// At most this many points of a trajectory are drawn ([`trajectory_plot`] decimates more).
pub const MAX_TRAJECTORY_POINTS: usize = 200_000;

/// One run's phase plane: its samples `(xs, vs)` from `t = 0` to `t_end` (at most
/// [`MAX_TRAJECTORY_POINTS`] of them drawn, evenly decimated, and the last), the start `ic`
/// and the fixed point `fp` marked, titled with the model `p`; in metres, m/s and seconds
/// for a physical system (`si`: its units and its line of the title, [`phase_plot_si`]).
pub fn trajectory_plot(
    path: &Path,
    (xs, vs): (&[f64], &[f64]),
    t_end: f64,
    (ic, fp): ((f64, f64), (f64, f64)),
    (p, si): (&ModelParams, Option<(SiState, &str)>),
) -> Result<(), PlotError> {
    let stride = xs.len().div_ceil(MAX_TRAJECTORY_POINTS).max(1);
    let (mut dx, mut dv): (Vec<f64>, Vec<f64>) = xs
        .iter()
        .zip(vs)
        .step_by(stride)
        .map(|(x, v)| (*x, *v))
        .unzip();
    if let (Some(x), Some(v)) = (xs.last(), vs.last()) {
        dx.push(*x);
        dv.push(*v);
    }
    // The numbers in the words, in SI units for a physical system.
    let (l, v, t, [lu, vu, tu]) = match si {
        Some((s, _)) => (s.length, s.velocity, s.time, [" m", " m/s", " s"]),
        None => (1.0, 1.0, 1.0, [""; 3]),
    };
    let title = phase_title(
        &format!(
            "Trajectory from (x0, x'0) = ({}{lu}, {}{vu})",
            fmt_number(ic.0 * l),
            fmt_number(ic.1 * v)
        ),
        p,
    ) + si.map_or("", |(_, system)| system);
    // (The model's numbers as before: in full.)
    let num = |x: f64, unit: f64| match si {
        Some(_) => fmt_number(x * unit),
        None => x.to_string(),
    };
    let curves = [Curve {
        label: format!("trajectory, t in [0, {}{tu}]", num(t_end, t)),
        xs: dx,
        ys: dv,
        color: Rgb(49, 110, 198),
        points_only: false,
    }];
    let markers = [
        Marker {
            label: format!("fixed point ({}{lu}, 0)", num(fp.0, l)),
            x: fp.0,
            y: fp.1,
            color: FIXED_POINT,
        },
        Marker {
            label: "start".to_string(),
            x: ic.0,
            y: ic.1,
            color: Rgb(238, 118, 22),
        },
    ];
    match si {
        Some((s, _)) => phase_plot_si(path, &title, s, &curves, &markers),
        None => phase_plot(path, &title, StateScale::of_law(&p.law), &curves, &markers),
    }
}

/// A phase plane `(x, x')`: as [`line_plot`] with the axis labels of `scale` (the law's
/// own units, [`StateScale::phase_labels`]) and equal scales on both axes (the shorter range
/// is widened about its centre, so a circle is drawn as a circle). Size 900x800.
pub fn phase_plot(
    path: &Path,
    title: &str,
    scale: StateScale,
    curves: &[Curve],
    markers: &[Marker],
) -> Result<(), PlotError> {
    let [x_label, y_label] = scale.phase_labels();
    line_chart(
        path,
        LineOpts {
            title,
            x_label,
            y_label,
            curves,
            markers,
            log_x: false,
            aspect: Some(1.0),
            gaps: None,
        },
    )
}

/// A phase plane of a physical system in SI units: the curves and markers (in the model's
/// units) drawn in metres and m/s ([`SiState::PHASE_LABELS`]), with one model unit of `x`
/// as long as one of `x'`, as [`phase_plot`] draws it (a circle of the model's units stays
/// a circle; metres against m/s at equal scales would squeeze it into a strip). Size 900x800.
pub fn phase_plot_si(
    path: &Path,
    title: &str,
    si: SiState,
    curves: &[Curve],
    markers: &[Marker],
) -> Result<(), PlotError> {
    let curves: Vec<Curve> = (curves.iter())
        .map(|c| Curve {
            xs: c.xs.iter().map(|x| x * si.length).collect(),
            ys: c.ys.iter().map(|v| v * si.velocity).collect(),
            ..c.clone()
        })
        .collect();
    let markers: Vec<Marker> = (markers.iter())
        .map(|m| Marker {
            x: m.x * si.length,
            y: m.y * si.velocity,
            ..m.clone()
        })
        .collect();
    let [x_label, y_label] = SiState::PHASE_LABELS;
    line_chart(
        path,
        LineOpts {
            title,
            x_label,
            y_label,
            curves: &curves,
            markers: &markers,
            log_x: false,
            aspect: Some(si.velocity / si.length),
            gaps: None,
        },
    )
}

struct LineOpts<'p> {
    title: &'p str,
    x_label: &'p str,
    y_label: &'p str,
    curves: &'p [Curve],
    markers: &'p [Marker],
    log_x: bool,
    /// Phase planes: `Some(r)` draws `r` units of y as long as one unit of x (1: equal
    /// scales; a physical system's `velocity / length` keeps its model units equal).
    aspect: Option<f64>,
    /// Sweep charts: the x values without data, by reason. Curves without any drawable point
    /// are then allowed.
    gaps: Option<&'p [Gap]>,
}

impl LineOpts<'_> {
    fn gap_xs(&self) -> impl Iterator<Item = f64> + '_ {
        self.gaps
            .into_iter()
            .flatten()
            .flat_map(|g| g.xs.iter().copied())
    }

    /// The legend's rows: labelled curves, gap groups with their counts, labelled markers.
    fn legend_labels(&self) -> Vec<String> {
        let curves = self.curves.iter().map(|c| c.label.clone());
        let gaps = self.gaps.into_iter().flatten().filter(|g| !g.xs.is_empty());
        let gaps = gaps.map(|g| format!("{} ({} values)", g.label, g.xs.len()));
        let markers = self
            .markers
            .iter()
            .filter(|m| marker_drawable(m, self.log_x));
        curves
            .chain(gaps)
            .chain(markers.map(|m| m.label.clone()))
            .filter(|l| !l.is_empty())
            .collect()
    }
}

/// Layout of line charts: margin, label areas (pixels).
const LINE_MARGIN: u32 = 18;
const LINE_X_AREA: u32 = 70;
const LINE_Y_AREA: u32 = 95;
/// Legend text size and its distance from the plot's edge (pixels).
const LEGEND_FONT: u32 = 17;
const LEGEND_MARGIN: u32 = 12;

/// The drawable data of a line chart: the curves' runs and the data's extent.
struct LineData {
    segs: Vec<Vec<Vec<(f64, f64)>>>,
    x: (f64, f64),
    y: (f64, f64),
}

impl LineData {
    fn of(o: &LineOpts<'_>) -> Result<LineData, PlotError> {
        let mut segs = Vec::with_capacity(o.curves.len());
        for curve in o.curves {
            check_curve(curve)?;
            let s = segments(curve, o.log_x);
            if s.is_empty() && o.gaps.is_none() {
                return Err(PlotError::NoDrawablePoint {
                    label: curve.label.clone(),
                });
            }
            segs.push(s);
        }
        let markers = o.markers.iter().filter(|m| marker_drawable(m, o.log_x));
        let points: Vec<(f64, f64)> = segs
            .iter()
            .flatten()
            .flatten()
            .copied()
            .chain(markers.map(|m| (m.x, m.y)))
            .collect();
        let xs = points.iter().map(|p| p.0).chain(o.gap_xs());
        let x = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        });
        if !x.0.is_finite() {
            return Err(PlotError::EmptyData(
                "line plot without curves or drawable markers",
            ));
        }
        let y = points
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                (a.min(p.1), b.max(p.1))
            });
        // Only missing values: an empty y axis.
        let y = if y.0.is_finite() { y } else { (0.0, 1.0) };
        // A log axis is drawn over the logarithms, always within range.
        if !o.log_x {
            crate::check_axis("x", x.0, x.1)?;
        }
        crate::check_axis("y", y.0, y.1)?;
        Ok(LineData { segs, x, y })
    }

    /// The axis ranges, with room at the bottom for gap marks and, where every corner of the
    /// plot holds data, room at the top for a legend of `legend` (fractions of the plotting
    /// area); and the corner for the legend.
    fn ranges(
        &self,
        o: &LineOpts<'_>,
        pixels: (u32, u32),
        legend: (f64, f64),
    ) -> (Range<f64>, Range<f64>, Corner) {
        let x_range = if o.log_x {
            let r = padded(self.x.0.log10(), self.x.1.log10(), 0.05);
            10f64.powf(r.start)..10f64.powf(r.end)
        } else {
            padded(self.x.0, self.x.1, 0.05)
        };
        let mut y_range = padded(self.y.0, self.y.1, 0.05);
        let gap_y = y_range.start;
        if o.gap_xs().next().is_some() {
            y_range.start -= 0.06 * (y_range.end - y_range.start);
        }
        let unit = |x: f64, y: f64| {
            let (a, b, v) = if o.log_x {
                (x_range.start.log10(), x_range.end.log10(), x.log10())
            } else {
                (x_range.start, x_range.end, x)
            };
            (
                (v - a) / (b - a),
                (y - y_range.start) / (y_range.end - y_range.start),
            )
        };
        let mut points = Vec::new();
        for run in self.segs.iter().flatten() {
            densify(
                &run.iter().map(|&(x, y)| unit(x, y)).collect::<Vec<_>>(),
                &mut points,
            );
        }
        points.extend(o.markers.iter().map(|m| unit(m.x, m.y)));
        points.extend(o.gap_xs().map(|x| unit(x, gap_y)));
        let (corner, stretch) = place_legend(&points, legend);
        y_range.end = y_range.start + stretch * (y_range.end - y_range.start);
        if let (Some(r), false) = (o.aspect, o.log_x) {
            let y = (y_range.start / r)..(y_range.end / r);
            let (x, y) = equal_aspect_ranges(x_range, y, pixels);
            return (x, (y.start * r)..(y.end * r), corner);
        }
        (x_range, y_range, corner)
    }
}

/// The points of a polyline in unit coordinates, at most 0.01 apart, appended to `out` (a
/// line crossing a corner counts there although its vertices lie outside).
pub(crate) fn densify(run: &[(f64, f64)], out: &mut Vec<(f64, f64)>) {
    out.extend(run.first());
    for w in run.windows(2) {
        let (a, b) = (w[0], w[1]);
        let d = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
        let n = (d / 0.01).ceil().clamp(1.0, 1e4) as usize;
        out.extend((1..=n).map(|k| {
            let t = k as f64 / n as f64;
            (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1))
        }));
    }
}

/// A corner of the plotting area for the legend.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Corner {
    UpperRight,
    UpperLeft,
    LowerRight,
    LowerLeft,
}

impl Corner {
    const ALL: [Corner; 4] = [
        Corner::UpperRight,
        Corner::UpperLeft,
        Corner::LowerRight,
        Corner::LowerLeft,
    ];

    /// The legend's box in unit coordinates for a legend of `(w, h)`.
    pub(crate) fn window(self, (w, h): (f64, f64)) -> (Range<f64>, Range<f64>) {
        let (right, left) = ((1.0 - w)..1.0, 0.0..w);
        let (top, bottom) = ((1.0 - h)..1.0, 0.0..h);
        match self {
            Corner::UpperRight => (right, top),
            Corner::UpperLeft => (left, top),
            Corner::LowerRight => (right, bottom),
            Corner::LowerLeft => (left, bottom),
        }
    }

    fn position(self) -> SeriesLabelPosition {
        match self {
            Corner::UpperRight => SeriesLabelPosition::UpperRight,
            Corner::UpperLeft => SeriesLabelPosition::UpperLeft,
            Corner::LowerRight => SeriesLabelPosition::LowerRight,
            Corner::LowerLeft => SeriesLabelPosition::LowerLeft,
        }
    }
}

/// Where a legend of `size` (fractions of the plotting area) covers none of `points` (unit
/// coordinates of the plot): a free corner if there is one, with `1.0`; otherwise an upper
/// corner and the factor by which the y range must grow upwards so that the data below it
/// stay clear. A legend taller than half the plot takes the corner with the fewest points.
pub(crate) fn place_legend(points: &[(f64, f64)], size: (f64, f64)) -> (Corner, f64) {
    let inside = |c: Corner| {
        let (wx, wy) = c.window(size);
        points
            .iter()
            .filter(|(x, y)| wx.contains(x) && wy.contains(y))
            .count()
    };
    let counts = Corner::ALL.map(|c| (c, inside(c)));
    if let Some(&(c, _)) = counts.iter().find(|(_, n)| *n == 0) {
        return (c, 1.0);
    }
    if size.1 >= 0.5 {
        let fewest = counts.iter().min_by_key(|(_, n)| *n);
        return (fewest.map_or(Corner::UpperRight, |c| c.0), 1.0);
    }
    // The data's top under each upper corner: stretched by top / (1 - h), it ends below
    // (a further 2% of the plot keeps a line off the legend's border).
    let stretch = |c: Corner| {
        let (wx, _) = c.window(size);
        let top = points
            .iter()
            .filter(|(x, _)| wx.contains(x))
            .fold(0.0f64, |t, p| t.max(p.1));
        (top / (1.0 - size.1 - 0.02)).max(1.0)
    };
    [Corner::UpperRight, Corner::UpperLeft]
        .map(|c| (c, stretch(c)))
        .into_iter()
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap_or((Corner::UpperRight, 1.0))
}

/// The legend's size as fractions of a plotting area of `pixels`: one row per label in the
/// legend font, as wide as the widest label plus its sample, and the margin to the edge.
fn legend_size(area: &Area<'_>, o: &LineOpts<'_>, pixels: (u32, u32)) -> (f64, f64) {
    let labels = o.legend_labels();
    if labels.is_empty() {
        return (0.0, 0.0);
    }
    let style = font(LEGEND_FONT);
    let text = labels
        .iter()
        .map(|l| area.estimate_text_size(l, &style).map_or(0, |s| s.0))
        .max()
        .unwrap_or(0);
    // plotters' series labels: about 23 px a row, the sample and padding about 50 px wide.
    let w = text + 50 + LEGEND_MARGIN;
    let h = 23 * labels.len() as u32 + 12 + LEGEND_MARGIN;
    (
        w as f64 / pixels.0.max(1) as f64,
        h as f64 / pixels.1.max(1) as f64,
    )
}

/// Most decades a logarithmic x axis may span; wider data are drawn on a linear axis, where
/// every point still shows. plotters' log axis counts its range's decades from the ratio of
/// its ends, which past about 308 decades overflows to inf, and its mesh loop then never ends:
/// `squeal scan` over `nu = [1e-300, 1e-3]` (297 decades, 327 with the 5% margins) hung in
/// drawing the cycle chart after its cells were done. 200 leaves room for the margins.
const MAX_LOG_DECADES: f64 = 200.0;

fn line_chart(path: &Path, o: LineOpts<'_>) -> Result<(), PlotError> {
    let mut o = o;
    let mut data = LineData::of(&o)?;
    if o.log_x && (data.x.1 / data.x.0).log10() > MAX_LOG_DECADES {
        o.log_x = false;
        data = LineData::of(&o)?;
    }
    let size = if o.aspect.is_some() {
        (900, 800)
    } else {
        (900, 700)
    };
    render(path, size, |root| {
        let body = draw_title(root, o.title, 24)?;
        let (w, h) = body.dim_in_pixel();
        let pixels = (
            w.saturating_sub(2 * LINE_MARGIN + LINE_Y_AREA),
            h.saturating_sub(2 * LINE_MARGIN + LINE_X_AREA),
        );
        let legend = legend_size(&body, &o, pixels);
        let (x_range, y_range, corner) = data.ranges(&o, pixels, legend);
        let plot = LinePlot {
            opts: &o,
            segs: &data.segs,
        };
        let pos = corner.position();
        if o.log_x {
            plot.draw(&body, x_range.clone().log_scale(), x_range, y_range, pos)
        } else {
            plot.draw(&body, x_range.clone(), x_range, y_range, pos)
        }
    })
}

struct LinePlot<'p> {
    opts: &'p LineOpts<'p>,
    segs: &'p [Vec<Vec<(f64, f64)>>],
}

type LineChart<'a, 'b, X> = ChartContext<'a, BitMapBackend<'b>, Cartesian2d<X, RangedCoordf64>>;

impl LinePlot<'_> {
    fn draw<X>(
        &self,
        root: &Area<'_>,
        x_spec: X,
        x_range: Range<f64>,
        y_range: Range<f64>,
        legend_pos: SeriesLabelPosition,
    ) -> DrawResult<()>
    where
        X: AsRangedCoord<Value = f64>,
        X::CoordDescType: ValueFormatter<f64>,
    {
        let mut chart = ChartBuilder::on(root)
            .margin(LINE_MARGIN)
            .x_label_area_size(LINE_X_AREA)
            .y_label_area_size(LINE_Y_AREA)
            .build_cartesian_2d(x_spec, y_range.clone())?;
        self.draw_axes(root, &mut chart, &x_range, &y_range)?;
        let mut any_label = self.draw_curves(&mut chart)?;
        any_label |= self.draw_gaps(&mut chart, &y_range)?;
        any_label |= self.draw_markers(&mut chart)?;
        if any_label {
            chart
                .configure_series_labels()
                .position(legend_pos)
                .margin(LEGEND_MARGIN)
                .label_font(font(LEGEND_FONT))
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .draw()?;
        }
        Ok(())
    }

    /// The mesh, tick labels and axis words; on a log axis the ticks of [`log_ticks`].
    fn draw_axes<X>(
        &self,
        root: &Area<'_>,
        chart: &mut LineChart<'_, '_, X>,
        x_range: &Range<f64>,
        y_range: &Range<f64>,
    ) -> DrawResult<()>
    where
        X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    {
        let o = self.opts;
        let x_span = x_range.end - x_range.start;
        let y_span = y_range.end - y_range.start;
        let log_x = o.log_x;
        // On a log axis plotters' own labels stay empty (see the ticks drawn below).
        let x_fmt = move |v: &f64| {
            if log_x {
                String::new()
            } else {
                fmt_linear(*v, x_span)
            }
        };
        let y_fmt = move |v: &f64| fmt_linear(*v, y_span);
        chart
            .configure_mesh()
            .x_desc(o.x_label)
            .y_desc(o.y_label)
            .axis_desc_style(font(20))
            .label_style(font(16))
            .x_labels(10)
            .y_labels(10)
            .x_label_formatter(&x_fmt)
            .y_label_formatter(&y_fmt)
            .light_line_style(RGBColor(240, 240, 240))
            .bold_line_style(RGBColor(215, 215, 215))
            .draw()?;
        if !log_x {
            return Ok(());
        }
        // plotters' log key points can repeat a value (0.01 twice from rounding): draw the
        // ticks, grid lines and labels of `log_ticks` instead.
        let ticks = log_ticks(x_range.start, x_range.end);
        chart.draw_series(ticks.iter().map(|&(v, _)| {
            PathElement::new(
                vec![(v, y_range.start), (v, y_range.end)],
                RGBColor(215, 215, 215),
            )
        }))?;
        let (bx, by) = root.get_base_pixel();
        let style = font(16).pos(plotters::style::text_anchor::Pos::new(
            plotters::style::text_anchor::HPos::Center,
            plotters::style::text_anchor::VPos::Top,
        ));
        for (v, text) in &ticks {
            let (px, py) = chart.backend_coord(&(*v, y_range.start));
            let (px, py) = (px - bx, py - by);
            root.draw(&PathElement::new(vec![(px, py), (px, py + 6)], BLACK))?;
            root.draw_text(text, &style, (px, py + 9))?;
        }
        Ok(())
    }

    /// The curves (sweep charts: with a dot at every value); true if one has a label.
    fn draw_curves<'a, 'b: 'a, X>(&self, chart: &mut LineChart<'a, 'b, X>) -> DrawResult<bool>
    where
        X: Ranged<ValueType = f64>,
    {
        let mut any_label = false;
        let dots_on_lines = self.opts.gaps.is_some();
        for (curve, segs) in self.opts.curves.iter().zip(self.segs) {
            let color = curve.color.color();
            let points = segs.iter().flatten();
            if curve.points_only || dots_on_lines {
                let r = if curve.points_only { 2 } else { 4 };
                chart.draw_series(points.map(|&p| Circle::new(p, r, color.filled())))?;
            }
            let lines = segs
                .iter()
                .filter(|_| !curve.points_only)
                .map(|s| PathElement::new(s.clone(), color.stroke_width(2)));
            let series = chart.draw_series(lines)?;
            if curve.label.is_empty() {
                continue;
            }
            any_label = true;
            let points_only = curve.points_only;
            series.label(curve.label.as_str()).legend(
                move |(x, y)| -> DynElement<'static, _, (i32, i32)> {
                    if points_only {
                        Circle::new((x + 10, y), 3, color.filled()).into_dyn()
                    } else {
                        PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                            .into_dyn()
                    }
                },
            );
        }
        Ok(any_label)
    }

    /// The gap marks along the bottom, one glyph per group; true if any was drawn.
    fn draw_gaps<'a, 'b: 'a, X>(
        &self,
        chart: &mut LineChart<'a, 'b, X>,
        y_range: &Range<f64>,
    ) -> DrawResult<bool>
    where
        X: Ranged<ValueType = f64>,
    {
        let y = y_range.start + 0.03 * (y_range.end - y_range.start);
        let mut any = false;
        for gap in self.opts.gaps.into_iter().flatten() {
            if gap.xs.is_empty() {
                continue;
            }
            any = true;
            let (glyph, color) = (gap.glyph, gap.color);
            let series =
                chart.draw_series(gap.xs.iter().map(|&x| glyph_element(glyph, color, (x, y))))?;
            series
                .label(format!("{} ({} values)", gap.label, gap.xs.len()))
                .legend(move |(x, y)| glyph_element(glyph, color, (x + 10, y)));
        }
        Ok(any)
    }

    /// The markers (cross in a circle); true if one has a label.
    fn draw_markers<'a, 'b: 'a, X>(&self, chart: &mut LineChart<'a, 'b, X>) -> DrawResult<bool>
    where
        X: Ranged<ValueType = f64>,
    {
        let mut any_label = false;
        let o = self.opts;
        for m in o.markers.iter().filter(|m| marker_drawable(m, o.log_x)) {
            let (color, r) = (m.color, 7);
            let series = chart.draw_series(
                marker_glyph(color, r)
                    .into_iter()
                    .map(|g| EmptyElement::at((m.x, m.y)) + g),
            )?;
            if !m.label.is_empty() {
                any_label = true;
                series.label(m.label.as_str()).legend(move |(x, y)| {
                    EmptyElement::at((x + 10, y))
                        + Circle::new((0, 0), 6, color.color())
                        + Cross::new((0, 0), 4, color.color())
                });
            }
        }
        Ok(any_label)
    }
}
