//! Off the paper's parameters the two labelling rules agree: early stopping
//! on the located unstable cycle (`early_stop = "cycle"`) and runs taken to settlement
//! (`early_stop = "none"`), on 64 x 64 grids at lambda in {0.5, 1, 5}, tau in {0.05, 1} and
//! Phi in {0.3, 1.4}, each varied alone from Table 1.

use rayon::prelude::*;
use squeal_core::{Reason, Regime, State};
use squeal_scan::Plan;
use squeal_scan::scanner::MapContext;

/// One case: the varied parameter, nu, and the grid box (half-width about the fixed point).
struct Case {
    name: &'static str,
    model: &'static str,
    nu: f64,
    half: f64,
}

const CASES: [Case; 7] = [
    Case {
        name: "lambda=0.5",
        model: "lambda = 0.5\ntau = 0.31622776601683794\nphi = 1.0",
        nu: 1e-2,
        half: 0.6,
    },
    Case {
        name: "lambda=1",
        model: "lambda = 1.0\ntau = 0.31622776601683794\nphi = 1.0",
        nu: 1e-2,
        half: 1.0,
    },
    Case {
        name: "lambda=5",
        model: "lambda = 5.0\ntau = 0.31622776601683794\nphi = 1.0",
        nu: 3e-3,
        half: 3.0,
    },
    Case {
        name: "tau=0.05",
        model: "lambda = 3.0\ntau = 0.05\nphi = 1.0",
        nu: 2e-3,
        half: 4.0,
    },
    Case {
        name: "tau=1",
        model: "lambda = 3.0\ntau = 1.0\nphi = 1.0",
        nu: 1e-2,
        half: 3.0,
    },
    Case {
        name: "phi=0.3",
        model: "lambda = 3.0\ntau = 0.31622776601683794\nphi = 0.3",
        nu: 1e-2,
        half: 3.5,
    },
    Case {
        name: "phi=1.4",
        model: "lambda = 3.0\ntau = 0.31622776601683794\nphi = 1.4",
        nu: 1e-2,
        half: 3.5,
    },
];

fn plan(case: &Case, n: usize, dt: f64, rule: &str) -> Plan {
    let text = format!(
        "version = 1\n[model]\nlaw = \"mcmillan\"\nnu = {nu:?}\n{model}\n\
         [grid]\nx0 = {{ min = {x0:?}, max = {x1:?}, count = {n} }}\n\
         v0 = {{ min = {v0:?}, max = {v1:?}, count = {n} }}\n\
         [integration]\ndt = {dt:?}\n[classifier]\nearly_stop = \"{rule}\"\n\
         [output]\npath = \"unused.h5\"\n",
        nu = case.nu,
        model = case.model,
        x0 = 1.0 - case.half,
        x1 = 1.0 + case.half,
        v0 = -case.half,
        v1 = case.half,
    );
    Plan::from_toml(&text, case.name).expect("a valid spec")
}

/// Labels (regime, reason) of every cell, row-major.
fn labels(plan: &Plan) -> Vec<(Regime, Reason)> {
    let ctx = MapContext::prepare(plan, 0).expect("prepared");
    let g = &plan.map.grid;
    (0..g.x0.count * g.v0.count)
        .into_par_iter()
        .map(|k| {
            let ic = State {
                x: g.x0.value(k % g.x0.count),
                v: g.v0.value(k / g.x0.count),
            };
            // The scan's rule: the start rule, then the classifier with its trap.
            let out = ctx.classify(ic);
            (out.regime, out.reason)
        })
        .collect()
}

#[test]
#[ignore]
fn measure() {
    let n: usize = std::env::var("N")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(32);
    let dt: f64 = std::env::var("DT")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0.01);
    for case in &CASES {
        let t = std::time::Instant::now();
        let a = labels(&plan(case, n, dt, "cycle"));
        let ta = t.elapsed().as_secs_f64();
        let b = labels(&plan(case, n, dt, "none"));
        let tb = t.elapsed().as_secs_f64() - ta;
        let count = |v: &[(Regime, Reason)], r: Regime| v.iter().filter(|x| x.0 == r).count();
        let disagree = a
            .iter()
            .zip(&b)
            .filter(|(x, y)| x.0 != Regime::Undecided && y.0 != Regime::Undecided && x.0 != y.0)
            .count();
        let mut reasons = std::collections::BTreeMap::new();
        for x in &b {
            *reasons.entry(x.1.name()).or_insert(0) += 1;
        }
        println!(
            "{}: cycle steady {} stick {} undecided {} ({ta:.1} s) | none steady {} stick {} undecided {} ({tb:.1} s) | disagree {disagree} | none reasons {reasons:?}",
            case.name,
            count(&a, Regime::SteadySlip),
            count(&a, Regime::StickSlip),
            count(&a, Regime::Undecided),
            count(&b, Regime::SteadySlip),
            count(&b, Regime::StickSlip),
            count(&b, Regime::Undecided),
        );
    }
}

