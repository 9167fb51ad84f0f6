//! Boundaries in the damping `nu` or the belt speed `lambda` ([`BoundaryParam`]), located
//! by bisection (not read off pixels):
//!
//! * the **fold** [`fold_nu`]: the damping above which no start squeals for good. For
//!   McMillan's hysteretic law it is the crisis of the stick-slip band ([`fold_crisis`],
//!   [`crate::band::crisis_in`]: a coarse scan for every change of regime, bisections at
//!   dt, an uncertainty covering dt/2 and a longer horizon). For the non-hysteretic law and
//!   laws with true stick it is the bisection of "some start stays on stick-slip for the
//!   attractor's window" ([`quiet_everywhere`]; why: [`crisis_applies`]).
//! * the **critical damping** [`critical_nu`] of the operating point: the damping at which
//!   the unstable cycle first encloses it, or (hysteretic law) the band above the cycle
//!   leaks (from then on it does not squeal). Above the fold
//!   there is no cycle and nothing squeals, which counts as enclosed (as in
//!   [`crate::ulc::point_enclosed`]), so the critical damping never exceeds the fold. Its
//!   bisection counts an undecided band as squealing; where it finds such a value above
//!   the crisis's interval (a window the coarse scan stepped over), the fold's interval is
//!   raised to cover it ([`cover_critical`]), so the critical damping lies at or below the
//!   fold's upper end at every belt speed.
//!
//! Both bisect geometrically to a relative bracket width `rtol`; the bracket is stored with
//! the value. When the predicate does not change sign over `[lo, hi]`, the status says on
//! which side the boundary lies. In `lambda` the same predicates are bisected: the
//! operating point is quiet above the **critical belt speed** ([`critical_in`]) and no
//! start squeals above the **fold in lambda** ([`fold_in`]). The crisis's coarse scan finds
//! every change of regime along the parameter (more than one: `Boundary::changes`); the
//! other bisections assume one change in the range, and a second crossing is not looked
//! for there.
//!
//! Each bisection step warm-starts its cycle search from the crossing at the nearest value
//! already analysed ([`Crossings`]; the warm bracket is kept only once checked, as for the
//! points along a line), and the shared search ([`both_in`]) runs the stick-slip attractor
//! only where a predicate needs it.
//!
//! **Accuracy of the window predicate (why the hysteretic fold is now the crisis).** Near
//! the fold the predicate is not a clean step: whether a start outside the cycle stays on stick-slip for
//! the attractor window depends on digits far below any tolerance (runs linger on the ghost
//! of the vanished stable cycle, or in a band the return map can jump out of, and then fall
//! inside). A change of the cycle's crossing by 1e-10 (false position instead of bisection,
//! or a warm instead of a cold search) moved the bisected fold on the 64 x 64 chart
//! (`scans/atlas-lambda-nu.toml`) by more than its 1e-3 bracket at 40-44 of 64 belt speeds
//! (median 0.4%, up to 10%, the largest below lambda = 1.3; the critical damping too where
//! it equals the fold). So [`both_in`] checks every bracket at `dt / 2`: the predicate again
//! at both ends ([`Boundary::half_dt_holds`], stored as `fold_half_dt` and
//! `critical_half_dt`). On that chart the fold's bracket holds at dt / 2 at 15 of 64 belt
//! speeds and the critical damping's at 44 (those where the cycle comes to enclose rest,
//! a sharp predicate).

use serde::{Deserialize, Serialize};
use squeal_core::{Params, Setup, State};

use super::attractor::{StickFail, find_stick_slip};
use super::note::Note;
use super::point::{PointSettings, analyse, settings_for};
use crate::band::{Budget, Crisis, CrisisStatus, SharedReturns, Variant, crisis_in};
use crate::error::ScanError;
use crate::section::{Change, ParamRange, Search, coarse_changes};

