//! The Stribeck law with true stick: located events against closed forms,
//! convergence of event times, the energy of a stick phase, no chattering, bad input, counters.

use squeal_core::landscape::{Landscape, StickCycle, stick_slip_cycle};
use squeal_core::{Params, Reason, Run, Scheme, State, Stribeck};

use crate::common;
use common::{events, stepper};

/// Coulomb friction (mu_sd = 1, mu_v = 0: mu(s) = mu_d for every slip) with damping: the force
/// is constant on each side, so the scheme is exact and the located stick onset matches the
/// closed form of the damped oscillator to rounding, at any step. Closed form: while the block
/// outruns the belt (x' > v_d) the force is -mu_d, so y = x + mu_d obeys y'' + 2 xi y' + y = 0:
/// y = e^{-xi t} (y0 cos wt + (v0 + xi y0) sin(wt) / w), w = sqrt(1 - xi^2). The onset is the
/// first root of x'(t) = v_d (bisection on the closed form, below); the stick then lasts until
/// x + 2 xi v_d = mu_s: breakaway at t_on + (mu_s - 2 xi v_d - x_on) / v_d.
#[test]
fn coulomb_events_match_the_closed_form_at_any_step() {
    let (xi, v_d, mu_d) = (0.05, 1.5, 0.5);
    let s = Stribeck {
        mu_d,
        mu_sd: 1.0,
        v_0: 0.5,
        mu_v: 0.0,
    };
    let p = Params::stribeck(xi, v_d, s);
    common::coulomb_events_match_the_closed_form(p, mu_d, State { x: -0.3, v: 1.6 });
    // Equal static and kinetic friction with damping: the orbit from breakaway never reaches
    // the belt again (energy decays about the fixed point x* = mu_d): no stick-slip cycle.
    let st = stepper(p, 0.01, Scheme::Foh);
    assert_eq!(stick_slip_cycle(&st, 500.0, 1e-3), Some(StickCycle::Absent));
}

/// Coulomb with static and kinetic coefficients is the limit v_0 -> 0 (mu(s) -> mu_d for every
/// s > 0, mu(0) = mu_d mu_sd). Closed form at xi = 0 (independent of squeal): breakaway at
/// x = mu_s with x' = v_d; slip with force +mu_k about x = mu_k, a circle of radius
/// A = sqrt((mu_s - mu_k)^2 + v_d^2), back at x' = v_d after 2 pi - 2 alpha
/// (alpha = atan((mu_s - mu_k) / v_d)) at x = 2 mu_k - mu_s; stuck until x = mu_s again:
/// 2 (mu_s - mu_k) / v_d. The force jumps from mu_k to mu_s inside the step of each event
/// (the linear force of that step blurs it), so the durations are within a fraction of dt of
/// the closed form, depending on where the event falls in its step (measured: 6e-4 at
/// dt = 4e-3, 7e-4 at 2e-3, 3e-4 at 1e-3).
#[test]
fn coulomb_with_static_friction_is_the_small_v0_limit() {
    let (v_d, mu_k, mu_sd) = (1.5, 0.5, 2.0);
    let mu_s = mu_k * mu_sd;
    let s = Stribeck {
        mu_d: mu_k,
        mu_sd,
        v_0: 1e-12,
        mu_v: 0.0,
    };
    let p = Params::stribeck(0.0, v_d, s);
    let alpha = ((mu_s - mu_k) / v_d).atan();
    let slip = 2.0 * std::f64::consts::PI - 2.0 * alpha;
    let stick = 2.0 * (mu_s - mu_k) / v_d;
    let mut errs = Vec::new();
    for dt in [4e-3, 2e-3, 1e-3] {
        let st = stepper(p, dt, Scheme::Foh);
        let (on, off, rev) = events(&st, State { x: mu_s, v: v_d }, 4.0 * (slip + stick));
        assert_eq!(rev, 0);
        assert!(on.len() >= 3 && off.len() >= 3, "{on:?} {off:?}");
        // off[0] is at t = 0 (starts at breakaway); slip off[k] -> on[k], stick on[k] -> off[k+1].
        let e_slip = (on[1] - off[1] - slip).abs();
        let e_stick = (off[2] - on[1] - stick).abs();
        errs.push(e_slip.max(e_stick));
        assert!(
            e_slip < 0.5 * dt && e_stick < 0.5 * dt,
            "dt {dt}: {e_slip} {e_stick}"
        );
    }
    // And the error shrinks with dt overall.
    assert!(errs[2] < 0.5 * errs[0], "{errs:?}");
}

