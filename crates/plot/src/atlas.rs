//! The atlas's stability chart: parameter-plane cells coloured by regime, contours of a
//! scalar field (the basin fraction), and boundary curves (the fold and critical damping).

use std::path::Path;

use plotters::prelude::*;

use super::{
    Area, Curve, DrawResult, Glyph, Plane, PlotError, Rgb, bold, check_curve, fmt_sig, font,
    glyph_element, render,
};
use crate::legend::{LegendItem, draw_legend};

/// A stability chart over two parameters.
///
/// `classes` and `field` are row-major with shape `(ys.len(), xs.len())`: entry
/// `j * xs.len() + i` is the point `(xs[i], ys[j])`. Coordinates are cell centres, strictly
/// monotone; with `log_x`/`log_y` the axis is logarithmic (values must be > 0).
#[derive(Clone, Debug)]
pub struct StabilityChart<'a> {
    /// Title (first line).
    pub title: String,
    /// Second line under the title (smaller).
    pub subtitle: String,
    /// Horizontal axis words and units.
    pub x_label: String,
    /// Vertical axis words and units.
    pub y_label: String,
    /// Cell centres along x.
    pub xs: &'a [f64],
    /// Cell centres along y.
    pub ys: &'a [f64],
    /// Logarithmic x axis.
    pub log_x: bool,
    /// Logarithmic y axis.
    pub log_y: bool,
    /// Class of each cell (looked up in `palette`).
    pub classes: &'a [u8],
    /// (value, name, colour) of the classes, in legend order.
    pub palette: Vec<(u8, &'a str, Rgb)>,
    /// A scalar field to contour (NaN: no value).
    pub field: Option<&'a [f64]>,
    /// Contour levels of `field`.
    pub levels: Vec<f64>,
    /// Name of the field in the legend.
    pub field_name: String,
    /// Curves on top (in data coordinates; NaN breaks a curve).
    pub curves: Vec<Curve>,
    /// Curves drawn dashed on top of `curves`: a line that can lie exactly on one of them
    /// (the fold on the critical line under true stick) shows with the other between its
    /// dashes.
    pub dashed: Vec<Curve>,
    /// Flagged points on top of the curves, each set with its own glyph.
    pub marks: Vec<Marks>,
}

/// Flagged points of a [`StabilityChart`] (e.g. fold values whose bracket moves at dt/2),
/// drawn as a glyph filled with `fill` and outlined in black, never joined: a shape, not a
/// line, so they cannot be mistaken for a boundary curve.
#[derive(Clone, Debug)]
pub struct Marks {
    /// Legend label.
    pub label: String,
    /// x coordinates (NaN: no mark).
    pub xs: Vec<f64>,
    /// y coordinates, as many as `xs`.
    pub ys: Vec<f64>,
    /// The shape.
    pub glyph: Glyph,
    /// The fill colour.
    pub fill: Rgb,
}

/// Formats a value with about four significant digits (titles, legends).
pub fn fmt_value(v: f64) -> String {
    fmt_sig(v)
}

fn edges(c: &[f64]) -> Vec<f64> {
    let n = c.len();
    if n == 1 {
        return vec![c[0] - 0.5, c[0] + 0.5];
    }
    let mut e = Vec::with_capacity(n + 1);
    e.push(c[0] - 0.5 * (c[1] - c[0]));
    for w in c.windows(2) {
        e.push(0.5 * (w[0] + w[1]));
    }
    e.push(c[n - 1] + 0.5 * (c[n - 1] - c[n - 2]));
    e
}

/// Tick values for a log axis over `[lo, hi]` (lo > 0): 1, 2, 5 x 10^k (also 3 for spans
/// under two decades; only 10^k over more than four).
pub fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let (a, b) = (lo.min(hi), lo.max(hi));
    let decades = (b / a).log10();
    let mults: &[f64] = if decades > 4.0 {
        &[1.0]
    } else if decades > 2.0 {
        &[1.0, 2.0, 5.0]
    } else {
        &[1.0, 2.0, 3.0, 5.0]
    };
    let mut out = Vec::new();
    for k in a.log10().floor() as i32..=b.log10().ceil() as i32 {
        for m in mults {
            let v = m * 10f64.powi(k);
            if v >= a * (1.0 - 1e-12) && v <= b * (1.0 + 1e-12) {
                out.push(v);
            }
        }
    }
    out
}

