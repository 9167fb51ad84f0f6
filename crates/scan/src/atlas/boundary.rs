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
//!   [`crate::ulc::point_enclosed`]), so the critical damping never exceeds the fold.
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
use super::point::{PointSettings, analyse, settings_for};
use crate::band::{Budget, Crisis, CrisisStatus, Variant, crisis_in};
use crate::error::ScanError;
use crate::section::{ParamRange, Search};

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
    if crisis_applies(setup.params.law) {
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

/// Whether the fold of `law` is the crisis of the band ([`fold_crisis`]): McMillan's
/// hysteretic law only. Laws with true stick have no band to leak. For the non-hysteretic
/// law the section's return map misses a stick-slip orbit that runs keep: at Table 1's
/// lambda, tau, phi and nu = 0.0403 (dt 0.01) the section search finds `D < 0` up to r = 6
/// (`squeal ulc --law mcmillan-nonhysteretic --nu 0.0403 --dt 0.01`), so the band's verdict
/// says quiet, while `squeal trajectory` with the same flags from (1, 3) still oscillates at
/// t = 20000 with section amplitude 2.946; its crisis would lie at 0.0390, below that run.
/// There the fold stays the bisection of "no start stays on stick-slip for the attractor's
/// window" (0.04106 at dt 0.01, above the run), until the section map sees that orbit.
pub fn crisis_applies(law: squeal_core::FrictionLaw) -> bool {
    law == squeal_core::FrictionLaw::McMillan
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
    let verdict = |v: f64, which: Variant| {
        let s = setup.with_params(param.with(setup.params, v));
        which.lasting(s, &settings_for(&s.params, &ps.cycle), base)
    };
    crisis_in(verdict, range, coarse)
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
    let at_dt = Evaluator::new(param, setup, ps, point);
    let run = |which: Which| bisect_nu(|v| at_dt.answer(v, which), range);
    // The fold of McMillan's laws is the crisis, its uncertainty covering dt/2 already.
    let crisis = crisis_applies(setup.params.law);
    let fold_of = || match crisis {
        true => fold_crisis(param, setup, ps, range, (coarse, Budget::Standard))
            .map(|c| Boundary::from_crisis(&c)),
        false => run(Which::Fold),
    };
    let mut out = [fold.then(fold_of), critical.then(|| run(Which::Critical))];
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
    out
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
enum Which {
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
        let band_rule = crisis_applies(p.law);
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
mod tests {
    use super::*;
    use squeal_core::FrictionLaw;

    use squeal_core::{SolverConfig, Stepper};

    use super::super::point::AtlasRegime;
    use crate::ulc::CycleSettings;

    fn setup(p: Params, dt: f64) -> Setup {
        Setup::new(p, dt, SolverConfig::default())
    }

    #[test]
    fn bisection_finds_a_known_threshold() {
        // Predicate nu >= 0.0123: the bracket must hold it to rtol.
        let b = bisect_nu(|nu| Ok(nu >= 0.0123), ParamRange::new(1e-3, 1e-1, 1e-6)).unwrap();
        assert_eq!(b.status, BoundaryStatus::Found);
        assert!(b.bracket[0] < 0.0123 && b.bracket[1] >= 0.0123);
        assert!(b.bracket[1] / b.bracket[0] - 1.0 <= 1e-6);
        let b = bisect_nu(|nu| Ok(nu >= 0.5), ParamRange::new(1e-3, 1e-1, 1e-6)).unwrap();
        assert_eq!(b.status, BoundaryStatus::AboveRange);
        let b = bisect_nu(|_| Ok(true), ParamRange::new(1e-3, 1e-1, 1e-6)).unwrap();
        assert_eq!(b.status, BoundaryStatus::BelowRange);
    }

    #[test]
    fn fold_lies_where_the_nu_sweep_says_for_both_laws() {
        for law in [FrictionLaw::McMillan, FrictionLaw::McMillanNonHysteretic] {
            let base = Params::paper(law, 0.0);
            let b = fold_nu(
                setup(base, 0.01),
                &PointSettings::default(),
                ParamRange::new(1e-3, 0.1, 1e-3),
            )
            .unwrap();
            assert_eq!(b.status, BoundaryStatus::Found, "{law}");
            if law == FrictionLaw::McMillan {
                // MODEL.md (the hysteretic nu-sweep, scans/nu-sweep.toml): all squeal
                // vanishes between nu = 0.019 and 0.031.
                assert!(b.nu > 0.019 && b.nu < 0.031, "{law}: fold at {}", b.nu);
            } else {
                // MODEL.md: hysteresis moves the fold a lot. `squeal trajectory --law
                // mcmillan-nonhysteretic --nu 0.039 --x0 -4 --t-end 3000` still ends on
                // stick-slip (section amplitude 2.96), so the fold lies above 0.031 here.
                assert!(b.nu > 0.031 && b.nu < 0.06, "{law}: fold at {}", b.nu);
            }
            // Independent check by runs to settlement (the rule every path labels by,
            // `crate::scanner::classifier_for`: a band that leaks labels nothing stick-slip):
            // 10% below the fold's interval a start at (x*, lambda) on the section does not
            // return to steady slip (the non-hysteretic band is irregular enough that the run
            // may stay undecided at t_max); 3% above it, neither that start nor a big one at
            // (-4, 0) is labelled stick-slip (steady slip, or undecided while a transient
            // lasts). Before the fold was the crisis, the 80-revolution fold lay above the
            // crisis and the raw band rules labelled runs there stick-slip that end at the
            // fixed point (issue 17).
            // The crisis (hysteretic law) states an uncertainty; the non-hysteretic fold its
            // bracket.
            let (lo, hi) = match b.uncertainty.is_finite() {
                true => (b.nu - b.uncertainty, b.nu + b.uncertainty),
                false => (b.bracket[0], b.bracket[1]),
            };
            for (nu, above) in [(0.9 * lo, false), (1.03 * hi, true)] {
                let st =
                    Stepper::new(Params { nu, ..base }, 0.01, SolverConfig::default()).unwrap();
                let starts: &[State] = if above {
                    &[
                        State {
                            x: 1.0,
                            v: base.lambda,
                        },
                        State { x: -4.0, v: 0.0 },
                    ]
                } else {
                    &[State {
                        x: 1.0,
                        v: base.lambda,
                    }]
                };
                let cl =
                    crate::scanner::classifier_for(&st, squeal_core::Classifier::default(), 6.0);
                for &start in starts {
                    let o = cl.classify(&st, start);
                    let wrong = match above {
                        true => squeal_core::Regime::StickSlip,
                        false => squeal_core::Regime::SteadySlip,
                    };
                    assert_ne!(
                        o.regime, wrong,
                        "{law} at nu {nu}, fold {b:?} from {start:?}: {o:?}"
                    );
                }
            }
            // Below the fold the unstable cycle exists and grows with nu (MODEL.md).
            let r = |nu: f64| {
                analyse(
                    setup(Params { nu, ..base }, 0.01),
                    &PointSettings::default(),
                    None,
                    false,
                )
                .unwrap()
                .cycle
                .unwrap()
                .r_section
            };
            let (r1, r2, r3) = (r(0.25 * b.nu), r(0.5 * b.nu), r(0.95 * b.nu));
            assert!(r1 < r2 && r2 < r3, "{law}: {r1} {r2} {r3}");
        }
    }

    #[test]
    fn critical_matches_the_single_point_command() {
        // `squeal critical` (ulc::critical_nu) at Table 1, rest, rtol 1e-4.
        let base = Params::paper(FrictionLaw::McMillan, 0.0);
        let rest = State { x: 0.0, v: 0.0 };
        let range = ParamRange::new(1e-3, 5e-2, 1e-4);
        let ours = critical_nu(setup(base, 0.01), &PointSettings::default(), rest, range).unwrap();
        let theirs =
            crate::ulc::critical_nu(setup(base, 0.01), &CycleSettings::default(), rest, range)
                .unwrap();
        assert_eq!(ours.status, BoundaryStatus::Found);
        // Both brackets are 1e-4 wide (relative) and must overlap.
        assert!(
            ours.bracket[0] <= theirs.bracket[1] && theirs.bracket[0] <= ours.bracket[1],
            "{:?} vs {:?}",
            ours.bracket,
            theirs.bracket
        );
        // Between the paper's two points: encloses at 1e-2, not at 1e-3.
        assert!(ours.nu > 1e-3 && ours.nu < 1e-2);
    }

    #[test]
    fn critical_belt_speed_flips_the_label_of_rest() {
        // Fig 10's damping nu = 1e-2: rest squeals at low belt speed and is quiet at
        // Table 1's lambda = 3 (paper Fig 10), so a critical belt speed lies between.
        let base = Params::paper(FrictionLaw::McMillan, 1e-2);
        let rest = State { x: 0.0, v: 0.0 };
        let ps = PointSettings::default();
        let dt = 0.01;
        let b = critical_in(
            BoundaryParam::Lambda,
            setup(base, dt),
            &ps,
            rest,
            ParamRange::new(1.0, 3.0, 1e-3),
        )
        .unwrap();
        assert_eq!(b.status, BoundaryStatus::Found);
        assert!(b.bracket[1] / b.bracket[0] - 1.0 <= 1e-3);
        // Independent evidence: runs to settlement from rest (the classifier's rules, no
        // section map), 2% below and above the bracket.
        let cl = squeal_core::Classifier::default();
        for (f, steady) in [(0.98 * b.bracket[0], false), (1.02 * b.bracket[1], true)] {
            let st = Stepper::new(
                BoundaryParam::Lambda.with(base, f),
                dt,
                SolverConfig::default(),
            )
            .unwrap();
            let o = cl.classify(&st, rest);
            assert_eq!(
                o.regime == squeal_core::Regime::SteadySlip,
                steady,
                "lambda = {f} (critical {:?}): {o:?}",
                b.bracket
            );
            // And the atlas's own label of the point.
            let p = super::super::point::compute_point(
                setup(BoundaryParam::Lambda.with(base, f), dt),
                &ps,
                None,
            )
            .unwrap();
            assert_eq!(p.regime.operating_point_squeals(), Some(!steady), "{f}");
        }
    }

    #[test]
    fn warm_and_cold_starts_agree_across_the_fold() {
        // A line in nu across the fold at Table 1 (MODEL.md: between 0.019 and 0.031),
        // each point warm-started from the previous one as the atlas's lines are, against
        // the same points searched cold.
        let base = Params::paper(FrictionLaw::McMillan, 0.0);
        let ps = PointSettings::default();
        let (dt, solver) = (0.01, SolverConfig::default());
        let nus: Vec<f64> = (0..8).map(|k| 0.012 * 1.16f64.powi(k)).collect();
        let mut warm = None;
        let mut n_warm = 0;
        let mut crossed = (false, false);
        let mut line = Vec::new();
        for &nu in &nus {
            let p = Setup::new(Params { nu, ..base }, dt, solver);
            let w = super::super::point::compute_point(p, &ps, warm).unwrap();
            let c = super::super::point::compute_point(p, &ps, None).unwrap();
            assert_eq!(w.regime, c.regime, "nu = {nu}");
            n_warm += usize::from(w.warm_started);
            match (w.cycle, c.cycle) {
                (Some(a), Some(b)) => {
                    // Both brackets are narrower than rtol = 1e-9 (relative).
                    let tol = 2.0 * ps.cycle.rtol * b.r_section;
                    assert!((a.r_section - b.r_section).abs() <= tol, "nu = {nu}");
                }
                (None, None) => {}
                (a, b) => panic!("nu = {nu}: warm {a:?} vs cold {b:?}"),
            }
            crossed.0 |= w.regime != AtlasRegime::SteadySlipOnly;
            crossed.1 |= w.regime == AtlasRegime::SteadySlipOnly;
            line.push(w.regime == AtlasRegime::SteadySlipOnly);
            warm = w.cycle.map(|c| c.r_section);
        }
        // The line does cross the fold, and the warm starts were used.
        assert!(crossed.0 && crossed.1, "the line should cross the fold");
        assert!(n_warm >= 3, "{n_warm} warm starts");
        // The bisected fold agrees with both lines: every point below its bracket has
        // some start that squeals, every point above it none.
        let fold = fold_nu(
            Setup::new(base, dt, solver),
            &ps,
            ParamRange::new(0.012, 0.04, 1e-3),
        )
        .unwrap();
        assert_eq!(fold.status, BoundaryStatus::Found);
        for (&nu, &steady) in nus.iter().zip(&line) {
            if nu < fold.bracket[0] {
                assert!(!steady, "nu = {nu} below the fold {:?}", fold.bracket);
            } else if nu > fold.bracket[1] {
                assert!(steady, "nu = {nu} above the fold {:?}", fold.bracket);
            }
        }
    }

    #[test]
    fn shared_boundaries_equal_separate_ones() {
        // At lambda = 1 (the chart's fold and critical damping coincide below lambda ~ 1.3)
        // and at Table 1's lambda = 3 (they differ): bit-identical to separate bisections.
        let ps = PointSettings::default();
        let (dt, solver) = (0.01, SolverConfig::default());
        let rest = State { x: 0.0, v: 0.0 };
        for lambda in [1.0, 3.0] {
            let base = Params {
                lambda,
                ..Params::paper(FrictionLaw::McMillan, 0.0)
            };
            let (s, range) = (
                Setup::new(base, dt, solver),
                ParamRange::new(1e-3, 0.05, 1e-2),
            );
            let [f, c] = both_in(BoundaryParam::Nu, s, &ps, rest, range, [true, true]);
            let fold = fold_nu(s, &ps, range).unwrap();
            let crit = critical_nu(s, &ps, rest, range).unwrap();
            let (f, c) = (f.unwrap().unwrap(), c.unwrap().unwrap());
            // The shared search also checks the critical bracket at dt / 2 (the separate
            // search does not).
            // (NaN uncertainties of the critical value set to 0: NaN != NaN.)
            let unchecked = |b: Boundary| Boundary {
                half_dt_holds: None,
                uncertainty: 0.0,
                ..b
            };
            // The fold (the crisis) checks itself at dt / 2 in both.
            assert_eq!(f, fold, "lambda = {lambda}");
            assert_eq!(unchecked(c), unchecked(crit), "lambda = {lambda}");
            assert!(f.half_dt_holds.is_some() && c.half_dt_holds.is_some());
            if lambda == 3.0 {
                // At lambda = 3 the critical damping is where the cycle comes to enclose
                // rest: the cycle moves by about 1e-6 when dt halves (`squeal ulc`), far
                // inside the 1% bracket, so the bracket holds at dt / 2.
                assert_eq!(c.half_dt_holds, Some(true), "{c:?}");
            }
        }
    }
}
