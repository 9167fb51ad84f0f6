//! One parameter point to its figures of merit: the unstable cycle, the stick-slip
//! attractor, the regime, and the basin fraction of steady slip over a disturbance box.
//!
//! The cycle is found as in [`crate::ulc`]: a root of `D(r) = P(r) - r` on the section
//! `x = x*, x' > 0`. The search here adds two things:
//! * a **warm start**: a bracket around a neighbour's crossing, checked (`D <= 0` below,
//!   `D > 0` above) before it is trusted, falling back to the cold search otherwise;
//! * a **tangency check** in the cold search: when every sample of `D` is negative, the
//!   largest sample is refined by golden-section search, so that a narrow window of
//!   `D > 0` just below the fold of cycles (where the unstable cycle and the stick-slip
//!   oscillation are about to meet) is not missed between samples.
//!
//! Once bracketed, [`crate::ulc::locate`] bisects and describes the cycle, so the figures are
//! the same as `squeal ulc` gives.

use serde::{Deserialize, Serialize};
use squeal_core::classify::crossing;
use squeal_core::{Params, Setup, SolverStats, State, Stepper, friction};

use crate::error::ScanError;
use crate::section::{self, Bracket, ReturnMap, Search, SectionCycles, search};

use crate::ulc::{CycleReport, CycleSettings, describe_bracket};

/// The regime of one parameter point. Stored as the HDF5 enum `regime`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[repr(u8)]
#[serde(rename_all = "snake_case")]
pub enum AtlasRegime {
    /// The evidence conflicts (the section method says the operating point squeals but its
    /// own run settles, a cycle but no stick-slip attractor found, or a failed run); the
    /// point's note says which.
    Undecided = 0,
    /// No start squeals: `D(r) < 0` on the whole sampled section range.
    SteadySlipOnly = 1,
    /// Steady slip and stick-slip coexist; the operating point is inside the unstable cycle.
    BistableQuiet = 2,
    /// Steady slip and stick-slip coexist; the operating point is outside: it squeals.
    BistableSqueals = 3,
    /// `D(r_min) > 0`: the fixed point repels, or its unstable cycle is smaller than the
    /// search's resolution `r_min` (the label rests on that): every start squeals.
    FixedPointUnstable = 4,
}

impl AtlasRegime {
    /// All regimes, in value order.
    pub const ALL: [AtlasRegime; 5] = [
        AtlasRegime::Undecided,
        AtlasRegime::SteadySlipOnly,
        AtlasRegime::BistableQuiet,
        AtlasRegime::BistableSqueals,
        AtlasRegime::FixedPointUnstable,
    ];

    /// The name in files and output.
    pub fn name(self) -> &'static str {
        match self {
            AtlasRegime::Undecided => "undecided",
            AtlasRegime::SteadySlipOnly => "steady_slip_only",
            AtlasRegime::BistableQuiet => "bistable_quiet",
            AtlasRegime::BistableSqueals => "bistable_squeals",
            AtlasRegime::FixedPointUnstable => "fixed_point_unstable",
        }
    }

    /// Words for legends.
    pub fn description(self) -> &'static str {
        match self {
            AtlasRegime::Undecided => "undecided",
            AtlasRegime::SteadySlipOnly => "steady slip only (no start squeals)",
            AtlasRegime::BistableQuiet => "bistable, operating point quiet",
            AtlasRegime::BistableSqueals => "bistable, operating point squeals",
            AtlasRegime::FixedPointUnstable => "every start squeals (no cycle above r_min)",
        }
    }

    /// From the stored value.
    pub fn from_u8(v: u8) -> Option<AtlasRegime> {
        AtlasRegime::ALL.into_iter().find(|r| *r as u8 == v)
    }

    /// Whether the operating point squeals, where the regime says.
    pub fn operating_point_squeals(self) -> Option<bool> {
        match self {
            AtlasRegime::Undecided => None,
            AtlasRegime::SteadySlipOnly | AtlasRegime::BistableQuiet => Some(false),
            AtlasRegime::BistableSqueals | AtlasRegime::FixedPointUnstable => Some(true),
        }
    }
}

/// A box of the phase plane `[x0, x1] x [v0, v1]` (nondimensional).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Region {
    /// `x` range.
    pub x: [f64; 2],
    /// `x'` range.
    pub v: [f64; 2],
}

impl Region {
    /// Area of the box.
    pub fn area(&self) -> f64 {
        (self.x[1] - self.x[0]) * (self.v[1] - self.v[0])
    }
}

