use super::*;
use squeal_core::{FrictionLaw, SolverConfig};

/// Table 1's model at damping `nu`, step `dt`.
fn paper(nu: f64, dt: f64) -> Setup {
    Setup::new(
        Params::paper(FrictionLaw::McMillan, nu),
        dt,
        SolverConfig::default(),
    )
}

const REST: State = State { x: 0.0, v: 0.0 };

/// The spread: rest first, then twelve starts at four distances from the fixed point.
#[test]
fn the_spread_is_rest_and_four_rings() {
    let p = Params::paper(FrictionLaw::McMillan, 0.001);
    let s = Spread::of(&p);
    assert_eq!(s.starts.len(), 13);
    assert_eq!(s.starts[0], REST);
    let fp = p.fixed_point();
    let r: Vec<f64> = s.starts[1..]
        .iter()
        .map(|q| (q.x - fp.x).hypot(q.v))
        .collect();
    // Radii s/2, s, 2 s, 4 s with s = lambda = 3 (Table 1).
    for (i, want) in [1.5, 3.0, 6.0, 12.0].into_iter().enumerate() {
        for k in 0..3 {
            assert!((r[3 * i + k] - want).abs() < 1e-12, "{r:?}");
        }
    }
}

/// At Table 1's nu = 1e-3 rest lies outside the unstable cycle (its critical damping is
/// 3.02e-3, MODEL.md section 13) and squeals (the paper's Fig. 9): the run lasts. At
/// nu = 0.03, above the fold of cycles (2.38e-2 +- 4e-4, `squeal critical --fold`),
/// it reaches the fixed point.
#[test]
fn fates_at_table_1() {
    let (f, _) = fate(paper(1e-3, 0.005), REST, 3000.0, None).unwrap();
    assert!(f.lasts(), "{f:?}");
    let Fate::Lasts {
        lasting: Some(l), ..
    } = f
    else {
        panic!("no figures: {f:?}")
    };
    assert!(l.stuck, "the paper's stick-slip loop sticks: {l:?}");
    let (f, _) = fate(paper(0.03, 0.005), REST, 3000.0, None).unwrap();
    assert!(f.settles(), "{f:?}");
}

/// The runs' critical damping of rest at Table 1 holds the unstable cycle's, found by an
/// independent method (the damping at which the cycle first encloses rest,
/// [`crate::ulc::critical_nu`]).
#[test]
#[ignore = "long check against long runs (a minute or more on 2 cores): run by scripts/ci/long-checks.sh, which .ci/run calls"]
fn the_runs_find_the_cycles_critical_damping_at_table_1() {
    let s = paper(1e-3, 0.005);
    let cs = crate::ulc::CycleSettings::default();
    let range = ParamRange::new(2.5e-3, 3.5e-3, 1e-3);
    let cycle = crate::ulc::critical_nu(s, &cs, REST, ParamRange::new(1e-3, 5e-2, 1e-5));
    let cycle = cycle.unwrap().nu;
    let rb = critical(BoundaryParam::Nu, s, REST, (range, range.hi), HORIZON).unwrap();
    assert_eq!(rb.status, BoundaryStatus::Found);
    let [lo, hi] = rb.interval;
    assert!(
        lo <= cycle && cycle <= hi,
        "{cycle} not in {:?}",
        rb.interval
    );
    assert!(hi / lo - 1.0 < 0.01, "{:?}", rb.interval);
    // The bracket's ends are runs: the start does not settle below, settles above.
    assert!(!rb.below.as_ref().unwrap().all_settle());
    assert!(rb.above.as_ref().unwrap().all_settle());
}

