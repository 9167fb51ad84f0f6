//! The unstable limit cycle: the boundary between the steady-slip and stick-slip basins.
//!
//! Method. Every revolution crosses the section `S = { x = x*, x' > 0 }` once, going right.
//! Let `P(r)` be the return map on `S` (one revolution from `(x*, r)`) and `D(r) = P(r) - r`.
//! Near the stable fixed point `D < 0`; just outside the unstable cycle `D > 0`. So:
//!
//! 1. sample `D` on log-spaced `r` in `[r_min, r_max]` and take the first sign change from
//!    `-` to `+`: a bracket of the cycle's crossing `r_u` of `S`;
//! 2. bisect `D` in that bracket to `rtol` (each evaluation is one revolution);
//! 3. integrate one revolution from `(x*, r_u)`: the closed curve, its period, extent, area
//!    (shoelace), distance from the fixed point along `+x`, whether it encloses a point;
//! 4. the Floquet multiplier is `P'(r_u)` (central difference): above 1, unstable;
//! 5. repeat 1-2 with `dt / 2` to show how the result moves with the step.
//!
//! This is the "periodic orbit" refinement: an unstable cycle of a planar flow is a stable
//! one in reversed time; on the section it is a root of `D`, found by bisection without ever
//! running to settlement. [`verify_rays`] checks the whole curve, not only its section
//! crossing: on rays from the fixed point, a start just inside the curve moves inward and
//! one just outside moves outward, followed for as many revolutions as the Floquet
//! multiplier says the deviation needs to grow.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use squeal_core::classify::Half;
use squeal_core::section::half_return;
use squeal_core::{Params, Setup, SolverConfig, SolverStats, State, Stepper};

use crate::curve::ClosedCurve;
use crate::error::{BracketProblem, NoCycle, ScanError};
use crate::section::{Bracket, ParamRange, ReturnMap, SectionCycles, Work, section_cycles};

pub use crate::section::CycleSettings;

/// How the located cycle moves when `dt` is halved.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct HalfStepCheck {
    /// Section crossing with `dt / 2`.
    pub r_section: f64,
    /// `r(dt/2) - r(dt)`.
    pub shift: f64,
}

/// The located unstable limit cycle (one serialisable record: the store writes it field by
/// field generically, never by hand).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CycleReport {
    /// Model parameters.
    pub params: Params,
    /// Time step.
    pub dt: f64,
    /// Crossing of the section `x = x*, x' > 0` (the cycle's `x'` there).
    pub r_section: f64,
    /// Final bisection bracket on `r_section`.
    pub bracket: [f64; 2],
    /// Period of one revolution.
    pub period: f64,
    /// Angular frequency `2 pi / period`.
    pub omega: f64,
    /// Extent in `x`.
    pub x_range: [f64; 2],
    /// Extent in `x'`.
    pub v_range: [f64; 2],
    /// Distance from the fixed point to the cycle along `+x` (at `x' = 0`).
    pub distance_plus_x: f64,
    /// Enclosed area (shoelace formula).
    pub area: f64,
    /// Floquet multiplier `P'(r_u)`: growth of a small deviation per revolution (> 1: unstable).
    pub multiplier: f64,
    /// Whether the cycle encloses the state at rest `(0, 0)`.
    pub encloses_origin: bool,
    /// The same search with `dt / 2`, if asked for.
    pub half_dt: Option<HalfStepCheck>,
    /// Section returns computed (each one revolution).
    pub returns: u64,
    /// Solver counters over all those runs.
    pub solver: SolverStats,
    /// The stable stick-slip crossing seen above the cycle, if sampled.
    pub stable_above: Option<f64>,
    /// The smallest sampled start outside the cycle whose return falls back inside
    /// ([`crate::section::escape_above`]): when present, the outside of the cycle is not invariant.
    pub escape: Option<f64>,
    /// The closed curve: the states of one revolution.
    pub curve: ClosedCurve,
}

