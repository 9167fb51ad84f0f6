//! Steady slip's own stability: every law linearised at the fixed point (crates/core/MODEL.md,
//! section 5, "Is steady slip stable at all?").
//!
//! With `y = x - x*`, `u = x'` and `a = x''`, the equation of motion near the fixed point
//! `(x*, 0)` (slip velocity `v = u - lambda < 0`) reads `a + 2 nu u + y = F(v, a) - F(-lambda, 0)`.
//!
//! **Laws of the slip velocity only** (Coulomb, Stribeck, cubic, tabulated): `F = mu(lambda -
//! u)`, so `F - F* = -mu'(lambda) u + O(u^2)` and the linearisation is the damped oscillator
//! `y'' + d y' + y = 0` with `d = 2 nu + mu'(lambda)` ([`Linear::Smooth`]; `mu' = 0` for
//! Coulomb): eigenvalues `-d/2 +- sqrt(d^2/4 - 1)`. Steady slip attracts for `d > 0` and
//! repels for `d < 0`; `d = 0` is marginal (the nonlinear terms decide).
//!
//! **McMillan's laws** (both): as `a -> 0` at `v = -lambda`, `F1 = 1 + (2/pi) |a| tau / v +
//! O(a^3)` and `F2 = |a| tau / lambda + O(a^2)`, so `F - 1 = k |a| + O(|a| u, a^2)` with
//! `k = (1 - 2/pi) tau / lambda`. The `|a|` term is as large as the acceleration itself: it
//! does not vanish under linearisation, it makes the linear system piecewise
//! ([`Linear::OneSided`]): `(1 + k) a = -sigma` while the block decelerates (`a < 0`) and
//! `(1 - k) a = -sigma` while it accelerates (`a > 0`), `sigma = y + 2 nu u`. Each half is a
//! damped oscillator of mass `m = 1 +- k`, and the system is positively homogeneous, so its
//! stability decides the fixed point's:
//! * `k < 1`: both masses positive. In each half the acceleration obeys the same linear
//!   equation as `y`, so its zeros (the switching line `sigma = 0`) are half a damped period
//!   `pi / omega` apart, `omega = sqrt(m - nu^2) / m`, and the state comes back scaled by
//!   `-exp(-pi nu / sqrt(m - nu^2))`. One revolution multiplies the amplitude by
//!   `rho = exp(-pi nu (1 / sqrt(1 - k - nu^2) + 1 / sqrt(1 + k - nu^2)))` (`rho < 1` for
//!   `nu > 0`): steady slip attracts. A half with `nu^2 >= m` is overdamped and the run
//!   closes on the point inside it, faster still.
//! * `k > 1`: the accelerating half has a negative mass, and the force equation has two
//!   roots near `a = 0` where `sigma > 0` and none where `sigma < 0`: a start with `sigma < 0`
//!   has no small acceleration at all, and a run on the decelerating half that reaches
//!   `sigma = 0` loses its root and jumps. If the decelerating half oscillates (`nu^2 < 1 +
//!   k`) every run reaches that line: steady slip repels ([`Stability::Repels`]). If it is
//!   overdamped, the runs between its two eigendirections on the side `y < 0` close on the
//!   point without ever reaching the line, every other start leaves: it attracts a sector
//!   only ([`Stability::AttractsSector`]), and no neighbourhood of it is a basin.
//! * `k = 1`, or `nu = 0` with `k < 1`, is marginal: the linear terms decide nothing.
//!
//! Checked against runs (tests in `crates/core/tests/model/steady.rs`): the threshold `k = 1`,
//! the multiplier per revolution and the period of a small revolution.

use serde::Serialize;

use crate::law::Friction;
use crate::params::Params;

/// What the linearisation says of steady slip.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
#[repr(u8)]
pub enum Stability {
    /// Every start near the fixed point closes on it.
    Attracts = 1,
    /// No start near it stays (except the point itself).
    Repels = 2,
    /// McMillan's laws with `k > 1` and an overdamped decelerating half: the starts of one
    /// sector close on it, every other start near it leaves.
    AttractsSector = 3,
    /// The linear terms decide nothing (`d = 0`, `k = 1`, or `nu = 0`).
    Marginal = 4,
}