/// Marching squares: the segments of `f = level` on the grid `(us, vs)` (cell corners at
/// the grid points), skipping squares with a NaN corner.
pub fn contour_segments(us: &[f64], vs: &[f64], f: &[f64], level: f64) -> Vec<[(f64, f64); 2]> {
    let nx = us.len();
    let mut out = Vec::new();
    if nx < 2 || vs.len() < 2 {
        return out;
    }
    for j in 0..vs.len() - 1 {
        for i in 0..nx - 1 {
            let c = [
                (us[i], vs[j], f[j * nx + i]),
                (us[i + 1], vs[j], f[j * nx + i + 1]),
                (us[i + 1], vs[j + 1], f[(j + 1) * nx + i + 1]),
                (us[i], vs[j + 1], f[(j + 1) * nx + i]),
            ];
            if c.iter().any(|p| p.2.is_nan()) {
                continue;
            }
            let mut pts = Vec::with_capacity(4);
            for k in 0..4 {
                let (a, b) = (c[k], c[(k + 1) % 4]);
                let (da, db) = (a.2 - level, b.2 - level);
                if (da < 0.0) != (db < 0.0) {
                    let t = da / (da - db);
                    pts.push((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)));
                }
            }
            if pts.len() >= 2 {
                out.push([pts[0], pts[1]]);
            }
            if pts.len() == 4 {
                out.push([pts[2], pts[3]]);
            }
        }
    }
    out
}

/// Draws a stability chart to `path` (1300 x 900).
pub fn stability_chart(path: &Path, chart: &StabilityChart<'_>) -> Result<(), PlotError> {
    check_chart(chart)?;
    let (nx, ny) = (chart.xs.len(), chart.ys.len());
    let tx = |x: f64| if chart.log_x { x.log10() } else { x };
    let ty = |y: f64| if chart.log_y { y.log10() } else { y };
    let us: Vec<f64> = chart.xs.iter().map(|&x| tx(x)).collect();
    let vs: Vec<f64> = chart.ys.iter().map(|&y| ty(y)).collect();
    let (ue, ve) = (edges(&us), edges(&vs));
    let xr = ue[0].min(ue[nx])..ue[0].max(ue[nx]);
    let yr = ve[0].min(ve[ny])..ve[0].max(ve[ny]);
    crate::check_axis("x", xr.start, xr.end)?;
    crate::check_axis("y", yr.start, yr.end)?;
    render(path, (1300, 900), |root| {
        // A title wider than the picture (every fixed parameter of a physical system) wraps
        // after a comma onto a second line.
        let (w, _) = root.dim_in_pixel();
        let title = super::wrap_line(root, &chart.title, &bold(22), w.saturating_sub(40));
        let (head, body) = root.split_vertically(54 + 28 * title.len() as u32);
        for (i, line) in title.iter().enumerate() {
            head.draw_text(line, &bold(22), (20, 12 + 28 * i as i32))?;
        }
        head.draw_text(
            &chart.subtitle,
            &font(16),
            (20, 18 + 28 * title.len() as i32),
        )?;
        let (plot, legend) = body.split_horizontally(900);
        draw_plot(&plot, chart, (&us, &vs), (&ue, &ve), (xr, yr))?;
        draw_legend(&legend, "regime", &legend_items(chart))
    })
}

/// A chart's data checked before drawing: the shapes of classes, field and marks, the curves,
/// and finite coordinates (> 0 on a log axis).
fn check_chart(chart: &StabilityChart<'_>) -> Result<(), PlotError> {
    let (nx, ny) = (chart.xs.len(), chart.ys.len());
    if nx == 0 || ny == 0 {
        return Err(PlotError::EmptyData("stability chart without points"));
    }
    if chart.classes.len() != nx * ny {
        return Err(PlotError::ShapeMismatch {
            what: "stability chart classes (ys.len() rows x xs.len() columns)".into(),
            expected: nx * ny,
            found: chart.classes.len(),
        });
    }
    if let Some(f) = chart.field {
        if f.len() != nx * ny {
            return Err(PlotError::ShapeMismatch {
                what: "stability chart field".into(),
                expected: nx * ny,
                found: f.len(),
            });
        }
    }
    for c in chart.curves.iter().chain(&chart.dashed) {
        check_curve(c)?;
    }
    for m in &chart.marks {
        if m.xs.len() != m.ys.len() {
            return Err(PlotError::ShapeMismatch {
                what: format!("marks {:?}: ys vs xs", m.label),
                expected: m.xs.len(),
                found: m.ys.len(),
            });
        }
    }
    for (name, v, log) in [("xs", chart.xs, chart.log_x), ("ys", chart.ys, chart.log_y)] {
        if v.iter().any(|x| !x.is_finite() || (log && *x <= 0.0)) {
            return Err(PlotError::InvalidGrid(format!(
                "{name}: non-finite value, or <= 0 on a log axis"
            )));
        }
    }
    Ok(())
}

