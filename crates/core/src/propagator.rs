//! Exact solution of the linear oscillator `x'' + 2 nu x' + x = F(t)` over one step, with the
//! force either held constant (zero-order hold: the paper's Duhamel integral, eqs. 4.3-4.6,
//! propagated from the current state instead of the moving frame of eqs. 4.7-4.8) or linear
//! over the step (first-order hold, [`Scheme::Foh`]).
//!
//! With `y = x - F` the step is the free damped oscillator, so the end state is linear in
//! `(x0 - F, v0)`:
//!
//! ```text
//! x(h) = F + c11 (x0 - F) + c12 v0
//! v(h) =     c21 (x0 - F) + c22 v0
//! ```
//!
//! The four coefficients play the role of the paper's T1..T6; they depend only on `nu` and
//! `h` and are computed once. All damping ratios `nu >= 0` are covered: under-damped
//! (`nu < 1`), critically damped (`nu = 1`) and over-damped (`nu > 1`, written with
//! exponentials and `expm1` so that large `nu` neither overflows nor cancels).

use serde::{Deserialize, Serialize};

use crate::error::CoreError;

/// How the friction force varies over one step of length `h` (the linear part is exact in
/// both).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Scheme {
    /// First-order hold: `F(t) = F_j + (F_{j+1} - F_j) t / h`, integrated exactly (an
    /// exponential integrator). Second order in `h`.
    #[default]
    Foh,
    /// Zero-order hold at the end-of-step force, `F(t) = F_{j+1}`: the paper's scheme
    /// (eqs. 4.3-4.6). First order in `h`.
    Zoh,
}

impl Scheme {
    /// The name used on the command line, in specs and in files.
    pub fn name(self) -> &'static str {
        match self {
            Scheme::Foh => "foh",
            Scheme::Zoh => "zoh",
        }
    }
}

impl std::str::FromStr for Scheme {
    type Err = CoreError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "foh" => Ok(Scheme::Foh),
            "zoh" => Ok(Scheme::Zoh),
            _ => Err(CoreError::UnknownScheme(s.to_string())),
        }
    }
}

impl std::fmt::Display for Scheme {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The step matrix of the free oscillator over one step `h`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Propagator {
    /// Step length.
    pub h: f64,
    /// Damping ratio.
    pub nu: f64,
    /// `dx(h)/dy0`.
    pub c11: f64,
    /// `dx(h)/dv0`.
    pub c12: f64,
    /// `dv(h)/dy0`.
    pub c21: f64,
    /// `dv(h)/dv0`.
    pub c22: f64,
    /// `x(h)` per unit of a force falling linearly from 1 at the start of the step to 0 at
    /// its end: `(1/h) int_0^h u g(u) du`, `g` the impulse response (first-order hold).
    pub q1: f64,
    /// `v(h)` for the same force: `(1/h) int_0^h u g'(u) du`.
    pub q2: f64,
}

impl Propagator {
    /// Builds the propagator; refuses `h <= 0`, non-finite values and `nu < 0`.
    pub fn new(nu: f64, h: f64) -> Result<Propagator, CoreError> {
        if !h.is_finite() || h <= 0.0 {
            return Err(CoreError::InvalidParameter {
                name: "dt",
                value: h,
                expected: "a finite step > 0",
            });
        }
        if !nu.is_finite() || nu < 0.0 {
            return Err(CoreError::InvalidParameter {
                name: "nu",
                value: nu,
                expected: "a finite damping ratio >= 0",
            });
        }
        // Free solution from (y0, v0): y = e^{-nu t} [y0 C + (v0 + nu y0) S],
        // v = e^{-nu t} [v0 C - (nu v0 + y0) S], with (C, S) = (cos wt, sin(wt)/w),
        // (1, t) or (cosh wt, sinh(wt)/w).
        let (ec, es) = if nu < 1.0 {
            let w = ((1.0 - nu) * (1.0 + nu)).sqrt();
            let e = (-nu * h).exp();
            let (sn, cs) = (w * h).sin_cos();
            (e * cs, e * sn / w)
        } else if nu == 1.0 {
            let e = (-h).exp();
            (e, e * h)
        } else {
            let w = ((nu - 1.0) * (nu + 1.0)).sqrt();
            // e^{-nu h} cosh(w h) = (e1 + e2)/2 and e^{-nu h} sinh(w h)/w = (e1 - e2)/(2w),
            // with e1 = e^{-(nu-w)h}, e2 = e^{-(nu+w)h} and nu - w = 1/(nu + w) exactly.
            let e1 = (-h / (nu + w)).exp();
            let e2 = (-(nu + w) * h).exp();
            let diff = -e1 * (-2.0 * w * h).exp_m1();
            ((e1 + e2) / 2.0, diff / (2.0 * w))
        };
        let (q1, q2) = ramp_response(nu, h);
        Ok(Propagator {
            h,
            nu,
            c11: ec + nu * es,
            c12: es,
            c21: -es,
            c22: ec - nu * es,
            q1,
            q2,
        })
    }

