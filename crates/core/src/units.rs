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
//! The paper's block rests on the belt under its own weight: the normal force is `N = m g`
//! and friction is `mu N`. A block pressed on the belt by a normal force `N` of its own (a
//! brake pad under its clamp, [`Load::NormalForce`]) has `N / m` in place of `g` in every
//! line above: the force unit is `mu_k N`, the length unit `mu_k N / k`, the velocity unit
//! `mu_k N / sqrt(m k)`, and `lambda = v_B sqrt(m k) / (mu_k N)`. `g` then has no part in
//! the law, so a system takes one of the two ([`Load::of`] refuses both; MODEL.md, "Units").
//!
//! `tau` and `mu_s` are constants of McMillan's surfaces ([`SurfaceSi`]): his two laws need
//! them, Coulomb's force has neither, so a Coulomb system is `m, k, c, v_B, mu_k, g` alone
//! ([`friction_keys`] says which a law takes).
//!
//! A measured curve (`law = "table"`, [`FrictionSi::Table`]: `mu` against slip speed in
//! m/s) has no `mu_k`: the law is written in the normal load (MODEL.md section 8), so the
//! force unit is `N` itself, the length unit `N / k`, the velocity unit `N / sqrt(m k)`,
//! `xi = c / (2 sqrt(m k))`, `v_d = v_B sqrt(m k) / N`, and the nondimensional table is the
//! measured one with its slip speeds divided by the velocity unit (its `mu` unchanged).
//!
//! [`Physical`] holds the physical system, [`Physical::params`] converts it, and
//! [`Scales`] turns nondimensional figures back into SI: lengths in m, velocities in m/s,
//! times in s, angular frequencies in Hz, damping ratios in N s/m.

use serde::{Deserialize, Serialize};

use crate::error::CoreError;
use crate::params::{Friction, FrictionLaw, FrictionTable, Params, Surface};

/// Standard gravity, the default of `g` (m/s^2).
pub const G_STANDARD: f64 = 9.81;

/// What presses the block on the belt, so that friction is `mu N`: its own weight (the
/// paper's block, `N = m g`) or a normal force given in newtons (a clamp). Serialised
/// flattened as the key given (`g` or `normal_force`). `T` as in [`Physical`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum Load<T = f64> {
    /// The block under its own weight: gravitational acceleration `g` (m/s^2), `N = m g`.
    #[serde(rename = "g")]
    Weight(T),
    /// A normal force `N` (N) pressing the block on the belt; `g` plays no part.
    #[serde(rename = "normal_force")]
    NormalForce(T),
}

impl<T> Load<T> {
    /// The load of the keys `g` and `normal_force` as given: the normal force when it is
    /// given, else the weight under `g` (`standard` when `g` is not given either). Both
    /// given is refused ([`CoreError::BothLoads`]): `N` replaces `m g` in the law, so a `g`
    /// beside it would mean nothing.
    pub fn of(g: Option<T>, normal_force: Option<T>, standard: T) -> Result<Load<T>, CoreError> {
        match (g, normal_force) {
            (Some(_), Some(_)) => Err(CoreError::BothLoads),
            (None, Some(n)) => Ok(Load::NormalForce(n)),
            (g, None) => Ok(Load::Weight(g.unwrap_or(standard))),
        }
    }
}

/// The physical keys of a system's friction, in the order of [`Physical::values`]' friction
/// keys: the kinetic coefficient, McMillan's surfaces, and a measured curve (`friction_table`,
/// which a spec may give as `friction_csv`).
pub const FRICTION_KEYS: [&str; 4] = ["mu_k", "mu_s", "tau", "friction_table"];

/// The physical keys of McMillan's surfaces, in the order of [`SurfaceSi`]'s fields.
pub const SURFACE_KEYS: [&str; 2] = ["mu_s", "tau"];

/// McMillan's surfaces in SI units: what his two laws need beyond the oscillator. `T` is
/// `f64` but for a spec's table of values (see [`Physical`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SurfaceSi<T = f64> {
    /// "Static" friction coefficient `mu_s > mu_k`.
    pub mu_s: T,
    /// Characteristic time of the surfaces `tau` (s).
    pub tau: T,
}