/// Settings of one point's computation.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PointSettings {
    /// Cycle search (`r_max` is raised to `2 lambda` where that is larger).
    pub cycle: CycleSettings,
    /// Golden-section refinements of the largest negative `D` (0: no tangency check).
    pub tangency_iters: u32,
    /// Stick-slip revolutions discarded before the window.
    pub transient: u32,
    /// Stick-slip revolutions in the window.
    pub window: u32,
    /// The operating point (nondimensional).
    pub operating: State,
    /// The disturbance region (nondimensional).
    pub disturbance: Region,
}

impl Default for PointSettings {
    fn default() -> Self {
        PointSettings {
            cycle: CycleSettings {
                rtol: 1e-9,
                ..CycleSettings::default()
            },
            tangency_iters: 24,
            transient: 40,
            window: 40,
            operating: State { x: 0.0, v: 0.0 },
            disturbance: Region {
                x: [-2.0, 4.0],
                v: [-3.0, 3.0],
            },
        }
    }
}

/// The unstable cycle's figures of merit (nondimensional).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct CycleFigures {
    /// `x'` where the cycle crosses `x = x*` going right.
    pub r_section: f64,
    /// Final bisection bracket.
    pub bracket: [f64; 2],
    /// How `r_section` moves when `dt` halves (NaN if not checked or not found).
    pub half_dt_shift: f64,
    /// Distance from the fixed point to the cycle along `+x`.
    pub distance_plus_x: f64,
    /// Smallest distance from the fixed point to the cycle (smallest disturbance that squeals).
    pub min_distance: f64,
    /// Smallest pure velocity kick from steady slip that leaves the cycle.
    pub min_kick: f64,
    /// Period of one revolution.
    pub period: f64,
    /// Floquet multiplier `P'(r_u)`.
    pub multiplier: f64,
    /// Enclosed area.
    pub area: f64,
    /// Extent in `x`.
    pub x_range: [f64; 2],
    /// Extent in `x'`.
    pub v_range: [f64; 2],
    /// Whether the cycle encloses the operating point.
    pub encloses_operating: bool,
}

/// The stick-slip attractor's figures of merit over a window of revolutions.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct StickSlipFigures {
    /// Section amplitudes over the window: min, mean, max.
    pub r_band: [f64; 3],
    /// Relative change of the mean section amplitude from the window's first half to its
    /// second half (near 0 when settled).
    pub drift: f64,
    /// Extent in `x`.
    pub x_range: [f64; 2],
    /// Extent in `x'`.
    pub v_range: [f64; 2],
    /// `max x' - lambda`: how far the block overtakes the belt (negative: it never does).
    pub overshoot: f64,
    /// Mean angular frequency over the window's revolutions.
    pub omega_mean: f64,
    /// Standard deviation of the per-revolution angular frequency.
    pub omega_std: f64,
    /// Share of the window's steps on the quasi-static branch of the law.
    pub quasi_static_share: f64,
}

/// Everything computed at one parameter point.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PointResult {
    /// The regime.
    pub regime: AtlasRegime,
    /// The unstable cycle, where there is one.
    pub cycle: Option<CycleFigures>,
    /// The stick-slip attractor, where it was reached.
    pub stick_slip: Option<StickSlipFigures>,
    /// Share of the disturbance box from which the system returns to steady slip.
    pub basin_fraction: f64,
    /// Its uncertainty (see [`basin_fraction`]).
    pub basin_fraction_err: f64,
    /// Whether the cycle search started from the neighbour's bracket and kept it.
    pub warm_started: bool,
    /// Section returns computed (each one revolution).
    pub returns: u64,
    /// Friction-law evaluations.
    pub evaluations: u64,
    /// Solver failures met.
    pub failures: u64,
    /// Why the point is undecided, if it is.
    pub note: Option<String>,
    /// The landscape and its evidence, for laws with true stick ([`super::stribeck`]).
    #[serde(default)]
    pub landscape: Option<super::stribeck::LandscapeRecord>,
}

pub use crate::section::Work;

/// The section range searched at these parameters: `r_max` at least `2 lambda` (the
/// stick-slip crossing lies below the belt speed, MODEL.md).
pub fn settings_for(p: &Params, cs: &CycleSettings) -> CycleSettings {
    CycleSettings {
        r_max: cs.r_max.max(2.0 * p.lambda),
        ..*cs
    }
}

