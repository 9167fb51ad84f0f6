//! The cubic law with true stick (Popp and Stelter; Thomsen 1999): its parameters, defaults,
//! `mu`, checks and names.

use serde::{Deserialize, Serialize};

use crate::error::CoreError;
use crate::params::Named;

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

// The defaults: mu(s) = mu_0 - a1 s + a3 s^3 at the shape used by Thomsen (J. Sound Vib.
// 228(5), 1999) and Thomsen and Fidlin (Int. J. Non-Linear Mech. 38, 2003): static
// coefficient 0.4, least coefficient mu_m = 0.25 at slip speed v_m = 0.5, so
// a1 = (3/2) (0.4 - mu_m) / v_m = 0.45 and a3 = (1/2) (0.4 - mu_m) / v_m^3 = 0.6, with
// damping ratio 0.05. (As recalled from those papers; not re-read here.) The belt speed 0.3
// lies on the falling part of mu (below its minimum at 0.5), where the fixed point repels
// (2 xi + mu'(0.3) = -0.188) and every start squeals. No belt speed of this shape was found
// where steady slip and stick-slip coexist: the landscape turns from stick-slip only to
// steady slip only at the fixed point's loss of stability, v_d = 0.441 (scanned on a grid
// of 0.0005; `crates/core/tests/model/cubic.rs`, `landscape_and_labels`).
impl Default for Cubic {
    /// Thomsen's shape: `mu_0 = 0.4`, `a1 = 0.45`, `a3 = 0.6` (the comment above says why).
    fn default() -> Self {
        Cubic {
            mu_0: 0.4,
            a1: 0.45,
            a3: 0.6,
        }
    }
}

impl Cubic {
    /// The law's keys in specs, flags and files, damping and belt speed first.
    pub const KEYS: [&'static str; 5] = ["xi", "v_d", "mu_0", "a1", "a3"];
    /// Default damping ratio `xi` (Thomsen's, above [`Cubic::default`]).
    pub const XI: f64 = 0.05;
    /// Default belt speed `v_d`, on the falling part of `mu` (above [`Cubic::default`]).
    pub const V_D: f64 = 0.3;

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

    /// A bound on `mu` at belt speed `v_d`: `mu(s) <= mu_0 + a3 s^3`, and the slip speed stays
    /// below `1e6` (the classifier's divergence radius) plus the belt speed.
    pub fn force_bound(&self, v_d: f64) -> f64 {
        self.mu_0 + self.a3 * (1e6 + v_d).powi(3)
    }

    /// The law's own values with their names (after `xi` and `v_d`).
    pub fn named(&self) -> Vec<Named> {
        vec![
            Named::new(
                "mu_0",
                self.mu_0,
                "static friction coefficient mu_0 = mu(0)",
                "1",
            ),
            Named::new(
                "a1",
                self.a1,
                "linear coefficient a1 of mu(s) = mu_0 - a1 s + a3 s^3",
                "1 / (natural-frequency velocity scale)",
            ),
            Named::new(
                "a3",
                self.a3,
                "cubic coefficient a3 of mu(s) = mu_0 - a1 s + a3 s^3",
                "1 / (natural-frequency velocity scale)^3",
            ),
        ]
    }

    /// The inverse of [`Cubic::named`]: the first missing key is the error.
    pub fn from_named(
        mut val: impl FnMut(&'static str) -> Result<f64, &'static str>,
    ) -> Result<Cubic, &'static str> {
        Ok(Cubic {
            mu_0: val("mu_0")?,
            a1: val("a1")?,
            a3: val("a3")?,
        })
    }
}
