//! One way to advance a run: [`Run`] owns the current [`Sample`], the solver counters and what
//! the run has seen (largest residual, the quasi-static branch), and yields one [`Step`] at a
//! time. The classifier, section returns, the trajectory command, the tests and the benches
//! are all observers of this one loop.
//!
//! ```
//! use squeal_core::{FrictionLaw, Params, Run, SolverConfig, State, Stepper};
//! let st = Stepper::new(Params::paper(FrictionLaw::McMillan, 1e-3), 0.01,
//!                       SolverConfig::default()).unwrap();
//! let mut run = Run::new(&st, State { x: 0.0, v: 0.0 });
//! let last = run.by_ref().take(1000).last().unwrap();
//! assert_eq!(last.next.t, 10.0);
//! assert!(run.stats().failures == 0 && run.steps() == 1000);
//! ```

use crate::friction::Branch;
use crate::solver::{Solution, SolverStats};
use crate::stepper::{Sample, State, Stepper};
use crate::stick::StickEvents;

/// One step of a run: the samples before and after it and the solve of its force.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Step {
    /// The sample at the start of the step.
    pub prev: Sample,
    /// The sample at its end.
    pub next: Sample,
    /// The implicit solve of the end-of-step force.
    pub solution: Solution,
    /// Stick events located inside the step (laws with true stick; times from `prev.t`).
    pub events: StickEvents,
}

/// A run of the oscillator from one initial condition. As an [`Iterator`] it never ends:
/// bound it with `take` or a time limit ([`Run::steps_to`]).
#[derive(Clone, Debug)]
pub struct Run<'a> {
    stepper: &'a Stepper,
    sample: Sample,
    t0: f64,
    steps: u64,
    stats: SolverStats,
    initial: Option<Solution>,
    max_residual: f64,
    quasi_static: bool,
}

impl<'a> Run<'a> {
    /// Starts at `ic` with the initial force and acceleration solved (paper: from `x''(0) = 0`).
    pub fn new(stepper: &'a Stepper, ic: State) -> Run<'a> {
        Run::new_near(stepper, ic, None)
    }

    /// [`Run::new`] on the root nearest the force `near`, where given
    /// ([`Stepper::initial_near`]).
    pub fn new_near(stepper: &'a Stepper, ic: State, near: Option<f64>) -> Run<'a> {
        let mut stats = SolverStats::default();
        let (sample, sol) = stepper.initial_near(ic, near, &mut stats);
        Run {
            stepper,
            sample,
            t0: 0.0,
            steps: 0,
            stats,
            initial: Some(sol),
            max_residual: sol.residual,
            quasi_static: sol.branch == Branch::QuasiStatic,
        }
    }

    /// Continues from a sample (its force is the previous step's), with fresh counters.
    pub fn from_sample(stepper: &'a Stepper, sample: Sample) -> Run<'a> {
        Run {
            stepper,
            sample,
            t0: sample.t,
            steps: 0,
            stats: SolverStats::default(),
            initial: None,
            max_residual: 0.0,
            quasi_static: false,
        }
    }

    /// One step. Time is `t0 + k dt` by index, not by accumulated addition.
    #[inline]
    pub fn step(&mut self) -> Step {
        let prev = self.sample;
        let (mut next, solution, events) = self.stepper.advance(&prev, &mut self.stats);
        self.steps += 1;
        next.t = self.t0 + self.steps as f64 * self.stepper.dt();
        self.max_residual = self.max_residual.max(solution.residual);
        self.quasi_static |= solution.branch == Branch::QuasiStatic;
        self.sample = next;
        Step {
            prev,
            next,
            solution,
            events,
        }
    }

    /// Steps needed to reach time `t` from the start (rounded up).
    pub fn steps_to(&self, t: f64) -> u64 {
        ((t - self.t0) / self.stepper.dt()).ceil().max(0.0) as u64
    }

    /// The current sample.
    pub fn sample(&self) -> &Sample {
        &self.sample
    }

    /// The stepper.
    pub fn stepper(&self) -> &'a Stepper {
        self.stepper
    }

    /// This run's solver counters (the initial solve included).
    pub fn stats(&self) -> &SolverStats {
        &self.stats
    }

    /// The initial solve, if the run started from a state.
    pub fn initial(&self) -> Option<&Solution> {
        self.initial.as_ref()
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Whether this run's robust solve failed anywhere (its own counters only).
    pub fn failed(&self) -> bool {
        self.stats.failures > 0
    }

    /// Largest `|G(F)|` of any solve of this run.
    pub fn max_residual(&self) -> f64 {
        self.max_residual
    }

    /// Whether any solve of this run ended on the quasi-static branch of the law (the branch
    /// of the evaluation that gave the force).
    pub fn quasi_static(&self) -> bool {
        self.quasi_static
    }
}

impl Iterator for Run<'_> {
    type Item = Step;
    #[inline]
    fn next(&mut self) -> Option<Step> {
        Some(self.step())
    }
}

/// The samples of a run kept for output, column by column (a trajectory file's datasets).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Samples {
    /// Time.
    pub t: Vec<f64>,
    /// Displacement `x`.
    pub x: Vec<f64>,
    /// Velocity `x'`.
    pub v: Vec<f64>,
    /// Acceleration `x''`.
    pub a: Vec<f64>,
    /// Friction force `F`.
    pub force: Vec<f64>,
}

impl Samples {
    /// Appends one sample.
    pub fn push(&mut self, s: &Sample) {
        self.t.push(s.t);
        self.x.push(s.x);
        self.v.push(s.v);
        self.a.push(s.a);
        self.force.push(s.force);
    }

    /// Number of samples kept.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// Whether none is kept.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }
}
