//! The key at fault when a figure made of several keys is out of range.
//!
//! Every nondimensional number and scale of a physical system is a product of its keys'
//! powers (`nu = c m^-1/2 k^-1/2 / 2`, `lambda = v_belt m^1/2 k^1/2 / (mu_k N)`, ...). When
//! one is out of range, the message names the key the user gave whose value pushes it
//! there most: each factor's distance from a plausible system, `e log10(value / typical)`
//! for a key of exponent `e`, in the direction the figure failed (too large or too small).
//! A value hundreds of decades out (`m = 1e-300`, `normal_force = 5e-324`, `k = 1e300`)
//! wins over any plausible one, whatever the typical values; they only rank keys that are
//! a few decades off. Before, the figure named a fixed key: `normal_force = 5e-324` was
//! blamed on `m`, `m = 1e-300` on `c` (through `nu`), and `k = 1e300` on `v_belt`.

use crate::error::{CoreError, Number};
use crate::params::Params;

use super::{FrictionSi, Load, Physical};

/// A plausible value of each key, from the systems squeal's docs use (the brake of
/// README section 4: 0.8 kg, 200 kN/m, 20-60 N s/m, 0.3 m/s, mu 0.38-0.48, 0.5 ms, 1.5
/// kN; the paper's block under its weight, g = 9.81): only their order of magnitude counts.
fn typical(key: &str) -> f64 {
    match key {
        "m" => 1.0,
        "k" => 1e5,
        "c" => 30.0,
        "v_belt" => 0.3,
        "mu_k" => 0.4,
        "mu_s" => 0.5,
        "tau" => 1e-3,
        "g" => 9.81,
        "normal_force" => 1e3,
        _ => 1.0,
    }
}

/// A factor of a figure: a key, the normal force `N` (`m g` or `normal_force`), or `mu_k`
/// (1 for a measured curve).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Factor {
    Key(&'static str),
    Load,
    Mu,
}

/// A figure made of the keys: its words, its formula and its factors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Figure {
    /// `omega_0 = sqrt(k/m)` and the time unit, its inverse.
    Omega,
    /// The critical damping `2 sqrt(m k)`.
    Critical,
    /// The acceleration `N / m` of a clamp force.
    LoadAcceleration,
    /// The length unit `mu_k N / k`.
    Length,
    /// The velocity unit `mu_k N / sqrt(m k)`.
    Velocity,
    /// The damping ratio `c / (2 sqrt(m k))`.
    Ratio,
    /// The belt speed `v_belt sqrt(m k) / (mu_k N)`.
    Speed,
    /// The surface time `tau sqrt(k/m) / mu_k`.
    Tau,
}

impl Figure {
    /// The figure in words with its formula.
    fn words(self, measured: bool) -> &'static str {
        match (self, measured) {
            (Figure::Omega, _) => "omega_0 = sqrt(k/m) (the time unit is its inverse)",
            (Figure::Critical, _) => "the critical damping 2 sqrt(m k)",
            (Figure::LoadAcceleration, _) => "N / m",
            (Figure::Length, false) => "the length unit mu_k N / k",
            (Figure::Length, true) => "the length unit N / k",
            (Figure::Velocity, false) => "the velocity unit mu_k N / sqrt(m k)",
            (Figure::Velocity, true) => "the velocity unit N / sqrt(m k)",
            (Figure::Ratio, false) => "the damping ratio nu = c / (2 sqrt(m k))",
            (Figure::Ratio, true) => "the damping ratio xi = c / (2 sqrt(m k))",
            (Figure::Speed, false) => "the model's belt speed lambda = v_belt sqrt(m k) / (mu_k N)",
            (Figure::Speed, true) => "the model's belt speed v_d = v_belt sqrt(m k) / N",
            (Figure::Tau, _) => "the surface time tau' = tau sqrt(k/m) / mu_k",
        }
    }
}

impl Physical {
    /// The keys of figure `f` with their exponents (`N` is `m g` under the block's weight;
    /// `mu_k` is absent for a measured curve), each key once.
    fn factors(&self, f: Figure) -> Vec<(&'static str, f64)> {
        use Factor::{Key, Load as N, Mu};
        let raw: &[(Factor, f64)] = match f {
            Figure::Omega => &[(Key("k"), 0.5), (Key("m"), -0.5)],
            Figure::Critical => &[(Key("m"), 0.5), (Key("k"), 0.5)],
            Figure::LoadAcceleration => &[(N, 1.0), (Key("m"), -1.0)],
            Figure::Length => &[(Mu, 1.0), (N, 1.0), (Key("k"), -1.0)],
            Figure::Velocity => &[(Mu, 1.0), (N, 1.0), (Key("m"), -0.5), (Key("k"), -0.5)],
            Figure::Ratio => &[(Key("c"), 1.0), (Key("m"), -0.5), (Key("k"), -0.5)],
            Figure::Speed => &[
                (Key("v_belt"), 1.0),
                (Key("m"), 0.5),
                (Key("k"), 0.5),
                (Mu, -1.0),
                (N, -1.0),
            ],
            Figure::Tau => &[
                (Key("tau"), 1.0),
                (Key("k"), 0.5),
                (Key("m"), -0.5),
                (Mu, -1.0),
            ],
        };
        let mut out: Vec<(&'static str, f64)> = Vec::new();
        let mut add = |key: &'static str, e: f64| match out.iter_mut().find(|(k, _)| *k == key) {
            Some(slot) => slot.1 += e,
            None => out.push((key, e)),
        };
        let kinetic = matches!(self.friction, FrictionSi::Kinetic { .. });
        for &(factor, e) in raw {
            match (factor, self.load) {
                (Key(key), _) => add(key, e),
                (N, Load::Weight(_)) => {
                    add("m", e);
                    add("g", e);
                }
                (N, Load::NormalForce(_)) => add("normal_force", e),
                (Mu, _) if kinetic => add("mu_k", e),
                (Mu, _) => {}
            }
        }
        out.retain(|(_, e)| *e != 0.0);
        out
    }