/// The smallest pure velocity kick from the fixed point that leaves the cycle: the smaller
/// of the cycle's two crossings of `x = x*` (upper `r_section`, lower at `x' < 0`).
pub fn min_kick(rep: &CycleReport, x_star: f64) -> f64 {
    let (xs, vs) = (&rep.curve.x, &rep.curve.v);
    let n = xs.len();
    let mut lower = f64::NAN;
    for i in 0..n {
        let j = (i + 1) % n;
        if (xs[i] - x_star) * (xs[j] - x_star) <= 0.0 && xs[i] != xs[j] {
            let t = (x_star - xs[i]) / (xs[j] - xs[i]);
            let v = vs[i] + t * (vs[j] - vs[i]);
            if v < 0.0 {
                lower = if lower.is_nan() { -v } else { lower.min(-v) };
            }
        }
    }
    if lower.is_nan() {
        rep.r_section
    } else {
        rep.r_section.min(lower)
    }
}

/// Area of the part of the closed polygon `(xs, vs)` inside the box (Sutherland-Hodgman
/// clipping against the box's four half-planes, then the shoelace formula). The clipping
/// is exact for a convex clip region and any simple polygon (degenerate edges it creates
/// enclose no area).
pub fn clipped_area(xs: &[f64], vs: &[f64], region: &Region) -> f64 {
    let mut poly: Vec<(f64, f64)> = xs.iter().copied().zip(vs.iter().copied()).collect();
    // Each half-plane as (axis 0 = x / 1 = v, bound, keep if >= bound when `lower`).
    let planes = [
        (0, region.x[0], true),
        (0, region.x[1], false),
        (1, region.v[0], true),
        (1, region.v[1], false),
    ];
    for (axis, bound, lower) in planes {
        if poly.is_empty() {
            break;
        }
        let coord = |p: &(f64, f64)| if axis == 0 { p.0 } else { p.1 };
        let inside = |p: &(f64, f64)| {
            if lower {
                coord(p) >= bound
            } else {
                coord(p) <= bound
            }
        };
        let mut out = Vec::with_capacity(poly.len() + 4);
        for i in 0..poly.len() {
            let a = poly[i];
            let b = poly[(i + 1) % poly.len()];
            let (ia, ib) = (inside(&a), inside(&b));
            if ia {
                out.push(a);
            }
            if ia != ib {
                let t = (bound - coord(&a)) / (coord(&b) - coord(&a));
                out.push((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)));
            }
        }
        poly = out;
    }
    let n = poly.len();
    if n < 3 {
        return 0.0;
    }
    0.5 * (0..n)
        .map(|i| {
            let j = (i + 1) % n;
            poly[i].0 * poly[j].1 - poly[j].0 * poly[i].1
        })
        .sum::<f64>()
        .abs()
}

/// Basin fraction of steady slip over `region` from the cycle, and its uncertainty: the
/// change when the curve is scaled about the fixed point by `r(dt/2) / r(dt)` (the section
/// crossing's move when the step halves; this assumes the shape moves with its crossing),
/// plus the polygon's chord error (one step's travel times the clipped perimeter, bounded
/// here by `max |x'| dt` times the curve length over the box area).
pub fn basin_fraction(
    rep: &CycleReport,
    half_dt_shift: f64,
    region: &Region,
    fp: State,
) -> (f64, f64) {
    let a = region.area();
    let f = clipped_area(&rep.curve.x, &rep.curve.v, region) / a;
    let mut err = 0.0;
    if half_dt_shift.is_finite() {
        let s = 1.0 + half_dt_shift / rep.r_section;
        let xs: Vec<f64> = rep.curve.x.iter().map(|x| fp.x + s * (x - fp.x)).collect();
        let vs: Vec<f64> = rep.curve.v.iter().map(|v| fp.v + s * (v - fp.v)).collect();
        err += (clipped_area(&xs, &vs, region) / a - f).abs();
    } else {
        err = f64::NAN;
    }
    // Chord error: each chord of length l cuts off at most l * sagitta <= l * (l / 8) * ...
    // bounded crudely by l^2 per chord.
    let n = rep.curve.x.len();
    let chords: f64 = (0..n)
        .map(|i| {
            let j = (i + 1) % n;
            let l = (rep.curve.x[j] - rep.curve.x[i]).hypot(rep.curve.v[j] - rep.curve.v[i]);
            l * l
        })
        .sum();
    (f, err + chords / a)
}

/// Why a stick-slip run did not give the attractor.
#[derive(Clone, Debug, PartialEq)]
pub enum StickFail {
    /// A section crossing fell inside the unstable cycle (below `r_inside`), or the run
    /// reached the fixed point: this start returns to steady slip.
    FellInside {
        /// Time of that crossing.
        t: f64,
    },
    /// The run failed (solver failure, blow-up, no crossing for `t_return`).
    Failed(String),
}

