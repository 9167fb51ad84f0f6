//! Line charts: curves and markers on axes, phase planes at equal scales, sweep charts.

use super::*;

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
            equal_aspect: false,
            missing: None,
        },
    )
}

/// A phase plane `(x, x')`: as [`line_plot`] with the axis labels [`X_LABEL`] and
/// [`V_LABEL`] and equal scales on both axes (the shorter range is widened about its centre,
/// so a circle is drawn as a circle). Size 900x800.
pub fn phase_plot(
    path: &Path,
    title: &str,
    curves: &[Curve],
    markers: &[Marker],
) -> Result<(), PlotError> {
    line_chart(
        path,
        LineOpts {
            title,
            x_label: X_LABEL,
            y_label: V_LABEL,
            curves,
            markers,
            log_x: false,
            equal_aspect: true,
            missing: None,
        },
    )
}

/// A quantity against a swept parameter (e.g. the unstable cycle's size against `nu`).
///
/// Each curve is drawn as a line with a dot at every value (so a value between two gaps still
/// shows). The x values where no curve has a finite y (e.g. no cycle was located) are drawn as
/// hollow triangles on the bottom of the chart and listed in the legend as
/// `missing_label` with their count; if every value is missing, the chart holds only those
/// marks. Curves must share one set of x values only in the sense that "missing" is decided per
/// x value over all curves. Size 900x700.
pub fn sweep_chart(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    curves: &[Curve],
    log_x: bool,
    missing_label: &str,
) -> Result<(), PlotError> {
    for c in curves {
        check_curve(c)?;
    }
    let mut xs: Vec<f64> = curves
        .iter()
        .flat_map(|c| c.xs.iter().copied())
        .filter(|x| x.is_finite() && (!log_x || *x > 0.0))
        .collect();
    xs.sort_by(f64::total_cmp);
    xs.dedup();
    let missing: Vec<f64> = missing_values(curves, &xs);
    line_chart(
        path,
        LineOpts {
            title,
            x_label,
            y_label,
            curves,
            markers: &[],
            log_x,
            equal_aspect: false,
            missing: Some((&missing, missing_label)),
        },
    )
}

/// The values of `xs` at which no curve has a finite y.
pub(crate) fn missing_values(curves: &[Curve], xs: &[f64]) -> Vec<f64> {
    xs.iter()
        .copied()
        .filter(|&x| {
            !curves.iter().any(|c| {
                c.xs.iter()
                    .zip(&c.ys)
                    .any(|(&cx, &cy)| cx == x && cy.is_finite())
            })
        })
        .collect()
}

struct LineOpts<'p> {
    title: &'p str,
    x_label: &'p str,
    y_label: &'p str,
    curves: &'p [Curve],
    markers: &'p [Marker],
    log_x: bool,
    equal_aspect: bool,
    /// Sweep charts: the x values without data, and their legend label. Curves without any
    /// drawable point are then allowed.
    missing: Option<(&'p [f64], &'p str)>,
}

/// Layout of line charts: margin, label areas (pixels).
const LINE_MARGIN: u32 = 18;
const LINE_X_AREA: u32 = 70;
const LINE_Y_AREA: u32 = 95;

fn line_chart(path: &Path, o: LineOpts<'_>) -> Result<(), PlotError> {
    let log_x = o.log_x;
    let mut segs = Vec::with_capacity(o.curves.len());
    let (mut x_lo, mut x_hi) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut y_lo, mut y_hi) = (f64::INFINITY, f64::NEG_INFINITY);
    let mut extend_x = |x: f64| {
        x_lo = x_lo.min(x);
        x_hi = x_hi.max(x);
    };
    let mut ys_seen = Vec::new();
    for curve in o.curves {
        check_curve(curve)?;
        let s = segments(curve, log_x);
        if s.is_empty() && o.missing.is_none() {
            return Err(PlotError::NoDrawablePoint {
                label: curve.label.clone(),
            });
        }
        s.iter().flatten().for_each(|&(x, y)| {
            extend_x(x);
            ys_seen.push(y);
        });
        segs.push(s);
    }
    for m in o.markers.iter().filter(|m| marker_drawable(m, log_x)) {
        extend_x(m.x);
        ys_seen.push(m.y);
    }
    if let Some((missing, _)) = o.missing {
        missing.iter().for_each(|&x| extend_x(x));
    }
    for y in ys_seen {
        y_lo = y_lo.min(y);
        y_hi = y_hi.max(y);
    }
    if !x_lo.is_finite() {
        return Err(PlotError::EmptyData(
            "line plot without curves or drawable markers",
        ));
    }
    if !y_lo.is_finite() {
        // Only missing values: an empty y axis.
        (y_lo, y_hi) = (0.0, 1.0);
    }
    let all_points: Vec<(f64, f64)> = segs
        .iter()
        .flatten()
        .flatten()
        .copied()
        .chain(o.markers.iter().map(|m| (m.x, m.y)))
        .collect();
    let size = if o.equal_aspect {
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
        let mut y_range = padded(y_lo, y_hi, 0.05);
        if let Some((missing, _)) = o.missing
            && !missing.is_empty()
        {
            // Room below the data for the "missing" marks.
            let span = y_range.end - y_range.start;
            y_range.start -= 0.06 * span;
        }
        let plot = LinePlot {
            opts: &o,
            segs: &segs,
        };
        if log_x {
            let (a, b) = (x_lo.log10(), x_hi.log10());
            let r = padded(a, b, 0.05);
            let x_range = 10f64.powf(r.start)..10f64.powf(r.end);
            let pos = legend_corner(&all_points, &x_range, &y_range, true);
            plot.draw(&body, x_range.clone().log_scale(), x_range, y_range, pos)
        } else {
            let mut x_range = padded(x_lo, x_hi, 0.05);
            if o.equal_aspect {
                (x_range, y_range) = equal_aspect_ranges(x_range, y_range, pixels);
            }
            let pos = legend_corner(&all_points, &x_range, &y_range, false);
            plot.draw(&body, x_range.clone(), x_range, y_range, pos)
        }
    })
}

