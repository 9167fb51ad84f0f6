//! How long a scan will take, measured rather than assumed: a pilot prepares a few of the
//! plan's maps (the cycle search and, for laws with true stick, the landscape, as the scan
//! does) and classifies a spread sample of their cells with the scan's own classifier (early
//! stopping, the start rule, the audit). Its time per cell therefore follows the law, each
//! map's landscape and whether early stopping holds there (near the fold of cycles it does
//! not, and cells run to settlement): a fixed "documented rate" was off 50-fold on
//! `scans/nu-sweep.toml` and on `scans/bstab-friction.toml` (issue 21).
//!
//! `scripts/bench-estimate.sh` checks the estimate against the measured time of shipped
//! specs (BENCHMARKS.md, "Scan time estimates").

use std::time::{Duration, Instant};

use crate::atlas::AtlasPlan;
use crate::error::ScanError;
use crate::scanner::MapContext;
use crate::spec::Plan;

/// At most this many maps are prepared by the pilot (evenly spread over a sweep).
pub const PILOT_MAPS: usize = 8;
/// The pilot stops after this many cells ...
pub const PILOT_CELLS: usize = 512;
/// ... or after this much time classifying cells (after the maps are prepared), whichever
/// comes first (at least one cell per map).
pub const PILOT_BUDGET: Duration = Duration::from_millis(1500);

/// A pilot's measurements and the estimate they give.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    /// Maps prepared by the pilot.
    pub maps: usize,
    /// Cells classified by the pilot.
    pub cells: usize,
    /// Seconds the pilot took.
    pub pilot_seconds: f64,
    /// Mean seconds to prepare one map (one thread).
    pub prepare_seconds: f64,
    /// Mean seconds per cell (one thread).
    pub cell_seconds: f64,
}

impl Estimate {
    /// Wall seconds for `maps` maps with `cells` cells in all on `threads` threads (maps are
    /// prepared one at a time; cells run in parallel).
    pub fn seconds(&self, maps: usize, cells: usize, threads: usize) -> f64 {
        maps as f64 * self.prepare_seconds
            + cells as f64 * self.cell_seconds / threads.max(1) as f64
    }
}

/// Runs the pilot on `plan` (single-threaded).
pub fn pilot(plan: &Plan) -> Result<Estimate, ScanError> {
    let t0 = Instant::now();
    let n = plan.maps.len();
    let picked: Vec<usize> = if n <= PILOT_MAPS {
        (0..n).collect()
    } else {
        (0..PILOT_MAPS)
            .map(|i| i * (n - 1) / (PILOT_MAPS - 1))
            .collect()
    };
    let mut contexts = Vec::with_capacity(picked.len());
    for &m in &picked {
        // Maps whose preparation is slow (long cycle searches) are sampled fewer.
        if !contexts.is_empty() && t0.elapsed() >= PILOT_BUDGET {
            break;
        }
        contexts.push(MapContext::prepare(plan, m)?);
    }
    let prepare = t0.elapsed().as_secs_f64();
    let g = &plan.grid;
    let per_map = g.cells() as u64;
    let t1 = Instant::now();
    let mut cells = 0usize;
    'sample: for j in 0u64.. {
        for ctx in &contexts {
            // A spread sample: Fibonacci hashing of the sample number over the map's cells.
            let idx = (j.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 11) % per_map;
            let (row, col) = ((idx as usize) / g.x0.count, (idx as usize) % g.x0.count);
            let (x, v) = g.state(row, col);
            ctx.classify(squeal_core::State { x, v });
            cells += 1;
            if cells >= contexts.len() && t1.elapsed() >= PILOT_BUDGET {
                break 'sample;
            }
        }
        if cells >= PILOT_CELLS
            || t1.elapsed() >= PILOT_BUDGET
            || cells as u64 >= per_map * contexts.len() as u64
        {
            break 'sample;
        }
    }
    let cell_seconds = t1.elapsed().as_secs_f64() / cells.max(1) as f64;
    Ok(Estimate {
        maps: contexts.len(),
        cells,
        pilot_seconds: t0.elapsed().as_secs_f64(),
        prepare_seconds: prepare / contexts.len().max(1) as f64,
        cell_seconds: cell_seconds
            + audit_seconds(plan, &contexts[0]) / plan.audit_every.max(1) as f64,
    })
}

/// Mean seconds of one audited cell (a run to settlement without the trap; 0 without an
/// audit), timed on [`AUDIT_SAMPLES`] spread cells of the first map: about one cell in
/// `audit_every` costs this much more. Audited cells are too rare for the pilot's sample to
/// meet them, and each can cost as much as thousands of early-stopped cells (a start near the
/// unstable cycle runs long before it settles).
fn audit_seconds(plan: &Plan, ctx: &MapContext) -> f64 {
    if ctx.classifier.trap.is_none() || plan.audit_every == 0 {
        return 0.0;
    }
    let settle = squeal_core::Classifier {
        trap: None,
        ..ctx.classifier
    };
    let g = &plan.grid;
    let t = Instant::now();
    for j in 1..=AUDIT_SAMPLES {
        let idx = (j.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 11) % g.cells() as u64;
        let (x, v) = g.state(idx as usize / g.x0.count, idx as usize % g.x0.count);
        settle.classify(&ctx.stepper, squeal_core::State { x, v });
    }
    t.elapsed().as_secs_f64() / AUDIT_SAMPLES as f64
}

