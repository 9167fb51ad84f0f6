//! A certified region of attraction of the steady-slip fixed point: a disc around it inside
//! which every run of the equations of motion converges to it (crates/core/MODEL.md,
//! section 9). Computed once per map; the classifier labels a run steady slip the moment it
//! enters the disc ([`crate::Reason::EnteredRegion`]), and a scan labels a start inside it
//! without a run ([`crate::Reason::StartInRegion`]).
//!
//! **The argument (Stribeck law, slipping backwards).** With `y = x - x*` and `u = x'`,
//! while `x' < v_d` the block slips with `v = u - v_d < 0` and
//!
//! ```text
//! y' = u,   u' = -y - h(u),   h(u) = 2 xi u + mu(v_d) - mu(v_d - u)
//! ```
//!
//! a Lienard system. Its energy `E = (y^2 + u^2) / 2` changes at `E' = -u h(u)`, and
//! `h(u) / u = 2 xi + (mean of mu' between v_d - u and v_d)`. The law's `mu'` is
//! non-decreasing in the slip speed (`mu'(s) = (mu_v - mu_d (mu_sd - 1) e^{-s/v_0}) / v_0`,
//! `mu_sd >= 1`), so for `|u| <= R < v_d` that mean is at least `mu'(v_d - R)`, and
//! `E' <= -k u^2` with `k = 2 xi + mu'(v_d - R)`. Where `k > 0` the disc `E < R^2 / 2`
//! (radius `R`) is invariant (`|u| <= sqrt(2 E) < R` inside it, so the estimate holds all
//! along the run, and `x' < v_d`: the block never reaches zero slip, never sticks), `E`
//! falls whenever `u != 0`, and the only orbit with `u = 0` throughout is the fixed point:
//! every run in the disc converges to it (LaSalle's invariance principle). No linearisation
//! and no remainder bound are needed: the estimate is exact over the disc.
//!
//! **The margin.** `R` is the largest radius at which the least damping over the disc, `k`,
//! is still a quarter of the fixed point's own (`2 xi + mu'(v_d)`), and at most `0.9 v_d`:
//! the energy then falls by a fixed share per revolution everywhere in the disc, which the
//! step error of the scheme (`O(dt^2)` per unit time, relative) cannot undo at the shipped
//! steps. The audit checks it against runs to settlement in every scan.
//!
//! McMillan's laws have no certified region here (`None`): their force depends on `|x''|`,
//! which is not smooth at the fixed point itself (MODEL.md section 9 says what a proof would
//! need); their runs still end at `fp_radius` or on the located cycle's trap.

use serde::Serialize;

use crate::params::{FrictionLaw, Params};
use crate::stepper::State;

/// The share of the fixed point's damping kept everywhere in the disc (the margin).
const KEPT_DAMPING: f64 = 0.25;

/// The largest radius as a share of the belt speed (the disc stays clear of zero slip).
const MAX_SHARE_OF_BELT: f64 = 0.9;

/// A disc around the steady-slip fixed point that every run inside it stays in and
/// converges from (see the module's argument).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Region {
    /// The fixed point.
    pub centre: State,
    /// The disc's radius in the `(x, x')` plane.
    pub radius: f64,
    /// The least damping `2 xi + mu'(v_d - radius)` over the disc (positive).
    pub least_damping: f64,
}

impl Region {
    /// The certified region of `p`, where the argument applies (`None` otherwise: McMillan's
    /// laws, Coulomb, or a fixed point that does not attract).
    pub fn of(p: &Params) -> Option<Region> {
        match p.law {
            FrictionLaw::Stribeck => stribeck(p),
            FrictionLaw::McMillan | FrictionLaw::McMillanNonHysteretic | FrictionLaw::Coulomb => {
                None
            }
        }
    }

    /// Whether `(x, v)` lies inside the disc (strictly).
    #[inline]
    pub fn contains(&self, x: f64, v: f64) -> bool {
        let (dx, dv) = (x - self.centre.x, v - self.centre.v);
        dx * dx + dv * dv < self.radius * self.radius
    }
}

