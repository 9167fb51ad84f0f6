//! Reading an atlas spec's tables into the parts of an [`AtlasPlan`](super::AtlasPlan), one
//! function per part, each checking its keys (errors name the key).

use squeal_core::error::Number;
use squeal_core::{FrictionLaw, State};

use super::{
    AtlasFile, AtlasPlan, BoundariesFile, BoundaryParam, DAMPING_RANGE, MapSettings, ParamAxis,
    SPEED_RANGE, Units, invalid,
};
use crate::atlas::geometry::Region;
use crate::atlas::point::PointSettings;
use crate::bounds::{Rules, count};
use crate::error::ScanError;
use crate::spec::Invalid;

/// The counts of revolutions `[attractor] transient` and `window` may take (stated in
/// docs/atlas-spec.md; a test holds the two together).
pub const ATTRACTOR_REVOLUTIONS: std::ops::RangeInclusive<i64> = 4..=100_000;

/// The point settings: `[cycle]`, `[attractor]`, `[operating_point]`, `[disturbance]`,
/// checked under `rules`.
pub(super) fn point_settings(
    f: &AtlasFile,
    path: &str,
    rules: Rules,
    inv: Invalid,
) -> Result<PointSettings, ScanError> {
    let mut ps = PointSettings::default();
    let cycle = f
        .cycle
        .clone()
        .unwrap_or_default()
        .check(crate::spec::Shape::Atlas, rules, inv)?;
    ps.cycle = cycle.search;
    ps.tangency_iters = cycle.tangency_iters;
    let at = f.attractor.clone().unwrap_or_default();
    for (key, v, slot) in [
        ("attractor.transient", at.transient, &mut ps.transient),
        ("attractor.window", at.window, &mut ps.window),
    ] {
        if let Some(v) = v {
            rules.require(ATTRACTOR_REVOLUTIONS.contains(&v), || {
                invalid(path, key, v, "a count of revolutions in 4..=100000")
            })?;
            *slot = count(key, v, "a count of revolutions", inv)?;
        }
    }
    if let Some(op) = &f.operating_point {
        let d = ps.operating;
        let state = |key: &str, v: f64| match rules {
            Rules::Today => crate::bounds::state(key, v, &inv),
            Rules::Stored => Ok(v),
        };
        ps.operating = State {
            x: state("operating_point.x", op.x.unwrap_or(d.x))?,
            v: state("operating_point.v", op.v.unwrap_or(d.v))?,
        };
    }
    if let Some(b) = &f.disturbance {
        use crate::bounds::{Width, pair, state_range};
        let d = ps.disturbance;
        let range = |key: &str, given: Option<Vec<f64>>, default: [f64; 2]| match (given, rules) {
            (Some(list), Rules::Today) => state_range(key, &list, Width::Positive, &inv),
            (Some(list), Rules::Stored) => pair(key, &list, &inv),
            (None, _) => Ok(default),
        };
        ps.disturbance = Region {
            x: range("disturbance.x", b.x.clone(), d.x)?,
            v: range("disturbance.v", b.v.clone(), d.v)?,
        };
    }
    Ok(ps)
}

/// The basin maps (`[grid]`, `[classifier]`) of a plan in `units` at step `dt`, if asked
/// for, checked under `rules`; their cells' box becomes the disturbance box of `ps`.
pub(super) fn map_settings(
    f: &AtlasFile,
    path: &str,
    dt: f64,
    ps: &mut PointSettings,
    rules: Rules,
    inv: Invalid,
) -> Result<Option<MapSettings>, ScanError> {
    let has_disturbance = f.disturbance.is_some();
    let maps = match (&f.grid, &f.classifier) {
        (None, Some(_)) => {
            return Err(invalid(
                path,
                "classifier",
                "given without [grid]",
                "a [grid] table: the classifier settings are for basin maps",
            ));
        }
        (None, None) => None,
        (Some(g), c) => {
            // A physical spec's grid is in m and m/s, as a scan's ([`physical_grid`]).
            let grid = g.check(rules, &inv)?;
            // The cells' box is the disturbance box: each axis needs two points or more
            // to span one (a single point has no spacing and so no box).
            for (key, a) in [("grid.x0.count", grid.x0), ("grid.v0.count", grid.v0)] {
                if a.count < 2 {
                    return Err(inv(
                        key,
                        a.count.to_string(),
                        "a count >= 2 (an atlas map's cells tile the disturbance box)",
                    ));
                }
            }
            let default = crate::spec::ClassifierSpec::default();
            let c = c.as_ref().unwrap_or(&default);
            let c = c.check(dt, grid.cells(), rules, &inv)?;
            // One box: the basin fraction from the map and from the cycle cover the
            // same initial conditions, the area the cells tile (each cell centred on
            // its grid point, half a spacing beyond the first and last).
            let (hx, hv) = (0.5 * grid.x0.spacing(), 0.5 * grid.v0.spacing());
            let gbox = Region {
                x: [grid.x0.min - hx, grid.x0.max + hx],
                v: [grid.v0.min - hv, grid.v0.max + hv],
            };
            if has_disturbance {
                return Err(invalid(
                    path,
                    "disturbance",
                    format!("x {:?}, v {:?}", ps.disturbance.x, ps.disturbance.v),
                    "no [disturbance] with [grid]: the box the grid's cells cover is the disturbance box",
                ));
            }
            if gbox.area() <= 0.0 {
                return Err(invalid(
                    path,
                    "grid",
                    format!("x0 {:?}, v0 {:?}", gbox.x, gbox.v),
                    "a box of positive area (x0 and v0 each with min < max)",
                ));
            }
            ps.disturbance = gbox;
            Some(MapSettings {
                grid,
                classifier: c.classifier,
                early_stop: c.early_stop,
                trap_margin: c.trap_margin,
                audit_every: c.audit_every,
                sensitivity_samples: c.sensitivity_samples,
            })
        }
    };
    Ok(maps)
}

