//! Helpers shared by the tests of the laws with true stick (`stribeck.rs`, `cubic.rs`).

use squeal_core::{Params, Run, Scheme, SolverConfig, State, Stepper};

/// The stepper of `p` at step `dt` with `scheme` (the robust solver).
pub fn stepper(p: Params, dt: f64, scheme: Scheme) -> Stepper {
    Stepper::new(
        p,
        dt,
        SolverConfig {
            scheme,
            ..Default::default()
        },
    )
    .unwrap()
}

/// Absolute times of the first `n` onsets and breakaways of a run from `ic`.
pub fn events(st: &Stepper, ic: State, t_end: f64) -> (Vec<f64>, Vec<f64>, u64) {
    let mut run = Run::new(st, ic);
    let (mut on, mut off, mut rev) = (Vec::new(), Vec::new(), 0);
    for _ in 0..run.steps_to(t_end) {
        let s = run.step();
        if s.events.onsets > 0 {
            assert_eq!(s.events.onsets, 1, "one onset per step at most here");
            on.push(s.prev.t + s.events.onset_at);
        }
        if s.events.breakaways > 0 {
            off.push(s.prev.t + s.events.breakaway_at);
        }
        rev += u64::from(s.events.reversals);
    }
    assert_eq!(run.stats().failures, 0);
    (on, off, rev)
}
