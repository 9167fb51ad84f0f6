//! Nondimensional model parameters (paper Section 4, Table 1) and their validation.

use serde::{Deserialize, Serialize};

use crate::error::CoreError;

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
}

impl FrictionLaw {
    /// The name used on the command line, in specs and in HDF5 attributes.
    pub fn name(self) -> &'static str {
        match self {
            FrictionLaw::McMillan => "mcmillan",
            FrictionLaw::McMillanNonHysteretic => "mcmillan-nonhysteretic",
            FrictionLaw::Coulomb => "coulomb",
            FrictionLaw::Stribeck => "stribeck",
        }
    }

    /// McMillan's parameterisation (`nu`, `lambda`, `tau`, `phi`): the three laws of the paper.
    pub const MCMILLAN: [FrictionLaw; 3] = [
        FrictionLaw::McMillan,
        FrictionLaw::McMillanNonHysteretic,
        FrictionLaw::Coulomb,
    ];

    /// All laws, in a fixed order.
    pub const ALL: [FrictionLaw; 4] = [
        FrictionLaw::McMillan,
        FrictionLaw::McMillanNonHysteretic,
        FrictionLaw::Coulomb,
        FrictionLaw::Stribeck,
    ];

    /// Whether the law sticks with a static limit, stepped with located stick events
    /// ([`crate::stick`]).
    pub fn has_true_stick(self) -> bool {
        self == FrictionLaw::Stribeck
    }

    /// The names of the law's own parameters, damping and belt speed first, as they appear in
    /// specs, flags and files ([`Params::named`] gives their values).
    pub fn keys(self) -> &'static [&'static str] {
        match self {
            FrictionLaw::Stribeck => &["xi", "v_d", "mu_d", "mu_sd", "v_0", "mu_v"],
            _ => &["nu", "lambda", "tau", "phi"],
        }
    }
}

impl std::str::FromStr for FrictionLaw {
    type Err = CoreError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        FrictionLaw::ALL
            .into_iter()
            .find(|l| l.name() == s)
            .ok_or_else(|| CoreError::UnknownLaw(s.to_string()))
    }
}