/// Runs the stick-slip attractor from `(x*, r_start)`: `transient` revolutions discarded,
/// then `window` measured. A crossing below `r_inside` (the unstable cycle's crossing; 0 if
/// there is none) means the run fell inside the cycle: in the plane it then cannot leave.
#[allow(clippy::too_many_arguments)] // start, cycle, window lengths and limits are independent
pub fn stick_slip(
    st: &Stepper,
    r_start: f64,
    r_inside: f64,
    transient: u32,
    window: u32,
    t_return: f64,
    stats: &mut SolverStats,
) -> Result<StickSlipFigures, StickFail> {
    let p = *st.params();
    let fp = p.fixed_point();
    let (mut s, _) = st.initial(
        State {
            x: fp.x,
            v: r_start,
        },
        stats,
    );
    let mut crossings = 0u32;
    let mut last_cross = f64::NAN;
    let mut t_last = 0.0;
    let (mut rs, mut omegas) = (Vec::new(), Vec::new());
    let mut x_range = [f64::INFINITY, f64::NEG_INFINITY];
    let mut v_range = [f64::INFINITY, f64::NEG_INFINITY];
    let (mut steps, mut qs) = (0u64, 0u64);
    let total = transient + window;
    while crossings <= total {
        let (n, _) = st.step(&s, stats);
        if stats.failures > 0 || !n.x.is_finite() || n.x.abs() > 1e6 {
            return Err(StickFail::Failed(format!(
                "the stick-slip run failed at t = {:.1}",
                n.t
            )));
        }
        if (n.x - fp.x).hypot(n.v - fp.v) < 1e-3 {
            return Err(StickFail::FellInside { t: n.t });
        }
        if n.t - t_last > t_return {
            return Err(StickFail::Failed(format!(
                "no crossing of the section x = x*, x' > 0 for {t_return} time units without reaching the fixed point: an oscillation that does not surround the fixed point, which the section method cannot measure"
            )));
        }
        if crossings > transient {
            steps += 1;
            qs += u64::from(friction::on_quasi_static_branch(&p, n.v - p.lambda, n.a));
            x_range = [x_range[0].min(n.x), x_range[1].max(n.x)];
            v_range = [v_range[0].min(n.v), v_range[1].max(n.v)];
        }
        if let Some(c) = crossing(fp.x, &s, &n) {
            if c.r < r_inside {
                return Err(StickFail::FellInside { t: c.t });
            }
            crossings += 1;
            t_last = n.t;
            if crossings > transient {
                rs.push(c.r);
                if crossings > transient + 1 {
                    omegas.push(std::f64::consts::TAU / (c.t - last_cross));
                }
            }
            last_cross = c.t;
        }
        s = n;
    }
    // The window is the revolutions between crossing transient+1 and the last one.
    rs.pop();
    let m = rs.len().max(1) as f64;
    let mean = rs.iter().sum::<f64>() / m;
    let half = rs.len() / 2;
    let m1 = rs[..half].iter().sum::<f64>() / half.max(1) as f64;
    let m2 = rs[rs.len() - half..].iter().sum::<f64>() / half.max(1) as f64;
    let no = omegas.len().max(1) as f64;
    let om = omegas.iter().sum::<f64>() / no;
    let var = omegas.iter().map(|o| (o - om).powi(2)).sum::<f64>() / no;
    Ok(StickSlipFigures {
        r_band: [
            rs.iter().copied().fold(f64::INFINITY, f64::min),
            mean,
            rs.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        ],
        drift: (m2 - m1) / mean,
        x_range,
        v_range,
        overshoot: v_range[1] - p.lambda,
        omega_mean: om,
        omega_std: var.sqrt(),
        quasi_static_share: qs as f64 / steps.max(1) as f64,
    })
}

/// The starts tried for stick-slip outside a cycle crossing `r_u` (upper end `hi` of the
/// window where `D > 0` first showed): far out (`max(1.5 r_u, lambda)`), then just outside
/// the cycle. The return map jumps where the orbit starts to stick (D falls from positive to
/// strongly negative), so a start just outside the cycle can overshoot and fall back inside:
/// squeal exists only if some start settles.
fn stick_starts(r_u: f64, lambda: f64) -> [f64; 2] {
    [(1.5 * r_u).max(lambda), r_u * 1.02]
}