/// A physical spec's map grid, given in m and m/s, in the model's units: every point has
/// the same units (no key of [`crate::space::SCALE_KEYS`] swept), so one grid serves every map, checked
/// there as a scan's ([`crate::spec::physical::grid_to_nondimensional`]).
pub(super) fn physical_grid(
    plan: &mut AtlasPlan,
    rules: Rules,
    inv: Invalid,
) -> Result<(), ScanError> {
    let (Some(ph), Some(m)) = (plan.space.physical_at(0), plan.maps.as_ref()) else {
        return Ok(());
    };
    plan.space.check_map_units(inv)?;
    let mut grid = m.grid;
    crate::spec::physical::grid_to_nondimensional(&mut grid, &ph, rules, inv)?;
    plan.maps.as_mut().expect("maps").grid = grid;
    Ok(())
}

/// Steps of the atlas's coarse scan along the bisected parameter before the fold's
/// bisection, by default: fewer than `squeal critical`'s [`crate::band::COARSE`] (64) to keep
/// the 64 boundaries of the shipped chart affordable (docs/history/benchmarks.md); flips of the
/// regime closer together than one step (a factor 1.24 over the chart's 1e-4 to 0.1) can hide.
pub const FOLD_COARSE: usize = 32;

/// The boundaries' settings (`[boundaries]`).
pub(super) struct BoundaryPlan {
    pub fold: bool,
    pub critical: bool,
    pub nu_range: [f64; 2],
    pub lambda_range: [f64; 2],
    pub boundary_in: BoundaryParam,
    pub boundary_rtol: f64,
    pub boundary_coarse: usize,
    pub lifetime_starts: usize,
}

/// Reads `[boundaries]`: the bisected parameter, its ranges under the law's own names, the
/// relative width; the values checked under `rules`.
pub(super) fn boundaries(
    f: &AtlasFile,
    path: &str,
    units: Units,
    params: &[ParamAxis],
    rules: Rules,
    inv: Invalid,
) -> Result<BoundaryPlan, ScanError> {
    let law = f.model.law;
    let bd = f.boundaries.clone().unwrap_or_default();
    let (dk, sk) = (law.keys()[0], law.keys()[1]);
    let own = own_ranges(&bd, law, path)?;
    let nu_range = [
        own[0].unwrap_or(DAMPING_RANGE[0]),
        own[1].unwrap_or(DAMPING_RANGE[1]),
    ];
    rules.bound(|| bisection_range(&inv, dk, nu_range, 10.0))?;
    let lambda_range = [
        own[2].unwrap_or(SPEED_RANGE[0]),
        own[3].unwrap_or(SPEED_RANGE[1]),
    ];
    rules.bound(|| bisection_range(&inv, sk, lambda_range, 1e3))?;
    let boundary_in = bisected(&bd, law, path, params)?;
    if units == Units::Physical {
        swept_alone(&bd, boundary_in, path, params)?;
    }
    let boundary_rtol = bd.rtol.unwrap_or(1e-3);
    rules.require(boundary_rtol > 0.0 && boundary_rtol < 0.5, || {
        invalid(
            path,
            "boundaries.rtol",
            Number(boundary_rtol),
            "a relative width in (0, 0.5)",
        )
    })?;
    // The fold's coarse scan before bisecting: one step would see no change of regime it
    // could not bisect; more than 1000 is more verdicts than the chart's whole boundary.
    let coarse = bd.coarse.unwrap_or(FOLD_COARSE as i64);
    rules.require((2..=1000).contains(&coarse), || {
        invalid(
            path,
            "boundaries.coarse",
            coarse,
            "a number of steps in [2, 1000]",
        )
    })?;
    let lifetime_starts = lifetime_starts(&bd, law, boundary_in, rules, inv)?;
    Ok(BoundaryPlan {
        boundary_coarse: count("boundaries.coarse", coarse, "a number of steps", inv)?,
        lifetime_starts,
        fold: bd.fold.unwrap_or(true),
        critical: bd.critical.unwrap_or(true),
        nu_range,
        lambda_range,
        boundary_in,
        boundary_rtol,
    })
}

