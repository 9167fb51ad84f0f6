//! The grid of initial conditions and its blocks.

use serde::Serialize;

/// Equally spaced values `min + i (max - min) / (count - 1)` (computed by index, never by
/// adding a step); a single value is `min`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Axis {
    /// First value.
    pub min: f64,
    /// Last value.
    pub max: f64,
    /// Number of values.
    pub count: usize,
}

impl Axis {
    /// The `i`-th value.
    #[inline]
    pub fn value(&self, i: usize) -> f64 {
        if self.count <= 1 {
            self.min
        } else if i + 1 == self.count {
            self.max
        } else {
            self.min + i as f64 * (self.max - self.min) / (self.count - 1) as f64
        }
    }

    /// All values.
    pub fn values(&self) -> Vec<f64> {
        (0..self.count).map(|i| self.value(i)).collect()
    }

    /// Spacing between neighbours (0 for one value).
    pub fn spacing(&self) -> f64 {
        if self.count <= 1 {
            0.0
        } else {
            (self.max - self.min) / (self.count - 1) as f64
        }
    }
}

/// Initial conditions drawn uniformly at random in a rectangle (bSTAB's sampling).
///
/// Sample `i` depends only on `(seed, i)`: its coordinates are SplitMix64 (Steele, Lea and
/// Flood, OOPSLA 2014) of the counters `2 i` and `2 i + 1` offset by the seed, the top 53
/// bits scaled to `[0, 1)`. So a sample is the same whatever the thread count, the block
/// order, a resume or a shard.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct RandomSample {
    /// Number of initial conditions.
    pub n: usize,
    /// The seed.
    pub seed: u64,
}

