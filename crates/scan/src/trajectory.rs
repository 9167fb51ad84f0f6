//! One run from a start to `t_end`, integrated once, with everything `squeal trajectory` and
//! the Python `squeal.trajectory` report about it: the kept samples, the label every path
//! gives the start (taken at its decision while the run goes on to `t_end`, and refuted where
//! the run then contradicts it), the final oscillation from the last crossings of the section
//! `x = x*, x' > 0`, the stick phases of a law with true stick and the solver's counts. Both
//! front ends call [`run_in`]; neither has a stepping loop of its own.

use std::sync::atomic::{AtomicBool, Ordering};

use serde::Serialize;
use squeal_core::classify::{Watch, crossing};
use squeal_core::{
    Classifier, Lasting, Outcome, Reason, Regime, Run, Sample, Samples, Shortcuts, SolverStats,
    State, Step, Stepper, TurnWatch,
};

use crate::error::ScanError;
use crate::scanner::MapContext;

/// How many times of unconverged paper-iteration steps are kept.
pub const FIRST_UNCONVERGED: usize = 5;
/// How many stick onset and breakaway times are kept from the start of the run.
pub const FIRST_EVENTS: usize = 5;

/// The stick phases of a law with true stick, from the events located inside the steps.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct StickPhases {
    /// Stick onsets.
    pub onsets: u64,
    /// Breakaways.
    pub breakaways: u64,
    /// Passages through zero slip without sticking.
    pub reversals: u64,
    /// Times of the first few onsets.
    pub first_onsets: Vec<f64>,
    /// Times of the first few breakaways.
    pub first_breakaways: Vec<f64>,
    /// Time of the last onset located (`null` if none; the first onset of its step).
    pub last_onset: Option<f64>,
    /// Time of the last breakaway located (`null` if none; the first of its step).
    pub last_breakaway: Option<f64>,
    /// Whether the block is stuck at the end of the run.
    pub stuck_at_end: bool,
}

impl StickPhases {
    fn observe(&mut self, step: &Step) {
        let e = &step.events;
        self.stuck_at_end = step.solution.branch == squeal_core::friction::Branch::Stick;
        self.onsets += u64::from(e.onsets);
        self.breakaways += u64::from(e.breakaways);
        self.reversals += u64::from(e.reversals);
        if e.onsets > 0 {
            let t = step.prev.t + e.onset_at;
            if self.first_onsets.len() < FIRST_EVENTS {
                self.first_onsets.push(t);
            }
            self.last_onset = Some(t);
        }
        if e.breakaways > 0 {
            let t = step.prev.t + e.breakaway_at;
            if self.first_breakaways.len() < FIRST_EVENTS {
                self.first_breakaways.push(t);
            }
            self.last_breakaway = Some(t);
        }
    }
}

/// The final oscillation, from the last section crossings.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Oscillation {
    /// Section crossings over the whole run.
    pub crossings: u64,
    /// `2 pi / (t_k - t_{k-1})` of the last two crossings; `null` if fewer than two.
    pub omega: Option<f64>,
    /// `x'` at the last crossing; `null` if none.
    pub amplitude: Option<f64>,
    /// Time of the last crossing; `null` if none.
    pub t_last_crossing: Option<f64>,
}

impl Oscillation {
    /// No crossing yet.
    const NONE: Oscillation = Oscillation {
        crossings: 0,
        omega: None,
        amplitude: None,
        t_last_crossing: None,
    };

    /// A crossing of the section at time `t` with `x' = r`.
    fn observe(&mut self, t: f64, r: f64) {
        self.crossings += 1;
        let finite = |x: f64| x.is_finite().then_some(x);
        self.omega = self
            .t_last_crossing
            .and_then(|t0| finite(std::f64::consts::TAU / (t - t0)));
        self.t_last_crossing = finite(t);
        self.amplitude = finite(r);
    }
}

/// The steps whose solve did not converge: how many, and the times of the first few.
#[derive(Default)]
struct Unconverged {
    steps: u64,
    first: Vec<f64>,
}

impl Unconverged {
    fn observe(&mut self, t: f64, converged: bool) {
        if !converged {
            self.steps += 1;
            if self.first.len() < FIRST_UNCONVERGED {
                self.first.push(t);
            }
        }
    }
}

