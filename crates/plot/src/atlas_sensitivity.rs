//! The atlas's picture of final-state sensitivity, `<name>-sensitivity.png`
//! ([`squeal_scan::sensitivity`]): per point with a basin map, the boundary basin entropy
//! `S_bb` against ln 2 with the log 2 test's verdict, and the share of starts near the
//! boundary whose fate moves when the step halves against 1%. Over one swept parameter:
//! stacked panels against it (and the uncertainty exponent where it was fitted); over two:
//! side-by-side panels of coloured markers over the parameter plane. Points without a
//! complete map, or not measured, are left out.

use std::f64::consts::LN_2;
use std::ops::Range;
use std::path::{Path, PathBuf};

use plotters::coord::ranged1d::Ranged;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use squeal_scan::atlas::{AtlasPlan, ParamAxis};
use squeal_scan::sensitivity::{ENTROPY_BOX, Log2Test, SENSITIVITY_FIELDS, STEP_SHARE_SMALL};

use crate::atlas_sheet::{axis_label, is_log, title};
use crate::legend::{LegendItem, draw_legend};
// The colour scale (dark to light: low to high).
use crate::viridis as ramp;
use crate::{
    Area, DrawResult, Glyph, Plane, PlotError, Rgb, bold, fmt_sig, font, glyph_element, render,
};

/// The picture of final-state sensitivity beside an atlas chart `png`:
/// `<stem>-sensitivity.png`.
pub fn sensitivity_path(png: &Path) -> PathBuf {
    let stem = png
        .file_stem()
        .map_or("atlas".into(), |s| s.to_string_lossy());
    png.with_file_name(format!("{stem}-sensitivity.png"))
}

/// Whether an atlas of `plan` has a picture of final-state sensitivity: basin maps over
/// one or two swept parameters (it is drawn where some point was measured).
pub fn has_sensitivity(plan: &AtlasPlan) -> bool {
    plan.maps.is_some() && matches!(plan.space.axes().len(), 1 | 2)
}

/// Draws the final-state sensitivity of an atlas's maps to `png`: `values` holds per point
/// (C order over the swept axes) the figures of [`SENSITIVITY_FIELDS`] in their order (an
/// atlas file's `map_` datasets; NaN: no complete map, or not measured), `log2_test` the
/// log 2 test's verdict per point (`None`: no complete map). Returns whether it drew:
/// nothing is written where no point has a measured figure, or without one or two swept
/// parameters ([`has_sensitivity`]).
pub fn atlas_sensitivity(
    plan: &AtlasPlan,
    values: &[Vec<f64>],
    log2_test: &[Option<Log2Test>],
    png: &Path,
) -> Result<bool, PlotError> {
    let n = plan.space.n_points();
    for (what, found) in [
        ("sensitivity figures (one list per point)", values.len()),
        ("log 2 test verdicts (one per point)", log2_test.len()),
    ] {
        if found != n {
            let what = what.to_string();
            return Err(PlotError::ShapeMismatch {
                what,
                expected: n,
                found,
            });
        }
    }
    let f = Figures::of(values, log2_test);
    if !has_sensitivity(plan) || !f.measured() {
        return Ok(false);
    }
    match plan.space.axes()[..] {
        [a] => column(plan, a, &f, png)?,
        [y, x] => chart(plan, (&Axis::of(x), &Axis::of(y)), &f, png)?,
        _ => return Ok(false),
    }
    Ok(true)
}

/// The figures drawn, per point (NaN: no complete map, or not measured).
struct Figures {
    sbb: Vec<f64>,
    verdict: Vec<Option<Log2Test>>,
    /// The step sensitivity and its standard error, in percent.
    step: Vec<f64>,
    step_se: Vec<f64>,
    alpha: Vec<f64>,
    alpha_se: Vec<f64>,
    /// The most starts sampled near a map's boundary (NaN: none sampled).
    samples: f64,
}

