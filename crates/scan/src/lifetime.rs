//! Transient lifetimes of the leaking stick-slip band, past its crisis.
//!
//! Above the crisis ([`crate::band::crisis_nu`]) the stick-slip band above the unstable
//! cycle has a hole: every run on it falls inside the cycle sooner or later and ends in
//! steady slip. How long it squeals first is its `t_squeal` (the end of its last stuck step,
//! [`squeal_core::classify::t_squeal`]). Near a boundary crisis the mean lifetime grows as
//! a power of the distance from it, `<t> ~ (nu - nu_c)^(-gamma)` (Grebogi, Ott and Yorke,
//! Physica D 7 (1983) 181; Phys. Rev. Lett. 57 (1986) 1284), so the mean lifetime at several
//! distances and the fitted exponent say how sharply squeal stops lasting.
//!
//! **The starts.** `n` starts spread uniformly over the band's sampled span `[s, b]` on the
//! section `x = x*` ([`crate::band::band_span`]): the stretch of the section the band's
//! chaotic orbits visit, above the window where runs still climb away from the cycle.
//!
//! **The runs.** Each start is run with the cycle's trap (`inside_cycle` at the first
//! crossing below `r_u (1 - margin)`), the band rules off, to `t_max`. Inside the cycle no
//! revolution sticks (it lies on the slip branch), so the trap stops a run after its last
//! stuck step: its `t_squeal` is its whole lifetime (test: the same as a run to the fixed
//! point, `crates/scan/tests/scanning/transient.rs`). A run still outside at `t_max` is censored.
//!
//! **The estimate.** The lifetimes of a leaking chaotic set are close to exponential, whose
//! mean with censoring at `t_max` has the maximum-likelihood estimate `(sum of lifetimes +
//! censored x t_max) / exits`; without censoring it is the sample mean, with standard error
//! `sd / sqrt(n)`; with censoring the exponential's `mean / sqrt(exits)` is stated.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use squeal_core::{Classifier, Params, Regime, Setup, State, Trap};

use crate::band::band_span;
use crate::error::ScanError;
use crate::section::{ReturnMap, SectionCycles, Work, section_cycles};
use crate::ulc::CycleSettings;

/// How the lifetimes are measured.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LifetimeSettings {
    /// Starts on the band.
    pub starts: usize,
    /// Runs still squealing at this time are censored.
    pub t_max: f64,
    /// The trap's relative margin below the cycle's crossing.
    pub trap_margin: f64,
}

impl Default for LifetimeSettings {
    fn default() -> Self {
        LifetimeSettings {
            starts: 128,
            t_max: 40_000.0,
            trap_margin: 1e-5,
        }
    }
}

/// The mean lifetime of one sample of runs (times nondimensional).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MeanLifetime {
    /// Runs that left the band (fell inside the cycle) by `t_max`.
    pub exits: usize,
    /// Runs still on it at `t_max`.
    pub censored: usize,
    /// The mean lifetime (`None` if no run left).
    pub mean: Option<f64>,
    /// Its standard error.
    pub se: Option<f64>,
    /// The shortest and longest lifetime seen (of the runs that left).
    pub range: Option<[f64; 2]>,
}

/// The mean of the lifetimes `times` (of runs that left) with `censored` more runs cut at
/// `t_max` (the module's estimate).
pub fn mean_lifetime(times: &[f64], censored: usize, t_max: f64) -> MeanLifetime {
    let n = times.len();
    let sum: f64 = times.iter().sum();
    let range = times.iter().fold(None, |r: Option<[f64; 2]>, &t| match r {
        None => Some([t, t]),
        Some([a, b]) => Some([a.min(t), b.max(t)]),
    });
    let (mean, se) = if n == 0 {
        (None, None)
    } else if censored == 0 {
        let m = sum / n as f64;
        let var = times.iter().map(|t| (t - m).powi(2)).sum::<f64>() / (n.max(2) - 1) as f64;
        (Some(m), Some((var / n as f64).sqrt()))
    } else {
        let m = (sum + censored as f64 * t_max) / n as f64;
        (Some(m), Some(m / (n as f64).sqrt()))
    };
    MeanLifetime {
        exits: n,
        censored,
        mean,
        se,
        range,
    }
}

