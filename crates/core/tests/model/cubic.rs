//! The cubic law with true stick: `mu(s) = mu_0 - a1 s + a3 s^3` (Popp
//! and Stelter; Thomsen 1999). Its stick phases and events are tested as the Stribeck law's
//! are (`stribeck.rs`): located events against a closed form, convergence order of event
//! times, the energy of a stick phase, one stick per period, the landscape, bad input.

use squeal_core::landscape::Landscape;
use squeal_core::{Cubic, Friction, FrictionLaw, Params, State};

use crate::common;

/// The cubic law with damping `xi`, belt speed `v_d` and coefficients `(mu_0, a1, a3)`.
fn cubic(xi: f64, v_d: f64, mu_0: f64, a1: f64, a3: f64) -> Params {
    Params {
        law: Friction::Cubic(Cubic { mu_0, a1, a3 }),
        nu: xi,
        lambda: v_d,
    }
}

/// With `a1 = a3 = 0` the law is Coulomb friction with `mu = mu_0` on both sides, so the
/// scheme is exact and the located onset and breakaway match the closed form of the damped
/// oscillator to rounding at any step (the same closed form as the Stribeck law's Coulomb
/// case): while `x' > v_d` the force is `-mu_0`, `y = x + mu_0` obeys `y'' + 2 xi y' + y = 0`,
/// `y = e^{-xi t} (y0 cos wt + (v0 + xi y0) sin(wt) / w)`, `w = sqrt(1 - xi^2)`; the onset is
/// the first root of `x'(t) = v_d`, the breakaway `(mu_0 - 2 xi v_d - x_on) / v_d` later.
#[test]
fn coulomb_limit_events_match_the_closed_form_at_any_step() {
    let mu_0 = 0.4;
    let ic = State { x: -0.3, v: 0.7 };
    common::coulomb_events_match_the_closed_form(cubic(0.05, 0.5, mu_0, 0.0, 0.0), mu_0, ic);
}

/// Thomsen's shape (the defaults, v_d = 0.3): the first two stick onsets and the first breakaway
/// converge at second order as dt halves (first-order hold), against a run at dt / 64.
#[test]
fn event_times_converge_at_second_order() {
    let ic = State { x: -0.5, v: 0.3 };
    common::event_times_converge_at_second_order(Params::defaults(FrictionLaw::Cubic), ic, 40.0);
}

/// While stuck `x' = v_d` exactly (kinetic energy constant to the bit), the acceleration is 0,
/// and the change of the spring energy `x^2 / 2` equals the work of friction and damping,
/// `int (F - 2 xi x') x' dt`: `F` is linear in time while stuck, so the trapezoid rule over
/// the samples is exact (to rounding).
#[test]
fn stick_phase_energy_balance_is_exact() {
    let ic = State { x: -0.5, v: 0.3 };
    common::stick_phase_energy_balance_is_exact(Params::defaults(FrictionLaw::Cubic), ic, 60.0);
}

/// On the defaults' stick-slip cycle, exactly one stick phase per period: every stick ends
/// with one breakaway at the breakaway state, no passage through zero slip, equal periods.
#[test]
fn one_stick_phase_per_period_no_chattering() {
    let ic = State { x: -0.5, v: 0.3 };
    common::one_stick_phase_per_period(Params::defaults(FrictionLaw::Cubic), ic, 1.0);
}

/// The landscape and the labels next to the fixed point. The fixed point's damping is
/// `2 xi + mu'(v_d) = 0.1 - 0.45 + 1.8 v_d^2` (Thomsen's shape), negative below
/// `v_d = sqrt(0.35 / 1.8) = 0.441`: at the defaults' `v_d = 0.3` it repels (`-0.188`) and
/// every start sticks; at `v_d = 0.5` (`mu' = 0`, damped by `2 xi` alone) and at `v_d = 1.2`
/// (`mu'(1.2) = 2.142`) it attracts and the orbit from breakaway decays: no stick-slip cycle.
/// (This shape has no bistable belt speed: a grid of 0.0005 from 0.441 to 0.45 found none.)
#[test]
fn landscape_and_labels() {
    let d = Params::defaults(FrictionLaw::Cubic);
    for (v_d, want) in [
        (0.3, Landscape::StickSlipOnly),
        (0.5, Landscape::SteadySlipOnly),
        (1.2, Landscape::SteadySlipOnly),
    ] {
        common::landscape_and_start_label(Params { lambda: v_d, ..d }, want);
    }
    // Fixed point x* = mu(v_d) = 0.4 - 0.45 * 0.5 + 0.6 * 0.125 = 0.25 at v_d = 0.5 (the
    // least mu), damped by 2 xi = 0.1 there.
    let p = Params { lambda: 0.5, ..d };
    assert!((p.fixed_point().x - 0.25).abs() < 1e-15);
    assert!((p.fixed_point_damping().unwrap() - 0.1).abs() < 1e-15);
}

/// `mu` stays positive exactly when its least value `mu_0 - (2 a1 / 3) sqrt(a1 / (3 a3))` is:
/// the closed form against a scan of `mu` over slip speeds, and parameters that let `mu`
/// reach zero are refused naming `a1`; every other bad value names its key.
#[test]
fn bad_input_names_the_key() {
    let c = Cubic::default();
    // Thomsen's shape: least mu 0.25 at s = 0.5 (closed form), and no smaller value on a grid.
    assert!((c.least() - 0.25).abs() < 1e-15);
    let scanned = (0..=4000)
        .map(|i| c.mu(i as f64 * 1e-3).0)
        .fold(f64::INFINITY, f64::min);
    assert!(scanned >= c.least() - 1e-15 && scanned - c.least() < 1e-6);
    let cases = [
        (cubic(0.05, 0.5, 0.0, 0.45, 0.6), "mu_0"),
        (cubic(0.05, 0.5, f64::NAN, 0.45, 0.6), "mu_0"),
        (cubic(0.05, 0.5, 0.4, -0.1, 0.6), "a1"),
        (cubic(0.05, 0.5, 0.4, 0.45, -1.0), "a3"),
        (cubic(0.05, 0.5, 0.4, 0.45, f64::INFINITY), "a3"),
        // a3 = 0 < a1: mu falls for ever.
        (cubic(0.05, 0.5, 0.4, 0.45, 0.0), "a1"),
        // a3 = 0.05: least mu = 0.4 - 0.3 sqrt(3) = -0.12 < 0.
        (cubic(0.05, 0.5, 0.4, 0.45, 0.05), "a1"),
        (cubic(-0.1, 0.5, 0.4, 0.45, 0.6), "xi"),
        (cubic(0.05, 0.0, 0.4, 0.45, 0.6), "v_d"),
    ];
    for (p, key) in cases {
        let e = p.validate().unwrap_err().to_string();
        assert!(e.contains(&format!("invalid {key} =")), "{key}: {e}");
    }
    // a3 = 0.1: least mu = 0.4 - 0.3 sqrt(1.5) = 0.0326 > 0, accepted; a1 = 0 with a3 = 0
    // (Coulomb) too.
    assert!(cubic(0.05, 0.5, 0.4, 0.45, 0.1).validate().is_ok());
    assert!(cubic(0.05, 0.5, 0.4, 0.0, 0.0).validate().is_ok());
    assert!(
        cubic(0.05, 0.5, 0.4, 0.45, 0.05)
            .validate()
            .unwrap_err()
            .to_string()
            .contains("positive")
    );
}