impl Figures {
    fn of(values: &[Vec<f64>], log2: &[Option<Log2Test>]) -> Figures {
        let get = |name: &str, scale: f64| -> Vec<f64> {
            let k = SENSITIVITY_FIELDS.iter().position(|f| f.0 == name);
            (values.iter())
                .map(|v| k.and_then(|k| v.get(k)).map_or(f64::NAN, |x| scale * x))
                .collect()
        };
        let sbb = get("boundary_basin_entropy", 1.0);
        // The stored verdict; where a file lacks it, the test on S_bb.
        let verdict = (log2.iter().zip(&sbb))
            .map(|(t, &s)| {
                t.or_else(|| match s.is_finite() {
                    true if s > LN_2 => Some(Log2Test::Fractal),
                    true => Some(Log2Test::Inconclusive),
                    false => None,
                })
            })
            .collect();
        let samples = get("uncertainty_samples", 1.0);
        Figures {
            sbb,
            verdict,
            step: get("step_sensitivity", 100.0),
            step_se: get("step_sensitivity_se", 100.0),
            alpha: get("uncertainty_exponent", 1.0),
            alpha_se: get("uncertainty_exponent_se", 1.0),
            samples: samples.into_iter().fold(f64::NAN, f64::max),
        }
    }

    /// Whether some point has a measured figure.
    fn measured(&self) -> bool {
        [&self.sbb, &self.step, &self.alpha]
            .iter()
            .any(|v| v.iter().any(|x| x.is_finite()))
    }

    /// The points of verdict `t` (no boundary: at 0), NaN elsewhere.
    fn of_verdict(&self, t: Log2Test) -> Vec<f64> {
        (self.verdict.iter().zip(&self.sbb))
            .map(|(v, &s)| match v {
                Some(v) if *v == t && t == Log2Test::NoBoundary => 0.0,
                Some(v) if *v == t => s,
                _ => f64::NAN,
            })
            .collect()
    }
}

/// The largest finite value of `v` (NaN: none).
fn top(v: impl IntoIterator<Item = f64>) -> f64 {
    v.into_iter()
        .filter(|x| x.is_finite())
        .fold(f64::NAN, f64::max)
}

/// How many values of `v` are finite.
fn count(v: &[f64]) -> usize {
    v.iter().filter(|x| x.is_finite()).count()
}

/// `1 point`, `3 points`.
fn points(n: usize) -> String {
    match n {
        1 => "1 point".into(),
        n => format!("{n} points"),
    }
}

/// A swept parameter as drawn: its values, log10 of them on a log axis.
struct Axis {
    values: Vec<f64>,
    log: bool,
    label: String,
}

impl Axis {
    fn of(a: &ParamAxis) -> Axis {
        Axis {
            values: a.values.clone(),
            log: is_log(&a.values),
            label: axis_label(a),
        }
    }

    /// A value in the plane's coordinates.
    fn at(&self, v: f64) -> f64 {
        if self.log { v.log10() } else { v }
    }

    /// The plane's coordinates of the values.
    fn coords(&self) -> Vec<f64> {
        self.values.iter().map(|&v| self.at(v)).collect()
    }

    /// The range drawn: the values padded by half a step (a point's cell) at both ends.
    fn range(&self) -> Range<f64> {
        let c = self.coords();
        let (lo, hi) = (c[0].min(c[c.len() - 1]), c[0].max(c[c.len() - 1]));
        let half = match c.len() {
            1 => 0.5,
            n => 0.5 * (hi - lo) / (n - 1) as f64,
        };
        (lo - half)..(hi + half)
    }
}