/// The boundaries of one combination of the non-damping axes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BoundaryResult {
    /// Index into the boundary array.
    pub index: usize,
    /// The fold of cycles (damping above which no start squeals).
    pub fold: Boundary,
    /// The damping at which the operating point stops squealing.
    pub critical: Boundary,
    /// The transient lifetimes above the fold (`[boundaries] lifetime_starts`; NaN where
    /// not measured).
    #[serde(default)]
    pub lifetime: crate::lifetime::FoldLifetime,
    /// Why a search was not computed (a failed run), or what the coarse scan found.
    pub note: Option<Note>,
}

/// The parameter a boundary is bisected in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BoundaryParam {
    /// The damping ratio `nu` (paper Section 4; `c` in physical specs).
    #[default]
    Nu,
    /// The belt speed `lambda` (paper Section 4; `v_belt` in physical specs).
    Lambda,
}

impl BoundaryParam {
    /// The nondimensional key (`nu`, `lambda`), also the suffix of the stored datasets.
    pub fn key(self) -> &'static str {
        match self {
            BoundaryParam::Nu => "nu",
            BoundaryParam::Lambda => "lambda",
        }
    }

    /// The physical key (`c`, `v_belt`).
    pub fn physical_key(self) -> &'static str {
        match self {
            BoundaryParam::Nu => "c",
            BoundaryParam::Lambda => "v_belt",
        }
    }

    /// The SI value of one unit of the parameter, and its units: the damping c in N s/m per
    /// unit of nu, the belt speed in m/s per unit of lambda.
    pub fn si(self, s: &squeal_core::Scales) -> (f64, &'static str) {
        match self {
            BoundaryParam::Nu => (s.damping, "N s/m"),
            BoundaryParam::Lambda => (s.velocity, "m/s"),
        }
    }

    /// Words for messages and long names.
    pub fn words(self) -> &'static str {
        match self {
            BoundaryParam::Nu => "damping ratio nu",
            BoundaryParam::Lambda => "belt speed lambda",
        }
    }

    /// Its value in `p`.
    pub fn get(self, p: &Params) -> f64 {
        match self {
            BoundaryParam::Nu => p.nu,
            BoundaryParam::Lambda => p.lambda,
        }
    }

    /// `p` with this parameter set to `v`.
    pub fn with(self, p: Params, v: f64) -> Params {
        match self {
            BoundaryParam::Nu => Params { nu: v, ..p },
            BoundaryParam::Lambda => Params { lambda: v, ..p },
        }
    }

    /// From its key.
    pub fn from_key(key: &str) -> Option<BoundaryParam> {
        [BoundaryParam::Nu, BoundaryParam::Lambda]
            .into_iter()
            .find(|b| b.key() == key)
    }

    /// The bracket a critical value or fold is bisected over when none is given, by every
    /// door (`squeal critical --nu-lo --nu-hi`, Python's `critical(bracket=)`): nu in
    /// [1e-3, 5e-2] (the paper's damping range), lambda in [0.5, 6] (Table 1's 3 within).
    pub fn default_bracket(self) -> (f64, f64) {
        match self {
            BoundaryParam::Nu => (1e-3, 5e-2),
            BoundaryParam::Lambda => (0.5, 6.0),
        }
    }

    /// The ceiling of the runs' search over `range`: where the bracket's top was given, the
    /// top itself; else how far the search raises the default top while a start still
    /// squeals there: nu to 4 (four times critical damping of the spring), lambda to 16
    /// times its default top.
    pub fn ceiling(self, range: ParamRange, top_given: bool) -> f64 {
        let raised = match self {
            BoundaryParam::Nu => 4.0,
            BoundaryParam::Lambda => 16.0 * self.default_bracket().1,
        };
        if top_given {
            range.hi
        } else {
            raised.max(range.hi)
        }
    }
}

/// How a boundary search ended. Stored as the HDF5 enum `*_status`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[repr(u8)]
#[serde(rename_all = "snake_case")]
pub enum BoundaryStatus {
    /// Located: the value lies in the stored bracket.
    Found = 0,
    /// The predicate already holds at `nu_lo`: the boundary lies below the range.
    BelowRange = 1,
    /// The predicate does not hold yet at `nu_hi`: the boundary lies above the range.
    AboveRange = 2,
    /// Not computed (the run failed, or not asked for).
    NotComputed = 255,
}