impl Stability {
    /// Every verdict, in value order.
    pub const ALL: [Stability; 4] = [
        Stability::Attracts,
        Stability::Repels,
        Stability::AttractsSector,
        Stability::Marginal,
    ];

    /// The verdict's name in files and output.
    pub fn name(self) -> &'static str {
        match self {
            Stability::Attracts => "attracts",
            Stability::Repels => "repels",
            Stability::AttractsSector => "attracts_a_sector",
            Stability::Marginal => "marginal",
        }
    }

    /// From the stored value.
    pub fn from_u8(v: u8) -> Option<Stability> {
        Stability::ALL.into_iter().find(|s| *s as u8 == v)
    }

    /// Whether every start close enough to the fixed point ends there: the premise of any
    /// "near the fixed point, so steady slip" decision.
    pub fn attracts(self) -> bool {
        self == Stability::Attracts
    }
}

/// The form the linearisation takes.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "form", rename_all = "snake_case")]
pub enum Linear {
    /// `y'' + damping y' + y = 0`, `damping = 2 nu + mu'(lambda)`.
    Smooth {
        /// The effective damping `d`.
        damping: f64,
    },
    /// McMillan's laws: `(1 + k) a = -sigma` while decelerating, `(1 - k) a = -sigma` while
    /// accelerating.
    OneSided {
        /// `k = (1 - 2/pi) tau / lambda`.
        k: f64,
    },
}

/// A damped oscillator `m y'' + 2 nu y' + y = 0` (one half of the one-sided linearisation, or
/// the smooth one with `m = 1`, `2 nu = d`): its two eigenvalues, each `(re, im)`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Oscillator {
    /// The mass (1 for the smooth form).
    pub mass: f64,
    /// The eigenvalues `(-c +- sqrt(c^2 - 4 m)) / (2 m)`, `c` the damping coefficient, as
    /// `(re, im)` (the one with the larger real part first).
    pub eigenvalues: [(f64, f64); 2],
}

impl Oscillator {
    /// `m y'' + c y' + y = 0`.
    fn new(m: f64, c: f64) -> Oscillator {
        let disc = c * c - 4.0 * m;
        let eigenvalues = if disc >= 0.0 {
            let s = disc.sqrt();
            let (a, b) = ((-c + s) / (2.0 * m), (-c - s) / (2.0 * m));
            [(a.max(b), 0.0), (a.min(b), 0.0)]
        } else {
            let (re, im) = (-c / (2.0 * m), (-disc).sqrt() / (2.0 * m));
            [(re, im), (re, -im)]
        };
        Oscillator {
            mass: m,
            eigenvalues,
        }
    }

    /// Whether it oscillates (complex eigenvalues).
    pub fn oscillates(&self) -> bool {
        self.eigenvalues[0].1 != 0.0
    }

    /// The largest real part.
    pub fn growth(&self) -> f64 {
        self.eigenvalues[0].0
    }
}

/// Steady slip's linearisation and its verdict.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SteadySlip {
    /// The verdict.
    pub stability: Stability,
    /// The linearisation's form.
    pub linear: Linear,
    /// The oscillator of the smooth form, or of the decelerating half (`a < 0`).
    pub decelerating: Oscillator,
    /// The accelerating half (`a > 0`) of the one-sided form (its mass is negative where
    /// `k > 1`); `None` for the smooth form.
    pub accelerating: Option<Oscillator>,
    /// The growth rate of small motions, per nondimensional time unit: the logarithm of the
    /// multiplier per revolution over its period where every half oscillates, else the
    /// largest real part of an eigenvalue that a run near the point follows (the decelerating
    /// half's slow one for [`Stability::AttractsSector`]). Negative where it attracts; NaN
    /// where the runs jump ([`Stability::Repels`] of McMillan's laws).
    pub growth: f64,
    /// The factor on the amplitude over one small revolution, where every half oscillates.
    pub multiplier: Option<f64>,
    /// The period of one small revolution (nondimensional), where every half oscillates.
    pub period: Option<f64>,
}

impl SteadySlip {
    /// The linearisation of the model `p` at its fixed point.
    pub fn of(p: &Params) -> SteadySlip {
        match &p.law {
            Friction::McMillan(s) | Friction::NonHysteretic(s) => {
                one_sided(p.nu, (1.0 - std::f64::consts::FRAC_2_PI) * s.tau / p.lambda)
            }
            law => {
                let slope = law.mu(p.lambda).map_or(0.0, |(_, d)| d);
                smooth(2.0 * p.nu + slope)
            }
        }
    }

