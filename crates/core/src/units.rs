//! Physical units: the paper's scaling between the physical system and [`Params`].
//!
//! McMillan (1997) Section 4 nondimensionalises `m x'' + c x' + k x = F` with
//!
//! ```text
//! omega_0 = sqrt(k / m)                      (rad/s; the undamped natural frequency)
//! t'      = omega_0 t
//! x'      = (k / m) x / (mu_k g)             (so a length unit is mu_k g / omega_0^2)
//! nu      = c / (2 sqrt(m k))                (damping ratio)
//! lambda  = (v_B / (mu_k g)) omega_0         (belt speed)
//! tau'    = (tau / mu_k) omega_0             (characteristic time of the surfaces)
//! Phi     = arcsin(mu_k / mu_s)
//! ```
//!
//! [`Physical`] holds the physical system, [`Physical::params`] converts it, and
//! [`Scales`] turns nondimensional figures back into SI: lengths in m, velocities in m/s,
//! times in s, angular frequencies in Hz, damping ratios in N s/m.

use serde::{Deserialize, Serialize};

use crate::error::CoreError;
use crate::params::{Friction, FrictionLaw, Params, Surface};

/// Standard gravity, the default of `g` (m/s^2).
pub const G_STANDARD: f64 = 9.81;

/// A physical friction oscillator in SI units.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Physical {
    /// Mass `m` (kg).
    pub m: f64,
    /// Spring stiffness `k` (N/m).
    pub k: f64,
    /// Dashpot coefficient `c` (N s/m).
    pub c: f64,
    /// Belt speed `v_B` (m/s).
    pub v_belt: f64,
    /// Kinetic friction coefficient `mu_k`.
    pub mu_k: f64,
    /// "Static" friction coefficient `mu_s > mu_k`.
    pub mu_s: f64,
    /// Characteristic time of the surfaces `tau` (s).
    pub tau: f64,
    /// Gravitational acceleration `g` (m/s^2).
    pub g: f64,
}

/// SI size of one nondimensional unit, for one physical system.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Scales {
    /// Undamped natural angular frequency `omega_0 = sqrt(k/m)` (rad/s).
    pub omega0: f64,
    /// Seconds per nondimensional time unit, `1 / omega_0`.
    pub time: f64,
    /// Metres per nondimensional length unit, `mu_k g / omega_0^2`.
    pub length: f64,
    /// Metres per second per nondimensional velocity unit, `mu_k g / omega_0`.
    pub velocity: f64,
    /// N s/m per unit of damping ratio, `2 sqrt(m k)` (critical damping coefficient).
    pub damping: f64,
}

impl Scales {
    /// A nondimensional angular frequency in Hz.
    pub fn hz(&self, omega: f64) -> f64 {
        omega * self.omega0 / std::f64::consts::TAU
    }
    /// A phase-plane area `x * x'` in m^2/s.
    pub fn area(&self) -> f64 {
        self.length * self.velocity
    }
    /// The nondimensional state of a phase-plane point `s` given in m and m/s.
    pub fn state(&self, s: crate::State) -> crate::State {
        crate::State {
            x: s.x / self.length,
            v: s.v / self.velocity,
        }
    }
}

impl Physical {
    /// Checks every value; the error names the key.
    pub fn validate(&self) -> Result<(), CoreError> {
        let bad = CoreError::invalid::<()>;
        let pos = |x: f64| x.is_finite() && x > 0.0;
        if !pos(self.m) {
            return bad("m", self.m, "a finite mass > 0 (kg)");
        }
        if !pos(self.k) {
            return bad("k", self.k, "a finite stiffness > 0 (N/m)");
        }
        if !self.c.is_finite() || self.c < 0.0 {
            return bad("c", self.c, "a finite damping coefficient >= 0 (N s/m)");
        }
        if !pos(self.v_belt) {
            return bad(
                "v_belt",
                self.v_belt,
                "a finite belt speed > 0 (m/s; the model needs lambda > 0)",
            );
        }
        if !pos(self.mu_k) {
            return bad("mu_k", self.mu_k, "a finite friction coefficient > 0");
        }
        if !self.mu_s.is_finite() || self.mu_s <= self.mu_k {
            return bad(
                "mu_s",
                self.mu_s,
                "a static coefficient > mu_k (Phi = arcsin(mu_k/mu_s) needs mu_k < mu_s)",
            );
        }
        // Phi = arcsin(mu_k / mu_s) >= MIN_PHI, named by the key the user gave.
        if (self.mu_k / self.mu_s).asin() < crate::law::MIN_PHI {
            return bad(
                "mu_s",
                self.mu_s,
                "a static coefficient at most about 1e5 mu_k (Phi = arcsin(mu_k/mu_s) >= 1e-5: \
                 a higher static peak puts the stick-slip orbit, about 1.4 mu_s/mu_k wide in the \
                 model's units, at the escape radius 1e6)",
            );
        }
        if !pos(self.tau) {
            return bad("tau", self.tau, "a finite time > 0 (s)");
        }
        if !pos(self.g) {
            return bad("g", self.g, "a finite acceleration > 0 (m/s^2)");
        }
        Ok(())
    }

    /// The scales of this system.
    pub fn scales(&self) -> Scales {
        let omega0 = (self.k / self.m).sqrt();
        Scales {
            omega0,
            time: 1.0 / omega0,
            length: self.mu_k * self.g / (omega0 * omega0),
            velocity: self.mu_k * self.g / omega0,
            damping: 2.0 * (self.m * self.k).sqrt(),
        }
    }