/// Which of [`FRICTION_KEYS`] `law` takes in physical units: McMillan's two laws `mu_k`,
/// `mu_s`, `tau`; Coulomb `mu_k`; the table law its curve alone. Any other law has no
/// physical units (an error).
pub fn friction_keys(law: FrictionLaw) -> Result<[bool; 4], CoreError> {
    match law {
        FrictionLaw::McMillan | FrictionLaw::McMillanNonHysteretic => Ok([true, true, true, false]),
        FrictionLaw::Coulomb => Ok([true, false, false, false]),
        FrictionLaw::Table => Ok([false, false, false, true]),
        // The Stribeck and cubic laws are written in the normal load too, but their
        // coefficients' speeds would need a unit of their own: not yet.
        _ => Err(CoreError::NoPhysicalUnits(law.name())),
    }
}

/// Whether `law` takes McMillan's surfaces (`mu_s`, `tau`) in physical units: his two laws
/// do, Coulomb and the table law do not; a law without physical units is an error.
pub fn takes_surface(law: FrictionLaw) -> Result<bool, CoreError> {
    friction_keys(law).map(|k| k[1])
}

/// Checks which of [`FRICTION_KEYS`] are given (`given`, in that order) under `law`: the
/// error names the first key missing or not used, and the law.
pub fn check_friction_keys(law: FrictionLaw, given: [bool; 4]) -> Result<(), CoreError> {
    let takes = friction_keys(law)?;
    match FRICTION_KEYS
        .into_iter()
        .zip(takes)
        .zip(given)
        .find(|((_, t), g)| t != g)
    {
        None => Ok(()),
        Some(((key, true), _)) => Err(CoreError::MissingPhysicalKey {
            key,
            law: law.name(),
        }),
        Some(((key, false), _)) => Err(CoreError::UnusedPhysicalKey {
            key,
            law: law.name(),
        }),
    }
}

/// What the physical keys of friction mean, for the messages that name one missing or not
/// used (`key` one of [`FRICTION_KEYS`]).
pub fn friction_key_meaning(key: &str) -> &'static str {
    match key {
        "mu_k" => {
            "mu_k is the kinetic friction coefficient of McMillan's laws and Coulomb's, whose \
             force unit is mu_k N; a measured curve (law table) carries its own mu at every \
             slip speed, its force unit is N"
        }
        "friction_table" => {
            "the measured curve of law table: friction_table = [[s, mu], ...] or friction_csv, \
             slip speed in m/s, the first row at 0; the other laws are formulas in mu_k"
        }
        _ => {
            "mu_s and tau are McMillan's surfaces, the static coefficient mu_s > mu_k and the \
             surface time tau in s, for laws mcmillan and mcmillan-nonhysteretic"
        }
    }
}

/// The friction of a physical system: McMillan's or Coulomb's kinetic coefficient (with
/// McMillan's surfaces), or a measured curve. Serialised flattened as its keys (`mu_k` and
/// `surface`, or `friction_table`). `T` as in [`Physical`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum FrictionSi<T = f64> {
    /// McMillan's laws and Coulomb's: the force unit is `mu_k N`.
    Kinetic {
        /// Kinetic friction coefficient `mu_k`.
        mu_k: T,
        /// McMillan's surfaces (his two laws); `None` for Coulomb, which has none.
        surface: Option<SurfaceSi<T>>,
    },
    /// `law = "table"`: `mu` against slip speed in m/s, as measured (rows `(s, mu)`); the
    /// force unit is `N`.
    Table {
        /// The curve in SI: slip speeds in m/s.
        friction_table: &'static FrictionTable,
    },
}

impl<T: Copy> FrictionSi<T> {
    /// `mu_k` (McMillan's laws and Coulomb).
    pub fn mu_k(&self) -> Option<T> {
        match self {
            FrictionSi::Kinetic { mu_k, .. } => Some(*mu_k),
            FrictionSi::Table { .. } => None,
        }
    }
    /// McMillan's surfaces (his two laws).
    pub fn surface(&self) -> Option<SurfaceSi<T>> {
        match self {
            FrictionSi::Kinetic { surface, .. } => *surface,
            FrictionSi::Table { .. } => None,
        }
    }
    /// The measured curve in SI (the table law).
    pub fn table(&self) -> Option<&'static FrictionTable> {
        match self {
            FrictionSi::Table { friction_table } => Some(friction_table),
            FrictionSi::Kinetic { .. } => None,
        }
    }
}