    /// End of the step from `(x0, v0)` with the force `f0` at the start and `f1` at the end,
    /// linear in between (first-order hold).
    #[inline]
    pub fn advance_linear(&self, x0: f64, v0: f64, f0: f64, f1: f64) -> (f64, f64) {
        let (x, v) = self.advance(x0, v0, f1);
        (x + self.q1 * (f0 - f1), v + self.q2 * (f0 - f1))
    }

    /// End of the step from `(x0, v0)` with the force `f` held constant.
    #[inline]
    pub fn advance(&self, x0: f64, v0: f64, f: f64) -> (f64, f64) {
        let y0 = x0 - f;
        (
            f + self.c11 * y0 + self.c12 * v0,
            self.c21 * y0 + self.c22 * v0,
        )
    }
}

/// `psi(z) = int_0^1 s e^{z s} ds = (e^z (z - 1) + 1) / z^2`, by its series
/// `sum z^n / (n! (n + 2))` where the closed form cancels (`|z| <= 1`).
fn psi(z: f64) -> f64 {
    if z.abs() <= 1.0 {
        let (mut term, mut sum) = (1.0, 0.5);
        for n in 1..40 {
            term *= z / n as f64;
            let add = term / (n + 2) as f64;
            sum += add;
            if add.abs() <= 1e-17 * sum.abs() {
                break;
            }
        }
        sum
    } else {
        (z.exp() * (z - 1.0) + 1.0) / (z * z)
    }
}

/// The ramp response `(q1, q2)` of [`Propagator`]: `(1/h) int_0^h u (g(u), g'(u)) du` with `g`
/// the impulse response (`g'' + 2 nu g' + g = 0`, `g(0) = 0`, `g'(0) = 1`).
///
/// Free of cancellation at small `h`: while `rho h <= 2` (`rho` the largest `|root|` of
/// `r^2 + 2 nu r + 1`: always for `nu <= 1` since `dt <= 1`), the Taylor series of `g`
/// (`g_{n+2} = -2 nu g_{n+1} - g_n`) is integrated term by term, every term of size
/// `(rho h)^n / n!`; beyond, the over-damped modes `r1 = -1/(nu + w)`, `r2 = -(nu + w)`
/// (`w = sqrt(nu^2 - 1)`, `r1 - r2 = 2 w > 1.5` there) are integrated with [`psi`].
fn ramp_response(nu: f64, h: f64) -> (f64, f64) {
    let rho = if nu > 1.0 {
        nu + ((nu - 1.0) * (nu + 1.0)).sqrt()
    } else {
        1.0
    };
    if rho * h <= 2.0 {
        ramp_series(nu, h)
    } else {
        ramp_modes(nu, h)
    }
}

/// q1 = sum_{n>=1} g_n h^{n+1} / ((n+2) n!), q2 = sum_{n>=0} g_{n+1} h^{n+1} / ((n+2) n!).
fn ramp_series(nu: f64, h: f64) -> (f64, f64) {
    let (mut g0, mut g1) = (0.0f64, 1.0f64); // g_n, g_{n+1}
    let (mut q1, mut q2) = (0.0, 0.0);
    let mut hn = h; // h^{n+1} / n!
    for n in 0..80 {
        let k = 1.0 / (n + 2) as f64;
        let (a1, a2) = (g0 * hn * k, g1 * hn * k);
        q1 += a1;
        q2 += a2;
        if n > 4 && a1.abs() <= 1e-18 * q1.abs() && a2.abs() <= 1e-18 * q2.abs() {
            break;
        }
        (g0, g1) = (g1, -2.0 * nu * g1 - g0);
        hn *= h / (n + 1) as f64;
    }
    (q1, q2)
}

/// The over-damped modes: `g = (e^{r1 u} - e^{r2 u}) / (r1 - r2)`.
fn ramp_modes(nu: f64, h: f64) -> (f64, f64) {
    let w = ((nu - 1.0) * (nu + 1.0)).sqrt();
    let (r1, r2) = (-1.0 / (nu + w), -(nu + w));
    let (p1, p2) = (psi(r1 * h), psi(r2 * h));
    (
        h * (p1 - p2) / (2.0 * w),
        h * (r1 * p1 - r2 * p2) / (2.0 * w),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Closed-form damped oscillator with constant force, evaluated directly at time t
    /// (textbook formulas, e.g. Meirovitch, "Elements of Vibration Analysis", ch. 3).
    fn exact(nu: f64, f: f64, x0: f64, v0: f64, t: f64) -> (f64, f64) {
        let y0 = x0 - f;
        if nu < 1.0 {
            let w = (1.0 - nu * nu).sqrt();
            let a = y0;
            let b = (v0 + nu * y0) / w;
            let e = (-nu * t).exp();
            let y = e * (a * (w * t).cos() + b * (w * t).sin());
            let v = e * ((b * w - nu * a) * (w * t).cos() - (a * w + nu * b) * (w * t).sin());
            (f + y, v)
        } else if nu == 1.0 {
            let e = (-t).exp();
            let c = v0 + y0;
            (f + e * (y0 + c * t), e * (c - y0 - c * t))
        } else {
            // Roots r1,2 = -nu +- sqrt(nu^2 - 1); y = A e^{r1 t} + B e^{r2 t}.
            // r1 = -nu + w written as -1/(nu + w) (r1 r2 = 1), which does not cancel at
            // large nu.
            let w = (nu * nu - 1.0).sqrt();
            let (r1, r2) = (-1.0 / (nu + w), -nu - w);
            let a = (v0 - r2 * y0) / (r1 - r2);
            let b = y0 - a;
            (
                f + a * (r1 * t).exp() + b * (r2 * t).exp(),
                a * r1 * (r1 * t).exp() + b * r2 * (r2 * t).exp(),
            )
        }
    }

    #[test]
    fn matches_closed_form_for_all_damping_regimes() {
        for nu in [0.0, 1e-3, 0.3, 0.999_999, 1.0, 1.000_001, 2.5, 40.0] {
            for h in [1e-3, 0.01, 0.37] {
                let p = Propagator::new(nu, h).unwrap();
                let (f, x0, v0) = (0.7, -1.3, 2.1);
                let (mut x, mut v) = (x0, v0);
                let n = 50;
                for _ in 0..n {
                    (x, v) = p.advance(x, v, f);
                }
                let (xe, ve) = exact(nu, f, x0, v0, n as f64 * h);
                let tol = 1e-12 * (1.0 + xe.abs() + ve.abs());
                assert!((x - xe).abs() < tol, "nu={nu} h={h}: x {x} vs {xe}");
                assert!((v - ve).abs() < tol, "nu={nu} h={h}: v {v} vs {ve}");
            }
        }
    }

    /// The oscillator driven by a force linear in time, `F = alpha + beta t`: the particular
    /// solution is `x_p = alpha + beta t - 2 nu beta` (undetermined coefficients:
    /// `x_p'' + 2 nu x_p' + x_p = 2 nu beta + alpha + beta t - 2 nu beta`), plus the free
    /// motion from `(x0 - x_p(0), v0 - beta)`, evaluated once at the final time (no
    /// cancellation there). First-order hold is exact for this force, step after step.
    #[test]
    fn first_order_hold_is_exact_for_a_force_linear_in_time() {
        let (alpha, beta, x0, v0) = (0.7, -0.45, -1.3, 2.1);
        for nu in [
            0.0, 1e-3, 0.3, 0.999_999, 1.0, 1.000_001, 1.3, 2.5, 40.0, 1e3,
        ] {
            for (h, n) in [(1e-3, 2000), (0.01, 200), (0.37, 20), (1.0, 8)] {
                let p = Propagator::new(nu, h).unwrap();
                let force = |k: u32| alpha + beta * (k as f64 * h);
                let (mut x, mut v) = (x0, v0);
                for k in 0..n {
                    (x, v) = p.advance_linear(x, v, force(k), force(k + 1));
                }
                let t = n as f64 * h;
                let (yx, yv) = exact(nu, 0.0, x0 - (alpha - 2.0 * nu * beta), v0 - beta, t);
                let (xe, ve) = (alpha + beta * t - 2.0 * nu * beta + yx, beta + yv);
                let tol = 1e-11 * (1.0 + xe.abs() + ve.abs());
                assert!((x - xe).abs() < tol, "nu={nu} h={h}: x {x} vs {xe}");
                assert!((v - ve).abs() < tol, "nu={nu} h={h}: v {v} vs {ve}");
            }
        }
    }

    /// At small `h` the ramp coefficients keep full relative accuracy: against their Taylor
    /// expansion (integrate `g = u - nu u^2 + (4 nu^2 - 1) u^3 / 6 + ...` term by term):
    /// `q1 = h^2/3 - nu h^3/4 + O(h^4)`, `q2 = h/2 - 2 nu h^2/3 + (4 nu^2 - 1) h^3/8 + O(h^4)`.
    #[test]
    fn ramp_coefficients_do_not_cancel_at_small_steps() {
        for nu in [0.0, 1e-3, 0.5, 1.0, 3.0] {
            let h = 1e-6;
            let p = Propagator::new(nu, h).unwrap();
            let q1 = h * h / 3.0 - nu * h * h * h / 4.0;
            let q2 = h / 2.0 - 2.0 * nu * h * h / 3.0 + (4.0 * nu * nu - 1.0) * h * h * h / 8.0;
            assert!((p.q1 / q1 - 1.0).abs() < 1e-11, "nu={nu}: {} vs {q1}", p.q1);
            assert!((p.q2 / q2 - 1.0).abs() < 1e-11, "nu={nu}: {} vs {q2}", p.q2);
        }
    }

    /// Where the series and the over-damped mode formula meet (`rho h = 2`), both agree.
    #[test]
    fn ramp_series_and_modes_agree() {
        for nu in [1.3, 2.0, 5.0] {
            let rho = nu + (nu * nu - 1.0f64).sqrt();
            for h in [1.5 / rho, 2.0 / rho, 2.5 / rho] {
                let (a1, a2) = ramp_series(nu, h);
                let (b1, b2) = ramp_modes(nu, h);
                assert!((a1 / b1 - 1.0).abs() < 1e-12, "nu={nu} h={h}: {a1} {b1}");
                assert!((a2 / b2 - 1.0).abs() < 1e-12, "nu={nu} h={h}: {a2} {b2}");
            }
        }
    }

    #[test]
    fn undamped_conserves_energy() {
        let p = Propagator::new(0.0, 0.01).unwrap();
        let (mut x, mut v) = (1.0, 0.0);
        for _ in 0..100_000 {
            (x, v) = p.advance(x, v, 0.0);
        }
        assert!((x * x + v * v - 1.0).abs() < 1e-11);
    }

    #[test]
    fn refuses_bad_step_and_damping() {
        for h in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let e = Propagator::new(0.1, h).unwrap_err();
            assert!(e.to_string().contains("dt"), "{e}");
        }
        assert!(
            Propagator::new(-1.0, 0.1)
                .unwrap_err()
                .to_string()
                .contains("nu")
        );
        assert!(
            Propagator::new(f64::NAN, 0.1)
                .unwrap_err()
                .to_string()
                .contains("nu")
        );
        // Huge damping does not overflow.
        let p = Propagator::new(1e6, 1.0).unwrap();
        assert!(p.c11.is_finite() && p.c12.is_finite() && p.c22.is_finite());
    }
}
