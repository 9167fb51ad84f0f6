//! The friction laws and their own parameters: [`Friction`], one enum whose variants carry
//! what each law needs (and nothing else), and [`FrictionLaw`], the law's name alone (what a
//! spec's `law = "..."`, `--law` and the files' `law` attribute give before the parameters
//! are read).
//!
//! This file is where a law is registered: its two variants and one arm in each `match`
//! below. A law's own parameters live in a module of their own ([`Stribeck`] in
//! `law/stribeck.rs`, [`Cubic`] in `law/cubic.rs`, [`FrictionTable`] in `table.rs`), with
//! `mu(s)`, the checks that name each key, the keys' long names and units, and the defaults
//! with their sources. Flags, `--help`, spec keys, files, JSON and Python keywords are all
//! made from [`FrictionLaw::keys`] and [`Friction::named`], so a law with true stick needs no
//! edit elsewhere (`docs/extending.md` counts it).

use serde::{Deserialize, Serialize};

use crate::error::CoreError;
use crate::params::Named;
pub use crate::table::FrictionTable;

mod cubic;
mod stribeck;

pub use cubic::Cubic;
pub use stribeck::{PerV0, Stribeck};

/// Which friction law closes the equation of motion `x'' + 2 nu x' + x = F(x' - lambda, x'')`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FrictionLaw {
    /// McMillan's hysteretic law, paper eq. (4.1) with the two misprints corrected.
    #[serde(rename = "mcmillan")]
    McMillan,
    /// The non-hysteretic variant, paper eq. (5.1) with `|x''|` in the sine argument.
    #[serde(rename = "mcmillan-nonhysteretic")]
    McMillanNonHysteretic,
    /// Plain Coulomb friction `F = -sgn(v)`, set-valued (`F` in `[-1, 1]`) at `v = 0`.
    #[serde(rename = "coulomb")]
    Coulomb,
    /// A Stribeck-type law with true stick (the friction case of bSTAB, Stender et al. 2021):
    /// `F = -sgn(v) mu(|v|)` while slipping, any value in `[-mu_s, mu_s]` while stuck; its
    /// parameters are [`Stribeck`].
    #[serde(rename = "stribeck")]
    Stribeck,
    /// The cubic law with true stick (Popp and Stelter; Thomsen 1999): `F = -sgn(v) mu(|v|)`,
    /// `mu(s) = mu_0 - a1 s + a3 s^3`, while slipping; any value in `[-mu_0, mu_0]` while
    /// stuck; its parameters are [`Cubic`].
    #[serde(rename = "cubic")]
    Cubic,
    /// A tabulated law with true stick: `F = -sgn(v) mu(|v|)` while slipping, `mu` a
    /// monotone interpolation of a table of `(s, mu)` rows ([`FrictionTable`]); any value in
    /// `[-mu_s, mu_s]` while stuck, `mu_s` the row at slip speed 0.
    #[serde(rename = "table")]
    Table,
}

