//! Sweep charts: a quantity against a swept parameter, the values without data marked by why.

use super::*;

/// Swept values without data, grouped by why (e.g. "no unstable cycle: every start
/// squeals"): drawn on the bottom of a [`sweep_chart`], one glyph and colour per group, and
/// listed in the legend as `label (n values)`.
#[derive(Clone, Debug)]
pub struct Gap {
    /// Legend label (the count is appended).
    pub label: String,
    /// The swept values in this group.
    pub xs: Vec<f64>,
    /// The mark's shape: groups with different reasons need different shapes.
    pub glyph: Glyph,
    /// The mark's colour.
    pub color: Rgb,
}

/// A quantity against a swept parameter (e.g. the unstable cycle's size against `nu`).
///
/// Each curve is drawn as a line with a dot at every value (so a value between two gaps still
/// shows). The swept values without data (find them with [`missing_values`]) are drawn in
/// `gaps` on the bottom of the chart, each group with its own glyph; if every value is
/// missing, the chart holds only those marks. Size 900x700.
pub fn sweep_chart(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    curves: &[Curve],
    log_x: bool,
    gaps: &[Gap],
) -> Result<(), PlotError> {
    for c in curves {
        check_curve(c)?;
    }
    line_chart(
        path,
        LineOpts {
            title,
            x_label,
            y_label,
            curves,
            markers: &[],
            log_x,
            aspect: None,
            gaps: Some(gaps),
        },
    )
}

/// The drawable values of the curves' `xs` (finite, and `> 0` if `log_x`) at which no curve
/// has a finite y, ascending and once each: the gaps of a [`sweep_chart`].
pub fn missing_values(curves: &[Curve], log_x: bool) -> Vec<f64> {
    let mut xs: Vec<f64> = curves
        .iter()
        .flat_map(|c| c.xs.iter().copied())
        .filter(|x| x.is_finite() && (!log_x || *x > 0.0))
        .collect();
    xs.sort_by(f64::total_cmp);
    xs.dedup();
    xs.retain(|&x| {
        !curves.iter().any(|c| {
            c.xs.iter()
                .zip(&c.ys)
                .any(|(&cx, &cy)| cx == x && cy.is_finite())
        })
    });
    xs
}

/// The swept values without a cycle (`missing`), grouped by what map `i` (at `xs[i]`, cell
/// counts `[undecided, steady, stick, not computed, slip oscillation]`) found: only stick-slip, only steady
/// slip, or neither alone. Each group has its own glyph (under one triangle, "every
/// start squeals" and "no start squeals" could not be told apart).
pub fn cycle_gaps(missing: &[f64], xs: &[f64], counts: &[[u64; 5]]) -> Vec<Gap> {
    let mut gaps = [
        (
            "no unstable cycle: every start squeals",
            Glyph::TriangleUp,
            Rgb(200, 40, 40),
        ),
        (
            "no unstable cycle: no start squeals",
            Glyph::TriangleDown,
            STEADY,
        ),
        (
            "no unstable cycle located (both basins or undecided)",
            Glyph::Diamond,
            MISSING,
        ),
    ]
    .map(|(label, glyph, color)| Gap {
        label: label.into(),
        xs: Vec::new(),
        glyph,
        color,
    });
    for &x in missing {
        let c = xs.iter().position(|&v| v == x).and_then(|i| counts.get(i));
        let group = match c {
            Some([_, 0, stick, _, 0]) if *stick > 0 => 0,
            Some([_, steady, 0, _, 0]) if *steady > 0 => 1,
            _ => 2,
        };
        gaps[group].xs.push(x);
    }
    gaps.into_iter().filter(|g| !g.xs.is_empty()).collect()
}