/// The Stribeck law's disc: `k(R) = 2 xi + mu'(v_d - R)` is non-decreasing as `R` falls, so
/// the radius where `k` is a quarter of `k(0)` has the closed form below.
fn stribeck(p: &Params) -> Option<Region> {
    let s = p.stribeck?;
    let k0 = p.fixed_point_damping()?;
    // NaN damping fails `k0 > 0` too.
    if k0.is_nan() || k0 <= 0.0 || s.mu_sd < 1.0 || s.mu_v < 0.0 {
        return None;
    }
    let v_d = p.lambda;
    let amp = s.mu_d * (s.mu_sd - 1.0);
    // k(R) >= KEPT k0  <=>  amp e^{-(v_d - R)/v_0} <= c, with
    // c = mu_v + v_0 (2 xi - KEPT k0) (positive when k0 > 0).
    let c = s.mu_v + s.v_0 * (2.0 * p.nu - KEPT_DAMPING * k0);
    let cap = MAX_SHARE_OF_BELT * v_d;
    let radius = if amp <= c {
        cap
    } else {
        (v_d - s.v_0 * (amp / c).ln()).min(cap)
    };
    let least_damping = 2.0 * p.nu + s.mu(v_d - radius).1;
    // The closed form and the law must agree; anything else is a bug, not a region.
    if radius.is_nan()
        || radius <= 0.0
        || least_damping.is_nan()
        || least_damping < KEPT_DAMPING * k0 * (1.0 - 1e-9)
    {
        return None;
    }
    Some(Region {
        centre: p.fixed_point(),
        radius,
        least_damping,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Stribeck;

    /// bSTAB's case at v_d = 2.0 (xi = 0.05, mu_d = 0.5, mu_sd = 2, v_0 = 0.5, mu_v = 0):
    /// k0 = 0.1 - e^{-4} = 0.0816844; k(R) = 0.1 - e^{-(2 - R)/0.5} = k0 / 4 gives
    /// R = 2 - 0.5 ln(1 / (0.1 - k0 / 4)) = 0.7357 (closed form, by hand). At v_d = 1.0 the
    /// fixed point repels (k0 = 0.1 - e^{-2} < 0): no region.
    #[test]
    fn bstab_region_has_the_closed_form_radius() {
        let p = Params::stribeck(0.05, 2.0, Stribeck::default());
        let r = Region::of(&p).expect("a region at v_d = 2");
        let k0 = 0.1 - (-4.0f64).exp();
        let want = 2.0 - 0.5 * (1.0 / (0.1 - k0 / 4.0)).ln();
        assert!((r.radius - want).abs() < 1e-12, "{r:?} vs {want}");
        assert!((r.least_damping - k0 / 4.0).abs() < 1e-12, "{r:?}");
        assert!(r.contains(r.centre.x + 0.99 * want, 0.0));
        assert!(!r.contains(r.centre.x, 1.01 * want));
        assert_eq!(
            Region::of(&Params::stribeck(0.05, 1.0, Stribeck::default())),
            None
        );
        let mc = Params::paper(FrictionLaw::McMillan, 1e-2);
        assert_eq!(Region::of(&mc), None);
    }

    /// The energy estimate over the disc, checked pointwise: for every `|u| <= R`,
    /// `u h(u) >= k u^2` with the region's `k` (the module's inequality), at 2001 points
    /// across the disc at the 20 belt speeds of bSTAB's study where a region exists.
    #[test]
    fn energy_falls_at_least_at_the_least_damping_over_the_disc() {
        let mut found = 0;
        for i in 0..20 {
            let v_d = 0.8 + 0.075 * i as f64;
            let p = Params::stribeck(0.05, v_d, Stribeck::default());
            let Some(r) = Region::of(&p) else { continue };
            found += 1;
            let s = p.stribeck.unwrap();
            for j in 0..=2000 {
                let u = r.radius * (j as f64 / 1000.0 - 1.0);
                let h = 2.0 * p.nu * u + s.mu(v_d).0 - s.mu(v_d - u).0;
                assert!(
                    u * h >= r.least_damping * u * u - 1e-15,
                    "v_d {v_d} u {u}: {} < {}",
                    u * h,
                    r.least_damping * u * u
                );
            }
        }
        // The fixed point attracts above v_d = 0.5 ln 10 = 1.151: the 15 speeds 1.175 .. 2.225.
        assert_eq!(found, 15);
    }
}