/// A located cycle's figures in SI units (a physical system): lengths in m, velocities in
/// m/s, the period in s, the frequency in Hz.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CycleSi {
    /// The crossing of the section, m/s.
    pub r_section_m_per_s: f64,
    /// Extent in `x`, m.
    pub x_range_m: [f64; 2],
    /// Extent in `x'`, m/s.
    pub v_range_m_per_s: [f64; 2],
    /// Distance beyond the fixed point along `+x`, m.
    pub distance_plus_x_m: f64,
    /// Period, s.
    pub period_s: f64,
    /// Frequency, Hz.
    pub frequency_hz: f64,
    /// Enclosed phase-plane area, m^2/s.
    pub area_m2_per_s: f64,
}

impl std::fmt::Display for CycleSi {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "section x' = {:.4e} m/s; extent x in [{:.4e}, {:.4e}] m, x' in [{:.4e}, {:.4e}] \
             m/s; {:.4e} m beyond the fixed point along +x; period {:.4e} s ({:.2} Hz)",
            self.r_section_m_per_s,
            self.x_range_m[0],
            self.x_range_m[1],
            self.v_range_m_per_s[0],
            self.v_range_m_per_s[1],
            self.distance_plus_x_m,
            self.period_s,
            self.frequency_hz
        )
    }
}

impl CycleReport {
    /// The figures in SI units with the scales `s` of a physical system.
    pub fn si(&self, s: &squeal_core::Scales) -> CycleSi {
        CycleSi {
            r_section_m_per_s: self.r_section * s.velocity,
            x_range_m: self.x_range.map(|x| x * s.length),
            v_range_m_per_s: self.v_range.map(|v| v * s.velocity),
            distance_plus_x_m: self.distance_plus_x * s.length,
            period_s: self.period * s.time,
            frequency_hz: s.hz(self.omega),
            area_m2_per_s: self.area * s.area(),
        }
    }

    /// Whether `(x, v)` lies inside the closed curve.
    pub fn encloses(&self, x: f64, v: f64) -> bool {
        self.curve.encloses(State { x, v })
    }

    /// Distance from `(x, v)` to the curve.
    pub fn distance_to(&self, x: f64, v: f64) -> f64 {
        self.curve.distance_to(State { x, v })
    }
}

/// The closed curve of the cycle crossing the section at `r`: the states of one revolution
/// from `(x*, r)` (the step past the section dropped, so the curve closes on its first
/// point), and the revolution's period; `None` if the run does not return within `t_return`.
pub fn cycle_curve(
    st: &Stepper,
    r: f64,
    t_return: f64,
    stats: &mut SolverStats,
) -> Option<(ClosedCurve, f64)> {
    turn(st, Half::Upper, r, t_return, stats).map(|t| (t.curve, t.period))
}

/// One revolution of the run from amplitude `r` on a half of the line `x = x*` (the section,
/// [`cycle_curve`], or its lower half) to its next crossing of that half.
#[derive(Clone, Debug)]
pub struct Turn {
    /// Its states, the step past the half dropped: closed by that half between the return
    /// and `r`.
    pub curve: ClosedCurve,
    /// Its duration.
    pub period: f64,
    /// The amplitude `|x'|` of its return to the half it started on.
    pub returns_to: f64,
    /// Whether every step had one root on the slip branch: no state of the turn is one
    /// where the force's branch is history ([`squeal_core::friction::on_quasi_static_branch`],
    /// crates/core/MODEL.md section 4), so two orbits meeting it cannot pass each other.
    pub slip_only: bool,
}

/// The revolution from amplitude `r` on `half`, counted in `stats`; `None` if the run does
/// not return within `t_return`.
pub fn turn(
    st: &Stepper,
    half: Half,
    r: f64,
    t_return: f64,
    stats: &mut SolverStats,
) -> Option<Turn> {
    let p = *st.params();
    let (mut xs, mut vs, mut quasi) = (Vec::new(), Vec::new(), false);
    let mut own = SolverStats::default();
    let c = half_return(st, half, r, t_return, &mut own, |s| {
        xs.push(s.x);
        vs.push(s.v);
        quasi |= squeal_core::friction::on_quasi_static_branch(&p, s.v - p.lambda, s.a);
    });
    stats.merge(&own);
    let c = c.ok()?;
    xs.pop();
    vs.pop();
    Some(Turn {
        curve: ClosedCurve::new(xs, vs),
        period: c.t,
        returns_to: c.r,
        slip_only: !quasi && own.multi_root == 0,
    })
}