    /// The value of a scalar key as given (`None` for a key this system has not).
    fn given(&self, key: &str) -> Option<f64> {
        const KEYS: [&str; 9] = [
            "m",
            "k",
            "c",
            "v_belt",
            "mu_k",
            "mu_s",
            "tau",
            "g",
            "normal_force",
        ];
        let i = KEYS.iter().position(|k| *k == key)?;
        self.values()[i]
    }

    /// The key at fault for figure `f` failing upwards (`up`: too large, infinite) or
    /// downwards (too small, 0), with its value as given.
    pub(super) fn culprit(&self, f: Figure, up: bool) -> (&'static str, f64) {
        let sign = if up { 1.0 } else { -1.0 };
        self.factors(f)
            .into_iter()
            .filter_map(|(key, e)| Some((key, self.given(key)?, e)))
            .map(|(key, v, e)| (key, v, sign * e * (v / typical(key)).log10()))
            .max_by(|a, b| a.2.total_cmp(&b.2))
            .map(|(key, v, _)| (key, v))
            .expect("every figure has a factor")
    }

    /// The refusal of figure `f` at `value` (which failed upwards where `up`), naming the
    /// key at fault: "invalid m = 1e-300: it makes the damping ratio nu = ... = 6.7e148,
    /// expected ...".
    pub(super) fn blame(&self, f: Figure, value: f64, up: bool, expected: &str) -> CoreError {
        let (key, given) = self.culprit(f, up);
        let measured = self.friction.table().is_some();
        CoreError::Source {
            key,
            value: given,
            why: format!(
                "it makes {} = {}, expected {expected}",
                f.words(measured),
                Number(value)
            ),
        }
    }

    /// Refuses a system whose scales are not representable (infinite, or 0 from nonzero
    /// keys), naming the key at fault: `m = k = 1e308` has a critical damping `2 sqrt(m
    /// k)` of `inf` (`m`), a clamp of 5e-324 N an acceleration `N / m` of 0
    /// (`normal_force`).
    pub(super) fn check_scales(&self) -> Result<(), CoreError> {
        let s = self.scales();
        let fine = |x: f64| x.is_finite() && x > 0.0;
        let load = match self.load {
            Load::NormalForce(_) => Some(self.load_acceleration()),
            Load::Weight(_) => None,
        };
        let figures = [
            (Figure::LoadAcceleration, load),
            (Figure::Omega, Some(s.omega0)),
            (Figure::Omega, Some(s.time.recip())),
            (Figure::Critical, Some(s.damping)),
            (Figure::Length, Some(s.length)),
            (Figure::Velocity, Some(s.velocity)),
        ];
        for (f, value) in figures {
            match value {
                Some(v) if !fine(v) => {
                    return Err(self.blame(f, v, v > 1.0, "finite and nonzero in f64"));
                }
                _ => {}
            }
        }
        Ok(())
    }

    /// Refuses nondimensional numbers `p` that are not representable (infinite, or 0 from
    /// nonzero keys) or out of the model's range ([`Params::validate`]: `nu` or `lambda`
    /// above 1e6), naming the key at fault.
    pub(super) fn check_derived(&self, p: &Params) -> Result<(), CoreError> {
        let fine = |x: f64| x.is_finite() && x > 0.0;
        if !fine(p.lambda) {
            let e = "finite and nonzero in f64";
            return Err(self.blame(Figure::Speed, p.lambda, p.lambda > 1.0, e));
        }
        if !p.nu.is_finite() || (self.c > 0.0 && p.nu == 0.0) {
            let e = "finite, and nonzero for c > 0, in f64";
            return Err(self.blame(Figure::Ratio, p.nu, p.nu > 1.0, e));
        }
        if let Some(c) = p.law.surface() {
            if !fine(c.tau) {
                let e = "finite and nonzero in f64";
                return Err(self.blame(Figure::Tau, c.tau, c.tau > 1.0, e));
            }
        }
        p.validate().map_err(|e| self.blame_model(e))
    }

    /// A model's refusal ([`Params::validate`], [`Params::check_step`]) of a figure the
    /// physical keys make (`nu` or `xi`, `lambda` or `v_d`, `tau`), as the refusal of the
    /// key at fault; any other passes as it is.
    pub(super) fn blame_model(&self, e: CoreError) -> CoreError {
        let (name, value) = match &e {
            CoreError::InvalidParameter { name, value, .. }
            | CoreError::Unresolved { name, value, .. } => (*name, *value),
            _ => return e,
        };
        let expected = e.to_string();
        let expected = match expected.split_once(": expected ") {
            Some((_, rest)) => rest.to_string(),
            None => return e,
        };
        let (f, up) = match name {
            "nu" | "xi" => (Figure::Ratio, value > 1.0),
            "lambda" | "v_d" => (Figure::Speed, value > 1.0),
            "tau" => (Figure::Tau, value > 1.0),
            _ => return e,
        };
        self.blame(f, value, up, &expected)
    }

    /// Refuses a belt speed the step `dt` cannot resolve ([`Params::check_step`], which
    /// gives the argument), naming the key at fault: `normal_force = 1e308` on a 0.05 m/s
    /// belt makes `lambda = 4.5e-307`.
    pub fn check_step(&self, p: &Params, dt: f64) -> Result<(), CoreError> {
        p.check_step(dt).map_err(|e| self.blame_model(e))
    }
}