/// The plane of a panel on `area` over `(xr, yr)`: axes with their words and ticks (log
/// axes labelled at 1, 2, 5 x 10^k by [`crate::log_ticks`]), light horizontal grid lines.
fn axes_plane<'a, 'b>(
    area: &'a Area<'b>,
    (x, y): (&Axis, Option<&Axis>),
    y_label: &str,
    (xr, yr): (Range<f64>, Range<f64>),
) -> DrawResult<Plane<'a, 'b>> {
    crate::check_axis("x", xr.start, xr.end)?;
    crate::check_axis("y", yr.start, yr.end)?;
    let mut c = ChartBuilder::on(area)
        .margin(14)
        .x_label_area_size(64)
        .y_label_area_size(92)
        .build_cartesian_2d(xr.clone(), yr.clone())?;
    let log_y = y.is_some_and(|y| y.log);
    let fmt = |v: &f64| fmt_sig(*v);
    c.configure_mesh()
        .disable_x_mesh()
        .light_line_style(WHITE)
        .bold_line_style(RGBColor(228, 228, 228))
        .x_desc(x.label.as_str())
        .y_desc(y_label)
        .axis_desc_style(font(19))
        .label_style(font(15))
        .x_labels(if x.log { 0 } else { 8 })
        .y_labels(if log_y { 0 } else { 8 })
        .x_label_formatter(&fmt)
        .y_label_formatter(&fmt)
        .draw()?;
    let (bx, by) = area.get_base_pixel();
    let at = |u: f64, v: f64| {
        let p = c.backend_coord(&(u, v));
        (p.0 - bx, p.1 - by)
    };
    if x.log {
        let style = font(15).pos(Pos::new(HPos::Center, VPos::Top));
        for (t, text) in crate::log_ticks(10f64.powf(xr.start), 10f64.powf(xr.end)) {
            let p = at(t.log10(), yr.start);
            area.draw(&PathElement::new(vec![p, (p.0, p.1 + 6)], BLACK))?;
            area.draw_text(&text, &style, (p.0, p.1 + 9))?;
        }
    }
    if log_y {
        let style = font(15).pos(Pos::new(HPos::Right, VPos::Center));
        for (t, text) in crate::log_ticks(10f64.powf(yr.start), 10f64.powf(yr.end)) {
            let p = at(xr.start, t.log10());
            area.draw(&PathElement::new(vec![p, (p.0 - 6, p.1)], BLACK))?;
            area.draw_text(&text, &style, (p.0 - 9, p.1))?;
        }
    }
    Ok(c)
}

/// The title (the atlas's name, law and every fixed parameter) and what was measured over
/// the width of `root`; returns the area below.
fn header<'a>(root: &Area<'a>, plan: &AtlasPlan, f: &Figures) -> DrawResult<Area<'a>> {
    let (w, _) = root.dim_in_pixel();
    let head = title(plan, Some("final-state sensitivity of the basin maps"));
    let width = w.saturating_sub(40);
    let lines: Vec<(String, TextStyle)> = (crate::wrap_line(root, &head, &bold(22), width))
        .into_iter()
        .map(|l| (l, bold(22)))
        .chain(
            (subtitle(plan, f).iter())
                .flat_map(|s| crate::wrap_line(root, s, &font(16), width))
                .map(|l| (l, font(16))),
        )
        .collect();
    let height = |s: &TextStyle| if s.font.get_size() > 20.0 { 28 } else { 22 };
    let total: i32 = lines.iter().map(|(_, s)| height(s)).sum();
    let (top, rest) = root.split_vertically(20 + total as u32);
    let mut y = 12;
    for (line, style) in &lines {
        top.draw_text(line, style, (20, y))?;
        y += height(style);
    }
    Ok(rest)
}

/// The lines under the title: what each map's figures are and how they were measured.
fn subtitle(plan: &AtlasPlan, f: &Figures) -> Vec<String> {
    let grid = plan.maps.as_ref().map(|m| m.grid);
    let cells = grid.map_or(String::new(), |g| {
        format!(" of {} x {} starts", g.x0.count, g.v0.count)
    });
    let step = if f.samples.is_finite() {
        format!(
            "step sensitivity: {} starts near each map's boundary, classified at dt = {} and again at dt/2 ({} scheme)",
            f.samples,
            crate::fmt_number(plan.dt),
            plan.solver.scheme.name()
        )
    } else {
        "step sensitivity: not measured (no map was sampled near a boundary)".to_string()
    };
    vec![
        format!(
            "per basin map{cells}: boundary basin entropy S_bb over boxes of {ENTROPY_BOX} x {ENTROPY_BOX} cells (Daza et al. 2016), above ln 2 a fractal boundary (log 2 test, Puy et al. 2021)"
        ),
        format!("{step}; left out: points without a complete map, or not measured"),
    ]
}

