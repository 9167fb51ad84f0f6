//! Where runs end, and the boundaries bisected on runs alone.
//!
//! The critical damping and the fold were first answered from the paper's picture: one
//! unstable cycle around the fixed point, every start outside it ending on a stick-slip
//! band. Where that picture does not hold (a brake clamped hard at low belt speed, whose
//! lasting oscillation overtakes the belt and never crosses the section the cycle lives
//! on), those answers can be ten times too low. This module answers the same questions
//! from runs, with no rule about the landscape:
//!
//! * [`Fate`]: a run from a start to a horizon `T` either reaches the fixed point
//!   ([`Fate::Settles`]), or ends on an oscillation the classifier's band test identified,
//!   the squeal ([`Fate::Lasts`]) or the slip oscillation about an unstable steady slip
//!   ([`Fate::SlipOscillation`]), certified as a periodic orbit (the run then stops) or
//!   still on it at `T` ("lasts to `T`", the claim a finite run can make), or neither
//!   ([`Fate::Undecided`]).
//! * [`Spread`]: the starts a fold is sampled over (rest and twelve starts on four rings
//!   around the fixed point).
//! * [`critical`] and [`fold`]: the last change of "the start settles" and "every sampled
//!   start settles" along the parameter ([`boundary`]: down from the top of the range in
//!   geometric steps, then bisected), each end of the bracket a run (so the answer is
//!   confirmed by runs: below it a start does not settle, above it all do), then the
//!   bracket checked at `dt / 2` and widened to cover the boundary there
//!   ([`RunBoundary::interval`]), its starts' fates compared there ([`step_share`]).
//!
//! A run ends "quiet" at the fixed point or, where steady slip does not attract, on the slip
//! oscillation about it ([`Fate::quiet`]): the boundaries are about the squeal. An undecided
//! run is not quiet (squeal is not ruled out) and is counted; where the bracket's lower end
//! rests on one, the answer is only an upper bound (`squeal critical` says so).

use std::sync::atomic::{AtomicBool, Ordering};

use rayon::prelude::*;
use serde::Serialize;
use squeal_core::{Params, Setup, SolverStats, State};

use crate::atlas::{BoundaryParam, BoundaryStatus};
use crate::error::ScanError;
use crate::section::ParamRange;
use crate::sensitivity::StepShare;

/// The horizon of the runs behind a boundary, nondimensional (the unforced period is
/// `2 pi`): the long checks' (runs to t = 20000 are their truth, `scripts/ci/long-checks.sh`).
/// Near the critical damping at Table 1's parameters the run from rest, just inside the
/// unstable cycle, spirals in slowly: it reaches the fixed point at t = 5368 (`squeal
/// critical` at the defaults), and would read undecided at t = 3000.
pub const HORIZON: f64 = 20_000.0;

mod confirm;
mod run;
pub use confirm::{Confirmation, Unconfirmed, confirm, unchecked};
pub use run::{Fate, fate};

/// The starts a fold is sampled over: rest, and twelve starts on four rings around the
/// fixed point, of radii `s/2, s, 2 s, 4 s` with `s = max(lambda, 1/4)` (the belt speed
/// sets the size of a stick-slip loop), three to a ring at angles turned by 30 degrees
/// from ring to ring.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Spread {
    /// The starts, rest first.
    pub starts: Vec<State>,
}

impl Spread {
    /// The spread for parameters `p`.
    pub fn of(p: &Params) -> Spread {
        let fp = p.fixed_point();
        let s = p.lambda.max(0.25);
        let mut starts = vec![State { x: 0.0, v: 0.0 }];
        for (ring, r) in [0.5, 1.0, 2.0, 4.0].into_iter().enumerate() {
            for k in 0..3 {
                let a = (30.0 * ring as f64 + 120.0 * k as f64).to_radians();
                starts.push(State {
                    x: fp.x + r * s * a.cos(),
                    v: r * s * a.sin(),
                });
            }
        }
        Spread { starts }
    }
}