/// Picks the chart corner with the fewest data points for the legend.
fn legend_corner(
    points: &[(f64, f64)],
    xr: &Range<f64>,
    yr: &Range<f64>,
    log_x: bool,
) -> SeriesLabelPosition {
    let fx = |x: f64| {
        if log_x {
            (x.log10() - xr.start.log10()) / (xr.end.log10() - xr.start.log10())
        } else {
            (x - xr.start) / (xr.end - xr.start)
        }
    };
    let fy = |y: f64| (y - yr.start) / (yr.end - yr.start);
    // (position, x window, y window) in unit coordinates; the legend box is roughly this big.
    let corners = [
        (SeriesLabelPosition::UpperRight, 0.6..1.0, 0.7..1.0),
        (SeriesLabelPosition::UpperLeft, 0.0..0.4, 0.7..1.0),
        (SeriesLabelPosition::LowerRight, 0.6..1.0, 0.0..0.3),
        (SeriesLabelPosition::LowerLeft, 0.0..0.4, 0.0..0.3),
    ];
    let mut best = (SeriesLabelPosition::UpperRight, usize::MAX);
    for (pos, wx, wy) in corners {
        let n = points
            .iter()
            .filter(|&&(x, y)| wx.contains(&fx(x)) && wy.contains(&fy(y)))
            .count();
        if n < best.1 {
            best = (pos, n);
        }
    }
    best.0
}

struct LinePlot<'p> {
    opts: &'p LineOpts<'p>,
    segs: &'p [Vec<Vec<(f64, f64)>>],
}

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
        let o = self.opts;
        let mut chart = ChartBuilder::on(root)
            .margin(LINE_MARGIN)
            .x_label_area_size(LINE_X_AREA)
            .y_label_area_size(LINE_Y_AREA)
            .build_cartesian_2d(x_spec, y_range.clone())?;
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

        if log_x {
            // plotters' log key points can repeat a value (0.01 twice from rounding): draw
            // the ticks, grid lines and labels of `log_ticks` instead.
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
        }
        let mut any_label = false;
        let dots_on_lines = o.missing.is_some();
        for (curve, segs) in o.curves.iter().zip(self.segs) {
            let color = curve.color.color();
            let series = if curve.points_only {
                chart.draw_series(
                    segs.iter()
                        .flatten()
                        .map(|&p| Circle::new(p, 2, color.filled())),
                )?
            } else {
                if dots_on_lines {
                    chart.draw_series(
                        segs.iter()
                            .flatten()
                            .map(|&p| Circle::new(p, 4, color.filled())),
                    )?;
                }
                chart.draw_series(
                    segs.iter()
                        .map(|s| PathElement::new(s.clone(), color.stroke_width(2))),
                )?
            };
            if !curve.label.is_empty() {
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
        }
        if let Some((missing, label)) = o.missing
            && !missing.is_empty()
        {
            let y = y_range.start + 0.03 * y_span;
            let ink = MISSING.color();
            let series = chart.draw_series(missing.iter().map(|&x| {
                EmptyElement::at((x, y))
                    + Polygon::new(vec![(0, -7), (-7, 6), (7, 6)], WHITE.filled())
                    + PathElement::new(vec![(0, -7), (-7, 6), (7, 6), (0, -7)], ink.stroke_width(2))
            }))?;
            any_label = true;
            series
                .label(format!("{label} ({} values)", missing.len()))
                .legend(move |(x, y)| {
                    EmptyElement::at((x + 10, y))
                        + PathElement::new(
                            vec![(0, -7), (-7, 6), (7, 6), (0, -7)],
                            ink.stroke_width(2),
                        )
                });
        }
        for m in o.markers.iter().filter(|m| marker_drawable(m, log_x)) {
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
        if any_label {
            chart
                .configure_series_labels()
                .position(legend_pos)
                .margin(12)
                .label_font(font(17))
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .draw()?;
        }
        Ok(())
    }
}
