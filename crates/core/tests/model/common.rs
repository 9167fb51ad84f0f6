//! Helpers shared by the tests of the laws with true stick (`stribeck.rs`, `cubic.rs`).

use squeal_core::landscape::{Landscape, StickCycle, landscape, stick_slip_cycle};
use squeal_core::{
    Classifier, Outcome, Params, Reason, Regime, Run, Scheme, SolverConfig, State, Stepper,
};

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

/// The located onset and breakaway of a law that is Coulomb friction with limit `mu` on both
/// sides (its force constant on each side, so the scheme is exact) against the closed form of
/// the damped oscillator, to 1e-10 at any step and with either scheme. While the block outruns
/// the belt (`x' > v_d`) the force is `-mu`, so `y = x + mu` obeys `y'' + 2 xi y' + y = 0`:
/// `y = e^{-xi t} (y0 cos wt + (v0 + xi y0) sin(wt) / w)`, `w = sqrt(1 - xi^2)`. The onset is
/// the first root of `x'(t) = v_d` (bisection on the closed form); the stick then lasts until
/// `x + 2 xi v_d = mu`: breakaway at `t_on + (mu - 2 xi v_d - x_on) / v_d`.
pub fn coulomb_events_match_the_closed_form(p: Params, mu: f64, ic: State) {
    let (xi, v_d) = (p.nu, p.lambda);
    let (x0, v0) = (ic.x, ic.v);
    let w = (1.0 - xi * xi).sqrt();
    let y0 = x0 + mu;
    let xv = |t: f64| {
        let e = (-xi * t).exp();
        let (sn, cs) = (w * t).sin_cos();
        let y = e * (y0 * cs + (v0 + xi * y0) * sn / w);
        let v = e * (v0 * cs - (xi * v0 + y0) * sn / w);
        (y - mu, v)
    };
    // x'(0) - v_d > 0; find the first sign change on a fine scan, then bisect.
    let mut lo = 0.0;
    while xv(lo + 1e-3).1 > v_d {
        lo += 1e-3;
    }
    let mut hi = lo + 1e-3;
    for _ in 0..100 {
        let m = 0.5 * (lo + hi);
        if xv(m).1 > v_d {
            lo = m;
        } else {
            hi = m;
        }
    }
    let t_on = 0.5 * (lo + hi);
    let x_on = xv(t_on).0;
    assert!((x_on + 2.0 * xi * v_d).abs() <= mu, "sticks: {x_on}");
    let t_off = t_on + (mu - 2.0 * xi * v_d - x_on) / v_d;
    for dt in [0.1, 0.01, 0.003] {
        for scheme in [Scheme::Foh, Scheme::Zoh] {
            let st = stepper(p, dt, scheme);
            let (on, off, rev) = events(&st, ic, t_off + 1.0);
            assert_eq!((on.len(), off.len(), rev), (1, 1, 0), "dt {dt}");
            assert!(
                (on[0] - t_on).abs() < 1e-10 && (off[0] - t_off).abs() < 1e-10,
                "dt {dt} {scheme}: onset {} vs {t_on}, breakaway {} vs {t_off}",
                on[0],
                off[0]
            );
        }
    }
}

/// The first two onsets and the first breakaway of a run from `ic` converge at second order
/// as dt halves from 0.04 (first-order hold), against a run at dt = 0.02 / 32.
pub fn event_times_converge_at_second_order(p: Params, ic: State, t_end: f64) {
    let reference = events(&stepper(p, 0.02 / 32.0, Scheme::Foh), ic, t_end);
    let mut errs = Vec::new();
    for dt in [0.04, 0.02, 0.01] {
        let (on, off, _) = events(&stepper(p, dt, Scheme::Foh), ic, t_end);
        let e = (on[0] - reference.0[0])
            .abs()
            .max((off[0] - reference.1[0]).abs())
            .max((on[1] - reference.0[1]).abs());
        errs.push(e);
    }
    let orders: Vec<f64> = errs.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
    eprintln!("event-time errors {errs:?}, orders {orders:?}");
    assert!(
        orders.iter().all(|&o| o > 1.7),
        "errors {errs:?}, orders {orders:?}"
    );
}