/// SplitMix64's output function of the counter `z`.
fn splitmix64(z: u64) -> u64 {
    let mut z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

impl RandomSample {
    /// Uniform number in `[0, 1)` number `k` of the stream.
    fn unit(&self, k: u64) -> f64 {
        let z = splitmix64(
            self.seed
                .wrapping_mul(0xD1B5_4A32_D192_ED03)
                .wrapping_add(k.wrapping_mul(0x9E37_79B9_7F4A_7C15)),
        );
        (z >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Sample `i` in the rectangle `x0 x v0`: `(x, v)`.
    pub fn point(&self, i: usize, x0: &Axis, v0: &Axis) -> (f64, f64) {
        let (a, b) = (self.unit(2 * i as u64), self.unit(2 * i as u64 + 1));
        (
            x0.min + a * (x0.max - x0.min),
            v0.min + b * (v0.max - v0.min),
        )
    }
}

/// The initial conditions of a map and their blocks. A grid has `x0` along the columns and
/// `v0` along the rows; blocks are runs of `block_rows` rows.
///
/// With `sample` (uniform random initial conditions) the layout is a list: one sample per
/// row, `x0.count = 1`, `v0.count = n`, and `x0`, `v0` hold the rectangle's bounds (not grid
/// values); [`Grid::state`] gives each cell's initial condition in both layouts.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Grid {
    /// Initial displacements (for a sample: the bounds, count 1).
    pub x0: Axis,
    /// Initial velocities (for a sample: the bounds, count n).
    pub v0: Axis,
    /// Rows of `v0` per block (the unit of storage, resume and sharding).
    pub block_rows: usize,
    /// Where the runs start: the grid's cells or random samples.
    pub starts: Starts,
}

/// Where a map's runs start.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub enum Starts {
    /// The cells of the grid: cell `(row, col)` starts at `(x0[col], v0[row])`.
    Grid,
    /// Random initial conditions in the rectangle of `x0`'s and `v0`'s bounds, a list in
    /// rows (`x0.count = 1`, `v0.count = n`): sample `row` is [`RandomSample::point`].
    Sample(RandomSample),
}

impl Grid {
    /// The initial condition `(x0, v0)` of the cell at `row`, `col`.
    #[inline]
    pub fn state(&self, row: usize, col: usize) -> (f64, f64) {
        match &self.starts {
            Starts::Sample(s) => s.point(row, &self.x0, &self.v0),
            Starts::Grid => (self.x0.value(col), self.v0.value(row)),
        }
    }

    /// Whether the initial conditions are random samples (a list, not a grid).
    pub fn is_sample(&self) -> bool {
        matches!(self.starts, Starts::Sample(_))
    }

    /// Cells in one map.
    pub fn cells(&self) -> usize {
        self.x0.count * self.v0.count
    }

    /// Blocks in one map.
    pub fn blocks(&self) -> usize {
        self.v0.count.div_ceil(self.block_rows)
    }

    /// Rows `[start, end)` of block `b`.
    pub fn block_rows(&self, b: usize) -> std::ops::Range<usize> {
        let start = b * self.block_rows;
        start..((b + 1) * self.block_rows).min(self.v0.count)
    }
}

/// The farthest start of `grid` from the fixed point of `params`.
pub fn grid_reach(grid: &Grid, params: &squeal_core::Params) -> f64 {
    let fp = params.fixed_point();
    [grid.x0.min, grid.x0.max]
        .iter()
        .flat_map(|&x| [grid.v0.min, grid.v0.max].map(|v| (x - fp.x).hypot(v - fp.v)))
        .fold(0.0f64, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn random_samples_are_uniform_and_reproducible() {
        let s = RandomSample { n: 20_000, seed: 7 };
        let (x0, v0) = (
            Axis {
                min: -2.0,
                max: 2.0,
                count: 1,
            },
            Axis {
                min: 0.0,
                max: 2.0,
                count: s.n,
            },
        );
        let pts: Vec<(f64, f64)> = (0..s.n).map(|i| s.point(i, &x0, &v0)).collect();
        assert!(
            pts.iter()
                .all(|&(x, v)| (-2.0..2.0).contains(&x) && (0.0..2.0).contains(&v))
        );
        assert_eq!(pts[123], s.point(123, &x0, &v0));
        assert_ne!(
            pts[123],
            RandomSample { n: s.n, seed: 8 }.point(123, &x0, &v0)
        );
        // Quadrant counts of a uniform sample: binomial with p = 1/4, sd = sqrt(n p (1 - p))
        // = 61.2; each within 4 sd of n / 4. Means within 4 standard errors (x: 4 / sqrt(12 n)).
        let mut q = [0usize; 4];
        for &(x, v) in &pts {
            q[(x > 0.0) as usize + 2 * (v > 1.0) as usize] += 1;
        }
        for c in q {
            assert!((c as f64 - 5000.0).abs() < 4.0 * 61.2, "{q:?}");
        }
        let mx = pts.iter().map(|p| p.0).sum::<f64>() / s.n as f64;
        assert!(mx.abs() < 4.0 * 4.0 / (12.0 * s.n as f64).sqrt(), "{mx}");
    }

    #[test]
    fn axis_by_index_hits_both_ends() {
        let a = Axis {
            min: -3.0,
            max: 5.0,
            count: 7,
        };
        assert_eq!(a.value(0), -3.0);
        assert_eq!(a.value(6), 5.0);
        assert!((a.value(3) - 1.0).abs() < 1e-15);
        assert_eq!(
            Axis {
                min: 2.0,
                max: 2.0,
                count: 1
            }
            .values(),
            vec![2.0]
        );
    }

    #[test]
    fn blocks_cover_rows_once() {
        let g = Grid {
            x0: Axis {
                min: 0.0,
                max: 1.0,
                count: 3,
            },
            v0: Axis {
                min: 0.0,
                max: 1.0,
                count: 10,
            },
            block_rows: 4,
            starts: Starts::Grid,
        };
        assert_eq!(g.blocks(), 3);
        let rows: Vec<usize> = (0..g.blocks()).flat_map(|b| g.block_rows(b)).collect();
        assert_eq!(rows, (0..10).collect::<Vec<_>>());
    }
}