/// The lifetime of the band at one damping.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BandLifetime {
    /// The damping.
    pub nu: f64,
    /// The unstable cycle's crossing of the section.
    pub r_u: f64,
    /// The span of the starts on the section.
    pub span: [f64; 2],
    /// The mean lifetime.
    pub lifetime: MeanLifetime,
}

/// The mean transient lifetime of the band above the unstable cycle at `setup`.
pub fn band_lifetime(
    setup: Setup,
    cs: &CycleSettings,
    ls: &LifetimeSettings,
) -> Result<BandLifetime, ScanError> {
    let st = setup.stepper()?;
    let nu = setup.params.nu;
    let (mut stats, mut returns) = (Default::default(), 0);
    let SectionCycles::Unstable {
        r, stable_above, ..
    } = section_cycles(&st, cs, &mut stats, &mut returns)
    else {
        return Err(ScanError::Undetermined(format!(
            "nu = {nu}: no unstable cycle, so no band above it to leave"
        )));
    };
    let map = ReturnMap::new(&st, cs.t_return);
    let top = stable_above.unwrap_or(2.0 * r);
    let (s, b) = band_span(&map, r, top, &mut Work::default()).ok_or_else(|| {
        ScanError::Undetermined(format!("nu = {nu}: no band top above the cycle"))
    })?;
    let fp = setup.params.fixed_point();
    let cl = Classifier {
        t_max: ls.t_max,
        trap: Some(Trap {
            r_inner: r * (1.0 - ls.trap_margin),
            r_outer: f64::INFINITY,
        }),
        band_rules: false,
        ..Classifier::default()
    };
    let n = ls.starts.max(1);
    let outcomes: Vec<_> = (0..n)
        .into_par_iter()
        .map(|k| {
            let v = s + (b - s) * (k as f64 + 0.5) / n as f64;
            cl.classify(&st, State { x: fp.x, v })
        })
        .collect();
    let times: Vec<f64> = outcomes
        .iter()
        .filter(|o| o.regime == Regime::SteadySlip)
        .map(|o| o.t_squeal)
        .collect();
    let censored = outcomes
        .iter()
        .filter(|o| o.regime != Regime::SteadySlip)
        .count();
    Ok(BandLifetime {
        nu,
        r_u: r,
        span: [s, b],
        lifetime: mean_lifetime(&times, censored, ls.t_max),
    })
}

/// A weighted least-squares line `y = a + slope x`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PowerLaw {
    /// `gamma` of `<t> ~ (nu - nu_c)^(-gamma)`: minus the slope of `ln <t>` against
    /// `ln (nu - nu_c)`.
    pub exponent: f64,
    /// Its standard error (from the weights; scaled by the reduced chi-square where that
    /// exceeds 1, with at least three points).
    pub se: f64,
    /// `ln <t>` at `nu - nu_c = 1`.
    pub intercept: f64,
    /// Points fitted.
    pub points: usize,
}

