//! The certified early decisions (crates/core/MODEL.md section 9) against runs taken to
//! settlement: the region of attraction of the fixed point and the orbit from breakaway of
//! a law with true stick.

use std::sync::atomic::AtomicBool;

use squeal_core::{
    Classifier, Params, Reason, Regime, Region, SolverConfig, State, Stepper, Stribeck,
};
use squeal_scan::{MemorySink, NoObserver, Plan, drive};

/// bSTAB's friction case at belt speed `v_d` on an `n x n` grid over its region
/// (x0 in [-2, 2], x'0 in [0, 2]), with early stopping `early_stop`.
fn plan(v_d: f64, n: usize, early_stop: &str) -> Plan {
    Plan::from_toml(
        &format!(
            r#"version = 1
[model]
law = "stribeck"
xi = 0.05
v_d = {v_d}
[grid]
x0 = {{ min = -2.0, max = 2.0, count = {n} }}
v0 = {{ min = 0.0, max = 2.0, count = {n} }}
[classifier]
early_stop = "{early_stop}"
[output]
path = "t.h5"
"#
        ),
        "t.toml",
    )
    .unwrap()
}

/// (regime, reason) of every cell of map 0, row-major.
fn cells(plan: &Plan) -> Vec<(u8, u8)> {
    let mut sink = MemorySink::default();
    let done = drive(plan, None, &mut sink, &NoObserver, &AtomicBool::new(false)).unwrap();
    assert!(!done.interrupted);
    let cells = sink.map_cells(plan, 0).unwrap();
    cells.iter().map(|c| (c.regime, c.reason)).collect()
}

/// At v_d = 2.0 (no stick-slip cycle: the orbit from breakaway decays) and v_d = 1.0 (the
/// fixed point repels: the orbit from breakaway sticks again), every cell of a 12 x 12 grid
/// gets the label of its run taken to settlement (`early_stop = "none"`, no shortcut), and
/// the shortcuts are what decided them: at 2.0 starts inside the region, runs crossing the
/// section below a start that settles, and runs that stuck; at 1.0 runs that stuck and runs
/// crossing the section between two starts that stuck. Before the shortcuts, no cell had
/// these reasons (values 11-16 did not exist).
#[test]
fn shortcuts_give_the_labels_of_runs_to_settlement() {
    for (v_d, want) in [
        (
            2.0,
            vec![
                Reason::StartInRegion,
                Reason::BelowSettlingStart,
                Reason::StuckThenSettles,
            ],
        ),
        (
            1.0,
            vec![Reason::StuckOntoCycle, Reason::BetweenStickingStarts],
        ),
    ] {
        let fast = cells(&plan(v_d, 12, "cycle"));
        let slow = cells(&plan(v_d, 12, "none"));
        for (k, (f, s)) in fast.iter().zip(&slow).enumerate() {
            assert_eq!(f.0, s.0, "v_d {v_d} cell {k}: {f:?} vs settled {s:?}");
            assert_ne!(f.0, Regime::Undecided as u8, "v_d {v_d} cell {k}");
        }
        for r in want {
            assert!(
                fast.iter().any(|c| c.1 == r as u8),
                "v_d {v_d}: no cell decided by {r:?}"
            );
        }
        // Runs to settlement never use a shortcut.
        assert!(slow.iter().all(|c| c.1 <= Reason::StickCycle as u8));
    }
}

