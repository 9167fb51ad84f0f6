//! Fates against long runs where steady slip is unstable (McMillan's law with
//! `k = (1 - 2/pi) tau / lambda > 1`, crates/core/MODEL.md section 5): ten starts at each of
//! three belt speeds, lambda = 0.1, 0.2 and 0.3 at tau = 1, phi = 0.9 (k = 3.63, 1.82,
//! 1.21), each at the damping where the start at rest stops squealing (`squeal critical
//! --lambda L --tau 1 --phi 0.9 --nu-hi 8`: nu = 1.663, 0.519, 0.269 at dt = 0.005), so
//! that both oscillations occur among the starts.
//!
//! The truth is each start's own run to t = 20000, read without any rule: where it ends on
//! an oscillation (the turns' band of its last window), whether a turn of that window stuck
//! or reversed the slip (the squeal) or none did (the slip oscillation about the unstable
//! steady slip); where it ends within `fp_radius` of the fixed point, it settled. No label
//! (the scan's, as `squeal scan`, `classify` and `trajectory` decide it) and no fate (as
//! `squeal critical` decides it, [`squeal_scan::fates::fate`]) may name another attractor;
//! undecided is allowed, counted and printed.
//!
//! ```text
//! cargo test --workspace --test scanning -- --ignored --nocapture unstable_steady::
//! ```

use rayon::prelude::*;
use squeal_core::{Classifier, Regime, Run, Setup, State, TurnWatch};
use squeal_scan::Plan;
use squeal_scan::fates::{Fate, fate};
use squeal_scan::scanner::MapContext;

/// The truth's horizon.
const T_TRUTH: f64 = 20000.0;

/// `(lambda, nu)`: the three belt speeds and the damping where the start at rest stops
/// squealing there (module docs).
const CASES: [(f64, f64); 3] = [(0.1, 1.663), (0.2, 0.519), (0.3, 0.269)];

/// Where a run ends, by its own last window.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum End {
    Settles,
    Squeals,
    SlipOscillation,
    Unknown,
}

/// The one-map spec of the ten starts at `lambda`, `nu`: `x0` in {0, 0.5, 1, 1.5, 2} (the
/// squeal's loop lies about x = 0.5, the fixed point at 1), `x'0` in {-0.05, 0.3}.
fn spec(lambda: f64, nu: f64) -> Plan {
    let text = format!(
        "version = 1\n[model]\nlaw = \"mcmillan\"\nnu = {nu:?}\nlambda = {lambda:?}\n\
         tau = 1.0\nphi = 0.9\n\
         [grid]\nx0 = {{ min = 0.0, max = 2.0, count = 5 }}\n\
         v0 = {{ min = -0.05, max = 0.3, count = 2 }}\n\
         [integration]\ndt = 0.005\n[output]\npath = \"unused.h5\"\n"
    );
    Plan::from_toml(&text, "unstable_steady").expect("a valid spec")
}

/// The run from `ic` to [`T_TRUTH`] with no rule: where it ends.
fn truth(ctx: &MapContext, ic: State) -> End {
    let p = *ctx.stepper.params();
    let cl = Classifier::default();
    let mut run = Run::new(&ctx.stepper, ic);
    let mut turns = TurnWatch::new(&p, cl.turn_settings(&p));
    let mut last = None;
    for _ in 0..run.steps_to(T_TRUTH) {
        let step = run.step();
        if turns.observe_step(&run, &step).is_some() {
            last = turns.lasting().map(|l| (l.t, l.sticks()));
        }
    }
    let s = run.sample();
    let fp = p.fixed_point();
    match last {
        _ if (s.x - fp.x).hypot(s.v - fp.v) <= cl.fp_radius => End::Settles,
        // The window must be the run's last turns, not an early transient's.
        Some((t, true)) if t > T_TRUTH - 100.0 => End::Squeals,
        Some((t, false)) if t > T_TRUTH - 100.0 => End::SlipOscillation,
        _ => End::Unknown,
    }
}

/// Whether `label` names the attractor the run ends on (undecided names none).
fn agrees(label: Regime, end: End) -> bool {
    match label {
        Regime::Undecided => true,
        Regime::SteadySlip => end == End::Settles,
        Regime::StickSlip => end == End::Squeals,
        Regime::SlipOscillation => end == End::SlipOscillation,
    }
}

/// The same for a fate.
fn fate_agrees(f: &Fate, end: End) -> bool {
    match f {
        Fate::Settles { .. } => end == End::Settles,
        Fate::Lasts { .. } => end == End::Squeals,
        Fate::SlipOscillation { .. } => end == End::SlipOscillation,
        Fate::Undecided | Fate::Stopped => true,
    }
}

/// Ten starts at each of the three belt speeds of [`CASES`]: every label and every fate
/// names the attractor the start's run to t = 20000 ends on, or none.
#[test]
#[ignore = "long physics check (minutes): run by scripts/ci/long-checks.sh, which .ci/run calls"]
fn fates_agree_with_long_runs_where_steady_slip_is_unstable() {
    let mut wrong = Vec::new();
    let (mut undecided, mut unknown) = (0, 0);
    for (lambda, nu) in CASES {
        let plan = spec(lambda, nu);
        let ctx = MapContext::prepare(&plan, 0).expect("prepared");
        let g = &plan.map.grid;
        let setup = Setup {
            params: plan.maps[0],
            dt: plan.dt,
            solver: plan.solver,
        };
        let rows: Vec<_> = (0..g.cells())
            .into_par_iter()
            .map(|k| {
                let (x, v) = g.state(k / g.x0.count, k % g.x0.count);
                let ic = State { x, v };
                let label = ctx.classify(ic);
                let (f, _) = fate(setup, ic, T_TRUTH, None).expect("a fate");
                (ic, label, f, truth(&ctx, ic))
            })
            .collect();
        for (ic, label, f, end) in rows {
            println!(
                "lambda {lambda} nu {nu}: ({:.2}, {:.2}) ends {end:?}; label {} ({}), fate {}",
                ic.x,
                ic.v,
                label.regime.name(),
                label.reason.name(),
                f.words(T_TRUTH)
            );
            undecided += usize::from(label.regime == Regime::Undecided);
            undecided += usize::from(matches!(f, Fate::Undecided));
            if end == End::Unknown {
                unknown += 1;
                continue;
            }
            if !agrees(label.regime, end) || !fate_agrees(&f, end) {
                wrong.push(format!(
                    "lambda {lambda} ({}, {}): {end:?}, {label:?}, {f:?}",
                    ic.x, ic.v
                ));
            }
        }
    }
    println!("{undecided} undecided labels and fates of 60; {unknown} runs end on no band");
    assert!(wrong.is_empty(), "{wrong:#?}");
    // A truth that names no attractor checks nothing: at most one run of the 30 may end so.
    assert!(unknown <= 1, "{unknown} runs end on no identified band");
}
