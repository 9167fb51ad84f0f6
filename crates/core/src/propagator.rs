//! Exact solution of the linear oscillator `x'' + 2 nu x' + x = F` over one step with `F`
//! held constant (the paper's Duhamel integral, eqs. 4.3-4.6, propagated from the current
//! state instead of the moving frame of eqs. 4.7-4.8).
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

use crate::error::CoreError;

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
        Ok(Propagator {
            h,
            nu,
            c11: ec + nu * es,
            c12: es,
            c21: -es,
            c22: ec - nu * es,
        })
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
            let w = (nu * nu - 1.0).sqrt();
            let (r1, r2) = (-nu + w, -nu - w);
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