/// The gate: a shortcut whose bracket a run contradicts (rest squeals at nu = 1e-3, so
/// a "critical damping" just below it is refuted by the run above it) hands over to the
/// runs, which say why; a bracket the runs confirm is kept; outside the checked region
/// (lambda 0.2) the shortcut is not even asked.
#[test]
fn the_gate_confirms_refutes_or_skips_the_shortcut() {
    let s = paper(1e-3, 0.005);
    let range = ParamRange::new(2.5e-3, 3.5e-3, 1e-2);
    let gate = (s, BoundaryParam::Nu);
    let wrong = || Ok(((), Some([0.9e-3, 1e-3])));
    match decide(gate, &[REST], (range, range.hi), 3000.0, wrong).unwrap() {
        Decided::Runs {
            why: Why::Refuted(w),
            boundary,
        } => {
            assert!(w.contains("above the answer"), "{w}");
            assert!(boundary.value() > 2.5e-3, "{boundary:?}");
        }
        d => panic!("not refuted: {d:?}"),
    }
    // Rest lasts at 2.9e-3 and settles at 3.2e-3 (the cycle's 3.02e-3 between them),
    // by t = 20000.
    let right = || Ok(((), Some([2.9e-3, 3.2e-3])));
    match decide(gate, &[REST], (range, range.hi), HORIZON, right).unwrap() {
        Decided::Shortcut {
            confirmed: Some(c), ..
        } => assert!(c.confirmed && c.refuted.is_none(), "{c:?}"),
        d => panic!("not confirmed: {d:?}"),
    }
    let low = Setup::new(
        Params {
            lambda: 0.2,
            ..Params::paper(FrictionLaw::McMillan, 0.2)
        },
        0.005,
        SolverConfig::default(),
    );
    let never = || -> Result<((), Option<[f64; 2]>), ScanError> { panic!("asked") };
    let range = ParamRange::new(0.05, 0.4, 0.05);
    let d = decide(
        (low, BoundaryParam::Nu),
        &[REST],
        (range, 0.4),
        3000.0,
        never,
    );
    assert!(
        matches!(
            d,
            Ok(Decided::Runs {
                why: Why::Unchecked(_),
                ..
            }) | Err(_)
        ),
        "{d:?}"
    );
}

/// With `until_one`, every start after the first that does not settle reads stopped, with no
/// solver counts, whatever the threads' timing. Rest at nu = 1e-3 lasts (the paper's Fig. 9;
/// its run goes on to the horizon), and the start at the fixed point after it settles at
/// once, long before rest's run is decided, on a pool of 2 threads. Before, that start read
/// "settles", its counts added, whenever its run ended before the stop reached it.
#[test]
fn after_the_first_unsettled_start_every_start_reads_stopped() {
    let s = paper(1e-3, 0.005);
    let starts = [REST, s.params.fixed_point()];
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let out = pool.install(|| fates(s, &starts, 3000.0, true)).unwrap();
    assert!(out[0].0.lasts(), "{out:?}");
    assert_eq!(out[1], (Fate::Stopped, SolverStats::default()));
    // Run on its own, the same start settles: the rule says stopped, not the run.
    let alone = pool.install(|| fates(s, &starts, 3000.0, false)).unwrap();
    assert!(alone[1].0.settles(), "{alone:?}");
    assert!(alone[1].1.evaluations > 0, "{alone:?}");
}

/// An answer the runs neither refute nor confirm names why. Table 1 at lambda 3, where rest
/// lasts at nu = 2.9e-3 and settles at 3.2e-3 (the test above): with the horizon at t = 50
/// no start is decided on either side (`undecided_above`); a bracket above the critical
/// value, [3.2e-3, 3.3e-3], for two starts (rest and the fixed point) has every start
/// settling on both sides (`settles_below`, no refutation: with two starts the squeal the
/// shortcut found below may lie where neither goes).
#[test]
fn an_unconfirmed_answer_names_why() {
    let s = paper(1e-3, 0.005);
    let c = confirm(s, BoundaryParam::Nu, &[REST], [2.9e-3, 3.2e-3], 50.0).unwrap();
    assert!(!c.confirmed && c.refuted.is_none(), "{c:?}");
    assert_eq!(c.unconfirmed, Some(Unconfirmed::UndecidedAbove), "{c:?}");
    assert!(c.line.contains("(undecided_above)"), "{}", c.line);
    let starts = [REST, State { x: 1.0, v: 0.0 }];
    let c = confirm(s, BoundaryParam::Nu, &starts, [3.2e-3, 3.3e-3], HORIZON).unwrap();
    assert!(!c.confirmed && c.refuted.is_none(), "{c:?}");
    assert_eq!(c.unconfirmed, Some(Unconfirmed::SettlesBelow), "{c:?}");
    assert!(c.line.contains("(settles_below)"), "{}", c.line);
    // Both starts ran at both ends at dt and at dt / 2, and settled at all four: the step
    // moved none of the four fates.
    assert_eq!((c.step.changed, c.step.compared), (0, 4), "{:?}", c.step);
    // Confirmed: no reason; the one start at each end compared at both steps, and at dt / 2
    // it too lasts below and settles above (the bracket is 10% wide about the critical
    // value 3.02e-3 that `squeal critical` prints at Table 1).
    let c = confirm(s, BoundaryParam::Nu, &[REST], [2.9e-3, 3.2e-3], HORIZON).unwrap();
    assert!(c.confirmed && c.unconfirmed.is_none(), "{c:?}");
    assert_eq!((c.step.changed, c.step.compared), (0, 2), "{:?}", c.step);
}