/// Samples per natural period `2 pi` that a run keeps by default: a circle drawn through
/// 100 points strays from its radius by under 0.05% (`1 - cos(pi / 100)`), and a stick-slip
/// cycle (longer than the natural period) gets more.
pub const SAMPLES_PER_PERIOD: f64 = 100.0;

/// At most this many samples are kept by default (about 7 MB of CSV for a physical run):
/// `every = 1` wrote every one of 200 000 steps of a six-second brake run.
pub const DEFAULT_MAX_SAMPLES: u64 = 100_000;

/// How the stride of the kept samples was chosen: given by the user (`--every N`, Python's
/// `every=`), or by [`default_every`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sampling {
    /// The user's stride.
    Given,
    /// The stride [`default_every`] chose.
    Default,
}

impl Sampling {
    /// The stride in words, as files and summaries state it.
    pub fn words(self, every: u64, dt: f64) -> String {
        let stride = format!("one sample every {every} steps of dt = {dt}");
        match self {
            Sampling::Given => format!("{stride} (as asked)"),
            Sampling::Default => format!(
                "{stride} (the default: at least {SAMPLES_PER_PERIOD} samples per natural \
                 period 2 pi, at most {DEFAULT_MAX_SAMPLES} samples; an explicit every sets it)"
            ),
        }
    }
}

/// The default stride of a run of `t_end` with steps of `dt`: the largest that keeps at
/// least [`SAMPLES_PER_PERIOD`] samples per natural period `2 pi`, raised where the run would
/// keep more than [`DEFAULT_MAX_SAMPLES`] (the start and every `every`-th step).
pub fn default_every(dt: f64, t_end: f64) -> u64 {
    let per_period = (std::f64::consts::TAU / (SAMPLES_PER_PERIOD * dt)).floor();
    let steps = (t_end / dt).ceil();
    let capped = (steps / (DEFAULT_MAX_SAMPLES - 1) as f64).ceil();
    // `as` saturates: a NaN (refused before by `Span::check`) gives 0, raised to 1.
    (per_period.max(capped) as u64).max(1)
}

/// At most this many samples of a run are kept in memory for a file or a plot (40 bytes
/// each), by every door (`squeal trajectory --out/--plot`, Python's `trajectory`).
pub const MAX_ROWS: u64 = 20_000_000;

/// What to run: the start, the end, and which samples to keep.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Span {
    /// The start (nondimensional).
    pub ic: State,
    /// The end of the run (`t_max` of the classifier too).
    pub t_end: f64,
    /// Keep every `every`-th sample (and the start); 0 keeps none.
    pub every: u64,
}

impl Span {
    /// The run's start and end checked before any computing, by the rules every path to a
    /// run follows (`squeal trajectory`, the Python `squeal.trajectory`): each coordinate of
    /// the start finite and within the escape radius ([`crate::bounds::state`]; beyond it
    /// the classifier labels the run before its first step), `t_end` finite and > 0, and at
    /// most [`crate::bounds::MAX_STEPS`] steps of `dt`. `keys` name the start's two
    /// coordinates and the end in messages (flags or argument names).
    pub fn check(
        &self,
        dt: f64,
        keys: [&str; 3],
        invalid: crate::bounds::Invalid,
    ) -> Result<(), ScanError> {
        crate::bounds::state(keys[0], self.ic.x, invalid)?;
        crate::bounds::state(keys[1], self.ic.v, invalid)?;
        if !(self.t_end.is_finite() && self.t_end > 0.0) {
            return Err(invalid(
                keys[2],
                format!("{:?}", self.t_end),
                "a finite time > 0",
            ));
        }
        let steps = self.t_end / dt;
        if steps > crate::bounds::MAX_STEPS {
            return Err(invalid(
                keys[2],
                format!("{:?}", self.t_end),
                &format!(
                    "with dt {dt:?}, {steps:.3e} steps, at most 1e10 (about 40 minutes at 250 \
                     ns per step): a shorter run or a larger step"
                ),
            ));
        }
        Ok(())
    }
}

