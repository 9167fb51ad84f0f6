//! Model and integration flags shared by `trajectory`, `classify`, `ulc` and `critical`.

use anyhow::{Context, bail};
use squeal_core::{CoreError, FrictionLaw, Params, SolverConfig, SolverKind, Stepper};

/// Model flags (nondimensional, paper Section 4; defaults are the paper's Table 1).
#[derive(clap::Args, Debug, Clone)]
pub struct ModelArgs {
    /// Friction law: mcmillan, mcmillan-nonhysteretic or coulomb.
    #[arg(long, default_value = "mcmillan")]
    pub law: String,
    /// Damping ratio nu >= 0.
    #[arg(long, default_value_t = 1e-3, allow_negative_numbers = true)]
    pub nu: f64,
    /// Belt speed lambda.
    #[arg(long, default_value_t = 3.0, allow_negative_numbers = true)]
    pub lambda: f64,
    /// Characteristic time tau > 0 of the surfaces.
    #[arg(long, default_value_t = 0.1 * 10f64.sqrt(), allow_negative_numbers = true)]
    pub tau: f64,
    /// Phi = arcsin(mu_k/mu_s), in (0, pi/2].
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    pub phi: f64,
    /// Time step (see BENCHMARKS.md for the convergence study behind the default).
    #[arg(long, default_value_t = 0.01, allow_negative_numbers = true)]
    pub dt: f64,
    /// Implicit force solver: robust (true root nearest the previous force) or paper.
    #[arg(long, default_value = "robust")]
    pub solver: String,
}

impl ModelArgs {
    /// Checked parameters; errors name the flag.
    pub fn params(&self) -> anyhow::Result<Params> {
        let law: FrictionLaw = self.law.parse().context("--law")?;
        let p = Params {
            law,
            nu: self.nu,
            lambda: self.lambda,
            tau: self.tau,
            phi: self.phi,
        };
        p.validate().map_err(flag_error)?;
        Ok(p)
    }

    /// The stepper for these flags; errors name the flag.
    pub fn stepper(&self) -> anyhow::Result<Stepper> {
        let p = self.params()?;
        let kind: SolverKind = self.solver.parse().context("--solver")?;
        if !self.dt.is_finite() || self.dt <= 0.0 || self.dt > 1.0 {
            bail!(
                "--dt: invalid dt = {}: expected a finite step in (0, 1]",
                self.dt
            );
        }
        Stepper::new(
            p,
            self.dt,
            SolverConfig {
                kind,
                ..Default::default()
            },
        )
        .map_err(flag_error)
    }
}

/// Prefixes a core error with the flag it concerns: "--nu: invalid nu = -1: expected ...".
pub fn flag_error(e: CoreError) -> anyhow::Error {
    match &e {
        CoreError::InvalidParameter { name, .. } => {
            anyhow::anyhow!("--{}: {e}", name.replace('_', "-"))
        }
        _ => anyhow::anyhow!(e),
    }
}