impl BoundaryStatus {
    /// All statuses, in value order.
    pub const ALL: [BoundaryStatus; 4] = [
        BoundaryStatus::Found,
        BoundaryStatus::BelowRange,
        BoundaryStatus::AboveRange,
        BoundaryStatus::NotComputed,
    ];
    /// The name in files.
    pub fn name(self) -> &'static str {
        match self {
            BoundaryStatus::Found => "found",
            BoundaryStatus::BelowRange => "below_range",
            BoundaryStatus::AboveRange => "above_range",
            BoundaryStatus::NotComputed => "not_computed",
        }
    }
    /// From the stored value.
    pub fn from_u8(v: u8) -> Option<BoundaryStatus> {
        BoundaryStatus::ALL.into_iter().find(|s| *s as u8 == v)
    }
}

/// A boundary in `nu` or `lambda` (which one: the plan's [`BoundaryParam`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Boundary {
    /// How the search ended.
    pub status: BoundaryStatus,
    /// Geometric middle of the bracket (NaN unless found), in the bisected parameter (the
    /// field keeps its historical name `nu`).
    pub nu: f64,
    /// `[lo, hi]`: the predicate is false at `lo`, true at `hi`.
    pub bracket: [f64; 2],
    /// Predicate evaluations.
    pub evaluations: u32,
    /// The bracket checked at `dt / 2`: `Some(true)` when the predicate is still false at
    /// `lo` and true at `hi` (the boundary at `dt / 2` lies in the same bracket),
    /// `Some(false)` when it moved out, `None` when not checked (not found, a failed run).
    #[serde(default)]
    pub half_dt_holds: Option<bool>,
    /// Half the width of the interval that holds the boundary at dt, at dt / 2 and with the
    /// longer horizon (the fold of McMillan's laws, [`crate::band::crisis_in`]: `nu -+
    /// uncertainty`); NaN where not estimated.
    #[serde(default = "nan")]
    pub uncertainty: f64,
    /// Changes of regime the coarse scan before the bisection found along the parameter (0:
    /// no coarse scan); more than one: the regime flips back and forth, and this boundary is
    /// the last of them.
    #[serde(default)]
    pub changes: u32,
}

fn nan() -> f64 {
    f64::NAN
}

impl Boundary {
    /// Not computed.
    pub fn none() -> Boundary {
        Boundary {
            status: BoundaryStatus::NotComputed,
            nu: f64::NAN,
            bracket: [f64::NAN; 2],
            evaluations: 0,
            half_dt_holds: None,
            uncertainty: f64::NAN,
            changes: 0,
        }
    }

    /// The fold as the crisis `c` found over `range` (its status as the bisection's).
    pub fn from_crisis(c: &Crisis) -> Boundary {
        let status = match c.status {
            CrisisStatus::Found => BoundaryStatus::Found,
            CrisisStatus::BelowRange => BoundaryStatus::BelowRange,
            CrisisStatus::AboveRange => BoundaryStatus::AboveRange,
        };
        let found = status == BoundaryStatus::Found;
        Boundary {
            status,
            nu: c.nu,
            bracket: c.interval,
            evaluations: c.evaluations,
            half_dt_holds: found.then_some(c.half_dt_holds),
            uncertainty: c.uncertainty,
            changes: c.changes.len() as u32,
        }
    }

