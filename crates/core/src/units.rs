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

    /// The key and value a scale of friction's force unit is named by: `mu_k`, or for a
    /// measured curve the load (`normal_force` or `g`).
    fn force_key(&self) -> (&'static str, f64) {
        match (self.friction.mu_k(), self.load) {
            (Some(mu_k), _) => ("mu_k", mu_k),
            (None, Load::NormalForce(n)) => ("normal_force", n),
            (None, Load::Weight(g)) => ("g", g),
        }
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

    /// Refuses a system whose scales are not representable (infinite, or 0 from nonzero
    /// keys), naming the key they come from: `m = k = 1e308` has a critical damping
    /// `2 sqrt(m k)` of `inf`, and a clamped `m = 1e-308` an acceleration `N / m` of `inf`.
    fn check_scales(&self) -> Result<(), CoreError> {
        let s = self.scales();
        let fine = |x: f64| x.is_finite() && x > 0.0;
        if let Load::NormalForce(_) = self.load {
            if !fine(self.load_acceleration()) {
                return CoreError::invalid(
                    "m",
                    self.m,
                    "a mass whose ratio N / m to the normal force is finite and nonzero in f64",
                );
            }
        }
        let (force_key, force_value) = self.force_key();
        for (value, key, given, expected) in [
            (
                s.omega0,
                "k",
                self.k,
                "a stiffness whose ratio to m is representable: omega_0 = sqrt(k/m) and its inverse, the time unit, must be finite and nonzero in f64",
            ),
            (
                s.time,
                "k",
                self.k,
                "a stiffness whose ratio to m is representable: omega_0 = sqrt(k/m) and its inverse, the time unit, must be finite and nonzero in f64",
            ),
            (
                s.damping,
                "m",
                self.m,
                "a mass whose product with k is representable: the critical damping 2 sqrt(m k) must be finite in f64",
            ),
            (
                s.length,
                force_key,
                force_value,
                "a value whose length unit mu_k N / k (N / k for a measured curve) is finite \
                 and nonzero in f64",
            ),
            (
                s.velocity,
                force_key,
                force_value,
                "a value whose velocity unit mu_k N / sqrt(m k) (N / sqrt(m k) for a measured \
                 curve) is finite and nonzero in f64",
            ),
        ] {
            if !fine(value) {
                return CoreError::invalid(key, given, expected);
            }
        }
        Ok(())
    }

    /// Refuses nondimensional numbers `p` that are not representable (infinite, or 0 from
    /// nonzero keys), naming the key they come from.
    fn check_derived(&self, p: &Params) -> Result<(), CoreError> {
        let fine = |x: f64| x.is_finite() && x > 0.0;
        for (value, key, given, expected) in [(
            p.lambda,
            "lambda",
            p.lambda,
            "a belt speed lambda = v_belt sqrt(m k) / (mu_k N) finite and nonzero in f64",
        )] {
            if !fine(value) {
                return CoreError::invalid(key, given, expected);
            }
        }
        if !p.nu.is_finite() || (self.c > 0.0 && p.nu == 0.0) {
            return CoreError::invalid(
                "nu",
                p.nu,
                "a damping ratio c / (2 sqrt(m k)) finite, and nonzero for c > 0, in f64",
            );
        }
        if let Some(c) = p.law.surface() {
            if !fine(c.tau) {
                return CoreError::invalid(
                    "tau",
                    c.tau,
                    "a surface time tau sqrt(k/m) / mu_k finite and nonzero in f64",
                );
            }
        }
        Ok(())
    }

    /// The nondimensional parameters (paper Section 4), validated.
    pub fn params(&self, law: FrictionLaw) -> Result<Params, CoreError> {
        self.validate()?;
        // The scales first: a measured curve is divided by the velocity unit.
        self.check_scales()?;
        let p = self.nondimensional(law)?;
        self.check_derived(&p)?;
        p.validate()?;
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
        Ok(Params {
            law,
            nu: ratio(&[self.c], &[2.0, sm, sk]),
            lambda: {
                let ([a, b, c], [d, e]) = self.velocity_factors();
                ratio(&[self.v_belt, d, e], &[a, b, c])
            },
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
        FrictionTable::new(&rows).or_else(|_| {
            let (key, value) = self.force_key();
            CoreError::invalid(
                key,
                value,
                "a value whose velocity unit N / sqrt(m k) keeps the measured curve's slip \
                 speeds finite and distinct in f64",
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The surfaces of a McMillan system, to edit.
    fn sf(p: &mut Physical) -> &mut SurfaceSi {
        match &mut p.friction {
            FrictionSi::Kinetic {
                surface: Some(s), ..
            } => s,
            other => panic!("{other:?}"),
        }
    }

    /// The system `p` with the surfaces `surface`.
    fn with_surface(p: Physical, surface: Option<SurfaceSi>) -> Physical {
        Physical {
            friction: FrictionSi::Kinetic {
                mu_k: p.friction.mu_k().unwrap(),
                surface,
            },
            ..p
        }
    }

    fn example() -> Physical {
        // A 2 kg block on a 20 kN/m spring: omega_0 = 100 rad/s (about 15.9 Hz).
        Physical {
            m: 2.0,
            k: 2.0e4,
            c: 4.0,
            v_belt: 0.1,
            friction: FrictionSi::Kinetic {
                mu_k: 0.4,
                surface: Some(SurfaceSi {
                    mu_s: 0.5,
                    tau: 1e-3,
                }),
            },
            load: Load::Weight(G_STANDARD),
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
        let (sb, sf) = (
            back.friction.surface().unwrap(),
            ph.friction.surface().unwrap(),
        );
        for (a, b) in [
            (back.c, ph.c),
            (back.v_belt, ph.v_belt),
            (sb.tau, sf.tau),
            (sb.mu_s, sf.mu_s),
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
            (|p| sf(p).mu_s = 0.4, "mu_s"),
            // Phi = arcsin(0.4 / 1e300) = 4e-301: the static peak 2.5e300 times kinetic
            // friction (law::MIN_PHI).
            (|p| sf(p).mu_s = 1e300, "mu_s"),
            (|p| p.c = f64::NAN, "c"),
            (|p| sf(p).tau = -1e-3, "tau"),
        ];
        // mu_s / mu_k = 9e4: Phi = arcsin(1 / 9e4) = 1.1e-5 >= 1e-5, accepted.
        let high = with_surface(
            example(),
            Some(SurfaceSi {
                mu_s: 0.4 * 9e4,
                tau: 1e-3,
            }),
        );
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

    /// Coulomb's force has no static peak and no surface time: its physical system is
    /// `m, k, c, v_B, mu_k, g` alone, and `mu_s` or `tau` given to it is refused by name
    /// (they were required and then ignored); McMillan's laws need both.
    #[test]
    fn each_law_takes_its_own_surface_keys() {
        let coulomb = with_surface(example(), None);
        let p = coulomb.params(FrictionLaw::Coulomb).unwrap();
        assert_eq!(p.law, Friction::Coulomb);
        // nu and lambda as for McMillan's laws (scaling_is_the_papers): c / (2 sqrt(m k)).
        assert!((p.nu - 0.01).abs() < 1e-15);
        let back = Physical::from_params(&coulomb, &p);
        assert_eq!(back.friction.surface(), None);
        let key_of = |r: Result<Params, CoreError>| match r {
            Err(
                e @ (CoreError::MissingPhysicalKey { .. } | CoreError::UnusedPhysicalKey { .. }),
            ) => (e.key().unwrap(), e.to_string()),
            other => panic!("{other:?}"),
        };
        let (key, msg) = key_of(example().params(FrictionLaw::Coulomb));
        assert_eq!(key, "mu_s");
        assert!(msg.contains("law coulomb does not use it"), "{msg}");
        for law in [FrictionLaw::McMillan, FrictionLaw::McMillanNonHysteretic] {
            let (key, msg) = key_of(coulomb.params(law));
            assert_eq!(key, "mu_s");
            assert!(msg.contains(&format!("law {law} needs it")), "{msg}");
        }
        // One of the two given: the other is named.
        let of = |law, mu_s, tau| FrictionSi::of(law, Some(0.4), mu_s, tau, None);
        let only_tau = of(FrictionLaw::McMillan, None, Some(1e-3)).unwrap_err();
        assert_eq!(only_tau.key(), Some("mu_s"));
        let only_mu_s = of(FrictionLaw::McMillan, Some(0.5), None).unwrap_err();
        assert_eq!(only_mu_s.key(), Some("tau"));
        let tau_to_coulomb = of(FrictionLaw::Coulomb, None, Some(1e-3)).unwrap_err();
        assert_eq!(tau_to_coulomb.key(), Some("tau"));
        assert_eq!(
            of(FrictionLaw::Coulomb, None, None),
            Ok(FrictionSi::Kinetic {
                mu_k: 0.4,
                surface: None
            })
        );
        assert!(matches!(
            of(FrictionLaw::Stribeck, None, None),
            Err(CoreError::NoPhysicalUnits(_))
        ));
    }

    /// The disc-brake pad of issue 34: 0.8 kg on a 200 kN/m mount, clamped with 1.5 kN.
    fn clamped(load: Load) -> Physical {
        Physical {
            m: 0.8,
            k: 2e5,
            c: 20.0,
            v_belt: 0.3,
            friction: FrictionSi::Kinetic {
                mu_k: 0.38,
                surface: Some(SurfaceSi {
                    mu_s: 0.48,
                    tau: 5e-4,
                }),
            },
            load,
        }
    }

    /// Friction is mu N: a normal force N stands where the weight m g stood, so the pad
    /// clamped with 1500 N is the paper's system of a 0.8 kg block under g = N / m = 1875
    /// m/s^2 (the only way to state it before `normal_force`), bit for bit.
    #[test]
    fn a_normal_force_stands_for_the_weight() {
        let pad = clamped(Load::NormalForce(1500.0));
        let p = pad.params(FrictionLaw::McMillan).unwrap();
        let hack = clamped(Load::Weight(1875.0));
        assert_eq!(p, hack.params(FrictionLaw::McMillan).unwrap());
        assert_eq!(pad.scales(), hack.scales());
        assert_eq!(pad.normal_force(), 1500.0);
        assert_eq!(hack.normal_force(), 1500.0);
        // Closed form (MODEL.md, "Units"): omega_0 = sqrt(2e5 / 0.8) = 500 rad/s;
        // nu = c / (2 sqrt(m k)) = 20 / 800 = 0.025; lambda = v_B sqrt(m k) / (mu_k N)
        // = 0.3 * 400 / 570 = 0.2105...; tau' = tau omega_0 / mu_k = 0.25 / 0.38 = 0.6579;
        // Phi = arcsin(0.38 / 0.48) = 0.9135.
        assert!((p.nu - 0.025).abs() < 1e-15);
        assert!((p.lambda - 120.0 / 570.0).abs() < 1e-15);
        let sf = p.law.surface().unwrap();
        assert!((sf.tau - 0.25 / 0.38).abs() < 1e-14);
        assert!((sf.phi - (0.38f64 / 0.48).asin()).abs() < 1e-15);
        // The length unit mu_k N / k = 570 / 2e5 m = 2.85 mm.
        assert!((pad.scales().length - 2.85e-3).abs() < 1e-17);
        // The weight's normal force is m g.
        assert_eq!(example().normal_force(), 2.0 * G_STANDARD);
    }

    /// A normal force <= 0, NaN or infinite is refused naming `normal_force`; `g` and
    /// `normal_force` both given are refused naming `normal_force` (N replaces m g).
    #[test]
    fn a_bad_normal_force_is_named() {
        for n in [0.0, -1500.0, f64::NAN, f64::INFINITY] {
            let e = clamped(Load::NormalForce(n)).validate().unwrap_err();
            assert_eq!(e.key(), Some("normal_force"), "{n}: {e}");
        }
        let both = Load::of(Some(9.81), Some(1500.0), G_STANDARD).unwrap_err();
        assert_eq!(both, CoreError::BothLoads);
        assert_eq!(both.key(), Some("normal_force"));
        assert_eq!(
            Load::of(None, None, G_STANDARD),
            Ok(Load::Weight(G_STANDARD))
        );
        assert_eq!(
            Load::of(None, Some(1500.0), G_STANDARD),
            Ok(Load::NormalForce(1500.0))
        );
    }

    /// The static peak's bound is Phi's ([`crate::law::MIN_PHI`], checked by
    /// [`crate::Surface::check_phi`]), named by `mu_s` with the value given: `mu_s` just
    /// inside it (Phi = 1.01e-5) is taken, just outside (Phi = 0.99e-5) refused.
    #[test]
    fn the_static_peak_takes_phis_bound() {
        let mut ph = example();
        let mu_k = ph.friction.mu_k().unwrap();
        let at = |phi: f64| SurfaceSi {
            mu_s: mu_k / phi.sin(),
            tau: 1e-3,
        };
        ph = with_surface(ph, Some(at(1.01e-5)));
        assert!(ph.validate().is_ok());
        ph = with_surface(ph, Some(at(0.99e-5)));
        let e = ph.validate().unwrap_err().to_string();
        // mu_s = 0.4 / sin(0.99e-5) = 40404.04...
        assert!(
            e.contains("invalid mu_s = 40404.04") && e.contains("1e5 mu_k"),
            "{e}"
        );
    }

    /// Issue 32: `m = k = 1e200` overflowed `m k` (the critical damping was `inf`, `nu` 0
    /// and "every start squeals"). The same system scaled by 1e200 in m, k and c has the
    /// same nondimensional numbers as `m = k = 1, c = [1, 2]` (nu = c / (2 sqrt(m k)) =
    /// 0.5 and 1, computed in ratios); one whose scales no f64 holds is refused by key.
    #[test]
    fn huge_and_tiny_systems_scale_without_overflow() {
        let at = |m: f64, k: f64, c: f64| Physical {
            m,
            k,
            c,
            ..example()
        };
        let close = |a: f64, b: f64| (a - b).abs() <= 4.0 * f64::EPSILON * b.abs();
        for c in [1.0, 2.0] {
            let one = at(1.0, 1.0, c).params(FrictionLaw::McMillan).unwrap();
            let big = at(1e200, 1e200, c * 1e200)
                .params(FrictionLaw::McMillan)
                .unwrap();
            let tiny = at(1e-200, 1e-200, c * 1e-200)
                .params(FrictionLaw::McMillan)
                .unwrap();
            assert!(close(one.nu, 0.5 * c) && close(big.nu, one.nu), "{big:?}");
            assert!(close(tiny.nu, one.nu), "{tiny:?}");
            for p in [big, tiny] {
                assert!(close(p.lambda, one.lambda), "{p:?} vs {one:?}");
                let (a, b) = (p.law.surface().unwrap(), one.law.surface().unwrap());
                assert!(close(a.tau, b.tau), "{a:?} vs {b:?}");
            }
            let s = at(1e200, 1e200, c * 1e200).scales();
            assert!(close(s.damping, 2e200) && close(s.omega0, 1.0), "{s:?}");
        }
        // 2 sqrt(m k) = 2e308 is no f64: refused, naming m.
        let e = at(1e308, 1e308, 1.0)
            .params(FrictionLaw::McMillan)
            .unwrap_err();
        assert_eq!(e.key(), Some("m"), "{e}");
        // nu = 1e-300 / 2e300 underflows to 0 from c > 0: refused, naming nu (c).
        let e = at(1e300, 1e300, 1e-300)
            .params(FrictionLaw::McMillan)
            .unwrap_err();
        assert_eq!(e.key(), Some("nu"), "{e}");
    }

    /// A clamped pad of mass 6.6e-309 kg (found by the shipped-spec mutation test on
    /// `scans/brake-curve.toml`): `N / m = 1500 / 6.6e-309` is `inf` in f64, so the velocity
    /// unit was `inf`, every slip speed of the curve 0, and the refusal named the curve's
    /// rows. It names `m`.
    #[test]
    fn a_mass_too_small_for_the_clamp_force_is_named() {
        let pad = Physical {
            m: 6.58514077742547e-309,
            k: 2e5,
            c: 20.0,
            v_belt: 0.3,
            friction: FrictionSi::Table {
                friction_table: pad_curve(),
            },
            load: Load::NormalForce(1500.0),
        };
        let e = pad.params(FrictionLaw::Table).unwrap_err();
        assert_eq!(e.key(), Some("m"), "{e}");
    }

    /// A clamp force of 4.1e-311 N (found by the same test): the velocity unit `N / sqrt(m
    /// k)` is 1e-313, a subnormal f64, and the curve's speeds divided by it are `inf`. The
    /// refusal named the curve's rows; it names `normal_force`.
    #[test]
    fn a_clamp_force_too_small_for_the_curve_is_named() {
        let pad = Physical {
            m: 0.8,
            k: 2e5,
            c: 20.0,
            v_belt: 0.3,
            friction: FrictionSi::Table {
                friction_table: pad_curve(),
            },
            load: Load::NormalForce(4.1444957096256e-311),
        };
        let e = pad.params(FrictionLaw::Table).unwrap_err();
        assert_eq!(e.key(), Some("normal_force"), "{e}");
    }

    /// A pad's measured curve in SI: mu falls from 0.48 at rest to 0.36 at 1 m/s (rows in
    /// m/s), for the table law's tests.
    fn pad_curve() -> &'static FrictionTable {
        FrictionTable::new(&[
            (0.0, 0.48),
            (0.05, 0.44),
            (0.2, 0.4),
            (0.5, 0.37),
            (1.0, 0.36),
        ])
        .unwrap()
    }

    /// The clamped pad of issue 34 with a measured curve: the law is written in the normal
    /// load (MODEL.md section 8), so with m = 0.8 kg, k = 2e5 N/m, c = 20 N s/m, v_B = 0.3
    /// m/s, N = 1500 N: omega_0 = 500 rad/s, sqrt(m k) = 400 kg/s, the force unit N =
    /// 1500 N, the length unit N / k = 7.5 mm, the velocity unit N / sqrt(m k) = 3.75 m/s,
    /// xi = c / (2 sqrt(m k)) = 0.025, v_d = v_B / 3.75 = 0.08, and the table's speeds
    /// divided by 3.75 (its mu as measured). The g-hack g = N / m = 1875 gives the same, bit
    /// for bit; mu_k or a surface given to it is refused by name.
    #[test]
    fn a_measured_curve_scales_in_the_normal_load() {
        let pad = |load| Physical {
            m: 0.8,
            k: 2e5,
            c: 20.0,
            v_belt: 0.3,
            friction: FrictionSi::Table {
                friction_table: pad_curve(),
            },
            load,
        };
        let clamped = pad(Load::NormalForce(1500.0));
        let p = clamped.params(FrictionLaw::Table).unwrap();
        assert_eq!(
            p,
            pad(Load::Weight(1875.0))
                .params(FrictionLaw::Table)
                .unwrap()
        );
        let s = clamped.scales();
        assert!((s.length - 7.5e-3).abs() < 1e-17 && (s.velocity - 3.75).abs() < 1e-15);
        assert!(
            (p.nu - 0.025).abs() < 1e-15 && (p.lambda - 0.08).abs() < 1e-15,
            "{p:?}"
        );
        let t = p.law.table().unwrap();
        for ((s_nd, mu_nd), (s_si, mu_si)) in t.rows().into_iter().zip(pad_curve().rows()) {
            assert_eq!(mu_nd, mu_si);
            assert!((s_nd - s_si / 3.75).abs() <= 1e-16, "{s_nd} vs {s_si}");
        }
        assert_eq!(clamped.values()[4], None, "a table has no mu_k");
        assert_eq!(
            Physical::from_params(&clamped, &p).friction,
            clamped.friction
        );
        let e = FrictionSi::of(FrictionLaw::Table, Some(0.4), None, None, Some(pad_curve()));
        assert_eq!(e.unwrap_err().key(), Some("mu_k"));
        let e = FrictionSi::of(FrictionLaw::Table, None, None, None, None).unwrap_err();
        assert_eq!(e.key(), Some("friction_table"));
        assert!(e.to_string().contains("m/s"), "{e}");
        let e = FrictionSi::of(
            FrictionLaw::Coulomb,
            Some(0.4),
            None,
            None,
            Some(pad_curve()),
        );
        assert_eq!(e.unwrap_err().key(), Some("friction_table"));
        // A McMillan system asked for the table law: the curve is named missing.
        let e = example().params(FrictionLaw::Table).unwrap_err();
        assert_eq!(e.key(), Some("mu_k"), "{e}");
    }
}
