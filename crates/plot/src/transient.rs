//! The transient-squeal map: over a scan's grid of starts, how long each start that ends in
//! steady slip squealed (stuck, revolution after revolution) before it settled: the stored
//! per-cell `t_squeal`. A brake that squeals for 400 periods and then stops is what this
//! picture shows; every other cell is drawn in one of four neutral classes.

use super::*;
use crate::basin::{
    Classes, MAP_LAYOUT, SHEET_LAYOUT, SHEET_PANEL, check_panel, draw_basin_chart,
    sheet_title_height,
};
use crate::legend::{LEGEND_WIDTH, LegendItem, draw_legend, overlay_items};

/// Colour steps of the ramp.
const LEVELS: usize = 250;
/// The first cell code of the ramp (codes below are the fixed classes).
const RAMP: u8 = 4;

/// The fixed classes: (code, name, colour).
const FIXED: [(u8, &str, Rgb); 4] = [
    (0, "steady slip, never stuck", Rgb(235, 235, 235)),
    (1, "stick-slip (squeals for good)", Rgb(95, 95, 95)),
    (2, "undecided, or not known", Rgb(230, 0, 200)),
    (3, "not computed", Rgb(255, 255, 255)),
];

/// The ramp (dark to light: short to long squeal).
use crate::viridis as ramp;

/// Whether a cell squealed and then settled: steady slip (label 1) with `0 < t_squeal < inf`.
fn transient(label: u8, t: f64) -> bool {
    label == 1 && t > 0.0 && t.is_finite()
}

/// Whether any cell of `labels` (the stored label values) squealed before it settled in
/// steady slip: the transient map is drawn only then.
pub fn has_transients(labels: &[u8], t_squeal: &[f64]) -> bool {
    use rayon::prelude::*;
    labels
        .par_iter()
        .zip(t_squeal)
        .any(|(&l, &t)| transient(l, t))
}

/// The colour scale of the transient times `lo..=hi`: logarithmic where they span more than
/// a decade (lifetimes near a crisis spread over decades), else linear from 0.
#[derive(Clone, Copy, Debug)]
struct Scale {
    lo: f64,
    hi: f64,
    log: bool,
}

impl Scale {
    /// No times yet: the start of [`Scale::widen`].
    const NONE: (f64, f64) = (f64::INFINITY, 0.0);

    /// The span of two spans of times (`(lo, hi)`): exact in any order, the times being
    /// positive and finite.
    fn widen((l, h): (f64, f64), (a, b): (f64, f64)) -> (f64, f64) {
        (l.min(a), h.max(b))
    }

    /// The scale of times spanning `lo..=hi`.
    fn spanning((lo, hi): (f64, f64)) -> Scale {
        let log = hi > 10.0 * lo;
        Scale {
            lo: if log { lo } else { 0.0 },
            hi,
            log,
        }
    }

    /// Position of `t` on the bar, 0 at `lo`, 1 at `hi`.
    fn at(&self, t: f64) -> f64 {
        let s = if self.log {
            (t / self.lo).ln() / (self.hi / self.lo).ln()
        } else if self.hi > 0.0 {
            t / self.hi
        } else {
            0.0
        };
        if s.is_finite() {
            s.clamp(0.0, 1.0)
        } else {
            1.0
        }
    }

    /// The labelled ticks of the bar.
    fn ticks(&self) -> Vec<(f64, String)> {
        if self.log {
            return log_ticks(self.lo, self.hi);
        }
        (0..=4)
            .map(|k| {
                let v = self.hi * k as f64 / 4.0;
                (v, fmt_linear(v, self.hi))
            })
            .collect()
    }
}

/// The cell codes of the picture: the fixed classes, or [`RAMP`] plus the ramp level.
fn codes(labels: &[u8], t_squeal: &[f64], scale: &Scale) -> Vec<u8> {
    use rayon::prelude::*;
    labels
        .par_iter()
        .zip(t_squeal)
        .map(|(&l, &t)| match l {
            _ if transient(l, t) => RAMP + (scale.at(t) * (LEVELS - 1) as f64).round() as u8,
            1 if t == 0.0 => 0,
            2 => 1,
            255 => 3,
            _ => 2,
        })
        .collect()
}

/// The colour classes: the fixed ones, then the ramp.
fn all_classes() -> Vec<(u8, &'static str, Rgb)> {
    let mut classes: Vec<(u8, &str, Rgb)> = FIXED.to_vec();
    classes.extend((0..LEVELS).map(|k| (RAMP + k as u8, "", ramp(k as f64 / (LEVELS - 1) as f64))));
    classes
}

/// The shared colour scale and each panel's cell codes.
type Coded = (Scale, Vec<Vec<u8>>);