    /// One line for reports: the verdict and its figures (nondimensional; `time_unit`
    /// seconds per unit of time adds the rate in 1/s).
    pub fn words(&self, time_unit: Option<f64>) -> String {
        let form = match self.linear {
            Linear::Smooth { damping } => {
                format!("effective damping 2 nu + mu'(lambda) = {damping:.6}")
            }
            Linear::OneSided { k } => {
                format!("one-sided in x'': k = (1 - 2/pi) tau / lambda = {k:.6}")
            }
        };
        let mut s = format!(
            "steady slip {} ({form}",
            self.stability.name().replace('_', " ")
        );
        if let Some(m) = self.multiplier {
            s += &format!(", amplitude x {m:.6} per small revolution");
        }
        if self.growth.is_finite() {
            s += &format!(", growth rate {:.6e}", self.growth);
            if let Some(t) = time_unit {
                s += &format!(" = {:.6e} 1/s", self.growth / t);
            }
        }
        s += ")";
        if let Some(why) = self.why() {
            s += &format!(": {why}");
        }
        s
    }

    /// Whether the state `y = x - x*`, `u = x'` with acceleration `a` lies in the sector that
    /// [`Stability::AttractsSector`] attracts, with a margin (always false for the other
    /// verdicts). In the overdamped decelerating half, `y = A e^{r1 t} + B e^{r2 t}` (`r1 > r2`
    /// its eigenvalues) and `a = A r1^2 e^{r1 t} + B r2^2 e^{r2 t}`: with `a < 0` now and
    /// `A = (u - r2 y) / (r1 - r2) < 0`, `a` stays negative (`e^{-r1 t} a` moves
    /// monotonically from its value now to `A r1^2`), so the run never reaches the line
    /// where its root is lost and closes on the point along the slow direction. The margin:
    /// `u - r2 y < -(r1 - r2) |y| / 2` (on the slow direction itself the left side is
    /// `-(r1 - r2) |y|`), which the nonlinear terms, of relative size `|a| / lambda` near the
    /// point, do not undo.
    pub fn closes_in_sector(&self, y: f64, u: f64, a: f64) -> bool {
        if self.stability != Stability::AttractsSector {
            return false;
        }
        let [(r1, _), (r2, _)] = self.decelerating.eigenvalues;
        y < 0.0 && a < 0.0 && u - r2 * y < -0.5 * (r1 - r2) * y.abs()
    }

    /// Why it does not attract, in words (`None` where it does).
    pub fn why(&self) -> Option<&'static str> {
        match (self.stability, self.linear) {
            (Stability::Attracts, _) => None,
            (Stability::Repels, Linear::OneSided { .. }) => Some(
                "k > 1: the force equation has no root near the fixed point's acceleration on one \
                 side, every start near it leaves, none settles",
            ),
            (Stability::Repels, _) => {
                Some("the falling friction curve beats the damping: no start near it settles")
            }
            (Stability::AttractsSector, _) => Some(
                "k > 1 with an overdamped decelerating half: only starts in one sector close on it, \
                 every other start near it leaves",
            ),
            (Stability::Marginal, _) => Some("marginal: the linear terms decide nothing, runs do"),
        }
    }
}

/// The smooth form with effective damping `d`.
fn smooth(d: f64) -> SteadySlip {
    let osc = Oscillator::new(1.0, d);
    let stability = if d > 0.0 {
        Stability::Attracts
    } else if d < 0.0 {
        Stability::Repels
    } else {
        Stability::Marginal
    };
    let (multiplier, period) = match osc.oscillates() {
        true => {
            let period = std::f64::consts::TAU / osc.eigenvalues[0].1;
            (Some((osc.growth() * period).exp()), Some(period))
        }
        false => (None, None),
    };
    SteadySlip {
        stability,
        linear: Linear::Smooth { damping: d },
        decelerating: osc,
        accelerating: None,
        growth: osc.growth(),
        multiplier,
        period,
    }
}

