//! Defaults of McMillan's model (the paper's Table 1) and of the integration, defined once
//! (specs, flags and constructors all read them from here). The defaults of a law with
//! parameters of its own live with those parameters, each beside its source
//! ([`crate::Stribeck`], [`crate::Cubic`], [`crate::FrictionTable::default_table`]).

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
/// docs/history/benchmarks.md, "Step size", gives the study;
/// `crates/scan/tests/scanning/accuracy.rs` checks it.
pub const DT: f64 = 0.005;
/// Relative half-width of the band around the located unstable cycle in which early
/// stopping leaves runs going (`r_u (1 -+ TRAP_MARGIN)` at the section). It only has to
/// cover the error of the cycle's location as the classifier sees it: the bisection bracket
/// (relative `1e-10`) and the crossing interpolation (cubic Hermite, `O(dt^4)`, below
/// `1e-11` at the default step), so `1e-5` leaves five orders to spare. Larger margins
/// give the same labels and cost more: a start at distance `d` inside the band takes
/// `ln(margin / d) / ln(m)` revolutions to leave it (Floquet multiplier `m` = 1.0064 at
/// nu = 1e-3). docs/history/benchmarks.md, "Early stopping", compares 1e-3, 1e-4, 1e-5 and 1e-6.
pub const TRAP_MARGIN: f64 = 1e-5;
/// Classifier time limit.
pub const T_MAX: f64 = 5000.0;
/// Iteration cap of the paper's fixed-point solver.
pub const MAX_ITER: u32 = 100;