/// `[boundaries] lifetime_starts`: starts on the band per damping for the transient
/// lifetimes above each fold, 0 (the default) for none, its bound checked under `rules`.
/// They follow the crisis of the band, so only McMillan's laws with boundaries in the
/// damping (as `squeal critical --fold --lifetimes`), and the fold must be asked for.
fn lifetime_starts(
    bd: &BoundariesFile,
    law: FrictionLaw,
    boundary_in: BoundaryParam,
    rules: Rules,
    inv: Invalid,
) -> Result<usize, ScanError> {
    let key = "boundaries.lifetime_starts";
    let n = bd.lifetime_starts.unwrap_or(0);
    let most = crate::bounds::MAX_LIFETIME_STARTS as i64;
    rules.require((0..=most).contains(&n), || {
        inv(
            key,
            n.to_string(),
            "a number of starts in [0, 4096] (0: none)",
        )
    })?;
    let n: usize = count(key, n, "a number of starts", inv)?;
    if n > 0 && !crate::atlas::boundary::crisis_applies(law) {
        return Err(inv(
            key,
            n.to_string(),
            &format!(
                "0 with law {law}: lifetimes follow the crisis of the band, McMillan's laws only"
            ),
        ));
    }
    if n > 0 && (boundary_in != BoundaryParam::Nu || bd.fold == Some(false)) {
        return Err(inv(
            key,
            n.to_string(),
            "0 unless the fold is bisected in the damping (in = \"nu\", fold = true)",
        ));
    }
    Ok(n)
}

/// The bisection ranges under the law's own names (`nu_lo` or `xi_lo`, ...), in the order
/// damping lo, hi, speed lo, hi; the other law's names are refused.
fn own_ranges(
    bd: &BoundariesFile,
    law: FrictionLaw,
    path: &str,
) -> Result<[Option<f64>; 4], ScanError> {
    let (own, foreign) = if law.family().has_own_names() {
        (
            [bd.xi_lo, bd.xi_hi, bd.v_d_lo, bd.v_d_hi],
            [
                ("nu_lo", bd.nu_lo),
                ("nu_hi", bd.nu_hi),
                ("lambda_lo", bd.lambda_lo),
                ("lambda_hi", bd.lambda_hi),
            ],
        )
    } else {
        (
            [bd.nu_lo, bd.nu_hi, bd.lambda_lo, bd.lambda_hi],
            [
                ("xi_lo", bd.xi_lo),
                ("xi_hi", bd.xi_hi),
                ("v_d_lo", bd.v_d_lo),
                ("v_d_hi", bd.v_d_hi),
            ],
        )
    };
    if let Some((k, _)) = foreign.iter().find(|(_, v)| v.is_some()) {
        let (dk, sk) = (law.keys()[0], law.keys()[1]);
        return Err(invalid(
            path,
            &format!("boundaries.{k}"),
            "given",
            &format!(
                "the bisection range under law {}'s names: {dk}_lo, {dk}_hi, {sk}_lo, {sk}_hi",
                law
            ),
        ));
    }
    Ok(own)
}

/// Whether the parameter `key` is swept (more than one value) in `params`.
fn is_swept(params: &[ParamAxis], key: &str) -> bool {
    params.iter().any(|a| a.key == key && a.values.len() > 1)
}

