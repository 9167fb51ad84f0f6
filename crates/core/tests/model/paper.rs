//! The engine against McMillan (1997) and against properties of its own scheme.
//!
//! * Results of the paper (../MODEL.md, sec. 7): which attractor a run from a given state settles
//!   on, the stick-slip frequency, the flat top of the non-hysteretic loop.
//! * The schemes: the paper's zero-order hold is first order in `dt` (the force held at its
//!   end-of-step value over each step), the default first-order hold second order; robust
//!   solves at rounding level where the paper's iteration diverges, the paper iteration's
//!   share of unconverged steps (both pinned to the paper's scheme), Coulomb friction never
//!   feeding energy in.
//! * A snapshot of the solver counters, to flag unintended algorithm changes in review.
//!
//! `cargo test -p squeal-core --test model -- --ignored --nocapture paper::dt_study` prints the
//! convergence study recorded in docs/history/benchmarks.md.

use std::f64::consts::TAU;
use std::sync::OnceLock;

use proptest::prelude::*;
use squeal_core::classify::{crossing, section_return};
use squeal_core::friction;
use squeal_core::{
    Classifier, FrictionLaw, Params, Regime, Run, Sample, Scheme, SolverConfig, SolverKind,
    SolverStats, State, Stepper,
};

const LAMBDA: f64 = 3.0;
const REST: State = State { x: 0.0, v: 0.0 };

fn stepper(law: FrictionLaw, nu: f64, dt: f64, kind: SolverKind) -> Stepper {
    stepper_with(law, nu, dt, kind, Scheme::default())
}

fn stepper_with(law: FrictionLaw, nu: f64, dt: f64, kind: SolverKind, scheme: Scheme) -> Stepper {
    let cfg = SolverConfig {
        kind,
        scheme,
        ..Default::default()
    };
    Stepper::new(Params::paper(law, nu), dt, cfg).expect("valid parameters")
}

/// The paper's scheme: zero-order hold, with the given solver.
fn paper_scheme(law: FrictionLaw, nu: f64, dt: f64, kind: SolverKind) -> Stepper {
    stepper_with(law, nu, dt, kind, Scheme::Zoh)
}

fn robust(law: FrictionLaw, nu: f64) -> Stepper {
    stepper(law, nu, 0.01, SolverKind::Robust)
}

/// Runs `n` steps from `s` (a [`Run`] continued from it), calling `visit` on each step's
/// samples and its solve's convergence; adds the run's counters to `stats`.
fn advance(
    st: &Stepper,
    s: Sample,
    n: u64,
    stats: &mut SolverStats,
    mut visit: impl FnMut(&Sample, &Sample, bool),
) -> Sample {
    let mut run = Run::from_sample(st, s);
    for step in run.by_ref().take(n as usize) {
        visit(&step.prev, &step.next, step.solution.converged);
    }
    stats.merge(run.stats());
    *run.sample()
}

/// Steps needed to cover `t` time units.
fn steps(st: &Stepper, t: f64) -> u64 {
    (t / st.dt()).round() as u64
}

/// The state after `t` time units from `ic`.
fn run_to(st: &Stepper, ic: State, t: f64) -> Sample {
    let mut run = Run::new(st, ic);
    run.by_ref().take(steps(st, t) as usize).for_each(drop);
    *run.sample()
}

/// Mean angular frequency and mean section amplitude over `t` time units from `s`:
/// `2 pi (k - 1) / (t_k - t_1)` over the `k` crossings of `x = 1, x' > 0`.
fn mean_cycle(st: &Stepper, s: Sample, t: f64) -> (f64, f64) {
    let mut stats = SolverStats::default();
    let (mut ts, mut rs) = (Vec::new(), Vec::new());
    advance(st, s, steps(st, t), &mut stats, |a, b, _| {
        if let Some(c) = crossing(1.0, a, b) {
            ts.push(c.t);
            rs.push(c.r);
        }
    });
    assert!(ts.len() > 2, "no oscillation");
    let omega = TAU * (ts.len() - 1) as f64 / (ts[ts.len() - 1] - ts[0]);
    (omega, rs.iter().sum::<f64>() / rs.len() as f64)
}