/// One run and what was seen on it.
#[derive(Clone, Debug)]
pub struct Trajectory {
    /// The kept samples.
    pub samples: Samples,
    /// The label of the start, as every path gives it ([`run_in`]), unless the run refuted
    /// it ([`Trajectory::refuted`]): then the run's own verdict.
    pub outcome: Outcome,
    /// The run's own verdict (the map's classifier without the trap or any shortcut: the
    /// fixed point reached, or its band rules), unless the run refuted it as it refutes the
    /// label.
    pub own: Outcome,
    /// The run with no rule at all: steady slip where it reached the fixed point by
    /// `t_end`, else undecided (`time_limit`: still moving at `t_end`).
    pub rest: Outcome,
    /// The label was decided at the start, without the run ([`run_in`]).
    pub at_start: bool,
    /// The rule that labelled the start stick-slip although its run then reached the fixed
    /// point: refuted by the run, whose verdict is the label.
    pub refuted: Option<Reason>,
    /// The steady-slip fixed point.
    pub fixed_point: State,
    /// The final oscillation.
    pub oscillation: Oscillation,
    /// The lasting oscillation of the run's last turns (maximum of `x` to maximum,
    /// [`squeal_core::turns`]), wherever it lies, if the band test of its window passed at
    /// the last closed turn (the classifier's window and widths): its frequency and extent,
    /// whether it sticks, reverses its slip and crosses the section.
    pub lasting: Option<Lasting>,
    /// Stick phases (laws with true stick only).
    pub stick: Option<StickPhases>,
    /// Steps (the initial solve included) whose solve did not converge.
    pub unconverged_steps: u64,
    /// Times of the first few of them.
    pub first_unconverged_times: Vec<f64>,
    /// The state at the end.
    pub final_state: Sample,
    /// The solver's counts.
    pub stats: SolverStats,
    /// Largest residual of a solve.
    pub max_residual: f64,
    /// Steps taken.
    pub steps: u64,
}

/// Runs `span` with `stepper` to its end (or until `stop` is raised, checked every 4096
/// steps, or the state is no longer finite, or, with `until_settled`, the fixed point is
/// reached), three classifiers watching the one run, each verdict taken at its decision
/// while the run goes on: `label` with `shortcuts` (the rules a scan decides by), `own` (the
/// run's own verdict: no trap, no shortcut) and `rest` (no rule at all: only the fixed point
/// reached decides).
fn watch_run(
    stepper: &Stepper,
    (label, shortcuts): (&Classifier, Shortcuts),
    (own_cl, rest_cl): (&Classifier, &Classifier),
    span: Span,
    (stop, until_settled): (Option<&AtomicBool>, bool),
) -> Trajectory {
    let p = *stepper.params();
    let fp = p.fixed_point();
    let mut watch = label.watch_with(&p, shortcuts);
    let mut own_watch = own_cl.watch(&p);
    let mut rest_watch = rest_cl.watch(&p);
    let (mut outcome, mut own, mut rest) = (None, None, None);
    let mut run = Run::new(stepper, span.ic);
    let mut samples = Samples::default();
    let mut unconverged = Unconverged::default();
    unconverged.observe(0.0, run.initial().is_none_or(|sol| sol.converged));
    if span.every > 0 {
        samples.push(run.sample());
    }
    let mut stick = p.law.family().locates_stick().then(StickPhases::default);
    let mut osc = Oscillation::NONE;
    let mut turns = TurnWatch::new(&p, label.turn_settings(&p));
    let mut lasting = None;
    let steps = (span.t_end / stepper.dt()).ceil() as u64;
    for k in 1..=steps {
        let step = run.step();
        let n = step.next;
        unconverged.observe(n.t, step.solution.converged);
        if let Some(sp) = stick.as_mut() {
            sp.observe(&step);
        }
        verdict(&mut watch, &mut outcome, (&run, &step));
        verdict(&mut own_watch, &mut own, (&run, &step));
        let settled = verdict(&mut rest_watch, &mut rest, (&run, &step));
        if until_settled && settled == Some(Regime::SteadySlip) {
            break;
        }
        if let Some(c) = crossing(fp.x, &step.prev, &n) {
            osc.observe(c.t, c.r);
        }
        if turns.observe_step(&run, &step).is_some() {
            lasting = turns.lasting();
        }
        if span.every > 0 && k % span.every == 0 {
            samples.push(&n);
        }
        if !n.x.is_finite() || !n.v.is_finite() {
            break;
        }
        if k % 4096 == 0 && stop.is_some_and(|s| s.load(Ordering::Relaxed)) {
            break;
        }
    }
    let undecided = (Regime::Undecided, Reason::TimeLimit);
    let outcome = outcome.unwrap_or_else(|| watch.finish(undecided, &run));
    let own = own.unwrap_or_else(|| own_watch.finish(undecided, &run));
    let rest = rest.unwrap_or_else(|| rest_watch.finish(undecided, &run));
    Trajectory {
        samples,
        outcome,
        own,
        rest,
        at_start: false,
        refuted: None,
        fixed_point: fp,
        oscillation: osc,
        lasting,
        stick,
        unconverged_steps: unconverged.steps,
        first_unconverged_times: unconverged.first,
        final_state: *run.sample(),
        stats: *run.stats(),
        max_residual: run.max_residual(),
        steps: run.steps(),
    }
}

