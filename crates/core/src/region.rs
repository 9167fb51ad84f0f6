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
//! **McMillan's laws** ([`mcmillan`]): the force depends on `|x''|`, not smooth at the fixed
//! point itself, so there is no linearisation; the function `V = u^2/2 + W(sigma, u)` with
//! `sigma = y + 2 nu u` and `W = -integral_0^sigma a(s, u) ds` absorbs the `|x''|` part
//! exactly and falls at `V' = -2 nu a^2 + W_u a`, where the remainder `W_u` (the law's
//! dependence on the slip speed) is bounded over the region (MODEL.md section 9 gives every
//! bound). The region is an ellipse in `(sigma, u)`.

use serde::Serialize;

use crate::law::{Friction, Stribeck, Surface};
use crate::params::Params;
use crate::stepper::State;

/// The share of the fixed point's damping kept everywhere in the disc (the margin).
const KEPT_DAMPING: f64 = 0.25;

/// The largest radius as a share of the belt speed (the disc stays clear of zero slip).
const MAX_SHARE_OF_BELT: f64 = 0.9;

/// The shape of a certified region, in `y = x - x*`, `u = x'`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub enum Shape {
    /// The disc `y^2 + u^2 < radius^2` (the Stribeck law's energy argument).
    Disc {
        /// The radius.
        radius: f64,
        /// The least damping `2 xi + mu'(v_d - radius)` over the disc (positive).
        least_damping: f64,
    },
    /// The ellipse `u^2 / u2 + sigma^2 / s2 < 1` with `sigma = y + 2 nu u` (McMillan's laws,
    /// [`mcmillan`]).
    Ellipse {
        /// `2 nu`.
        two_nu: f64,
        /// Its semi-axis in `u`, squared.
        u2: f64,
        /// Its semi-axis in `sigma`, squared.
        s2: f64,
    },
}

/// A neighbourhood of the steady-slip fixed point that every run inside it converges from
/// (see the module's argument).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Region {
    /// The fixed point.
    pub centre: State,
    /// The region around it.
    pub shape: Shape,
}

impl Region {
    /// The certified region of `p`, where the argument applies (`None` otherwise: Coulomb,
    /// or a fixed point that does not attract).
    pub fn of(p: &Params) -> Option<Region> {
        match p.law {
            Friction::Stribeck(s) => stribeck(p, &s),
            Friction::McMillan(c) => mcmillan(p, c, true),
            Friction::NonHysteretic(c) => mcmillan(p, c, false),
            // Coulomb, the cubic law and any law not named here: no region kept. Their runs
            // decide without it, which is always sound (the region only lets a run stop
            // early).
            _ => None,
        }
    }

    /// A radius about the fixed point that the region lies within: the disc's, or for the
    /// ellipse `|u| <= sqrt(u2)`, `|y| <= |sigma| + 2 nu |u| <= sqrt(s2) + 2 nu sqrt(u2)`.
    pub fn outer_radius(&self) -> f64 {
        match self.shape {
            Shape::Disc { radius, .. } => radius,
            Shape::Ellipse { two_nu, u2, s2 } => (s2.sqrt() + two_nu * u2.sqrt()).hypot(u2.sqrt()),
        }
    }

    /// Whether `(x, v)` lies inside the region (strictly).
    #[inline]
    pub fn contains(&self, x: f64, v: f64) -> bool {
        let (y, u) = (x - self.centre.x, v - self.centre.v);
        match self.shape {
            Shape::Disc { radius, .. } => y * y + u * u < radius * radius,
            Shape::Ellipse { two_nu, u2, s2 } => {
                let sigma = y + two_nu * u;
                u * u / u2 + sigma * sigma / s2 < 1.0
            }
        }
    }
}

/// The Stribeck law's disc: `k(R) = 2 xi + mu'(v_d - R)` is non-decreasing as `R` falls, so
/// the radius where `k` is a quarter of `k(0)` has the closed form below.
fn stribeck(p: &Params, s: &Stribeck) -> Option<Region> {
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
        shape: Shape::Disc {
            radius,
            least_damping,
        },
    })
}