/// A map's cycle search result: the cycle, or why there is none.
pub type CycleOutcome = Result<CycleReport, NoCycle>;

/// Locates the unstable cycle for one parameter set.
pub fn locate(setup: Setup, cs: &CycleSettings) -> Result<CycleReport, ScanError> {
    let st = setup.stepper()?;
    let mut stats = SolverStats::default();
    let mut returns = 0u64;
    let found = section_cycles(&st, cs, &mut stats, &mut returns);
    locate_from(&st, found, cs, stats, returns)
}

/// Finishes the cycle from an existing search of the section (so a scan searches once per
/// map): the curve, period, size, multiplier and the half-step check. `stats` and `returns`
/// are the counters of the search so far.
pub fn locate_from(
    st: &Stepper,
    found: SectionCycles,
    cs: &CycleSettings,
    mut stats: SolverStats,
    mut returns: u64,
) -> Result<CycleReport, ScanError> {
    let setup = st.setup();
    let (params, dt) = (setup.params, setup.dt);
    let damping = crate::error::Damping::of(&params);
    let (r, lo, hi, stable_above, escape) = match found {
        SectionCycles::Unstable {
            r,
            lo,
            hi,
            stable_above,
            escape,
        } => (r, lo, hi, stable_above, escape),
        SectionCycles::NoneBelow { r_max, .. } => {
            return Err(NoCycle::Decays { r_max, damping }.into());
        }
        SectionCycles::FixedPointUnstable { r_min } => {
            return Err(NoCycle::FixedPointRepels { r_min, damping }.into());
        }
    };
    returns += 1;
    let (curve, period) = cycle_curve(st, r, cs.t_return, &mut stats).ok_or(NoCycle::NoReturn {
        r,
        t_return: cs.t_return,
    })?;
    let fp = params.fixed_point();
    let h = 1e-4 * r;
    let map = ReturnMap::new(st, cs.t_return);
    let mut w = Work::default();
    let p_plus = map.d(r + h, &mut w) + r + h;
    let p_minus = map.d(r - h, &mut w) + r - h;
    stats.merge(&w.stats);
    returns += w.returns;
    let multiplier = (p_plus - p_minus) / (2.0 * h);
    // Crossing of v = 0 with x > x* (going down, on the right of the fixed point).
    let distance_plus_x = curve
        .distance_along_ray(State { x: fp.x, v: 0.0 }, 0.0)
        .unwrap_or(f64::NAN);
    let half_dt = match cs.check_half_dt {
        true => half_step_check(&setup, cs, r, &mut stats, &mut returns)?,
        false => None,
    };
    Ok(CycleReport {
        params,
        dt,
        r_section: r,
        bracket: [lo, hi],
        period,
        omega: std::f64::consts::TAU / period,
        x_range: curve.x_range(),
        v_range: curve.v_range(),
        distance_plus_x,
        area: curve.area(),
        multiplier,
        encloses_origin: curve.encloses(State { x: 0.0, v: 0.0 }),
        half_dt,
        returns,
        solver: stats,
        stable_above,
        escape,
        curve,
    })
}

/// The cycle found again with `dt / 2` (counted in `stats` and `returns`): its crossing and
/// the shift from `r`; `None` where that search finds no unstable cycle.
fn half_step_check(
    setup: &Setup,
    cs: &CycleSettings,
    r: f64,
    stats: &mut SolverStats,
    returns: &mut u64,
) -> Result<Option<HalfStepCheck>, ScanError> {
    let st2 = setup.half_dt().stepper()?;
    Ok(match section_cycles(&st2, cs, stats, returns) {
        SectionCycles::Unstable { r: r2, .. } => Some(HalfStepCheck {
            r_section: r2,
            shift: r2 - r,
        }),
        _ => None,
    })
}