/// Samples along the settled nu = 1e-3 hysteretic stick-slip cycle (robust solver, dt = 0.01):
/// after t = 1000 from rest, the next 20 time units (about three revolutions).
fn stick_slip_cycle() -> &'static [Sample] {
    static CYCLE: OnceLock<Vec<Sample>> = OnceLock::new();
    CYCLE.get_or_init(|| {
        let st = robust(FrictionLaw::McMillan, 1e-3);
        let s = run_to(&st, REST, 1000.0);
        let mut out = vec![s];
        let mut stats = SolverStats::default();
        advance(&st, s, 2000, &mut stats, |_, b, _| out.push(*b));
        out
    })
}

// ---------------------------------------------------------------------------------------------
// The scheme
// ---------------------------------------------------------------------------------------------

/// Errors in (x, x') at t = 20 from (1.5, 0), nu = 1e-2, against a dt = 1e-4 run of the same
/// scheme, at dt = 0.04, 0.02, 0.01, 0.005. The run stays on the slip branch (smooth).
fn slip_branch_errors(scheme: Scheme, t_end: f64) -> Vec<f64> {
    let ic = State { x: 1.5, v: 0.0 };
    let law = FrictionLaw::McMillan;
    let reference = run_to(
        &stepper_with(law, 1e-2, 1e-4, SolverKind::Robust, scheme),
        ic,
        t_end,
    );
    let mut errors = Vec::new();
    for dt in [0.04, 0.02, 0.01, 0.005] {
        let st = stepper_with(law, 1e-2, dt, SolverKind::Robust, scheme);
        let p = *st.params();
        let mut run = Run::new(&st, ic);
        for step in run.by_ref().take(steps(&st, t_end) as usize) {
            let b = step.next;
            assert!(t_end > 1.5 || b.a < 0.0, "x'' changed sign at t = {}", b.t);
            // A smooth case: the whole run stays on the slip branch of the law.
            assert!(
                !friction::on_quasi_static_branch(&p, b.v - p.lambda, b.a),
                "dt={dt}: left the slip branch at t={}",
                b.t
            );
        }
        let end = run.sample();
        assert!((end.t - t_end).abs() < 1e-9);
        errors.push((end.x - reference.x).hypot(end.v - reference.v));
    }
    errors
}

/// Zero-order hold (the paper's scheme) is first order: the error halves with dt (the force
/// is constant over a step at its end-of-step value, a backward-Euler-like quadrature of the
/// Duhamel integral; the linear part is exact). Measured errors: 5.36e-4, 2.67e-4, 1.33e-4,
/// 6.59e-5, orders 1.003, 1.006, 1.015. A coefficient typo in the propagator would break this.
#[test]
fn zoh_is_first_order_on_the_slip_branch() {
    let errors = slip_branch_errors(Scheme::Zoh, 20.0);
    for w in errors.windows(2) {
        let order = (w[0] / w[1]).log2();
        assert!((0.95..=1.1).contains(&order), "order {order} ({errors:?})");
    }
}