impl FrictionLaw {
    /// The name used on the command line, in specs and in HDF5 attributes.
    pub fn name(self) -> &'static str {
        match self {
            FrictionLaw::McMillan => "mcmillan",
            FrictionLaw::McMillanNonHysteretic => "mcmillan-nonhysteretic",
            FrictionLaw::Coulomb => "coulomb",
            FrictionLaw::Stribeck => "stribeck",
            FrictionLaw::Cubic => "cubic",
            FrictionLaw::Table => "table",
        }
    }

    /// How the law is named in the titles of pictures.
    pub fn title(self) -> &'static str {
        match self {
            FrictionLaw::McMillan => "McMillan law (hysteretic)",
            FrictionLaw::McMillanNonHysteretic => "McMillan law (non-hysteretic)",
            FrictionLaw::Coulomb => "Coulomb friction",
            FrictionLaw::Stribeck => "Stribeck law with true stick",
            FrictionLaw::Cubic => "cubic law with true stick",
            FrictionLaw::Table => "tabulated law with true stick",
        }
    }

    /// McMillan's parameterisation (`nu`, `lambda`, `tau`, `phi`): the three laws of the paper.
    pub const MCMILLAN: [FrictionLaw; 3] = [
        FrictionLaw::McMillan,
        FrictionLaw::McMillanNonHysteretic,
        FrictionLaw::Coulomb,
    ];

    /// The law where none is named: the command line's `--law` and Python's helpers
    /// (McMillan's hysteretic law, the paper's).
    pub const DEFAULT: FrictionLaw = FrictionLaw::McMillan;

    /// All laws, in a fixed order.
    pub const ALL: [FrictionLaw; 6] = [
        FrictionLaw::McMillan,
        FrictionLaw::McMillanNonHysteretic,
        FrictionLaw::Coulomb,
        FrictionLaw::Stribeck,
        FrictionLaw::Cubic,
        FrictionLaw::Table,
    ];

    /// Every law's name, for messages: `mcmillan, mcmillan-nonhysteretic, ...`.
    pub fn names() -> String {
        FrictionLaw::ALL.map(FrictionLaw::name).join(", ")
    }

    /// The law's family: which algorithms compute it ([`LawFamily`]).
    pub fn family(self) -> LawFamily {
        match self {
            FrictionLaw::McMillan | FrictionLaw::McMillanNonHysteretic | FrictionLaw::Coulomb => {
                LawFamily::Regularised
            }
            FrictionLaw::Stribeck | FrictionLaw::Cubic | FrictionLaw::Table => LawFamily::TrueStick,
        }
    }

    /// The names of the law's own parameters, damping and belt speed first, as they appear in
    /// specs, flags and files ([`crate::Params::named`] gives their values).
    pub fn keys(self) -> &'static [&'static str] {
        match self {
            FrictionLaw::Stribeck => &Stribeck::KEYS,
            FrictionLaw::Cubic => &Cubic::KEYS,
            FrictionLaw::Table => &FrictionTable::KEYS,
            // Coulomb's force has no surface time and no static limit of its own.
            FrictionLaw::Coulomb => &["nu", "lambda"],
            FrictionLaw::McMillan | FrictionLaw::McMillanNonHysteretic => {
                &["nu", "lambda", "tau", "phi"]
            }
        }
    }

    /// The default damping ratio and belt speed of the law (`nu` and `lambda`, or its own
    /// `xi` and `v_d`): the paper's Table 1 with `nu = 1e-3` for McMillan's laws and Coulomb,
    /// the law's own module's for the others.
    pub fn default_damping_and_speed(self) -> (f64, f64) {
        use crate::defaults::{LAMBDA, NU};
        match self {
            FrictionLaw::McMillan | FrictionLaw::McMillanNonHysteretic | FrictionLaw::Coulomb => {
                (NU, LAMBDA)
            }
            FrictionLaw::Stribeck => (Stribeck::XI, Stribeck::V_D),
            FrictionLaw::Cubic => (Cubic::XI, Cubic::V_D),
            FrictionLaw::Table => (FrictionTable::XI, FrictionTable::V_D),
        }
    }
}

/// How a family of friction laws is computed: the one value, taken from the law when a plan
/// is made, that the computation asks which algorithms, shortcuts, names and figures apply,
/// so that no caller tests the law itself. A new family is a new variant, and every `match`
/// on it names the places it must answer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LawFamily {
    /// McMillan's laws and Coulomb friction: the force switches with the sign of the slip
    /// velocity (set-valued or smoothed at zero, never stuck at a static limit); stick-slip
    /// is a band of the Poincare section bounded by the unstable cycle. States are in units
    /// of the kinetic friction, damping and belt speed are McMillan's `nu` and `lambda`.
    Regularised,
    /// The Stribeck, cubic and tabulated laws: a static limit, with stick phases located as
    /// events ([`crate::stick`]); the stick-slip cycle runs from breakaway (the landscape,
    /// [`crate::landscape`]). States are in units of the normal load, damping and belt speed
    /// are the law's own `xi` and `v_d`.
    TrueStick,
}