/// The monotone return map (crates/core/MODEL.md section 9) decides a run at its first
/// crossing of the section. At v_d = 1.0, a start 0.01 from the repelling fixed point spirals
/// out at the rate -(2 xi + mu'(v_d)) / 2 = (e^{-2} - 0.1) / 2 = 0.0177 (closed form), about
/// ln(100) / 0.0177 = 260 time units before it reaches amplitudes where it sticks. At
/// v_d = 2.0, a start 1.8 left of the fixed point decays at about k0 / 2 = (0.1 - e^{-4}) / 2
/// = 0.041 per time unit and needs about ln(1.8 / 0.7357) / 0.041 = 22 to reach the region
/// (radius 0.7357). Both are now decided within two revolutions (natural period 2 pi, so
/// t < 4 pi) with the label of their runs to settlement; with every other shortcut but
/// without this one they are decided later than that (the test checks it; measured:
/// t = 4.7 against 230.7 at v_d = 1.0, t = 1.6 against 33.8 at v_d = 2.0).
#[test]
fn monotone_map_decides_runs_at_their_first_crossing() {
    for (v_d, dx, regime, reason) in [
        (1.0, 0.01, Regime::StickSlip, Reason::BetweenStickingStarts),
        (2.0, -1.8, Regime::SteadySlip, Reason::BelowSettlingStart),
    ] {
        let plan = plan(v_d, 2, "cycle");
        let ctx = squeal_scan::MapContext::prepare(&plan, 0).unwrap();
        let fp = plan.maps[0].fixed_point();
        let ic = State {
            x: fp.x + dx,
            v: 0.0,
        };
        let fast = ctx.classify(ic);
        let settled = Classifier::default().classify(&ctx.stepper, ic);
        assert_eq!(fast.regime, regime, "v_d {v_d}: {fast:?}");
        assert_eq!(settled.regime, regime, "v_d {v_d}: {settled:?}");
        assert_eq!(fast.reason, reason, "v_d {v_d}: {fast:?}");
        let two_turns = 4.0 * std::f64::consts::PI;
        assert!(fast.t_decision < two_turns, "v_d {v_d}: {fast:?}");
        let without = squeal_core::Shortcuts {
            section: None,
            ..ctx.shortcuts
        };
        let before = ctx.classifier.classify_with(&ctx.stepper, ic, without);
        assert_eq!(before.regime, regime, "v_d {v_d}: {before:?}");
        assert!(before.t_decision > two_turns, "v_d {v_d}: {before:?}");
        eprintln!(
            "v_d {v_d}: decided at t = {} ({:?}), before at t = {} ({:?})",
            fast.t_decision, fast.reason, before.t_decision, before.reason
        );
    }
}

/// The monotone return map on the scheme itself: at the 11 belt speeds of bSTAB's study
/// without an unstable cycle (0.8-1.1: the fixed point repels; 1.85-2.225: no stick-slip
/// cycle), the sampled return map the certificate checks (the followed starts' crossings
/// and 16 one-return samples) never decreases by more than a tenth of the tolerance that
/// voids it (measured: at most 1.1e-16, rounding; 0 at 8 of the 11 speeds), and the certificate covers the section from the lowest start (`2.5e-4 r_max`
/// = 1e-3) to the top
/// (`r_max = 4`, the cycle search's range for this grid: 1.2 times the farthest corner's
/// distance, at least 4): every start settles at the steady speeds, every start sticks at
/// the others.
#[test]
fn the_sampled_return_map_is_monotone_where_the_certificate_is_used() {
    use squeal_core::witness::{MONOTONE_TOL, section_evidence, section_fates};
    for i in (0..5).chain(14..20) {
        let v_d = 0.8 + 0.075 * i as f64;
        let plan = plan(v_d, 2, "cycle");
        let ctx = squeal_scan::MapContext::prepare(&plan, 0).unwrap();
        assert_eq!(ctx.classifier.trap, None, "v_d {v_d}");
        let base = squeal_core::Shortcuts {
            section: None,
            ..ctx.shortcuts
        };
        let r_max = squeal_scan::scanner::cycle_settings(&plan, &plan.maps[0]).r_max;
        assert_eq!(r_max, 4.0, "v_d {v_d}");
        let ev = section_evidence(&ctx.stepper, &ctx.classifier, base, r_max).unwrap();
        let worst = ev.largest_decrease();
        eprintln!("v_d {v_d}: largest decrease of the sampled return map {worst:e}");
        assert!(worst < 0.1 * MONOTONE_TOL, "v_d {v_d}: decrease {worst}");
        let fates = section_fates(&ctx.stepper, &ctx.classifier, base, r_max).unwrap();
        if v_d < 1.5 {
            let (lo, hi) = fates.sticks_within.unwrap();
            assert!(lo <= 1e-3 * 1.0001 && hi >= r_max, "v_d {v_d}: {fates:?}");
            assert_eq!(fates.settles_up_to, None, "v_d {v_d}");
        } else {
            assert!(
                fates.settles_up_to.unwrap() >= r_max,
                "v_d {v_d}: {fates:?}"
            );
            assert_eq!(fates.sticks_within, None, "v_d {v_d}");
        }
    }
}