impl FrictionSi {
    /// The friction under `law` of the keys as given: `mu_k` with `mu_s` and `tau` for
    /// McMillan's laws, `mu_k` alone for Coulomb, the curve `table` (slip speed in m/s)
    /// alone for the table law ([`check_friction_keys`]; values are checked by
    /// [`Physical::validate`]).
    pub fn of(
        law: FrictionLaw,
        mu_k: Option<f64>,
        mu_s: Option<f64>,
        tau: Option<f64>,
        table: Option<&'static FrictionTable>,
    ) -> Result<FrictionSi, CoreError> {
        let given = [
            mu_k.is_some(),
            mu_s.is_some(),
            tau.is_some(),
            table.is_some(),
        ];
        check_friction_keys(law, given)?;
        Ok(match (mu_k, mu_s.zip(tau), table) {
            (Some(mu_k), surface, _) => FrictionSi::Kinetic {
                mu_k,
                surface: surface.map(|(mu_s, tau)| SurfaceSi { mu_s, tau }),
            },
            (None, _, Some(friction_table)) => FrictionSi::Table { friction_table },
            _ => unreachable!("check_friction_keys: every law takes mu_k or a table"),
        })
    }
}

/// A physical friction oscillator in SI units. `T` is `f64` but for a spec's table of the
/// values each key is given (a number, a list or a range), laid out in the same fields so
/// that [`Physical::values`] puts both in key order.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Physical<T = f64> {
    /// Mass `m` (kg).
    pub m: T,
    /// Spring stiffness `k` (N/m).
    pub k: T,
    /// Dashpot coefficient `c` (N s/m).
    pub c: T,
    /// Belt speed `v_B` (m/s).
    pub v_belt: T,
    /// The friction: `mu_k` (and McMillan's surfaces), or a measured curve.
    #[serde(flatten)]
    pub friction: FrictionSi<T>,
    /// What presses the block on the belt: `g` (its weight `m g`) or `normal_force`.
    #[serde(flatten)]
    pub load: Load<T>,
}

/// SI size of one nondimensional unit, for one physical system.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Scales {
    /// Undamped natural angular frequency `omega_0 = sqrt(k/m)` (rad/s).
    pub omega0: f64,
    /// Seconds per nondimensional time unit, `1 / omega_0`.
    pub time: f64,
    /// Metres per nondimensional length unit, `mu_k g / omega_0^2` (`mu_k N / k`).
    pub length: f64,
    /// Metres per second per nondimensional velocity unit, `mu_k g / omega_0`
    /// (`mu_k N / sqrt(m k)`).
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

impl<T: Copy> Physical<T> {
    /// The values in the order of the keys `m, k, c, v_belt, mu_k, mu_s, tau, g,
    /// normal_force` (the order of a spec's `[physical]` table, of the flags and of the
    /// stored attributes); `mu_s` and `tau` are `None` for a system without McMillan's
    /// surfaces (Coulomb, a table), `mu_k` for a measured curve (its table is no scalar:
    /// [`FrictionSi::table`]), and one of `g` and `normal_force` is `None` (the one not
    /// given).
    pub fn values(&self) -> [Option<T>; 9] {
        let sf = self.friction.surface();
        let (g, n) = match self.load {
            Load::Weight(g) => (Some(g), None),
            Load::NormalForce(n) => (None, Some(n)),
        };
        [
            Some(self.m),
            Some(self.k),
            Some(self.c),
            Some(self.v_belt),
            self.friction.mu_k(),
            sf.map(|s| s.mu_s),
            sf.map(|s| s.tau),
            g,
            n,
        ]
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
        // A measured curve's rows were checked when it was made (FrictionTable::new).
        let (mu_k, surface) = match self.friction {
            FrictionSi::Kinetic { mu_k, surface } => (mu_k, surface),
            FrictionSi::Table { .. } => (1.0, None),
        };
        if !pos(mu_k) {
            return bad("mu_k", mu_k, "a finite friction coefficient > 0");
        }
        if let Some(sf) = surface {
            if !sf.mu_s.is_finite() || sf.mu_s <= mu_k {
                return bad(
                    "mu_s",
                    sf.mu_s,
                    "a static coefficient > mu_k (Phi = arcsin(mu_k/mu_s) needs mu_k < mu_s)",
                );
            }
            // Phi = arcsin(mu_k / mu_s) checked by the one check of Phi (law::MIN_PHI), but
            // named by the key the user gave, with the value given: its own message would show
            // Phi's value under mu_s.
            if crate::Surface::check_phi((mu_k / sf.mu_s).asin()).is_err() {
                return bad(
                    "mu_s",
                    sf.mu_s,
                    "a static coefficient at most about 1e5 mu_k (Phi = arcsin(mu_k/mu_s) >= 1e-5: \
                     the stick-slip orbit reaches |x| about 1.43 mu_s/mu_k in the model's units, \
                     and a higher static peak brings it to the escape radius 1e6)",
                );
            }
            if !pos(sf.tau) {
                return bad("tau", sf.tau, "a finite time > 0 (s)");
            }
        }
        match self.load {
            Load::Weight(g) if !pos(g) => {
                return bad("g", g, "a finite acceleration > 0 (m/s^2)");
            }
            Load::NormalForce(n) if !pos(n) => {
                return bad("normal_force", n, "a finite normal force > 0 (N)");
            }
            _ => {}
        }
        Ok(())
    }

