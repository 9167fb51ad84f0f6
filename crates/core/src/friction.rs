//! Friction laws of McMillan (1997), nondimensional, with their partial derivatives.
//!
//! With slip velocity `v = x' - lambda`, acceleration `a = x''`, `s = sgn(a)`, `b = |a| tau`:
//!
//! ```text
//! F1 = -(2/pi) arctan(v / b)
//! F2 = -b / (v - a tau)                              if s v < 0 or s v > 2 b   (slip branch)
//! F2 = (s / sin Phi) sin((pi - Phi) v / (a tau) + Phi)   if 0 <= s v <= 2 b  (quasi-static)
//! F  = F1 + F2                                                               (eq. 4.1)
//!
//! non-hysteretic (eq. 5.1):  F = F1 + ( -b / v                          if |v| > b
//!                                     ( sin((Phi - pi) v / b) / sin Phi  otherwise
//! ```
//!
//! **Convention where the formula is undefined.** At `a = 0` the laws take their limit as
//! `a -> 0` with `v != 0`: `F = -sgn(v)` (Coulomb). At `v = 0` and `a = 0` every value in
//! `[-1, 1]` is a limit point; squeal takes `F = 0` there (the middle of Coulomb's set).
//! Coulomb's own law is `-sgn(v)` with the same `F(0) = 0`; its implicit solve treats `v = 0`
//! as the set `[-1, 1]` (sticking), see [`crate::solver`].

use std::f64::consts::{FRAC_2_PI, PI};

use crate::atan::atan_ratio;
use crate::law::{Friction, FrictionLaw, PerV0, Stribeck, Surface};
use crate::params::Params;

/// Which piece of the law was used.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Branch {
    /// `a = 0` (Coulomb limit) or the Coulomb law itself.
    Coulomb,
    /// Slip branch of F2.
    Slip,
    /// Quasi-static branch of F2 (`0 <= s v <= 2|a| tau`; `|v| <= |a| tau` non-hysteretic).
    QuasiStatic,
    /// Stuck to the belt under a law with true stick: the force is whatever holds the block,
    /// within the static limit.
    Stick,
}

/// A value of the friction law and its partial derivatives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForceEval {
    /// `F(v, a)`.
    pub force: f64,
    /// `dF/dv` (slip velocity).
    pub dv: f64,
    /// `dF/da` (acceleration).
    pub da: f64,
    /// The branch used.
    pub branch: Branch,
}

/// `sgn` with `sgn(0) = 0`.
fn sgn0(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// The nondimensional friction force at slip velocity `v` and acceleration `a` (builds the
/// law's constants on every call; the stepper holds a [`Law`] instead).
#[inline]
pub fn force(p: &Params, v: f64, a: f64) -> ForceEval {
    Law::new(p).eval(v, a)
}

/// McMillan's constants (`sin Phi`, `pi - Phi`), shared by his two laws.
#[derive(Clone, Copy, Debug, PartialEq)]
struct McMillanConsts {
    tau: f64,
    phi: f64,
    /// `1 / sin Phi`.
    inv_sin_phi: f64,
    /// `pi - Phi`.
    pi_minus_phi: f64,
}

impl McMillanConsts {
    fn new(c: Surface) -> McMillanConsts {
        McMillanConsts {
            tau: c.tau,
            phi: c.phi,
            inv_sin_phi: 1.0 / c.phi.sin(),
            pi_minus_phi: PI - c.phi,
        }
    }
}

/// The Stribeck law with the division by `v_0` built once (see [`PerV0`]).
#[derive(Clone, Copy, Debug, PartialEq)]
struct StribeckConsts {
    params: Stribeck,
    per_v0: PerV0,
}

/// The law's form with its constants: what [`Law`] branches on.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Form {
    McMillan(McMillanConsts),
    NonHysteretic(McMillanConsts),
    Coulomb,
    Stribeck(StribeckConsts),
    /// Every other law with true stick: `mu` and the static limit are the law's own
    /// ([`Friction::mu`], [`Friction::static_limit`]).
    Stick(Friction),
}