    /// This boundary, found by a shortcut over `range` for the start `point`, as the gate
    /// ([`crate::fates::decide`]) takes it: with its bracket to confirm where found; where
    /// it lies above the range and the top may be raised (`ceiling` above it), the error
    /// that has the runs raise it, as they do for the critical damping (`squeal critical
    /// --fold` of the README's brake stopped at "--nu-hi 0.05: raise --nu-hi").
    pub fn gated(
        self,
        point: squeal_core::State,
        (range, ceiling): (ParamRange, f64),
    ) -> Result<(Boundary, Option<[f64; 2]>), crate::ScanError> {
        match self.status {
            BoundaryStatus::AboveRange if ceiling > range.hi => Err(crate::ScanError::Bracket {
                nu_lo: range.lo,
                nu_hi: range.hi,
                x: point.x,
                v: point.v,
                problem: crate::error::BracketProblem::SquealsAtHigh,
            }),
            BoundaryStatus::Found => Ok((self, Some(self.bracket))),
            _ => Ok((self, None)),
        }
    }
}

/// Geometric bisection of a predicate that is false below the boundary and true above (in
/// any positive parameter; the name is historical).
pub fn bisect_nu(
    mut pred: impl FnMut(f64) -> Result<bool, ScanError>,
    range: ParamRange,
) -> Result<Boundary, ScanError> {
    let ParamRange {
        lo: nu_lo,
        hi: nu_hi,
        rtol,
    } = range;
    if !(nu_lo > 0.0 && nu_hi > nu_lo && nu_hi.is_finite() && rtol > 0.0) {
        return Err(ScanError::Undetermined(format!(
            "bracket [{nu_lo}, {nu_hi}] / rtol {rtol}: need 0 < lo < hi, rtol > 0"
        )));
    }
    let mut b = Boundary {
        status: BoundaryStatus::Found,
        nu: f64::NAN,
        bracket: [nu_lo, nu_hi],
        evaluations: 2,
        half_dt_holds: None,
        uncertainty: f64::NAN,
        changes: 0,
    };
    if pred(nu_lo)? {
        b.status = BoundaryStatus::BelowRange;
        b.evaluations = 1;
        return Ok(b);
    }
    if !pred(nu_hi)? {
        b.status = BoundaryStatus::AboveRange;
        return Ok(b);
    }
    let ((lo, hi), evaluations) =
        crate::section::geometric_bisection(pred, (nu_lo, nu_hi), rtol, 200)?;
    b.evaluations = evaluations;
    b.bracket = [lo, hi];
    b.nu = (lo * hi).sqrt();
    Ok(b)
}

/// The section crossings found so far in one bisection, by parameter value: each step's
/// cycle search warm-starts from the crossing at the nearest value already analysed (in
/// `|ln v|`), as the points of a line do ([`crate::section::search`]: the warm bracket is
/// only kept once checked, else the cold search runs).
#[derive(Debug, Default)]
pub struct Crossings(std::cell::RefCell<Vec<(f64, f64)>>);

impl Crossings {
    /// The crossing at the analysed value nearest `v`, if any had a cycle.
    pub fn nearest(&self, v: f64) -> Option<f64> {
        self.0
            .borrow()
            .iter()
            .min_by(|a, b| (a.0 / v).ln().abs().total_cmp(&(b.0 / v).ln().abs()))
            .map(|&(_, r)| r)
    }

    /// Analyses parameter value `v` (`p` its parameters), warm-started from the nearest
    /// crossing, and keeps its crossing.
    pub fn analyse(
        &self,
        v: f64,
        setup: Setup,
        ps: &PointSettings,
        stick: bool,
    ) -> Result<super::point::Analysis, ScanError> {
        let a = analyse(setup, ps, self.nearest(v), stick)?;
        if let Some(rep) = &a.cycle {
            self.0.borrow_mut().push((v, rep.r_section));
        }
        Ok(a)
    }
}

/// Whether no start squeals at these parameters: no `D > 0` on the section, or an unstable
/// cycle with no stick-slip attractor outside it (see [`super::attractor::find_stick_slip`]).
pub fn quiet_everywhere(setup: Setup, ps: &PointSettings) -> Result<bool, ScanError> {
    let origin = State { x: 0.0, v: 0.0 };
    Evaluator::new(BoundaryParam::Nu, setup, ps, origin).answer(setup.params.nu, Which::Fold)
}