/// First-order hold is second order: the error falls by 4 when dt halves (the force's linear
/// interpolation over a step is exact to O(dt^2), integrated exactly). A wrong ramp
/// coefficient (q1, q2) would leave it first order.
///
/// The clean order needs a smooth force: McMillan's law has a kink in `|x''|`, so `F(t)` kinks
/// wherever the acceleration changes sign. From (1.5, 0) `x'' < 0` until about t = pi/2, so
/// t = 1.2 is smooth: measured errors 1.556e-6, 3.890e-7, 9.725e-8, 2.430e-8 at dt = 0.04 ..
/// 0.005 (orders 2.000, 2.000, 2.000; the paper's scheme: about 90 times larger at dt = 0.01).
/// Over t = 20 (about 6 kinks) the order is still 2 on average, with a scatter from where
/// each kink falls inside its step: errors 5.88e-6, 1.84e-6, 4.00e-7, 1.23e-7 (mean order 1.86).
#[test]
fn foh_is_second_order_on_the_slip_branch() {
    let errors = slip_branch_errors(Scheme::Foh, 1.2);
    for w in errors.windows(2) {
        let order = (w[0] / w[1]).log2();
        assert!((1.95..=2.05).contains(&order), "order {order} ({errors:?})");
    }
    let zoh = slip_branch_errors(Scheme::Zoh, 1.2);
    assert!(errors[2] * 50.0 < zoh[2], "{errors:?} vs {zoh:?}");
    let long = slip_branch_errors(Scheme::Foh, 20.0);
    let mean_order = (long[0] / long[3]).log2() / 3.0;
    assert!((1.7..=2.3).contains(&mean_order), "{mean_order} ({long:?})");
}

/// States along the stick-slip cycle are where the paper's fixed-point iteration diverges
/// (`|dF/dF| > 1` on the quasi-static branch); the robust solver returns a root to rounding
/// there, from the force the cycle had and from forces far from it.
#[test]
fn robust_solves_where_the_paper_iteration_diverges() {
    let paper = paper_scheme(FrictionLaw::McMillan, 1e-3, 0.01, SolverKind::Paper);
    let robust = paper_scheme(FrictionLaw::McMillan, 1e-3, 0.01, SolverKind::Robust);
    let (mut diverged, mut stats) = (0, SolverStats::default());
    for s in stick_slip_cycle() {
        let (_, p_sol) = paper.step(s, &mut SolverStats::default());
        let (_, r_sol) = robust.step(s, &mut stats);
        assert!(
            r_sol.converged && r_sol.residual <= 1e-14,
            "{s:?} {r_sol:?}"
        );
        if !p_sol.converged {
            diverged += 1;
        }
    }
    assert!(
        diverged >= 20,
        "the paper iteration should fail here: {diverged}"
    );
    assert_eq!((stats.failures, stats.discontinuities), (0, 0));
}

/// The samples of 20 time units of the settled nu = 1e-3 non-hysteretic stick-slip cycle.
fn nonhysteretic_cycle() -> &'static [Sample] {
    static CYCLE: OnceLock<Vec<Sample>> = OnceLock::new();
    CYCLE.get_or_init(|| {
        let st = robust(FrictionLaw::McMillanNonHysteretic, 1e-3);
        let s = run_to(&st, REST, 1000.0);
        let mut out = vec![s];
        let mut stats = SolverStats::default();
        advance(&st, s, 2000, &mut stats, |_, b, _| out.push(*b));
        out
    })
}

/// Steps from `samples` whose robust force is not the root of `G` nearest to the previous
/// force, all roots located as sign changes on a grid of 20 001 points over `[-B, B]`.
fn not_nearest(law: FrictionLaw, samples: &[Sample]) -> (usize, usize) {
    let st = robust(law, 1e-3);
    let p = *st.params();
    let b = p.force_bound();
    let (mut wrong, mut several) = (0, 0);
    let mut scratch = SolverStats::default();
    for s in samples {
        let eq = st.equation(s);
        let got = st.step(s, &mut SolverStats::default()).0.force;
        let n = 20_000;
        let grid = |i: usize| -b + 2.0 * b * i as f64 / n as f64;
        let mut roots = Vec::new();
        let mut prev = eq.eval(st.law(), grid(0), &mut scratch).g;
        for i in 1..=n {
            let g = eq.eval(st.law(), grid(i), &mut scratch).g;
            if (g > 0.0) != (prev > 0.0) {
                roots.push(0.5 * (grid(i - 1) + grid(i)));
            }
            prev = g;
        }
        several += usize::from(roots.len() > 1);
        let nearest = roots
            .iter()
            .copied()
            .min_by(|x, y| (x - s.force).abs().total_cmp(&(y - s.force).abs()))
            .expect("a root");
        wrong += usize::from((nearest - got).abs() > 1e-3);
    }
    (wrong, several)
}

