//! Basin maps in the atlas: one map per parameter point, made by the scan's spine.
//!
//! An atlas spec with a `[grid]` table ([`super::spec::MapSettings`]) turns into a scan
//! [`Plan`] whose maps are the atlas's parameter points ([`AtlasPlan::map_plan`]): the same
//! [`crate::MapContext`], [`crate::scanner::run_block`], classifier, early stopping, audit
//! and cell schema ([`crate::cell::COLUMNS`]) as `squeal scan`, driven by [`crate::drive`]
//! over `(point, block)` pairs. Resume and shards follow the scan's rules
//! ([`crate::shard_owns`] on the global block index).
//!
//! Per point, [`map_fraction`] reads the basin fraction of steady slip off the map.

use crate::cell::Cell;
use crate::curve::ClosedCurve;
use crate::grid::Grid;
use crate::spec::Plan;
use squeal_core::Regime;

use super::spec::AtlasPlan;

impl AtlasPlan {
    /// The scan plan of the basin maps (map `i` = parameter point `i`), if the spec has a
    /// `[grid]`. Cycles are located (a scan's `[cycle]` defaults: the search reaches beyond
    /// the grid) so each map stores the cycle that bounds its basin.
    pub fn map_plan(&self) -> Option<Plan> {
        let m = self.maps.as_ref()?;
        Some(Plan {
            spec_text: self.spec_text.clone(),
            spec_path: self.spec_path.clone(),
            name: self.name.clone(),
            maps: (0..self.space.n_points())
                .map(|i| self.space.params_at(i))
                .collect(),
            sweep: None,
            space: self.space.clone(),
            map: *m,
            dt: self.dt,
            solver: self.solver,
            cycle: crate::spec::CycleOptions::scan(),
            output: self.out.clone(),
        })
    }
}

/// What point `i`'s map adds up to, as the atlas file stores it per point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointMap {
    /// The consistency checks of the blocks stored (a shard's own, in a shard file).
    pub checks: crate::MapChecks,
    /// The basin fraction, where the map is complete.
    pub fraction: Option<MapFraction>,
    /// The final-state sensitivity of the map ([`crate::sensitivity`]), where it is
    /// complete.
    pub sensitivity: Option<crate::sensitivity::Sensitivity>,
}

/// Every point's [`PointMap`] (point order; none without maps), the points in parallel.
/// Laws with true stick: the cells are checked against the point's landscape (every cell
/// steady slip, or every cell stick-slip, where it says so).
pub fn point_maps(plan: &AtlasPlan, res: &super::AtlasResults) -> Vec<PointMap> {
    use rayon::prelude::*;
    let Some(mp) = plan.map_plan() else {
        return Vec::new();
    };
    (0..plan.space.n_points())
        .into_par_iter()
        .map(|i| {
            let landscape = (res.points[i].as_ref())
                .and_then(|p| p.landscape)
                .and_then(|l| l.verdict());
            let tally = crate::MapTally::new(&mp, res.map_cycle(i), landscape);
            for b in 0..mp.map.grid.blocks() {
                if let Some(cells) = res.blocks.get(&(i, b)) {
                    tally.add_block(&mp, b, cells);
                }
            }
            let (checks, _, labels) = tally.finish(&mp);
            let fraction = res.map_fraction(plan, i);
            // A complete map's sensitivity (its census is taken again: an atlas does not
            // store which rule groups it withdrew).
            let complete = !labels.contains(&crate::cell::NOT_COMPUTED);
            let sensitivity =
                complete.then(|| crate::sensitivity::Sensitivity::of_map(&mp, i, None, &labels));
            PointMap {
                checks,
                fraction,
                sensitivity,
            }
        })
        .collect()
}

/// What an atlas's finish computes once every unit is in: the labels that contradict a
/// fold reconciled ([`super::AtlasResults::reconcile_folds`]; a point and its fold may
/// come from different shards), then every point's map figures. The writer stores them.
pub fn finish(plan: &AtlasPlan, res: &mut super::AtlasResults) -> Vec<PointMap> {
    res.reconcile_folds(plan);
    point_maps(plan, res)
}

/// The basin fraction of steady slip read off one map.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapFraction {
    /// Steady-slip cells over decided cells (steady slip + stick-slip); NaN if none decided.
    pub fraction: f64,
    /// Its uncertainty: (undecided cells + decided cells within one cell of the located
    /// cycle) over all cells. An undecided cell could go either way (it moves the share of
    /// decided cells by at most one cell in either direction); a cell whose pixel the cycle
    /// may cross stands for an area that lies partly on each side.
    pub err: f64,
    /// Cells in the map.
    pub cells: u64,
    /// Steady-slip cells.
    pub steady: u64,
    /// Stick-slip cells.
    pub stick: u64,
    /// Undecided (or not computed) cells.
    pub undecided: u64,
    /// Decided cells within one cell (in grid units, per axis) of the located cycle.
    pub near_cycle: u64,
}