/// Whether `point` does not squeal: inside the unstable cycle, or nothing squeals at all; a
/// repelling fixed point squeals.
pub fn point_quiet(setup: Setup, ps: &PointSettings, point: State) -> Result<bool, ScanError> {
    Evaluator::new(BoundaryParam::Nu, setup, ps, point).answer(setup.params.nu, Which::Critical)
}

/// The coarse scan `squeal critical` makes before trusting its one bisection in `param`
/// over `(lo, hi)`: every change of [`quiet_everywhere`] (`which` the fold) or of
/// [`point_quiet`] at `point` (the critical value) between [`crate::band::COARSE`]
/// geometric steps ([`coarse_changes`]).
pub fn coarse_scan(
    param: BoundaryParam,
    setup: Setup,
    (ps, point): (&PointSettings, State),
    which: Which,
    (lo, hi): (f64, f64),
) -> Result<Vec<Change>, ScanError> {
    coarse_changes(
        |v| {
            let s = setup.with_params(param.with(setup.params, v));
            match which {
                Which::Fold => quiet_everywhere(s, ps),
                Which::Critical => point_quiet(s, ps, point),
            }
        },
        (lo, hi),
        crate::band::COARSE,
    )
}

/// The fold in `param`: the value above which no start squeals for good. For McMillan's
/// laws the crisis of the stick-slip band ([`fold_crisis`], with [`crate::band::COARSE`]
/// coarse steps); for laws with true stick (no band to leak) the bisection of "no start
/// stays on stick-slip for the attractor's window" ([`quiet_everywhere`]).
pub fn fold_in(
    param: BoundaryParam,
    setup: Setup,
    ps: &PointSettings,
    range: ParamRange,
) -> Result<Boundary, ScanError> {
    if crisis_applies(setup.params.kind()) {
        let c = fold_crisis(
            param,
            setup,
            ps,
            range,
            (crate::band::COARSE, Budget::Standard),
        )?;
        return Ok(Boundary::from_crisis(&c));
    }
    let e = Evaluator::new(param, setup, ps, State { x: 0.0, v: 0.0 });
    bisect_nu(|v| e.answer(v, Which::Fold), range)
}

/// Whether the fold of `law` is the crisis of the band ([`fold_crisis`]): McMillan's two
/// laws. Laws with true stick have no band to leak (their fold is the bisection of "no start
/// stays on stick-slip for the attractor's window", with their landscape).
///
/// The non-hysteretic law joined once the section search saw its band: its return map jumps
/// where orbits begin to touch zero slip, and at Table 1's lambda, tau, phi and nu = 0.0403
/// (dt 0.01) the unstable crossing (2.9346) and the stick-slip orbit (2.946) sit behind such
/// a jump, which the search stepped over with r_max 3.5, 6 and 10 until peaks were refined
/// ([`crate::section::adaptive_samples`]). Its crisis at dt 0.01, 0.041382 +- 0.000008 over
/// [0.02, 0.06], agrees with runs to t = 20000 (still on stick-slip at nu = 0.0413, at the
/// fixed point by t = 530 at 0.0420; test
/// `the_non_hysteretic_crisis_lies_where_runs_put_it`), where the window bisection gave
/// 0.04106, below runs that keep squealing.
pub fn crisis_applies(law: squeal_core::FrictionLaw) -> bool {
    law.family().has_band()
}

/// The crisis of the stick-slip band in `param` over `range` ([`crate::band::crisis_in`]:
/// a coarse scan of `coarse` steps, the bisections, the uncertainty covering dt/2 and the
/// longer horizon; `base` the budget at dt and dt/2, [`Budget::Standard`] but for the
/// longer horizon's own crisis), the section searched with the point's settings at each
/// value ([`settings_for`]: `r_max` at least `2 lambda`).
pub fn fold_crisis(
    param: BoundaryParam,
    setup: Setup,
    ps: &PointSettings,
    range: ParamRange,
    (coarse, base): (usize, Budget),
) -> Result<Crisis, ScanError> {
    if !(range.lo > 0.0 && range.hi > range.lo && range.hi.is_finite() && range.rtol > 0.0) {
        return Err(ScanError::Undetermined(format!(
            "bracket [{}, {}] / rtol {}: need 0 < lo < hi, rtol > 0",
            range.lo, range.hi, range.rtol
        )));
    }
    let shared = SharedReturns::default();
    crisis_in(fold_verdict(param, setup, ps, base, &shared), range, coarse)
}