/// Which way a start near the cycle moved on the section `x = x*`, `x' > 0`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Drift {
    /// Its distance below the cycle's crossing grew by the required factor (or it came to rest
    /// at the fixed point): it lies in the steady-slip basin.
    Inward,
    /// Its distance above the cycle's crossing grew by the required factor: stick-slip basin.
    Outward,
    /// Neither within the revolution budget (or the solver failed).
    Undecided,
}

/// What one start of a ray did.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct RayStart {
    /// The verdict.
    pub drift: Drift,
    /// Section crossings followed.
    pub revolutions: u32,
    /// `x'` at the first crossing of the section.
    pub r_first: f64,
    /// `x'` at the last crossing (the first one that decided, if any).
    pub r_last: f64,
}

/// One ray of [`verify_rays`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct RayCheck {
    /// Angle of the ray from the fixed point (radians, from `+x`).
    pub angle: f64,
    /// Distance from the fixed point to the cycle along the ray.
    pub radius: f64,
    /// The start at `radius (1 - eps)`.
    pub inner: RayStart,
    /// The start at `radius (1 + eps)`.
    pub outer: RayStart,
}

impl RayCheck {
    /// The cycle separates the basins on this ray: inside moves in, outside moves out.
    pub fn agrees(&self) -> bool {
        self.inner.drift == Drift::Inward && self.outer.drift == Drift::Outward
    }
}

/// The result of [`verify_rays`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RayVerification {
    /// Relative offset of the starts from the cycle along each ray.
    pub eps: f64,
    /// Factor by which a start's distance from the cycle's section crossing must grow.
    pub growth: f64,
    /// One-sided Floquet multipliers `(P(r_u) - P(r_u - h)) / h` and `(P(r_u + h) - P(r_u)) / h`
    /// with `h = 1e-3 r_u` (the return map `P` may have a kink at the cycle).
    pub multipliers: [f64; 2],
    /// Revolutions allowed per start: `3 ln(growth) / ln(m)` plus 10 with `m` the smaller
    /// one-sided multiplier (the growth needs `ln(growth) / ln(m)` of them where the
    /// linearisation holds).
    pub revolutions_max: u32,
    /// The rays.
    pub rays: Vec<RayCheck>,
}

impl RayVerification {
    /// Rays on which the cycle separates the basins.
    pub fn agreeing(&self) -> usize {
        self.rays.iter().filter(|r| r.agrees()).count()
    }

    /// Whether every ray agrees.
    pub fn passed(&self) -> bool {
        !self.rays.is_empty() && self.agreeing() == self.rays.len()
    }
}

/// Factor by which a start's deviation from the cycle must grow before it counts as moved.
pub const RAY_GROWTH: f64 = 3.0;

/// Revolutions allowed per start for deviations growing by `multiplier` per revolution.
pub fn ray_revolutions(multiplier: f64, growth: f64) -> Result<u32, ScanError> {
    if !(multiplier.is_finite() && multiplier > 1.0) {
        return Err(ScanError::RayCheck(format!(
            "Floquet multiplier {multiplier}: deviations from the cycle do not grow, so the ray \
             check cannot tell its sides apart"
        )));
    }
    let n = 3.0 * growth.ln() / multiplier.ln() + 10.0;
    if n > 1e6 {
        return Err(ScanError::RayCheck(format!(
            "Floquet multiplier {multiplier}: a deviation needs {n:.0} revolutions to grow \
             {growth}-fold; too slow to verify by simulation"
        )));
    }
    Ok(n.ceil() as u32)
}

