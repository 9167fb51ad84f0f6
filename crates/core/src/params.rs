//! Nondimensional model parameters (paper Section 4, Table 1) and their validation.

use serde::{Deserialize, Serialize};

use crate::error::CoreError;
pub use crate::law::{
    Cubic, Friction, FrictionLaw, FrictionTable, LawFamily, PerV0, Stribeck, Surface,
};

/// Nondimensional parameters of the oscillator `x'' + 2 nu x' + x = F` (paper Section 4).
///
/// Damping ratio and belt speed are common to every law and keep McMillan's names `nu` and
/// `lambda` here (the Stribeck law names them `xi` and `v_d` in specs, flags and files:
/// [`Params::named`]); everything else a law needs is in its [`Friction`] variant.
///
/// Serialised by the law's own names ([`FrictionLaw::keys`]): `{law, nu, lambda, tau, phi}`
/// for McMillan's laws (as always), `{law, xi, v_d, mu_d, mu_sd, v_0, mu_v}` for the
/// Stribeck law. Records written before the Stribeck law had its own names (`nu`, `lambda`
/// and a `stribeck` table) still read.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(into = "ParamsWire", try_from = "ParamsWire")]
pub struct Params {
    /// Friction law with its own parameters.
    pub law: Friction,
    /// Damping ratio `nu = r / (2 sqrt(m s))` (Stribeck: `xi`); `nu >= 0` (under-, critically
    /// or over-damped).
    pub nu: f64,
    /// Belt speed `lambda = v_B / (mu_k g) sqrt(s/m)` (Stribeck: `v_d`); `0 < lambda <= 1e6`.
    pub lambda: f64,
}

/// The serde form of [`Params`]: the law's own keys, each present only for its law (the
/// table law's rows as `friction_table`, `[[s, mu], ...]`).
#[derive(Clone, Debug, Serialize, Deserialize)]
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
    #[serde(default, skip_serializing_if = "Option::is_none")]
    mu_0: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    a1: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    a3: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    friction_table: Option<Vec<[f64; 2]>>,
    /// Read only: the Stribeck parameters as a table (records of earlier builds).
    #[serde(default, skip_serializing)]
    stribeck: Option<Stribeck>,
}