/// Bounds of McMillan's law over a box `|sigma| <= s`, `|u| <= u_max` around the fixed point
/// (MODEL.md section 9 derives each one).
#[derive(Clone, Copy, Debug)]
struct Bounds {
    /// `|g| <= kappa |a|` along the slip root (`g = F - 1`).
    kappa: f64,
    /// `|dg/da| <= kappa_a` along it.
    kappa_a: f64,
    /// `w_min - b_max`: the least slip speed minus the largest `|a| tau`.
    d: f64,
    /// The level `c` of `V` whose set lies in the box.
    c: f64,
}

/// The bounds of McMillan's law (`hysteretic` or not) for the box of half-width `s` in
/// `sigma`, or `None` where one of the conditions of the argument fails there.
fn mcmillan_bounds(p: &Params, surface: Surface, hysteretic: bool, s: f64) -> Option<Bounds> {
    let tau = surface.tau;
    // |a| <= |sigma| / (1 - kappa) <= 2 s along the slip root, if kappa <= 1/2 (checked).
    let b1 = tau * 2.0 * s;
    let mut kappa = 0.5;
    let (mut c, mut w_min, mut d) = (0.0, 0.0, 0.0);
    // kappa depends on w_min, which depends on c, which depends on kappa: three passes from
    // kappa = 1/2, and the check below that c is within the box for the final kappa.
    for _ in 0..3 {
        c = s * s / (2.0 * (1.0 + kappa));
        w_min = p.lambda - (2.0 * c).sqrt();
        d = w_min - b1;
        if d.is_nan() || d <= 0.0 {
            return None;
        }
        kappa = tau / d;
    }
    // The conditions used: kappa <= 1/2 (with the c computed from it), the slip branch over
    // the box (w > 2 |a| tau, or > |a| tau without hysteresis), and a single root of the
    // force equation there ([`one_root_at`]).
    let c_kappa = s * s / (2.0 * (1.0 + kappa));
    let kappa_a = tau * w_min / (d * d);
    let branch = if hysteretic { 2.0 } else { 1.0 };
    let ok = kappa <= 0.5
        && c_kappa >= c * (1.0 - 1e-12)
        && kappa_a < 1.0
        && w_min > branch * b1
        && one_root_at(surface, hysteretic, w_min, s);
    ok.then_some(Bounds {
        kappa,
        kappa_a,
        d,
        c,
    })
}

/// Whether McMillan's force equation has exactly one root at every state whose slip speed
/// `w = lambda - x'` is at least `w` and whose `|sigma| = |x - x* + 2 nu x'|` is at most
/// `sigma`: every root has `|a| < a_all = 1 + 1/sin(phi) + sigma` (`|F| <= 1 + 1/sin(phi)`
/// and `a = F - sigma`), so with `w > 2 tau a_all` (`tau a_all` without hysteresis) every
/// root is on the slip branch, where `|dg/da| <= tau w / (w - tau a_all)^2 < 1` makes the
/// equation monotone: one root, and the state `(x, x')` is the whole state there.
fn one_root_at(surface: Surface, hysteretic: bool, w: f64, sigma: f64) -> bool {
    let tau = surface.tau;
    let a_all = 1.0 + 1.0 / surface.phi.sin() + sigma;
    let branch = if hysteretic { 2.0 } else { 1.0 };
    let d_all = w - tau * a_all;
    w > branch * tau * a_all && d_all > 0.0 && tau * w / (d_all * d_all) < 1.0
}

/// Whether the force equation of `p` has exactly one root at the state `(x, v)`, by the
/// closed-form bound of [`one_root_at`] (McMillan's laws; `false` for every other law,
/// where no such bound is kept). Where it holds, `(x, x')` determines the force, so two
/// runs through that state are one run from there on: the premise of the closed turns of
/// `squeal_scan::census` (MODEL.md section 12).
pub fn one_root(p: &Params, x: f64, v: f64) -> bool {
    let sigma = (x - p.fixed_point().x + 2.0 * p.nu * v).abs();
    one_root_within(p, v, sigma)
}

/// [`one_root`] at every state with `x' <= v_max` and `|sigma| <= sigma_max` (the bound
/// only weakens as the slip speed falls and `|sigma|` grows, so its worst corner decides).
pub fn one_root_within(p: &Params, v_max: f64, sigma_max: f64) -> bool {
    let (surface, hysteretic) = match p.law {
        Friction::McMillan(c) => (c, true),
        Friction::NonHysteretic(c) => (c, false),
        _ => return false,
    };
    one_root_at(surface, hysteretic, p.lambda - v_max, sigma_max)
}

