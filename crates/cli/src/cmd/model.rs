//! Model and integration flags shared by `trajectory`, `classify`, `ulc` and `critical`.

use anyhow::{Context, bail};
use squeal_core::{
    CoreError, FrictionLaw, Params, Physical, Scheme, SolverConfig, SolverKind, Stepper,
};

use super::law_flags::{LawFlags, flag};
use super::physical::PhysicalArgs;

/// The `--law` flag's help: every law's name.
fn law_help() -> String {
    format!("Friction law: {}.", FrictionLaw::names())
}

/// Model flags (nondimensional, paper Section 4; defaults are the paper's Table 1, or
/// bSTAB's friction case for `--law stribeck`).
#[derive(clap::Args, Debug, Clone)]
pub struct ModelArgs {
    /// Friction law (its names: [`FrictionLaw::names`]).
    #[arg(long, default_value = FrictionLaw::DEFAULT.name(), help = law_help())]
    pub law: String,
    /// The law's own parameters, one flag per key of any law (`--nu`, `--v-d`, `--mu-0`,
    /// ...); defaults: the paper's Table 1, bSTAB's friction case, or the cubic law's.
    #[command(flatten)]
    pub keys: LawFlags,
    /// `--law table`: the friction curve, a CSV of two columns (slip speed, mu; the first
    /// row at slip speed 0, its mu the static coefficient), an optional header, `#` comments.
    #[arg(long, value_name = "FILE")]
    pub friction_csv: Option<std::path::PathBuf>,
    /// The physical system's flags (the paper's laws, instead of --nu --lambda [--tau --phi]).
    #[command(flatten)]
    pub system: PhysicalArgs,
    /// Time step (see docs/history/benchmarks.md for the convergence study behind the default).
    #[arg(long, default_value_t = squeal_core::defaults::DT, allow_negative_numbers = true)]
    pub dt: f64,
    /// Implicit force solver: robust (true root nearest the previous force) or paper.
    #[arg(long, default_value = "robust")]
    pub solver: String,
    /// How the force varies over a step: foh (linear, second order) or zoh (held, the paper's).
    #[arg(long, default_value = "foh")]
    pub scheme: String,
}

impl ModelArgs {
    /// The physical system of `--m --k --c --v-belt --mu-k [--mu-s --tau-s] [--g |
    /// --normal-force]`, if any of them is given (all but `--g --normal-force` are then required, `--mu-s --tau-s` by the two
    /// McMillan laws only, and no nondimensional law flag); errors name the flag.
    pub fn physical(&self) -> anyhow::Result<Option<Physical>> {
        let law: FrictionLaw = self.law.parse().context("--law")?;
        // The curve is read only where the physical flags are given (its speeds then in
        // m/s); without them it is the model's, read by `params`.
        let table = match self.system.given() {
            true => self.table(law)?,
            false => None,
        };
        let system = self.system.system(law, table, self.keys.first())?;
        if let Some(ph) = &system {
            super::doubts::warn_system(ph, self.friction_csv.as_deref());
        }
        Ok(system)
    }

    /// Checked parameters; errors name the flag.
    pub fn params(&self) -> anyhow::Result<Params> {
        let law: FrictionLaw = self.law.parse().context("--law")?;
        if let Some(ph) = self.physical()? {
            return ph.params(law).map_err(super::physical::flag_error);
        }
        let own = law.keys();
        if let Some((k, _)) = self.keys.0.iter().find(|(k, _)| !own.contains(k)) {
            bail!(
                "{}: not a parameter of --law {law} (its flags: {})",
                flag(k),
                own.iter().map(|k| flag(k)).collect::<Vec<_>>().join(", ")
            );
        }
        let defaults = Params::defaults(law);
        let named = defaults.named();
        let table = self.table(law)?;
        if let Some(t) = table {
            super::doubts::warn_curve(t, self.friction_csv.as_deref());
        }
        let p = Params::from_named_table(law, table, |k| {
            self.keys
                .get(k)
                .or_else(|| named.iter().find(|n| n.name == k).map(|n| n.value))
        })
        .map_err(|k| anyhow::anyhow!("--{k}: missing"))?;
        p.validate().map_err(flag_error)?;
        Ok(p)
    }