/// A panel of a column: a figure against the swept parameter, in groups of glyphs, with
/// error bars, a labelled dashed reference line and a legend beside.
struct Series<'a> {
    heading: &'a str,
    y_label: &'a str,
    /// Per group: glyph, fill, legend words and the values (NaN: not in the group).
    groups: Vec<(Glyph, Rgb, String, Vec<f64>)>,
    /// The values and their standard errors, drawn as bars of +-1 standard error.
    errors: Option<(&'a [f64], &'a [f64])>,
    /// The reference line: its value and its words.
    reference: (f64, &'a str),
    y: Range<f64>,
}

/// Width of a column's picture and of its plots (the legend beside).
const COLUMN: (u32, u32) = (1500, 1010);
/// Height of a column's panel.
const PANEL: u32 = 380;

/// The column over the one swept parameter `a`: S_bb, the step sensitivity and, where
/// fitted, the uncertainty exponent, one panel above the other (the step's where some map
/// was sampled: `classifier.sensitivity_samples = 0` keeps only the entropies).
fn column(plan: &AtlasPlan, a: &ParamAxis, f: &Figures, png: &Path) -> Result<(), PlotError> {
    let x = Axis::of(a);
    let mut panels = vec![entropy_series(f)];
    panels.extend((count(&f.step) > 0).then(|| step_series(f)));
    panels.extend(alpha_series(f));
    let size = (COLUMN.0, 170 + PANEL * panels.len() as u32);
    render(png, size, |root| {
        let body = header(root, plan, f)?;
        for (area, s) in body.split_evenly((panels.len(), 1)).iter().zip(&panels) {
            draw_series(area, &x, s)?;
        }
        Ok(())
    })
}

/// The verdicts of the log 2 test: glyph, fill, words.
const VERDICTS: [(Log2Test, Glyph, Rgb, &str); 3] = [
    (
        Log2Test::Fractal,
        Glyph::Diamond,
        Rgb(205, 35, 35),
        "fractal: S_bb > ln 2",
    ),
    (
        Log2Test::Inconclusive,
        Glyph::Square,
        Rgb(49, 110, 198),
        "inconclusive: S_bb <= ln 2",
    ),
    (
        Log2Test::NoBoundary,
        Glyph::TriangleDown,
        Rgb(150, 150, 150),
        "no boundary box (drawn at 0)",
    ),
];

fn entropy_series(f: &Figures) -> Series<'_> {
    let groups = VERDICTS
        .iter()
        .map(|&(t, glyph, fill, words)| {
            let v = f.of_verdict(t);
            (glyph, fill, format!("{words}: {}", points(count(&v))), v)
        })
        .collect();
    Series {
        heading: "log 2 test (Puy et al. 2021)",
        y_label: "boundary basin entropy S_bb (1)",
        groups,
        errors: None,
        reference: (LN_2, "ln 2: above it the boundary is fractal"),
        y: {
            let hi = 1.15 * top(f.sbb.iter().copied().chain([LN_2]));
            -0.04 * hi..hi
        },
    }
}

fn step_series(f: &Figures) -> Series<'_> {
    let small = 100.0 * STEP_SHARE_SMALL;
    let split = |above: bool| -> Vec<f64> {
        (f.step.iter())
            .map(|&s| if (s > small) == above { s } else { f64::NAN })
            .collect()
    };
    let (hi, lo) = (split(true), split(false));
    let bars = f.step.iter().zip(&f.step_se).map(|(s, e)| s + e);
    Series {
        heading: "step sensitivity",
        y_label: "starts whose fate moves at dt/2 (%)",
        groups: vec![
            (
                Glyph::Diamond,
                Rgb(205, 35, 35),
                format!("above 1%, the step decides: {}", points(count(&hi))),
                hi,
            ),
            (
                Glyph::Square,
                Rgb(49, 110, 198),
                format!("at most 1%: {}", points(count(&lo))),
                lo,
            ),
        ],
        errors: Some((&f.step, &f.step_se)),
        reference: (small, "1%: above it the fates depend on the step"),
        y: {
            let hi = 1.15 * top(bars.chain([1.5 * small]));
            -0.04 * hi..hi
        },
    }
}