    /// The nondimensional parameters (paper Section 4), validated.
    pub fn params(&self, law: FrictionLaw) -> Result<Params, CoreError> {
        self.validate()?;
        let p = self.nondimensional(law)?;
        p.validate()?;
        Ok(p)
    }

    /// The nondimensional parameters, not validated (an error only for a law without
    /// physical units).
    pub fn nondimensional(&self, law: FrictionLaw) -> Result<Params, CoreError> {
        let s = self.scales();
        let surface = Surface {
            tau: self.tau / self.mu_k * s.omega0,
            phi: (self.mu_k / self.mu_s).asin(),
        };
        let law = match law {
            FrictionLaw::McMillan => Friction::McMillan(surface),
            FrictionLaw::McMillanNonHysteretic => Friction::NonHysteretic(surface),
            FrictionLaw::Coulomb => Friction::Coulomb,
            // Only McMillan's laws share the scaling of the physical units (the laws with
            // true stick, and any law not named here, are written in the normal load).
            _ => return Err(CoreError::NoPhysicalUnits(law.name())),
        };
        Ok(Params {
            law,
            nu: self.c / s.damping,
            lambda: self.v_belt / s.velocity,
        })
    }

    /// The physical system with mass, stiffness, `mu_k` and `g` taken from `base` whose
    /// nondimensional parameters are `p` (the inverse of [`Physical::params`]).
    /// A law without McMillan's surface constants (Coulomb) keeps `base`'s `tau` and `mu_s`.
    pub fn from_params(base: &Physical, p: &Params) -> Physical {
        let s = base.scales();
        let (tau, mu_s) = match p.law.surface() {
            Some(c) => (c.tau * base.mu_k / s.omega0, base.mu_k / c.phi.sin()),
            None => (base.tau, base.mu_s),
        };
        Physical {
            c: p.nu * s.damping,
            v_belt: p.lambda * s.velocity,
            tau,
            mu_s,
            ..*base
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn example() -> Physical {
        // A 2 kg block on a 20 kN/m spring: omega_0 = 100 rad/s (about 15.9 Hz).
        Physical {
            m: 2.0,
            k: 2.0e4,
            c: 4.0,
            v_belt: 0.1,
            mu_k: 0.4,
            mu_s: 0.5,
            tau: 1e-3,
            g: G_STANDARD,
        }
    }

    #[test]
    fn scaling_is_the_papers() {
        let ph = example();
        let p = ph.params(FrictionLaw::McMillan).unwrap();
        // nu = c / (2 sqrt(m k)) = 4 / (2 * 200) = 0.01.
        assert!((p.nu - 0.01).abs() < 1e-15);
        // lambda = v_B / (mu_k g) * omega_0 = 0.1 / 3.924 * 100.
        assert!((p.lambda - 0.1 / (0.4 * 9.81) * 100.0).abs() < 1e-12);
        // tau' = tau / mu_k * omega_0 = 1e-3 / 0.4 * 100 = 0.25.
        let c = p.law.surface().unwrap();
        assert!((c.tau - 0.25).abs() < 1e-15);
        // Phi = arcsin(0.8).
        assert!((c.phi - 0.8f64.asin()).abs() < 1e-15);
        let s = ph.scales();
        // One nondimensional length is mu_k g / omega_0^2 = 3.924e-4 m.
        assert!((s.length - 3.924e-4).abs() < 1e-16);
        // Angular frequency 1 is omega_0 / (2 pi) Hz.
        assert!((s.hz(1.0) - 100.0 / std::f64::consts::TAU).abs() < 1e-12);
    }

    #[test]
    fn conversion_round_trips() {
        let ph = example();
        let p = ph.params(FrictionLaw::McMillanNonHysteretic).unwrap();
        let back = Physical::from_params(&ph, &p);
        for (a, b) in [
            (back.c, ph.c),
            (back.v_belt, ph.v_belt),
            (back.tau, ph.tau),
            (back.mu_s, ph.mu_s),
        ] {
            assert!((a - b).abs() <= 1e-14 * b.abs(), "{a} vs {b}");
        }
        let p2 = back.params(p.kind()).unwrap();
        assert!((p2.nu - p.nu).abs() < 1e-15 && (p2.lambda - p.lambda).abs() < 1e-13);
    }

    #[test]
    fn bad_values_name_the_key() {
        type Edit = fn(&mut Physical);
        let cases: [(Edit, &str); 6] = [
            (|p| p.m = -1.0, "m"),
            (|p| p.k = 0.0, "k"),
            (|p| p.mu_s = 0.4, "mu_s"),
            // Phi = arcsin(0.4 / 1e300) = 4e-301: the static peak 2.5e300 times kinetic
            // friction (law::MIN_PHI).
            (|p| p.mu_s = 1e300, "mu_s"),
            (|p| p.c = f64::NAN, "c"),
            (|p| p.tau = -1e-3, "tau"),
        ];
        // mu_s / mu_k = 9e4: Phi = arcsin(1 / 9e4) = 1.1e-5 >= 1e-5, accepted.
        let high = Physical {
            mu_s: 0.4 * 9e4,
            ..example()
        };
        assert!(high.params(FrictionLaw::McMillan).is_ok());
        for (f, key) in cases {
            let mut p = example();
            f(&mut p);
            match p.validate() {
                Err(CoreError::InvalidParameter { name, .. }) => assert_eq!(name, key),
                other => panic!("{key}: {other:?}"),
            }
        }
    }
}