/// Whether any contour of the field is drawn: a level crossed between four neighbouring
/// values somewhere (the segments do not depend on the axes' scale).
fn contours_drawn(chart: &StabilityChart<'_>) -> bool {
    chart.field.is_some_and(|f| {
        (chart.levels.iter()).any(|&l| !contour_segments(chart.xs, chart.ys, f, l).is_empty())
    })
}

/// The legend: the classes present (with their counts), the curves, the marks drawn and the
/// field's contours.
fn legend_items(chart: &StabilityChart<'_>) -> Vec<LegendItem> {
    let mut items = Vec::new();
    let total = chart.classes.len();
    for &(value, name, color) in &chart.palette {
        let n = chart.classes.iter().filter(|&&c| c == value).count();
        if n > 0 {
            items.push(LegendItem::Swatch {
                name: name.to_string(),
                color,
                detail: Some(format!("{n} of {total} points")),
            });
        }
    }
    for c in &chart.curves {
        items.push(LegendItem::Line {
            name: c.label.clone(),
            color: c.color,
            dots: c.points_only,
        });
    }
    for c in &chart.dashed {
        items.push(LegendItem::Dashed {
            name: c.label.clone(),
            color: c.color,
        });
    }
    for m in chart
        .marks
        .iter()
        .filter(|m| m.xs.iter().any(|x| x.is_finite()))
    {
        items.push(LegendItem::Glyph {
            name: m.label.clone(),
            glyph: m.glyph,
            fill: m.fill,
        });
    }
    if contours_drawn(chart) {
        items.push(LegendItem::Line {
            name: "white lines, labelled:".into(),
            color: Rgb(255, 255, 255),
            dots: false,
        });
        items.push(LegendItem::Line {
            name: chart.field_name.clone(),
            color: Rgb(255, 255, 255),
            dots: false,
        });
    }
    items
}

fn draw_plot(
    area: &Area<'_>,
    chart: &StabilityChart<'_>,
    (us, vs): (&[f64], &[f64]),
    (ue, ve): (&[f64], &[f64]),
    (xr, yr): (std::ops::Range<f64>, std::ops::Range<f64>),
) -> DrawResult<()> {
    let mut c = ChartBuilder::on(area)
        .margin(14)
        .x_label_area_size(60)
        .y_label_area_size(90)
        .build_cartesian_2d(xr.clone(), yr.clone())?;
    let (lx, ly) = (chart.log_x, chart.log_y);
    let fx = move |u: &f64| fmt_sig(*u);
    let fy = move |v: &f64| fmt_sig(*v);
    // Log axes get their ticks drawn below (at 1, 2, 5 x 10^k); plotters labels linear ones.
    c.configure_mesh()
        .disable_mesh()
        .x_desc(chart.x_label.as_str())
        .y_desc(chart.y_label.as_str())
        .axis_desc_style(font(20))
        .label_style(font(15))
        .x_labels(if lx { 0 } else { 10 })
        .y_labels(if ly { 0 } else { 10 })
        .x_label_formatter(&fx)
        .y_label_formatter(&fy)
        .draw()?;
    draw_cells(&mut c, chart, (ue, ve))?;
    if let Some(f) = chart.field {
        let mid = (0.5 * (xr.start + xr.end), 0.5 * (yr.start + yr.end));
        draw_contours(&mut c, chart, (us, vs, f), mid)?;
    }
    draw_curves(&mut c, chart, &chart.curves, false)?;
    draw_curves(&mut c, chart, &chart.dashed, true)?;
    draw_marks(&mut c, chart)?;
    draw_log_ticks(area, &c, chart, (xr, yr))
}

/// Each point's cell (between the edges `ue`, `ve`) filled in its class's colour.
fn draw_cells(
    c: &mut Plane,
    chart: &StabilityChart<'_>,
    (ue, ve): (&[f64], &[f64]),
) -> DrawResult<()> {
    let nx = chart.xs.len();
    let color_of = |v: u8| {
        chart
            .palette
            .iter()
            .find(|p| p.0 == v)
            .map_or(super::OTHER, |p| p.2)
    };
    c.draw_series((0..chart.classes.len()).map(|k| {
        let (i, j) = (k % nx, k / nx);
        let Rgb(r, g, b) = color_of(chart.classes[k]);
        Rectangle::new(
            [(ue[i], ve[j]), (ue[i + 1], ve[j + 1])],
            RGBColor(r, g, b).filled(),
        )
    }))?;
    Ok(())
}

