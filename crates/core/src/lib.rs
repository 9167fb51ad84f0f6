//! # squeal-core: the numerics of McMillan's friction oscillator
//!
//! A block on a belt moving at speed `lambda`, tied to a wall by a spring and a dashpot and
//! driven by friction that depends on the slip velocity and the acceleration (McMillan, J.
//! Sound Vib. 205(3), 1997). Nondimensional equation of motion (paper Section 4):
//!
//! ```text
//! x'' + 2 nu x' + x = F(x' - lambda, x'')
//! ```
//!
//! * [`Params`] and [`FrictionLaw`]: the model (paper eq. 4.1, 5.1, Coulomb).
//! * [`friction`]: the laws with their derivatives, and the dimensional law (eqs. 3.2-3.4).
//! * [`Propagator`]: the exact linear step with constant force (eqs. 4.3-4.6).
//! * [`solver`]: the implicit force equation, solved by the paper's iteration or robustly.
//! * [`Stepper`]: one step of a run, [`Sample`] the state with acceleration and force.
//! * [`classify`]: one initial condition to a [`Regime`] with diagnostics.
//! * [`units`]: the paper's scaling between a [`Physical`] system and [`Params`].
//! * [`model`]: the model itself, in words and equations: units, the laws with the paper's
//!   two misprints corrected, the schemes, the conventions and the labels
//!   (`crates/core/MODEL.md`).
//!
//! ```
//! use squeal_core::{FrictionLaw, Params, SolverConfig, State, Stepper, SolverStats};
//! let stepper = Stepper::new(Params::paper(FrictionLaw::McMillan, 1e-3), 0.01,
//!                            SolverConfig::default()).unwrap();
//! let mut stats = SolverStats::default();
//! let (mut s, _) = stepper.initial(State { x: 0.0, v: 0.0 }, &mut stats);
//! for _ in 0..1000 { s = stepper.step(&s, &mut stats).0; }
//! assert!(stats.failures == 0 && s.t > 9.99);
//! ```

pub mod classify;
pub mod defaults;
pub mod error;
pub mod friction;
#[doc = include_str!("../MODEL.md")]
pub mod model {}
pub mod params;
pub mod propagator;
pub mod solver;
pub mod stepper;
pub mod units;

pub use classify::{Classifier, Outcome, Reason, Regime, Trap};
pub use error::CoreError;
pub use params::{FrictionLaw, Params};
pub use propagator::Propagator;
pub use solver::{SolverConfig, SolverKind, SolverStats};
pub use stepper::{Sample, State, Stepper};
pub use units::{Physical, Scales};