impl std::fmt::Display for FrictionLaw {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
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

/// Nondimensional parameters of the oscillator `x'' + 2 nu x' + x = F` (paper Section 4).
///
/// Damping ratio and belt speed are common to every law (the Stribeck law names them `xi`
/// and `v_d`); `tau` and `phi` belong to McMillan's laws, [`Stribeck`] to the Stribeck law
/// (present exactly when `law = stribeck`).
///
/// Serialised by the law's own names ([`FrictionLaw::keys`]): `{law, nu, lambda, tau, phi}`
/// for McMillan's laws (as always), `{law, xi, v_d, mu_d, mu_sd, v_0, mu_v}` for the
/// Stribeck law. Records written before the Stribeck law had its own names (`nu`, `lambda`
/// and a `stribeck` table) still read.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(into = "ParamsWire", try_from = "ParamsWire")]
pub struct Params {
    /// Friction law.
    pub law: FrictionLaw,
    /// Damping ratio `nu = r / (2 sqrt(m s))` (Stribeck: `xi`); `nu >= 0` (under-, critically
    /// or over-damped).
    pub nu: f64,
    /// Belt speed `lambda = v_B / (mu_k g) sqrt(s/m)` (Stribeck: `v_d`); `0 < lambda <= 1e6`.
    pub lambda: f64,
    /// Characteristic time `tau' = tau / mu_k sqrt(s/m)` of the surfaces; `tau > 0`.
    pub tau: f64,
    /// `Phi = arcsin(mu_k / mu_s)`, in `(0, pi/2]` since `mu_s >= mu_k > 0`.
    pub phi: f64,
    /// The Stribeck law's parameters (`Some` exactly when `law = stribeck`).
    pub stribeck: Option<Stribeck>,
}

/// The serde form of [`Params`]: the law's own keys, each present only for its law.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
struct ParamsWire {
    law: FrictionLaw,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    nu: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    lambda: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    tau: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    phi: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    xi: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    v_d: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    mu_d: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    mu_sd: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    v_0: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    mu_v: Option<f64>,
    /// Read only: the Stribeck parameters as a table (records of earlier builds).
    #[serde(default, skip_serializing)]
    stribeck: Option<Stribeck>,
}

impl From<Params> for ParamsWire {
    fn from(p: Params) -> ParamsWire {
        let mut w = ParamsWire {
            law: p.law,
            nu: None,
            lambda: None,
            tau: None,
            phi: None,
            xi: None,
            v_d: None,
            mu_d: None,
            mu_sd: None,
            v_0: None,
            mu_v: None,
            stribeck: None,
        };
        for n in p.named() {
            let slot = match n.name {
                "nu" => &mut w.nu,
                "lambda" => &mut w.lambda,
                "tau" => &mut w.tau,
                "phi" => &mut w.phi,
                "xi" => &mut w.xi,
                "v_d" => &mut w.v_d,
                "mu_d" => &mut w.mu_d,
                "mu_sd" => &mut w.mu_sd,
                "v_0" => &mut w.v_0,
                _ => &mut w.mu_v,
            };
            *slot = Some(n.value);
        }
        w
    }
}

impl TryFrom<ParamsWire> for Params {
    type Error = String;
    fn try_from(w: ParamsWire) -> Result<Params, String> {
        let legacy = w.stribeck;
        Params::from_named(w.law, |k| match k {
            "nu" => w.nu,
            "lambda" => w.lambda,
            "tau" => w.tau,
            "phi" => w.phi,
            "xi" => w.xi.or(w.nu),
            "v_d" => w.v_d.or(w.lambda),
            "mu_d" => w.mu_d.or(legacy.map(|s| s.mu_d)),
            "mu_sd" => w.mu_sd.or(legacy.map(|s| s.mu_sd)),
            "v_0" => w.v_0.or(legacy.map(|s| s.v_0)),
            "mu_v" => w.mu_v.or(legacy.map(|s| s.mu_v)),
            _ => None,
        })
        .map_err(|k| format!("missing parameter `{k}` of law {}", w.law))
    }
}

/// One named parameter of a law, as specs, flags, files and `info` show it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Named {
    /// The key (`nu`, `xi`, `mu_sd`, ...).
    pub name: &'static str,
    /// Its value.
    pub value: f64,
    /// A long name for files and plots.
    pub long_name: &'static str,
    /// Units (all nondimensional; the scale is named).
    pub units: &'static str,
}

impl Params {
    /// Table 1 of the paper: lambda = 3, tau = 0.1 sqrt(10), Phi = 1, with the given nu.
    pub fn paper(law: FrictionLaw, nu: f64) -> Params {
        Params {
            law,
            nu,
            lambda: crate::defaults::LAMBDA,
            tau: crate::defaults::TAU,
            phi: crate::defaults::PHI,
            stribeck: None,
        }
    }

    /// The Stribeck law with damping ratio `xi` and belt speed `v_d` (`tau`, `phi` at their
    /// defaults, unused).
    pub fn stribeck(xi: f64, v_d: f64, s: Stribeck) -> Params {
        Params {
            law: FrictionLaw::Stribeck,
            nu: xi,
            lambda: v_d,
            tau: crate::defaults::TAU,
            phi: crate::defaults::PHI,
            stribeck: Some(s),
        }
    }

    /// bSTAB's friction case: `xi = 0.05`, `v_d = 1.5`, `mu_sd = 2`, `mu_d = 0.5`,
    /// `v_0 = 0.5`, `mu_v = 0`.
    pub fn bstab() -> Params {
        Params::stribeck(
            crate::defaults::XI,
            crate::defaults::V_D,
            Stribeck::default(),
        )
    }

    /// The law's own parameters with their names ([`FrictionLaw::keys`] order).
    pub fn named(&self) -> Vec<Named> {
        let n = |name, value, long_name, units| Named {
            name,
            value,
            long_name,
            units,
        };
        match (self.law, self.stribeck) {
            (FrictionLaw::Stribeck, Some(s)) => vec![
                n("xi", self.nu, "damping ratio xi", "1"),
                n(
                    "v_d",
                    self.lambda,
                    "belt speed v_d",
                    "natural-frequency velocity scale",
                ),
                n("mu_d", s.mu_d, "dynamic friction coefficient mu_d", "1"),
                n("mu_sd", s.mu_sd, "static-to-dynamic ratio mu_sd", "1"),
                n(
                    "v_0",
                    s.v_0,
                    "Stribeck reference velocity v_0",
                    "natural-frequency velocity scale",
                ),
                n("mu_v", s.mu_v, "viscous strengthening mu_v", "1"),
            ],
            _ => vec![
                n("nu", self.nu, "damping ratio nu", "1"),
                n(
                    "lambda",
                    self.lambda,
                    "belt speed lambda",
                    "mu_k g / omega_n (nondimensional)",
                ),
                n("tau", self.tau, "surface time tau", "1 / omega_n"),
                n("phi", self.phi, "Phi = arcsin(mu_k / mu_s)", "rad"),
            ],
        }
    }

