//! The physical system's flags (`--m --k --c --v-belt --mu-k [--mu-s --tau-s] [--g |
//! --normal-force]`), shared by every command that takes the model flags. `--mu-s --tau-s`
//! are McMillan's surfaces: his laws need them, `--law coulomb` refuses them. `--law table`
//! takes its measured curve from `--friction-csv` (slip speed in m/s) and no `--mu-k`.
//! `--normal-force` presses the block on the belt in place of its weight `m g`.

use anyhow::bail;
use squeal_core::{CoreError, FrictionLaw, FrictionSi, FrictionTable, Load, Physical};

/// The physical flags with their spec key, in the order of [`Physical::values`].
pub const PHYSICAL_FLAGS: [(&str, &str); 9] = [
    ("--m", "m"),
    ("--k", "k"),
    ("--c", "c"),
    ("--v-belt", "v_belt"),
    ("--mu-k", "mu_k"),
    ("--mu-s", "mu_s"),
    ("--tau-s", "tau"),
    ("--g", "g"),
    ("--normal-force", "normal_force"),
];

/// The physical system in SI units instead of --nu --lambda [--tau --phi] (the paper's
/// three laws).
#[derive(clap::Args, Debug, Clone)]
pub struct PhysicalArgs {
    /// Mass m (kg). The physical system in SI units instead of --nu --lambda --tau --phi
    /// (the paper's laws): give --m --k --c --v-belt --mu-k --mu-s --tau-s (--g or
    /// --normal-force optional; --law coulomb takes no --mu-s --tau-s; --law table takes
    /// --friction-csv in m/s instead of --mu-k --mu-s --tau-s); then --x0/--v0 are in m and
    /// m/s and the results are printed in SI units too.
    #[arg(long, allow_negative_numbers = true)]
    pub m: Option<f64>,
    /// Spring stiffness k (N/m; physical system, see --m).
    #[arg(long, allow_negative_numbers = true)]
    pub k: Option<f64>,
    /// Dashpot coefficient c (N s/m; physical system, see --m).
    #[arg(long, allow_negative_numbers = true)]
    pub c: Option<f64>,
    /// Belt speed v_belt (m/s; physical system, see --m).
    #[arg(long = "v-belt", allow_negative_numbers = true)]
    pub v_belt: Option<f64>,
    /// Kinetic friction coefficient mu_k (physical system, see --m).
    #[arg(long = "mu-k", allow_negative_numbers = true)]
    pub mu_k: Option<f64>,
    /// Static friction coefficient mu_s > mu_k (physical system; --law mcmillan and mcmillan-nonhysteretic only, see --m).
    #[arg(long = "mu-s", allow_negative_numbers = true)]
    pub mu_s: Option<f64>,
    /// Characteristic time of the surfaces tau (s; physical system, McMillan's laws; see --m).
    #[arg(long = "tau-s", allow_negative_numbers = true)]
    pub tau_s: Option<f64>,
    /// Gravitational acceleration g (m/s^2; physical system, default 9.81): the block rests
    /// on the belt under its own weight, friction is mu m g. Not with --normal-force.
    #[arg(long, allow_negative_numbers = true)]
    pub g: Option<f64>,
    /// Normal force N pressing the block on the belt (N; physical system, default m g):
    /// friction is mu N, e.g. a brake pad's clamp force. It replaces the weight m g in the
    /// law, so --g is refused beside it.
    #[arg(long = "normal-force", allow_negative_numbers = true)]
    pub normal_force: Option<f64>,
}

impl PhysicalArgs {
    /// Whether any physical flag is given.
    pub fn given(&self) -> bool {
        self.values().iter().any(Option::is_some)
    }

    /// The flags' values in the order of [`PHYSICAL_FLAGS`].
    fn values(&self) -> [Option<f64>; 9] {
        [
            self.m,
            self.k,
            self.c,
            self.v_belt,
            self.mu_k,
            self.mu_s,
            self.tau_s,
            self.g,
            self.normal_force,
        ]
    }

