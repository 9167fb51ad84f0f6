//! The tabulated law with true stick: `mu` against slip speed from a
//! table, interpolated monotonically (PCHIP), static limit the row at slip speed 0. Its stick
//! phases are located as the Stribeck law's are (the same `stick` machinery); tested against
//! a closed form (a constant table is Coulomb friction with static limit, exact at any step)
//! and against the Stribeck law tabulated finely (same labels on a map, same cycle to the
//! table's interpolation error). Each test fails on the code before the law (no `table` law
//! there: `Friction::Table` and `FrictionTable` did not exist).

use squeal_core::landscape::{Landscape, StickCycle, stick_slip_cycle};
use squeal_core::{
    Classifier, Friction, FrictionLaw, FrictionTable, Params, Scheme, State, Stribeck,
};

use crate::common;

/// The table law with damping `xi`, belt speed `v_d` and `table`.
fn tabulated(xi: f64, v_d: f64, table: &'static FrictionTable) -> Params {
    Params {
        law: Friction::Table(table),
        nu: xi,
        lambda: v_d,
    }
}

/// bSTAB's Stribeck law tabulated at 2001 rows, `s = 0, 0.01, ..., 20` (where its `mu` is
/// within `0.5 exp(-40)` of `mu_d`, far below rounding).
fn fine_stribeck() -> &'static FrictionTable {
    let s = Stribeck::default();
    FrictionTable::sampled(|v| s.mu(v).0, 20.0, 2001).unwrap()
}

/// A constant table `mu(s) = 0.4` (two rows) is Coulomb friction with static limit 0.4 on
/// both sides: the force is constant on each side, so the scheme is exact and the located
/// onset and breakaway match the damped oscillator's closed form to 1e-10 at any step
/// (`common::coulomb_events_match_the_closed_form`: while `x' > v_d`, `x + mu` is
/// `e^{-xi t} (y0 cos wt + ...)`; with `xi = 0` it is `mu + A cos(t + phi)` exactly).
#[test]
fn a_constant_table_is_coulomb_friction_exactly() {
    let t = FrictionTable::new(&[(0.0, 0.4), (3.0, 0.4)]).unwrap();
    let ic = State { x: -0.3, v: 0.7 };
    for xi in [0.0, 0.05] {
        common::coulomb_events_match_the_closed_form(tabulated(xi, 0.5, t), 0.4, ic);
    }
}

/// The fine table's `mu` is the Stribeck formula's to its interpolation error, measured
/// here on 20001 points of `[0, 25]`: `1.7e-7` (PCHIP at `h = 0.01` on `mu'''` up to
/// `mu_d (mu_sd - 1) / v_0^3 = 4`, largest near the ends), and `mu'` to `1.3e-4`; bounds
/// 2e-7 and 1.5e-4. The static limits are equal.
#[test]
fn the_fine_table_is_the_stribeck_law_to_its_interpolation_error() {
    let (s, t) = (Stribeck::default(), fine_stribeck());
    assert_eq!(t.mu_s(), s.mu_s());
    let (mut e0, mut e1) = (0.0f64, 0.0f64);
    for i in 0..=20000 {
        let v = i as f64 * 25.0 / 20000.0;
        let (a, b) = (t.mu(v), s.mu(v));
        e0 = e0.max((a.0 - b.0).abs());
        e1 = e1.max((a.1 - b.1).abs());
    }
    assert!(
        e0 < 2e-7 && e1 < 1.5e-4,
        "mu error {e0:e}, mu' error {e1:e}"
    );
}