/// The band's verdict of the fold at value `v` of `param` ([`Variant::lasting_sharing`]: the
/// section searched with the point's settings there, [`settings_for`]), its returns shared
/// between the computations at one value: the one verdict of [`fold_crisis`] and
/// [`cover_critical`].
fn fold_verdict<'a>(
    param: BoundaryParam,
    setup: Setup,
    ps: &'a PointSettings,
    base: Budget,
    shared: &'a SharedReturns,
) -> impl Fn(f64, Variant) -> Result<crate::band::Lasting, ScanError> + 'a {
    move |v: f64, which: Variant| {
        let s = setup.with_params(param.with(setup.params, v));
        which.lasting_sharing(s, &settings_for(&s.params, &ps.cycle), base, &shared.at(v))
    }
}

/// The critical value of `param` for `point`: above it the point does not squeal.
pub fn critical_in(
    param: BoundaryParam,
    setup: Setup,
    ps: &PointSettings,
    point: State,
    range: ParamRange,
) -> Result<Boundary, ScanError> {
    let e = Evaluator::new(param, setup, ps, point);
    bisect_nu(|v| e.answer(v, Which::Critical), range)
}

/// Both boundaries of one combination of the other parameters, sharing work: each
/// evaluation at a parameter value analyses the point once (section search, cycle and the
/// stick-slip runs) and answers both predicates from it, so where the two bisections visit
/// the same value (always the two ends and the first middle; all the way where the fold and
/// the critical value coincide, as at low belt speed) the second costs nothing. Each
/// result is what [`fold_in`] and [`critical_in`] give alone: the critical predicate read
/// from that analysis is [`point_quiet`]'s (the same starts of the same stick-slip runs).
/// `None` for a boundary not asked for.
pub fn both_in(
    param: BoundaryParam,
    setup: Setup,
    ps: &PointSettings,
    point: State,
    range: ParamRange,
    [fold, critical]: [bool; 2],
) -> [Option<Result<Boundary, ScanError>>; 2] {
    both_with(
        param,
        setup,
        (ps, point),
        range,
        [fold, critical],
        crate::band::COARSE,
    )
}

/// [`both_in`] with `coarse` steps of the fold's coarse scan (the atlas's
/// `[boundaries] coarse`).
pub fn both_with(
    param: BoundaryParam,
    setup: Setup,
    (ps, point): (&PointSettings, State),
    range: ParamRange,
    [fold, critical]: [bool; 2],
    coarse: usize,
) -> [Option<Result<Boundary, ScanError>>; 2] {
    // The fold of McMillan's laws is the crisis, its uncertainty covering dt/2 already.
    let crisis = crisis_applies(setup.params.kind());
    let mut out = match crisis {
        // The crisis shares nothing with the critical value's bisection: the two run side
        // by side, each as it runs alone.
        true => {
            let (f, c) = rayon::join(
                || {
                    fold.then(|| {
                        fold_crisis(param, setup, ps, range, (coarse, Budget::Standard))
                            .map(|c| Boundary::from_crisis(&c))
                    })
                },
                || {
                    let at_dt = Evaluator::new(param, setup, ps, point);
                    critical.then(|| bisect_nu(|v| at_dt.answer(v, Which::Critical), range))
                },
            );
            [f, c]
        }
        // Both bisections read one analysis per value, warm-started from the values either
        // analysed before: one after the other.
        false => {
            let at_dt = Evaluator::new(param, setup, ps, point);
            let run = |which: Which| bisect_nu(|v| at_dt.answer(v, which), range);
            [
                fold.then(|| run(Which::Fold)),
                critical.then(|| run(Which::Critical)),
            ]
        }
    };
    // The accuracy of each bracket: its predicate again at its ends with dt / 2. Near the
    // fold the stick-slip test is a finite run beside a boundary crisis (runs outside the
    // cycle can linger for many revolutions and then fall inside), so the bracket at dt can
    // be off by far more than its width; this says where it holds.
    let half = Evaluator::new(param, setup.half_dt(), ps, point);
    let which = [Which::Fold, Which::Critical];
    check_half_dt(&mut out, |i, v| match (i, crisis) {
        // The crisis checked its own bracket at dt / 2.
        (0, true) => None,
        _ => half.answer(v, which[i]).ok(),
    });
    if crisis {
        cover_critical(param, setup, ps, range, &mut out);
    }
    out
}

