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
    #[arg(long, default_value_t = squeal_core::defaults::NU, allow_negative_numbers = true)]
    pub nu: f64,
    /// Belt speed lambda.
    #[arg(long, default_value_t = squeal_core::defaults::LAMBDA, allow_negative_numbers = true)]
    pub lambda: f64,
    /// Characteristic time tau > 0 of the surfaces.
    #[arg(long, default_value_t = squeal_core::defaults::TAU, allow_negative_numbers = true)]
    pub tau: f64,
    /// Phi = arcsin(mu_k/mu_s), in (0, pi/2].
    #[arg(long, default_value_t = squeal_core::defaults::PHI, allow_negative_numbers = true)]
    pub phi: f64,
    /// Time step (see BENCHMARKS.md for the convergence study behind the default).
    #[arg(long, default_value_t = squeal_core::defaults::DT, allow_negative_numbers = true)]
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

/// A model from flags or from a scan spec (`--spec FILE`, map `--map`).
pub struct Setup {
    /// The scan plan (from `--spec`, or built from the flags).
    pub plan: squeal_scan::Plan,
    /// Which map of the plan.
    pub map: usize,
}

/// Flags that pick the model: the model flags, or a spec.
#[derive(clap::Args, Debug, Clone)]
pub struct SetupArgs {
    #[command(flatten)]
    pub model: ModelArgs,
    /// Take the model, integration and classifier settings from a scan spec instead (the
    /// model flags and --t-max are then refused: the spec is the one place they come from).
    #[arg(
        long,
        conflicts_with_all = ["law", "nu", "lambda", "tau", "phi", "dt", "solver", "t_max"]
    )]
    pub spec: Option<std::path::PathBuf>,
    /// With --spec of a sweep: which map (0-based).
    #[arg(long, default_value_t = 0)]
    pub map: usize,
    /// Give up (undecided) at this time.
    #[arg(long, default_value_t = squeal_core::defaults::T_MAX, allow_negative_numbers = true)]
    pub t_max: f64,
}

impl SetupArgs {
    /// The plan and map.
    pub fn setup(&self) -> anyhow::Result<Setup> {
        let plan = match &self.spec {
            Some(path) => squeal_scan::Plan::from_file(path)?,
            None => {
                let m = &self.model;
                m.stepper()?;
                let text = format!(
                    "version = 1\n[model]\nlaw = \"{}\"\nnu = {:?}\nlambda = {:?}\ntau = {:?}\nphi = {:?}\n\
                     [grid]\nx0 = {{ min = 0.0, max = 0.0, count = 1 }}\nv0 = {{ min = 0.0, max = 0.0, count = 1 }}\n\
                     [integration]\ndt = {:?}\nsolver = \"{}\"\n[classifier]\nt_max = {:?}\n[output]\npath = \"unused.h5\"\n",
                    m.law, m.nu, m.lambda, m.tau, m.phi, m.dt, m.solver, self.t_max
                );
                squeal_scan::Plan::from_toml(&text, "command line").map_err(|e| {
                    anyhow::anyhow!("{}", e.to_string().replace("classifier.t_max", "--t-max"))
                })?
            }
        };
        if self.map >= plan.maps.len() {
            anyhow::bail!(
                "--map {}: the spec has {} map(s)",
                self.map,
                plan.maps.len()
            );
        }
        Ok(Setup {
            plan,
            map: self.map,
        })
    }
}
