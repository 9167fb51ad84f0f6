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
//! * [`Params`] and [`FrictionLaw`]: the model (paper eq. 4.1, 5.1, Coulomb, and a
//!   Stribeck law with true stick, [`Stribeck`]).
//! * [`stick`]: true stick with located onset and breakaway events (laws with a static
//!   limit), the stick-slip cycle's existence and the [`Landscape`] of a parameter point.
//! * [`friction`]: the laws with their derivatives, and the dimensional law (eqs. 3.2-3.4).
//! * [`Propagator`]: the exact linear step with the force constant (eqs. 4.3-4.6) or linear
//!   over the step ([`Scheme`]).
//! * [`solver`]: the implicit force equation, solved by the paper's iteration or robustly.
//! * [`Stepper`]: one step, [`Sample`] the state with acceleration and force; [`Run`]: the one
//!   loop that advances a run, yielding [`Step`]s to its observers.
//! * [`classify`]: one initial condition to a [`Regime`] with diagnostics.
//! * [`turns`]: the turning points of a run and the [`Lasting`] oscillation they show,
//!   wherever it lies in the plane (the section's rules see only those around `x*`).
//! * [`region`]: a certified region of attraction of the fixed point ([`Region`]).
//! * [`witness`]: certified fates of stretches of the section from a few followed starts
//!   (laws of the slip velocity only: the return map is monotone).
//! * [`validated`]: where the labels have been checked against long runs, and the warning
//!   for parameters outside that region ([`Validity`]).
//! * [`units`]: the paper's scaling between a [`Physical`] system and [`Params`].
//! * [`model`]: the model itself, in words and equations: units, the laws with the paper's
//!   two misprints corrected, the schemes, the conventions and the labels
//!   (`crates/core/MODEL.md`).
//!
//! ```
//! use squeal_core::{Classifier, FrictionLaw, Params, Regime, Run, SolverConfig, State, Stepper};
//! let stepper = Stepper::new(Params::paper(FrictionLaw::McMillan, 1e-3), 0.01,
//!                            SolverConfig::default()).unwrap();
//! let mut run = Run::new(&stepper, State { x: 0.0, v: 0.0 });
//! let end = run.by_ref().take(1000).last().unwrap().next;
//! assert!(run.stats().failures == 0 && end.t == 10.0);
//! let out = Classifier::default().classify(&stepper, State { x: 0.0, v: 0.0 });
//! assert_eq!(out.regime, Regime::StickSlip); // Fig. 9: from rest the block squeals
//! ```

pub mod atan;
pub mod classify;
pub mod defaults;
pub mod error;
pub mod friction;
pub mod landscape;
pub mod law;
#[doc = include_str!("../MODEL.md")]
pub mod model {}
pub mod orbit;
pub mod params;
pub mod propagator;
pub mod region;
pub mod run;
pub mod section;
pub mod setup;
pub mod solver;
pub mod state;
pub mod steady;
pub mod stepper;
pub mod stick;
pub mod table;
pub mod turns;
pub mod units;
pub mod validated;
pub mod verdict;
pub mod witness;

pub use classify::{
    Classifier, Outcome, Reason, Regime, Shortcuts, Squeal, T_SQUEAL_UNKNOWN, Trap,
};
pub use error::CoreError;
pub use friction::Law;
pub use landscape::{Landscape, LandscapeEvidence, StickCycle};
// Every law's parameters, by a glob: a new law's struct needs no line here.
pub use law::*;
pub use params::{Named, Params};
pub use propagator::{Propagator, Scheme};
pub use region::Region;
pub use run::{Run, Samples, Step};
pub use setup::Setup;
pub use solver::{SolverConfig, SolverKind, SolverStats};
pub use steady::{Stability, SteadySlip};
pub use stepper::{Sample, State, Stepper};
pub use stick::StickEvents;
pub use table::FrictionTable;
pub use turns::{Lasting, Turn, TurnSettings, TurnWatch};
pub use units::{FrictionSi, Load, Physical, Scales, SurfaceSi};
pub use validated::Validity;