/// The region's argument on the scheme squeal integrates: runs from 32 states just inside
/// the disc's edge (0.999 of its radius) at the 15 belt speeds of bSTAB's study where the
/// fixed point attracts never leave the disc (distance from the fixed point at every step
/// within the radius) and end at the fixed point when run to settlement.
#[test]
fn runs_from_the_region_edge_stay_inside_and_settle() {
    let cl = Classifier::default();
    for i in 5..20 {
        let v_d = 0.8 + 0.075 * i as f64;
        let p = Params::stribeck(0.05, v_d, Stribeck::default());
        let region = Region::of(&p).expect("the fixed point attracts above v_d = 1.151");
        let squeal_core::region::Shape::Disc { radius, .. } = region.shape else {
            panic!("{region:?}")
        };
        let st = Stepper::new(p, 0.005, SolverConfig::default()).unwrap();
        for k in 0..32 {
            let th = std::f64::consts::TAU * k as f64 / 32.0;
            let r0 = 0.999 * radius;
            let ic = State {
                x: region.centre.x + r0 * th.cos(),
                v: region.centre.v + r0 * th.sin(),
            };
            let mut run = squeal_core::Run::new(&st, ic);
            for _ in 0..2000 {
                let s = run.step().next;
                let d = (s.x - region.centre.x).hypot(s.v - region.centre.v);
                assert!(d < radius, "v_d {v_d} angle {k}: left the disc ({d})");
            }
            let out = cl.classify(&st, ic);
            assert_eq!(
                out.regime,
                Regime::SteadySlip,
                "v_d {v_d} angle {k}: {out:?}"
            );
            assert_eq!(out.reason, Reason::NearFixedPoint);
        }
    }
}

/// McMillan's hysteretic law above the fold (nu = 0.035 and 0.1 at Table 1's lambda, tau and
/// phi: no unstable cycle, `critical --crisis` gives about 0.024): on a
/// 12 x 12 grid over Fig. 10's window every cell gets the label of its run to settlement,
/// and the decaying section decided most of them: starts inside the first turn of the orbit
/// from its top without a run, and runs at their first crossing below that top (crates/core/
/// MODEL.md section 9). Before that shortcut (reasons 17 and 18 did not exist) these runs
/// went on to the certified region. (This test ran at nu = 0.03 until the section search
/// refined its samples: there the return map has a narrow window `D > 0` at `r` in about
/// [2.715, 2.765] that the fixed samples of the grid's `r_max` stepped over, so an unstable
/// cycle does exist and the trap decides those runs first.)
#[test]
fn mcmillan_maps_above_the_fold_give_the_labels_of_runs_to_settlement() {
    let spec = |nu: f64, early_stop: &str| {
        Plan::from_toml(
            &format!(
                r#"version = 1
[model]
law = "mcmillan"
nu = {nu}
[grid]
x0 = {{ min = -3.0, max = 5.0, count = 12 }}
v0 = {{ min = -4.0, max = 4.0, count = 12 }}
[classifier]
early_stop = "{early_stop}"
[output]
path = "t.h5"
"#
            ),
            "t.toml",
        )
        .unwrap()
    };
    for nu in [0.035, 0.1] {
        let fast = cells(&spec(nu, "cycle"));
        let slow = cells(&spec(nu, "none"));
        for (k, (f, s)) in fast.iter().zip(&slow).enumerate() {
            assert_eq!(f.0, s.0, "{nu} cell {k}: {f:?} vs settled {s:?}");
            assert_ne!(f.0, Regime::Undecided as u8, "{nu} cell {k}");
        }
        let share = |r: Reason| fast.iter().filter(|c| c.1 == r as u8).count();
        let (inside, below) = (
            share(Reason::StartInsideDecayingTurn),
            share(Reason::BelowDecayingSection),
        );
        assert!(
            inside > 0 && below > 0 && inside + below > fast.len() / 2,
            "{nu}: {inside} inside the turn, {below} below the top of {}",
            fast.len()
        );
    }
}