/// Audited cells timed by the pilot.
pub const AUDIT_SAMPLES: u64 = 3;

/// At most this many atlas points are computed by an atlas's pilot (spread over the points).
pub const ATLAS_PILOT_POINTS: usize = 4;

/// An atlas's pilot: a few of its points computed as the atlas computes them (cold: no
/// neighbour's crossing, so a little slower than a line's warm-started points), and the scan
/// pilot of its basin maps, if it has any.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AtlasEstimate {
    /// Points computed by the pilot.
    pub points: usize,
    /// Mean seconds per point (one thread).
    pub point_seconds: f64,
    /// Seconds the pilot took (points and maps).
    pub pilot_seconds: f64,
    /// The pilot of the basin maps.
    pub maps: Option<Estimate>,
}

impl AtlasEstimate {
    /// Wall seconds for the whole `plan` on `threads` threads (a lower bound: the writing of
    /// very large maps is not counted): its points; its boundary
    /// searches, each two bisections of `log2(ln(hi / lo) / rtol) + 2` evaluations that
    /// share their first ones, plus the dt/2 check of both brackets (4 evaluations at half
    /// the step, about twice the cost), every evaluation costed as one point; and its maps.
    pub fn seconds(&self, plan: &AtlasPlan, threads: usize) -> f64 {
        let evaluations = |j: usize| {
            let (_, [lo, hi]) = plan.boundary_setup(j);
            let steps = ((hi / lo).ln() / plan.boundary_rtol.max(1e-12))
                .log2()
                .ceil()
                .max(0.0);
            2.0 * (steps + 2.0) + 8.0
        };
        let boundaries: f64 = (0..plan.n_boundaries()).map(evaluations).sum();
        // A line's points run one after another (each warm-starts the next): one line is
        // never shared between threads.
        let line = plan.line_len() as f64 * self.point_seconds;
        let units = ((plan.n_points() as f64 + boundaries) * self.point_seconds
            / threads.max(1) as f64)
            .max(line);
        let maps = match (&self.maps, plan.map_plan()) {
            (Some(e), Some(mp)) => {
                e.seconds(mp.maps.len(), mp.grid.cells() * mp.maps.len(), threads)
            }
            _ => 0.0,
        };
        units + maps
    }
}

/// Runs an atlas's pilot (single-threaded): up to [`ATLAS_PILOT_POINTS`] spread points,
/// stopping early once [`PILOT_BUDGET`] is spent (at least one point), then the scan pilot
/// of its basin maps.
pub fn atlas_pilot(plan: &AtlasPlan) -> Result<AtlasEstimate, ScanError> {
    let t0 = Instant::now();
    let n = plan.n_points();
    let k = ATLAS_PILOT_POINTS.min(n).max(1);
    let mut points = 0usize;
    for j in 0..k {
        let i = if k == 1 { 0 } else { j * (n - 1) / (k - 1) };
        crate::atlas::driver::compute_at(plan, i, None);
        points += 1;
        if t0.elapsed() >= PILOT_BUDGET {
            break;
        }
    }
    let point_seconds = t0.elapsed().as_secs_f64() / points as f64;
    let maps = plan.map_plan().map(|mp| pilot(&mp)).transpose()?;
    Ok(AtlasEstimate {
        points,
        point_seconds,
        pilot_seconds: t0.elapsed().as_secs_f64(),
        maps,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_estimate_scales_with_cells_and_threads() {
        let e = Estimate {
            maps: 1,
            cells: 10,
            pilot_seconds: 0.1,
            prepare_seconds: 0.5,
            cell_seconds: 1e-3,
        };
        // 4 maps prepared one at a time, 8000 cells over 2 threads.
        assert!((e.seconds(4, 8000, 2) - (2.0 + 4.0)).abs() < 1e-12);
    }

    #[test]
    fn the_pilot_samples_every_prepared_map() {
        let plan = Plan::from_toml(
            r#"version = 1
[model]
law = "mcmillan"
nu = { from = 1e-3, to = 2e-2, count = 12 }
[grid]
x0 = { min = -3.0, max = 5.0, count = 8 }
v0 = { min = -4.0, max = 4.0, count = 8 }
[output]
path = "t.h5"
"#,
            "t.toml",
        )
        .unwrap();
        let e = pilot(&plan).unwrap();
        // At most PILOT_MAPS maps (fewer when preparing them outlasts the budget).
        assert!((1..=PILOT_MAPS).contains(&e.maps), "{e:?}");
        assert!(e.cells >= e.maps, "{e:?}");
        assert!(e.cell_seconds > 0.0 && e.prepare_seconds > 0.0);
    }
}