/// Follows a start over section crossings until its distance from `r_u` has grown
/// `growth`-fold from the first crossing, on either side (or `revolutions_max` crossings
/// pass).
fn follow(
    st: &Stepper,
    start: State,
    r_u: f64,
    growth: f64,
    revolutions_max: u32,
    t_return: f64,
) -> RayStart {
    let fp = st.params().fixed_point();
    let mut stats = SolverStats::default();
    let (mut s, _) = st.initial(start, &mut stats);
    let steps_per_return = (t_return / st.dt()).ceil() as u64;
    let mut out = RayStart {
        drift: Drift::Undecided,
        revolutions: 0,
        r_first: f64::NAN,
        r_last: f64::NAN,
    };
    let mut since = 0u64;
    while out.revolutions < revolutions_max {
        let (n, _) = st.step(&s, &mut stats);
        if stats.failures > 0 || !n.x.is_finite() || !n.v.is_finite() {
            return out;
        }
        since += 1;
        if let Some(c) = squeal_core::classify::crossing(fp.x, &s, &n) {
            since = 0;
            out.revolutions += 1;
            out.r_last = c.r;
            if out.revolutions == 1 {
                out.r_first = c.r;
            } else {
                let (d0, d) = (out.r_first - r_u, c.r - r_u);
                if d.abs() >= growth * d0.abs() {
                    out.drift = if d < 0.0 {
                        Drift::Inward
                    } else {
                        Drift::Outward
                    };
                    return out;
                }
            }
        } else if since > steps_per_return {
            // No crossing for a whole return time: at rest on the fixed point (steady
            // slip) if the last crossing was inside, else undecided.
            if out.r_last < r_u {
                out.drift = Drift::Inward;
            }
            return out;
        }
        s = n;
    }
    out
}

/// Checks the located cycle on `rays` rays from the fixed point: a start at `1 - eps` of
/// the cycle's distance along the ray must move inward (its distance below the cycle's
/// section crossing grows [`RAY_GROWTH`]-fold), one at `1 + eps` outward. The number of
/// revolutions allowed follows from the cycle's Floquet multiplier (a deviation grows by it
/// per revolution), so slowly diverging cycles (multiplier 1.0064 at nu = 1e-3) get the
/// hundreds of revolutions they need.
pub fn verify_rays(
    report: &CycleReport,
    rays: usize,
    eps: f64,
    solver: SolverConfig,
) -> Result<RayVerification, ScanError> {
    if !(eps > 0.0 && eps < 0.5) {
        return Err(ScanError::RayCheck(format!(
            "ray offset eps = {eps}: expected a value in (0, 0.5)"
        )));
    }
    let st = Stepper::new(report.params, report.dt, solver)?;
    let fp = report.params.fixed_point();
    // Longest wait for one return: ten periods of the cycle.
    let t_return = 10.0 * report.period;
    let r_u = report.r_section;
    let h = 1e-3 * r_u;
    let once = |r: f64| {
        follow(
            &st,
            State { x: fp.x, v: r },
            r_u,
            f64::INFINITY,
            1,
            t_return,
        )
        .r_last
    };
    // A start on the section does not count as a crossing: the first one is P(r). One-sided
    // slopes of P around the reported crossing (P(r_u) = r_u only if the cycle is right).
    let p_u = once(r_u);
    let multipliers = [(p_u - once(r_u - h)) / h, (once(r_u + h) - p_u) / h];
    let revolutions_max = ray_revolutions(multipliers[0].min(multipliers[1]), RAY_GROWTH)?;
    let checks = (0..rays)
        .into_par_iter()
        .map(|k| {
            let angle = std::f64::consts::TAU * k as f64 / rays as f64;
            let (c, s) = (angle.cos(), angle.sin());
            let radius = report
                .curve
                .distance_along_ray(fp, angle)
                .ok_or(ScanError::RayMissesCurve { angle })?;
            let at = |f: f64| State {
                x: fp.x + f * radius * c,
                v: fp.v + f * radius * s,
            };
            let run = |f: f64| {
                follow(
                    &st,
                    at(f),
                    report.r_section,
                    RAY_GROWTH,
                    revolutions_max,
                    t_return,
                )
            };
            Ok(RayCheck {
                angle,
                radius,
                inner: run(1.0 - eps),
                outer: run(1.0 + eps),
            })
        })
        .collect::<Result<Vec<_>, ScanError>>()?;
    Ok(RayVerification {
        eps,
        growth: RAY_GROWTH,
        multipliers,
        revolutions_max,
        rays: checks,
    })
}

