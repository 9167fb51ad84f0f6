//! Basin stability as bSTAB defines it (Menck et al., Nature Physics 2013; Stender et al.,
//! Nonlinear Dynamics 2021): the share of a region's initial conditions that end on each
//! attractor, here per [`Regime`] (steady slip, stick-slip, and undecided, a label of its own).
//!
//! * For `N` initial conditions drawn uniformly at random, a share `p` has the binomial
//!   standard error `sqrt(p (1 - p) / N)`.
//! * For a grid the error is not statistical: it comes from the cells cut by the basin
//!   boundary and shrinks with the spacing `h`. [`GridShares`] gives the share on the grid
//!   (`h`), on its nested sub-grids of every second (`2h`) and fourth (`4h`) point along
//!   each axis, and the change `p_h - p_2h`, the grid-converged value's error bar. No
//!   Richardson extrapolation: the share of grid points in a basin does not converge at a
//!   clean order (on a straight boundary the errors at 65, 129, 257 and 513 points per axis
//!   are 5.0e-3, 2.1e-3, 5.1e-4, 3.9e-4: lattice effects, see the test below), so an
//!   extrapolated value would rest on an assumption that does not hold. The sub-grids hold the points whose indices are multiples of 2 (4)
//!   along both axes; they span the same region when `count - 1` is divisible by 2 (4), as
//!   with counts `2^k + 1`; otherwise they stop one or three spacings short of `max`.
//!
//! [`BASIN_FIELDS`] is the one table of what a file and a report hold per map.

use rayon::prelude::*;
use serde::Serialize;
use squeal_core::Regime;

use crate::cell::NOT_COMPUTED;

/// One regime's share of a set of initial conditions.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Share {
    /// Initial conditions with this label.
    pub count: u64,
    /// `count / n` (NaN when `n = 0`).
    pub p: f64,
    /// `sqrt(p (1 - p) / n)`: the standard error if the initial conditions were drawn
    /// uniformly at random (NaN when `n = 0`).
    pub se: f64,
}

impl Share {
    /// The share of `count` in `n`.
    pub fn of(count: u64, n: u64) -> Share {
        if n == 0 {
            return Share {
                count,
                p: f64::NAN,
                se: f64::NAN,
            };
        }
        let p = count as f64 / n as f64;
        Share {
            count,
            p,
            se: (p * (1.0 - p) / n as f64).sqrt(),
        }
    }
}

/// The regimes a basin-stability report covers, in report order.
pub const REGIMES: [Regime; 4] = [
    Regime::SteadySlip,
    Regime::StickSlip,
    Regime::Undecided,
    Regime::SlipOscillation,
];

/// Shares of each regime among `labels` (stored label values; cells not computed are left
/// out of `n`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Shares {
    /// Labelled initial conditions.
    pub n: u64,
    /// Per regime of [`REGIMES`].
    pub shares: [Share; REGIMES.len()],
}

impl Shares {
    /// Counts the labels.
    pub fn of<'a>(labels: impl IntoIterator<Item = &'a u8>) -> Shares {
        let mut c = Counts::default();
        for &l in labels {
            c.add(l);
        }
        c.shares()
    }

    /// The share of `regime`.
    pub fn get(&self, regime: Regime) -> Share {
        let i = REGIMES.iter().position(|r| *r == regime).expect("a regime");
        self.shares[i]
    }
}

/// A map's shares: for a grid at its spacing and on its nested coarser sub-grids; for a
/// random sample (`random`) the sub-grid shares are NaN (`n = 0`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct GridShares {
    /// Whether the initial conditions are uniform random samples (then `se` is the error).
    pub random: bool,
    /// On every point (spacing `h`).
    pub h: Shares,
    /// On every second point along each axis (`2h`).
    pub h2: Shares,
    /// On every fourth point along each axis (`4h`).
    pub h4: Shares,
}

/// Labels counted per regime of [`REGIMES`] (`c`) and in all (`n`, cells not computed left
/// out): integer sums, so counts of parts added up are those of the whole.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Counts {
    c: [u64; REGIMES.len()],
    n: u64,
}

impl Counts {
    fn add(&mut self, l: u8) {
        if l == NOT_COMPUTED {
            return;
        }
        self.n += 1;
        if let Some(i) = REGIMES.iter().position(|r| *r as u8 == l) {
            self.c[i] += 1;
        }
    }

    fn plus(self, o: Counts) -> Counts {
        Counts {
            c: std::array::from_fn(|i| self.c[i] + o.c[i]),
            n: self.n + o.n,
        }
    }

    fn shares(self) -> Shares {
        Shares {
            n: self.n,
            shares: self.c.map(|k| Share::of(k, self.n)),
        }
    }
}