    /// The table of `--friction-csv`, which `--law table` needs and the other laws refuse.
    fn table(
        &self,
        law: FrictionLaw,
    ) -> anyhow::Result<Option<&'static squeal_core::FrictionTable>> {
        match (&self.friction_csv, law) {
            (None, FrictionLaw::Table) => bail!(
                "--friction-csv: missing: --law table needs its friction curve, a CSV of slip \
                 speed and mu (the first row at slip speed 0)"
            ),
            (None, _) => return Ok(None),
            (Some(_), FrictionLaw::Table) => {}
            (Some(_), _) => bail!(
                "--friction-csv: not a flag of --law {law} (only --law table takes a friction \
                 curve)"
            ),
        }
        let path = self.friction_csv.as_deref().expect("given");
        squeal_scan::spec::read_friction_csv(path)
            .map(Some)
            .map_err(|e| anyhow::anyhow!("--friction-csv: {e}"))
    }

    /// The `[model]` table of a scan spec for these flags (and its `[physical]` table when
    /// the physical flags are given).
    pub fn model_toml(&self) -> anyhow::Result<String> {
        let p = self.params()?;
        let mut t = format!("law = \"{}\"\n", p.law);
        if let Some(ph) = self.physical()? {
            t.push_str(&super::physical::spec_table(&ph));
            self.push_csv(&mut t);
            return Ok(t);
        }
        for n in p.named() {
            t.push_str(&format!("{} = {:?}\n", n.name, n.value));
        }
        self.push_csv(&mut t);
        Ok(t)
    }

    /// `friction_csv = "FILE"` of `--friction-csv`, if given, as the last line of the table
    /// `t` (`[model]`, or `[physical]` where its speeds are in m/s).
    fn push_csv(&self, t: &mut String) {
        if let Some(csv) = &self.friction_csv {
            // Read again by the plan, relative to the working folder (the spec's folder of
            // "command line" is "").
            let path = toml::Value::String(csv.to_string_lossy().into_owned());
            t.push_str(&format!("friction_csv = {path}\n"));
        }
    }

    /// The stepper for these flags; errors name the flag.
    pub fn stepper(&self) -> anyhow::Result<Stepper> {
        let p = self.params()?;
        // A belt speed below the step, named by the physical flag at fault (the stepper
        // below would name the model's lambda, a flag not given).
        if let Some(ph) = self.physical()? {
            if self.dt.is_finite() && self.dt > 0.0 {
                ph.check_step(&p, self.dt)
                    .map_err(super::physical::flag_error)?;
            }
        }
        let kind: SolverKind = self.solver.parse().context("--solver")?;
        let scheme: Scheme = self.scheme.parse().context("--scheme")?;
        if !self.dt.is_finite() || self.dt <= 0.0 || self.dt > 1.0 {
            bail!(
                "--dt: invalid dt = {}: expected a finite step in (0, 1]",
                squeal_core::error::Number(self.dt)
            );
        }
        Stepper::new(
            p,
            self.dt,
            SolverConfig {
                kind,
                scheme,
                ..Default::default()
            },
        )
        .map_err(flag_error)
    }

    /// The one-map scan plan of these flags with the classifier's time limit `t_max` (given
    /// by `flag`): what `MapContext::prepare` needs to label a start as a scan does.
    pub fn plan(&self, t_max: f64, flag: &str) -> anyhow::Result<squeal_scan::Plan> {
        self.stepper()?;
        // Checked here, not in the spec built below: a NaN would be written as `t_max =
        // NaN`, which TOML refuses without naming the flag.
        if !(t_max.is_finite() && t_max > 0.0) {
            bail!(
                "{flag} {}: expected a finite time > 0",
                squeal_core::error::Number(t_max)
            );
        }
        let text = format!(
            "version = 1\n[model]\n{}\
             [grid]\nx0 = {{ min = 0.0, max = 0.0, count = 1 }}\nv0 = {{ min = 0.0, max = 0.0, count = 1 }}\n\
             [integration]\ndt = {:?}\nsolver = \"{}\"\nscheme = \"{}\"\n[classifier]\nt_max = {:?}\n[output]\npath = \"unused.h5\"\n",
            self.model_toml()?,
            self.dt,
            self.solver,
            self.scheme,
            t_max
        );
        squeal_scan::Plan::from_toml(&text, "command line")
            .map_err(|e| anyhow::anyhow!("{}", e.to_string().replace("classifier.t_max", flag)))
    }
}

/// Prefixes a core error with the flag it concerns: "--nu: invalid nu = -1: expected ...".
pub fn flag_error(e: CoreError) -> anyhow::Error {
    match &e {
        CoreError::InvalidParameter { name, .. } | CoreError::Unresolved { name, .. } => {
            anyhow::anyhow!("{}: {e}", flag(name))
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
        conflicts_with_all = spec_conflicts()
    )]
    pub spec: Option<std::path::PathBuf>,
    /// With --spec of a sweep: which map (0-based).
    #[arg(long, default_value_t = 0)]
    pub map: usize,
    /// Give up (undecided) at this time.
    #[arg(long, default_value_t = squeal_core::defaults::T_MAX, allow_negative_numbers = true)]
    pub t_max: f64,
}

/// The flags `--spec` refuses: the model's (every law key among them), the integration's and
/// `--t-max`. Each by name, so the refusal names the flag given.
fn spec_conflicts() -> Vec<&'static str> {
    let mut ids = vec!["law"];
    ids.extend(super::law_flags::all_keys());
    ids.extend([
        "m",
        "k",
        "c",
        "v_belt",
        "mu_k",
        "mu_s",
        "tau_s",
        "g",
        "normal_force",
        "friction_csv",
        "dt",
        "solver",
        "t_max",
    ]);
    ids
}

impl SetupArgs {
    /// The plan and map.
    pub fn setup(&self) -> anyhow::Result<Setup> {
        let plan = match &self.spec {
            Some(path) => {
                let plan = squeal_scan::Plan::from_file(path)?;
                super::doubts::warn_space(&plan.space);
                plan
            }
            None => self.model.plan(self.t_max, "--t-max")?,
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