/// A friction law with its constants computed once (`sin Phi`, `pi - Phi`, ...): what the
/// stepper and the solver evaluate. Built from the law's parameters ([`Friction`]): a law
/// with true stick needs nothing here (its `mu` and static limit are [`Friction`]'s); a
/// law of another family is a variant of its own with arms in [`Law::new`] and
/// [`Law::eval`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Law {
    form: Form,
    /// Bound on `|F|` over all states ([`Params::force_bound`]).
    bound: f64,
}

impl Law {
    /// The law of `p` with its constants.
    pub fn new(p: &Params) -> Law {
        let form = match p.law {
            Friction::McMillan(c) => Form::McMillan(McMillanConsts::new(c)),
            Friction::NonHysteretic(c) => Form::NonHysteretic(McMillanConsts::new(c)),
            Friction::Coulomb => Form::Coulomb,
            Friction::Stribeck(s) => Form::Stribeck(StribeckConsts {
                params: s,
                per_v0: PerV0::new(s.v_0),
            }),
            stick => {
                debug_assert!(stick.family().locates_stick(), "{stick}");
                Form::Stick(stick)
            }
        };
        Law {
            form,
            bound: p.force_bound(),
        }
    }

    /// Which law.
    pub fn kind(&self) -> FrictionLaw {
        match self.form {
            Form::McMillan(_) => FrictionLaw::McMillan,
            Form::NonHysteretic(_) => FrictionLaw::McMillanNonHysteretic,
            Form::Coulomb => FrictionLaw::Coulomb,
            Form::Stribeck(_) => FrictionLaw::Stribeck,
            Form::Stick(f) => f.kind(),
        }
    }

    /// McMillan's surface time `tau` (`None` for the other laws).
    pub fn tau(&self) -> Option<f64> {
        match self.form {
            Form::McMillan(c) | Form::NonHysteretic(c) => Some(c.tau),
            _ => None,
        }
    }

    /// Every root of a force equation lies in `[-bound, bound]`.
    pub fn bound(&self) -> f64 {
        self.bound
    }

    /// `F(v, a)` with its partial derivatives and the branch used (at a set-valued point,
    /// `v = 0` for a law that sticks, the middle of the set).
    #[inline]
    pub fn eval(&self, v: f64, a: f64) -> ForceEval {
        match &self.form {
            Form::McMillan(c) => mcmillan_k(v, a, c.tau, c.phi, c.inv_sin_phi, c.pi_minus_phi),
            Form::NonHysteretic(c) => nonhysteretic_k(v, a, c.tau, c.inv_sin_phi, c.pi_minus_phi),
            Form::Coulomb => coulomb(v),
            Form::Stribeck(_) | Form::Stick(_) => {
                if v == 0.0 {
                    // Set-valued: the middle of [-mu_s, mu_s], as Coulomb's F(0) = 0.
                    return ForceEval {
                        force: 0.0,
                        dv: 0.0,
                        da: 0.0,
                        branch: Branch::Stick,
                    };
                }
                let (mu, dmu) = self.mu(v.abs());
                ForceEval {
                    force: -sgn0(v) * mu,
                    dv: -dmu,
                    da: 0.0,
                    branch: Branch::Slip,
                }
            }
        }
    }

    /// `mu(s)` and `mu'(s)` of a law with true stick at slip speed `s > 0` (the force is
    /// `-sgn(v) mu(|v|)` while slipping); `(0, 0)` for the others, never called for them.
    #[inline]
    fn mu(&self, s: f64) -> (f64, f64) {
        match &self.form {
            Form::Stribeck(c) => c.params.mu_by(s, &c.per_v0),
            Form::Stick(f) => f.mu(s).unwrap_or((0.0, 0.0)),
            _ => (0.0, 0.0),
        }
    }