impl LawFamily {
    /// Whether the law is stepped with located stick and breakaway events ([`crate::stick`]):
    /// its stick phases are the block stuck to the belt, not quasi-static stretches of a
    /// regularised force.
    pub fn locates_stick(self) -> bool {
        self == LawFamily::TrueStick
    }

    /// Whether the law has a stick-slip cycle from breakaway and its landscape
    /// ([`crate::landscape`]), computed, stored and read beside each map.
    pub fn has_landscape(self) -> bool {
        self == LawFamily::TrueStick
    }

    /// Whether the section's fates can be certified by witnesses ([`crate::witness`]): the
    /// law depends on the slip velocity alone and sticks, so its return map is monotone.
    pub fn has_section_witnesses(self) -> bool {
        self == LawFamily::TrueStick
    }

    /// Whether stick-slip is a band of the section bounded by the unstable cycle: the
    /// classifier's band rules apply (so each map's section is searched), and the band has
    /// a crisis to bisect for.
    pub fn has_band(self) -> bool {
        self == LawFamily::Regularised
    }

    /// Whether damping and belt speed go by the law's own keys (`xi`, `v_d`, each with a
    /// default, stored with its long name and units) rather than McMillan's `nu` and
    /// `lambda` (the damping required).
    pub fn has_own_names(self) -> bool {
        self == LawFamily::TrueStick
    }

    /// Whether states and forces are in units of the normal load `m g` rather than of the
    /// kinetic friction `mu_k m g`.
    pub fn in_normal_load(self) -> bool {
        self == LawFamily::TrueStick
    }
}

impl std::str::FromStr for FrictionLaw {
    type Err = CoreError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        FrictionLaw::ALL
            .into_iter()
            .find(|l| l.name() == s)
            .ok_or_else(|| CoreError::UnknownLaw {
                name: s.to_string(),
                expected: FrictionLaw::names(),
            })
    }
}

impl std::fmt::Display for FrictionLaw {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// McMillan's surface constants, shared by his two laws (paper Table 1).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Surface {
    /// Characteristic time `tau' = tau / mu_k sqrt(s/m)` of the surfaces; `tau > 0`.
    pub tau: f64,
    /// `Phi = arcsin(mu_k / mu_s)`, in `[MIN_PHI, pi/2]` (`mu_s >= mu_k > 0`, and a static
    /// peak of at most about `1e5` times the kinetic friction: [`MIN_PHI`]).
    pub phi: f64,
}

/// Smallest `Phi = arcsin(mu_k / mu_s)` (radians): a static peak `mu_s / mu_k = 1 / sin(Phi)`
/// of at most about `1e5`.
///
/// `1 / sin(Phi)` scales the quasi-static branch of both laws: it is the largest friction
/// force, in units of kinetic friction ([`crate::Params::force_bound`]). A stuck block is
/// held until the spring's pull reaches that peak, so the stick-slip orbit swings to
/// `|x| = 1.43 / sin(Phi)`: measured at Table 1 (`nu = 1e-3`, `lambda = 3`) with `squeal
/// trajectory --x0 0.5 --t-end 3000 --phi P`, `max |x|` = 1.42e4, 1.43e5, 7.14e5, 1.42e6 for
/// `P` = 1e-4, 1e-5, 2e-6, 1e-6. The classifier's escape radius is `1e6`
/// ([`crate::Classifier`]'s `max_radius`): from `Phi` of about `1.4e-6` down, every stick-slip
/// run crosses it and is labelled `diverged` (at `Phi = 1e-300` every start outside the
/// unstable cycle was), a label of the radius, not of the model. `1e-5` keeps the orbit a
/// factor 7 inside the radius. The solver's bracket `[-B, B]`, `B = 1 + 1 / sin(Phi)`, and the
/// quasi-static branch (rounding of `sin` times `1 / sin(Phi)`, about `7e-11` here against
/// forces up to `1e5`) stay meaningful in `f64` well below this bound, so it is the radius that
/// sets it.
pub const MIN_PHI: f64 = 1e-5;