/// Runs from 32 states just inside the edge of McMillan's certified ellipse (0.999 of each
/// semi-axis), at nu = 1e-3, 1e-2 and 0.03 and both of his laws, all settle on the fixed
/// point when run to settlement (no shortcut).
#[test]
#[ignore = "long check against long runs (a minute or more on 2 cores): run by scripts/ci/long-checks.sh, which .ci/run calls"]
fn runs_from_mcmillans_region_edge_settle() {
    let cl = Classifier::default();
    for law in [
        squeal_core::FrictionLaw::McMillan,
        squeal_core::FrictionLaw::McMillanNonHysteretic,
    ] {
        for nu in [1e-3, 1e-2, 0.03] {
            let p = Params::paper(law, nu);
            let region = Region::of(&p).expect("a region");
            let squeal_core::region::Shape::Ellipse { two_nu, u2, s2 } = region.shape else {
                panic!("{region:?}")
            };
            let st = Stepper::new(p, 0.005, SolverConfig::default()).unwrap();
            for k in 0..32 {
                let th = std::f64::consts::TAU * k as f64 / 32.0;
                let (u, sigma) = (0.999 * u2.sqrt() * th.sin(), 0.999 * s2.sqrt() * th.cos());
                let ic = State {
                    x: region.centre.x + sigma - two_nu * u,
                    v: u,
                };
                assert!(region.contains(ic.x, ic.v));
                let out = cl.classify(&st, ic);
                assert_eq!(out.regime, Regime::SteadySlip, "{law:?} {nu} {k}: {out:?}");
            }
        }
    }
}

/// The decaying-section rule rests on the sampled return map, so it is given only where the
/// search's resolution statement holds over its whole range (no interval left unrefined by
/// the budget), and only to McMillan's laws (a law with true stick has exact shortcuts
/// instead). Its top is the search's `r_max` less the trap's margin.
#[test]
fn the_decaying_section_needs_a_resolved_search_and_mcmillans_laws() {
    use squeal_scan::section::SectionCycles;
    let mcmillan = Plan::from_toml(
        "version = 1\n[model]\nlaw = \"mcmillan\"\nnu = 0.05\n\
         [grid]\nx0 = { min = 0.0, max = 1.0, count = 2 }\nv0 = { min = 0.0, max = 1.0, count = 2 }\n\
         [output]\npath = \"t.h5\"\n",
        "t.toml",
    )
    .unwrap();
    let p = mcmillan.maps[0];
    let found = |unresolved| SectionCycles::NoneBelow {
        r_max: 8.0,
        unresolved,
    };
    let top = squeal_scan::scanner::shortcuts(&mcmillan, &p, None, Some(&found(0))).decay_below;
    assert_eq!(top, Some(8.0 * (1.0 - mcmillan.map.trap_margin)));
    let unresolved = squeal_scan::scanner::shortcuts(&mcmillan, &p, None, Some(&found(1)));
    assert_eq!(unresolved.decay_below, None);
    let stribeck = plan(2.0, 2, "cycle");
    let q = stribeck.maps[0];
    let with_stick = squeal_scan::scanner::shortcuts(&stribeck, &q, None, Some(&found(0)));
    assert_eq!(with_stick.decay_below, None);
}

/// McMillan's law at nu = 0.3 on a 12 x 12 grid, with early stopping `early_stop`.
fn damped_plan(early_stop: &str) -> Plan {
    Plan::from_toml(
        &format!(
            "version = 1\n[model]\nlaw = \"mcmillan\"\nnu = 0.3\n[grid]\n\
             x0 = {{ min = -3.0, max = 5.0, count = 12 }}\n\
             v0 = {{ min = -4.0, max = 4.0, count = 12 }}\n\
             [classifier]\nearly_stop = \"{early_stop}\"\n[output]\npath = \"t.h5\"\n"
        ),
        "t.toml",
    )
    .unwrap()
}