/// The white contours of the field `f` on the grid `(us, vs)`, each level labelled once, at
/// its segment nearest the chart's middle `mid`.
fn draw_contours(
    c: &mut Plane,
    chart: &StabilityChart<'_>,
    (us, vs, f): (&[f64], &[f64], &[f64]),
    mid: (f64, f64),
) -> DrawResult<()> {
    for &level in &chart.levels {
        let segs = contour_segments(us, vs, f, level);
        c.draw_series(
            segs.iter()
                .map(|s| PathElement::new(s.to_vec(), WHITE.stroke_width(2))),
        )?;
        if let Some(s) = segs.iter().min_by(|a, b| {
            let d = |s: &[(f64, f64); 2]| (s[0].0 - mid.0).powi(2) + (s[0].1 - mid.1).powi(2);
            d(a).total_cmp(&d(b))
        }) {
            c.draw_series(std::iter::once(Text::new(
                fmt_sig(level),
                s[0],
                font(14).color(&BLACK),
            )))?;
        }
    }
    Ok(())
}

/// Whether `(x, y)` can be drawn: finite, and > 0 on a log axis.
fn drawable(chart: &StabilityChart<'_>, x: f64, y: f64) -> bool {
    x.is_finite() && y.is_finite() && (!chart.log_x || x > 0.0) && (!chart.log_y || y > 0.0)
}

/// A point in the plane's coordinates (log10 on a log axis).
fn to_plane(chart: &StabilityChart<'_>, x: f64, y: f64) -> (f64, f64) {
    (
        if chart.log_x { x.log10() } else { x },
        if chart.log_y { y.log10() } else { y },
    )
}

/// The boundary curves `curves` (`dashed` or not), each broken where a point cannot be
/// drawn: a line per run of drawable points, a dot for a run of one.
fn draw_curves(
    c: &mut Plane,
    chart: &StabilityChart<'_>,
    curves: &[Curve],
    dashed: bool,
) -> DrawResult<()> {
    for curve in curves {
        let color = RGBColor(curve.color.0, curve.color.1, curve.color.2);
        let mut run: Vec<(f64, f64)> = Vec::new();
        let mut runs = Vec::new();
        for (&x, &y) in curve.xs.iter().zip(&curve.ys) {
            if drawable(chart, x, y) {
                run.push(to_plane(chart, x, y));
            } else if !run.is_empty() {
                runs.push(std::mem::take(&mut run));
            }
        }
        if !run.is_empty() {
            runs.push(run);
        }
        for r in runs {
            if r.len() == 1 {
                c.draw_series(std::iter::once(Circle::new(r[0], 4, color.filled())))?;
            } else if dashed {
                let dashes =
                    plotters::element::DashedPathElement::new(r, 12, 8, color.stroke_width(3));
                c.draw_series(std::iter::once(dashes))?;
            } else {
                c.draw_series(std::iter::once(PathElement::new(r, color.stroke_width(3))))?;
            }
        }
    }
    Ok(())
}

/// The flagged points, each set in its glyph.
fn draw_marks(c: &mut Plane, chart: &StabilityChart<'_>) -> DrawResult<()> {
    for m in &chart.marks {
        let points =
            m.xs.iter()
                .zip(&m.ys)
                .filter(|(x, y)| drawable(chart, **x, **y));
        c.draw_series(
            points.map(|(&x, &y)| glyph_element(m.glyph, m.fill, to_plane(chart, x, y))),
        )?;
    }
    Ok(())
}