    /// The normal force `N` pressing the block on the belt (N): `m g` for a block under its
    /// own weight.
    pub fn normal_force(&self) -> f64 {
        match self.load {
            Load::Weight(g) => self.m * g,
            Load::NormalForce(n) => n,
        }
    }

    /// The acceleration `N / m` that friction's scale divides by `mu_k` (m/s^2): `g` for a
    /// block under its own weight, `N / m` for a pressed one (so that the clamp force and
    /// the same system stated with `g = N / m` give the same numbers, bit for bit).
    fn load_acceleration(&self) -> f64 {
        match self.load {
            Load::Weight(g) => g,
            Load::NormalForce(n) => ratio(&[n], &[self.m]),
        }
    }

    /// The coefficient of the force unit `mu_k N`: `mu_k` for McMillan's laws and Coulomb,
    /// 1 for a measured curve (written in the normal load: its force unit is `N`).
    fn force_coefficient(&self) -> f64 {
        self.friction.mu_k().unwrap_or(1.0)
    }

    /// The velocity scale `mu_k a sqrt(m) / sqrt(k)` (`a = N / m`; `mu_k` is 1 for a
    /// measured curve) as factors over factors, for [`ratio`].
    fn velocity_factors(&self) -> ([f64; 3], [f64; 2]) {
        let (sm, sk) = (self.m.sqrt(), self.k.sqrt());
        (
            [self.force_coefficient(), self.load_acceleration(), sm],
            [sk, 1.0],
        )
    }

    /// The scales of this system, each a ratio of the keys' square roots and values taken
    /// in an order that overflows only where the result does ([`ratio`]): `2 sqrt(m k)`
    /// was `inf` for `m = k = 1e200`, and `nu = c / inf` then 0. Friction's force scale is
    /// `mu_k N`: `mu_k m g` for a block under its own weight.
    pub fn scales(&self) -> Scales {
        let (sm, sk) = (self.m.sqrt(), self.k.sqrt());
        let ([a, b, c], [d, e]) = self.velocity_factors();
        // length = velocity / omega_0 = velocity sqrt(m) / sqrt(k).
        let (length, velocity) = (
            ratio(&[a, b, c, sm], &[d, e, sk]),
            ratio(&[a, b, c], &[d, e]),
        );
        Scales {
            omega0: ratio(&[sk], &[sm]),
            time: ratio(&[sm], &[sk]),
            length,
            velocity,
            damping: ratio(&[2.0, sm, sk], &[]),
        }
    }

    /// The nondimensional parameters (paper Section 4), validated.
    pub fn params(&self, law: FrictionLaw) -> Result<Params, CoreError> {
        self.validate()?;
        // The scales first: a measured curve is divided by the velocity unit.
        self.check_scales()?;
        let p = self.nondimensional(law)?;
        // Every figure out of range names the key at fault (sources.rs), `validate` too.
        self.check_derived(&p)?;
        Ok(p)
    }

    /// The nondimensional parameters, not validated (an error for a law without physical
    /// units, and for surfaces given to a law without them or missing from one with them).
    pub fn nondimensional(&self, law: FrictionLaw) -> Result<Params, CoreError> {
        let (sm, sk) = (self.m.sqrt(), self.k.sqrt());
        let mu_k = self.force_coefficient();
        let nd = |sf: SurfaceSi| Surface {
            tau: ratio(&[sf.tau, sk], &[mu_k, sm]),
            phi: (mu_k / sf.mu_s).asin(),
        };
        let f = self.friction;
        let law = match (law, f.surface(), f.table()) {
            (FrictionLaw::McMillan, Some(sf), _) => Friction::McMillan(nd(sf)),
            (FrictionLaw::McMillanNonHysteretic, Some(sf), _) => Friction::NonHysteretic(nd(sf)),
            (FrictionLaw::Coulomb, None, None) => Friction::Coulomb,
            (FrictionLaw::Table, _, Some(t)) => Friction::Table(self.table_in_units(t)?),
            // A key missing or not used (check_friction_keys names it), or a law without
            // physical units at all.
            (law, sf, t) => {
                let given = [f.mu_k().is_some(), sf.is_some(), sf.is_some(), t.is_some()];
                return Err(check_friction_keys(law, given)
                    .err()
                    .unwrap_or(CoreError::NoPhysicalUnits(law.name())));
            }
        };
        // The damping and the belt speed over their units ([`Physical::scales`], each
        // computed so that it overflows only where it is itself out of range, and refused
        // then by `check_scales`): one division each, so that a model's `nu` times the
        // damping unit gives back `c` as closely as one rounding allows, and so that every
        // door (a scan's maps, an atlas's points, a trajectory) converts alike.
        let s = self.scales();
        Ok(Params {
            law,
            nu: self.c / s.damping,
            lambda: self.v_belt / s.velocity,
        })
    }