    /// The static limit of a law with true stick: while `v = 0` the force can take any value
    /// in `[-limit, limit]`. Such laws are stepped with located stick events
    /// ([`crate::stick`]); `None` for the others.
    pub fn static_limit(&self) -> Option<f64> {
        match &self.form {
            Form::Stribeck(c) => Some(c.params.mu_s()),
            Form::Stick(f) => f.static_limit(),
            _ => None,
        }
    }

    /// The force while slipping on the side `sigma = sgn(v)` (+1 or -1), extended to the other
    /// side by its value at `v = 0` (continuous, so a step that overshoots zero slip can be
    /// bisected to the event), with `dF/dv`.
    #[inline]
    pub fn sliding(&self, sigma: f64, v: f64) -> (f64, f64) {
        if let Some(mu_s) = self.static_limit() {
            let s = sigma * v;
            return if s > 0.0 {
                let (mu, dmu) = self.mu(s);
                (-sigma * mu, -dmu)
            } else {
                (-sigma * mu_s, 0.0)
            };
        }
        let e = self.eval(if sigma * v > 0.0 { v } else { 0.0 }, 0.0);
        (e.force, if sigma * v > 0.0 { e.dv } else { 0.0 })
    }

    /// Whether `(v, a)` lies on a quasi-static branch of the law (cheap; no evaluation).
    #[inline]
    pub fn quasi_static(&self, v: f64, a: f64) -> bool {
        match &self.form {
            Form::McMillan(c) => {
                let b = a.abs() * c.tau;
                a != 0.0 && (0.0..=2.0 * b).contains(&(v * a.signum()))
            }
            Form::NonHysteretic(c) => a != 0.0 && v.abs() <= a.abs() * c.tau,
            _ => false,
        }
    }
}

/// Whether `(v, a)` lies on the quasi-static branch of the law (cheap; no evaluation).
#[inline]
pub fn on_quasi_static_branch(p: &Params, v: f64, a: f64) -> bool {
    Law::new(p).quasi_static(v, a)
}

/// Plain Coulomb friction `-sgn(v)`, with `F(0) = 0`.
#[inline]
pub fn coulomb(v: f64) -> ForceEval {
    ForceEval {
        force: -sgn0(v),
        dv: 0.0,
        da: 0.0,
        branch: Branch::Coulomb,
    }
}

/// McMillan's hysteretic law, eq. (4.1) corrected.
#[inline]
pub fn mcmillan(v: f64, a: f64, tau: f64, phi: f64) -> ForceEval {
    mcmillan_k(v, a, tau, phi, 1.0 / phi.sin(), PI - phi)
}

#[inline]
fn mcmillan_k(
    v: f64,
    a: f64,
    tau: f64,
    phi: f64,
    inv_sin_phi: f64,
    pi_minus_phi: f64,
) -> ForceEval {
    if a == 0.0 {
        return coulomb(v);
    }
    let s = if a > 0.0 { 1.0 } else { -1.0 };
    let b = a.abs() * tau;
    let den1 = b * b + v * v;
    let f1 = -FRAC_2_PI * atan_ratio(v, b);
    let f1_dv = -FRAC_2_PI * b / den1;
    let f1_da = FRAC_2_PI * v * s * tau / den1;
    let sv = s * v;
    if sv < 0.0 || sv > 2.0 * b {
        let d = v - a * tau;
        let f2 = -b / d;
        ForceEval {
            force: f1 + f2,
            dv: f1_dv + b / (d * d),
            da: f1_da - s * tau / d - b * tau / (d * d),
            branch: Branch::Slip,
        }
    } else {
        let k = pi_minus_phi / (a * tau);
        let theta = k * v + phi;
        let (sn, cs) = theta.sin_cos();
        let amp = s * inv_sin_phi;
        ForceEval {
            force: f1 + amp * sn,
            dv: f1_dv + amp * cs * k,
            da: f1_da - amp * cs * k * v / a,
            branch: Branch::QuasiStatic,
        }
    }
}