/// Fits `ln mean = a - gamma ln d` to `(d, mean, se)` points (`d = nu - nu_c > 0`),
/// weights `(mean / se)^2` (the variance of `ln mean` is about `(se / mean)^2`). `None`
/// with fewer than two usable points.
pub fn fit_power_law(points: &[(f64, f64, f64)]) -> Option<PowerLaw> {
    let pts: Vec<(f64, f64, f64)> = points
        .iter()
        .filter(|(d, m, se)| *d > 0.0 && *m > 0.0 && *se > 0.0 && se.is_finite())
        .map(|&(d, m, se)| (d.ln(), m.ln(), (m / se).powi(2)))
        .collect();
    if pts.len() < 2 {
        return None;
    }
    let sw: f64 = pts.iter().map(|p| p.2).sum();
    let mx = pts.iter().map(|p| p.2 * p.0).sum::<f64>() / sw;
    let my = pts.iter().map(|p| p.2 * p.1).sum::<f64>() / sw;
    let sxx: f64 = pts.iter().map(|p| p.2 * (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| p.2 * (p.0 - mx) * (p.1 - my)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let slope = sxy / sxx;
    let a = my - slope * mx;
    let chi2: f64 = pts
        .iter()
        .map(|p| p.2 * (p.1 - a - slope * p.0).powi(2))
        .sum();
    let dof = pts.len().saturating_sub(2);
    let scale = if dof > 0 {
        (chi2 / dof as f64).max(1.0)
    } else {
        1.0
    };
    Some(PowerLaw {
        exponent: -slope,
        se: (scale / sxx).sqrt(),
        intercept: a,
        points: pts.len(),
    })
}

/// Lifetimes at several dampings above the crisis `nu_c` and their power law.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LifetimeTable {
    /// The crisis they are measured from.
    pub nu_c: f64,
    /// Its uncertainty.
    pub nu_c_uncertainty: f64,
    /// One row per damping (in the order asked).
    pub rows: Vec<BandLifetime>,
    /// Dampings skipped, and why (no unstable cycle there, say).
    pub skipped: Vec<(f64, String)>,
    /// The fit against `nu - nu_c`, of the rows with a mean lifetime above
    /// [`FIT_MIN_PERIODS`] periods.
    pub fit: Option<PowerLaw>,
    /// The exponent fitted against `nu - (nu_c -+ uncertainty)`: how much the crisis's own
    /// uncertainty moves it (`None` where that fit fails).
    pub exponent_at_crisis_ends: [Option<f64>; 2],
}

/// The dampings `nu_c + d` of the table: `d = nu_c x factor`, geometric (ratio 1.25) from
/// 1% above the crisis (at Table 1 about 1.2 times the crisis's own uncertainty) to 7.5%,
/// where most starts already fall through the hole at their first return.
pub const DISTANCE_FACTORS: [f64; 10] = [
    0.01,
    0.0125,
    0.015625,
    0.01953125,
    0.0244140625,
    0.030517578125,
    0.03814697265625,
    0.0476837158203125,
    0.059604644775390625,
    0.07450580596923828,
];

/// Only rows whose mean lifetime is longer than this many natural periods (`2 pi`) enter
/// the fit: the power law of a crisis holds where runs spend many revolutions on the band;
/// farther out most starts fall through the hole at their first return and the mean is
/// about one revolution whatever the damping.
pub const FIT_MIN_PERIODS: f64 = 10.0;

/// Lifetimes at `nu_c (1 + f)` for each `f` of `factors`, and their fit.
pub fn lifetime_table(
    setup: Setup,
    cs: &CycleSettings,
    ls: &LifetimeSettings,
    (nu_c, u): (f64, f64),
    factors: &[f64],
) -> Result<LifetimeTable, ScanError> {
    let mut rows = Vec::new();
    let mut skipped = Vec::new();
    for f in factors {
        let nu = nu_c * (1.0 + f);
        let at = setup.with_params(Params { nu, ..setup.params });
        match band_lifetime(at, cs, ls) {
            Ok(row) => rows.push(row),
            Err(ScanError::Undetermined(why)) => skipped.push((nu, why)),
            Err(e) => return Err(e),
        }
    }
    let long = FIT_MIN_PERIODS * std::f64::consts::TAU;
    let fit_at = |c: f64| {
        let pts: Vec<(f64, f64, f64)> = rows
            .iter()
            .filter_map(|r| Some((r.nu - c, r.lifetime.mean?, r.lifetime.se?)))
            .filter(|p| p.1 > long)
            .collect();
        fit_power_law(&pts)
    };
    Ok(LifetimeTable {
        nu_c,
        nu_c_uncertainty: u,
        fit: fit_at(nu_c),
        exponent_at_crisis_ends: [fit_at(nu_c - u), fit_at(nu_c + u)]
            .map(|f| f.map(|f| f.exponent)),
        skipped,
        rows,
    })
}

/// The lifetimes above one fold as an atlas stores them per boundary ([`lifetime_table`] at
/// the distances [`DISTANCE_FACTORS`] above the crisis): the mean lifetime at the nearest
/// damping where one was measured, and the fitted exponent of the power law. NaN where not
/// measured.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct FoldLifetime {
    /// The damping of the nearest row (about 1% above the crisis).
    pub nu: f64,
    /// The mean lifetime there (nondimensional time).
    pub mean: f64,
    /// Its standard error.
    pub se: f64,
    /// The share of its runs still squealing at `t_max` (censored).
    pub censored: f64,
    /// `gamma` of `<t> ~ (nu - nu_c)^(-gamma)`.
    pub exponent: f64,
    /// Its standard error.
    pub exponent_se: f64,
}

