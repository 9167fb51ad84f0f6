//! The Stribeck law with true stick (bSTAB's friction case, Stender et al. 2021): its
//! parameters, defaults, `mu`, checks and names.

use serde::{Deserialize, Serialize};

use crate::error::CoreError;
use crate::params::Named;

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
    /// bSTAB's friction case (Stender et al., Nonlinear Dynamics 2021): `mu_d = 0.5`,
    /// `mu_sd = 2`, `v_0 = 0.5`, `mu_v = 0`.
    fn default() -> Self {
        Stribeck {
            mu_d: 0.5,
            mu_sd: 2.0,
            v_0: 0.5,
            mu_v: 0.0,
        }
    }
}

impl Stribeck {
    /// The law's keys in specs, flags and files, damping and belt speed first.
    pub const KEYS: [&'static str; 6] = ["xi", "v_d", "mu_d", "mu_sd", "v_0", "mu_v"];
    /// bSTAB's friction case: damping ratio `xi`.
    pub const XI: f64 = 0.05;
    /// bSTAB's friction case: belt speed `v_d`.
    pub const V_D: f64 = 1.5;

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

    /// Checks each coefficient; the error names the key.
    pub fn validate(&self) -> Result<(), CoreError> {
        let bad = CoreError::invalid::<()>;
        if !self.mu_d.is_finite() || self.mu_d <= 0.0 || self.mu_d > 1e6 {
            return bad(
                "mu_d",
                self.mu_d,
                "a dynamic friction coefficient in (0, 1e6]",
            );
        }
        if !self.mu_sd.is_finite() || self.mu_sd < 1.0 || self.mu_sd > 1e6 {
            return bad(
                "mu_sd",
                self.mu_sd,
                "a static-to-dynamic ratio in [1, 1e6] (static friction is at least dynamic)",
            );
        }
        if !self.v_0.is_finite() || self.v_0 <= 0.0 || self.v_0 > 1e12 {
            return bad("v_0", self.v_0, "a reference velocity in (0, 1e12]");
        }
        if !self.mu_v.is_finite() || self.mu_v < 0.0 || self.mu_v > 1e6 {
            return bad("mu_v", self.mu_v, "a viscous coefficient in [0, 1e6]");
        }
        Ok(())
    }

    /// A bound on `mu` at belt speed `v_d`: `mu(|v|) <= mu_s + mu_v |v| / v_0`, and `|v|` stays
    /// below `1e6` (the classifier's divergence radius) plus the belt speed.
    pub fn force_bound(&self, v_d: f64) -> f64 {
        self.mu_s().max(self.mu_d) + self.mu_v * (1e6 + v_d) / self.v_0
    }

    /// The law's own values with their names (after `xi` and `v_d`).
    pub fn named(&self) -> Vec<Named> {
        vec![
            Named::new("mu_d", self.mu_d, "dynamic friction coefficient mu_d", "1"),
            Named::new("mu_sd", self.mu_sd, "static-to-dynamic ratio mu_sd", "1"),
            Named::new(
                "v_0",
                self.v_0,
                "Stribeck reference velocity v_0",
                "natural-frequency velocity scale",
            ),
            Named::new("mu_v", self.mu_v, "viscous strengthening mu_v", "1"),
        ]
    }

    /// The inverse of [`Stribeck::named`]: the first missing key is the error.
    pub fn from_named(
        mut val: impl FnMut(&'static str) -> Result<f64, &'static str>,
    ) -> Result<Stribeck, &'static str> {
        Ok(Stribeck {
            mu_d: val("mu_d")?,
            mu_sd: val("mu_sd")?,
            v_0: val("v_0")?,
            mu_v: val("mu_v")?,
        })
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
}
