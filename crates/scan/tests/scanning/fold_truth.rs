//! Labels against long runs around the fold of the stick-slip band:
//! ten starts at each of three dampings around the fold at lambda = 0.3, 0.5 and 1 (the
//! paper's tau = 1/sqrt(10), Phi = 1, McMillan's law), and the lambda = 0.5, nu = 0.0197
//! long transient. The truth is each start's own run to t = 20000: it settles where it
//! ends within the classifier's `fp_radius` (1e-3) of the fixed point, else it swings. No
//! label of the start, as `scan`, `classify` or `trajectory` gives it, says stick_slip where
//! the run settles, nor steady_slip where it swings; undecided is allowed, counted and
//! printed.
//!
//! ```text
//! cargo test --workspace --test scanning -- --ignored --nocapture fold_truth::
//! ```

use std::sync::atomic::AtomicBool;

use rayon::prelude::*;
use squeal_core::{Regime, State};
use squeal_scan::cell::Audit;
use squeal_scan::scanner::MapContext;
use squeal_scan::trajectory::{Span, run_in};
use squeal_scan::{MemorySink, NoObserver, Plan, drive};

/// The truth's horizon: a run still off the fixed point here swings.
const T_TRUTH: f64 = 20000.0;

/// The paper's surface time, tau = 1/sqrt(10) (Table 1), written as the specs write it.
const TAU: &str = "0.31622776601683794";

/// The folds of this revision (94a9132), each from `squeal critical --fold --lambda L` (the
/// paper's tau, Phi = 1, McMillan's law, dt = 0.005, 2026-11-28):
/// lambda = 0.3: nu = 1.013146e-2 +- 2.55e-3 (with a warning: the regime changes 3 times
/// along nu); lambda = 0.5: nu = 2.013934e-2 +- 6.40e-4; lambda = 1: nu = 2.425657e-2 +-
/// 7.71e-5.
const FOLDS: [(f64, f64); 3] = [(0.3, 1.013146e-2), (0.5, 2.013934e-2), (1.0, 2.425657e-2)];

/// The three dampings around a fold: 2% below, at, and 2% above it.
const AROUND: [f64; 3] = [0.98, 1.0, 1.02];

/// Cases beside the three dampings, each `(lambda, nu)`. The first: `squeal trajectory
/// --lambda 0.5 --nu 0.0197 --x0=0 --v0=1 --t-end 20000` said stick_slip (`sticking_band`)
/// on 48d225a while its run ended at the fixed point; (0, 1) is a start of the spread at
/// lambda = 0.5 ([`spec`]). And two where the spread's runs at lambda = 0.5 do not all
/// settle, so that a steady_slip label on a run that swings would be seen (within 2% of the
/// folds only lambda = 1 has one): at 0.95 of the fold the run from (1, 1) is a transient
/// of over 6000 (`squeal trajectory --lambda 0.5 --nu 0.019132373 --x0=1 --v0=1 --t-end
/// 20000`: near_fixed_point at t = 6704.65) and at 0.9 the runs from (1, 1) and (2, -0.05)
/// swing to t = 20000 (section amplitude x' = 0.27 and 0.29).
const EXTRA: [(f64, f64); 3] = [
    (0.5, 0.0197),
    (0.5, 0.95 * FOLDS[1].1),
    (0.5, 0.9 * FOLDS[1].1),
];