/// The fates of `starts` with `setup` by `horizon`, run in parallel; with `until_one`, once
/// a start does not settle the runs of the starts after it (by index) are stopped
/// ([`Fate::Stopped`]). Only later starts are stopped, so the result does not depend on the
/// threads' timing: the first start that does not settle, and every start before it, always
/// run to their end (stopping any other run made which start an atlas point named, and
/// whether its operating point lasted, change from run to run). Every start after that one
/// reads [`Fate::Stopped`] with no solver counts, also where its run ended before the stop
/// reached it ([`after_the_first_unsettled`]): whether it did is the threads' timing.
pub fn fates(
    setup: Setup,
    starts: &[State],
    horizon: f64,
    until_one: bool,
) -> Result<Vec<(Fate, SolverStats)>, ScanError> {
    let stops: Vec<AtomicBool> = starts.iter().map(|_| AtomicBool::new(false)).collect();
    starts
        .par_iter()
        .enumerate()
        .map(|(i, &s)| {
            let stop = until_one.then_some(&stops[i]);
            if stop.is_some_and(|f| f.load(Ordering::Relaxed)) {
                return Ok((Fate::Stopped, SolverStats::default()));
            }
            let out = fate(setup, s, horizon, stop)?;
            if until_one && !out.0.quiet() && out.0 != Fate::Stopped {
                for later in &stops[i + 1..] {
                    later.store(true, Ordering::Relaxed);
                }
            }
            Ok(out)
        })
        .collect::<Result<Vec<_>, ScanError>>()
        .map(|out| match until_one {
            true => after_the_first_unsettled(out),
            false => out,
        })
}

/// `out` with every start after the first that did not settle (by index) read as
/// [`Fate::Stopped`] with no solver counts. Such a start's run is stopped once that one is
/// decided, but a short one may end first: its fate and its counts (an atlas point's
/// `evaluations`, a boundary's runs) then depended on the threads' timing (the 4 x 4 chart
/// of `scans/atlas-lambda-nu.toml` gave one point 6136217, 7658863 and 5322316 evaluations
/// in three runs on 2 threads).
fn after_the_first_unsettled(mut out: Vec<(Fate, SolverStats)>) -> Vec<(Fate, SolverStats)> {
    if let Some(first) = out.iter().position(|(f, _)| !f.quiet()) {
        for later in &mut out[first + 1..] {
            *later = (Fate::Stopped, SolverStats::default());
        }
    }
    out
}

/// What the runs at one end of a boundary's bracket did.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Ends {
    /// The value.
    pub value: f64,
    /// The fate of each start there.
    pub fates: Vec<Fate>,
}

impl Ends {
    /// Whether every start ended quiet ([`Fate::quiet`]: settled, or on the slip oscillation
    /// about an unstable steady slip).
    pub fn all_settle(&self) -> bool {
        self.fates.iter().all(Fate::quiet)
    }

    /// The first start that ended on the slip oscillation, by index.
    pub fn first_slip_oscillation(&self) -> Option<(usize, &Fate)> {
        self.fates
            .iter()
            .enumerate()
            .find(|(_, f)| matches!(f, Fate::SlipOscillation { .. }))
    }

    /// The first start that lasted, by index.
    pub fn first_lasting(&self) -> Option<(usize, &Fate)> {
        self.fates.iter().enumerate().find(|(_, f)| f.lasts())
    }

    /// The first start that did not settle (lasted or undecided), by index.
    pub fn first_unsettled(&self) -> Option<(usize, &Fate)> {
        self.fates
            .iter()
            .enumerate()
            .find(|(_, f)| matches!(f, Fate::Lasts { .. } | Fate::Undecided))
    }

    /// How many were undecided.
    pub fn undecided(&self) -> usize {
        self.fates
            .iter()
            .filter(|f| matches!(f, Fate::Undecided))
            .count()
    }
}