/// The shared scale of the transients of every panel, and each panel's cell codes; `None`
/// if no cell squealed before settling.
fn coded(panels: &[BasinPanel<'_>], t_squeal: &[&[f64]]) -> Result<Option<Coded>, PlotError> {
    for (p, t) in panels.iter().zip(t_squeal) {
        if t.len() != p.labels.len() {
            return Err(PlotError::ShapeMismatch {
                what: format!("t_squeal of the transient map {:?}", p.title),
                expected: p.labels.len(),
                found: t.len(),
            });
        }
    }
    if !panels
        .iter()
        .zip(t_squeal)
        .any(|(p, t)| has_transients(p.labels, t))
    {
        return Ok(None);
    }
    let scale = Scale::spanning(panels.iter().zip(t_squeal).fold(Scale::NONE, |s, (p, t)| {
        use rayon::prelude::*;
        let span = (p.labels.par_iter().zip(t.par_iter()))
            .filter(|&(&l, &t)| transient(l, t))
            .map(|(_, &t)| (t, t))
            .reduce(|| Scale::NONE, Scale::widen);
        Scale::widen(s, span)
    }));
    let codes = panels
        .iter()
        .zip(t_squeal)
        .map(|(p, t)| codes(p.labels, t, &scale))
        .collect();
    Ok(Some((scale, codes)))
}

/// The legend rows of the fixed classes present (with their counts) and the overlays.
fn other_items(counts: &[usize], panels: &[BasinPanel<'_>]) -> Vec<LegendItem> {
    let mut items: Vec<LegendItem> = FIXED
        .iter()
        .zip(counts)
        .filter(|(_, n)| **n > 0)
        .map(|(&(_, name, color), &n)| LegendItem::Swatch {
            name: name.into(),
            color,
            detail: Some(format!("{n} cells")),
        })
        .collect();
    items.extend(overlay_items(panels));
    items
}

/// One transient map: `panel` gives the grid, title, overlays and markers (its `labels`
/// are the stored label values), `t_squeal` the stored column in the same order, and
/// `bar` the colour bar's words: its quantity and unit lines (e.g. `["t_squeal",
/// "nondimensional time", "(natural period 2π)"]`). Steady-slip cells that stuck before
/// settling are coloured by their `t_squeal`; the others are drawn in four neutral classes,
/// listed with their counts under the bar. Axes at equal scales, as the basin map.
/// Returns `false` (and writes nothing) if no cell squealed before settling
/// ([`has_transients`]).
pub fn transient_map(
    path: &Path,
    panel: &BasinPanel<'_>,
    t_squeal: &[f64],
    bar: &[&str],
) -> Result<bool, PlotError> {
    let axes = check_panel(panel)?;
    let panels = std::slice::from_ref(panel);
    let Some((scale, codes)) = coded(panels, &[t_squeal])? else {
        return Ok(false);
    };
    let classes = all_classes();
    let lookup = Classes::new(&classes);
    let counts = lookup.counts(&codes[0]);
    let squealed: usize = counts[FIXED.len()..classes.len()].iter().sum();
    let items = other_items(&counts, panels);
    let coded = BasinPanel {
        labels: &codes[0],
        ..panel.clone()
    };
    render(path, (900 + 40, 800), |root| {
        let (left, right) = root.split_horizontally(900 + 40 - LEGEND_WIDTH);
        draw_basin_chart(&left, &coded, axes, &lookup, MAP_LAYOUT)?;
        let (top, bottom) = right.split_vertically(470);
        draw_bar(&top, &scale, bar, squealed)?;
        draw_legend(&bottom, "Other cells", &items)
    })?;
    Ok(true)
}

/// A sheet of transient maps (one per map of a sweep) with one shared colour scale, laid out
/// as [`crate::basin_sheet`] (`ncols` columns, `title` over all); the arguments as for
/// [`transient_map`], one `t_squeal` per panel. `false` (nothing written) if no cell of any
/// panel squealed before settling.
pub fn transient_sheet(
    path: &Path,
    title: &str,
    panels: &[BasinPanel<'_>],
    t_squeal: &[&[f64]],
    (bar, ncols): (&[&str], usize),
) -> Result<bool, PlotError> {
    if panels.is_empty() || panels.len() != t_squeal.len() {
        return Err(PlotError::EmptyData(
            "transient sheet: one t_squeal per panel",
        ));
    }
    let axes = panels
        .iter()
        .map(check_panel)
        .collect::<Result<Vec<_>, _>>()?;
    let Some((scale, codes)) = coded(panels, t_squeal)? else {
        return Ok(false);
    };
    let classes = all_classes();
    let lookup = Classes::new(&classes);
    let all: Vec<u8> = codes.iter().flatten().copied().collect();
    let counts = lookup.counts(&all);
    let squealed: usize = counts[FIXED.len()..classes.len()].iter().sum();
    let items = other_items(&counts, panels);
    let ncols = ncols.clamp(1, panels.len());
    let nrows = panels.len().div_ceil(ncols);
    let (pw, ph) = SHEET_PANEL;
    let size = (
        ncols as u32 * pw + LEGEND_WIDTH + 40,
        (sheet_title_height(title) + nrows as u32 * ph).max(800),
    );
    render(path, size, |root| {
        let body = draw_title(root, title, 26)?;
        let (grid, side) = body.split_horizontally(ncols as u32 * pw);
        let cells = grid.split_evenly((nrows, ncols));
        for (((p, ax), c), cell) in panels.iter().zip(axes).zip(&codes).zip(&cells) {
            let coded = BasinPanel {
                labels: c,
                ..p.clone()
            };
            draw_basin_chart(cell, &coded, ax, &lookup, SHEET_LAYOUT)?;
        }
        let (top, bottom) = side.split_vertically(470);
        draw_bar(&top, &scale, bar, squealed)?;
        draw_legend(&bottom, "Other cells", &items)
    })?;
    Ok(true)
}

/// The colour bar with its words, ticks and the count of cells that squealed.
fn draw_bar(area: &Area<'_>, scale: &Scale, words: &[&str], squealed: usize) -> DrawResult<()> {
    let (x, mut y) = (12, 40);
    for (i, w) in words.iter().enumerate() {
        let style = if i == 0 { bold(18) } else { font(15) };
        area.draw_text(w, &style, (x, y))?;
        y += if i == 0 { 26 } else { 20 };
    }
    let scale_words = if scale.log {
        "log scale"
    } else {
        "linear scale"
    };
    area.draw_text(scale_words, &font(14), (x, y))?;
    y += 28;
    let (top, h, w) = (y, 300i32, 28i32);
    // Long squeal at the top.
    crate::draw_viridis_strip(area, (x, top, w, h))?;
    for (v, label) in scale.ticks() {
        let py = top + ((1.0 - scale.at(v)) * (h - 1) as f64).round() as i32;
        area.draw(&PathElement::new(vec![(x + w, py), (x + w + 6, py)], BLACK))?;
        area.draw_text(&label, &font(14), (x + w + 10, py - 7))?;
    }
    let note = format!("{squealed} steady-slip cells squealed first");
    area.draw_text(&note, &font(14), (x, top + h + 14))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn panel<'a>(x0: &'a [f64], v0: &'a [f64], labels: &'a [u8]) -> BasinPanel<'a> {
        BasinPanel {
            title: "t".into(),
            x0,
            v0,
            labels,
            overlays: vec![],
            markers: vec![],
            axis_labels: None,
        }
    }

    /// Drawn only where a steady-slip cell stuck first: stick-slip cells (inf), unknown ones
    /// (-1) and never-stuck ones (0) alone draw nothing; one transient draws the picture.
    #[test]
    fn drawn_only_where_a_steady_slip_cell_squealed_first() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.png");
        let (x0, v0) = ([0.0, 1.0], [0.0, 1.0]);
        let labels = [1, 2, 0, 1];
        let none = [0.0, f64::INFINITY, -1.0, 0.0];
        assert!(!transient_map(&path, &panel(&x0, &v0, &labels), &none, &["t"]).unwrap());
        assert!(!path.exists());
        // A stick-slip cell with a finite time is not a transient either.
        assert!(!has_transients(&[2], &[5.0]));
        let some = [0.0, f64::INFINITY, -1.0, 412.5];
        assert!(transient_map(&path, &panel(&x0, &v0, &labels), &some, &["t"]).unwrap());
        assert!(std::fs::metadata(&path).unwrap().len() > 1000);
        let short = [1.0];
        let e = transient_map(&path, &panel(&x0, &v0, &labels), &short, &["t"]).unwrap_err();
        assert!(matches!(e, PlotError::ShapeMismatch { .. }), "{e}");
    }

    /// A sweep's sheet: drawn when one panel of two has a transient, not when none has;
    /// one `t_squeal` per panel.
    #[test]
    fn a_sheet_is_drawn_where_any_panel_squealed_first() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.png");
        let (x0, v0) = ([0.0, 1.0], [0.0, 1.0]);
        let labels = [1, 2, 0, 1];
        let panels = [panel(&x0, &v0, &labels), panel(&x0, &v0, &labels)];
        let none = [0.0, f64::INFINITY, -1.0, 0.0];
        let some = [0.0, f64::INFINITY, -1.0, 30.0];
        let draw = |ts: &[&[f64]]| transient_sheet(&path, "s", &panels, ts, (&["t"], 2));
        assert!(!draw(&[&none, &none]).unwrap());
        assert!(!path.exists());
        assert!(draw(&[&none, &some]).unwrap());
        assert!(std::fs::metadata(&path).unwrap().len() > 1000);
        assert!(draw(&[&none]).is_err());
    }

    /// The codes: a log scale over two decades puts the shortest transient at the ramp's
    /// start and the longest at its end; the fixed classes keep their codes.
    #[test]
    fn codes_place_times_on_the_ramp() {
        let labels = [1, 1, 1, 2, 0, 255];
        let t = [1.0, 100.0, 0.0, f64::INFINITY, -1.0, f64::NAN];
        let s = Scale::spanning((1.0, 100.0));
        assert!(s.log);
        // 10 is half way on a log scale from 1 to 100.
        assert!((s.at(10.0) - 0.5).abs() < 1e-12);
        let c = codes(&labels, &t, &s);
        assert_eq!(c, vec![RAMP, RAMP + (LEVELS - 1) as u8, 0, 1, 2, 3]);
    }
}