impl Default for FoldLifetime {
    fn default() -> Self {
        FoldLifetime::none()
    }
}

impl FoldLifetime {
    /// Not measured.
    pub fn none() -> FoldLifetime {
        FoldLifetime {
            nu: f64::NAN,
            mean: f64::NAN,
            se: f64::NAN,
            censored: f64::NAN,
            exponent: f64::NAN,
            exponent_se: f64::NAN,
        }
    }

    /// The figures of table `t`: its first row with a mean lifetime, and its fit.
    pub fn of(t: &LifetimeTable) -> FoldLifetime {
        let mut f = FoldLifetime::none();
        if let Some(r) = t.rows.iter().find(|r| r.lifetime.mean.is_some()) {
            let l = &r.lifetime;
            f.nu = r.nu;
            f.mean = l.mean.unwrap_or(f64::NAN);
            f.se = l.se.unwrap_or(f64::NAN);
            f.censored = l.censored as f64 / (l.censored + l.exits).max(1) as f64;
        }
        if let Some(fit) = t.fit {
            f.exponent = fit.exponent;
            f.exponent_se = fit.se;
        }
        f
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Without censoring the estimate is the sample mean with `sd / sqrt(n)`: lifetimes
    /// 1, 2, 3, 4 have mean 2.5 and sample sd sqrt(5/3), so se = sqrt(5/3) / 2. With one
    /// more run censored at 10 the exponential MLE is (10 + 10) / 4 = 5, se 5 / 2.
    #[test]
    fn the_mean_lifetime_in_closed_form() {
        let m = mean_lifetime(&[1.0, 2.0, 3.0, 4.0], 0, 10.0);
        assert_eq!(m.mean, Some(2.5));
        assert!((m.se.unwrap() - (5.0f64 / 3.0).sqrt() / 2.0).abs() < 1e-15);
        assert_eq!(m.range, Some([1.0, 4.0]));
        let c = mean_lifetime(&[1.0, 2.0, 3.0, 4.0], 1, 10.0);
        assert_eq!((c.mean, c.se, c.censored), (Some(5.0), Some(2.5), 1));
        let none = mean_lifetime(&[], 3, 10.0);
        assert_eq!((none.mean, none.se, none.exits), (None, None, 0));
    }

    /// Exact power laws are fitted exactly: `<t> = 7 d^-1.5` at d = 1e-3 ... 1.6e-2 gives
    /// gamma = 1.5 and ln 7. The residual is zero, so the exponent's standard error is the
    /// weights' own, `1 / sqrt(sum w (x - mean x)^2)` (se = 10% of each mean: w = 100).
    #[test]
    fn an_exact_power_law_is_fitted_exactly() {
        let pts: Vec<(f64, f64, f64)> = [1e-3, 2e-3, 4e-3, 8e-3, 1.6e-2]
            .iter()
            .map(|&d: &f64| {
                let m = 7.0 * d.powf(-1.5);
                (d, m, 0.1 * m)
            })
            .collect();
        let f = fit_power_law(&pts).unwrap();
        assert!((f.exponent - 1.5).abs() < 1e-12, "{f:?}");
        assert!((f.intercept - 7f64.ln()).abs() < 1e-10, "{f:?}");
        // Weights 100 each; ln d spaced by ln 2 about their mean: sum (x - mx)^2 =
        // (4 + 1 + 0 + 1 + 4) (ln 2)^2 = 10 (ln 2)^2.
        let want = 1.0 / (100.0 * 10.0 * 2f64.ln().powi(2)).sqrt();
        assert!((f.se - want).abs() < 1e-12, "{} {want}", f.se);
        assert!(fit_power_law(&pts[..1]).is_none());
    }
}