/// The ticks and labels of the log axes (at 1, 2, 5 x 10^k), drawn on `area` beside the
/// plane `c` spanning `(xr, yr)`.
fn draw_log_ticks(
    area: &Area<'_>,
    c: &Plane,
    chart: &StabilityChart<'_>,
    (xr, yr): (std::ops::Range<f64>, std::ops::Range<f64>),
) -> DrawResult<()> {
    let (bx, by) = area.get_base_pixel();
    let at = |u: f64, v: f64| {
        let p = c.backend_coord(&(u, v));
        (p.0 - bx, p.1 - by)
    };
    if chart.log_x {
        for t in log_ticks(10f64.powf(xr.start), 10f64.powf(xr.end)) {
            let p = at(t.log10(), yr.start);
            area.draw(&PathElement::new(vec![p, (p.0, p.1 + 6)], BLACK))?;
            let text = fmt_sig(t);
            let w = 4 * text.len() as i32;
            area.draw_text(&text, &font(15), (p.0 - w, p.1 + 10))?;
        }
    }
    if chart.log_y {
        for t in log_ticks(10f64.powf(yr.start), 10f64.powf(yr.end)) {
            let p = at(xr.start, t.log10());
            area.draw(&PathElement::new(vec![p, (p.0 - 6, p.1)], BLACK))?;
            let text = fmt_sig(t);
            let w = 9 * text.len() as i32;
            area.draw_text(&text, &font(15), (p.0 - 10 - w, p.1 - 8))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_ticks_are_round() {
        assert_eq!(log_ticks(0.5, 6.0), vec![0.5, 1.0, 2.0, 3.0, 5.0]);
        assert_eq!(
            log_ticks(1e-4, 0.1),
            vec![1e-4, 2e-4, 5e-4, 1e-3, 2e-3, 5e-3, 0.01, 0.02, 0.05, 0.1]
        );
    }

    #[test]
    fn contour_of_a_plane_is_a_straight_line() {
        // f = u on a 3 x 3 grid: the level 0.5 is the vertical line u = 0.5.
        let us = [0.0, 1.0, 2.0];
        let vs = [0.0, 1.0, 2.0];
        let f: Vec<f64> = (0..9).map(|k| us[k % 3]).collect();
        let segs = contour_segments(&us, &vs, &f, 0.5);
        assert_eq!(segs.len(), 2);
        for s in segs {
            assert!((s[0].0 - 0.5).abs() < 1e-15 && (s[1].0 - 0.5).abs() < 1e-15);
        }
    }

    #[test]
    fn draws_a_small_chart() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("c.png");
        let xs = [1.0, 2.0, 4.0];
        let ys = [0.1, 0.2];
        let chart = StabilityChart {
            title: "t".into(),
            subtitle: "s".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            xs: &xs,
            ys: &ys,
            log_x: true,
            log_y: false,
            classes: &[1, 2, 3, 1, 2, 3],
            palette: vec![(1, "a", Rgb(1, 2, 3)), (2, "b", Rgb(200, 2, 3))],
            field: Some(&[0.0, 0.5, 1.0, 0.0, 0.5, 1.0]),
            levels: vec![0.25],
            field_name: "f".into(),
            curves: vec![],
            dashed: vec![],
            marks: vec![],
        };
        stability_chart(&p, &chart).unwrap();
        assert!(std::fs::metadata(&p).unwrap().len() > 1000);
        let bad = StabilityChart {
            classes: &[1, 2],
            ..chart
        };
        assert!(matches!(
            stability_chart(&p, &bad),
            Err(PlotError::ShapeMismatch { .. })
        ));
    }

    /// The names of a legend's rows.
    fn names(items: &[LegendItem]) -> Vec<String> {
        items
            .iter()
            .map(|i| match i {
                LegendItem::Swatch { name, .. }
                | LegendItem::Line { name, .. }
                | LegendItem::Dashed { name, .. }
                | LegendItem::Marker { name, .. }
                | LegendItem::Glyph { name, .. } => name.clone(),
            })
            .collect()
    }

    /// The legend listed "white lines, labelled: basin fraction" wherever a field was given,
    /// though no contour is drawn where the field has no level crossing between four
    /// neighbouring values (an atlas's bistable points alone carry it). The legend's rows are
    /// what is drawn: the contours' only where a segment of them is.
    #[test]
    fn the_legend_lists_the_contours_only_where_drawn() {
        let (xs, ys) = ([1.0, 2.0, 4.0], [0.1, 0.2]);
        let nan = f64::NAN;
        // Bistable points apart: no 2 x 2 block of values, so no segment at any level.
        let apart = [0.3, nan, 0.6, nan, 0.8, nan];
        let crossing = [0.0, 0.5, 1.0, 0.0, 0.5, 1.0];
        let chart = |field| StabilityChart {
            title: "t".into(),
            subtitle: "s".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            xs: &xs,
            ys: &ys,
            log_x: false,
            log_y: false,
            classes: &[1; 6],
            palette: vec![(1, "a", Rgb(1, 2, 3))],
            field: Some(field),
            levels: vec![0.25, 0.5],
            field_name: "basin fraction".into(),
            curves: vec![],
            dashed: vec![],
            marks: vec![],
        };
        assert!(contour_segments(&xs, &ys, &apart, 0.5).is_empty());
        let rows = names(&legend_items(&chart(&apart)));
        assert_eq!(rows, ["a"], "no contour drawn, none listed");
        assert!(!contour_segments(&xs, &ys, &crossing, 0.5).is_empty());
        let rows = names(&legend_items(&chart(&crossing)));
        assert!(
            rows.iter().any(|r| r.contains("basin fraction")),
            "{rows:?}"
        );
    }
}