/// Marks the cells of `grid` within one cell of the closed curve `c` (distance from the
/// cell centre to a segment of the curve at most one cell, measured in cells per axis).
pub fn cells_near_curve(grid: &Grid, c: &ClosedCurve) -> Vec<bool> {
    let (nx, nv) = (grid.x0.count, grid.v0.count);
    let mut near = vec![false; nx * nv];
    let n = c.x.len().min(c.v.len());
    if n == 0 {
        return near;
    }
    let dx = if nx > 1 { grid.x0.spacing() } else { 1.0 };
    let dv = if nv > 1 { grid.v0.spacing() } else { 1.0 };
    // Curve points in cell units: cell (i, j) sits at (i, j).
    let u: Vec<(f64, f64)> = (0..n)
        .map(|k| ((c.x[k] - grid.x0.min) / dx, (c.v[k] - grid.v0.min) / dv))
        .collect();
    for k in 0..n {
        let (a, b) = (u[k], u[(k + 1) % n]);
        if !(a.0.is_finite() && a.1.is_finite() && b.0.is_finite() && b.1.is_finite()) {
            continue;
        }
        let i0 = (a.0.min(b.0) - 1.0).ceil().max(0.0);
        let i1 = (a.0.max(b.0) + 1.0).floor().min(nx as f64 - 1.0);
        let j0 = (a.1.min(b.1) - 1.0).ceil().max(0.0);
        let j1 = (a.1.max(b.1) + 1.0).floor().min(nv as f64 - 1.0);
        if i0 > i1 || j0 > j1 {
            continue;
        }
        let (ex, ey) = (b.0 - a.0, b.1 - a.1);
        let len2 = ex * ex + ey * ey;
        for j in j0 as usize..=j1 as usize {
            for i in i0 as usize..=i1 as usize {
                let (px, py) = (i as f64 - a.0, j as f64 - a.1);
                let t = if len2 > 0.0 {
                    ((px * ex + py * ey) / len2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                if (px - t * ex).hypot(py - t * ey) <= 1.0 {
                    near[j * nx + i] = true;
                }
            }
        }
    }
    near
}

/// The basin fraction of steady slip of one map (cells row-major over `(v0, x0)`), with the
/// uncertainty of [`MapFraction::err`]; `cycle` is the map's located cycle, if any.
pub fn map_fraction(grid: &Grid, cells: &[Cell], cycle: Option<&ClosedCurve>) -> MapFraction {
    let near = cycle.map(|c| cells_near_curve(grid, c));
    let mut f = MapFraction {
        fraction: f64::NAN,
        err: f64::NAN,
        cells: cells.len() as u64,
        steady: 0,
        stick: 0,
        undecided: 0,
        near_cycle: 0,
    };
    for (k, c) in cells.iter().enumerate() {
        let decided = match c.regime() {
            Some(Regime::SteadySlip) => {
                f.steady += 1;
                true
            }
            Some(Regime::StickSlip) => {
                f.stick += 1;
                true
            }
            _ => {
                f.undecided += 1;
                false
            }
        };
        if decided && near.as_ref().is_some_and(|n| n.get(k) == Some(&true)) {
            f.near_cycle += 1;
        }
    }
    let decided = f.steady + f.stick;
    if decided > 0 {
        f.fraction = f.steady as f64 / decided as f64;
    }
    if f.cells > 0 {
        f.err = (f.undecided + f.near_cycle) as f64 / f.cells as f64;
    }
    f
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::Axis;

    fn grid(n: usize) -> Grid {
        Grid {
            x0: Axis {
                min: -1.0,
                max: 1.0,
                count: n,
            },
            v0: Axis {
                min: -1.0,
                max: 1.0,
                count: n,
            },
            block_rows: 4,
            starts: crate::grid::Starts::Grid,
        }
    }

    fn circle(r: f64, n: usize) -> ClosedCurve {
        let t = |k: usize| 2.0 * std::f64::consts::PI * k as f64 / n as f64;
        ClosedCurve {
            x: (0..n).map(|k| r * t(k).cos()).collect(),
            v: (0..n).map(|k| r * t(k).sin()).collect(),
        }
    }

    #[test]
    fn a_disc_map_gives_the_disc_area_within_its_bound() {
        // Cells inside a circle of radius 0.6 steady, outside stick-slip: the share tends
        // to the area ratio pi 0.36 / 4 (closed form), and the near-cycle band bounds the
        // pixel error.
        let g = grid(41);
        let c = circle(0.6, 400);
        let cells: Vec<Cell> = (0..g.cells())
            .map(|k| {
                let (x, v) = (g.x0.value(k % 41), g.v0.value(k / 41));
                let mut cell = Cell::fill();
                cell.regime = if x.hypot(v) < 0.6 { 1 } else { 2 };
                cell
            })
            .collect();
        let f = map_fraction(&g, &cells, Some(&c));
        let exact = std::f64::consts::PI * 0.36 / 4.0;
        assert!(f.near_cycle > 0 && f.undecided == 0);
        assert!((f.fraction - exact).abs() <= f.err, "{f:?} vs {exact}");
        // The band is a ring about two cells wide: of the order of the perimeter in cells.
        let ring = 2.0 * std::f64::consts::PI * 0.6 / g.x0.spacing() * 2.0;
        assert!((f.near_cycle as f64) < 1.5 * ring && (f.near_cycle as f64) > 0.5 * ring);
    }

    #[test]
    fn undecided_cells_widen_the_bound() {
        let g = grid(4);
        let mut cells = vec![Cell::fill(); 16];
        for (k, c) in cells.iter_mut().enumerate() {
            c.regime = match k {
                0..=7 => 1,
                8..=11 => 2,
                _ => 0,
            };
        }
        let f = map_fraction(&g, &cells, None);
        assert_eq!((f.steady, f.stick, f.undecided), (8, 4, 4));
        assert_eq!(f.fraction, 8.0 / 12.0);
        assert_eq!(f.err, 4.0 / 16.0);
    }
}