impl GridShares {
    /// From a map's labels, row-major `(v0, x0)` with `nx` columns. The rows are counted on
    /// the rayon pool (a 4096 x 4096 map's three passes took 0.1 s on one thread at the end
    /// of a scan); the counts are integer sums, the same on any number of threads.
    pub fn of(labels: &[u8], nx: usize) -> GridShares {
        let nx = nx.max(1);
        // Every point; every second row and in it every second column; every fourth.
        let [h, h2, h4] = labels
            .par_chunks(nx)
            .enumerate()
            .map(|(r, row)| {
                let level = |s: usize| {
                    let mut c = Counts::default();
                    if r % s == 0 {
                        row.iter().step_by(s).for_each(|&l| c.add(l));
                    }
                    c
                };
                [level(1), level(2), level(4)]
            })
            .reduce(
                || [Counts::default(); 3],
                |a, b| std::array::from_fn(|i| a[i].plus(b[i])),
            );
        GridShares {
            random: false,
            h: h.shares(),
            h2: h2.shares(),
            h4: h4.shares(),
        }
    }

    /// From the labels of uniform random samples (no sub-grids).
    pub fn random(labels: &[u8]) -> GridShares {
        let none = Shares::of(&[]);
        GridShares {
            random: true,
            h: Shares::of(labels),
            h2: none,
            h4: none,
        }
    }

    /// `p_h - p_2h` for regime number `i` of [`REGIMES`].
    pub fn change(&self, i: usize) -> f64 {
        self.h.shares[i].p - self.h2.shares[i].p
    }

    /// The values of [`BASIN_FIELDS`], in order.
    pub fn values(&self) -> Vec<f64> {
        let mut v = Vec::with_capacity(BASIN_FIELDS.len());
        for i in 0..REGIMES.len() {
            v.push(self.h.shares[i].p);
            v.push(self.h.shares[i].se);
            v.push(self.h2.shares[i].p);
            v.push(self.h4.shares[i].p);
            v.push(self.change(i));
        }
        v
    }
}

/// A stored map read back: its cells per label and its basin stability.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapSummary {
    /// Cells per [`MapSummary::COUNT_NAMES`]: undecided, steady_slip, stick_slip, not
    /// computed, slip_oscillation.
    pub counts: [u64; 5],
    /// The basin stability of its labels ([`GridShares`]).
    pub basin: GridShares,
}

impl MapSummary {
    /// The names of [`MapSummary::counts`], in order.
    pub const COUNT_NAMES: [&'static str; 5] = [
        "undecided",
        "steady_slip",
        "stick_slip",
        "not_computed",
        "slip_oscillation",
    ];

    /// Of a map's labels, row-major `(v0, x0)` with `nx` columns, or a list of random
    /// samples (`random`).
    pub fn of(labels: &[u8], nx: usize, random: bool) -> MapSummary {
        let mut counts = [0u64; 5];
        for &l in labels {
            counts[match l {
                0 => 0,
                1 => 1,
                2 => 2,
                3 => 4,
                _ => 3,
            }] += 1;
        }
        let basin = if random {
            GridShares::random(labels)
        } else {
            GridShares::of(labels, nx)
        };
        MapSummary { counts, basin }
    }
}

