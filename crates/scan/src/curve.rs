//! A closed curve in the phase plane `(x, x')`: the unstable limit cycle as a polygon of
//! the states of one revolution. Shared by the cycle search, the scan's consistency checks
//! and the store (which writes its points).

use serde::{Deserialize, Serialize};
use squeal_core::State;

/// A closed polygon `(x[i], v[i])`; the last point joins the first.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ClosedCurve {
    /// `x` of each point.
    pub x: Vec<f64>,
    /// `x'` of each point.
    pub v: Vec<f64>,
}

impl ClosedCurve {
    /// A curve through the given points (the closing segment is implied). `x` and `v` must
    /// have the same length.
    pub fn new(x: Vec<f64>, v: Vec<f64>) -> ClosedCurve {
        debug_assert_eq!(x.len(), v.len());
        ClosedCurve { x, v }
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.x.len().min(self.v.len())
    }

    /// Whether the curve has no points.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn segments(&self) -> impl Iterator<Item = ((f64, f64), (f64, f64))> + '_ {
        let n = self.len();
        (0..n).map(move |i| {
            let j = (i + 1) % n;
            ((self.x[i], self.v[i]), (self.x[j], self.v[j]))
        })
    }

    /// Whether `p` lies inside the curve (even-odd rule).
    pub fn encloses(&self, p: State) -> bool {
        let mut inside = false;
        for ((xi, vi), (xj, vj)) in self.segments() {
            if (vi > p.v) != (vj > p.v) && p.x < (xj - xi) * (p.v - vi) / (vj - vi) + xi {
                inside = !inside;
            }
        }
        inside
    }

    /// Euclidean distance from `p` to the curve (nearest point of any segment).
    pub fn distance_to(&self, p: State) -> f64 {
        let mut best = f64::INFINITY;
        for ((ax, av), (bx, bv)) in self.segments() {
            let (dx, dv) = (bx - ax, bv - av);
            let l2 = dx * dx + dv * dv;
            let t = if l2 > 0.0 {
                (((p.x - ax) * dx + (p.v - av) * dv) / l2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            best = best.min((p.x - ax - t * dx).hypot(p.v - av - t * dv));
        }
        best
    }

    /// Distance from `centre` to the curve along the ray at `angle` (radians from `+x`): the
    /// farthest crossing, or `None` if the ray does not meet the curve.
    pub fn distance_along_ray(&self, centre: State, angle: f64) -> Option<f64> {
        let (c, s) = (angle.cos(), angle.sin());
        let mut radius: Option<f64> = None;
        for ((ax, av), (bx, bv)) in self.segments() {
            let (ax, av, bx, bv) = (ax - centre.x, av - centre.v, bx - centre.x, bv - centre.v);
            // Solve a + t (b - a) = rho (c, s).
            let (dx, dv) = (bx - ax, bv - av);
            let den = dx * s - dv * c;
            if den.abs() < 1e-300 {
                continue;
            }
            let t = (av * c - ax * s) / den;
            if (0.0..=1.0).contains(&t) {
                let rho = (ax + t * dx) * c + (av + t * dv) * s;
                if rho > 0.0 && radius.is_none_or(|r| rho > r) {
                    radius = Some(rho);
                }
            }
        }
        radius
    }

    /// Enclosed area (shoelace formula).
    pub fn area(&self) -> f64 {
        0.5 * self
            .segments()
            .map(|((xi, vi), (xj, vj))| xi * vj - xj * vi)
            .sum::<f64>()
            .abs()
    }

    /// `[min, max]` of `x`.
    pub fn x_range(&self) -> [f64; 2] {
        min_max(&self.x)
    }

    /// `[min, max]` of `x'`.
    pub fn v_range(&self) -> [f64; 2] {
        min_max(&self.v)
    }
}

/// A closed curve with the bounds that answer most point queries in constant time: about a
/// centre inside it, no point of the curve is nearer than `r_in` or farther than `r_out`
/// (a polygon's farthest point from any centre is a vertex). Points well inside the
/// inner disc or outside the outer one are decided without visiting the segments.
#[derive(Clone, Debug)]
pub struct CurveLocator {
    curve: ClosedCurve,
    centre: State,
    /// Nearest distance from `centre` to the curve (0 when `centre` is not enclosed, which
    /// turns the inner test off).
    r_in: f64,
    r_out: f64,
}

impl CurveLocator {
    /// The locator of `curve` about the mean of its points.
    pub fn new(curve: ClosedCurve) -> CurveLocator {
        let n = curve.len().max(1) as f64;
        let centre = State {
            x: curve.x.iter().sum::<f64>() / n,
            v: curve.v.iter().sum::<f64>() / n,
        };
        let r_in = if curve.encloses(centre) {
            curve.distance_to(centre)
        } else {
            0.0
        };
        let r_out = (0..curve.len())
            .map(|i| (curve.x[i] - centre.x).hypot(curve.v[i] - centre.v))
            .fold(0.0f64, f64::max);
        CurveLocator {
            curve,
            centre,
            r_in,
            r_out,
        }
    }

    /// The curve.
    pub fn curve(&self) -> &ClosedCurve {
        &self.curve
    }

    /// Which side of the curve `p` lies on (`Some(true)`: inside), if it is farther than
    /// `margin` from the curve; `None` within the margin.
    pub fn side(&self, p: State, margin: f64) -> Option<bool> {
        let rho = (p.x - self.centre.x).hypot(p.v - self.centre.v);
        if rho + margin < self.r_in {
            return Some(true);
        }
        if rho - margin > self.r_out {
            return Some(false);
        }
        if margin > 0.0 && self.curve.distance_to(p) <= margin {
            return None;
        }
        Some(self.curve.encloses(p))
    }

    /// Whether `p` lies inside the curve (as [`ClosedCurve::encloses`]).
    pub fn encloses(&self, p: State) -> bool {
        self.side(p, 0.0).unwrap_or_else(|| self.curve.encloses(p))
    }
}

fn min_max(a: &[f64]) -> [f64; 2] {
    a.iter().fold([f64::INFINITY, f64::NEG_INFINITY], |m, &x| {
        [m[0].min(x), m[1].max(x)]
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit square `[0, 1]^2`, counter-clockwise.
    fn square() -> ClosedCurve {
        ClosedCurve::new(vec![0.0, 1.0, 1.0, 0.0], vec![0.0, 0.0, 1.0, 1.0])
    }

    fn st(x: f64, v: f64) -> State {
        State { x, v }
    }

    #[test]
    fn square_geometry() {
        let q = square();
        // Exact values for the unit square.
        assert_eq!(q.area(), 1.0);
        assert!(q.encloses(st(0.5, 0.5)));
        assert!(!q.encloses(st(1.5, 0.5)));
        assert!(!q.encloses(st(0.5, -0.1)));
        assert_eq!(q.distance_to(st(0.5, 0.5)), 0.5);
        assert_eq!(q.distance_to(st(2.0, 0.5)), 1.0);
        assert_eq!(q.x_range(), [0.0, 1.0]);
        let c = st(0.5, 0.5);
        assert!((q.distance_along_ray(c, 0.0).unwrap() - 0.5).abs() < 1e-15);
        // Towards a corner: half the diagonal.
        let d = q
            .distance_along_ray(c, std::f64::consts::FRAC_PI_4)
            .unwrap();
        assert!((d - 0.5 * 2f64.sqrt()).abs() < 1e-12);
        // A ray from outside pointing away misses.
        assert_eq!(q.distance_along_ray(st(3.0, 0.5), 0.0), None);
    }

    /// The locator's constant-time answers agree with the polygon tests everywhere on a grid
    /// over a 64-gon circle of radius 1 (the inner and outer discs are exercised) and the
    /// square, and the margin withholds exactly the points near the curve.
    #[test]
    fn locator_agrees_with_polygon_tests() {
        let n = 64;
        let circle = ClosedCurve::new(
            (0..n)
                .map(|i| 2.0 + (std::f64::consts::TAU * i as f64 / n as f64).cos())
                .collect(),
            (0..n)
                .map(|i| -1.0 + (std::f64::consts::TAU * i as f64 / n as f64).sin())
                .collect(),
        );
        for curve in [square(), circle] {
            let loc = CurveLocator::new(curve.clone());
            for i in 0..81 {
                for j in 0..81 {
                    let p = st(-1.0 + 0.05 * i as f64, -3.0 + 0.05 * j as f64);
                    assert_eq!(loc.encloses(p), curve.encloses(p), "{p:?}");
                    match loc.side(p, 0.1) {
                        Some(inside) => {
                            assert_eq!(inside, curve.encloses(p));
                            assert!(curve.distance_to(p) > 0.1);
                        }
                        None => assert!(curve.distance_to(p) <= 0.1),
                    }
                }
            }
        }
    }
}