impl Surface {
    /// `tau` and `phi` with their names (after `nu` and `lambda`).
    pub fn named(&self) -> Vec<Named> {
        vec![
            Named::new("tau", self.tau, "surface time tau", "1 / omega_n"),
            Named::new("phi", self.phi, "Phi = arcsin(mu_k / mu_s)", "rad"),
        ]
    }

    /// The inverse of [`Surface::named`]: the first missing key is the error.
    pub fn from_named(
        mut val: impl FnMut(&'static str) -> Result<f64, &'static str>,
    ) -> Result<Surface, &'static str> {
        Ok(Surface {
            tau: val("tau")?,
            phi: val("phi")?,
        })
    }

    /// Checks `tau` and `phi`; the error names the key.
    pub fn validate(&self) -> Result<(), CoreError> {
        if !self.tau.is_finite() || self.tau <= 0.0 {
            return CoreError::invalid("tau", self.tau, "a finite time > 0");
        }
        Surface::check_phi(self.phi)
    }

    /// Checks `Phi = arcsin(mu_k / mu_s)`: within `[MIN_PHI, pi/2]` ([`MIN_PHI`] says why).
    pub fn check_phi(phi: f64) -> Result<(), CoreError> {
        if phi.is_finite() && (MIN_PHI..=std::f64::consts::FRAC_PI_2).contains(&phi) {
            return Ok(());
        }
        CoreError::invalid(
            "phi",
            phi,
            "an angle in [1e-5, pi/2], a static peak mu_s of at most about 1e5 mu_k (why: \
             docs/spec.md, `phi`)",
        )
    }
}

impl Default for Surface {
    /// Table 1 of the paper: `tau = 0.1 sqrt(10)`, `Phi = 1`.
    fn default() -> Self {
        Surface {
            tau: crate::defaults::TAU,
            phi: crate::defaults::PHI,
        }
    }
}

/// The friction law with its own parameters: what closes `x'' + 2 nu x' + x = F`. The
/// damping ratio and the belt speed, common to every law, are [`crate::Params`]' own.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Friction {
    /// McMillan's hysteretic law, paper eq. (4.1) with the two misprints corrected.
    McMillan(Surface),
    /// The non-hysteretic variant, paper eq. (5.1) with `|x''|` in the sine argument.
    NonHysteretic(Surface),
    /// Plain Coulomb friction `F = -sgn(v)`, set-valued (`F` in `[-1, 1]`) at `v = 0`.
    Coulomb,
    /// The Stribeck law with true stick (bSTAB's friction case).
    Stribeck(Stribeck),
    /// The cubic law with true stick (Popp and Stelter; Thomsen 1999).
    Cubic(Cubic),
    /// A tabulated law with true stick (interned: [`FrictionTable::new`]).
    Table(&'static FrictionTable),
}

impl Friction {
    /// The law's name.
    pub fn kind(&self) -> FrictionLaw {
        match self {
            Friction::McMillan(_) => FrictionLaw::McMillan,
            Friction::NonHysteretic(_) => FrictionLaw::McMillanNonHysteretic,
            Friction::Coulomb => FrictionLaw::Coulomb,
            Friction::Stribeck(_) => FrictionLaw::Stribeck,
            Friction::Cubic(_) => FrictionLaw::Cubic,
            Friction::Table(_) => FrictionLaw::Table,
        }
    }

