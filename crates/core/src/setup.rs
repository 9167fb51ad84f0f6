//! One integration setting: the law with its parameters, the step, and the scheme and
//! solver (the scheme lives in [`SolverConfig`]). Everything that integrates takes one
//! [`Setup`] rather than the three values apart, and asks it for its [`Stepper`] and for
//! the same setting at half the step (the accuracy check of every figure).

use serde::{Deserialize, Serialize};

use crate::error::CoreError;
use crate::params::Params;
use crate::solver::SolverConfig;
use crate::stepper::Stepper;

/// The law and its parameters, the step `dt`, and the scheme and solver.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Setup {
    /// The law and its parameters.
    pub params: Params,
    /// Time step (nondimensional).
    pub dt: f64,
    /// Scheme and solver of the implicit force equation.
    pub solver: SolverConfig,
}

impl Setup {
    /// The setting of `params` with step `dt` and `solver`.
    pub fn new(params: Params, dt: f64, solver: SolverConfig) -> Setup {
        Setup { params, dt, solver }
    }

    /// Its stepper (validates the parameters and the step).
    pub fn stepper(&self) -> Result<Stepper, CoreError> {
        Stepper::new(self.params, self.dt, self.solver)
    }

    /// The same setting with `dt / 2`.
    pub fn half_dt(&self) -> Setup {
        Setup {
            dt: self.dt / 2.0,
            ..*self
        }
    }

    /// The same step and solver with other parameters.
    pub fn with_params(&self, params: Params) -> Setup {
        Setup { params, ..*self }
    }
}

impl Stepper {
    /// The setting this stepper was made from.
    pub fn setup(&self) -> Setup {
        Setup::new(*self.params(), self.dt(), *self.solver())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::FrictionLaw;

    #[test]
    fn half_dt_halves_the_step_only() {
        let s = Setup::new(
            Params::paper(FrictionLaw::McMillan, 1e-3),
            0.005,
            SolverConfig::default(),
        );
        let h = s.half_dt();
        assert_eq!(h.dt, 0.0025);
        assert_eq!((h.params, h.solver), (s.params, s.solver));
        assert_eq!(s.stepper().unwrap().setup(), s);
    }
}
