//! The friction laws and their own parameters: [`Friction`], one enum whose variants carry
//! what each law needs (and nothing else), and [`FrictionLaw`], the law's name alone (what a
//! spec's `law = "..."`, `--law` and the files' `law` attribute give before the parameters
//! are read).

use serde::{Deserialize, Serialize};

use crate::error::CoreError;
pub use crate::table::FrictionTable;

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
            FrictionLaw::Stribeck => &["xi", "v_d", "mu_d", "mu_sd", "v_0", "mu_v"],
            FrictionLaw::Cubic => &["xi", "v_d", "mu_0", "a1", "a3"],
            // The table itself is no scalar key (`friction_table`, `friction_csv`).
            FrictionLaw::Table => &["xi", "v_d"],
            // Coulomb's force has no surface time and no static limit of its own.
            FrictionLaw::Coulomb => &["nu", "lambda"],
            FrictionLaw::McMillan | FrictionLaw::McMillanNonHysteretic => {
                &["nu", "lambda", "tau", "phi"]
            }
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
    /// [`crate::defaults::table`]).
    pub fn default_of(kind: FrictionLaw) -> Friction {
        match kind {
            FrictionLaw::McMillan => Friction::McMillan(Surface::default()),
            FrictionLaw::McMillanNonHysteretic => Friction::NonHysteretic(Surface::default()),
            FrictionLaw::Coulomb => Friction::Coulomb,
            FrictionLaw::Stribeck => Friction::Stribeck(Stribeck::default()),
            FrictionLaw::Cubic => Friction::Cubic(Cubic::default()),
            FrictionLaw::Table => Friction::Table(crate::defaults::table()),
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
    pub fn mu(&self, s: f64) -> Option<(f64, f64)> {
        match self {
            Friction::Stribeck(l) => Some(l.mu(s)),
            Friction::Cubic(l) => Some(l.mu(s)),
            Friction::Table(t) => Some(t.mu(s)),
            _ => None,
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

/// The Stribeck law's own parameters (bSTAB's friction case): the friction coefficient
/// while slipping at speed `s = |v|` is
///
/// ```text
/// mu(s) = mu_d + mu_d (mu_sd - 1) exp(-s / v_0) + mu_v s / v_0,    static limit mu_s = mu_d mu_sd
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Stribeck {
    /// Dynamic (kinetic) coefficient `mu_d > 0`.
    pub mu_d: f64,
    /// Static-to-dynamic ratio `mu_sd >= 1`.
    pub mu_sd: f64,
    /// Reference slip velocity of the exponential decay, `v_0 > 0`.
    pub v_0: f64,
    /// Linear viscous strengthening `mu_v >= 0`.
    pub mu_v: f64,
}

impl Default for Stribeck {
    /// bSTAB's friction case.
    fn default() -> Self {
        Stribeck {
            mu_d: crate::defaults::MU_D,
            mu_sd: crate::defaults::MU_SD,
            v_0: crate::defaults::V_0,
            mu_v: crate::defaults::MU_V,
        }
    }
}

impl Stribeck {
    /// The static limit `mu_s = mu_d mu_sd` (`= mu(0)`).
    pub fn mu_s(&self) -> f64 {
        self.mu_d * self.mu_sd
    }

    /// `mu(s)` and `mu'(s)` for a slip speed `s >= 0`.
    #[inline]
    pub fn mu(&self, s: f64) -> (f64, f64) {
        self.mu_by(s, &PerV0::new(self.v_0))
    }

    /// [`Stribeck::mu`] with the divisions by `v_0` done by `per` (built once per law: the
    /// stepper's hot path).
    #[inline]
    pub fn mu_by(&self, s: f64, per: &PerV0) -> (f64, f64) {
        let amp = self.mu_d * (self.mu_sd - 1.0);
        let e = per.of(-s).exp();
        (
            self.mu_d + amp * e + per.of(self.mu_v * s),
            per.of(self.mu_v - amp * e),
        )
    }
}

/// The cubic law's own parameters (Popp and Stelter; Thomsen 1999): the friction
/// coefficient while slipping at speed `s = |v|` is
///
/// ```text
/// mu(s) = mu_0 - a1 s + a3 s^3,    static limit mu_0 = mu(0)
/// ```
///
/// falling from `mu_0` to its least value `mu_0 - (2 a1 / 3) sqrt(a1 / (3 a3))` at
/// `s = sqrt(a1 / (3 a3))`, then rising. The static limit is named `mu_0` (Thomsen's `mu_s`):
/// `mu_s` is the physical system's static coefficient in specs and flags.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Cubic {
    /// Static limit `mu_0 > 0`.
    pub mu_0: f64,
    /// Linear (falling) coefficient `a1 >= 0`.
    pub a1: f64,
    /// Cubic (rising) coefficient `a3 >= 0`.
    pub a3: f64,
}

impl Default for Cubic {
    /// Thomsen's shape ([`crate::defaults::CUBIC_MU_0`]).
    fn default() -> Self {
        Cubic {
            mu_0: crate::defaults::CUBIC_MU_0,
            a1: crate::defaults::CUBIC_A1,
            a3: crate::defaults::CUBIC_A3,
        }
    }
}

impl Cubic {
    /// `mu(s)` and `mu'(s)` for a slip speed `s >= 0`.
    #[inline]
    pub fn mu(&self, s: f64) -> (f64, f64) {
        (
            self.mu_0 - self.a1 * s + self.a3 * s * s * s,
            -self.a1 + 3.0 * self.a3 * s * s,
        )
    }

    /// Checks each coefficient and that `mu` stays positive for every slip speed (a
    /// friction coefficient that changes sign would drive the block, not hold it); the error
    /// names the key.
    pub fn validate(&self) -> Result<(), CoreError> {
        let bad = CoreError::invalid::<()>;
        if !self.mu_0.is_finite() || self.mu_0 <= 0.0 || self.mu_0 > 1e6 {
            return bad(
                "mu_0",
                self.mu_0,
                "a static friction coefficient in (0, 1e6]",
            );
        }
        if !self.a1.is_finite() || self.a1 < 0.0 || self.a1 > 1e6 {
            return bad("a1", self.a1, "a linear coefficient in [0, 1e6]");
        }
        if !self.a3.is_finite() || self.a3 < 0.0 || self.a3 > 1e6 {
            return bad("a3", self.a3, "a cubic coefficient in [0, 1e6]");
        }
        if self.least().is_nan() || self.least() <= 0.0 {
            return bad(
                "a1",
                self.a1,
                "a coefficient that keeps mu(s) = mu_0 - a1 s + a3 s^3 positive for every slip \
                 speed s >= 0: its least value mu_0 - (2 a1 / 3) sqrt(a1 / (3 a3)) must be > 0 \
                 (lower a1 or raise a3 or mu_0)",
            );
        }
        Ok(())
    }

    /// The least value of `mu` over `s >= 0`: `mu_0 - (2 a1 / 3) sqrt(a1 / (3 a3))` (where
    /// `mu' = 0`), `mu_0` when `a1 = 0`, `-inf` when `a3 = 0 < a1` (`mu` falls for ever).
    pub fn least(&self) -> f64 {
        if self.a1 == 0.0 {
            self.mu_0
        } else if self.a3 == 0.0 {
            f64::NEG_INFINITY
        } else {
            self.mu_0 - 2.0 * self.a1 / 3.0 * (self.a1 / (3.0 * self.a3)).sqrt()
        }
    }
}

/// Division by `v_0`, as a multiplication by `1 / v_0` where that gives the same bits: when
/// `v_0` is a power of two its reciprocal is exact, and `x / v_0` and `x * (1 / v_0)` are then
/// both the correctly rounded value of the same real number (IEEE 754 rounds each operation
/// correctly, overflow and subnormal results included). For any other `v_0` the reciprocal is
/// rounded and the product could differ in the last bit, so it divides. A division sits on
/// the critical path of every slip solve (before the `exp`); bSTAB's `v_0 = 0.5` takes the
/// multiplication.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PerV0 {
    v_0: f64,
    /// `1 / v_0` when it is exact.
    recip: Option<f64>,
}

impl PerV0 {
    /// The division by `v_0`.
    pub fn new(v_0: f64) -> PerV0 {
        const MANTISSA: u64 = (1 << 52) - 1;
        let r = 1.0 / v_0;
        let exact = v_0.is_normal() && r.is_normal() && v_0.to_bits() & MANTISSA == 0;
        PerV0 {
            v_0,
            recip: exact.then_some(r),
        }
    }

    /// `x / v_0`.
    #[inline]
    pub fn of(&self, x: f64) -> f64 {
        match self.recip {
            Some(r) => x * r,
            None => x / self.v_0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `PerV0` multiplies only where that is the division bit for bit: powers of two (bSTAB's
    /// 0.5, and 1, 2, 2^-10) take the exact reciprocal, other values (0.3, 0.75) divide.
    #[test]
    fn per_v0_is_the_division_bit_for_bit() {
        for v_0 in [0.5, 1.0, 2.0, 0.0009765625, 0.3, 0.75] {
            let per = PerV0::new(v_0);
            assert_eq!(
                per.recip.is_some(),
                [0.5, 1.0, 2.0, 0.0009765625].contains(&v_0)
            );
            // Values over many binades, both signs, and the ends of the range.
            let mut x = 1e-300f64;
            while x < 1e300 {
                for y in [x, -x, x * 1.234_567_891, f64::MIN_POSITIVE * 0.75] {
                    assert_eq!(per.of(y).to_bits(), (y / v_0).to_bits(), "{y} / {v_0}");
                }
                x *= 3.7;
            }
        }
        let s = Stribeck::default();
        for slip in [0.0, 1e-9, 0.3, 1.7, 40.0] {
            let (mu, dmu) = s.mu(slip);
            let amp = s.mu_d * (s.mu_sd - 1.0);
            let e = (-slip / s.v_0).exp();
            let want = (
                s.mu_d + amp * e + s.mu_v * slip / s.v_0,
                (s.mu_v - amp * e) / s.v_0,
            );
            assert_eq!(
                (mu.to_bits(), dmu.to_bits()),
                (want.0.to_bits(), want.1.to_bits())
            );
        }
    }

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