/// A boundary bisected on runs: below it some start does not settle, above it every start
/// does.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RunBoundary {
    /// How the search ended ([`BoundaryStatus::BelowRange`]: every start settles already at
    /// the lower end; [`BoundaryStatus::AboveRange`]: some start still does not at the
    /// upper end).
    pub status: BoundaryStatus,
    /// The bisected parameter.
    pub param: BoundaryParam,
    /// The bracket at `dt` (not all settle at its lower end, all at its upper).
    pub bracket: [f64; 2],
    /// The runs at the bracket's ends at `dt` (the confirmation).
    pub below: Option<Ends>,
    /// ... and above.
    pub above: Option<Ends>,
    /// The bracket at `dt / 2`, where it was searched (`None`: the bracket at `dt` held at
    /// `dt / 2`, or not found).
    pub half_dt_bracket: Option<[f64; 2]>,
    /// Whether the bracket at `dt` held at `dt / 2` (the same verdicts at both its ends).
    pub half_dt_holds: Option<bool>,
    /// The step sensitivity of the starts at the bracket's ends ([`step_share`] of
    /// `below`, `above` and their runs at `dt / 2`; `None`: not checked at `dt / 2`).
    /// Not serialised here: the doors write its four figures flat
    /// (`step_sensitivity`, `_se`, `_changed`, `_compared`).
    #[serde(skip)]
    pub step: Option<StepShare>,
    /// The interval holding the boundary at `dt` and at `dt / 2`.
    pub interval: [f64; 2],
    /// Runs made, at `dt` and at `dt / 2`.
    pub runs: u64,
    /// Runs undecided by the horizon (not quiet: squeal is not ruled out).
    pub undecided: u64,
    /// The horizon of every run.
    pub horizon: f64,
    /// The solver's counts over every run.
    pub stats: SolverStats,
}

impl RunBoundary {
    /// As the atlas stores a boundary: the interval (which covers dt/2) as its bracket,
    /// its half-width as the uncertainty, the runs as its evaluations.
    pub fn as_boundary(&self) -> crate::atlas::Boundary {
        let found = self.status == BoundaryStatus::Found;
        crate::atlas::Boundary {
            status: self.status,
            nu: self.value(),
            bracket: self.interval,
            evaluations: u32::try_from(self.runs).unwrap_or(u32::MAX),
            half_dt_holds: self.half_dt_holds,
            uncertainty: match found {
                true => 0.5 * (self.interval[1] - self.interval[0]),
                false => f64::NAN,
            },
            changes: 0,
        }
    }

    /// The geometric middle of [`RunBoundary::interval`] (NaN unless found).
    pub fn value(&self) -> f64 {
        match self.status {
            BoundaryStatus::Found => (self.interval[0] * self.interval[1]).sqrt(),
            _ => f64::NAN,
        }
    }
}

/// The search's running tally.
struct Tally<'a> {
    param: BoundaryParam,
    setup: Setup,
    starts: &'a [State],
    horizon: f64,
    runs: u64,
    undecided: u64,
    stats: SolverStats,
}