/// Feeds `step` to `watch` while `verdict` is not yet taken, and takes it at the watch's
/// decision: the regime decided at this step, if any.
fn verdict(
    watch: &mut Watch,
    verdict: &mut Option<Outcome>,
    (run, step): (&Run, &Step),
) -> Option<Regime> {
    if verdict.is_some() {
        return None;
    }
    let decision = watch.observe(run, step)?;
    *verdict = Some(watch.finish(decision, run));
    Some(decision.0)
}

/// One run from `span`'s start to its end in the map context `ctx` ([`MapContext::prepare`]),
/// labelled as [`MapContext::classify`] labels the start (`squeal classify`, `scan`): by the
/// start rule or the certified region where they decide it, else by the map's classifier
/// (its trap, band rules and shortcuts) watching this run, with `t_max = t_end`. One path:
/// the same rules in the same order, so the commands agree.
///
/// The run goes on to `t_end` after that decision, watched also by the classifier without
/// the trap or a shortcut ([`Trajectory::own`]) and by one without any rule
/// ([`Trajectory::rest`]: only the fixed point reached decides). A run never contradicts its
/// own label: where a rule said stick-slip and the run then reaches the fixed point, the
/// rule is refuted by the run ([`Trajectory::refuted`]) and the label is the run's.
pub fn run_in(ctx: &MapContext, span: Span, stop: Option<&AtomicBool>) -> Trajectory {
    let label = Classifier {
        t_max: span.t_end,
        ..ctx.classifier
    };
    let own = Classifier {
        trap: None,
        ..label
    };
    let rest = Classifier {
        band_rules: false,
        ..own
    };
    let at = ctx.decide_at_start(span.ic);
    let shortcuts = match at {
        Some(_) => Shortcuts::NONE,
        None => ctx.shortcuts,
    };
    let at_dt = (&label, shortcuts);
    let mut t = watch_run(&ctx.stepper, at_dt, (&own, &rest), span, (stop, false));
    if let Some(at) = at {
        t.at_start = true;
        t.outcome = at;
    }
    refute(&mut t);
    t
}

/// The band rules and limits every path sets for a run from `ic` to `t_end`
/// ([`crate::scanner::classifier_for`], its section searched out to beyond the start).
fn classifier(stepper: &Stepper, base: &Classifier, span: &Span) -> Classifier {
    let fp = stepper.params().fixed_point();
    crate::scanner::classifier_for(
        stepper,
        Classifier {
            t_max: span.t_end,
            ..*base
        },
        1.2 * (span.ic.x - fp.x).hypot(span.ic.v - fp.v),
    )
}

/// Runs `span` with `stepper` to its end (or until `stop` is raised, checked every 4096
/// steps, or the state is no longer finite), labelled by `base` with the band rules set by
/// the section searched out to beyond the start ([`crate::scanner::classifier_for`]), with
/// no map context: no start rule, no shortcut. The run keeps its label as [`run_in`] does.
pub fn run(
    stepper: &Stepper,
    base: &Classifier,
    span: Span,
    stop: Option<&AtomicBool>,
) -> Trajectory {
    let cl = classifier(stepper, base, &span);
    let rest = Classifier {
        trap: None,
        band_rules: false,
        ..cl
    };
    let mut t = watch_run(
        stepper,
        (&cl, Shortcuts::NONE),
        (&cl, &rest),
        span,
        (stop, false),
    );
    refute(&mut t);
    t
}