/// The robust solver keeps the force on its branch: of several roots it takes the one nearest
/// to the previous force (../MODEL.md, sec. 4: hysteresis). Over these 2001 steps of each
/// stick-slip cycle, 383-392 (hysteretic) and about 170 (non-hysteretic) have several roots.
/// Hysteretic law: always the nearest. Non-hysteretic law: in its stick phase `G` can have four
/// or more roots inside one interval of the outward search, and 8 of the 2001 steps took a
/// farther root; the test allows 1%. Before `solver::hidden_pair` the outward search stepped
/// over any pair of roots that fell in one interval: 1 hysteretic step here (1 of 5000 over a
/// longer stretch) and 63 of 5000 non-hysteretic steps took a farther root.
#[test]
fn robust_solver_takes_the_nearest_root() {
    let (wrong, several) = not_nearest(FrictionLaw::McMillan, stick_slip_cycle());
    assert!(several > 100, "{several}");
    assert_eq!(wrong, 0, "hysteretic: {wrong} steps not nearest");
    let c = nonhysteretic_cycle();
    let (wrong, several) = not_nearest(FrictionLaw::McMillanNonHysteretic, c);
    assert!(several > 100, "{several}");
    assert!(
        wrong * 100 <= c.len(),
        "non-hysteretic: {wrong} of {} steps not nearest",
        c.len()
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// Residual at rounding level on states near the stick-slip cycle with a perturbed
    /// previous force.
    #[test]
    fn robust_residual_near_the_stick_slip_cycle(
        i in any::<prop::sample::Index>(),
        dx in -1e-2..1e-2f64,
        dv in -1e-2..1e-2f64,
        df in -0.5..0.5f64,
        nonhysteretic in any::<bool>(),
    ) {
        let law = if nonhysteretic { FrictionLaw::McMillanNonHysteretic } else { FrictionLaw::McMillan };
        let st = robust(law, 1e-3);
        let c = stick_slip_cycle();
        let s = c[i.index(c.len())];
        let s = Sample { x: s.x + dx, v: s.v + dv, force: s.force + df, ..s };
        let mut stats = SolverStats::default();
        let (n, sol) = st.step(&s, &mut stats);
        prop_assert!(sol.converged && sol.residual <= 1e-14, "{:?} {:?}", s, sol);
        prop_assert!(n.x.is_finite() && n.v.is_finite());
        prop_assert_eq!((stats.failures, stats.discontinuities), (0, 0));
    }

    /// Residual at rounding level on random states and previous forces, both laws, a range of
    /// damping and steps; also the initial solve.
    #[test]
    fn robust_residual_on_random_states(
        x in -6.0..6.0f64,
        v in -6.0..6.0f64,
        f_prev in -2.2..2.2f64,
        nu in prop::sample::select(vec![0.0, 1e-3, 1e-2, 0.3, 2.0]),
        dt in prop::sample::select(vec![0.0025, 0.01, 0.04, 0.3]),
        nonhysteretic in any::<bool>(),
    ) {
        let law = if nonhysteretic { FrictionLaw::McMillanNonHysteretic } else { FrictionLaw::McMillan };
        let st = stepper(law, nu, dt, SolverKind::Robust);
        let mut stats = SolverStats::default();
        let s = Sample { t: 0.0, x, v, a: 0.0, force: f_prev };
        let (_, sol) = st.step(&s, &mut stats);
        prop_assert!(sol.converged && sol.residual <= 1e-14, "{:?} {:?}", s, sol);
        let (_, sol) = st.initial(State { x, v }, &mut stats);
        prop_assert!(sol.converged && sol.residual <= 1e-14, "initial {:?}", sol);
        prop_assert_eq!(stats.failures, 0);
    }

    /// Coulomb friction never feeds energy in: while the block is slower than the belt
    /// (`|x'| < lambda`) it slips with `F = 1`, the motion is the damped linear oscillator about
    /// `x = 1` and `E = (x - 1)^2 / 2 + x'^2 / 2` can only fall (`dE/dt = -2 nu x'^2`). Starts with
    /// `sqrt(2 E) < 2.9 < lambda` keep `|x'| < lambda` for ever. The exact propagator keeps this
    /// to rounding.
    #[test]
    fn coulomb_never_feeds_energy_in(
        rho in 0.0..2.9f64,
        theta in 0.0..TAU,
        nu in 1e-4..0.5f64,
    ) {
        let st = stepper(FrictionLaw::Coulomb, nu, 0.01, SolverKind::Robust);
        let energy = |s: &Sample| 0.5 * ((s.x - 1.0).powi(2) + s.v * s.v);
        let mut stats = SolverStats::default();
        let (s0, _) = st.initial(State { x: 1.0 + rho * theta.cos(), v: rho * theta.sin() }, &mut stats);
        let tol = 1e-13 * (1.0 + energy(&s0));
        let mut worst = f64::NEG_INFINITY;
        advance(&st, s0, 3000, &mut stats, |a, b, _| {
            worst = worst.max(energy(b) - energy(a));
        });
        prop_assert!(worst <= tol, "energy rose by {worst}");
        prop_assert_eq!(stats.sticks, 0);
    }
}

/// Along the stick-slip cycle the paper's iteration (cap 100, tolerance 1e-12) fails on a
/// sizeable share of the steps. ../MODEL.md reports 5-13% from an independent implementation;
/// measured here: 12.4% of the steps over t in [1000, 2000] from rest at nu = 1e-3 (hysteretic;
/// 11.3% for the non-hysteretic law).
#[test]
fn paper_iteration_fails_on_part_of_the_stick_slip_cycle() {
    for law in [FrictionLaw::McMillan, FrictionLaw::McMillanNonHysteretic] {
        let st = paper_scheme(law, 1e-3, 0.01, SolverKind::Paper);
        let s = run_to(&st, REST, 1000.0);
        let mut stats = SolverStats::default();
        let (mut n, mut failed) = (0u64, 0u64);
        advance(&st, s, steps(&st, 1000.0), &mut stats, |_, _, ok| {
            n += 1;
            failed += u64::from(!ok);
        });
        let share = failed as f64 / n as f64;
        assert_eq!(failed, stats.unconverged);
        assert!((0.03..=0.20).contains(&share), "{law}: {share}");
    }
}

// ---------------------------------------------------------------------------------------------
// Results of the paper
// ---------------------------------------------------------------------------------------------

/// Fig 9: at nu = 1e-3 the unstable cycle does not enclose the rest state, so the block goes
/// to stick-slip; its angular frequency is about 0.96. Measured mean over t in [1000, 3000]:
/// 0.9614 (single revolutions vary by about +-0.006 in the quasi-periodic band; the dt study
/// in docs/history/benchmarks.md gives 0.9558 as dt -> 0).
#[test]
fn light_damping_from_rest_is_stick_slip_at_0_96() {
    let st = robust(FrictionLaw::McMillan, 1e-3);
    let out = Classifier::default().classify(&st, REST);
    assert_eq!(out.regime, Regime::StickSlip, "{out:?}");
    let (omega, _) = mean_cycle(&st, run_to(&st, REST, 1000.0), 2000.0);
    assert!((omega - 0.96).abs() <= 0.01, "omega {omega}");
    assert!(
        (out.omega - 0.96).abs() <= 0.015,
        "last revolution {}",
        out.omega
    );
}

/// Fig 10: at nu = 1e-2 the unstable cycle encloses the rest state: steady slip.
#[test]
fn heavier_damping_from_rest_is_steady_slip() {
    let out = Classifier::default().classify(&robust(FrictionLaw::McMillan, 1e-2), REST);
    assert_eq!(out.regime, Regime::SteadySlip, "{out:?}");
}

/// Fig 10: at nu = 1e-2 an energetic start, (-2.5, 0), reaches stick-slip at about 0.98.
/// Measured mean over t in [1000, 3000]: 0.9782 (0.9784 as dt -> 0).
#[test]
fn heavier_damping_from_far_is_stick_slip_at_0_98() {
    let st = robust(FrictionLaw::McMillan, 1e-2);
    let ic = State { x: -2.5, v: 0.0 };
    let out = Classifier::default().classify(&st, ic);
    assert_eq!(out.regime, Regime::StickSlip, "{out:?}");
    let (omega, _) = mean_cycle(&st, run_to(&st, ic, 1000.0), 2000.0);
    assert!((omega - 0.98).abs() <= 0.01, "omega {omega}");
}

/// Fig 11: the non-hysteretic stick-slip loop (nu = 1e-3) is flat-topped: x' rises to the belt
/// speed and stays there, while the hysteretic loop has a sharp peak above it.
///
/// Measured (robust solver, from rest, over t in [1000, 2000]):
/// * overshoot max x' - lambda: non-hysteretic 0.0047, 0.0053, 0.0056, 0.0057 at
///   dt = 0.02, 0.01, 0.005, 0.0025, so it does not shrink with dt: a property of the
///   regularised law, not step error; hysteretic 0.134, 0.135, 0.137, 0.137.
/// * share of the time with |x' - lambda| < 0.01: non-hysteretic 9.5% (about 0.6 time units
///   per revolution, the stick phase), hysteretic 0.5%.
/// * One stick phase per revolution. During it the regularised law chatters: x' dips to
///   lambda - 0.02 and, in a few revolutions, below (the stick phase then splits on a 0.02
///   threshold), so "x' within 0.01 of lambda over the stick phase" is not true of this law at
///   dt = 0.01; the band is about [lambda - 0.02, lambda + 0.006]. Where the phase ends is a
///   matter of threshold (the departure is gradual), so the band's lower edge is not asserted.
#[test]
fn nonhysteretic_loop_is_flat_topped() {
    let measure = |law| {
        let st = robust(law, 1e-3);
        let s = run_to(&st, REST, 1000.0);
        let mut stats = SolverStats::default();
        let (mut top, mut near, mut n) = (f64::NEG_INFINITY, 0u64, 0u64);
        // Stick phases: from x' >= lambda - 0.01 until x' < lambda - 0.05 (the slip).
        let (mut inside, mut phases, mut revolutions) = (false, 0u32, 0u32);
        advance(&st, s, steps(&st, 1000.0), &mut stats, |a, b, _| {
            let dv = b.v - LAMBDA;
            top = top.max(dv);
            n += 1;
            near += u64::from(dv.abs() < 0.01);
            if !inside && dv >= -0.01 {
                inside = true;
                phases += 1;
            } else if inside && dv < -0.05 {
                inside = false;
            }
            revolutions += u32::from(crossing(1.0, a, b).is_some());
        });
        (top, near as f64 / n as f64, phases, revolutions)
    };
    let (top_nh, near_nh, phases, revolutions) = measure(FrictionLaw::McMillanNonHysteretic);
    let (top_h, near_h, _, _) = measure(FrictionLaw::McMillan);
    assert!(top_nh < 0.01, "non-hysteretic overshoot {top_nh}");
    assert!(10.0 * top_nh < top_h, "overshoots {top_nh} vs {top_h}");
    assert!(
        near_nh > 0.05 && near_nh > 5.0 * near_h,
        "{near_nh} {near_h}"
    );
    assert!(
        revolutions > 100 && phases.abs_diff(revolutions) <= 1,
        "one stick phase per revolution: {phases} phases, {revolutions} revolutions"
    );
}

// ---------------------------------------------------------------------------------------------
// Snapshot
// ---------------------------------------------------------------------------------------------

/// A SNAPSHOT, not a physical fact: the solver counters of fixed 10 000-step runs (nu = 1e-3,
/// dt = 0.01) from (-2.5, 0), which reaches the stick-slip cycle within a few revolutions, so
/// the counts cover the quasi-static branch, multiple roots and the paper iteration's failures.
/// Recorded on x86-64 Linux. Any change of the solver, the stepper or the laws changes these
/// numbers; if the change is intended, record the new ones here and say so in review. (The
/// counts depend on libm's `sin`, so another platform may differ slightly.)
///
/// Last recorded with certified Newton and the first-order hold. The zero-order-hold
/// trajectories are bit for bit those of the code before (c44a1a5 gives the same newton_steps,
/// bisections, expansions, iterations and unconverged; its own snapshot was stale there).
/// Evaluations: robust 56_508 -> 44_205 (hysteretic) and 63_026 -> 50_711 (non-hysteretic)
/// from certified Newton; paper +10_002 because the final residual evaluation of every solve
/// (and the initial guess) is now counted.
///
/// Re-recorded when McMillan's laws took their own arctangent (`squeal_core::atan`):
/// it differs from libm's in the last bit for a few percent of arguments, and these
/// stick-slip runs pass that difference on (hysteretic robust 44_205 -> 44_212 evaluations,
/// paper 236_139 -> 234_338; non-hysteretic robust 50_711 -> 49_990, 50_913 -> 50_877). The
/// counts of both are within the spread of rounding; the labels of the shipped specs are the
/// same (docs/history/benchmarks.md, "Cost per step, reduced").
#[test]
fn solver_counters_snapshot() {
    let mut got = Vec::new();
    for law in [FrictionLaw::McMillan, FrictionLaw::McMillanNonHysteretic] {
        for (kind, scheme) in [
            (SolverKind::Robust, Scheme::Zoh),
            (SolverKind::Paper, Scheme::Zoh),
            (SolverKind::Robust, Scheme::Foh),
        ] {
            let st = stepper_with(law, 1e-3, 0.01, kind, scheme);
            let mut run = Run::new(&st, State { x: -2.5, v: 0.0 });
            run.by_ref().take(10_000).for_each(drop);
            got.push(*run.stats());
        }
    }
    let expected = vec![
        // Hysteretic, robust, zero-order hold.
        SolverStats {
            solves: 10_001,
            evaluations: 44_212,
            newton_steps: 24_533,
            bisections: 6,
            expansions: 38,
            fallbacks: 3_849,
            ..SolverStats::default()
        },
        // Hysteretic, paper, zero-order hold.
        SolverStats {
            solves: 10_001,
            evaluations: 234_338,
            iterations: 224_336,
            unconverged: 1_285,
            ..SolverStats::default()
        },
        // Hysteretic, robust, first-order hold.
        SolverStats {
            solves: 10_001,
            evaluations: 43_889,
            newton_steps: 24_499,
            bisections: 2,
            expansions: 33,
            fallbacks: 3_851,
            ..SolverStats::default()
        },
        // Non-hysteretic, robust, zero-order hold.
        SolverStats {
            solves: 10_001,
            evaluations: 49_990,
            newton_steps: 27_209,
            bisections: 1_045,
            expansions: 93,
            multi_root: 93,
            fallbacks: 3_842,
            ..SolverStats::default()
        },
        // Non-hysteretic, paper, zero-order hold.
        SolverStats {
            solves: 10_001,
            evaluations: 223_990,
            iterations: 213_988,
            unconverged: 1_125,
            ..SolverStats::default()
        },
        // Non-hysteretic, robust, first-order hold.
        SolverStats {
            solves: 10_001,
            evaluations: 50_877,
            newton_steps: 27_122,
            bisections: 878,
            expansions: 143,
            multi_root: 92,
            fallbacks: 3_830,
            ..SolverStats::default()
        },
    ];
    assert_eq!(got, expected, "{got:#?}");
}

// ---------------------------------------------------------------------------------------------
// Convergence study (docs/history/benchmarks.md)
// ---------------------------------------------------------------------------------------------

/// The unstable cycle's crossing `r_u` of the section `x = 1, x' > 0`: the first `r` where the
/// return map's displacement `P(r) - r` turns from negative (decay) to positive (growth),
/// located by bisection to 1e-9.
fn unstable_cycle(st: &Stepper) -> Option<f64> {
    let displacement = |r: f64| {
        let mut stats = SolverStats::default();
        section_return(st, r, 100.0, &mut stats, |_| {})
            .ok()
            .map(|c| c.r - r)
    };
    let (mut lo, mut r) = (f64::NAN, 0.01);
    while r < 3.0 {
        if displacement(r)? > 0.0 {
            break;
        }
        lo = r;
        r *= 1.1;
    }
    let mut hi = r;
    if lo.is_nan() || hi >= 3.0 {
        return None;
    }
    while hi - lo > 1e-9 {
        let mid = 0.5 * (lo + hi);
        if displacement(mid)? > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Some(0.5 * (lo + hi))
}

/// Prints the dt study recorded in docs/history/benchmarks.md:
/// `cargo test -p squeal-core --test model -- --ignored --nocapture paper::dt_study`.
#[test]
#[ignore]
fn dt_study() {
    for scheme in [Scheme::Zoh, Scheme::Foh] {
        println!("scheme {scheme}");
        println!(
            "| dt | omega nu=1e-3 | r_ss nu=1e-3 | omega nu=1e-2 | r_u nu=1e-3 | r_u nu=1e-2 | r_u nu=1e-3 non-hyst | paper unconverged nu=1e-3 |"
        );
        println!("|---|---|---|---|---|---|---|---|");
        for dt in [0.04, 0.02, 0.01, 0.005, 0.0025, 0.00125, 0.000625] {
            let at = |law, nu, kind| stepper_with(law, nu, dt, kind, scheme);
            let light = at(FrictionLaw::McMillan, 1e-3, SolverKind::Robust);
            let heavy = at(FrictionLaw::McMillan, 1e-2, SolverKind::Robust);
            let nh = at(FrictionLaw::McMillanNonHysteretic, 1e-3, SolverKind::Robust);
            let (w1, r1) = mean_cycle(&light, run_to(&light, REST, 1000.0), 2000.0);
            let far = State { x: -2.5, v: 0.0 };
            let (w2, _) = mean_cycle(&heavy, run_to(&heavy, far, 1000.0), 2000.0);
            let ru1 = unstable_cycle(&light).unwrap_or(f64::NAN);
            let ru2 = unstable_cycle(&heavy).unwrap_or(f64::NAN);
            let ru3 = unstable_cycle(&nh).unwrap_or(f64::NAN);
            let paper = at(FrictionLaw::McMillan, 1e-3, SolverKind::Paper);
            let s = run_to(&paper, REST, 1000.0);
            let mut stats = SolverStats::default();
            advance(&paper, s, steps(&paper, 1000.0), &mut stats, |_, _, _| {});
            let share = stats.unconverged as f64 / stats.solves as f64;
            println!(
                "| {dt} | {w1:.4} | {r1:.4} | {w2:.4} | {ru1:.5} | {ru2:.5} | {ru3:.5} | {:.1}% |",
                100.0 * share
            );
        }
    }
}