/// Where the critical value of the operating point lies above the fold's stated interval
/// (its predicate, counting an undecided band as squealing, changes once more above the
/// crisis), the fold's interval is raised to cover it ([`crate::band::raise_top`]: above
/// the crisis the band can be undecided again over narrow windows the crisis's coarse scan
/// stepped over). Then the critical damping of the operating point never exceeds the fold
/// beyond its uncertainty. A failed verdict leaves the fold as it was
/// and says so in its place ([`Boundary::none`] is not used: the crisis itself stands).
fn cover_critical(
    param: BoundaryParam,
    setup: Setup,
    ps: &PointSettings,
    range: ParamRange,
    out: &mut [Option<Result<Boundary, ScanError>>; 2],
) {
    let [Some(Ok(fold)), Some(Ok(critical))] = out else {
        return;
    };
    let found = |b: &Boundary| b.status == BoundaryStatus::Found;
    if !(found(fold) && found(critical)) || critical.bracket[0] <= fold.nu + fold.uncertainty {
        return;
    }
    let shared = SharedReturns::default();
    let raised = crate::band::raise_top(
        fold_verdict(param, setup, ps, Budget::Standard, &shared),
        (fold.nu, fold.uncertainty),
        critical.bracket[1],
        (range.hi, range.rtol),
    );
    if let Ok(((nu, u), evaluations)) = raised {
        fold.nu = nu;
        fold.uncertainty = u;
        fold.evaluations += evaluations;
    }
}

/// Fills [`Boundary::half_dt_holds`] of each found bracket in `[fold, critical]`:
/// `at_half_dt(i, v)` answers predicate `i` (0 fold, 1 critical) at value `v` with `dt / 2`
/// (`None`: no answer). The bracket holds when the predicate is still false at its lower
/// end and true at its upper.
pub fn check_half_dt(
    out: &mut [Option<Result<Boundary, ScanError>>; 2],
    at_half_dt: impl Fn(usize, f64) -> Option<bool>,
) {
    for (i, b) in out.iter_mut().enumerate() {
        let Some(Ok(b)) = b else { continue };
        if b.status != BoundaryStatus::Found || b.half_dt_holds.is_some() {
            continue;
        }
        b.half_dt_holds = match (at_half_dt(i, b.bracket[0]), at_half_dt(i, b.bracket[1])) {
            (Some(at_lo), Some(at_hi)) => Some(!at_lo && at_hi),
            _ => None,
        };
    }
}

/// Which boundary's predicate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Which {
    /// Quiet everywhere ([`quiet_everywhere`]).
    Fold,
    /// The operating point quiet ([`point_quiet`]).
    Critical,
}

/// Answers both predicates at parameter values, analysing each value once (warm-started
/// from the nearest value's crossing) and running the stick-slip attractor only when a
/// predicate needs it: the critical predicate does not where the cycle encloses the point.
/// Each answer is the one [`quiet_everywhere`] or [`point_quiet`] gives (the same starts of
/// the same stick-slip runs).
struct Evaluator<'a> {
    param: BoundaryParam,
    setup: Setup,
    ps: &'a PointSettings,
    point: State,
    crossings: Crossings,
    memo: std::cell::RefCell<std::collections::HashMap<u64, super::point::Analysis>>,
}

