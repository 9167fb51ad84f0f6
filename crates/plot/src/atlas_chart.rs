//! The chart of an atlas: a stability chart over two swept parameters (regimes, the basin
//! fraction's contours, the fold and the critical boundary), or a bifurcation diagram over
//! one (the unstable cycle and the stick-slip band against the swept parameter).

use std::path::Path;

use squeal_scan::atlas::{
    AtlasPlan, AtlasRegime, AtlasResults, Boundary, BoundaryResult, BoundaryStatus, ParamAxis,
    PointResult, Units,
};

use crate::atlas_sheet::{axis_label, is_log, regime_classes, title};
use crate::{Curve, Glyph, Marks, PlotError, Rgb, StabilityChart};

/// Draws the chart of an atlas: a stability chart (2 swept parameters) or a bifurcation
/// diagram (1); nothing for other counts.
pub fn atlas_chart(plan: &AtlasPlan, res: &AtlasResults, png: &Path) -> Result<(), PlotError> {
    match plan.space.axes().len() {
        2 => stability(plan, res, png),
        1 => bifurcation(plan, res, png),
        _ => Ok(()),
    }
}

/// Per boundary search, the boundary `f` picks where it was found (in SI units for a
/// physical plan), NaN elsewhere.
fn boundary_values(
    plan: &AtlasPlan,
    res: &AtlasResults,
    f: fn(&BoundaryResult) -> Boundary,
) -> Vec<f64> {
    res.boundaries
        .iter()
        .enumerate()
        .map(|(j, b)| {
            b.as_ref().map_or(f64::NAN, |b| {
                let bd = f(b);
                if bd.status != BoundaryStatus::Found {
                    return f64::NAN;
                }
                plan.boundary_si(plan.boundary_setup(j).0, bd.nu)
                    .map_or(bd.nu, |(v, _)| v)
            })
        })
        .collect()
}

/// The stability chart over the swept axes `(y, x)`.
fn stability(plan: &AtlasPlan, res: &AtlasResults, png: &Path) -> Result<(), PlotError> {
    let axes = plan.space.axes();
    let (ya, xa) = (axes[0], axes[1]);
    let classes: Vec<u8> = res
        .points
        .iter()
        .map(|p| p.as_ref().map_or(255, |p| p.regime as u8))
        .collect();
    // Contours inside the bistable region only: elsewhere the fraction is 0 or 1 by the
    // regime, and contours would crowd along its edge. With maps, the map's.
    let field: Vec<f64> = res
        .points
        .iter()
        .enumerate()
        .map(|(i, p)| match p {
            Some(p)
                if matches!(
                    p.regime,
                    AtlasRegime::BistableQuiet | AtlasRegime::BistableSqueals
                ) =>
            {
                res.basin_fraction(plan, i).0
            }
            _ => f64::NAN,
        })
        .collect();
    let (curves, dashed, marks) = boundary_lines(plan, res, (xa, ya));
    let chart = StabilityChart {
        title: title(plan, Some("stability chart")),
        subtitle: stability_subtitle(plan),
        x_label: axis_label(xa),
        y_label: axis_label(ya),
        xs: &xa.values,
        ys: &ya.values,
        log_x: is_log(&xa.values),
        log_y: is_log(&ya.values),
        classes: &classes,
        palette: regime_classes(),
        field: Some(&field),
        levels: vec![0.25, 0.5, 0.75, 0.9],
        field_name: "basin fraction of steady slip".into(),
        curves,
        dashed,
        marks,
    };
    crate::stability_chart(png, &chart)
}

/// The critical line and the fold's error bars of a stability chart over `(x, y)`, the fold
/// line (drawn dashed on top: under true stick it lies exactly on the critical line, which
/// hid it), and the fold values whose bracket does not hold at dt/2 as marks. A boundary is
/// a value of the y axis over x (bisected in the y parameter) or of the x axis over y.
fn boundary_lines(
    plan: &AtlasPlan,
    res: &AtlasResults,
    (xa, ya): (&ParamAxis, &ParamAxis),
) -> (Vec<Curve>, Vec<Curve>, Vec<Marks>) {
    let (_, dpos) = plan.boundary_axis();
    if dpos.is_none() {
        return (Vec::new(), Vec::new(), Vec::new());
    }
    let place = |bs: Vec<f64>| {
        if dpos == Some(0) {
            (xa.values.clone(), bs)
        } else {
            (bs, ya.values.clone())
        }
    };
    let fold = boundary_values(plan, res, |b| b.fold);
    let line = |label: &str, color: Rgb, bs: Vec<f64>| {
        bs.iter().any(|v| v.is_finite()).then(|| {
            let (xs, ys) = place(bs);
            Curve {
                label: label.into(),
                xs,
                ys,
                color,
                points_only: false,
            }
        })
    };
    let critical = boundary_values(plan, res, |b| b.critical);
    let mut curves = Vec::from_iter(line(
        "critical: above it the operating point is quiet",
        Rgb(120, 0, 160),
        critical,
    ));
    let dashed = Vec::from_iter(line(
        "fold (dashed): above it no start squeals",
        Rgb(0, 0, 0),
        fold.clone(),
    ));
    if let Some(bars) = fold_error_bars(plan, res, &fold) {
        let (xs, ys) = place(bars);
        // The bars run along the bisected axis: the other coordinate repeats each point's.
        let (xs, ys) = match dpos {
            Some(0) => (repeat3(&xs), ys),
            _ => (xs, repeat3(&ys)),
        };
        curves.push(Curve {
            label: "fold uncertainty (covers dt, dt/2, longer horizon)".into(),
            xs,
            ys,
            color: Rgb(90, 90, 90),
            points_only: false,
        });
    }
    let marks = fold_marks(res, &fold, place);
    (curves, dashed, marks)
}