    /// The parameters of `law` from named values (the inverse of [`Params::named`]); `get`
    /// returns `None` for a missing key, reported by name. Not validated.
    pub fn from_named(
        law: FrictionLaw,
        mut get: impl FnMut(&'static str) -> Option<f64>,
    ) -> Result<Params, &'static str> {
        let mut val = |k: &'static str| get(k).ok_or(k);
        Ok(if law == FrictionLaw::Stribeck {
            let (xi, v_d) = (val("xi")?, val("v_d")?);
            let s = Stribeck {
                mu_d: val("mu_d")?,
                mu_sd: val("mu_sd")?,
                v_0: val("v_0")?,
                mu_v: val("mu_v")?,
            };
            Params::stribeck(xi, v_d, s)
        } else {
            Params {
                law,
                nu: val("nu")?,
                lambda: val("lambda")?,
                tau: val("tau")?,
                phi: val("phi")?,
                stribeck: None,
            }
        })
    }

    /// The damping name of the law (`nu` or `xi`).
    pub fn damping_key(&self) -> &'static str {
        self.law.keys()[0]
    }

    /// The belt-speed name of the law (`lambda` or `v_d`).
    pub fn speed_key(&self) -> &'static str {
        self.law.keys()[1]
    }

    /// Checks every value; the error names the parameter and the value.
    pub fn validate(&self) -> Result<(), CoreError> {
        let bad = |name: &'static str, value: f64, expected: &'static str| {
            Err(CoreError::InvalidParameter {
                name,
                value,
                expected,
            })
        };
        if self.law == FrictionLaw::Stribeck {
            return self.validate_stribeck();
        }
        if self.stribeck.is_some() {
            return Err(CoreError::ForeignParameters {
                law: self.law.name(),
                keys: "mu_d, mu_sd, v_0, mu_v",
            });
        }
        if !self.nu.is_finite() || self.nu < 0.0 {
            return bad("nu", self.nu, "a finite damping ratio >= 0");
        }
        if self.nu > 1e6 {
            return bad("nu", self.nu, "a damping ratio <= 1e6");
        }
        // A belt at rest or reversed is outside the model as written: there is no steady slip
        // at x' = 0 (the fixed point's slip velocity -lambda vanishes or changes sign), the law
        // chatters about v = 0 (a "stick-slip" at about 14 times the natural frequency at
        // lambda = 0), and labels change with dt (MODEL.md, issue 9).
        if !self.lambda.is_finite() || self.lambda <= 0.0 || self.lambda > 1e6 {
            return bad(
                "lambda",
                self.lambda,
                "a belt speed in (0, 1e6] (a belt at rest or reversed is outside the model: \
                 the law chatters about zero slip and labels depend on dt)",
            );
        }
        if !self.tau.is_finite() || self.tau <= 0.0 {
            return bad("tau", self.tau, "a finite time > 0");
        }
        if !self.phi.is_finite() || self.phi <= 0.0 || self.phi > std::f64::consts::FRAC_PI_2 {
            return bad(
                "phi",
                self.phi,
                "an angle in (0, pi/2] (Phi = arcsin(mu_k/mu_s))",
            );
        }
        Ok(())
    }

    /// The Stribeck law's checks, naming its keys (`xi`, `v_d`, ...).
    fn validate_stribeck(&self) -> Result<(), CoreError> {
        let bad = |name: &'static str, value: f64, expected: &'static str| {
            Err(CoreError::InvalidParameter {
                name,
                value,
                expected,
            })
        };
        let Some(s) = self.stribeck else {
            return Err(CoreError::MissingParameters {
                law: "stribeck",
                keys: "mu_d, mu_sd, v_0, mu_v",
            });
        };
        if !self.nu.is_finite() || self.nu < 0.0 || self.nu > 1e6 {
            return bad("xi", self.nu, "a finite damping ratio in [0, 1e6]");
        }
        if !self.lambda.is_finite() || self.lambda <= 0.0 || self.lambda > 1e6 {
            return bad(
                "v_d",
                self.lambda,
                "a belt speed in (0, 1e6] (stick means moving with the belt; a belt at rest \
                 has no steady slip)",
            );
        }
        if !s.mu_d.is_finite() || s.mu_d <= 0.0 || s.mu_d > 1e6 {
            return bad("mu_d", s.mu_d, "a dynamic friction coefficient in (0, 1e6]");
        }
        if !s.mu_sd.is_finite() || s.mu_sd < 1.0 || s.mu_sd > 1e6 {
            return bad(
                "mu_sd",
                s.mu_sd,
                "a static-to-dynamic ratio in [1, 1e6] (static friction is at least dynamic)",
            );
        }
        if !s.v_0.is_finite() || s.v_0 <= 0.0 || s.v_0 > 1e12 {
            return bad("v_0", s.v_0, "a reference velocity in (0, 1e12]");
        }
        if !s.mu_v.is_finite() || s.mu_v < 0.0 || s.mu_v > 1e6 {
            return bad("mu_v", s.mu_v, "a viscous coefficient in [0, 1e6]");
        }
        Ok(())
    }

    /// The steady-slip fixed point: `x' = x'' = 0`, so `x* = F(-lambda, 0)`
    /// (`x* = 1` for `lambda > 0` under McMillan's laws, `x* = mu(v_d)` under Stribeck's).
    pub fn fixed_point(&self) -> crate::State {
        let f = crate::friction::force(self, -self.lambda, 0.0).force;
        crate::State { x: f, v: 0.0 }
    }

    /// An upper bound on `|F|` over all states: every root of the implicit force equation lies
    /// in `[-bound, bound]`. `|F1| < 1`; `|F2| <= 1 / sin(Phi)` (McMillan) and `|F2| <= 1` on the
    /// slip branches.
    pub fn force_bound(&self) -> f64 {
        match (self.law, self.stribeck) {
            (FrictionLaw::Coulomb, _) => 1.0,
            // |F| <= mu(|v|) <= mu_s + mu_v |v| / v_0, and |v| stays below 1e6 (the classifier's
            // divergence radius) plus the belt speed.
            (FrictionLaw::Stribeck, Some(s)) => {
                s.mu_s().max(s.mu_d) + s.mu_v * (1e6 + self.lambda) / s.v_0
            }
            _ => 1.0 + 1.0 / self.phi.sin(),
        }
    }

    /// The effective damping `2 nu - dF/dv` of the fixed point's linearisation, for laws whose
    /// force depends on the slip velocity only (Stribeck): the fixed point repels where it is
    /// negative (`mu'(v_d) < -2 xi`, the falling friction curve beats the damping). `None` for
    /// McMillan's laws (the force depends on the acceleration too; their stability is found by
    /// runs) and Coulomb.
    pub fn fixed_point_damping(&self) -> Option<f64> {
        let s = self.stribeck?;
        let (_, dmu) = s.mu(self.lambda);
        Some(2.0 * self.nu + dmu)
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

    /// lambda <= 0 is refused with the reason; the smallest positive speeds are accepted.
    #[test]
    fn belt_at_rest_or_reversed_is_refused() {
        for lambda in [0.0, -0.0, -3.0, f64::NAN, 2e6] {
            let p = Params {
                lambda,
                ..Params::paper(FrictionLaw::McMillan, 1e-3)
            };
            let e = p.validate().unwrap_err().to_string();
            assert!(e.contains("lambda") && e.contains("(0, 1e6]"), "{e}");
        }
        let e = Params {
            lambda: 0.0,
            ..Params::paper(FrictionLaw::McMillan, 1e-3)
        }
        .validate()
        .unwrap_err()
        .to_string();
        assert!(e.contains("belt at rest or reversed"), "{e}");
        for lambda in [1e-6, 0.5, 3.0, 1e6] {
            let p = Params {
                lambda,
                ..Params::paper(FrictionLaw::McMillan, 1e-3)
            };
            assert!(p.validate().is_ok(), "{lambda}");
        }
    }
}