/// The uncertainty exponent's panel, where some map's was fitted.
fn alpha_series(f: &Figures) -> Option<Series<'_>> {
    if count(&f.alpha) == 0 {
        return None;
    }
    let err = |sign: f64| (f.alpha.iter().zip(&f.alpha_se)).map(move |(a, e)| a + sign * e);
    let lo = -top(err(-1.0).map(|v| -v).chain([0.0]));
    let hi = top(err(1.0).chain([1.2]));
    let pad = 0.08 * (hi - lo);
    Some(Series {
        heading: "uncertainty exponent (Grebogi et al. 1983)",
        y_label: "uncertainty exponent alpha (1)",
        groups: vec![(
            Glyph::Square,
            Rgb(20, 130, 80),
            format!("alpha, fitted at {}", points(count(&f.alpha))),
            f.alpha.clone(),
        )],
        errors: Some((&f.alpha, &f.alpha_se)),
        reference: (1.0, "1: a smooth boundary; below 1: fractal"),
        y: (lo - pad)..(hi + pad),
    })
}

/// One panel of a column on `area`: the plot, and the legend beside it.
fn draw_series(area: &Area<'_>, x: &Axis, s: &Series<'_>) -> DrawResult<()> {
    let (left, legend) = area.split_horizontally(COLUMN.1);
    let xr = x.range();
    let c = axes_plane(&left, (x, None), s.y_label, (xr.clone(), s.y.clone()))?;
    let xs = x.coords();
    draw_reference(&c, s, &xs)?;
    if let Some((mid, se)) = s.errors {
        let bars = (xs.iter().zip(mid.iter().zip(se)))
            .filter(|(_, (m, e))| m.is_finite() && e.is_finite());
        let ink = BLACK.stroke_width(2);
        for (&u, (&m, &e)) in bars {
            let cap =
                |v: f64| EmptyElement::at((u, v)) + PathElement::new(vec![(-6, 0), (6, 0)], ink);
            c.plotting_area()
                .draw(&PathElement::new(vec![(u, m - e), (u, m + e)], ink))?;
            c.plotting_area().draw(&cap(m - e))?;
            c.plotting_area().draw(&cap(m + e))?;
        }
    }
    let mut items = Vec::new();
    for (glyph, fill, name, v) in &s.groups {
        let points = (xs.iter().zip(v)).filter(|(_, y)| y.is_finite());
        for (&u, &y) in points {
            c.plotting_area()
                .draw(&glyph_element(*glyph, *fill, (u, y)))?;
        }
        if count(v) > 0 {
            let (name, glyph, fill) = (name.clone(), *glyph, *fill);
            items.push(LegendItem::Glyph { name, glyph, fill });
        }
    }
    let (name, color) = (s.reference.1.to_string(), REFERENCE);
    items.push(LegendItem::Dashed { name, color });
    if s.errors.is_some() {
        let (name, color, dots) = ("bars: +-1 standard error".into(), Rgb(0, 0, 0), false);
        items.push(LegendItem::Line { name, color, dots });
    }
    draw_legend(&legend, s.heading, &items)
}

/// The colour of a column's reference line and its words.
const REFERENCE: Rgb = Rgb(110, 110, 110);

