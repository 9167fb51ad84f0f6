//! Defaults of the model and the integration, defined once (specs, flags and constructors
//! all read them from here).

/// Table 1 of the paper: belt speed `lambda = 3`.
pub const LAMBDA: f64 = 3.0;
/// Table 1 of the paper: `tau' = 0.1 sqrt(10)`.
pub const TAU: f64 = 0.316_227_766_016_837_94;
/// Table 1 of the paper: `Phi = 1`.
pub const PHI: f64 = 1.0;
/// Damping ratio used where none is given (the paper's Fig. 9).
pub const NU: f64 = 1e-3;
/// Time step, chosen by accuracy for the default scheme (first-order hold): the unstable
/// cycle's section crossing and distance along +x (nu = 1e-3, 1e-2), the stick-slip frequency
/// (nu = 1e-3) and the critical damping for (0, 0) are within 0.1% of their dt -> 0 limits
/// (at dt = 0.01 the stick-slip frequency is 0.22% off; the cycle figures would allow it).
/// BENCHMARKS.md, "Step size", gives the study; `crates/scan/tests/scanning/accuracy.rs` checks it.
pub const DT: f64 = 0.005;
/// Relative half-width of the band around the located unstable cycle in which early
/// stopping leaves runs going (`r_u (1 -+ TRAP_MARGIN)` at the section). It only has to
/// cover the error of the cycle's location as the classifier sees it: the bisection bracket
/// (relative `1e-10`) and the crossing interpolation (cubic Hermite, `O(dt^4)`, below
/// `1e-11` at the default step), so `1e-5` leaves five orders to spare. Larger margins
/// give the same labels and cost more: a start at distance `d` inside the band takes
/// `ln(margin / d) / ln(m)` revolutions to leave it (Floquet multiplier `m` = 1.0064 at
/// nu = 1e-3). BENCHMARKS.md, "Early stopping", compares 1e-3, 1e-4, 1e-5 and 1e-6.
pub const TRAP_MARGIN: f64 = 1e-5;
/// Classifier time limit.
pub const T_MAX: f64 = 5000.0;
/// Iteration cap of the paper's fixed-point solver.
pub const MAX_ITER: u32 = 100;

/// bSTAB's friction case (Stender et al., Nonlinear Dynamics 2021): damping ratio `xi`.
pub const XI: f64 = 0.05;
/// bSTAB's friction case: belt speed `v_d`.
pub const V_D: f64 = 1.5;
/// bSTAB's friction case: dynamic friction coefficient `mu_d`.
pub const MU_D: f64 = 0.5;
/// bSTAB's friction case: static-to-dynamic ratio `mu_sd`.
pub const MU_SD: f64 = 2.0;
/// bSTAB's friction case: Stribeck reference velocity `v_0`.
pub const V_0: f64 = 0.5;
/// bSTAB's friction case: viscous strengthening `mu_v`.
pub const MU_V: f64 = 0.0;

// The cubic law mu(s) = mu_0 - a1 s + a3 s^3 at the shape used by Thomsen (J. Sound Vib.
// 228(5), 1999) and Thomsen and Fidlin (Int. J. Non-Linear Mech. 38, 2003): static
// coefficient 0.4, least coefficient mu_m = 0.25 at slip speed v_m = 0.5, so
// a1 = (3/2) (0.4 - mu_m) / v_m = 0.45 and a3 = (1/2) (0.4 - mu_m) / v_m^3 = 0.6, with
// damping ratio 0.05. (As recalled from those papers; not re-read here.) The belt speed 0.3
// lies on the falling part of mu (below its minimum at 0.5), where the fixed point repels
// (2 xi + mu'(0.3) = -0.188) and every start squeals. No belt speed of this shape was found
// where steady slip and stick-slip coexist: the landscape turns from stick-slip only to
// steady slip only at the fixed point's loss of stability, v_d = 0.441 (scanned on a grid
// of 0.0005; `crates/core/tests/model/cubic.rs`, `landscape_and_labels`).
/// The cubic law: damping ratio `xi`.
pub const CUBIC_XI: f64 = 0.05;
/// The cubic law: belt speed `v_d` (on the falling part of `mu`).
pub const CUBIC_V_D: f64 = 0.3;
/// The cubic law: static limit `mu_0 = mu(0)`.
pub const CUBIC_MU_0: f64 = 0.4;
/// The cubic law: linear coefficient `a1`.
pub const CUBIC_A1: f64 = 0.45;
/// The cubic law: cubic coefficient `a3`.
pub const CUBIC_A3: f64 = 0.6;

/// The table law: damping ratio `xi` (bSTAB's, [`XI`]).
pub const TABLE_XI: f64 = XI;
/// The table law: belt speed `v_d` (bSTAB's, [`V_D`]).
pub const TABLE_V_D: f64 = V_D;

/// The table law's default table: bSTAB's Stribeck law (`mu_d = 0.5`, `mu_sd = 2`,
/// `v_0 = 0.5`, `mu_v = 0`) sampled at 201 rows, slip speeds `0, 0.05, ..., 10` (where its
/// `mu` is within `0.5 exp(-20) = 1e-9` of `mu_d`). A run names its table by
/// `friction_table` or `friction_csv`; this one is what help lines and defaults show.
pub fn table() -> &'static crate::FrictionTable {
    static T: std::sync::OnceLock<&'static crate::FrictionTable> = std::sync::OnceLock::new();
    T.get_or_init(|| {
        let s = crate::Stribeck::default();
        crate::FrictionTable::sampled(|v| s.mu(v).0, 10.0, 201).expect("a valid table")
    })
}