/// The one-map spec of the ten starts at `lambda`, `nu`: the scan's grid (5 x 2, by index)
/// with `x0 = 1 + lambda * {-2, -1, 0, 1, 2}` (the fixed point is x* = 1) and
/// `v0 = lambda * {-0.1, 2}`. Why: the unstable cycle's section amplitude at these dampings
/// is about 0.12, 0.4 and 0.67 lambda (`squeal ulc` at nu = 0.0099, 0.0197, 0.0237), so the
/// spread has starts inside it (x0 = 1, v0 = -0.1 lambda) and outside it out to 3 lambda
/// from the fixed point, starts below the belt's speed and starts above it (slip reversed),
/// and at lambda = 0.5 it holds the mislabelled start (0, 1). The classifier's settings are the
/// defaults, as `squeal scan` and `squeal classify` take them (t_max = 5000).
fn spec(lambda: f64, nu: f64, grid: Option<(f64, f64, f64, f64)>) -> Plan {
    let (x0, x1, v0, v1) = grid.unwrap_or((
        1.0 - 2.0 * lambda,
        1.0 + 2.0 * lambda,
        -0.1 * lambda,
        2.0 * lambda,
    ));
    let (nx, nv) = match grid {
        None => (5, 2),
        Some(_) => (1, 1),
    };
    let text = format!(
        "version = 1\n[model]\nlaw = \"mcmillan\"\nnu = {nu:?}\nlambda = {lambda:?}\n\
         tau = {TAU}\nphi = 1.0\n\
         [grid]\nx0 = {{ min = {x0:?}, max = {x1:?}, count = {nx} }}\n\
         v0 = {{ min = {v0:?}, max = {v1:?}, count = {nv} }}\n\
         [integration]\ndt = 0.005\n[output]\npath = \"unused.h5\"\n"
    );
    Plan::from_toml(&text, "fold_truth").expect("a valid spec")
}

/// One start's labels and its run's end.
struct Row {
    ic: State,
    /// The run to [`T_TRUTH`] ends within the classifier's `fp_radius` of the fixed point.
    settles: bool,
    /// When it first came that near (the classifier without any rule: `rest`), if it did.
    settled_at: Option<f64>,
    /// `x'` at the last section crossing of that run (its swing where it swings).
    last_amplitude: Option<f64>,
    scan: Regime,
    scan_reason: &'static str,
    classify: Regime,
    classify_reason: &'static str,
    trajectory: Regime,
    trajectory_reason: &'static str,
}

/// Whether `label` contradicts the run: stick_slip where it settles, steady_slip where it
/// swings.
fn contradicts(label: Regime, settles: bool) -> bool {
    matches!(
        (label, settles),
        (Regime::StickSlip, true) | (Regime::SteadySlip, false)
    )
}

/// The ten starts at `lambda`, `nu`: labelled by a scan of them (the driver and the audit that
/// acts, as `squeal scan`), by `squeal classify`'s path (the one-point plan of the command's
/// flags, [`MapContext::classify`]) and by `squeal trajectory`'s ([`run_in`] to
/// [`T_TRUTH`], which is also the truth's run). Asserts that the scan ends with no audited
/// cell disagreeing (a DISAGREEMENT whose cell keeps its refuted label).
fn case(lambda: f64, nu: f64) -> Vec<Row> {
    let plan = spec(lambda, nu, None);
    let mut sink = MemorySink::default();
    let stop = AtomicBool::new(false);
    let done = drive(&plan, None, &mut sink, &NoObserver, &stop).expect("the scan runs");
    squeal_scan::redo::act_on_audits(&plan, None, &mut sink, Some(&done.computed))
        .expect("the audit acts");
    let cells = sink.map_cells(&plan, 0).expect("every block");
    let kept: Vec<usize> = (0..cells.len())
        .filter(|&k| cells[k].audit == Audit::Disagrees as u8)
        .collect();
    assert!(
        kept.is_empty(),
        "lambda {lambda} nu {nu}: the scan ends with disagreeing audited cells {kept:?}"
    );
    // `squeal classify --lambda L --nu N` (crates/cli/src/cmd/model.rs: its grid is the one
    // point (0, 0)).
    let one = spec(lambda, nu, Some((0.0, 0.0, 0.0, 0.0)));
    let ctx = MapContext::prepare(&one, 0).expect("prepared");
    let g = &plan.map.grid;
    (0..g.cells())
        .into_par_iter()
        .map(|k| {
            let (x, v) = g.state(k / g.x0.count, k % g.x0.count);
            let ic = State { x, v };
            let label = ctx.classify(ic);
            let span = Span {
                ic,
                t_end: T_TRUTH,
                every: 0,
            };
            let t = run_in(&ctx, span, None);
            let cell = &cells[k];
            // The truth: where the run is at its end, no rule asked.
            let (end, fp) = (t.final_state, t.fixed_point);
            let settles = (end.x - fp.x).hypot(end.v - fp.v) <= ctx.classifier.fp_radius;
            let reason = |r: u8| squeal_core::Reason::ALL[r as usize].name();
            Row {
                ic,
                settles,
                settled_at: (t.rest.regime == Regime::SteadySlip).then_some(t.rest.t_decision),
                last_amplitude: t.oscillation.amplitude,
                scan: cell.regime().expect("a stored label"),
                scan_reason: reason(cell.reason),
                classify: label.regime,
                classify_reason: label.reason.name(),
                trajectory: t.outcome.regime,
                trajectory_reason: t.outcome.reason.name(),
            }
        })
        .collect()
}

