//! `atan(y / x)` for `x > 0`, the arctangent in McMillan's laws (`F1 = -(2/pi) atan(v / b)`),
//! with a short chain of dependent operations.
//!
//! **Why.** A robust solve is a chain of Newton iterates, each needing the force at the last
//! one, so the law's latency, not its throughput, sets the cost of a step. The C library's
//! `atan` took about 45 ns from argument to result on the measurement machine (10 ns per call
//! when calls are independent), and 32-40% of the time of a McMillan scan in a profile
//! (docs/history/benchmarks.md, "Cost per step, reduced"). This one takes one division (the one
//! that formed `v / b` before) and a table look-up with a polynomial evaluated in parallel halves.
//!
//! **How.** With `n = |y|`, the argument is reduced to `t` in `[0, 1]`: `t = n / x` if
//! `n <= x`, else `t = x / n` and `atan = pi/2 - atan(t)`. Then
//! * `t < 7.5 / 256`: the odd Taylor series `t - t^3/3 + ... + t^13/13` (the first term left
//!   out, `t^15 / 15`, is below `2^-75 t`);
//! * otherwise the node `c = k / 256` nearest to `t` (`k >= 8`), `h = t - c` (exact, `|h| <=
//!   1/512`), and the degree-6 Taylor polynomial of `atan` at `c` (the rest is below
//!   `|h|^7 / 7 < 2^-65`, since `|g_n| <= (1 + c^2)^(-(n+1)/2) <= 1` below, against a result
//!   of at least `0.029`, whose ulp is `2^-58`).
//!
//! The Taylor coefficients at `c` come from `g = atan' = 1 / (1 + t^2)`: `(1 + t^2) g = 1`
//! gives `(1 + c^2) g_n + 2 c g_(n-1) + g_(n-2) = 0` for `n >= 1`, and `atan(c + h) =
//! atan(c) + sum g_n h^(n+1) / (n + 1)`; `atan(c)` itself is the library's, once per node.
//!
//! **Accuracy.** The value is `atan(c)` (the library's, within its own error) plus a tail at
//! most `1/14` of the result in size and accurate to a few of its own ulps, rounded once: an
//! error of about one ulp. `pi/2 - atan(t)` adds a rounding of a result at least `pi/4`. The
//! test below measures it against the library on a million arguments: at most 2 ulps apart
//! (part of which is the library's own error and the different rounding of `x / n` against
//! `1 / (n / x)`), and the same bits in most cases (crates/core/MODEL.md, "The arctangent").

use std::f64::consts::FRAC_PI_2;
use std::sync::OnceLock;

/// Nodes per unit of `t`: `c = k / NODES` (a power of two, so `c` and `t - c` are exact).
pub const NODES: usize = 256;
/// The first node used; below `(FIRST - 0.5) / NODES` the Taylor series at 0.
pub const FIRST: usize = 8;
/// Coefficients per node: `atan(c)` and the degree-6 tail.
pub const TERMS: usize = 7;
/// The bits of `pi/2` below `FRAC_PI_2`: `pi/2 - FRAC_PI_2 = 6.123233995736766e-17`.
pub const FRAC_PI_2_LO: f64 = 6.123_233_995_736_766e-17;

/// The Taylor coefficients of `atan` at every node `k / NODES`, `k = 0..=NODES`: row `k` is
/// `atan(c)` and the tail's coefficients, lowest power first. Public so that code evaluating
/// [`atan_ratio`] on several arguments at once (`crates/core/examples/lanes.rs`) reads the
/// same table and gets the same bits.
pub fn table() -> &'static [[f64; TERMS]; NODES + 1] {
    static TABLE: OnceLock<[[f64; TERMS]; NODES + 1]> = OnceLock::new();
    TABLE.get_or_init(|| {
        let mut t = [[0.0; TERMS]; NODES + 1];
        for (k, row) in t.iter_mut().enumerate() {
            let c = k as f64 / NODES as f64;
            let q = 1.0 + c * c;
            row[0] = c.atan();
            // g_n, the Taylor coefficients of 1 / (1 + t^2) at c; row[n + 1] = g_n / (n + 1).
            let (mut g2, mut g1) = (0.0, 1.0 / q);
            row[1] = g1;
            for n in 1..TERMS - 1 {
                let g = -(2.0 * c * g1 + g2) / q;
                row[n + 1] = g / (n + 1) as f64;
                (g2, g1) = (g1, g);
            }
        }
        t
    })
}