/// The stick-slip attractor outside a cycle at `r_u` (0: none), tried from each start.
pub fn find_stick_slip(
    st: &Stepper,
    r_u: f64,
    ps: &PointSettings,
    t_return: f64,
    stats: &mut SolverStats,
) -> Result<StickSlipFigures, StickFail> {
    let lambda = st.params().lambda;
    let starts: Vec<f64> = if r_u > 0.0 {
        stick_starts(r_u, lambda).to_vec()
    } else {
        vec![lambda.max(10.0 * ps.cycle.r_min)]
    };
    let mut last = StickFail::Failed("no start".into());
    for r0 in starts {
        match stick_slip(st, r0, r_u, ps.transient, ps.window, t_return, stats) {
            Ok(s) => return Ok(s),
            Err(e @ StickFail::Failed(_)) => return Err(e),
            Err(e) => last = e,
        }
    }
    Err(last)
}

/// What the section search and the stick-slip runs show at one point (no dt/2 check).
#[derive(Debug)]
pub struct Analysis {
    /// The parameters analysed.
    pub params: Params,
    /// The search's end.
    pub search: Search,
    /// The located cycle, for a bracket.
    pub cycle: Option<CycleReport>,
    /// The stick-slip attractor, if tried.
    pub stick: Option<Result<StickSlipFigures, StickFail>>,
    /// Work done.
    pub work: Work,
}

impl Analysis {
    /// Whether some start squeals (stick-slip reached); `Err` with the reason when the runs
    /// cannot tell.
    pub fn squeals_somewhere(&self) -> Result<bool, String> {
        match (&self.stick, self.search) {
            (Some(Ok(_)), _) => Ok(true),
            (Some(Err(StickFail::FellInside { .. })), _) => Ok(false),
            (Some(Err(StickFail::Failed(e))), _) => Err(e.clone()),
            (None, Search::NoneBelow { .. }) => Ok(false),
            (None, _) => Err("no stick-slip run".into()),
        }
    }
}

/// Searches the cycle, describes it and (if `stick`) looks for the stick-slip attractor.
pub fn analyse(
    setup: Setup,
    ps: &PointSettings,
    warm: Option<f64>,
    stick: bool,
) -> Result<Analysis, ScanError> {
    let st = setup.stepper()?;
    let cs = settings_for(&setup.params, &ps.cycle);
    let mut work = Work::default();
    let found = search(&st, &cs, ps.tangency_iters, warm, &mut work);
    let mut a = Analysis {
        params: setup.params,
        search: found,
        cycle: None,
        stick: None,
        work: Work::default(),
    };
    match found {
        Search::NoneBelow { .. } => {}
        Search::FixedPointUnstable { .. } => {
            if stick {
                a.stick = Some(find_stick_slip(&st, 0.0, ps, cs.t_return, &mut work.stats));
            }
        }
        Search::Bracket { lo, hi, d, .. } => {
            let rep = describe_bracket(&st, &cs, [lo, hi], d, Work::default())?;
            work.returns += rep.returns;
            work.stats.merge(&rep.solver);
            if stick {
                a.stick = Some(find_stick_slip(
                    &st,
                    rep.r_section,
                    ps,
                    cs.t_return,
                    &mut work.stats,
                ));
            }
            a.cycle = Some(rep);
        }
    }
    a.work = work;
    Ok(a)
}

/// How the cycle's crossing moves when `dt` halves (NaN if not found at `dt / 2`): the
/// crossing at `dt / 2` bracketed in `r (1 -+ 2%)` and narrowed by [`ReturnMap::illinois`] to the same
/// tolerance as at `dt`; the whole search range when that bracket does not hold.
fn half_dt_shift(setup: Setup, cs: &CycleSettings, r: f64, w: &mut Work) -> Result<f64, ScanError> {
    let st2 = setup.half_dt().stepper()?;
    let (lo, hi) = (r * 0.98, r * 1.02);
    let map = ReturnMap::new(&st2, cs.t_return);
    let d = [map.d(lo, w), map.d(hi, w)];
    let bracket = Bracket { lo, hi, d };
    if bracket.holds() {
        let (lo, hi) = map.illinois(bracket, cs.rtol, w);
        return Ok(0.5 * (lo + hi) - r);
    }
    Ok(match section::search_section(&map, cs, w) {
        SectionCycles::Unstable { r: r2, .. } => r2 - r,
        _ => f64::NAN,
    })
}