/// The one-sided form of McMillan's laws with damping ratio `nu` and `k`.
fn one_sided(nu: f64, k: f64) -> SteadySlip {
    let (dec, acc) = (
        Oscillator::new(1.0 + k, 2.0 * nu),
        Oscillator::new(1.0 - k, 2.0 * nu),
    );
    let linear = Linear::OneSided { k };
    let both = dec.oscillates() && acc.oscillates() && k < 1.0;
    let (multiplier, period) = match both {
        true => {
            let half = |o: &Oscillator| std::f64::consts::PI / o.eigenvalues[0].1;
            let period = half(&dec) + half(&acc);
            let m = (dec.growth() * half(&dec) + acc.growth() * half(&acc)).exp();
            (Some(m), Some(period))
        }
        false => (None, None),
    };
    let (stability, growth) = if k < 1.0 {
        match nu > 0.0 {
            true => (
                Stability::Attracts,
                match (multiplier, period) {
                    (Some(m), Some(t)) => m.ln() / t,
                    _ => dec.growth().max(acc.growth()),
                },
            ),
            false => (Stability::Marginal, 0.0),
        }
    } else if k > 1.0 {
        match dec.oscillates() {
            true => (Stability::Repels, f64::NAN),
            false if dec.eigenvalues[0].0 < 0.0 && dec.eigenvalues[0] != dec.eigenvalues[1] => {
                (Stability::AttractsSector, dec.growth())
            }
            false => (Stability::Marginal, f64::NAN),
        }
    } else {
        (Stability::Marginal, f64::NAN)
    };
    SteadySlip {
        stability,
        linear,
        decelerating: dec,
        accelerating: Some(acc),
        growth,
        multiplier,
        period,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::law::FrictionLaw;

    /// Table 1: k = (1 - 2/pi) 0.31623 / 3 = 0.36338 x 0.10541 = 0.038304; the multiplier is the closed form of
    /// the module's argument.
    #[test]
    fn table_1_attracts_with_the_closed_form_multiplier() {
        let p = Params::paper(FrictionLaw::McMillan, 1e-2);
        let s = SteadySlip::of(&p);
        let Linear::OneSided { k } = s.linear else {
            panic!("{s:?}")
        };
        assert!((k - 0.038_304).abs() < 1e-6, "{k}");
        assert_eq!(s.stability, Stability::Attracts);
        let nu = 1e-2_f64;
        let rho = (-std::f64::consts::PI
            * nu
            * (1.0 / (1.0 - k - nu * nu).sqrt() + 1.0 / (1.0 + k - nu * nu).sqrt()))
        .exp();
        assert!((s.multiplier.unwrap() - rho).abs() < 1e-12);
        assert!(s.growth < 0.0);
    }

    /// k = 1 is the threshold; past it the verdict turns on the decelerating half's
    /// oscillation (nu^2 against 1 + k).
    #[test]
    fn past_k_one_it_repels_or_attracts_a_sector() {
        let mut p = Params::paper(FrictionLaw::McMillan, 2.0);
        p.lambda = 0.1;
        p.law = p.law.with_surface(|s| s.tau = 1.0);
        // k = 3.634, 1 + k = 4.634: nu = 2 oscillates, nu = 3 does not.
        assert_eq!(SteadySlip::of(&p).stability, Stability::Repels);
        p.nu = 3.0;
        let s = SteadySlip::of(&p);
        assert_eq!(s.stability, Stability::AttractsSector);
        assert!(s.growth < 0.0);
        p.nu = 0.0;
        p.lambda = 3.0;
        assert_eq!(SteadySlip::of(&p).stability, Stability::Marginal);
    }

    /// Stribeck: d = 2 xi + mu'(v_d), the damping the region's argument uses.
    #[test]
    fn smooth_laws_use_the_slope_of_the_curve() {
        let p = Params::bstab();
        let s = SteadySlip::of(&p);
        let Linear::Smooth { damping } = s.linear else {
            panic!("{s:?}")
        };
        assert_eq!(Some(damping), p.fixed_point_damping());
        let want = if damping > 0.0 {
            Stability::Attracts
        } else {
            Stability::Repels
        };
        assert_eq!(s.stability, want);
        // The eigenvalues of y'' + d y' + y = 0 satisfy it.
        let (re, im) = s.decelerating.eigenvalues[0];
        let (r2, i2) = (re * re - im * im, 2.0 * re * im);
        assert!((r2 + damping * re + 1.0).abs() < 1e-12 && (i2 + damping * im).abs() < 1e-12);
    }
}