/// `atan(t)` for `t` in `[0, 1]` (or NaN).
#[inline(always)]
fn atan_unit(t: f64) -> f64 {
    // The nearest node by the float adder: adding 2^52 to `t NODES` (in [0, 256]) rounds it
    // to an integer, whose value is then the low bits of the sum (NaN gives 0 and stays NaN
    // through the series). Cheaper than a float-to-integer cast and back.
    const ROUND: f64 = 4_503_599_627_370_496.0; // 2^52
    let sum = t * NODES as f64 + ROUND;
    let k = (sum.to_bits() & 0x1ff) as usize;
    if k < FIRST {
        // t - t^3/3 + t^5/5 - ... + t^13/13, in two halves of z = t^2.
        let z = t * t;
        let z2 = z * z;
        let lo = -1.0 / 3.0 + z * (1.0 / 5.0) + z2 * (-1.0 / 7.0);
        let hi = 1.0 / 9.0 + z * (-1.0 / 11.0) + z2 * (1.0 / 13.0);
        let p = lo + (z2 * z) * hi;
        return t + t * z * p;
    }
    let a = &table()[k.min(NODES)];
    // c = k / NODES exactly, and t - c is exact (Sterbenz: c / 2 <= t <= 2 c).
    let h = t - (sum - ROUND) * (1.0 / NODES as f64);
    // a1 + a2 h + ... + a6 h^5 by Estrin's scheme, then atan(c) + h (...), added last.
    let h2 = h * h;
    let p01 = a[1] + a[2] * h;
    let p23 = a[3] + a[4] * h;
    let p45 = a[5] + a[6] * h;
    let tail = p01 + h2 * (p23 + h2 * p45);
    a[0] + h * tail
}

/// `atan(y / x)` for `x > 0` (`y` any; NaN in, NaN out), within about one ulp: see the module
/// docs. Odd in `y`, `+-0` for `y = +-0`, `+-pi/2` for infinite `y`.
#[inline]
pub fn atan_ratio(y: f64, x: f64) -> f64 {
    let n = y.abs();
    let r = if n <= x {
        atan_unit(n / x)
    } else {
        FRAC_PI_2 - (atan_unit(x / n) - FRAC_PI_2_LO)
    };
    r.copysign(y)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Distance in ulps between two finite doubles of the same sign.
    fn ulps(a: f64, b: f64) -> u64 {
        (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs()
    }

    /// A deterministic stream of doubles in `[0, 1)` (a 64-bit LCG, Knuth's MMIX constants).
    fn uniform(state: &mut u64) -> f64 {
        *state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (*state >> 11) as f64 / (1u64 << 53) as f64
    }

    #[test]
    fn within_two_ulps_of_the_library_and_mostly_equal() {
        // Ratios over 2^-40 .. 2^40 (both reductions, the series and every node), both signs.
        let mut state = 7u64;
        let (mut worst, mut same, total) = (0u64, 0u64, 1_000_000u64);
        for _ in 0..total {
            let e = 80.0 * uniform(&mut state) - 40.0;
            let y = (1.0 + uniform(&mut state)) * e.exp2();
            let y = if uniform(&mut state) < 0.5 { -y } else { y };
            let x = 0.25 + 4.0 * uniform(&mut state);
            let (got, want) = (atan_ratio(y, x), (y / x).atan());
            let d = ulps(got, want);
            assert!(d <= 2, "atan({y} / {x}): {got} against {want}, {d} ulps");
            worst = worst.max(d);
            same += u64::from(d == 0);
        }
        eprintln!("worst {worst} ulps; {same} of {total} the same bits");
        // The reduction keeps most results on the library's bits (measured: 97.6%, see
        // crates/core/MODEL.md); far fewer would mean a wrong coefficient that the 2-ulp
        // bound alone might not catch near the nodes.
        assert!(same * 10 >= total * 8, "{same} of {total} the same bits");
    }

    #[test]
    fn nodes_and_interval_ends() {
        // At a node h = 0 and the value is the library's atan(c); around each node's interval
        // ends (the switch between neighbouring polynomials) both sides agree with the library.
        for k in 0..=NODES {
            let c = k as f64 / NODES as f64;
            if k >= FIRST {
                assert_eq!(atan_ratio(c, 1.0), c.atan(), "node {k}");
            }
            for t in [c - 0.5 / 256.0, c + 0.5 / 256.0] {
                for u in [t.next_down(), t, t.next_up()] {
                    if (0.0..=1.0).contains(&u) {
                        assert!(ulps(atan_ratio(u, 1.0), u.atan()) <= 1, "t = {u}");
                    }
                }
            }
        }
    }

    #[test]
    fn special_values() {
        assert_eq!(atan_ratio(0.0, 1.0).to_bits(), 0.0f64.to_bits());
        assert_eq!(atan_ratio(-0.0, 1.0).to_bits(), (-0.0f64).to_bits());
        assert_eq!(atan_ratio(f64::INFINITY, 2.0), FRAC_PI_2);
        assert_eq!(atan_ratio(f64::NEG_INFINITY, 2.0), -FRAC_PI_2);
        assert_eq!(atan_ratio(1.0, f64::INFINITY), 0.0);
        assert!(atan_ratio(f64::NAN, 1.0).is_nan());
        assert!(atan_ratio(1.0, f64::NAN).is_nan());
        // Tiny and huge ratios: atan(t) = t and pi/2 to rounding.
        assert_eq!(atan_ratio(1e-300, 1.0), 1e-300);
        assert_eq!(atan_ratio(1e300, 1.0), FRAC_PI_2);
    }
}