/// The step share compares fates start by start, by kind: at the lower end (value 1) start
/// 0 lasts at both steps (times and figures differ: the same fate), start 1 lasts at `dt`
/// and is undecided at `dt / 2` (changed), start 2 was stopped at `dt` (not compared); at
/// the upper end (value 2) start 0 settles at both, start 1 settles at `dt` and ends on the
/// slip oscillation at `dt / 2` (changed), start 2 settles at `dt` and was stopped at
/// `dt / 2` (not compared). So 2 changed of 4 compared: share 1/2, standard error
/// sqrt(1/2 * 1/2 / 4) = 1/4.
#[test]
fn the_step_share_compares_fates_start_by_start() {
    let lasts = |t| Fate::Lasts {
        t,
        lasting: None,
        certified: None,
    };
    let ends = |value, fates| Ends { value, fates };
    let lo = ends(1.0, vec![lasts(10.0), lasts(20.0), Fate::Stopped]);
    let lo_half = ends(1.0, vec![lasts(11.0), Fate::Undecided, Fate::Undecided]);
    let settles = |t| Fate::Settles { t };
    let hi = ends(2.0, vec![settles(5.0), settles(6.0), settles(7.0)]);
    let slip = Fate::SlipOscillation {
        t: 6.0,
        lasting: None,
        certified: None,
    };
    let hi_half = ends(2.0, vec![settles(5.5), slip, Fate::Stopped]);
    let s = step_share(&[(&lo, &lo_half), (&hi, &hi_half)]);
    assert_eq!((s.changed, s.compared), (2, 4), "{s:?}");
    assert_eq!((s.share, s.se), (0.5, 0.25), "{s:?}");
    assert!(s.not_small() && s.warning(crate::sensitivity::StepOf::Answer).is_some());
    // The same runs at both steps: nothing changes.
    let s = step_share(&[(&lo, &lo), (&hi, &hi)]);
    assert_eq!((s.changed, s.compared, s.share), (0, 5, 0.0), "{s:?}");
    assert!(s.warning(crate::sensitivity::StepOf::Answer).is_none());
}

/// A boundary's search fills its step sensitivity from the runs at its bracket's ends. Rest
/// and the fixed point at Table 1 (rest's critical damping 3.02e-3, MODEL.md section 13):
/// below the bracket rest does not settle, so the fixed point's run after it is stopped at
/// `dt` and not compared; above it both settle at `dt`, and (the bracket holding at
/// `dt / 2`, as it does here) at `dt / 2`: 3 starts compared. (Rest's fate is the same at
/// both steps at both ends here, 0 changed, but a lasting run at `dt` that is undecided at
/// `dt / 2` by t = 3000 would be a change, not an error.)
#[test]
fn a_boundary_search_reports_its_step_sensitivity() {
    let s = paper(1e-3, 0.005);
    let range = ParamRange::new(2.5e-3, 3.5e-3, 1e-2);
    let starts = [REST, s.params.fixed_point()];
    let rb = boundary(BoundaryParam::Nu, s, &starts, (range, range.hi), 3000.0).unwrap();
    assert_eq!(rb.status, BoundaryStatus::Found, "{rb:?}");
    assert_eq!(rb.half_dt_holds, Some(true), "{rb:?}");
    let step = rb.step.expect("checked at dt / 2");
    assert_eq!(step.compared, 3, "{step:?} {rb:?}");
    assert!(step.changed <= step.compared, "{step:?}");
}