/// Both rules on 64 x 64 grids of every case: they agree on every cell both decide, and
/// neither leaves more than 1% of the cells undecided.
///
/// Why these settings. nu = 1e-2 where both basins then exist (lambda = 0.5, 1, tau = 1,
/// Phi = 0.3, 1.4), 3e-3 at lambda = 5 and 2e-3 at tau = 0.05 (at 1e-2 the unstable cycle
/// there has grown past the stick-slip oscillation): runs taken to settlement inside the
/// cycle need about ln(r / fp_radius) / (decay per revolution) revolutions and the decay per
/// revolution scales with nu, so at nu = 1e-3 they outlast t_max = 5000 (measured: all 16
/// steady-slip cells of a 16 x 16 grid at lambda = 5 and all 32 at tau = 0.05 ran out of
/// time). The box is centred on the fixed point and reaches past the cycle, so both basins
/// show. dt = 0.01 keeps the run time reasonable: the settlement rule costs 20-60 ms per cell.
///
/// Measured at 64 x 64, dt = 0.01 (`N=64 cargo test --release -p squeal-scan --test
/// off_paper -- --ignored --nocapture measure`, 2026-11-22, counts steady / stick /
/// undecided, the same under both rules unless said):
/// lambda = 0.5: 97 / 3999 / 0 (settlement: 3999 by the wide-band rule);
/// lambda = 1: 467 / 3629 / 0; lambda = 5: 2047 / 2049 / 0; tau = 0.05: 1196 / 2900 / 0 with
/// 8 cells undecided by settlement (slow decay at nu = 2e-3, time limit); tau = 1:
/// 346 / 3750 / 0; Phi = 0.3 and Phi = 1.4: 1158 / 2938 / 0. Before the wide-band rule the
/// settlement rule left every stick-slip cell undecided at lambda = 0.5 and 1.
/// That run also found 5 cells (the same at both Phi: slip-branch dynamics) that settlement
/// called stick-slip and the cycle called steady slip: starts just inside the nu = 1e-2
/// cycle whose amplitudes drifted inward at an accelerating pace inside a 5% band, which the
/// old settling test took for a settled band. The settling test now also asks for reversals
/// (`probe_disagreements` finds none since at Phi = 0.3; the other 64 x 64 counts above were
/// measured before that change; this test asserts them with it). Run time of this test: 149 s
/// on the idle 2-core VM (`cargo test -p squeal-scan --test scanning off_paper::`, 2026-11-22; the
/// settlement rule is 95% of it).
#[test]
#[ignore = "long physics check (minutes): run by scripts/ci/long-checks.sh, which .ci/run calls"]
fn early_stopping_agrees_with_settlement_off_the_paper() {
    let (n, dt) = (64, 0.01);
    for case in &CASES {
        let a = labels(&plan(case, n, dt, "cycle"));
        let b = labels(&plan(case, n, dt, "none"));
        let undecided =
            |v: &[(Regime, Reason)]| v.iter().filter(|x| x.0 == Regime::Undecided).count();
        let disagree: Vec<usize> = (0..a.len())
            .filter(|&k| {
                a[k].0 != Regime::Undecided && b[k].0 != Regime::Undecided && a[k].0 != b[k].0
            })
            .collect();
        assert!(
            disagree.is_empty(),
            "{}: cells {disagree:?} disagree",
            case.name
        );
        assert!(
            undecided(&a) * 100 <= a.len(),
            "{}: cycle rule {}",
            case.name,
            undecided(&a)
        );
        assert!(
            undecided(&b) * 100 <= b.len(),
            "{}: settlement {}",
            case.name,
            undecided(&b)
        );
        // Both basins are in view.
        for rule in [&a, &b] {
            assert!(
                rule.iter().any(|x| x.0 == Regime::SteadySlip),
                "{}",
                case.name
            );
            assert!(
                rule.iter().any(|x| x.0 == Regime::StickSlip),
                "{}",
                case.name
            );
        }
    }
}

#[test]
#[ignore]
fn probe_disagreements() {
    let case = &CASES[5];
    let (n, dt) = (64, 0.01);
    let pa = plan(case, n, dt, "cycle");
    let pb = plan(case, n, dt, "none");
    let ca = MapContext::prepare(&pa, 0).unwrap();
    let cb = MapContext::prepare(&pb, 0).unwrap();
    println!("trap {:?}", ca.classifier.trap);
    let g = &pa.map.grid;
    let bad: Vec<String> = (0..n * n)
        .into_par_iter()
        .filter_map(|k| {
            let ic = State {
                x: g.x0.value(k % n),
                v: g.v0.value(k / n),
            };
            let a = ca.classifier.classify(&ca.stepper, ic);
            if a.regime != Regime::SteadySlip {
                return None;
            }
            let b = cb.classifier.classify(&cb.stepper, ic);
            (b.regime != a.regime).then(|| format!("{ic:?}: cycle {a:?}\n   none {b:?}"))
        })
        .collect();
    for b in bad {
        println!("{b}");
    }
}