impl From<Params> for ParamsWire {
    fn from(p: Params) -> ParamsWire {
        let mut w = ParamsWire {
            law: p.law.kind(),
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
            mu_0: None,
            a1: None,
            a3: None,
            friction_table: p
                .law
                .table()
                .map(|t| t.rows().into_iter().map(|(s, mu)| [s, mu]).collect()),
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
                "mu_v" => &mut w.mu_v,
                "mu_0" => &mut w.mu_0,
                "a1" => &mut w.a1,
                _ => &mut w.a3,
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
        let table = match &w.friction_table {
            Some(rows) => {
                let rows: Vec<(f64, f64)> = rows.iter().map(|r| (r[0], r[1])).collect();
                Some(FrictionTable::new(&rows).map_err(|e| e.to_string())?)
            }
            None => None,
        };
        Params::from_named_table(w.law, table, |k| match k {
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
            "mu_0" => w.mu_0,
            "a1" => w.a1,
            "a3" => w.a3,
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
    /// Table 1 of the paper: lambda = 3, tau = 0.1 sqrt(10), Phi = 1, with the given nu (a
    /// law of another parameterisation at its own defaults, [`Friction::default_of`]).
    pub fn paper(law: FrictionLaw, nu: f64) -> Params {
        Params {
            law: Friction::default_of(law),
            nu,
            lambda: crate::defaults::LAMBDA,
        }
    }

    /// The Stribeck law with damping ratio `xi` and belt speed `v_d`.
    pub fn stribeck(xi: f64, v_d: f64, s: Stribeck) -> Params {
        Params {
            law: Friction::Stribeck(s),
            nu: xi,
            lambda: v_d,
        }
    }

    /// The law `law` at its defaults: the paper's Table 1 with `nu = 1e-3` (McMillan's laws
    /// and Coulomb), bSTAB's friction case (Stribeck).
    pub fn defaults(law: FrictionLaw) -> Params {
        match law {
            FrictionLaw::Stribeck => Params::bstab(),
            FrictionLaw::Cubic => Params {
                law: Friction::Cubic(Cubic::default()),
                nu: crate::defaults::CUBIC_XI,
                lambda: crate::defaults::CUBIC_V_D,
            },
            FrictionLaw::Table => Params {
                law: Friction::Table(crate::defaults::table()),
                nu: crate::defaults::TABLE_XI,
                lambda: crate::defaults::TABLE_V_D,
            },
            _ => Params::paper(law, crate::defaults::NU),
        }
    }

    /// The law's name.
    pub fn kind(&self) -> FrictionLaw {
        self.law.kind()
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
        let (damping, speed) = (
            n("nu", self.nu, "damping ratio nu", "1"),
            n(
                "lambda",
                self.lambda,
                "belt speed lambda",
                "mu_k g / omega_n (nondimensional)",
            ),
        );
        // The laws with true stick name them as bSTAB does.
        let (xi, v_d) = (
            n("xi", self.nu, "damping ratio xi", "1"),
            n(
                "v_d",
                self.lambda,
                "belt speed v_d",
                "natural-frequency velocity scale",
            ),
        );
        match self.law {
            Friction::Cubic(c) => vec![
                xi,
                v_d,
                n(
                    "mu_0",
                    c.mu_0,
                    "static friction coefficient mu_0 = mu(0)",
                    "1",
                ),
                n(
                    "a1",
                    c.a1,
                    "linear coefficient a1 of mu(s) = mu_0 - a1 s + a3 s^3",
                    "1 / (natural-frequency velocity scale)",
                ),
                n(
                    "a3",
                    c.a3,
                    "cubic coefficient a3 of mu(s) = mu_0 - a1 s + a3 s^3",
                    "1 / (natural-frequency velocity scale)^3",
                ),
            ],
            Friction::Stribeck(s) => vec![
                xi,
                v_d,
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
            // The table is no scalar: stored beside the keys (`friction_table`).
            Friction::Table(_) => vec![xi, v_d],
            Friction::Coulomb => vec![damping, speed],
            Friction::McMillan(c) | Friction::NonHysteretic(c) => vec![
                damping,
                speed,
                n("tau", c.tau, "surface time tau", "1 / omega_n"),
                n("phi", c.phi, "Phi = arcsin(mu_k / mu_s)", "rad"),
            ],
        }
    }

    /// The parameters of `law` from named values (the inverse of [`Params::named`]); `get`
    /// returns `None` for a missing key, reported by name. Not validated. The table law
    /// needs its table: [`Params::from_named_table`] (here it is missing, named
    /// `friction_table`).
    pub fn from_named(
        law: FrictionLaw,
        get: impl FnMut(&'static str) -> Option<f64>,
    ) -> Result<Params, &'static str> {
        Params::from_named_table(law, None, get)
    }

    /// [`Params::from_named`] with the table law's table (`None`, for that law, is the
    /// missing key `friction_table`; ignored for the other laws).
    pub fn from_named_table(
        law: FrictionLaw,
        table: Option<&'static FrictionTable>,
        mut get: impl FnMut(&'static str) -> Option<f64>,
    ) -> Result<Params, &'static str> {
        let mut val = |k: &'static str| get(k).ok_or(k);
        let (damping, speed) = (law.keys()[0], law.keys()[1]);
        let (nu, lambda) = (val(damping)?, val(speed)?);
        let mut surface = || -> Result<Surface, &'static str> {
            Ok(Surface {
                tau: val("tau")?,
                phi: val("phi")?,
            })
        };
        let law = match law {
            FrictionLaw::McMillan => Friction::McMillan(surface()?),
            FrictionLaw::McMillanNonHysteretic => Friction::NonHysteretic(surface()?),
            FrictionLaw::Coulomb => Friction::Coulomb,
            FrictionLaw::Stribeck => Friction::Stribeck(Stribeck {
                mu_d: val("mu_d")?,
                mu_sd: val("mu_sd")?,
                v_0: val("v_0")?,
                mu_v: val("mu_v")?,
            }),
            FrictionLaw::Cubic => Friction::Cubic(Cubic {
                mu_0: val("mu_0")?,
                a1: val("a1")?,
                a3: val("a3")?,
            }),
            FrictionLaw::Table => Friction::Table(table.ok_or("friction_table")?),
        };
        Ok(Params { law, nu, lambda })
    }

    /// The damping name of the law (`nu` or `xi`).
    pub fn damping_key(&self) -> &'static str {
        self.kind().keys()[0]
    }

    /// The belt-speed name of the law (`lambda` or `v_d`).
    pub fn speed_key(&self) -> &'static str {
        self.kind().keys()[1]
    }

    /// Checks every value; the error names the parameter and the value.
    pub fn validate(&self) -> Result<(), CoreError> {
        let bad = CoreError::invalid::<()>;
        match self.law {
            Friction::Stribeck(s) => return self.validate_stribeck(&s),
            Friction::Cubic(c) => {
                self.validate_stick()?;
                return c.validate();
            }
            // The rows were checked when the table was made (FrictionTable::new).
            Friction::Table(_) => return self.validate_stick(),
            _ => {}
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
        match self.law.surface() {
            Some(c) => c.validate(),
            None => Ok(()),
        }
    }

    /// The Stribeck law's checks, naming its keys (`xi`, `v_d`, ...).
    fn validate_stribeck(&self, s: &Stribeck) -> Result<(), CoreError> {
        let bad = CoreError::invalid::<()>;
        self.validate_stick()?;
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

    /// The damping and belt speed of a law with true stick, by their names there.
    fn validate_stick(&self) -> Result<(), CoreError> {
        let bad = CoreError::invalid::<()>;
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
        Ok(())
    }

    /// An upper bound on `|F|` over all states: every root of the implicit force equation lies
    /// in `[-bound, bound]`. `|F1| < 1`; `|F2| <= 1 / sin(Phi)` (McMillan) and `|F2| <= 1` on the
    /// slip branches.
    pub fn force_bound(&self) -> f64 {
        match self.law {
            Friction::Coulomb => 1.0,
            // |F| <= mu(|v|) <= mu_s + mu_v |v| / v_0, and |v| stays below 1e6 (the classifier's
            // divergence radius) plus the belt speed.
            Friction::Stribeck(s) => s.mu_s().max(s.mu_d) + s.mu_v * (1e6 + self.lambda) / s.v_0,
            Friction::McMillan(c) | Friction::NonHysteretic(c) => 1.0 + 1.0 / c.phi.sin(),
            // mu(s) <= mu_0 + a3 s^3 over the same range of slip speeds.
            Friction::Cubic(c) => c.mu_0 + c.a3 * (1e6 + self.lambda).powi(3),
            // The monotone interpolation stays within its rows' values.
            Friction::Table(t) => t.max_mu(),
        }
    }

    /// The effective damping `2 nu - dF/dv` of the fixed point's linearisation, for laws whose
    /// force depends on the slip velocity only (Stribeck): the fixed point repels where it is
    /// negative (`mu'(v_d) < -2 xi`, the falling friction curve beats the damping). `None` for
    /// McMillan's laws (the force depends on the acceleration too; their stability is found by
    /// runs) and Coulomb.
    pub fn fixed_point_damping(&self) -> Option<f64> {
        let (_, dmu) = self.law.mu(self.lambda)?;
        Some(2.0 * self.nu + dmu)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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

    /// `phi = 1e-300` was accepted and every stick-slip run read "diverged": the orbit swings
    /// to about 1.43 / sin(phi), beyond the escape radius 1e6 below phi = 1.4e-6 (measured
    /// figures in `law::MIN_PHI`). The bound is 1e-5, for both of McMillan's laws.
    #[test]
    fn a_static_peak_beyond_the_escape_radius_is_refused() {
        for law in [FrictionLaw::McMillan, FrictionLaw::McMillanNonHysteretic] {
            let with = |phi| Params {
                law: Friction::default_of(law).with_surface(|s| s.phi = phi),
                ..Params::paper(law, 1e-3)
            };
            for phi in [1e-300, 1e-6, 9.99e-6, 0.0, -1.0, f64::NAN, 1.6] {
                let e = with(phi).validate().unwrap_err().to_string();
                assert!(
                    e.contains("invalid phi") && e.contains("[1e-5, pi/2]"),
                    "{e}"
                );
            }
            for phi in [1e-5, 1e-3, 1.0, std::f64::consts::FRAC_PI_2] {
                assert!(with(phi).validate().is_ok(), "{law} {phi}");
            }
        }
    }
}