impl Tally<'_> {
    /// The runs of every start at value `v` with step `setup.dt` (or half of it), stopped
    /// once one does not settle.
    fn ends(&mut self, v: f64, half: bool) -> Result<Ends, ScanError> {
        let mut s = self
            .setup
            .with_params(self.param.with(self.setup.params, v));
        if half {
            s = s.half_dt();
        }
        let out = fates(s, self.starts, self.horizon, true)?;
        let mut fates_here = Vec::with_capacity(out.len());
        for (f, st) in out {
            self.runs += u64::from(f != Fate::Stopped);
            self.undecided += u64::from(f == Fate::Undecided);
            self.stats.merge(&st);
            fates_here.push(f);
        }
        crate::observe::step(crate::observe::SearchStep::Value(v));
        Ok(Ends {
            value: v,
            fates: fates_here,
        })
    }

    /// Geometric bisection of "all settle" between `lo` (not all) and `hi` (all), keeping
    /// the runs at the final ends.
    fn bisect(
        &mut self,
        (mut lo, mut hi): (Ends, Ends),
        rtol: f64,
        half: bool,
    ) -> Result<(Ends, Ends), ScanError> {
        let mut guard = 0;
        while hi.value / lo.value - 1.0 > rtol && guard < 200 {
            guard += 1;
            let mid = (lo.value * hi.value).sqrt();
            let e = self.ends(mid, half)?;
            if e.all_settle() {
                hi = e;
            } else {
                lo = e;
            }
        }
        Ok((lo, hi))
    }

    /// From `top` (every start settles), down by factors `g` to `floor`: the first value
    /// where some start does not settle and the one above it, bisected to `rtol` (`None`:
    /// every start settles down to `floor`).
    fn down_from(
        &mut self,
        top: Ends,
        (g, floor, rtol): (f64, f64, f64),
        half: bool,
    ) -> Result<Option<(Ends, Ends)>, ScanError> {
        let mut upper = top;
        loop {
            if upper.value <= floor {
                return Ok(None);
            }
            let e = self.ends((upper.value / g).max(floor), half)?;
            if !e.all_settle() {
                return self.bisect((e, upper), rtol, half).map(Some);
            }
            upper = e;
        }
    }

    /// From `bottom` (some start does not settle), up by factors `g` to `ceiling`: the first
    /// value where every start settles, and the one below it, bisected (`None`: some start
    /// does not settle up to `ceiling`).
    fn up_from(
        &mut self,
        bottom: Ends,
        (g, ceiling, rtol): (f64, f64, f64),
        half: bool,
    ) -> Result<Option<(Ends, Ends)>, ScanError> {
        let mut lower = bottom;
        loop {
            if lower.value >= ceiling {
                return Ok(None);
            }
            let e = self.ends((lower.value * g).min(ceiling), half)?;
            if e.all_settle() {
                return self.bisect((lower, e), rtol, half).map(Some);
            }
            lower = e;
        }
    }

    /// The bracket `out.bracket` checked at `dt / 2`: where a verdict at an end differs,
    /// the boundary there is searched outward from that end (by factors `g`, not below `lo`
    /// nor above `ceiling`, bisected to `rtol`) and `out.interval` widened to hold it; the
    /// fates of the starts at both ends compared with `out.below`, `out.above` (`out.step`).
    fn check_half_dt(
        &mut self,
        out: &mut RunBoundary,
        (g, lo, ceiling, rtol): (f64, f64, f64, f64),
    ) -> Result<(), ScanError> {
        let [a, b] = out.bracket;
        let (half_lo, half_hi) = (self.ends(a, true)?, self.ends(b, true)?);
        let holds = !half_lo.all_settle() && half_hi.all_settle();
        out.half_dt_holds = Some(holds);
        if let (Some(l), Some(h)) = (&out.below, &out.above) {
            out.step = Some(step_share(&[(l, &half_lo), (h, &half_hi)]));
        }
        if !holds {
            let below_a = half_hi.all_settle();
            let half = if below_a {
                // At dt / 2 every start settles at a too: the boundary lies below it.
                self.down_from(half_lo, (g, lo, rtol), true)?
            } else {
                self.up_from(half_hi, (g, ceiling, rtol), true)?
            };
            match half {
                Some((l, h)) => {
                    out.half_dt_bracket = Some([l.value, h.value]);
                    out.interval = [a.min(l.value), b.max(h.value)];
                }
                None if below_a => out.interval = [lo, b],
                None => out.interval = [a, ceiling],
            }
        }
        Ok(())
    }
}

/// Whether two runs of one start end the same way: the same kind of [`Fate`] (settles,
/// lasts, ends on the slip oscillation, undecided), whatever its times and figures (when it
/// settled or was identified, the oscillation's frequency and extent, whether its orbit was
/// certified): a fate names no attractor beyond its kind, and its figures move with the step.
pub fn same_fate(a: &Fate, b: &Fate) -> bool {
    std::mem::discriminant(a) == std::mem::discriminant(b)
}

/// The step sensitivity of a bracket's starts: for each pair (the runs at one end at `dt`,
/// and at `dt / 2`), start by start, those run at both steps (neither [`Fate::Stopped`])
/// are compared, and counted as changed where their fates differ ([`same_fate`]).
pub fn step_share(pairs: &[(&Ends, &Ends)]) -> StepShare {
    let (mut changed, mut compared) = (0, 0);
    for (at_dt, at_half) in pairs {
        for (a, b) in at_dt.fates.iter().zip(&at_half.fates) {
            if !matches!(a, Fate::Stopped) && !matches!(b, Fate::Stopped) {
                compared += 1;
                changed += u64::from(!same_fate(a, b));
            }
        }
    }
    StepShare::of(changed, compared)
}

/// Refuses a bracket, tolerance or ceiling the boundary search cannot use, and a horizon
/// that is not a finite time.
fn check_search(range: ParamRange, ceiling: f64, horizon: f64) -> Result<(), ScanError> {
    let ParamRange { lo, hi, rtol } = range;
    if !(lo > 0.0 && hi > lo && hi.is_finite() && rtol > 0.0 && ceiling.is_finite()) {
        return Err(ScanError::Undetermined(format!(
            "bracket [{lo}, {hi}] / rtol {rtol}: need 0 < lo < hi, rtol > 0"
        )));
    }
    if !(horizon.is_finite() && horizon > 0.0) {
        return Err(ScanError::Undetermined(format!(
            "horizon {horizon}: need a finite time > 0"
        )));
    }
    Ok(())
}