/// The dashed reference line of a column's panel across the plot, its words above it at
/// the end where fewer points (with their bars) come near the line.
fn draw_reference(c: &Plane<'_, '_>, s: &Series<'_>, xs: &[f64]) -> DrawResult<()> {
    let (xr, yr) = (c.x_range(), c.y_range());
    let (r, words) = s.reference;
    let grey = REFERENCE.color();
    let line = vec![(xr.start, r), (xr.end, r)];
    let dashes = plotters::element::DashedPathElement::new(line, 10, 7, grey.stroke_width(2));
    c.plotting_area().draw(&dashes)?;
    // Points within a third of the width from an end, near the line or above it.
    let crowd = |right: bool| {
        (0..xs.len())
            .filter(|&i| {
                let end = if right {
                    xr.end - xs[i]
                } else {
                    xs[i] - xr.start
                };
                let e = s.errors.map_or(0.0, |(_, se)| se[i]).max(0.0);
                let near = (s.groups.iter()).any(|g| {
                    let d = g.3[i] - r;
                    d.is_finite()
                        && d + e > -0.05 * (yr.end - yr.start)
                        && d - e < 0.15 * (yr.end - yr.start)
                });
                near && end < (xr.end - xr.start) / 3.0
            })
            .count()
    };
    let right = crowd(true) < crowd(false);
    let (at, h, dx) = match right {
        true => (xr.end, HPos::Right, -10),
        false => (xr.start, HPos::Left, 10),
    };
    let style = font(16).color(&grey).pos(Pos::new(h, VPos::Bottom));
    let label = EmptyElement::at((at, r)) + Text::new(words.to_string(), (dx, -6), style);
    c.plotting_area().draw(&label)?;
    Ok(())
}

/// Size of a chart's picture, and the width of each of its two panels' plots.
const CHART: (u32, u32, u32) = (2000, 1000, 740);