    /// The measured curve `t` (slip speed in m/s) in the model's units: every slip speed
    /// divided by the velocity unit `N / sqrt(m k)`, every `mu` as measured (the law is
    /// written in the normal load, so its force unit is `N`: MODEL.md section 8). A curve
    /// whose speeds no f64 holds in those units (infinite, or rows that collapse onto one
    /// speed) is refused naming the key of the velocity unit's force (`normal_force`, `g`):
    /// the curve's own rows were checked when it was read.
    pub fn table_in_units(&self, t: &FrictionTable) -> Result<&'static FrictionTable, CoreError> {
        let unit = self.scales().velocity;
        let rows: Vec<(f64, f64)> = t.rows().into_iter().map(|(s, mu)| (s / unit, mu)).collect();
        FrictionTable::new(&rows).map_err(|_| {
            // Speeds beyond f64 come from a unit too small, collapsed ones from one too large.
            let up = rows.iter().all(|r| r.0.is_finite());
            self.blame(
                sources::Figure::Velocity,
                unit,
                up,
                "a velocity unit that keeps the measured curve's slip speeds finite and \
                 distinct in f64",
            )
        })
    }

    /// The physical system with mass, stiffness, `mu_k` and load taken from `base` whose
    /// nondimensional parameters are `p` (the inverse of [`Physical::params`]).
    /// A law without McMillan's surface constants (Coulomb) gives a system without them.
    pub fn from_params(base: &Physical, p: &Params) -> Physical {
        let (sm, sk) = (base.m.sqrt(), base.k.sqrt());
        Physical {
            c: ratio(&[p.nu, 2.0, sm, sk], &[]),
            v_belt: {
                let ([a, b, c], [d, e]) = base.velocity_factors();
                ratio(&[p.lambda, a, b, c], &[d, e])
            },
            friction: match base.friction {
                FrictionSi::Kinetic { mu_k, .. } => FrictionSi::Kinetic {
                    mu_k,
                    surface: p.law.surface().map(|c| SurfaceSi {
                        tau: ratio(&[c.tau, mu_k, sm], &[sk]),
                        mu_s: mu_k / c.phi.sin(),
                    }),
                },
                // The curve is the base's: its speeds in m/s do not depend on c or v_B.
                table => table,
            },
            ..*base
        }
    }
}

/// The product of `num` over the product of `den` (all finite and > 0, as validated keys
/// and their square roots are), multiplying in the order that keeps each partial result
/// nearest 1: it overflows or underflows only where the result itself does (`1e200 *
/// 1e200 / 1e200` left to right is `inf`).
fn ratio(num: &[f64], den: &[f64]) -> f64 {
    // Each factor with its binary exponent (a divisor's negated); applied is NaN.
    let mut left: Vec<(f64, bool, f64)> = num
        .iter()
        .map(|&x| (x, false, x.log2()))
        .chain(den.iter().map(|&d| (d, true, -d.log2())))
        .collect();
    let (mut acc, mut scale) = (1.0f64, 0.0f64);
    while !left.is_empty() {
        let j = (0..left.len())
            .min_by(|&a, &b| {
                (scale + left[a].2)
                    .abs()
                    .total_cmp(&(scale + left[b].2).abs())
            })
            .expect("not empty");
        let (x, divide, e) = left.swap_remove(j);
        acc = if divide { acc / x } else { acc * x };
        scale += e;
    }
    acc
}

mod plausible;
mod sources;
pub use plausible::{Doubt, MU_PLAUSIBLE, SPEED_PLAUSIBLE, curve_doubts};

#[cfg(test)]
mod tests;
