//! Geometry of a located cycle against a disturbance box: the smallest kick that leaves it,
//! the part of its area inside the box, and the basin fraction of steady slip that follows.

use serde::{Deserialize, Serialize};
use squeal_core::State;

use crate::ulc::CycleReport;

/// A box of the phase plane `[x0, x1] x [v0, v1]` (nondimensional).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Region {
    /// `x` range.
    pub x: [f64; 2],
    /// `x'` range.
    pub v: [f64; 2],
}

/// The smallest pure velocity kick from the fixed point that leaves the cycle: the smaller
/// of the cycle's two crossings of `x = x*` (upper `r_section`, lower at `x' < 0`).
pub fn min_kick(rep: &CycleReport, x_star: f64) -> f64 {
    let (xs, vs) = (&rep.curve.x, &rep.curve.v);
    let n = xs.len();
    let mut lower = f64::NAN;
    for i in 0..n {
        let j = (i + 1) % n;
        if (xs[i] - x_star) * (xs[j] - x_star) <= 0.0 && xs[i] != xs[j] {
            let t = (x_star - xs[i]) / (xs[j] - xs[i]);
            let v = vs[i] + t * (vs[j] - vs[i]);
            if v < 0.0 {
                lower = if lower.is_nan() { -v } else { lower.min(-v) };
            }
        }
    }
    if lower.is_nan() {
        rep.r_section
    } else {
        rep.r_section.min(lower)
    }
}

/// Area of the part of the closed polygon `(xs, vs)` inside the box (Sutherland-Hodgman
/// clipping against the box's four half-planes, then the shoelace formula). The clipping
/// is exact for a convex clip region and any simple polygon (degenerate edges it creates
/// enclose no area).
pub fn clipped_area(xs: &[f64], vs: &[f64], region: &Region) -> f64 {
    let mut poly: Vec<(f64, f64)> = xs.iter().copied().zip(vs.iter().copied()).collect();
    // Each half-plane as (axis 0 = x / 1 = v, bound, keep if >= bound when `lower`).
    let planes = [
        (0, region.x[0], true),
        (0, region.x[1], false),
        (1, region.v[0], true),
        (1, region.v[1], false),
    ];
    for (axis, bound, lower) in planes {
        if poly.is_empty() {
            break;
        }
        let coord = |p: &(f64, f64)| if axis == 0 { p.0 } else { p.1 };
        let inside = |p: &(f64, f64)| {
            if lower {
                coord(p) >= bound
            } else {
                coord(p) <= bound
            }
        };
        let mut out = Vec::with_capacity(poly.len() + 4);
        for i in 0..poly.len() {
            let a = poly[i];
            let b = poly[(i + 1) % poly.len()];
            let (ia, ib) = (inside(&a), inside(&b));
            if ia {
                out.push(a);
            }
            if ia != ib {
                let t = (bound - coord(&a)) / (coord(&b) - coord(&a));
                out.push((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)));
            }
        }
        poly = out;
    }
    let n = poly.len();
    if n < 3 {
        return 0.0;
    }
    0.5 * (0..n)
        .map(|i| {
            let j = (i + 1) % n;
            poly[i].0 * poly[j].1 - poly[j].0 * poly[i].1
        })
        .sum::<f64>()
        .abs()
}

/// Basin fraction of steady slip over `region` from the cycle, and its uncertainty: the
/// change when the curve is scaled about the fixed point by `r(dt/2) / r(dt)` (the section
/// crossing's move when the step halves; this assumes the shape moves with its crossing),
/// plus the polygon's chord error (one step's travel times the clipped perimeter, bounded
/// here by `max |x'| dt` times the curve length over the box area).
pub fn basin_fraction(
    rep: &CycleReport,
    half_dt_shift: f64,
    region: &Region,
    fp: State,
) -> (f64, f64) {
    let a = region.area();
    let f = clipped_area(&rep.curve.x, &rep.curve.v, region) / a;
    let mut err = 0.0;
    if half_dt_shift.is_finite() {
        let s = 1.0 + half_dt_shift / rep.r_section;
        let xs: Vec<f64> = rep.curve.x.iter().map(|x| fp.x + s * (x - fp.x)).collect();
        let vs: Vec<f64> = rep.curve.v.iter().map(|v| fp.v + s * (v - fp.v)).collect();
        err += (clipped_area(&xs, &vs, region) / a - f).abs();
    } else {
        err = f64::NAN;
    }
    // Chord error: each chord of length l cuts off at most l * sagitta <= l * (l / 8) * ...
    // bounded crudely by l^2 per chord.
    let n = rep.curve.x.len();
    let chords: f64 = (0..n)
        .map(|i| {
            let j = (i + 1) % n;
            let l = (rep.curve.x[j] - rep.curve.x[i]).hypot(rep.curve.v[j] - rep.curve.v[i]);
            l * l
        })
        .sum();
    (f, err + chords / a)
}

impl Region {
    /// Area of the box.
    pub fn area(&self) -> f64 {
        (self.x[1] - self.x[0]) * (self.v[1] - self.v[0])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clipping_a_square() {
        // Unit square [0,1]^2 against the box [0.5, 2] x [-1, 0.25]: overlap 0.5 * 0.25.
        let xs = [0.0, 1.0, 1.0, 0.0];
        let vs = [0.0, 0.0, 1.0, 1.0];
        let b = Region {
            x: [0.5, 2.0],
            v: [-1.0, 0.25],
        };
        assert!((clipped_area(&xs, &vs, &b) - 0.125).abs() < 1e-15);
        // A box holding the whole square.
        let all = Region {
            x: [-1.0, 2.0],
            v: [-1.0, 2.0],
        };
        assert!((clipped_area(&xs, &vs, &all) - 1.0).abs() < 1e-15);
        // A box missing it.
        let none = Region {
            x: [3.0, 4.0],
            v: [-1.0, 2.0],
        };
        assert_eq!(clipped_area(&xs, &vs, &none), 0.0);
    }

    #[test]
    fn clipping_a_disc_matches_the_closed_form() {
        // Unit disc (2000-gon) clipped by the half-plane x >= 0 inside a big box: pi / 2
        // (up to the polygon's deficit, pi - n/2 sin(2 pi / n) ~ 5e-6).
        let n = 2000;
        let xs: Vec<f64> = (0..n)
            .map(|i| (i as f64 * std::f64::consts::TAU / n as f64).cos())
            .collect();
        let vs: Vec<f64> = (0..n)
            .map(|i| (i as f64 * std::f64::consts::TAU / n as f64).sin())
            .collect();
        let b = Region {
            x: [0.0, 5.0],
            v: [-5.0, 5.0],
        };
        assert!((clipped_area(&xs, &vs, &b) - std::f64::consts::FRAC_PI_2).abs() < 1e-5);
    }
}
