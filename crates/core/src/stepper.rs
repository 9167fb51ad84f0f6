//! One step of the oscillator: the exact linear step with the implicit end-of-step force
//! (paper eqs. 4.3-4.6), the force held ([`Scheme::Zoh`]) or linear ([`Scheme::Foh`]) over
//! the step. Runs of many steps go through [`crate::run::Run`].

use crate::error::CoreError;
use crate::friction::Law;
use crate::params::Params;
use crate::propagator::{Propagator, Scheme};
use crate::solver::{self, ForceEquation, Solution, SolverConfig, SolverStats};
use crate::stick::{StickEvents, StickStepper};

pub use crate::state::{Sample, State};

/// Integrates one run with a fixed step.
#[derive(Clone, Copy, Debug)]
pub struct Stepper {
    params: Params,
    law: Law,
    prop: Propagator,
    solver: SolverConfig,
    /// End state `x = x_free + w_x0 F_j + w_x1 F_{j+1}`, `v = v_free + w_v0 F_j + w_v1 F_{j+1}`.
    w_x0: f64,
    w_x1: f64,
    w_v0: f64,
    w_v1: f64,
    /// `da/dF_{j+1} = 1 - 2 nu w_v1 - w_x1`.
    qa: f64,
    /// The event stepper of a law with true stick.
    stick: Option<StickStepper>,
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
        // A belt speed below what the step resolves (the argument: Params::check_step).
        params.check_step(dt)?;
        if solver.kind == solver::SolverKind::Paper && solver.max_iter == 0 {
            return Err(CoreError::InvalidParameter {
                name: "max_iter",
                value: 0.0,
                expected: "an iteration cap >= 1",
            });
        }
        let prop = Propagator::new(params.nu, dt)?;
        let c = &prop;
        // Zero-order hold: the force F_{j+1} over the whole step, written as in the paper
        // (x = x_free + (1 - c11) F, v = v_free - c21 F). First-order hold: the ramp response
        // (q1, q2) moves weight from F_{j+1} to F_j.
        let (w_x0, w_x1, w_v0, w_v1, qa) = match solver.scheme {
            Scheme::Zoh => (
                0.0,
                1.0 - c.c11,
                0.0,
                -c.c21,
                c.c11 + 2.0 * params.nu * c.c21,
            ),
            Scheme::Foh => {
                let (wx1, wv1) = (1.0 - c.c11 - c.q1, -c.c21 - c.q2);
                (c.q1, wx1, c.q2, wv1, 1.0 - 2.0 * params.nu * wv1 - wx1)
            }
        };
        let law = Law::new(&params);
        let stick = StickStepper::new(&params, &law, &prop, solver.scheme);
        Ok(Stepper {
            params,
            law,
            stick,
            prop,
            solver,
            w_x0,
            w_x1,
            w_v0,
            w_v1,
            qa,
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

    /// The friction law with its constants.
    pub fn law(&self) -> &Law {
        &self.law
    }

    /// The scheme (how the force varies over a step).
    pub fn scheme(&self) -> Scheme {
        self.solver.scheme
    }

    /// The solver settings.
    pub fn solver(&self) -> &SolverConfig {
        &self.solver
    }

    /// The initial force and acceleration at `(x0, v0)`: `a = F(v0 - lambda, a) - 2 nu v0 - x0`,
    /// solved from the first guess `x''(0) = 0` as in the paper.
    pub fn initial(&self, s: State, stats: &mut SolverStats) -> (Sample, Solution) {
        self.initial_near(s, None, stats)
    }

    /// [`Stepper::initial`], with the root nearest the force `near` where one is given (the
    /// robust solver's rule for a step): a run restarted from a state a run passed through,
    /// on that run's root (laws with true stick ignore it).
    pub fn initial_near(
        &self,
        s: State,
        near: Option<f64>,
        stats: &mut SolverStats,
    ) -> (Sample, Solution) {
        if let Some(st) = &self.stick {
            stats.solves += 1;
            stats.evaluations += 1;
            return st.initial(&self.law, s);
        }
        let p = &self.params;
        let eq = ForceEquation {
            pv: s.v - p.lambda,
            qv: 0.0,
            pa: -2.0 * p.nu * s.v - s.x,
            qa: 1.0,
        };
        stats.evaluations += 1;
        let guess = near.unwrap_or_else(|| self.law.eval(s.v - p.lambda, 0.0).force);
        let sol = solver::solve(&self.law, &self.solver, &eq, guess, stats);
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

    /// One step with the stick events located inside it ([`StickEvents::NONE`] for laws
    /// without stick): what [`crate::Run`] calls.
    #[inline]
    pub fn advance(&self, s: &Sample, stats: &mut SolverStats) -> (Sample, Solution, StickEvents) {
        match &self.stick {
            None => {
                let (n, sol) = self.step(s, stats);
                (n, sol, StickEvents::NONE)
            }
            Some(st) => st.step(&self.law, s, stats),
        }
    }

    /// Whether the law sticks with located events.
    pub fn locates_stick(&self) -> bool {
        self.stick.is_some()
    }

    /// One step of length `dt` from `s`: the end-of-step force solves the implicit equation
    /// (nearest to `s.force` for the robust solver); the end state is affine in it. (A law
    /// with true stick is stepped with its events, [`Stepper::advance`].)
    #[inline]
    pub fn step(&self, s: &Sample, stats: &mut SolverStats) -> (Sample, Solution) {
        if let Some(st) = &self.stick {
            let (n, sol, _) = st.step(&self.law, s, stats);
            return (n, sol);
        }
        let (x_free, v_free) = self.free(s);
        let eq = self.equation_from(x_free, v_free);
        let sol = solver::solve(&self.law, &self.solver, &eq, s.force, stats);
        let f = sol.force;
        let x = x_free + self.w_x1 * f;
        let v = v_free + self.w_v1 * f;
        let a = f - 2.0 * self.params.nu * v - x;
        (
            Sample {
                t: s.t + self.prop.h,
                x,
                v,
                a,
                force: f,
            },
            sol,
        )
    }

    /// The implicit equation of the step from `s` (as [`Stepper::step`] builds it).
    pub fn equation(&self, s: &Sample) -> ForceEquation {
        let (x_free, v_free) = self.free(s);
        self.equation_from(x_free, v_free)
    }

    /// The end state with the end-of-step force set to zero.
    #[inline]
    fn free(&self, s: &Sample) -> (f64, f64) {
        let c = &self.prop;
        (
            c.c11 * s.x + c.c12 * s.v + self.w_x0 * s.force,
            c.c21 * s.x + c.c22 * s.v + self.w_v0 * s.force,
        )
    }

    #[inline]
    fn equation_from(&self, x_free: f64, v_free: f64) -> ForceEquation {
        let p = &self.params;
        ForceEquation {
            pv: v_free - p.lambda,
            qv: self.w_v1,
            pa: -2.0 * p.nu * v_free - x_free,
            qa: self.qa,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::FrictionLaw;

    #[test]
    fn fixed_point_stays_put() {
        for law in FrictionLaw::MCMILLAN {
            for (kind, scheme) in [
                (solver::SolverKind::Robust, Scheme::Foh),
                (solver::SolverKind::Robust, Scheme::Zoh),
                (solver::SolverKind::Paper, Scheme::Zoh),
            ] {
                let cfg = SolverConfig {
                    kind,
                    scheme,
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