/// McMillan's laws: the ellipse from `V = u^2/2 + W(sigma, u)` (MODEL.md section 9). The
/// half-width `s` in `sigma` is the largest (on a grid of 1/1000 of the belt speed) at which
/// every condition holds and `V` falls: `s <= 4 nu (1 - kappa)(1 - kappa_a) d^2 /
/// ((1 + kappa) tau)`. The labelled ellipse is the set `u^2/2 + sigma^2 / (2 (1 - kappa))
/// < c / 2`, inside `V < c / 2` (half the certified level: the margin).
fn mcmillan(p: &Params, surface: Surface, hysteretic: bool) -> Option<Region> {
    if p.nu.is_nan() || p.nu <= 0.0 || surface.tau <= 0.0 {
        return None;
    }
    let falls = |s: f64, b: &Bounds| {
        s <= 4.0 * p.nu * (1.0 - b.kappa) * (1.0 - b.kappa_a) * b.d * b.d
            / ((1.0 + b.kappa) * surface.tau)
    };
    let step = 1e-3 * p.lambda;
    let best = (1..1000)
        .map(|i| i as f64 * step)
        .filter_map(|s| Some((s, mcmillan_bounds(p, surface, hysteretic, s)?)))
        .take_while(|(s, b)| falls(*s, b))
        .last()?;
    let (_, b) = best;
    let level = 0.5 * b.c;
    Some(Region {
        centre: p.fixed_point(),
        shape: Shape::Ellipse {
            two_nu: 2.0 * p.nu,
            u2: 2.0 * level,
            s2: 2.0 * level * (1.0 - b.kappa),
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::law::{FrictionLaw, Stribeck};

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
        let Shape::Disc {
            radius,
            least_damping,
        } = r.shape
        else {
            panic!("{r:?}")
        };
        assert!((radius - want).abs() < 1e-12, "{r:?} vs {want}");
        assert!((least_damping - k0 / 4.0).abs() < 1e-12, "{r:?}");
        assert!(r.contains(r.centre.x + 0.99 * want, 0.0));
        assert!(!r.contains(r.centre.x, 1.01 * want));
        assert_eq!(
            Region::of(&Params::stribeck(0.05, 1.0, Stribeck::default())),
            None
        );
    }

    /// The roots of `g(a) = F(x' - lambda, a) - sigma - a` at `(x, x')`, counted by the sign
    /// changes of `g` on a fine grid over `[-a_all, a_all]` (`|a| < 1 + 1/sin(phi) + |sigma|`
    /// for every root): the independent count [`one_root`] is checked against.
    fn roots(p: &Params, x: f64, v: f64) -> usize {
        let sigma = x - 1.0 + 2.0 * p.nu * v;
        let phi = p.law.surface().map_or(1.0, |s| s.phi);
        let a_all = 1.0 + 1.0 / phi.sin() + sigma.abs();
        let g = |a: f64| crate::friction::force(p, v - p.lambda, a).force - sigma - a;
        let n = 400_000;
        let mut count = 0;
        let mut last = g(-a_all);
        for i in 1..=n {
            let now = g(-a_all + 2.0 * a_all * i as f64 / n as f64);
            if (now > 0.0) != (last > 0.0) {
                count += 1;
            }
            last = now;
        }
        count
    }

    /// [`one_root`] only where the force equation has one root: at Table 1's parameters
    /// (`lambda = 3`) the states of the plane up to `x' = 1.5` pass the bound and have one
    /// root each, counted on a grid of `a` (the unstable cycle there reaches `|x'| = 0.41`,
    /// `|x - 1| = 0.41`); near zero slip (`x' = 2.9`) the bound refuses,
    /// and there the equation has three roots at some states (the quasi-static branch,
    /// MODEL.md section 4). At `lambda = 0.5` the bound refuses the small cycle's states
    /// (`x' = 0.26`), too near zero slip for it. The bound is conservative: far from the
    /// fixed point (`(-3, 1.5)`, `|sigma| = 4`) it refuses states with one root. Other laws:
    /// never.
    #[test]
    fn one_root_holds_only_where_the_equation_has_one_root() {
        for law in [FrictionLaw::McMillan, FrictionLaw::McMillanNonHysteretic] {
            let p = Params::paper(law, 1e-3);
            for (x, v) in [(1.0, 0.4), (0.6, 0.0), (1.4, -0.4), (1.5, 0.5), (2.0, -1.0)] {
                assert!(one_root(&p, x, v), "{law:?} ({x}, {v})");
                assert_eq!(roots(&p, x, v), 1, "{law:?} ({x}, {v})");
            }
            assert!(!one_root(&p, 1.0, 2.9), "{law:?}");
            assert!(
                !one_root(&p, -3.0, 1.5) && roots(&p, -3.0, 1.5) == 1,
                "{law:?}"
            );
        }
        let p = Params::paper(FrictionLaw::McMillan, 1e-3);
        let three = (0..200)
            .map(|i| -3.0 + 0.04 * i as f64)
            .any(|x| roots(&p, x, 2.9) == 3);
        assert!(three, "no state with three roots near zero slip");
        let mut slow = Params::paper(FrictionLaw::McMillan, 0.0223);
        slow.lambda = 0.5;
        assert!(!one_root(&slow, 1.0, 0.26));
        let c = Params::paper(FrictionLaw::Coulomb, 1e-3);
        assert!(!one_root(&c, 1.0, 0.1));
    }

    /// [`Region::outer_radius`] bounds the ellipse: 3600 points on its boundary (the
    /// closed-form parametrisation `u = sqrt(u2) cos t`, `sigma = sqrt(s2) sin t`) lie
    /// within it, and the largest is more than half of it (a bound, not a wild one).
    #[test]
    fn the_ellipse_lies_within_its_outer_radius() {
        let r = Region::of(&Params::paper(FrictionLaw::McMillan, 1e-2)).unwrap();
        let Shape::Ellipse { two_nu, u2, s2 } = r.shape else {
            panic!("{r:?}")
        };
        let far = (0..3600)
            .map(|i| {
                let t = i as f64 * std::f64::consts::TAU / 3600.0;
                let (u, sigma) = (u2.sqrt() * t.cos(), s2.sqrt() * t.sin());
                (sigma - two_nu * u).hypot(u)
            })
            .fold(0.0f64, f64::max);
        assert!(
            far <= r.outer_radius() && far > 0.5 * r.outer_radius(),
            "{far} {r:?}"
        );
    }

    /// McMillan's region lies inside the unstable cycle, as it must (a start between would
    /// contradict it): the cycle crosses the section `x = 1` at `x' = 0.365` for
    /// `nu = 1e-3` (crates/scan/tests/scanning/science.rs) and at about `2.09` for `nu = 1e-2`
    /// (classify.rs, the settling test's comment). Without damping (`nu = 0`, the fixed point
    /// repels, every start squeals) there is none.
    #[test]
    fn mcmillan_region_lies_inside_the_unstable_cycle() {
        for (nu, r_u) in [(1e-3, 0.365), (1e-2, 2.09)] {
            for law in [FrictionLaw::McMillan, FrictionLaw::McMillanNonHysteretic] {
                let p = Params::paper(law, nu);
                let r = Region::of(&p).unwrap_or_else(|| panic!("{law:?} {nu}: no region"));
                let Shape::Ellipse { u2, .. } = r.shape else {
                    panic!("{r:?}")
                };
                // On the section sigma = 2 nu u, so the ellipse's reach there is below u2.
                assert!(u2.sqrt() < r_u, "{law:?} {nu}: {r:?}");
                assert!(r.contains(1.0, 0.0) && !r.contains(1.0, r_u));
            }
        }
        assert_eq!(Region::of(&Params::paper(FrictionLaw::McMillan, 0.0)), None);
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
            let Some(Region {
                shape:
                    Shape::Disc {
                        radius,
                        least_damping,
                    },
                ..
            }) = Region::of(&p)
            else {
                continue;
            };
            found += 1;
            let s = p.law.stribeck().unwrap();
            for j in 0..=2000 {
                let u = radius * (j as f64 / 1000.0 - 1.0);
                let h = 2.0 * p.nu * u + s.mu(v_d).0 - s.mu(v_d - u).0;
                assert!(
                    u * h >= least_damping * u * u - 1e-15,
                    "v_d {v_d} u {u}: {} < {}",
                    u * h,
                    least_damping * u * u
                );
            }
        }
        // The fixed point attracts above v_d = 0.5 ln 10 = 1.151: the 15 speeds 1.175 .. 2.225.
        assert_eq!(found, 15);
    }
}
