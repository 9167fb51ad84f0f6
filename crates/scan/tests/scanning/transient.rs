//! Transient squeal is a result. `t_squeal`, the time a run spent on
//! stick-slip before it settled, as every path stores it.

use squeal_core::friction::on_quasi_static_branch;
use squeal_core::{Classifier, FrictionLaw, Params, Reason, Regime, SolverConfig, State, Stepper};
use squeal_scan::Plan;
use squeal_scan::scanner::MapContext;
use squeal_scan::trajectory::{Span, run};

/// At nu = 0.025 (Table 1's lambda, tau, phi, hysteretic law) the band above the unstable
/// cycle leaks: the run from (10, 0) sticks on the band for about 150 time units and then
/// falls inside the cycle (it was once labelled `sticking_band` at t = 134.2).
const NU: f64 = 0.025;
const START: State = State { x: 10.0, v: 0.0 };

fn stepper() -> Stepper {
    Stepper::new(
        Params::paper(FrictionLaw::McMillan, NU),
        0.005,
        SolverConfig::default(),
    )
    .unwrap()
}

/// The run's `t_squeal` is the end of its last stuck step, read independently off the
/// plain run's samples (every step kept): the last sample before the decision on the
/// quasi-static branch of the law (slip velocity `x' - lambda`, acceleration `x''`; the
/// hysteretic law has no Coulomb stick in this run, `sticks = 0` in its counts).
#[test]
fn t_squeal_is_the_last_stuck_step_of_a_plain_run() {
    let st = stepper();
    let p = *st.params();
    let span = Span {
        ic: START,
        t_end: 1000.0,
        every: 1,
    };
    let t = run(&st, &Classifier::default(), span, None);
    let o = t.outcome;
    assert_eq!(
        (o.regime, o.reason),
        (Regime::SteadySlip, Reason::NearFixedPoint)
    );
    assert_eq!(t.stats.sticks, 0);
    let s = &t.samples;
    let last = (0..s.t.len())
        .filter(|&i| s.t[i] <= o.t_decision)
        .filter(|&i| on_quasi_static_branch(&p, s.v[i] - p.lambda, s.a[i]))
        .map(|i| s.t[i])
        .next_back()
        .expect("the run sticks");
    // Many revolutions stuck: squeal for about 150 time units (about 24 periods).
    assert!(last > 100.0 && last < o.t_decision, "{last} {o:?}");
    assert_eq!(o.t_squeal, last, "{o:?}");
}

fn plan(early_stop: &str) -> Plan {
    Plan::from_toml(
        &format!(
            r#"
version = 1
[model]
law = "mcmillan"
nu = {NU}
[grid]
x0 = {{ min = -3.0, max = 10.0, count = 14 }}
v0 = {{ min = -4.0, max = 4.0, count = 7 }}
[classifier]
early_stop = "{early_stop}"
[output]
path = "x.h5"
"#
        ),
        "x.toml",
    )
    .unwrap()
}

/// A scan stores the same `t_squeal` whether its runs go to settlement or stop at the
/// cycle's trap: inside the unstable cycle no revolution sticks, so a run stopped at its
/// first crossing inside has already had its last stuck step (the argument of
/// `squeal_core::classify::t_squeal`). A start decided inside the cycle without a run has
/// 0, a start outside a trapped band infinity (not here: the band leaks).
#[test]
fn the_trap_keeps_the_runs_t_squeal() {
    let settle = MapContext::prepare(&plan("none"), 0).unwrap();
    let early = MapContext::prepare(&plan("cycle"), 0).unwrap();
    let (a, b) = (settle.classify(START), early.classify(START));
    assert_eq!(a.reason, Reason::NearFixedPoint, "{a:?}");
    assert_eq!(b.reason, Reason::InsideCycle, "{b:?}");
    assert!(a.t_squeal > 100.0, "{a:?}");
    assert_eq!(a.t_squeal, b.t_squeal);
    let near = early.classify(State { x: 1.5, v: 0.0 });
    assert_eq!(
        (near.reason, near.t_squeal),
        (Reason::StartInsideCycle, 0.0)
    );
    // The same start through the scan's cell (the stored column).
    let g = &plan("cycle").map.grid;
    let (row, col) = (3, 13);
    assert_eq!(g.state(row, col), (10.0, 0.0));
    assert_eq!(early.cell(&plan("cycle"), row, col).t_squeal, b.t_squeal);
}

/// The band's mean lifetime (runs stopped by the cycle's trap) against direct runs from the
/// same starts taken on to the fixed point with `squeal_scan::trajectory::run` (no trap,
/// to t = 40000): the same lifetimes, start by start, so the same mean. This checks the
/// argument the lifetimes rest on: inside the cycle nothing sticks, so the trap stops a run
/// after its last stuck step. At nu = 0.025 every start leaves the band long before 40000
/// (mean lifetime about 40, longest under 300: `squeal critical --crisis --lifetimes`).
#[test]
#[ignore = "long check against long runs (a minute or more on 2 cores): run by scripts/ci/long-checks.sh, which .ci/run calls"]
fn band_lifetimes_match_direct_long_runs() {
    use squeal_core::Setup;
    use squeal_scan::band::band_span;
    use squeal_scan::lifetime::{LifetimeSettings, band_lifetime, mean_lifetime};
    use squeal_scan::section::{ReturnMap, SectionCycles, Work, section_cycles};
    use squeal_scan::ulc::CycleSettings;

    let st = stepper();
    let setup = Setup::new(*st.params(), 0.005, SolverConfig::default());
    let cs = CycleSettings::default();
    let ls = LifetimeSettings {
        starts: 12,
        ..LifetimeSettings::default()
    };
    let band = band_lifetime(setup, &cs, &ls).unwrap();
    assert_eq!(band.lifetime.censored, 0, "{band:?}");
    // The same starts, rebuilt from the same section search.
    let (mut stats, mut returns) = (Default::default(), 0);
    let SectionCycles::Unstable {
        r, stable_above, ..
    } = section_cycles(&st, &cs, &mut stats, &mut returns)
    else {
        panic!("no cycle at nu = {NU}");
    };
    let map = ReturnMap::new(&st, cs.t_return);
    let (s, b) = band_span(
        &map,
        r,
        stable_above.unwrap_or(2.0 * r),
        &mut Work::default(),
    )
    .unwrap();
    assert_eq!([s, b], band.span);
    let fp = st.params().fixed_point();
    let times: Vec<f64> = (0..ls.starts)
        .map(|k| {
            let v = s + (b - s) * (k as f64 + 0.5) / ls.starts as f64;
            let span = Span {
                ic: State { x: fp.x, v },
                t_end: 40_000.0,
                every: 0,
            };
            let o = run(&st, &Classifier::default(), span, None).outcome;
            assert_eq!(o.reason, Reason::NearFixedPoint, "{o:?}");
            o.t_squeal
        })
        .collect();
    let direct = mean_lifetime(&times, 0, ls.t_max);
    assert_eq!(direct, band.lifetime);
    assert!(direct.mean.unwrap() > 1.0, "{direct:?}");
}