/// All figures at one point; `warm` is a neighbour's section crossing, if known.
pub fn compute_point(
    setup: Setup,
    ps: &PointSettings,
    warm: Option<f64>,
) -> Result<PointResult, ScanError> {
    let mut a = analyse(setup, ps, warm, true)?;
    let cs = settings_for(&setup.params, &ps.cycle);
    let fp = setup.params.fixed_point();
    let mut res = PointResult {
        regime: AtlasRegime::Undecided,
        cycle: None,
        stick_slip: None,
        basin_fraction: f64::NAN,
        basin_fraction_err: f64::NAN,
        warm_started: matches!(a.search, Search::Bracket { warm: true, .. }),
        returns: 0,
        evaluations: 0,
        failures: 0,
        note: None,
        landscape: None,
    };
    if let Some(rep) = &a.cycle {
        let r = rep.r_section;
        let shift = if cs.check_half_dt {
            half_dt_shift(setup, &cs, r, &mut a.work)?
        } else {
            f64::NAN
        };
        res.cycle = Some(CycleFigures {
            r_section: r,
            bracket: rep.bracket,
            half_dt_shift: shift,
            distance_plus_x: rep.distance_plus_x,
            min_distance: rep.distance_to(fp.x, fp.v),
            min_kick: min_kick(rep, fp.x),
            period: rep.period,
            multiplier: rep.multiplier,
            area: rep.area,
            x_range: rep.x_range,
            v_range: rep.v_range,
            encloses_operating: rep.encloses(ps.operating.x, ps.operating.v),
        });
        let (f, e) = basin_fraction(rep, shift, &ps.disturbance, fp);
        res.basin_fraction = f;
        res.basin_fraction_err = e;
    }
    match (&a.search, &a.stick) {
        (Search::NoneBelow { .. }, _) => {
            res.regime = AtlasRegime::SteadySlipOnly;
            res.basin_fraction = 1.0;
            res.basin_fraction_err = 0.0;
        }
        (Search::FixedPointUnstable { .. }, Some(Ok(s))) => {
            res.regime = AtlasRegime::FixedPointUnstable;
            res.stick_slip = Some(*s);
            res.basin_fraction = 0.0;
            res.basin_fraction_err = 0.0;
        }
        (Search::Bracket { .. }, Some(Ok(s))) => {
            res.stick_slip = Some(*s);
            res.regime = if res.cycle.is_some_and(|c| c.encloses_operating) {
                AtlasRegime::BistableQuiet
            } else {
                AtlasRegime::BistableSqueals
            };
        }
        (Search::Bracket { .. }, Some(Err(StickFail::FellInside { t }))) => {
            // An unstable periodic orbit, but no attractor outside it: every start tried
            // falls back inside (the return map jumps past the cycle), so steady slip only.
            res.regime = AtlasRegime::SteadySlipOnly;
            res.basin_fraction = 1.0;
            res.basin_fraction_err = 0.0;
            res.note = Some(format!(
                "an unstable cycle at r = {:.6} but starts outside it fall back inside (t = {t:.1}): no stick-slip attractor",
                res.cycle.map_or(f64::NAN, |c| c.r_section)
            ));
        }
        (_, Some(Err(StickFail::FellInside { t }))) => {
            res.note = Some(format!(
                "D(r_min) > 0 but the run from outside reached the fixed point (t = {t:.1})"
            ));
        }
        (_, Some(Err(StickFail::Failed(e)))) => res.note = Some(e.clone()),
        (_, None) => res.note = Some("no stick-slip run".into()),
    }
    if res.regime == AtlasRegime::BistableSqueals {
        confirm_operating_point(setup, ps, &mut res, &mut a.work)?;
    }
    res.returns = a.work.returns;
    res.evaluations = a.work.stats.evaluations;
    res.failures = a.work.stats.failures;
    Ok(res)
}

