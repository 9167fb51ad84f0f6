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
}

impl FrictionLaw {
    /// The name used on the command line, in specs and in HDF5 attributes.
    pub fn name(self) -> &'static str {
        match self {
            FrictionLaw::McMillan => "mcmillan",
            FrictionLaw::McMillanNonHysteretic => "mcmillan-nonhysteretic",
            FrictionLaw::Coulomb => "coulomb",
        }
    }

    /// All laws, in a fixed order.
    pub const ALL: [FrictionLaw; 3] = [
        FrictionLaw::McMillan,
        FrictionLaw::McMillanNonHysteretic,
        FrictionLaw::Coulomb,
    ];
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

/// Nondimensional parameters of McMillan's oscillator (paper Section 4).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Params {
    /// Friction law.
    pub law: FrictionLaw,
    /// Damping ratio `nu = r / (2 sqrt(m s))`; `nu >= 0` (under-, critically or over-damped).
    pub nu: f64,
    /// Belt speed `lambda = v_B / (mu_k g) sqrt(s/m)`; `0 < lambda <= 1e6`.
    pub lambda: f64,
    /// Characteristic time `tau' = tau / mu_k sqrt(s/m)` of the surfaces; `tau > 0`.
    pub tau: f64,
    /// `Phi = arcsin(mu_k / mu_s)`, in `(0, pi/2]` since `mu_s >= mu_k > 0`.
    pub phi: f64,
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
        }
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

    /// The steady-slip fixed point: `x' = x'' = 0`, so `x* = F(-lambda, 0)`
    /// (`x* = 1` for `lambda > 0`).
    pub fn fixed_point(&self) -> crate::State {
        let f = crate::friction::force(self, -self.lambda, 0.0).force;
        crate::State { x: f, v: 0.0 }
    }

    /// An upper bound on `|F|` over all states: every root of the implicit force equation lies
    /// in `[-bound, bound]`. `|F1| < 1`; `|F2| <= 1 / sin(Phi)` (McMillan) and `|F2| <= 1` on the
    /// slip branches.
    pub fn force_bound(&self) -> f64 {
        match self.law {
            FrictionLaw::Coulomb => 1.0,
            _ => 1.0 + 1.0 / self.phi.sin(),
        }
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
}