/// Runs from `ic` until it reaches the fixed point or `t_end`, watched by `base` with its
/// band rules and no trap or shortcut (`own`) and by the fixed point alone (`rest`): the
/// run behind a [`crate::fates::Fate`]. No samples are kept and no section is searched.
pub fn run_to_fate(
    stepper: &Stepper,
    base: &Classifier,
    (ic, t_end): (State, f64),
    stop: Option<&AtomicBool>,
) -> Trajectory {
    let own = Classifier {
        t_max: t_end,
        trap: None,
        band_rules: true,
        ..*base
    };
    let rest = Classifier {
        band_rules: false,
        ..own
    };
    let span = Span {
        ic,
        t_end,
        every: 0,
    };
    let mut t = watch_run(
        stepper,
        (&own, Shortcuts::NONE),
        (&own, &rest),
        span,
        (stop, true),
    );
    refute(&mut t);
    t
}

/// A run never contradicts its own label: where the label (or the run's own verdict) is
/// stick-slip and the run then reached the fixed point, the rule that said so is refuted
/// and the run's verdict stands.
fn refute(t: &mut Trajectory) {
    let settles = t.rest.regime == Regime::SteadySlip;
    if t.outcome.regime == Regime::StickSlip && settles {
        t.refuted = Some(t.outcome.reason);
        t.outcome = t.rest;
    }
    if t.own.regime == Regime::StickSlip && settles {
        t.own = t.rest;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The run's checks at their bounds' ends: the escape radius 1e6 (`bounds::MAX_STATE`)
    /// and 1e10 steps (`bounds::MAX_STEPS`), each refusal naming the key it was given.
    #[test]
    fn a_run_is_checked_at_the_ends_of_its_bounds() {
        let inv = |key: &str, value: String, expected: &str| ScanError::Invalid {
            path: "t".into(),
            key: key.into(),
            value,
            expected: expected.into(),
        };
        let span = |x: f64, t_end: f64| Span {
            ic: State { x, v: 0.0 },
            t_end,
            every: 1,
        };
        let check = |s: Span| {
            s.check(0.5, ["x", "v", "end"], &inv)
                .map_err(|e| e.to_string())
        };
        assert!(
            check(span(1e6, 5e9)).is_ok(),
            "1e6 and exactly 1e10 steps of 0.5"
        );
        let e = check(span(1e6_f64.next_up(), 1.0)).unwrap_err();
        assert!(e.contains("`x` = 1000000.0000000001"), "{e}");
        let e = check(span(0.0, 5e9_f64.next_up())).unwrap_err();
        assert!(e.contains("`end` =") && e.contains("at most 1e10"), "{e}");
        for t_end in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(check(span(0.0, t_end)).unwrap_err().contains("`end`"));
        }
        let e = check(Span {
            ic: State {
                x: 0.0,
                v: f64::NAN,
            },
            ..span(0.0, 1.0)
        })
        .unwrap_err();
        assert!(e.contains("`v` = NaN"), "{e}");
    }

    /// The default stride: at least 100 samples per period 2 pi, at most 100 000 samples.
    #[test]
    fn the_default_stride_suits_the_run() {
        // dt = 0.005 (the default step): 2 pi / (100 * 0.005) = 12.57, so every 12th step,
        // 104.7 samples per period; t_end 1000 keeps 200 000 / 12 + 1 = 16 667 samples.
        assert_eq!(default_every(0.005, 1000.0), 12);
        // dt = 0.01: 2 pi / 1 = 6.28, so every 6th step.
        assert_eq!(default_every(0.01, 20.0), 6);
        // A step longer than a hundredth of the period keeps every step.
        assert_eq!(default_every(0.1, 20.0), 1);
        // 1e8 steps of 0.005: the cap, ceil(1e8 / 99 999) = 1001, at most 99 901 samples.
        let every = default_every(0.005, 5e5);
        assert_eq!(every, 1001);
        assert!(100_000_000 / every < DEFAULT_MAX_SAMPLES);
        let words = Sampling::Default.words(12, 0.005);
        assert!(
            words.contains("every 12 steps of dt = 0.005 (the default"),
            "{words}"
        );
        assert!(Sampling::Given.words(3, 0.01).ends_with("(as asked)"));
    }
}