/// The damping at which the unstable cycle first encloses `point`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CriticalReport {
    /// The state that must be enclosed.
    pub point: State,
    /// Best estimate (geometric middle of the bracket).
    pub nu: f64,
    /// `[nu_lo, nu_hi]`: not enclosed at `nu_lo`, enclosed at `nu_hi`.
    pub bracket: [f64; 2],
    /// Cycle locations made.
    pub evaluations: u32,
}

/// Where `point` lies relative to the unstable cycle for one parameter set.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PointSide {
    /// Inside the cycle: that start ends in steady slip.
    Inside,
    /// Outside the cycle: that start squeals.
    Outside,
    /// Outside the cycle, but the stick-slip band above it leaks
    /// ([`crate::band::Band::Leaks`]): runs from outside fall back inside sooner or later,
    /// so that start does not squeal for good (the scan labels no run there stick-slip).
    OutsideBandLeaks,
    /// No unstable cycle below `r_max`: the return map decays at every sampled amplitude.
    NoCycle,
    /// The return map grows already at `r_min`: the fixed point repels.
    FixedPointRepels,
}

/// Where `point` lies relative to the unstable cycle for these parameters.
pub fn point_side(setup: Setup, cs: &CycleSettings, point: State) -> Result<PointSide, ScanError> {
    let st = setup.stepper()?;
    let (mut stats, mut returns) = (SolverStats::default(), 0u64);
    let found = section_cycles(&st, cs, &mut stats, &mut returns);
    match found {
        SectionCycles::NoneBelow { .. } => return Ok(PointSide::NoCycle),
        SectionCycles::FixedPointUnstable { .. } => return Ok(PointSide::FixedPointRepels),
        SectionCycles::Unstable { .. } => {}
    }
    let cs1 = CycleSettings {
        check_half_dt: false,
        ..*cs
    };
    let rep = locate(setup, &cs1)?;
    if rep.encloses(point.x, point.v) {
        return Ok(PointSide::Inside);
    }
    // The scan's rule for the band ([`crate::scanner::outside_of`]): the same verdict here.
    let leaks = matches!(
        crate::band::outside_of(&st, cs, &found),
        Some(crate::band::Outside::Escapes {
            band: crate::band::Band::Leaks { .. },
            ..
        })
    );
    Ok(if leaks {
        PointSide::OutsideBandLeaks
    } else {
        PointSide::Outside
    })
}

/// Whether the system at `point` does not squeal for these parameters: inside the unstable
/// cycle, or no unstable cycle below `r_max` at all (the return map decays everywhere); a
/// repelling fixed point counts as squealing.
pub fn point_enclosed(setup: Setup, cs: &CycleSettings, point: State) -> Result<bool, ScanError> {
    Ok(matches!(
        point_side(setup, cs, point)?,
        PointSide::Inside | PointSide::NoCycle | PointSide::OutsideBandLeaks
    ))
}

/// The coarse scan `squeal critical` makes before trusting its bisection of [`critical_nu`]:
/// every change of [`point_enclosed`] between [`crate::band::COARSE`] geometric steps of
/// `nu` over `(lo, hi)` ([`crate::section::coarse_changes`]).
pub fn coarse_enclosed(
    setup: Setup,
    cs: &CycleSettings,
    point: State,
    (lo, hi): (f64, f64),
) -> Result<Vec<crate::section::Change>, ScanError> {
    crate::section::coarse_changes(
        |nu| {
            let p = squeal_core::Params { nu, ..setup.params };
            point_enclosed(setup.with_params(p), cs, point)
        },
        (lo, hi),
        crate::band::COARSE,
    )
}