/// The non-hysteretic law, eq. (5.1) corrected (`|x''|` in the sine argument).
#[inline]
pub fn nonhysteretic(v: f64, a: f64, tau: f64, phi: f64) -> ForceEval {
    nonhysteretic_k(v, a, tau, 1.0 / phi.sin(), PI - phi)
}

#[inline]
fn nonhysteretic_k(v: f64, a: f64, tau: f64, inv_sin_phi: f64, pi_minus_phi: f64) -> ForceEval {
    if a == 0.0 {
        return coulomb(v);
    }
    let s = if a > 0.0 { 1.0 } else { -1.0 };
    let b = a.abs() * tau;
    let den1 = b * b + v * v;
    let f1 = -FRAC_2_PI * atan_ratio(v, b);
    let f1_dv = -FRAC_2_PI * b / den1;
    let f1_da = FRAC_2_PI * v * s * tau / den1;
    if v.abs() > b {
        ForceEval {
            force: f1 - b / v,
            dv: f1_dv + b / (v * v),
            da: f1_da - s * tau / v,
            branch: Branch::Slip,
        }
    } else {
        let k = -pi_minus_phi / b;
        let psi = k * v;
        let (sn, cs) = psi.sin_cos();
        ForceEval {
            force: f1 + sn * inv_sin_phi,
            dv: f1_dv + cs * inv_sin_phi * k,
            da: f1_da - cs * inv_sin_phi * psi * s * tau / b,
            branch: Branch::QuasiStatic,
        }
    }
}

/// The dimensional law of the paper (eqs. 3.2-3.4) as `F / (m g)`.
///
/// `v_r` is the slip velocity in m/s, `acc` the acceleration in m/s^2, `tau` the surfaces'
/// characteristic time in s, `mu_k` the kinetic coefficient and `phi = arcsin(mu_k / mu_s)`.
/// It is `mu_k` times the nondimensional law with `tau / mu_k` in place of `tau`.
pub fn dimensional(v_r: f64, acc: f64, mu_k: f64, tau: f64, phi: f64) -> f64 {
    mu_k * mcmillan(v_r, acc, tau / mu_k, phi).force
}