    /// The law's name in specs, flags and files ([`FrictionLaw::name`]).
    pub fn name(&self) -> &'static str {
        self.kind().name()
    }

    /// The law `kind` with its default parameters (the paper's Table 1 for McMillan's laws,
    /// bSTAB's friction case for the Stribeck law, that law tabulated for the table law:
    /// [`FrictionTable::default_table`]).
    pub fn default_of(kind: FrictionLaw) -> Friction {
        match kind {
            FrictionLaw::McMillan => Friction::McMillan(Surface::default()),
            FrictionLaw::McMillanNonHysteretic => Friction::NonHysteretic(Surface::default()),
            FrictionLaw::Coulomb => Friction::Coulomb,
            FrictionLaw::Stribeck => Friction::Stribeck(Stribeck::default()),
            FrictionLaw::Cubic => Friction::Cubic(Cubic::default()),
            FrictionLaw::Table => Friction::Table(FrictionTable::default_table()),
        }
    }

    /// The parameters of law `kind` from named values (the inverse of [`Friction::named`]):
    /// `val` gives a key's value or the key as the error. The table law takes `table`
    /// (`None` is its missing key, `friction_table`).
    pub fn from_named(
        kind: FrictionLaw,
        table: Option<&'static FrictionTable>,
        mut val: impl FnMut(&'static str) -> Result<f64, &'static str>,
    ) -> Result<Friction, &'static str> {
        Ok(match kind {
            FrictionLaw::McMillan => Friction::McMillan(Surface::from_named(&mut val)?),
            FrictionLaw::McMillanNonHysteretic => {
                Friction::NonHysteretic(Surface::from_named(&mut val)?)
            }
            FrictionLaw::Coulomb => Friction::Coulomb,
            FrictionLaw::Stribeck => Friction::Stribeck(Stribeck::from_named(&mut val)?),
            FrictionLaw::Cubic => Friction::Cubic(Cubic::from_named(&mut val)?),
            FrictionLaw::Table => Friction::Table(table.ok_or("friction_table")?),
        })
    }

    /// The law's own values with their names, after damping and belt speed (McMillan's
    /// `tau` and `phi`; none for Coulomb and the table law, whose table is no scalar:
    /// stored beside the keys as `friction_table`).
    pub fn named(&self) -> Vec<Named> {
        match self {
            Friction::McMillan(c) | Friction::NonHysteretic(c) => c.named(),
            Friction::Coulomb | Friction::Table(_) => Vec::new(),
            Friction::Stribeck(s) => s.named(),
            Friction::Cubic(c) => c.named(),
        }
    }

    /// Checks the law's own values; the error names the key. (Damping and belt speed are
    /// [`crate::Params::validate`]'s; a table's rows were checked when it was made,
    /// [`FrictionTable::new`].)
    pub fn validate(&self) -> Result<(), CoreError> {
        match self {
            Friction::McMillan(c) | Friction::NonHysteretic(c) => c.validate(),
            Friction::Coulomb | Friction::Table(_) => Ok(()),
            Friction::Stribeck(s) => s.validate(),
            Friction::Cubic(c) => c.validate(),
        }
    }

    /// An upper bound on `|F|` over all states at belt speed `lambda`
    /// ([`crate::Params::force_bound`]).
    pub fn force_bound(&self, lambda: f64) -> f64 {
        match self {
            Friction::Coulomb => 1.0,
            // |F1| < 1 and |F2| <= 1 / sin(Phi) on the quasi-static branch, <= 1 on the slip
            // branches.
            Friction::McMillan(c) | Friction::NonHysteretic(c) => 1.0 + 1.0 / c.phi.sin(),
            Friction::Stribeck(s) => s.force_bound(lambda),
            Friction::Cubic(c) => c.force_bound(lambda),
            // The monotone interpolation stays within its rows' values.
            Friction::Table(t) => t.max_mu(),
        }
    }

    /// The static limit of a law with true stick: while stuck the force can take any value in
    /// `[-limit, limit]` (`= mu(0)`); `None` for the others.
    pub fn static_limit(&self) -> Option<f64> {
        match self {
            Friction::Stribeck(s) => Some(s.mu_s()),
            Friction::Cubic(c) => Some(c.mu_0),
            Friction::Table(t) => Some(t.mu_s()),
            Friction::McMillan(_) | Friction::NonHysteretic(_) | Friction::Coulomb => None,
        }
    }

    /// McMillan's surface constants (his two laws only).
    pub fn surface(&self) -> Option<Surface> {
        match self {
            Friction::McMillan(s) | Friction::NonHysteretic(s) => Some(*s),
            _ => None,
        }
    }

    /// The Stribeck law's parameters (that law only).
    pub fn stribeck(&self) -> Option<Stribeck> {
        match self {
            Friction::Stribeck(s) => Some(*s),
            _ => None,
        }
    }

    /// The surface constants of McMillan's two laws, changed by `f` (other laws unchanged).
    pub fn with_surface(self, f: impl FnOnce(&mut Surface)) -> Friction {
        match self {
            Friction::McMillan(mut s) => {
                f(&mut s);
                Friction::McMillan(s)
            }
            Friction::NonHysteretic(mut s) => {
                f(&mut s);
                Friction::NonHysteretic(s)
            }
            other => other,
        }
    }

    /// `mu(s)` and `mu'(s)` at slip speed `s >= 0` of a law with true stick (the force is
    /// `-sgn(v) mu(|v|)` while slipping); `None` for the others.
    #[inline]
    pub fn mu(&self, s: f64) -> Option<(f64, f64)> {
        match self {
            Friction::Stribeck(l) => Some(l.mu(s)),
            Friction::Cubic(l) => Some(l.mu(s)),
            Friction::Table(t) => Some(t.mu(s)),
            Friction::McMillan(_) | Friction::NonHysteretic(_) | Friction::Coulomb => None,
        }
    }

    /// The table of the tabulated law (that law only).
    pub fn table(&self) -> Option<&'static FrictionTable> {
        match self {
            Friction::Table(t) => Some(t),
            _ => None,
        }
    }

    /// The law's family: which algorithms compute it ([`FrictionLaw::family`]).
    pub fn family(&self) -> LawFamily {
        self.kind().family()
    }
}

