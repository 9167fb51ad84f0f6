//! One run of the oscillator: the exact step with the implicit force (paper eqs. 4.3-4.6).

use serde::Serialize;

use crate::error::CoreError;
use crate::friction;
use crate::params::Params;
use crate::propagator::Propagator;
use crate::solver::{self, ForceEquation, Solution, SolverConfig, SolverStats};

/// A point of the phase plane: displacement `x` and velocity `x'` (nondimensional).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct State {
    /// Displacement `x`.
    pub x: f64,
    /// Velocity `x'` (the block's, not the slip velocity).
    pub v: f64,
}

/// The full state of a run at one instant.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Sample {
    /// Time.
    pub t: f64,
    /// Displacement.
    pub x: f64,
    /// Velocity `x'`.
    pub v: f64,
    /// Acceleration `x''`.
    pub a: f64,
    /// Friction force `F`.
    pub force: f64,
}

impl Sample {
    /// The phase-plane point.
    pub fn state(&self) -> State {
        State {
            x: self.x,
            v: self.v,
        }
    }
}

/// Integrates one run with a fixed step.
#[derive(Clone, Copy, Debug)]
pub struct Stepper {
    params: Params,
    prop: Propagator,
    solver: SolverConfig,
}

impl Stepper {
    /// Validates the parameters and the step `dt` and precomputes the step matrix.
    pub fn new(params: Params, dt: f64, solver: SolverConfig) -> Result<Stepper, CoreError> {
        params.validate()?;
        if !dt.is_finite() || dt <= 0.0 || dt > 1.0 {
            return Err(CoreError::InvalidParameter {
                name: "dt",
                value: dt,
                expected: "a finite step in (0, 1] (the oscillator's period is about 6.3)",
            });
        }
        if solver.kind == solver::SolverKind::Paper && solver.max_iter == 0 {
            return Err(CoreError::InvalidParameter {
                name: "max_iter",
                value: 0.0,
                expected: "an iteration cap >= 1",
            });
        }
        Ok(Stepper {
            params,
            prop: Propagator::new(params.nu, dt)?,
            solver,
        })
    }

    /// The model parameters.
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// The step length.
    pub fn dt(&self) -> f64 {
        self.prop.h
    }

    /// The solver settings.
    pub fn solver(&self) -> &SolverConfig {
        &self.solver
    }

    /// The initial force and acceleration at `(x0, v0)`: `a = F(v0 - lambda, a) - 2 nu v0 - x0`,
    /// solved from the first guess `x''(0) = 0` as in the paper.
    pub fn initial(&self, s: State, stats: &mut SolverStats) -> (Sample, Solution) {
        let p = &self.params;
        let eq = ForceEquation {
            pv: s.v - p.lambda,
            qv: 0.0,
            pa: -2.0 * p.nu * s.v - s.x,
            qa: 1.0,
        };
        let guess = friction::force(p, s.v - p.lambda, 0.0).force;
        let sol = solver::solve(p, &self.solver, &eq, guess, stats);
        let a = eq.pa + eq.qa * sol.force;
        (
            Sample {
                t: 0.0,
                x: s.x,
                v: s.v,
                a,
                force: sol.force,
            },
            sol,
        )
    }

    /// One step of length `dt`: the force held constant over the step is the force at its end.
    #[inline]
    pub fn step(&self, s: &Sample, stats: &mut SolverStats) -> (Sample, Solution) {
        let p = &self.params;
        let c = &self.prop;
        let x_free = c.c11 * s.x + c.c12 * s.v;
        let v_free = c.c21 * s.x + c.c22 * s.v;
        let eq = ForceEquation {
            pv: v_free - p.lambda,
            qv: -c.c21,
            pa: -2.0 * p.nu * v_free - x_free,
            qa: c.c11 + 2.0 * p.nu * c.c21,
        };
        let sol = solver::solve(p, &self.solver, &eq, s.force, stats);
        let f = sol.force;
        let x = x_free + (1.0 - c.c11) * f;
        let v = v_free - c.c21 * f;
        let a = f - 2.0 * p.nu * v - x;
        (
            Sample {
                t: s.t + c.h,
                x,
                v,
                a,
                force: f,
            },
            sol,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::FrictionLaw;

    #[test]
    fn fixed_point_stays_put() {
        for law in FrictionLaw::ALL {
            for kind in [solver::SolverKind::Robust, solver::SolverKind::Paper] {
                let cfg = SolverConfig {
                    kind,
                    ..Default::default()
                };
                let st = Stepper::new(Params::paper(law, 1e-3), 0.01, cfg).unwrap();
                let mut stats = SolverStats::default();
                let (mut s, _) = st.initial(State { x: 1.0, v: 0.0 }, &mut stats);
                for _ in 0..10_000 {
                    s = st.step(&s, &mut stats).0;
                }
                assert!(
                    (s.x - 1.0).abs() < 1e-12 && s.v.abs() < 1e-12,
                    "{law} {kind}: {s:?}"
                );
            }
        }
    }
}
