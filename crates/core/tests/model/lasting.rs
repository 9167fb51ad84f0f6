//! A lasting oscillation that never crosses the section `x = x*, x' > 0`. At a
//! real brake's parameters (the README's disc-brake pad: m = 0.8 kg, k = 2e5 N/m, disc
//! 0.3 m/s, mu_k 0.38, mu_s 0.48, tau 0.5 ms, 1.5 kN clamp, c = 20 N s/m) the run from rest
//! swings for good around x ~ 0.6, below x* = 1, at about 3.5 times the natural frequency.

use squeal_core::section::{Miss, section_return};
use squeal_core::{
    Classifier, Friction, Params, Reason, Regime, SolverConfig, SolverStats, State, Stepper,
    Surface,
};

/// The README's disc brake at c = 20 N s/m: `--nu 0.025 --lambda 0.21053 --tau 0.65789
/// --phi 0.91353`, McMillan's hysteretic law, the default step 0.005.
fn brake() -> Stepper {
    let p = Params {
        law: Friction::McMillan(Surface {
            tau: 0.65789,
            phi: 0.91353,
        }),
        nu: 0.025,
        lambda: 0.21053,
    };
    Stepper::new(p, 0.005, SolverConfig::default()).unwrap()
}

/// From rest the classifier labels the brake's swing stick-slip by its turns (it never
/// crosses the section, so on 48d225a the run was `undecided`, `time_limit`, to any
/// t_max), with the swing's frequency (about 3.5, as an independent integration found:
/// 280 Hz against the natural 79.6 Hz) and its largest x' (above lambda: the slip reverses).
#[test]
fn the_brakes_swing_off_the_section_is_stick_slip() {
    let st = brake();
    let cl = Classifier {
        t_max: 500.0,
        ..Classifier::default()
    };
    let out = cl.classify(&st, State { x: 0.0, v: 0.0 });
    assert_eq!(
        (out.regime, out.reason, out.crossings),
        (Regime::StickSlip, Reason::LastingOscillation, 0),
        "{out:?}"
    );
    assert!((out.omega - 3.5).abs() < 0.2, "{out:?}");
    assert!(out.amplitude > st.params().lambda, "{out:?}");
    assert!(out.t_squeal == f64::INFINITY);
}

/// A return to the section from a start that falls into the swing stops at the swing, typed
/// as such, long before `t_return` (on 48d225a it ran the whole 200 time units and came
/// back as `None`, a time-out).
#[test]
fn a_return_into_the_brakes_swing_stops_there() {
    let st = brake();
    let mut stats = SolverStats::default();
    let ret = section_return(&st, 1.0, 200.0, &mut stats, |_| {});
    let Err(Miss::Lasting(l)) = ret else {
        panic!("{ret:?}")
    };
    assert!(l.misses_section() && l.t < 200.0, "{l:?}");
    assert!((l.omega - 3.5).abs() < 0.2, "{l:?}");
    assert!(l.x_range[1] < 1.0 && l.reversed, "{l:?}");
}