/// Ten starts at each of three dampings around the fold at lambda = 0.3, 0.5 and 1, and at
/// the dampings of [`EXTRA`] (the transient at lambda = 0.5, nu = 0.0197 among them): no label
/// (scan, classify, trajectory) contradicts the start's run to t = 20000, and no scan keeps
/// a disagreeing audited cell.
///
/// Measured on 94a9132 (2026-11-28): every label agrees with its run; 14 of 360 labels are
/// undecided (time_limit at t_max = 5000 on runs that settle at t = 6000-11000 or still
/// swing at 20000: lambda = 1 on the fold and lambda = 0.5 at 0.95 of it). Runs that
/// swing: 9 of 10 at lambda = 1, 0.98 of the fold, 2 of 10 and 9 of 10 at lambda = 0.5,
/// 0.95 and 0.9 of it; every other run settles. (At lambda = 0.3, `squeal trajectory
/// --t-end 20000` from (1, 0.6) and (1.6, -0.03) settles at 0.95, 0.9 and 0.8 of the fold
/// and at nu = 0.007 and 0.004 too.) The check can fail: with the band rules kept where the
/// cycle's outside is not invariant (`band_rules = true` in
/// `MapContext::prepare_checked`, the census off) scan and classify label stick_slip three
/// starts at lambda = 0.5, 0.95 of the fold whose runs settle by t = 4115-11121. Run time
/// on the 2-core VM shared with other work (`cargo test --workspace --test scanning fold_truth:: --
/// --ignored`): 147 s at load 3-5 (173 s of CPU), 195 s beside a build.
#[test]
#[ignore = "long physics check (minutes): run by scripts/ci/long-checks.sh, which .ci/run calls"]
fn labels_agree_with_long_runs_around_the_fold() {
    let mut cases: Vec<(f64, f64)> = FOLDS
        .iter()
        .flat_map(|&(lambda, fold)| AROUND.map(|f| (lambda, f * fold)))
        .collect();
    cases.extend(EXTRA);
    let mut wrong = Vec::new();
    let mut undecided = 0;
    for &(lambda, nu) in &cases {
        let rows = case(lambda, nu);
        let settle = rows.iter().filter(|r| r.settles).count();
        println!(
            "lambda {lambda} nu {nu:.6e}: {settle} of {} runs settle by t = {T_TRUTH}",
            rows.len()
        );
        for r in &rows {
            let settles = r.settles;
            let truth = match (settles, r.settled_at) {
                (true, Some(t)) => format!("settles (near the fixed point from t = {t:.1})"),
                (true, None) => "settles (near the fixed point at the end)".to_string(),
                (false, _) => format!("swings (last x' at x = 1: {:?})", r.last_amplitude),
            };
            println!(
                "  ({:+.3}, {:+.3}) {truth}: scan {} ({}), classify {} ({}), trajectory {} ({})",
                r.ic.x,
                r.ic.v,
                r.scan.name(),
                r.scan_reason,
                r.classify.name(),
                r.classify_reason,
                r.trajectory.name(),
                r.trajectory_reason
            );
            for (path, label) in [
                ("scan", r.scan),
                ("classify", r.classify),
                ("trajectory", r.trajectory),
            ] {
                undecided += usize::from(label == Regime::Undecided);
                if contradicts(label, settles) {
                    wrong.push(format!(
                        "lambda {lambda} nu {nu:e} start ({}, {}): {path} says {} but the run {truth}",
                        r.ic.x,
                        r.ic.v,
                        label.name()
                    ));
                }
            }
        }
    }
    println!(
        "{undecided} undecided labels of {} (3 paths x 10 starts x {} cases)",
        30 * cases.len(),
        cases.len()
    );
    assert!(
        wrong.is_empty(),
        "labels contradicted by their runs:\n{}",
        wrong.join("\n")
    );
}