/// What a file stores per map (dataset name, long name), in the order of
/// [`GridShares::values`]: five per regime of [`REGIMES`].
pub const BASIN_FIELDS: &[(&str, &str)] = &[
    (
        "basin_stability_steady_slip",
        "basin stability of steady slip: share of the computed initial conditions labelled steady_slip",
    ),
    (
        "basin_stability_steady_slip_se",
        "sqrt(p (1 - p) / N) of the steady-slip share (the standard error for uniform random samples; a grid's error is its change under refinement)",
    ),
    (
        "basin_stability_steady_slip_2h",
        "steady-slip share on the sub-grid of every second point along each axis (spacing 2h; NaN for random samples)",
    ),
    (
        "basin_stability_steady_slip_4h",
        "steady-slip share on the sub-grid of every fourth point along each axis (spacing 4h)",
    ),
    (
        "basin_stability_steady_slip_change",
        "p_h - p_2h: change of the steady-slip share from the 2h sub-grid to the full grid (the grid error bar)",
    ),
    (
        "basin_stability_stick_slip",
        "basin stability of stick-slip: share of the computed initial conditions labelled stick_slip",
    ),
    (
        "basin_stability_stick_slip_se",
        "sqrt(p (1 - p) / N) of the stick-slip share (the standard error for uniform random samples; a grid's error is its change under refinement)",
    ),
    (
        "basin_stability_stick_slip_2h",
        "stick-slip share on the sub-grid of every second point along each axis (spacing 2h; NaN for random samples)",
    ),
    (
        "basin_stability_stick_slip_4h",
        "stick-slip share on the sub-grid of every fourth point along each axis (spacing 4h)",
    ),
    (
        "basin_stability_stick_slip_change",
        "p_h - p_2h: change of the stick-slip share from the 2h sub-grid to the full grid (the grid error bar)",
    ),
    (
        "basin_stability_undecided",
        "share of the computed initial conditions left undecided by t_max",
    ),
    (
        "basin_stability_undecided_se",
        "sqrt(p (1 - p) / N) of the undecided share",
    ),
    (
        "basin_stability_undecided_2h",
        "undecided share on the sub-grid of every second point along each axis (spacing 2h; NaN for random samples)",
    ),
    (
        "basin_stability_undecided_4h",
        "undecided share on the sub-grid of every fourth point along each axis (spacing 4h)",
    ),
    (
        "basin_stability_undecided_change",
        "p_h - p_2h: change of the undecided share from the 2h sub-grid to the full grid (the grid error bar)",
    ),
    (
        "basin_stability_slip_oscillation",
        "share of the computed initial conditions labelled slip_oscillation (a steady slip that does not attract, the run on an oscillation about it that never sticks)",
    ),
    (
        "basin_stability_slip_oscillation_se",
        "sqrt(p (1 - p) / N) of the slip-oscillation share",
    ),
    (
        "basin_stability_slip_oscillation_2h",
        "slip-oscillation share on the sub-grid of every second point along each axis (spacing 2h; NaN for random samples)",
    ),
    (
        "basin_stability_slip_oscillation_4h",
        "slip-oscillation share on the sub-grid of every fourth point along each axis (spacing 4h)",
    ),
    (
        "basin_stability_slip_oscillation_change",
        "p_h - p_2h: change of the slip-oscillation share from the 2h sub-grid to the full grid (the grid error bar)",
    ),
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn standard_error_is_the_binomial_one() {
        // bSTAB's friction case 1 as kept in pyBasin (tests/data/bstab_friction_published.json):
        // 1520 of 5000 on the fixed point, published se 0.0065051364320819587.
        let s = Share::of(1520, 5000);
        assert_eq!(s.p, 0.304);
        assert!((s.se - 0.006_505_136_432_081_959).abs() < 1e-15);
        assert_eq!(Share::of(0, 5000).se, 0.0);
        assert!(Share::of(0, 0).p.is_nan());
    }

    /// The sub-grid shares counted by rows on the pool are those of the labels taken at
    /// each spacing one by one, on 1 and 3 threads, with a last row cut short and cells not
    /// computed among them.
    #[test]
    fn grid_shares_counted_by_rows_match_each_spacing() {
        let nx = 7;
        let labels: Vec<u8> = (0..(nx * 13 + 3) as u64)
            .map(
                |i| match (i.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 40) % 5 {
                    0 => NOT_COMPUTED,
                    k => (k % 3) as u8,
                },
            )
            .collect();
        let spacing = |s: usize| {
            Shares::of(
                labels
                    .chunks(nx)
                    .step_by(s)
                    .flat_map(|row| row.iter().step_by(s)),
            )
        };
        for threads in [1, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let g = pool.install(|| GridShares::of(&labels, nx));
            assert_eq!((g.h, g.h2, g.h4), (spacing(1), spacing(2), spacing(4)));
        }
        assert!(spacing(2).n < spacing(1).n && spacing(4).n < spacing(2).n);
    }

    #[test]
    fn shares_leave_out_cells_not_computed() {
        let s = Shares::of(&[1, 1, 2, 0, NOT_COMPUTED]);
        assert_eq!(s.n, 4);
        assert_eq!(s.get(Regime::SteadySlip).count, 2);
        assert_eq!(s.get(Regime::StickSlip).p, 0.25);
        assert_eq!(s.get(Regime::Undecided).p, 0.25);
    }

    #[test]
    fn nested_grids_converge_to_the_area_of_a_half_plane() {
        // A straight boundary x < v / 3 + 0.1 on [0, 1]^2: the exact steady-slip share is the
        // area 1/6 + 0.1 = 0.2666..., and the grid error falls with the spacing.
        let area = 0.1 + 1.0 / 6.0;
        let grid = |n: usize| {
            let mut l = Vec::with_capacity(n * n);
            for r in 0..n {
                for c in 0..n {
                    let (x, v) = (c as f64 / (n - 1) as f64, r as f64 / (n - 1) as f64);
                    l.push(if x < v / 3.0 + 0.1 { 1u8 } else { 2 });
                }
            }
            l
        };
        let n = 257;
        let g = GridShares::of(&grid(n), n);
        // The sub-grids of a 2^k + 1 grid are the 129- and 65-point grids.
        let coarse = GridShares::of(&grid(129), 129);
        assert_eq!(g.h2, coarse.h);
        assert_eq!(g.h4, coarse.h2);
        let e = |p: f64| (p - area).abs();
        let (eh, e2, e4) = (e(g.h.shares[0].p), e(g.h2.shares[0].p), e(g.h4.shares[0].p));
        assert!(eh < e2 && e2 < e4, "{eh} {e2} {e4}");
        // The node-sampled share of a half plane is biased by the closed edges, ~ 1/n.
        assert!(eh < 2.0 / n as f64, "{eh}");
        // The change from the 2h grid bounds the error of the h grid here (5.1e-4 vs 1.6e-3).
        assert!(eh < g.change(0).abs(), "{eh} vs {}", g.change(0));
        assert_eq!(g.values().len(), BASIN_FIELDS.len());
    }
}