impl std::fmt::Display for Friction {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.kind().name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The refusal of a small `Phi` names the key, the value and the range in one sentence,
    /// and the why it points to (docs/spec.md's `phi` row) states the orbit's reach, `|x|`
    /// about `1.43 / sin(Phi)` (measured, [`MIN_PHI`]): before, the message called
    /// 1.4/sin(Phi) the orbit's width, where the measured figure is the largest `|x|` it
    /// reaches.
    #[test]
    fn a_small_phi_is_refused_stating_the_orbits_reach() {
        let e = Surface::check_phi(2e-6).unwrap_err().to_string();
        assert!(
            e.contains("phi = 2e-6") && e.contains("[1e-5, pi/2]") && e.contains("docs/spec.md"),
            "{e}"
        );
        let doc = include_str!("../../../docs/spec.md");
        let row = doc
            .lines()
            .find(|l| l.starts_with("| `phi` |"))
            .expect("docs/spec.md has a row for phi");
        assert!(
            row.contains("reaches about `1.43 / sin(phi)`") && !row.contains("wide"),
            "{row}"
        );
        let mut ph = crate::Physical {
            m: 2.0,
            k: 2.0e4,
            c: 4.0,
            v_belt: 0.1,
            friction: crate::FrictionSi::Kinetic {
                mu_k: 0.4,
                surface: Some(crate::SurfaceSi {
                    mu_s: 1e6,
                    tau: 1e-3,
                }),
            },
            load: crate::units::Load::Weight(crate::units::G_STANDARD),
        };
        let e = ph.validate().unwrap_err().to_string();
        assert!(
            e.contains("reaches |x| about 1.43 mu_s/mu_k") && !e.contains("wide"),
            "{e}"
        );
        ph.friction = crate::FrictionSi::Kinetic {
            mu_k: 0.4,
            surface: None,
        };
        assert!(ph.validate().is_ok());
    }
}