    /// The system under `law`, if any flag is given (`--m --k --c --v-belt` are then
    /// required, with `--mu-k` but for `--law table`, `--mu-s --tau-s` by `mcmillan` and
    /// `mcmillan-nonhysteretic` alone, which alone use them, and one at most of `--g` and
    /// `--normal-force`); `table`: the curve of `--friction-csv` (slip speed in m/s with
    /// these flags), which `--law table` needs; `other`: a nondimensional law flag also
    /// given (refused). Errors name the flag.
    pub fn system(
        &self,
        law: FrictionLaw,
        table: Option<&'static FrictionTable>,
        other: Option<&str>,
    ) -> anyhow::Result<Option<Physical>> {
        let values = self.values();
        if !self.given() {
            return Ok(None);
        }
        // Before asking for the missing flags: the Stribeck and cubic laws take none of
        // them (`--law cubic --m ...` would ask for --mu-k, which that law never takes).
        if squeal_core::units::friction_keys(law).is_err() {
            bail!(
                "--law {law}: the physical flags use McMillan's scaling or a measured curve's \
                 (--law table), which the Stribeck and cubic laws do not share (give --xi, \
                 --v-d, ... instead)"
            );
        }
        let all = "--m --k --c --v-belt, with --mu-k, and --mu-s --tau-s for --law mcmillan and \
                   mcmillan-nonhysteretic, or --friction-csv (m/s) for --law table (and \
                   optionally --g or --normal-force)";
        if let Some((flag, _)) = PHYSICAL_FLAGS[..4]
            .iter()
            .zip(values)
            .find(|(_, v)| v.is_none())
        {
            bail!("{}: missing (the physical system takes {all})", flag.0);
        }
        if let Some(k) = other {
            bail!(
                "{}: not with the physical system ({all}): give one or the other",
                super::law_flags::flag(k)
            );
        }
        let v = |i: usize| values[i].unwrap_or_default();
        let ph = Physical {
            m: v(0),
            k: v(1),
            c: v(2),
            v_belt: v(3),
            friction: FrictionSi::of(law, self.mu_k, self.mu_s, self.tau_s, table)
                .map_err(flag_error)?,
            load: Load::of(self.g, self.normal_force, squeal_core::units::G_STANDARD)
                .map_err(flag_error)?,
        };
        ph.params(law).map_err(flag_error)?;
        Ok(Some(ph))
    }
}

/// The `[physical]` table of a scan spec for the system `ph` (without `mu_s` and `tau`
/// where it has no surfaces: Coulomb; with `g` or `normal_force`, the one it has).
pub fn spec_table(ph: &Physical) -> String {
    let v = ph.values();
    let mut t = String::from("[physical]\n");
    for ((_, key), v) in PHYSICAL_FLAGS.iter().zip(v) {
        if let Some(v) = v {
            t.push_str(&format!("{key} = {v:?}\n"));
        }
    }
    t
}

/// A physical-system error naming the flag: derived values name the flags they come from.
pub fn flag_error(e: CoreError) -> anyhow::Error {
    match e.key() {
        Some(name) => {
            let flag = match name {
                "nu" => "--c (nu = c / (2 sqrt(m k)))",
                "lambda" => {
                    "--v-belt (lambda = v_belt sqrt(m k) / (mu_k N), N = m g or --normal-force)"
                }
                "friction_table" => "--friction-csv",
                "xi" => "--c (xi = c / (2 sqrt(m k)))",
                "v_d" => "--v-belt (v_d = v_belt sqrt(m k) / N)",
                "phi" => "--mu-s",
                "tau" => "--tau-s",
                n => PHYSICAL_FLAGS
                    .iter()
                    .find(|(_, k)| *k == n)
                    .map_or(n, |(f, _)| *f),
            };
            anyhow::anyhow!("{flag}: {e}")
        }
        // A measured curve whose speeds no f64 holds in the model's units.
        None if matches!(e, CoreError::InvalidTable { .. }) => {
            anyhow::anyhow!("--friction-csv: {e}")
        }
        None => anyhow::anyhow!(e),
    }
}

/// How a start refused by the library's bounds is reported from `path` (the command line,
/// a file's line), as the given start in SI units (`si`) where there is one:
/// [`squeal_scan::bounds::start_invalid`], the one rule of every door.
pub fn start_invalid(
    path: String,
    si: Option<(squeal_core::State, squeal_core::Scales)>,
) -> impl Fn(&str, String, &str) -> squeal_scan::ScanError {
    squeal_scan::bounds::start_invalid(path, si)
}
