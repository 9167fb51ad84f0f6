//! Does stepping several independent runs in turn hide the latency of one run's solve?
//!
//! The McMillan step is latency bound (docs/history/benchmarks.md, "Cost per step, reduced"): each
//! Newton iterate waits for the law at the last one. Runs of a section search or of a line's points
//! are independent, so stepping `n` of them in turn, one step each, would let the processor
//! overlap their chains if the step were short and branch-free enough. This measures it: the
//! same `n` runs (nu = 1e-3, Table 1, starts (1.2 + 0.3 i, 0.1 i)), first one after the
//! other, then interleaved step by step, 2,000,000 steps each, in one process.
//!
//! `cargo run --release -p squeal-core --example interleave -- N`

use std::time::Instant;

use squeal_core::{FrictionLaw, Params, Run, SolverConfig, State, Stepper};

const STEPS: usize = 2_000_000;

fn main() {
    let n: usize = match std::env::args().nth(1).map(|s| s.parse()) {
        None => 4,
        Some(Ok(n)) if n > 0 => n,
        Some(_) => panic!("expected the number of runs, a positive integer"),
    };
    let params = Params::paper(FrictionLaw::McMillan, 1e-3);
    let st = Stepper::new(params, squeal_core::defaults::DT, SolverConfig::default())
        .expect("Table 1's parameters are valid");
    let ics: Vec<State> = (0..n)
        .map(|i| State {
            x: 1.2 + 0.3 * i as f64,
            v: 0.1 * i as f64,
        })
        .collect();

    let t0 = Instant::now();
    let mut end_seq = 0.0;
    for ic in &ics {
        let mut r = Run::new(&st, *ic);
        for _ in 0..STEPS {
            end_seq += r.step().next.state().x;
        }
    }
    let seq = t0.elapsed().as_secs_f64();

    let t0 = Instant::now();
    let mut runs: Vec<Run> = ics.iter().map(|ic| Run::new(&st, *ic)).collect();
    let mut end_il = 0.0;
    for _ in 0..STEPS {
        for r in runs.iter_mut() {
            end_il += r.step().next.state().x;
        }
    }
    let il = t0.elapsed().as_secs_f64();

    let per = |s: f64| s / (n * STEPS) as f64 * 1e9;
    // The sums of x over every step: the same runs either way, up to the order of addition.
    println!(
        "n = {n}: one after the other {:.1} ns/step, interleaved {:.1} ns/step, ratio {:.2} (sums of x {end_seq:.6e}, {end_il:.6e})",
        per(seq),
        per(il),
        seq / il
    );
}