/// bSTAB's case 1 (`xi = 0.05`, `v_d = 1.5`) with its Stribeck law and with that law
/// tabulated finely: every start of a 24 x 24 map of bSTAB's region (`x0` in `[-2, 2]`, `x'0`
/// in `[0, 2]`) gets the same label and reason, and the stick-slip cycle has the same period
/// and stuck time to `1e-6` (the interpolation error of `mu` is `1.7e-7`, above; measured
/// `dperiod = -5.0e-9`, `dstuck = -2.3e-8`).
#[test]
fn the_stribeck_law_tabulated_gives_the_same_labels_and_cycle() {
    let formula = Params::bstab();
    let table = tabulated(formula.nu, formula.lambda, fine_stribeck());
    let (sf, st) = (
        common::stepper(formula, 0.005, Scheme::Foh),
        common::stepper(table, 0.005, Scheme::Foh),
    );
    let c = Classifier::default();
    let mut squeals = 0;
    for i in 0..24 {
        for j in 0..24 {
            let ic = State {
                x: -2.0 + 4.0 * i as f64 / 23.0,
                v: 2.0 * j as f64 / 23.0,
            };
            let (a, b) = (c.classify(&sf, ic), c.classify(&st, ic));
            assert_eq!((a.regime, a.reason), (b.regime, b.reason), "{ic:?}");
            squeals += usize::from(a.regime == squeal_core::Regime::StickSlip);
        }
    }
    // Both labels occur: case 1 is bistable (bSTAB's basin stability of stick-slip there is
    // about 0.2).
    assert!(squeals > 0 && squeals < 576, "{squeals}");
    let cycle = |s| match stick_slip_cycle(s, 500.0, 1e-3) {
        Some(StickCycle::Exists { period, stuck }) => (period, stuck),
        other => panic!("{other:?}"),
    };
    let ((p1, s1), (p2, s2)) = (cycle(&sf), cycle(&st));
    assert!(
        (p1 - p2).abs() < 1e-6 && (s1 - s2).abs() < 1e-6,
        "period {p1} vs {p2}, stuck {s1} vs {s2}"
    );
}

/// The tabulated Stribeck law sticks as the formula does: one stick phase per period on its
/// cycle, no passage through zero slip (`common::one_stick_phase_per_period`), and the stick
/// phase's energy balance is exact, its event times converge at second order, and the
/// landscapes of `stribeck.rs` (`landscape_and_labels`) are the same: stick-slip only at
/// `v_d = 0.8`, steady slip only at `v_d = 2.225`.
#[test]
fn stick_phases_are_located_as_the_stribeck_laws() {
    let p = tabulated(0.05, 1.5, fine_stribeck());
    let ic = State { x: -1.0, v: 0.5 };
    common::one_stick_phase_per_period(p, ic, 1.0);
    common::stick_phase_energy_balance_is_exact(p, ic, 60.0);
    common::event_times_converge_at_second_order(p, ic, 40.0);
    for (v_d, want) in [
        (0.8, Landscape::StickSlipOnly),
        (2.225, Landscape::SteadySlipOnly),
    ] {
        common::landscape_and_start_label(Params { lambda: v_d, ..p }, want);
    }
}

/// A table with a hump (falls, rises, falls) never leaves its rows' range, so the force
/// bound is the largest row and the law has its name, title and keys.
#[test]
fn the_law_is_named_and_bounded() {
    let t = FrictionTable::new(&[(0.0, 0.5), (0.4, 0.3), (1.0, 0.45), (3.0, 0.35)]).unwrap();
    let p = tabulated(0.05, 0.5, t);
    assert_eq!(p.force_bound(), 0.5);
    assert!(p.validate().is_ok());
    let law: FrictionLaw = "table".parse().unwrap();
    assert_eq!(law, FrictionLaw::Table);
    assert_eq!(law.title(), "tabulated law with true stick");
    assert_eq!(law.keys(), ["xi", "v_d"]);
    assert_eq!(law.family(), squeal_core::LawFamily::TrueStick);
    // The wire form carries the rows and reads back to the same interned table.
    let json = serde_json::to_string(&p).unwrap();
    assert!(
        json.contains("\"friction_table\":[[0.0,0.5],[0.4,0.3]"),
        "{json}"
    );
    let back: Params = serde_json::from_str(&json).unwrap();
    assert_eq!(back, p);
    assert!(std::ptr::eq(back.law.table().unwrap(), t));
    // Without its table the law is refused naming the key.
    let e = serde_json::from_str::<Params>(r#"{"law":"table","xi":0.05,"v_d":0.5}"#)
        .unwrap_err()
        .to_string();
    assert!(e.contains("friction_table"), "{e}");
    // xi and v_d are checked under their names.
    let e = tabulated(-1.0, 0.5, t).validate().unwrap_err();
    assert_eq!(e.key(), Some("xi"));
}
