//! The cheaper robust solve (certified Newton, falling back to the full search) returns the
//! same root as the full two-sided bracket search (`solver::solve_full`): on random states and
//! previous forces, and along the stick-slip cycles of both McMillan laws, where many steps
//! have several roots.

use proptest::prelude::*;
use squeal_core::solver::{self, SolverStats};
use squeal_core::{FrictionLaw, Params, Run, Sample, Scheme, SolverConfig, State, Stepper};

fn stepper(law: FrictionLaw, nu: f64, dt: f64, scheme: Scheme) -> Stepper {
    let cfg = SolverConfig {
        scheme,
        ..Default::default()
    };
    Stepper::new(Params::paper(law, nu), dt, cfg).expect("valid parameters")
}

/// Solves the step from `s` both ways; returns (cheap, full) forces and the two counters.
fn both(st: &Stepper, s: &Sample) -> (f64, f64, SolverStats, SolverStats) {
    let eq = st.equation(s);
    let (mut a, mut b) = (SolverStats::default(), SolverStats::default());
    let fast = solver::solve(st.law(), st.solver(), &eq, s.force, &mut a);
    let full = solver::solve_full(st.law(), &eq, s.force, &mut b);
    assert!(fast.converged && full.converged, "{s:?}: {fast:?} {full:?}");
    (fast.force, full.force, a, b)
}

/// Whether the step's equation has several roots: sign changes of `G` on a grid of 2001
/// points over `[-B, B]` (B the bound on |F|).
fn several_roots(st: &Stepper, s: &Sample) -> bool {
    let eq = st.equation(s);
    let b = st.params().force_bound();
    let mut scratch = SolverStats::default();
    let n = 2000;
    let mut prev = eq.eval(st.law(), -b, &mut scratch).g;
    let mut changes = 0;
    for i in 1..=n {
        let g = eq
            .eval(st.law(), -b + 2.0 * b * i as f64 / n as f64, &mut scratch)
            .g;
        changes += usize::from((g > 0.0) != (prev > 0.0));
        prev = g;
    }
    changes > 1
}

/// Same root: the two iterations stop at different points within the residual tolerance
/// (4 ulps of `F`), so the forces agree to about 1e-15 where `|G'|` is not tiny.
fn same_root(x: f64, y: f64) -> bool {
    (x - y).abs() <= 1e-11 * (1.0 + x.abs())
}

/// Along 40 time units of the settled stick-slip cycle (nu = 1e-3, from rest, after t = 500)
/// every step's cheaper solve equals the full search, including the hundreds of steps whose
/// equation has several roots.
#[test]
fn same_root_along_the_stick_slip_cycles() {
    for law in [FrictionLaw::McMillan, FrictionLaw::McMillanNonHysteretic] {
        for scheme in [Scheme::Foh, Scheme::Zoh] {
            let st = stepper(law, 1e-3, 0.01, scheme);
            let mut run = Run::new(&st, State { x: 0.0, v: 0.0 });
            run.by_ref().take(50_000).for_each(drop);
            let (mut fast, mut full, mut n) = (SolverStats::default(), SolverStats::default(), 0);
            let mut several = 0;
            for step in run.take(4000) {
                let (x, y, a, b) = both(&st, &step.prev);
                assert!(
                    same_root(x, y),
                    "{law} {scheme} {:?}: {x} vs {y}",
                    step.prev
                );
                several += usize::from(several_roots(&st, &step.prev));
                fast.merge(&a);
                full.merge(&b);
                n += 1;
            }
            assert!(
                several > 100,
                "{law} {scheme}: {several} steps with several roots"
            );
            eprintln!("{law} {scheme}: {several} several, fast {fast:?} full {full:?}");
            assert!(
                fast.fallbacks < n * 3 / 4 && fast.fallbacks > 0,
                "{law} {scheme}: {fast:?}"
            );
            assert!(fast.evaluations < full.evaluations, "{fast:?} {full:?}");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// Random states, previous forces, damping, steps, laws and schemes.
    #[test]
    fn same_root_on_random_states(
        x in -6.0..6.0f64,
        v in -6.0..6.0f64,
        f_prev in -2.2..2.2f64,
        nu in prop::sample::select(vec![0.0, 1e-3, 1e-2, 0.3, 2.0]),
        dt in prop::sample::select(vec![0.0025, 0.01, 0.04, 0.3]),
        nonhysteretic in any::<bool>(),
        zoh in any::<bool>(),
    ) {
        let law = if nonhysteretic { FrictionLaw::McMillanNonHysteretic } else { FrictionLaw::McMillan };
        let scheme = if zoh { Scheme::Zoh } else { Scheme::Foh };
        let st = stepper(law, nu, dt, scheme);
        let s = Sample { t: 0.0, x, v, a: 0.0, force: f_prev };
        let (a, b, _, _) = both(&st, &s);
        prop_assert!(same_root(a, b), "{:?}: {} vs {}", s, a, b);
    }
}
