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

/// The grid: `x0` along the columns, `v0` along the rows; blocks are runs of `block_rows` rows.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Grid {
    /// Initial displacements.
    pub x0: Axis,
    /// Initial velocities.
    pub v0: Axis,
    /// Rows of `v0` per block (the unit of storage, resume and sharding).
    pub block_rows: usize,
}

impl Grid {
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

#[cfg(test)]
mod tests {
    use super::*;

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
        };
        assert_eq!(g.blocks(), 3);
        let rows: Vec<usize> = (0..g.blocks()).flat_map(|b| g.block_rows(b)).collect();
        assert_eq!(rows, (0..10).collect::<Vec<_>>());
    }
}