/// Checks a "bistable, operating point squeals" label by running the operating point
/// itself to settlement ([`squeal_core::Classifier`], the rules of `squeal classify`).
///
/// The label rests on two section-method findings: the operating point lies outside the
/// unstable cycle, and a run started outside the cycle stayed there for the attractor's
/// `transient + window` revolutions. Just above the fold of cycles that run can sit for
/// that long on the ghost of the vanished stable cycle (a bottleneck where `D` is barely
/// negative) and still end in steady slip: at nu = 0.0299, lambda = 0.803
/// (`scans/atlas-lambda-nu.toml`) rest and big starts all reach the fixed point by
/// t = 450 at dt = 0.005 and 0.0025 while the section method saw a band at r = 0.7968.
/// When the run from the operating point does not end in stick-slip, the evidence
/// conflicts: the point is undecided, with a note naming both findings (never a guess).
fn confirm_operating_point(
    setup: Setup,
    ps: &PointSettings,
    res: &mut PointResult,
    w: &mut Work,
) -> Result<(), ScanError> {
    let st = setup.stepper()?;
    let o = squeal_core::Classifier::default().classify(&st, ps.operating);
    w.stats.merge(&o.stats);
    if o.regime == squeal_core::Regime::Undecided {
        // No verdict within the classifier's t_max (seen at low damping, where the run from
        // near the fixed point grows slowly): no evidence against the label, but it is not
        // confirmed either, and the note says so.
        res.note = Some(format!(
            "unconfirmed: the operating point's own run did not settle by t = {:.0} ({})",
            o.t_decision,
            o.reason.name()
        ));
    } else if o.regime != squeal_core::Regime::StickSlip {
        let band = res.stick_slip.map_or(f64::NAN, |s| s.r_band[1]);
        res.note = Some(format!(
            "conflict: the section method says the operating point squeals (outside the unstable cycle at r = {:.6}, stick-slip band at r = {band:.6} for {} revolutions) but its own run ends {} ({} at t = {:.1})",
            res.cycle.map_or(f64::NAN, |c| c.r_section),
            ps.transient + ps.window,
            o.regime.name(),
            o.reason.name(),
            o.t_decision
        ));
        res.regime = AtlasRegime::Undecided;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use squeal_core::{FrictionLaw, SolverConfig};

    #[test]
    fn clipping_a_square() {
        // Unit square [0,1]^2 against the box [0.5, 2] x [-1, 0.25]: overlap 0.5 * 0.25.
        let xs = [0.0, 1.0, 1.0, 0.0];
        let vs = [0.0, 0.0, 1.0, 1.0];
        let b = Region {
            x: [0.5, 2.0],
            v: [-1.0, 0.25],
        };
        assert!((clipped_area(&xs, &vs, &b) - 0.125).abs() < 1e-15);
        // A box holding the whole square.
        let all = Region {
            x: [-1.0, 2.0],
            v: [-1.0, 2.0],
        };
        assert!((clipped_area(&xs, &vs, &all) - 1.0).abs() < 1e-15);
        // A box missing it.
        let none = Region {
            x: [3.0, 4.0],
            v: [-1.0, 2.0],
        };
        assert_eq!(clipped_area(&xs, &vs, &none), 0.0);
    }

    #[test]
    fn clipping_a_disc_matches_the_closed_form() {
        // Unit disc (2000-gon) clipped by the half-plane x >= 0 inside a big box: pi / 2
        // (up to the polygon's deficit, pi - n/2 sin(2 pi / n) ~ 5e-6).
        let n = 2000;
        let xs: Vec<f64> = (0..n)
            .map(|i| (i as f64 * std::f64::consts::TAU / n as f64).cos())
            .collect();
        let vs: Vec<f64> = (0..n)
            .map(|i| (i as f64 * std::f64::consts::TAU / n as f64).sin())
            .collect();
        let b = Region {
            x: [0.0, 5.0],
            v: [-5.0, 5.0],
        };
        assert!((clipped_area(&xs, &vs, &b) - std::f64::consts::FRAC_PI_2).abs() < 1e-5);
    }

    fn point(law: FrictionLaw, nu: f64, warm: Option<f64>) -> PointResult {
        compute_point(
            Setup::new(Params::paper(law, nu), 0.01, SolverConfig::default()),
            &PointSettings::default(),
            warm,
        )
        .unwrap()
    }

    #[test]
    fn paper_points_reproduce_ulc() {
        for (law, nu, enclosed) in [
            // Paper Figs 9 and 10: the cycle does not enclose rest at 1e-3, does at 1e-2.
            (FrictionLaw::McMillan, 1e-3, false),
            (FrictionLaw::McMillan, 1e-2, true),
            (FrictionLaw::McMillanNonHysteretic, 1e-3, false),
        ] {
            let p = point(law, nu, None);
            let rep = crate::ulc::locate(
                Setup::new(Params::paper(law, nu), 0.01, SolverConfig::default()),
                &CycleSettings::default(),
            )
            .unwrap();
            let c = p.cycle.unwrap();
            // Both bisect the same D to relative widths 1e-9 and 1e-10.
            assert!(
                (c.r_section - rep.r_section).abs() < 2e-9 * rep.r_section,
                "{law} {nu}: {} vs {}",
                c.r_section,
                rep.r_section
            );
            assert!((c.period - rep.period).abs() < 1e-6);
            assert!((c.area - rep.area).abs() < 1e-6 * rep.area);
            assert_eq!(c.encloses_operating, enclosed);
            let want = if enclosed {
                AtlasRegime::BistableQuiet
            } else {
                AtlasRegime::BistableSqueals
            };
            assert_eq!(p.regime, want, "{law} {nu}");
            // The smallest disturbance is no larger than the distance along +x.
            assert!(c.min_distance <= c.distance_plus_x + 1e-12);
            assert!(c.min_kick <= c.r_section);
            let s = p.stick_slip.unwrap();
            // Stick-slip lies outside the unstable cycle.
            assert!(s.r_band[0] > c.r_section);
            assert!(p.basin_fraction > 0.0 && p.basin_fraction < 1.0);
        }
    }

    #[test]
    fn pitch_is_flattened_as_in_the_paper() {
        // Paper Section 5: stick-slip angular frequency about 0.96 at nu = 1e-3 (Fig 9).
        let s = point(FrictionLaw::McMillan, 1e-3, None).stick_slip.unwrap();
        assert!((s.omega_mean - 0.96).abs() < 0.02, "{}", s.omega_mean);
        // The hysteretic law spends time on its quasi-static branch on the loop.
        assert!(s.quasi_static_share > 0.0);
    }

    #[test]
    fn warm_and_cold_starts_agree() {
        for law in [FrictionLaw::McMillan, FrictionLaw::McMillanNonHysteretic] {
            for nu in [2e-3, 1e-2, 1.8e-2] {
                let cold = point(law, nu, None);
                let rc = cold.cycle.unwrap().r_section;
                // A neighbour 10% away.
                let warm = point(law, nu, Some(1.1 * rc));
                assert!(warm.warm_started, "{law} {nu}");
                assert!(!cold.warm_started);
                let rw = warm.cycle.unwrap().r_section;
                // Both brackets end narrower than rtol = 1e-9 relative.
                assert!((rw - rc).abs() <= 2e-9 * rc, "{law} {nu}: {rw} vs {rc}");
                assert!(warm.returns < cold.returns);
            }
        }
    }

    #[test]
    fn regimes_at_the_extremes() {
        // Far above the fold (MODEL.md: between 0.019 and 0.031): no start squeals.
        let p = point(FrictionLaw::McMillan, 0.08, None);
        assert_eq!(p.regime, AtlasRegime::SteadySlipOnly);
        assert_eq!(p.basin_fraction, 1.0);
        // nu = 0: the fixed point repels (MODEL.md), every start squeals.
        let p = point(FrictionLaw::McMillan, 0.0, None);
        assert_eq!(p.regime, AtlasRegime::FixedPointUnstable);
        assert!(p.stick_slip.is_some());
    }

    #[test]
    fn conflicting_evidence_is_undecided() {
        // `scans/atlas-lambda-nu.toml` at nu index 52, lambda index 12, warm-started from
        // the previous point of its line (lambda index 11, crossing 0.52686, as stored by
        // that run at dt = 0.005): the section method found an unstable cycle and a
        // stick-slip band outside it for 80 revolutions, but `squeal trajectory --nu
        // 0.029935772947 --lambda 0.802653930857 --x0 0 --v0 0 --t-end 4000` reaches the
        // fixed point at dt = 0.005 (t = 334) and 0.0025 (t = 451), as do starts at
        // (-4, 0), (1, 2), (-2, -3), (4, 3): evidence that conflicts.
        let p = Params {
            nu: 0.029_935_772_947_204_92,
            lambda: 0.802_653_930_857_430_8,
            ..Params::paper(FrictionLaw::McMillan, 0.0)
        };
        let r = compute_point(
            Setup::new(p, 0.005, SolverConfig::default()),
            &PointSettings::default(),
            Some(0.526_863_078_829_873_4),
        )
        .unwrap();
        assert_eq!(r.regime, AtlasRegime::Undecided, "{r:?}");
        let note = r.note.unwrap();
        assert!(
            note.starts_with("conflict:") && note.contains("steady_slip"),
            "{note}"
        );
        // Where the evidence agrees (paper Fig 9, nu = 1e-3: rest squeals), the label stands.
        let r = compute_point(
            Setup::new(
                Params::paper(FrictionLaw::McMillan, 1e-3),
                0.005,
                SolverConfig::default(),
            ),
            &PointSettings::default(),
            None,
        )
        .unwrap();
        assert_eq!(r.regime, AtlasRegime::BistableSqueals);
        assert!(r.note.is_none());
    }
}