/// A panel of a chart: a figure over the parameter plane, one coloured marker per point.
struct Field<'a> {
    heading: &'a str,
    /// The colour bar's words.
    bar: [&'a str; 2],
    values: &'a [f64],
    /// The colour scale's top (its bottom is 0).
    hi: f64,
    /// The value marked on the bar, and its words there.
    mark: (f64, &'a str),
    /// The points ringed in black, and the words of the ring (lines).
    ringed: Vec<bool>,
    ring: [&'a str; 3],
    /// The points drawn as grey triangles, and their words.
    other: Option<(Vec<bool>, &'a str)>,
    /// A value as written under its marker (where the markers are large enough).
    text: fn(f64) -> String,
}

/// The chart over the swept parameters `x` (across) and `y` (up): S_bb and the step
/// sensitivity side by side.
fn chart(
    plan: &AtlasPlan,
    (x, y): (&Axis, &Axis),
    f: &Figures,
    png: &Path,
) -> Result<(), PlotError> {
    let fractal: Vec<bool> = f
        .verdict
        .iter()
        .map(|v| *v == Some(Log2Test::Fractal))
        .collect();
    let none = f
        .verdict
        .iter()
        .map(|v| *v == Some(Log2Test::NoBoundary))
        .collect();
    let small = 100.0 * STEP_SHARE_SMALL;
    let fields = [
        Field {
            heading: "boundary basin entropy S_bb per map (log 2 test)",
            bar: ["S_bb (1)", "mean entropy of the boundary's boxes"],
            values: &f.sbb,
            hi: top(f.sbb.iter().copied().chain([1.25 * LN_2])),
            mark: (LN_2, "ln 2"),
            ringed: fractal,
            ring: [
                "black ring: S_bb > ln 2,",
                "the boundary is fractal",
                "(Puy et al. 2021)",
            ],
            other: Some((none, "no boundary box")),
            text: |v| format!("{v:.2}"),
        },
        Field {
            heading: "step sensitivity: starts whose fate moves at dt/2",
            bar: ["share (%)", "of the sampled starts"],
            values: &f.step,
            hi: top(f.step.iter().copied().chain([2.0 * small])),
            mark: (small, "1%"),
            ringed: f.step.iter().map(|&s| s > small).collect(),
            ring: [
                "black ring: above 1%,",
                "the fates depend on",
                "the step, not the grid",
            ],
            other: None,
            text: |v| format!("{v:.1}%"),
        },
    ];
    render(png, (CHART.0, CHART.1), |root| {
        let body = header(root, plan, f)?;
        let halves = body.split_evenly((1, 2));
        for (area, field) in halves.iter().zip(&fields) {
            draw_field(area, (x, y), field)?;
        }
        Ok(())
    })
}

/// One panel of a chart on `area`: its heading, the plane with a marker per measured point
/// (its colour the value, ringed where [`Field::ringed`]), and the colour bar beside.
fn draw_field(area: &Area<'_>, (x, y): (&Axis, &Axis), f: &Field<'_>) -> DrawResult<()> {
    let (head, body) = area.split_vertically(40);
    head.draw_text(f.heading, &bold(18), (24, 10))?;
    let (left, side) = body.split_horizontally(CHART.2);
    let c = axes_plane(&left, (x, Some(y)), &y.label, (x.range(), y.range()))?;
    let (xs, ys) = (x.coords(), y.coords());
    let (pw, ph) = c.plotting_area().dim_in_pixel();
    let cell = (pw as f64 / xs.len() as f64).min(ph as f64 / ys.len() as f64);
    let r = (0.36 * cell).clamp(3.0, 24.0) as i32;
    let nx = xs.len();
    let grey = Rgb(150, 150, 150);
    for (k, &v) in f.values.iter().enumerate() {
        let at = (xs[k % nx], ys[k / nx]);
        let pa = c.plotting_area();
        if v.is_finite() {
            pa.draw(&Circle::new(at, r, ramp(v / f.hi).color().filled()))?;
            pa.draw(&Circle::new(at, r, RGBColor(60, 60, 60).stroke_width(1)))?;
            if f.ringed[k] {
                pa.draw(&Circle::new(at, r + 4, BLACK.stroke_width(3)))?;
            }
            if r >= 14 {
                let style = font(14).pos(Pos::new(HPos::Center, VPos::Top));
                pa.draw(&(EmptyElement::at(at) + Text::new((f.text)(v), (0, r + 7), style)))?;
            }
        } else if f.other.as_ref().is_some_and(|(o, _)| o[k]) {
            pa.draw(&glyph_element(Glyph::TriangleDown, grey, at))?;
        }
    }
    draw_bar(&side, f)
}

/// The colour bar of a chart's panel with its ticks and its marked value, then the words
/// of the rings and of the other marks.
fn draw_bar(area: &Area<'_>, f: &Field<'_>) -> DrawResult<()> {
    let (x, top, h, w) = (16, 90, 300, 28);
    area.draw_text(f.bar[0], &bold(17), (x, 30))?;
    area.draw_text(f.bar[1], &font(14), (x, 54))?;
    crate::draw_viridis_strip(area, (x, top, w, h))?;
    let py = |v: f64| top + ((1.0 - v / f.hi) * (h - 1) as f64).round() as i32;
    let (mark, words) = f.mark;
    let ticks = RangedCoordf64::from(0.0..f.hi).key_points(6);
    for v in ticks.into_iter().filter(|&v| (py(v) - py(mark)).abs() > 14) {
        area.draw(&PathElement::new(
            vec![(x + w, py(v)), (x + w + 6, py(v))],
            BLACK,
        ))?;
        area.draw_text(&fmt_sig(v), &font(14), (x + w + 10, py(v) - 7))?;
    }
    let m = py(mark);
    area.draw(&PathElement::new(
        vec![(x - 4, m), (x + w + 8, m)],
        BLACK.stroke_width(3),
    ))?;
    area.draw_text(words, &bold(15), (x + w + 12, m - 8))?;
    let mut y = top + h + 36;
    area.draw(&Circle::new((x + 12, y + 10), 10, BLACK.stroke_width(3)))?;
    for (i, line) in f.ring.iter().enumerate() {
        area.draw_text(line, &font(14), (x + 32, y + 18 * i as i32))?;
    }
    y += 18 * f.ring.len() as i32 + 20;
    if let Some((_, words)) = f.other.as_ref().filter(|(o, _)| o.contains(&true)) {
        area.draw(&glyph_element(
            Glyph::TriangleDown,
            Rgb(150, 150, 150),
            (x + 12, y + 8),
        ))?;
        area.draw_text(words, &font(14), (x + 32, y))?;
        y += 34;
    }
    for (i, line) in ["no marker: no complete map,", "or not measured"]
        .iter()
        .enumerate()
    {
        area.draw_text(line, &font(14), (x, y + 18 * i as i32))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests;