/// bSTAB's case (smooth mu): the first stick onset and breakaway from rest-ish converge as dt
/// shrinks, at second order (first-order hold), against a run at dt / 16.
#[test]
fn event_times_converge_at_second_order() {
    let p = Params::stribeck(0.05, 1.0, Stribeck::default());
    common::event_times_converge_at_second_order(p, State { x: -1.0, v: 0.5 }, 20.0);
}

/// During a stick phase x' = v_d exactly (kinetic energy constant to the bit) and the change of
/// the spring energy x^2/2 equals the work of friction and damping, int (F - 2 xi x') x' dt:
/// F is linear in time while stuck, so the trapezoid rule over the samples is exact.
#[test]
fn stick_phase_energy_balance_is_exact() {
    common::stick_phase_energy_balance_is_exact(Params::bstab(), State { x: -1.5, v: 1.8 }, 40.0);
}

/// On bSTAB's stick-slip cycle, exactly one stick phase per period: every stick ends with one
/// breakaway, no passage through zero slip, and the periods agree.
#[test]
fn one_stick_phase_per_period_no_chattering() {
    common::one_stick_phase_per_period(Params::bstab(), State { x: -1.5, v: 1.8 }, 5.0);
}

/// Labels: the fixed point repels at v_d = 0.8 (2 xi + mu'(v_d) = 0.1 - e^{-1.6} < 0), every
/// start sticks; at v_d = 2.225 the orbit from breakaway decays: no stick-slip.
#[test]
fn landscape_and_labels() {
    for (v_d, want) in [
        (0.8, Landscape::StickSlipOnly),
        (1.5, Landscape::Bistable),
        (2.225, Landscape::SteadySlipOnly),
    ] {
        let p = Params::stribeck(0.05, v_d, Stribeck::default());
        let o = common::landscape_and_start_label(p, want);
        assert!(o.stats.stick_onsets >= u64::from(o.reason == Reason::StickCycle));
    }
    // Fixed point x* = mu(v_d), as bSTAB's convention (-sgn(v - v_d) mu, v = 0 at rest).
    let p = Params::bstab();
    assert!((p.fixed_point().x - (0.5 + 0.5 * (-3.0f64).exp())).abs() < 1e-15);
}

/// Counters count events: the run's totals equal the per-step events.
#[test]
fn counters_count_events() {
    let st = stepper(Params::bstab(), 0.005, Scheme::Foh);
    let mut run = Run::new(&st, State { x: -1.5, v: 1.8 });
    let (mut on, mut off) = (0u64, 0u64);
    for _ in 0..run.steps_to(60.0) {
        let s = run.step();
        on += u64::from(s.events.onsets);
        off += u64::from(s.events.breakaways);
    }
    let s = run.stats();
    assert!(on >= 9 && off >= 9, "{on} {off}");
    assert_eq!((s.stick_onsets, s.breakaways), (on, off));
    assert!(s.event_iterations > 0 && s.sticks > 0 && s.failures == 0);
}

/// Bad input names the key.
#[test]
fn bad_input_names_the_key() {
    let base = Params::bstab();
    let s = base.law.stribeck().unwrap();
    let cases: Vec<(Params, &str)> = vec![
        (
            Params::stribeck(0.05, 1.5, Stribeck { mu_sd: 0.9, ..s }),
            "mu_sd",
        ),
        (
            Params::stribeck(0.05, 1.5, Stribeck { v_0: 0.0, ..s }),
            "v_0",
        ),
        (
            Params::stribeck(0.05, 1.5, Stribeck { v_0: -1.0, ..s }),
            "v_0",
        ),
        (Params::stribeck(-0.1, 1.5, s), "xi"),
        (Params::stribeck(f64::NAN, 1.5, s), "xi"),
        (Params::stribeck(0.05, 0.0, s), "v_d"),
        (
            Params::stribeck(
                0.05,
                1.5,
                Stribeck {
                    mu_d: f64::NAN,
                    ..s
                },
            ),
            "mu_d",
        ),
        (
            Params::stribeck(0.05, 1.5, Stribeck { mu_v: -1.0, ..s }),
            "mu_v",
        ),
    ];
    for (p, key) in cases {
        let e = p.validate().unwrap_err().to_string();
        assert!(e.contains(&format!("invalid {key} =")), "{key}: {e}");
    }
    // A Stribeck law without its parameters, or McMillan's with them, cannot be written:
    // each law's variant of `Friction` carries its own parameters and no other.
}
