//! The transient lifetimes above each fold of an atlas (`[boundaries] lifetime_starts`):
//! how long squeal lasts just past the crisis, and how sharply that time diverges towards
//! it, against the swept parameter the folds were found along.

use std::path::{Path, PathBuf};

use squeal_scan::atlas::{AtlasPlan, AtlasResults, BoundaryResult, Units};

use crate::atlas_sheet::{axis_label, is_log, title};
use crate::line::{missing_values, sweep_chart};
use crate::{Curve, Gap, Glyph, PlotError, Rgb};

/// Whether an atlas of `plan` has lifetime charts: it measures lifetimes
/// (`[boundaries] lifetime_starts`) along a line of folds (one swept parameter beside the
/// bisected one).
pub fn has_fold_lifetimes(plan: &AtlasPlan) -> bool {
    plan.lifetime_starts > 0 && plan.boundary_shape().len() == 1
}

/// Draws the mean lifetime about 1% above each fold (in natural periods, or seconds for a
/// physical plan, with its standard
/// error) to `paths[0]` and the exponent of its power law in the distance from the fold
/// (with its standard error) to `paths[1]`, against the swept parameter.
pub fn fold_lifetime_charts(
    plan: &AtlasPlan,
    res: &AtlasResults,
    paths: [&Path; 2],
) -> Result<(), PlotError> {
    let (dkey, _) = plan.boundary_axis();
    let Some(axis) = plan.space.axes().into_iter().find(|a| a.key != dkey) else {
        return Ok(());
    };
    let at = plan
        .space
        .params
        .iter()
        .position(|a| a.key == axis.key)
        .unwrap_or(0);
    let xs: Vec<f64> = (0..res.boundaries.len())
        .map(|j| plan.space.values_at(plan.boundary_setup(j).0)[at])
        .collect();
    let log_x = is_log(&axis.values);
    // Times in natural periods, or in seconds for a physical plan (the time unit at each
    // boundary's parameters).
    let physical = plan.space.units == Units::Physical;
    let per = |j: usize| match plan.space.physical_at(plan.boundary_setup(j).0) {
        Some(ph) if physical => 1.0 / ph.scales().time,
        _ => std::f64::consts::TAU,
    };
    let pick = |f: fn(&BoundaryResult) -> f64, time: bool| -> Vec<f64> {
        (res.boundaries.iter().enumerate())
            .map(|(j, b)| {
                let scale = if time { per(j) } else { 1.0 };
                b.as_ref().map_or(f64::NAN, |b| f(b) / scale)
            })
            .collect()
    };
    let band = |mid: Vec<f64>, err: Vec<f64>, what: &str, color: Rgb| {
        let lo = mid.iter().zip(&err).map(|(m, e)| m - e).collect();
        let hi = mid.iter().zip(&err).map(|(m, e)| m + e).collect();
        let faint = Rgb(color.0 / 2 + 127, color.1 / 2 + 127, color.2 / 2 + 127);
        vec![
            curve(what, &xs, mid, color),
            curve("- 1 standard error", &xs, lo, faint),
            curve("+ 1 standard error", &xs, hi, faint),
        ]
    };
    let x_label = axis_label(axis);
    let blue = Rgb(30, 90, 200);
    let mean = band(
        pick(|b| b.lifetime.mean, true),
        pick(|b| b.lifetime.se, true),
        "mean lifetime about 1% above the fold",
        blue,
    );
    let t = title(
        plan,
        Some("transient squeal just past the fold: mean lifetime"),
    );
    let y = match physical {
        true => "mean time squealing before settling (s)",
        false => "mean time squealing before settling (natural periods)",
    };
    draw(paths[0], (&t, &x_label, y), &mean, log_x)?;
    let exponent = band(
        pick(|b| b.lifetime.exponent, false),
        pick(|b| b.lifetime.exponent_se, false),
        "gamma of <t> ~ (nu - nu_fold)^(-gamma)",
        Rgb(200, 60, 30),
    );
    let t = title(
        plan,
        Some("transient squeal past the fold: divergence exponent"),
    );
    draw(
        paths[1],
        (&t, &x_label, "exponent gamma (1)"),
        &exponent,
        log_x,
    )
}

fn curve(label: &str, xs: &[f64], ys: Vec<f64>, color: Rgb) -> Curve {
    Curve {
        label: label.to_string(),
        xs: xs.to_vec(),
        ys,
        color,
        points_only: false,
    }
}

/// One chart, the swept values without a measurement marked on its floor.
fn draw(
    path: &Path,
    (title, x, y): (&str, &str, &str),
    curves: &[Curve],
    log_x: bool,
) -> Result<(), PlotError> {
    let gaps = vec![Gap {
        label: "not measured (no fold found, or no band above the cycle)".into(),
        xs: missing_values(&curves[..1], log_x),
        glyph: Glyph::TriangleUp,
        color: Rgb(120, 120, 120),
    }];
    sweep_chart(path, title, x, y, curves, log_x, &gaps)
}

/// The two pictures' paths beside an atlas chart `png`: `<stem>-lifetimes.png` and
/// `<stem>-lifetime-exponent.png`.
pub fn fold_lifetime_paths(png: &Path) -> [PathBuf; 2] {
    let stem = png
        .file_stem()
        .map_or("atlas".into(), |s| s.to_string_lossy());
    ["-lifetimes", "-lifetime-exponent"].map(|s| png.with_file_name(format!("{stem}{s}.png")))
}