/// The fixed point is where the force balances the spring at rest on the belt, so it is
/// computed from the force here rather than in `params` (which knows no forces).
impl Params {
    /// The steady-slip fixed point: `x' = x'' = 0`, so `x* = F(-lambda, 0)`
    /// (`x* = 1` for `lambda > 0` under McMillan's laws, `x* = mu(v_d)` under Stribeck's).
    pub fn fixed_point(&self) -> crate::State {
        let f = force(self, -self.lambda, 0.0).force;
        crate::State { x: f, v: 0.0 }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const TAU: f64 = 0.316_227_766_016_837_94;

    #[test]
    fn value_at_fixed_point_is_one() {
        for law in FrictionLaw::MCMILLAN {
            let p = Params::paper(law, 1e-3);
            assert_eq!(force(&p, -p.lambda, 0.0).force, 1.0, "{law}");
            let fp = p.fixed_point();
            assert_eq!((fp.x, fp.v), (1.0, 0.0));
        }
    }

    #[test]
    fn branch_values_at_boundaries() {
        // F2 = s at v = 0 and F2 = -s at s v = 2|a| tau (crates/core/MODEL.md, section 3).
        for a in [2.0, -2.0, 0.3, -7.0] {
            let s = f64::signum(a);
            let b = a.abs() * TAU;
            let f = mcmillan(0.0, a, TAU, 1.0).force;
            assert!((f - s).abs() < 1e-15, "a={a} f={f}");
            let v = 2.0 * b * s;
            let f1 = -FRAC_2_PI * (v / b).atan();
            let q = mcmillan(v, a, TAU, 1.0).force - f1;
            let slip = mcmillan(v * (1.0 + 1e-12), a, TAU, 1.0).force - f1;
            assert!(
                (q + s).abs() < 1e-12 && (slip + s).abs() < 1e-9,
                "a={a} {q} {slip}"
            );
        }
    }

    /// Continuity across each branch boundary: approach the boundary from both sides.
    fn check_continuity(law: fn(f64, f64, f64, f64) -> ForceEval, v_edge: f64, a: f64) {
        let eps = 1e-12 * (1.0 + v_edge.abs());
        let lo = law(v_edge - eps, a, TAU, 1.0).force;
        let hi = law(v_edge + eps, a, TAU, 1.0).force;
        assert!(
            (lo - hi).abs() < 1e-6,
            "jump at v={v_edge} a={a}: {lo} vs {hi}"
        );
    }

    #[test]
    fn continuity_across_branch_boundaries() {
        for a in [1.5, -1.5, 1e-3, -40.0] {
            let b = f64::abs(a) * TAU;
            let s = f64::signum(a);
            check_continuity(mcmillan, 0.0, a);
            check_continuity(mcmillan, 2.0 * b * s, a);
            check_continuity(nonhysteretic, b, a);
            check_continuity(nonhysteretic, -b, a);
            check_continuity(nonhysteretic, 0.0, a);
        }
        // Across a = 0 with v != 0 (both laws tend to -sgn v).
        for v in [-3.0, -0.2, 0.5] {
            for law in [mcmillan, nonhysteretic] {
                let l = law(v, -1e-9, TAU, 1.0).force;
                let r = law(v, 1e-9, TAU, 1.0).force;
                let z = law(v, 0.0, TAU, 1.0).force;
                assert!(
                    (l - z).abs() < 1e-6 && (r - z).abs() < 1e-6,
                    "v={v}: {l} {z} {r}"
                );
            }
        }
    }

    #[test]
    fn coulomb_limit_as_acceleration_vanishes() {
        for v in [-3.0, -1.0, 0.01, 2.0] {
            for law in [mcmillan, nonhysteretic] {
                let f = law(v, 1e-10, TAU, 1.0).force;
                assert!((f + v.signum()).abs() < 1e-6, "v={v} f={f}");
            }
        }
        assert_eq!(mcmillan(0.0, 0.0, TAU, 1.0).force, 0.0);
        assert_eq!(coulomb(0.0).force, 0.0);
    }

    /// The dimensional law (paper eqs. 3.2-3.4, as written in MODEL.md) transcribed term by
    /// term in SI units, as `F / (m g)`; `mu_s = mu_k / sin Phi`.
    fn paper_dimensional(v_r: f64, acc: f64, mu_k: f64, tau: f64, phi: f64) -> f64 {
        let mu_s = mu_k / phi.sin();
        let s = acc.signum();
        let f1 = -mu_k * FRAC_2_PI * (v_r * mu_k / (acc.abs() * tau)).atan();
        let f2 = if s * v_r < 0.0 || s * v_r > 2.0 * acc.abs() * tau / mu_k {
            -acc.abs() * tau / (v_r - acc * tau / mu_k)
        } else {
            let omega = mu_k * (PI - phi) / (acc * tau);
            s * mu_s * (omega * v_r + phi).sin()
        };
        f1 + f2
    }

    #[test]
    fn dimensional_law_scales_to_the_nondimensional_one() {
        // Section 4's scaling with natural frequency w = sqrt(s/m): x' = w v_R / (mu_k g),
        // x'' = acc / (mu_k g), tau' = tau w / mu_k and F' = F / (mu_k m g). So
        // F(v_R, acc) / (m g) = mu_k F'(w v_R / (mu_k g), acc / (mu_k g); tau', Phi), for
        // every mu_k, not only 1. Both sides computed independently: the left from the
        // transcription above, the right from the nondimensional law the engine integrates.
        let (g, w, tau) = (9.81, 200.0, 1e-3);
        let mut quasi_static = 0;
        for mu_k in [0.3, 0.55, 1.7] {
            for phi in [0.4, 1.0, 1.5] {
                // Both branches: the quasi-static window is 0 <= s v_R <= 2 |acc| tau / mu_k.
                for (v_r, acc) in [
                    (1e-3, 2.0),
                    (-1e-3, 2.0),
                    (5e-3, 2.0),
                    (1e-4, -2.0),
                    (-2e-3, -3.0),
                    (0.05, 0.7),
                    (-0.3, 40.0),
                    (2e-3, 0.9),
                ] {
                    let want = paper_dimensional(v_r, acc, mu_k, tau, phi);
                    let nd = mcmillan(w * v_r / (mu_k * g), acc / (mu_k * g), tau * w / mu_k, phi);
                    if nd.branch == Branch::QuasiStatic {
                        quasi_static += 1;
                    }
                    let scaled = mu_k * nd.force;
                    let tol = 1e-12 * (1.0 + want.abs());
                    assert!(
                        (scaled - want).abs() < tol,
                        "mu_k {mu_k} phi {phi} v_R {v_r} acc {acc}: {scaled} vs {want}"
                    );
                    let dim = dimensional(v_r, acc, mu_k, tau, phi);
                    assert!((dim - want).abs() < tol, "dimensional(): {dim} vs {want}");
                }
            }
        }
        assert!(
            quasi_static >= 9,
            "both branches covered: {quasi_static} quasi-static"
        );
        // At zero slip F2 = sgn(acc) mu_k (the peak of Figs 4-5 is mu_k, scaled by mu_k).
        let f = dimensional(0.0, 2.0, 0.5, 1e-3, 1.0);
        assert!((f - 0.5).abs() < 1e-15);
    }

    fn fd_check(law: fn(f64, f64, f64, f64) -> ForceEval, v: f64, a: f64) {
        let e = law(v, a, TAU, 1.0);
        let h = 1e-7 * (1.0 + v.abs());
        let (p, m) = (law(v + h, a, TAU, 1.0), law(v - h, a, TAU, 1.0));
        if p.branch == e.branch && m.branch == e.branch {
            let fd = (p.force - m.force) / (2.0 * h);
            assert!(
                (fd - e.dv).abs() < 1e-4 * (1.0 + fd.abs()),
                "dv v={v} a={a}: {fd} {}",
                e.dv
            );
        }
        let h = 1e-7 * (1.0 + a.abs());
        let (p, m) = (law(v, a + h, TAU, 1.0), law(v, a - h, TAU, 1.0));
        if p.branch == e.branch && m.branch == e.branch && (a - h) * (a + h) > 0.0 {
            let fd = (p.force - m.force) / (2.0 * h);
            assert!(
                (fd - e.da).abs() < 1e-4 * (1.0 + fd.abs()),
                "da v={v} a={a}: {fd} {}",
                e.da
            );
        }
    }

    proptest! {
        #[test]
        fn derivatives_match_finite_differences(v in -5.0f64..5.0, a in -10.0f64..10.0) {
            prop_assume!(a.abs() > 1e-3 && v.abs() > 1e-6);
            fd_check(mcmillan, v, a);
            fd_check(nonhysteretic, v, a);
        }

        #[test]
        fn force_is_bounded(v in -50.0f64..50.0, a in -50.0f64..50.0) {
            let bound = 1.0 + 1.0 / 1f64.sin();
            for law in [mcmillan, nonhysteretic] {
                let f = law(v, a, TAU, 1.0).force;
                prop_assert!(f.is_finite() && f.abs() <= bound, "F({v},{a}) = {f}");
            }
        }

        #[test]
        fn nonhysteretic_is_even_in_acceleration(v in -5.0f64..5.0, a in 1e-3f64..10.0) {
            let l = nonhysteretic(v, a, TAU, 1.0).force;
            let r = nonhysteretic(v, -a, TAU, 1.0).force;
            prop_assert!((l - r).abs() < 1e-14);
        }
    }
}