/// Bisection in `nu` (geometric) for the damping at which the cycle first encloses `point`.
pub fn critical_nu(
    setup: Setup,
    cs: &CycleSettings,
    point: State,
    range: ParamRange,
) -> Result<CriticalReport, ScanError> {
    let base = setup.params;
    let ParamRange {
        lo: nu_lo,
        hi: nu_hi,
        rtol,
    } = range;
    let side = |nu: f64| point_side(setup.with_params(Params { nu, ..base }), cs, point);
    let at = |nu: f64| -> Result<bool, ScanError> {
        Ok(matches!(
            side(nu)?,
            PointSide::Inside | PointSide::NoCycle | PointSide::OutsideBandLeaks
        ))
    };
    let bracket = |problem| ScanError::Bracket {
        nu_lo,
        nu_hi,
        x: point.x,
        v: point.v,
        problem,
    };
    if !(nu_lo > 0.0 && nu_hi > nu_lo && nu_hi.is_finite()) {
        return Err(bracket(BracketProblem::Order));
    }
    let fp = base.fixed_point();
    if point == fp {
        return Err(ScanError::NoCriticalDamping(format!(
            "({}, {}) is the fixed point, where a start stays at every nu: no damping is critical \
             for it",
            point.x, point.v
        )));
    }
    match side(nu_lo)? {
        PointSide::Inside | PointSide::OutsideBandLeaks => {
            return Err(bracket(BracketProblem::EnclosedAtLow));
        }
        PointSide::NoCycle => {
            return Err(ScanError::NoCriticalDamping(format!(
                "at the lower bound nu = {nu_lo} {} has no unstable limit cycle (the return \
                 map decays at every amplitude up to r = {}), so ({}, {}) ends in steady slip \
                 there already",
                base.law, cs.r_max, point.x, point.v
            )));
        }
        PointSide::Outside | PointSide::FixedPointRepels => {}
    }
    if !at(nu_hi)? {
        return Err(bracket(BracketProblem::NotEnclosedAtHigh));
    }
    let ((lo, hi), evaluations) =
        crate::section::geometric_bisection(at, (nu_lo, nu_hi), rtol, 200)?;
    Ok(CriticalReport {
        point,
        nu: (lo * hi).sqrt(),
        bracket: [lo, hi],
        evaluations,
    })
}

/// Narrows `[lo, hi]` with [`ReturnMap::illinois`] and describes the cycle there
/// ([`crate::ulc::locate_from`]: curve, period, multiplier, area). Falls back to
/// [`crate::ulc::locate`] on the range when the bracket does not hold (`D(lo) > 0` or
/// `D(hi) <= 0`).
pub fn describe(
    setup: Setup,
    cs: &CycleSettings,
    lo: f64,
    hi: f64,
) -> Result<CycleReport, ScanError> {
    let st = setup.stepper()?;
    let mut w = Work::default();
    let map = ReturnMap::new(&st, cs.t_return);
    let (d_lo, d_hi) = (map.d(lo, &mut w), map.d(hi, &mut w));
    describe_bracket(&st, cs, [lo, hi], [d_lo, d_hi], w)
}

/// [`describe`] with the bracket's `D` values known; `w` is the work so far (counted in
/// the report).
pub fn describe_bracket(
    st: &Stepper,
    cs: &CycleSettings,
    [lo, hi]: [f64; 2],
    [d_lo, d_hi]: [f64; 2],
    mut w: Work,
) -> Result<CycleReport, ScanError> {
    let narrow = CycleSettings {
        r_min: lo,
        r_max: hi,
        samples: 2,
        check_half_dt: false,
        ..*cs
    };
    if !(d_lo <= 0.0 && d_hi > 0.0) {
        return locate(st.setup(), &narrow);
    }
    let bracket = Bracket {
        lo,
        hi,
        d: [d_lo, d_hi],
    };
    let (lo, hi) = ReturnMap::new(st, cs.t_return).illinois(bracket, cs.rtol, &mut w);
    let found = SectionCycles::Unstable {
        r: 0.5 * (lo + hi),
        lo,
        hi,
        stable_above: None,
        escape: None,
    };
    locate_from(st, found, &narrow, w.stats, w.returns)
}