/// How many geometric steps the scan from the top takes over the range at least (those of
/// the crisis's coarse scan, [`crate::band::COARSE`]), each at most [`MAX_STEP`]: a window
/// of squeal narrower than one step between two values that settle can be stepped over.
pub const STEPS: usize = crate::band::COARSE;

/// The largest factor between two values of the scan from the top (2.5%): at the brake of
/// MODEL.md section 11 the start from rest does not settle by t = 10000 at c = 151 N s/m
/// and settles at 150.4 and 153 (dt 0.005): windows that narrow exist there.
pub const MAX_STEP: f64 = 1.025;

/// The boundary in `param` above which every start of `starts` settles by `horizon`: the
/// *last* change over the range. The top of `range` first (raised by factors of 4 up to
/// `ceiling` while some start does not settle there), then down from the top in
/// [`STEPS`] geometric steps over the range to the first value where some start does not
/// settle, then bisected to `rtol`; so every scanned value above the answer settles, and a
/// squealing window above a quiet stretch is not missed unless it is narrower than a step.
/// The bracket is then checked at `dt / 2`: where a verdict at an end differs, the boundary
/// there is searched outward from that end and the interval widened to hold it.
pub fn boundary(
    param: BoundaryParam,
    setup: Setup,
    starts: &[State],
    (range, ceiling): (ParamRange, f64),
    horizon: f64,
) -> Result<RunBoundary, ScanError> {
    check_search(range, ceiling, horizon)?;
    let ParamRange { lo, hi, rtol } = range;
    let mut t = Tally {
        param,
        setup,
        starts,
        horizon,
        runs: 0,
        undecided: 0,
        stats: SolverStats::default(),
    };
    let mut out = RunBoundary {
        status: BoundaryStatus::Found,
        param,
        bracket: [lo, hi],
        below: None,
        above: None,
        half_dt_bracket: None,
        half_dt_holds: None,
        step: None,
        interval: [lo, hi],
        runs: 0,
        undecided: 0,
        horizon,
        stats: SolverStats::default(),
    };
    let finish = |mut out: RunBoundary, t: &Tally| {
        out.runs = t.runs;
        out.undecided = t.undecided;
        out.stats = t.stats;
        Ok(out)
    };
    // The top, raised while some start does not settle there.
    crate::observe::stage("runs at the top", None);
    let mut top = t.ends(hi, false)?;
    while !top.all_settle() {
        if top.value >= ceiling {
            out.status = BoundaryStatus::AboveRange;
            out.bracket = [lo, top.value];
            out.below = Some(top);
            return finish(out, &t);
        }
        top = t.ends((top.value * 4.0).min(ceiling), false)?;
    }
    let g = (top.value / lo)
        .powf(1.0 / STEPS as f64)
        .min(MAX_STEP)
        .max(1.0 + rtol);
    crate::observe::stage("down from the top, then bisection", None);
    let Some((below, above)) = t.down_from(top, (g, lo, rtol), false)? else {
        out.status = BoundaryStatus::BelowRange;
        return finish(out, &t);
    };
    let [a, b] = [below.value, above.value];
    out.bracket = [a, b];
    out.interval = [a, b];
    (out.below, out.above) = (Some(below), Some(above));
    crate::observe::stage("the bracket at dt / 2", None);
    t.check_half_dt(&mut out, (g, lo, ceiling, rtol))?;
    finish(out, &t)
}

/// The critical value of `param` for `start`: above it the run from `start` settles by
/// `horizon`, below it the run lasts (or is undecided).
pub fn critical(
    param: BoundaryParam,
    setup: Setup,
    start: State,
    range: (ParamRange, f64),
    horizon: f64,
) -> Result<RunBoundary, ScanError> {
    boundary(param, setup, &[start], range, horizon)
}

/// The fold in `param`: above it every start of the [`Spread`] (of the parameters at the
/// range's lower end) settles by `horizon`.
pub fn fold(
    param: BoundaryParam,
    setup: Setup,
    range: (ParamRange, f64),
    horizon: f64,
) -> Result<RunBoundary, ScanError> {
    let spread = starts(true, (param, setup), range.0.lo, State { x: 0.0, v: 0.0 });
    boundary(param, setup, &spread, range, horizon)
}