/// While stuck `x' = v_d` exactly (kinetic energy constant to the bit), the acceleration is 0,
/// and the change of the spring energy `x^2 / 2` equals the work of friction and damping,
/// `int (F - 2 xi x') x' dt`: `F` is linear in time while stuck, so the trapezoid rule over
/// the samples is exact (to 1e-13). More than 50 stuck steps of a run from `ic` to `t_end`.
pub fn stick_phase_energy_balance_is_exact(p: Params, ic: State, t_end: f64) {
    let st = stepper(p, 0.01, Scheme::Foh);
    let mut run = Run::new(&st, ic);
    let mut stuck_steps = 0;
    let mut worst = 0.0f64;
    for _ in 0..run.steps_to(t_end) {
        let s = run.step();
        let (a, b) = (s.prev, s.next);
        if a.v == p.lambda && b.v == p.lambda && s.events.stuck && s.events.breakaways == 0 {
            stuck_steps += 1;
            let d_spring = 0.5 * (b.x * b.x - a.x * a.x);
            let pa = (a.force - 2.0 * p.nu * a.v) * a.v;
            let pb = (b.force - 2.0 * p.nu * b.v) * b.v;
            let work = 0.5 * (pa + pb) * (b.t - a.t);
            worst = worst.max((d_spring - work).abs());
            assert_eq!(b.a, 0.0);
        }
    }
    assert!(stuck_steps > 50, "{stuck_steps}");
    assert!(worst < 1e-13, "{worst}");
}

/// On the stick-slip cycle of `p` (period above `min_period`), exactly one stick phase per
/// period over 20 periods from `ic`: every stick ends with one breakaway, no passage through
/// zero slip, and the periods agree with the cycle's to 1e-6. The first onset ends the
/// transient from the start; from the second on the run is on the cycle (every breakaway
/// starts from the same state).
pub fn one_stick_phase_per_period(p: Params, ic: State, min_period: f64) {
    let st = stepper(p, 0.005, Scheme::Foh);
    let Some(StickCycle::Exists { period, stuck }) = stick_slip_cycle(&st, 500.0, 1e-3) else {
        panic!("{p:?} has a stick-slip cycle");
    };
    assert!(stuck > 0.1 && period > min_period, "{period} {stuck}");
    let (on, off, rev) = events(&st, ic, 20.0 * period);
    assert_eq!(rev, 0);
    let n = on.len().min(off.len());
    assert!(n >= 19, "{n}");
    for k in 2..n {
        let per = on[k] - on[k - 1];
        assert!((per - period).abs() < 1e-6, "period {per} vs {period}");
        assert!(
            on[k - 1] < off[k - 1] && off[k - 1] < on[k],
            "{on:?} {off:?}"
        );
    }
}

/// Where `p`'s landscape is `want`, a start 1e-4 to the right of the fixed point is
/// labelled as the landscape says: stick-slip onto the cycle where the fixed point repels
/// (`StickSlipOnly`), steady slip near the fixed point otherwise. Returns the outcome.
pub fn landscape_and_start_label(p: Params, want: Landscape) -> Outcome {
    let st = stepper(p, 0.005, Scheme::Foh);
    assert_eq!(landscape(&st, 2000.0, 1e-3), Some(want), "v_d {}", p.lambda);
    let fp = p.fixed_point();
    // A start right next to the fixed point: leaves it where it repels.
    let o = Classifier::default().classify(
        &st,
        State {
            x: fp.x + 1e-4,
            v: 0.0,
        },
    );
    let expect = if want == Landscape::StickSlipOnly {
        (Regime::StickSlip, Reason::StickCycle)
    } else {
        (Regime::SteadySlip, Reason::NearFixedPoint)
    };
    assert_eq!((o.regime, o.reason), expect, "v_d {}: {o:?}", p.lambda);
    o
}