/// The fold values `fold` flagged by [`FOLD_FLAGS`], placed on the chart by `place`.
fn fold_marks(
    res: &AtlasResults,
    fold: &[f64],
    place: impl Fn(Vec<f64>) -> (Vec<f64>, Vec<f64>),
) -> Vec<Marks> {
    FOLD_FLAGS
        .iter()
        .filter_map(|&(label, glyph, fill, flagged)| {
            let vs: Vec<f64> = fold
                .iter()
                .zip(&res.boundaries)
                .map(|(v, b)| match b {
                    Some(b) if flagged(b) => *v,
                    _ => f64::NAN,
                })
                .collect();
            vs.iter().any(|v| v.is_finite()).then(|| {
                let (xs, ys) = place(vs);
                Marks {
                    label: label.into(),
                    xs,
                    ys,
                    glyph,
                    fill,
                }
            })
        })
        .collect()
}

/// A fold value flagged on the chart: its legend label, glyph, fill and which boundaries.
type FoldFlag = (&'static str, Glyph, Rgb, fn(&BoundaryResult) -> bool);

/// The fold values flagged by a glyph (not a line: the fold's own line runs under them).
const FOLD_FLAGS: [FoldFlag; 2] = [
    (
        "fold: the regime changes more than once along the damping (the last change shown)",
        Glyph::Square,
        Rgb(230, 60, 60),
        |b| b.fold.changes > 1,
    ),
    // A fold with an uncertainty has it drawn as an error bar that covers dt/2.
    (
        "fold: bracket moves at dt/2",
        Glyph::Diamond,
        Rgb(250, 220, 0),
        |b| b.fold.half_dt_holds == Some(false) && !b.fold.uncertainty.is_finite(),
    ),
];

/// The fold's error bars, `fold -+ uncertainty` per boundary, as one list of values along
/// the bisected axis: `[lo, hi, NaN]` per boundary (the NaN breaks the line between bars);
/// `None` when no fold has an uncertainty.
fn fold_error_bars(plan: &AtlasPlan, res: &AtlasResults, fold: &[f64]) -> Option<Vec<f64>> {
    let errs = boundary_values(plan, res, |b| Boundary {
        nu: b.fold.uncertainty,
        ..b.fold
    });
    if !errs.iter().any(|e| e.is_finite() && *e > 0.0) {
        return None;
    }
    Some(
        fold.iter()
            .zip(&errs)
            .flat_map(|(&v, &e)| [v - e, v + e, f64::NAN])
            .collect(),
    )
}

/// Each value three times (the other coordinate of [`fold_error_bars`]' triples).
fn repeat3(v: &[f64]) -> Vec<f64> {
    v.iter().flat_map(|&x| [x, x, x]).collect()
}

/// The operating point and the disturbance box of the basin fraction, with their units.
fn stability_subtitle(plan: &AtlasPlan) -> String {
    let op = plan.point.operating;
    let d = plan.point.disturbance;
    let (units, box_units) = match (plan.space.units, plan.disturbance_nondimensional) {
        (Units::Physical, false) => (" (m, m/s)", " (m, m/s)"),
        (Units::Physical, true) => (
            " (m, m/s)",
            " (nondimensional at each point: the default box)",
        ),
        _ => ("", ""),
    };
    format!(
        "operating point ({}, {}){units}; basin fraction of steady slip over x in [{}, {}], x' in [{}, {}]{box_units}",
        op.x, op.v, d.x[0], d.x[1], d.v[0], d.v[1]
    )
}

/// The bifurcation diagram over the one swept axis.
fn bifurcation(plan: &AtlasPlan, res: &AtlasResults, png: &Path) -> Result<(), PlotError> {
    let a = plan.space.axes()[0];
    let (mut curves, top) = cycle_and_band(plan, res, &a.values);
    let (dkey, _) = plan.boundary_axis();
    if a.key == dkey {
        curves.extend(boundary_verticals(plan, res, a, top));
    }
    let y_label = if plan.space.units == Units::Physical {
        "x' at the section x = x* (m/s)"
    } else {
        "x' at the section x = x* (nondimensional)"
    };
    crate::line_plot(
        png,
        &title(plan, None),
        &axis_label(a),
        y_label,
        &curves,
        &[],
        is_log(&a.values),
    )
}

/// The unstable cycle and the stick-slip band at the section against the swept values `xs`
/// (m/s for a physical plan), and the largest value drawn.
fn cycle_and_band(plan: &AtlasPlan, res: &AtlasResults, xs: &[f64]) -> (Vec<Curve>, f64) {
    let scale = |i: usize, v: f64| match plan.space.physical_at(i) {
        Some(ph) => v * ph.scales().velocity,
        None => v,
    };
    let pick = |f: &dyn Fn(&PointResult) -> f64| -> Vec<f64> {
        res.points
            .iter()
            .enumerate()
            .map(|(i, p)| p.as_ref().map_or(f64::NAN, |p| scale(i, f(p))))
            .collect()
    };
    let cyc = pick(&|p| p.cycle.map_or(f64::NAN, |c| c.r_section));
    let band = |k: usize| pick(&|p| p.stick_slip.map_or(f64::NAN, |s| s.r_band[k]));
    let (smin, smean, smax) = (band(0), band(1), band(2));
    let top = smax
        .iter()
        .chain(&cyc)
        .copied()
        .filter(|v| v.is_finite())
        .fold(0.0f64, f64::max);
    // Where no stick-slip oscillation exists beside it (steady slip only) the unstable cycle
    // bounds no basin: drawn apart, as grey dots.
    let only_steady = |i: usize| {
        res.points[i]
            .as_ref()
            .is_some_and(|p| p.regime == AtlasRegime::SteadySlipOnly)
    };
    let split = |keep: bool| -> Vec<f64> {
        cyc.iter()
            .enumerate()
            .map(|(i, &v)| if only_steady(i) == keep { v } else { f64::NAN })
            .collect()
    };
    let none: Vec<f64> = res
        .points
        .iter()
        .map(|p| match p {
            Some(p) if p.cycle.is_none() => 0.0,
            _ => f64::NAN,
        })
        .collect();
    let curve = |label: &str, ys: Vec<f64>, color: Rgb, points_only: bool| Curve {
        label: label.into(),
        xs: xs.to_vec(),
        ys,
        color,
        points_only,
    };
    let mut curves = vec![
        curve(
            "unstable cycle (basin boundary)",
            split(false),
            Rgb(0, 0, 0),
            false,
        ),
        curve("stick-slip: band max", smax, crate::STICK, false),
        curve("stick-slip: mean", smean, Rgb(170, 70, 0), true),
        curve("stick-slip: band min", smin, crate::STICK, false),
    ];
    let alone = split(true);
    if alone.iter().any(|v| v.is_finite()) {
        let label = "unstable cycle, no stick-slip beside it (no basin boundary)";
        curves.push(curve(label, alone, Rgb(150, 150, 150), true));
    }
    if none.iter().any(|v| v.is_finite()) {
        curves.push(curve("no unstable cycle (at 0)", none, crate::STEADY, true));
    }
    // A figure no point has (no unstable cycle beside stick-slip anywhere, no stick-slip
    // anywhere) is left out of the chart and its legend: a curve without a point is refused.
    curves.retain(|c| c.ys.iter().any(|v| v.is_finite()));
    (curves, top)
}

/// The fold and the critical value as vertical lines from 0 to just above `top`, their
/// values (with the axis's units) in the legend.
fn boundary_verticals(plan: &AtlasPlan, res: &AtlasResults, a: &ParamAxis, top: f64) -> Vec<Curve> {
    let units = if a.units == "1" {
        String::new()
    } else {
        format!(" {}", a.units)
    };
    [
        (
            "fold (no start squeals above)",
            Rgb(0, 120, 0),
            boundary_values(plan, res, |b| b.fold),
        ),
        (
            "critical (operating point quiet above)",
            Rgb(120, 0, 160),
            boundary_values(plan, res, |b| b.critical),
        ),
    ]
    .into_iter()
    .filter_map(|(label, color, v)| {
        let x = *v.first().filter(|x| x.is_finite())?;
        Some(Curve {
            label: format!("{label}: {}{units}", crate::fmt_value(x)),
            xs: vec![x, x],
            ys: vec![0.0, 1.05 * top.max(1e-12)],
            color,
            points_only: false,
        })
    })
    .chain(fold_bar(plan, res, &units, top))
    .collect()
}

/// The fold's uncertainty in a bifurcation diagram: a horizontal bar `fold -+ uncertainty`
/// just above the drawn values, its width in the legend.
fn fold_bar(plan: &AtlasPlan, res: &AtlasResults, units: &str, top: f64) -> Option<Curve> {
    let fold = *boundary_values(plan, res, |b| b.fold).first()?;
    let bars = fold_error_bars(plan, res, &[fold])?;
    let e = 0.5 * (bars[1] - bars[0]);
    let y = 1.02 * top.max(1e-12);
    Some(Curve {
        label: format!(
            "fold uncertainty (covers dt, dt/2, longer horizon): +- {}{units}",
            crate::fmt_value(e)
        ),
        xs: bars[..2].to_vec(),
        ys: vec![y, y],
        color: Rgb(90, 90, 90),
        points_only: false,
    })
}