/// McMillan's hysteretic law at nu = 0.3 (Table 1's lambda, tau and phi; far above the fold):
/// the search's top `r_max` = 6.79 lies above lambda = 3, so the turn from the top of the
/// section passes zero slip velocity and the decaying turn from the section is small. The
/// turn from the section's lower half is larger (crates/core/MODEL.md section 9, "A
/// decaying section"), and a run crossing the lower half inside it is decided there
/// (`entered_decaying_turn`, value 19, new): half a revolution before its next crossing of
/// the section. Checked here:
/// * every cell of a 12 x 12 grid over Fig. 10's window gets the label of its run to
///   settlement, and some are decided by the new reason;
/// * runs from just right of the lower half at `|x'|` = 0.5 s and 0.9 s (`s` the turn's
///   start) are decided by it, and at 1.05 s and 1.1 s (outside the turn) are not;
/// * each run it decides, continued past its decision with no shortcut, never lies outside
///   the turn by more than the start rule's margin, and ends at the fixed point.
///
/// A rule with its threshold on the wrong side, or any higher (say the section's top),
/// decides runs outside the turn and fails the last two checks.
#[test]
fn runs_entering_the_lower_decaying_turn_stay_in_it_and_settle() {
    use squeal_core::Run;
    use squeal_core::classify::Half;
    use squeal_scan::curve::CurveLocator;
    let (plan, slow_plan) = (damped_plan("cycle"), damped_plan("none"));
    let fast = cells(&plan);
    for (k, (f, s)) in fast.iter().zip(&cells(&slow_plan)).enumerate() {
        assert_eq!(f.0, s.0, "cell {k}: {f:?} vs settled {s:?}");
        assert_ne!(f.0, Regime::Undecided as u8, "cell {k}");
    }
    let entered = fast
        .iter()
        .filter(|c| c.1 == Reason::EnteredDecayingTurn as u8)
        .count();
    assert!(entered > 0, "no cell entered the lower turn");

    let ctx = squeal_scan::MapContext::prepare(&plan, 0).unwrap();
    let cs = squeal_scan::scanner::cycle_settings(&plan, &plan.maps[0]);
    let top = ctx.shortcuts.decay_below.expect("a decaying section");
    let (s, curve) =
        squeal_scan::scanner::decaying_turn(&ctx.stepper, Half::Lower, cs.r_max, top, cs.t_return)
            .expect("a lower turn");
    assert_eq!(
        ctx.shortcuts.decay_lower_below,
        Some(s * (1.0 - plan.map.trap_margin))
    );
    eprintln!("top {top}, lower turn from s = {s}");
    let margin = plan.map.trap_margin * s + 0.01;
    let turn = CurveLocator::new(curve);
    let settle = Classifier::default();
    let fp = plan.maps[0].fixed_point();
    for (f, inside) in [(0.5, true), (0.9, true), (1.05, false), (1.1, false)] {
        let ic = State {
            x: fp.x + 0.01,
            v: -f * s,
        };
        let out = ctx.classify(ic);
        assert_eq!(
            out.reason == Reason::EnteredDecayingTurn,
            inside,
            "{f} s: {out:?}"
        );
        if !inside {
            continue;
        }
        // The same run, continued past its decision without any shortcut.
        let mut run = Run::new(&ctx.stepper, ic);
        let mut watch = settle.watch(&plan.maps[0]);
        let mut t_end = None;
        for _ in 0..run.steps_to(1000.0) {
            let step = run.step();
            let n = step.next;
            if n.t > out.t_decision {
                let p = State { x: n.x, v: n.v };
                assert_ne!(turn.side(p, margin), Some(false), "{f} s: left at {n:?}");
            }
            if let Some(d) = watch.observe(&run, &step) {
                assert_eq!(d, (Regime::SteadySlip, Reason::NearFixedPoint), "{f} s");
                t_end = Some(n.t);
                break;
            }
        }
        eprintln!(
            "{f} s: decided at t = {}, settled at {t_end:?}",
            out.t_decision
        );
        assert!(t_end.is_some(), "{f} s: not settled by t = 1000");
    }
}