/// The bisected parameter: `in` by the law's own name, else the one swept (damping first),
/// else the damping.
fn bisected(
    bd: &BoundariesFile,
    law: FrictionLaw,
    path: &str,
    params: &[ParamAxis],
) -> Result<BoundaryParam, ScanError> {
    let (dk, sk) = (law.keys()[0], law.keys()[1]);
    let swept = |k: &str| is_swept(params, k);
    Ok(match bd.in_.as_deref() {
        Some(k) if k == dk => BoundaryParam::Nu,
        Some(k) if k == sk => BoundaryParam::Lambda,
        Some(k) => {
            return Err(invalid(
                path,
                "boundaries.in",
                k,
                &format!("\"{dk}\" or \"{sk}\" (law {})", law),
            ));
        }
        None if swept(dk) || swept("c") => BoundaryParam::Nu,
        None if swept(sk) || swept("v_belt") => BoundaryParam::Lambda,
        None => BoundaryParam::Nu,
    })
}

/// A physical plan with boundaries: the bisected parameter must be swept alone along its
/// axis (lambda also moves with k, m, mu_k, g or normal_force, and nu with k and m).
fn swept_alone(
    bd: &BoundariesFile,
    boundary_in: BoundaryParam,
    path: &str,
    params: &[ParamAxis],
) -> Result<(), ScanError> {
    let others: &[&str] = match boundary_in {
        BoundaryParam::Nu => &["m", "k"],
        BoundaryParam::Lambda => &["m", "k", "mu_k", "g", "normal_force"],
    };
    if let Some(k) = others.iter().find(|k| is_swept(params, k)) {
        if bd.fold.unwrap_or(true) || bd.critical.unwrap_or(true) {
            return Err(invalid(
                path,
                "boundaries.in",
                boundary_in.key(),
                &format!(
                    "a parameter that only {} moves: {k} is swept too (set [boundaries] fold = false, critical = false, or bisect in the other one)",
                    boundary_in.physical_key()
                ),
            ));
        }
    }
    Ok(())
}

/// A boundary's bisection range `[lo, hi]` of parameter `key`: `0 < lo < hi <= top`. The
/// error names the key that breaks it (`boundaries.nu_hi` for a bad upper end).
fn bisection_range(inv: Invalid, key: &str, [lo, hi]: [f64; 2], top: f64) -> Result<(), ScanError> {
    let expected = format!("0 < {key}_lo < {key}_hi <= {top}");
    if !(lo.is_finite() && lo > 0.0 && lo < top) {
        return Err(inv(
            &format!("boundaries.{key}_lo"),
            Number(lo).to_string(),
            &expected,
        ));
    }
    if !(hi.is_finite() && hi > 0.0 && hi <= top) {
        return Err(inv(
            &format!("boundaries.{key}_hi"),
            Number(hi).to_string(),
            &expected,
        ));
    }
    if hi <= lo {
        return Err(inv(
            &format!("boundaries.{key}_lo/{key}_hi"),
            format!("[{}, {}]", Number(lo), Number(hi)),
            &expected,
        ));
    }
    Ok(())
}

/// The model at point `i` of `plan`: under [`Rules::Today`] checked (its parameters, and in a
/// physical plan its box and operating point in the model's units), under
/// [`Rules::Stored`] only that a physical system converts to one.
pub(super) fn check_point(
    plan: &AtlasPlan,
    i: usize,
    path: &str,
    rules: Rules,
) -> Result<(), ScanError> {
    let units = plan.space.units;
    let name_err = |name: &str, value: f64, expected: &str| {
        let key = format!("{}.{name}", units.table());
        invalid(path, &key, Number(value), expected)
    };
    let inv = |key: &str, value: String, expected: &str| invalid(path, key, value, expected);
    let Some(p) = plan.space.check_point(i, rules, &inv)? else {
        return Ok(());
    };
    if rules == Rules::Stored {
        return Ok(());
    }
    if units == Units::Physical {
        // The SI box and point, scaled by this point's units, must still be a box and
        // a point the classifier can run from.
        let s = plan.settings_at(i);
        let inv = |key: &str, value: String, expected: &str| {
            invalid(
                path,
                key,
                value,
                &format!(
                    "{expected}, in the model's units at parameter point {i} (lengths \
                     scaled by [physical] m, k, mu_k and g or normal_force)"
                ),
            )
        };
        use crate::bounds::{Width, state, state_range};
        state_range("disturbance.x", &s.disturbance.x, Width::Positive, &inv)?;
        state_range("disturbance.v", &s.disturbance.v, Width::Positive, &inv)?;
        state("operating_point.x", s.operating.x, &inv)?;
        state("operating_point.v", s.operating.v, &inv)?;
    }
    if p.lambda <= 0.0 {
        return Err(name_err(
            if units == Units::Physical {
                "v_belt"
            } else {
                "lambda"
            },
            p.lambda,
            "a belt speed > 0 (lambda <= 0 is outside the model as written)",
        ));
    }
    Ok(())
}