impl<'a> Evaluator<'a> {
    fn new(
        param: BoundaryParam,
        setup: Setup,
        ps: &'a PointSettings,
        point: State,
    ) -> Evaluator<'a> {
        Evaluator {
            param,
            setup,
            ps,
            point,
            crossings: Crossings::default(),
            memo: Default::default(),
        }
    }

    fn answer(&self, v: f64, which: Which) -> Result<bool, ScanError> {
        let setup = self
            .setup
            .with_params(self.param.with(self.setup.params, v));
        let p = setup.params;
        let mut memo = self.memo.borrow_mut();
        let a = match memo.entry(v.to_bits()) {
            std::collections::hash_map::Entry::Occupied(e) => e.into_mut(),
            std::collections::hash_map::Entry::Vacant(e) => {
                e.insert(self.crossings.analyse(v, setup, self.ps, false)?)
            }
        };
        let here = |e: String| {
            ScanError::Undetermined(format!("nu = {}, lambda = {}: {e}", p.nu, p.lambda))
        };
        let encloses = a
            .cycle
            .as_ref()
            .is_some_and(|rep| rep.encloses(self.point.x, self.point.v));
        // McMillan's laws: outside the cycle the operating point squeals unless the band
        // above the cycle leaks (the rule of `squeal critical` from a start,
        // `crate::ulc::point_side`, and of the fold's crisis), not by a stick-slip run that
        // may sit on a leaking band for its whole window.
        let band_rule = crisis_applies(p.kind());
        let needs_stick = match (which, &a.search) {
            (_, Search::NoneBelow { .. }) => false,
            (Which::Critical, Search::FixedPointUnstable { .. }) => false,
            (Which::Critical, _) => !encloses && !band_rule,
            (Which::Fold, _) => true,
        };
        if needs_stick && a.stick.is_none() {
            // As `analyse` with `stick`: from outside the cycle, or from 0 without one.
            let st = setup.stepper()?;
            let cs = settings_for(&p, &self.ps.cycle);
            let r_u = a.cycle.as_ref().map_or(0.0, |rep| rep.r_section);
            a.stick = Some(find_stick_slip(
                &st,
                r_u,
                self.ps,
                cs.t_return,
                &mut a.work.stats,
            ));
        }
        match which {
            Which::Fold => a
                .squeals_somewhere()
                .map(|s| !s)
                .map_err(|e| here(format!("cannot tell whether anything squeals: {e}"))),
            Which::Critical => match (&a.search, &a.cycle, &a.stick) {
                (Search::NoneBelow { .. }, _, _) => Ok(true),
                (Search::FixedPointUnstable { .. }, _, _) => Ok(false),
                (_, Some(_), _) if encloses => Ok(true),
                (_, Some(_), _) if band_rule => {
                    let cs = settings_for(&p, &self.ps.cycle);
                    Ok(crate::band::lasting(setup, &cs)? == crate::band::Lasting::Quiet)
                }
                (_, Some(_), Some(Ok(_))) => Ok(false),
                (_, Some(_), Some(Err(StickFail::FellInside { .. }))) => Ok(true),
                (_, Some(_), Some(Err(StickFail::Failed(e)))) => Err(here(e.clone())),
                _ => Err(ScanError::Undetermined("a bracket without a cycle".into())),
            },
        }
    }
}

/// The fold of cycles: the damping above which no start squeals.
pub fn fold_nu(setup: Setup, ps: &PointSettings, range: ParamRange) -> Result<Boundary, ScanError> {
    fold_in(BoundaryParam::Nu, setup, ps, range)
}

/// The critical damping of `point`: the cycle first encloses it.
pub fn critical_nu(
    setup: Setup,
    ps: &PointSettings,
    point: State,
    range: ParamRange,
) -> Result<Boundary, ScanError> {
    critical_in(BoundaryParam::Nu, setup, ps, point, range)
}

#[cfg(test)]
mod tests;