/// The starts a boundary in `param` samples: for a fold the [`Spread`] of the parameters at
/// the range's lower end `lo`, else the one `start` (of a critical value). The one choice of
/// `squeal critical`, the atlas's boundaries and Python's.
pub fn starts(
    fold: bool,
    (param, setup): (BoundaryParam, Setup),
    lo: f64,
    start: State,
) -> Vec<State> {
    match fold {
        true => Spread::of(&param.with(setup.params, lo)).starts,
        false => vec![start],
    }
}

/// Why an answer is the runs'.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "why", content = "words", rename_all = "snake_case")]
pub enum Why {
    /// The model lies outside the region the shortcuts were checked in (the warning of
    /// [`squeal_core::validated::Validity`]).
    Unchecked(String),
    /// A run at the shortcut's answer contradicted it (what the run did).
    Refuted(String),
    /// The shortcut found no answer in the range, whose top the runs may raise (why not).
    BeyondRange(String),
}

impl Why {
    /// In words.
    pub fn words(&self) -> String {
        match self {
            Why::Unchecked(w) => format!("the shortcuts are not checked here ({w})"),
            Why::Refuted(w) => format!("the shortcut's answer was refuted by a run: {w}"),
            Why::BeyondRange(w) => {
                format!("the shortcut has no answer in the range ({w}), whose top the runs raise")
            }
        }
    }
}

/// A boundary as a shortcut gave it and runs confirmed it, or as runs gave it.
#[derive(Clone, Debug, PartialEq)]
pub enum Decided<T> {
    /// The shortcut's answer, confirmed by runs at its bracket (`None`: nothing to confirm,
    /// the boundary lies outside the range).
    Shortcut {
        /// The shortcut's answer.
        answer: T,
        /// The runs at its bracket.
        confirmed: Option<Confirmation>,
    },
    /// The runs' answer ([`boundary`]), and why the shortcut's was not taken.
    Runs {
        /// The runs' boundary (boxed: it holds every start's fate at the bracket's ends).
        boundary: Box<RunBoundary>,
        /// Why.
        why: Why,
    },
}

/// The one gate of a boundary (the critical value of a start, the fold over the spread):
/// outside the region its shortcuts were checked in ([`Validity`]) the answer is the runs'
/// ([`boundary`]); inside, the `shortcut` (its answer and the bracket to confirm, `None`
/// outside its range) is confirmed by runs at its bracket's ends ([`confirm`]), and where a
/// run contradicts it the answer is the runs' again, saying why. Where the shortcut finds
/// the range's top too low and the top may be raised (`ceiling` above it), the runs answer. `CLI` and Python both
/// decide here.
pub fn decide<T>(
    (setup, param): (Setup, BoundaryParam),
    starts: &[State],
    (range, ceiling): (ParamRange, f64),
    horizon: f64,
    shortcut: impl FnOnce() -> Result<(T, Option<[f64; 2]>), ScanError>,
) -> Result<Decided<T>, ScanError> {
    let runs = |why: Why| -> Result<Decided<T>, ScanError> {
        let boundary = Box::new(boundary(param, setup, starts, (range, ceiling), horizon)?);
        Ok(Decided::Runs { boundary, why })
    };
    if let Some(w) = unchecked(&setup.params) {
        return runs(Why::Unchecked(w));
    }
    let (answer, bracket) = match shortcut() {
        // The cycle encloses the start only above the range's top: the runs raise the top
        // (to `ceiling`) as they do where the shortcut is not checked.
        Err(ScanError::Bracket { problem, nu_hi, .. })
            if ceiling > range.hi && problem.at_high().is_some() =>
        {
            let at_high = problem.at_high().unwrap_or_default();
            let w = format!("{at_high}, {}", squeal_core::error::Number(nu_hi));
            return runs(Why::BeyondRange(w));
        }
        r => r?,
    };
    let Some(bracket) = bracket else {
        return Ok(Decided::Shortcut {
            answer,
            confirmed: None,
        });
    };
    crate::observe::stage("runs at the answer", Some(2));
    let c = confirm(setup, param, starts, bracket, horizon)?;
    match c.refuted.clone() {
        Some(why) => runs(Why::Refuted(why)),
        None => Ok(Decided::Shortcut {
            answer,
            confirmed: Some(c),
        }),
    }
}

#[cfg(test)]
mod tests;
