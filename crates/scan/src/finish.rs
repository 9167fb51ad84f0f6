//! A scan's finish: the stored blocks read back once (and made ready to be written, as
//! compressed chunks) and tallied into their map's checks and basin stability
//! ([`MapTally`]) on the worker threads, each then written into the file, and the per-map
//! figures handed to the writer. The writer (the store's, a
//! shard merge's) only reads and writes ([`Finishing`]); what the cells add up to is computed
//! here.

use rayon::prelude::*;
use squeal_core::Landscape;

use crate::basin::GridShares;
use crate::cell::Cell;
use crate::census::Rules;
use crate::checks::{MapChecks, MapTally};
use crate::sensitivity::Sensitivity;
use crate::spec::Plan;
use crate::ulc::CycleReport;

/// What one map's cells add up to, as the file stores it per map.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapFigures {
    /// The consistency checks.
    pub checks: MapChecks,
    /// The basin stability.
    pub shares: GridShares,
    /// Steady slip's own stability (the law linearised at the fixed point).
    pub steady: squeal_core::SteadySlip,
    /// The final-state sensitivity: the basin entropy of the labels and the measures of
    /// extra runs ([`crate::sensitivity`]).
    pub sensitivity: Sensitivity,
}

/// Steady slip's stability as stored per map: the verdict's name and long name (an enum of
/// [`squeal_core::Stability`]), and the growth rate's.
pub const STEADY_SLIP: (&str, &str) = (
    "steady_slip_stability",
    "steady slip's own stability from the law linearised at the fixed point: attracts, repels \
     (no start near it settles), attracts_a_sector (only starts in one sector near it close on \
     it), marginal (the linear terms decide nothing)",
);

/// The stored growth rate of small motions about steady slip: name, long name.
pub const STEADY_SLIP_GROWTH: (&str, &str) = (
    "steady_slip_growth",
    "growth rate of small motions about steady slip per time unit 1/omega_n (negative: they \
     decay; NaN: McMillan's law with k > 1, where runs near it jump)",
);

/// A file being finished from stored blocks: the writer's side of [`finish`]. Reading a
/// block and writing one may run at the same time on different threads (the next blocks are
/// read while the last ones are written); writes come from one thread at a time.
pub trait Finishing: Sync {
    /// What reading or writing fails with.
    type Error: Send;
    /// A block read back and made ready to be written: its cells, and what the writer
    /// prepares from them on the reading thread (as compressed chunks).
    type Block: AsRef<[Cell]> + Send;
    /// The plan the blocks belong to.
    fn plan(&self) -> &Plan;
    /// The located cycle of `map`, as stored (none: not searched, or none found).
    fn cycle(&self, map: usize) -> Option<&CycleReport>;
    /// The rule groups withdrawn from `map`.
    fn withdrawn(&self, map: usize) -> Vec<Rules>;
    /// The landscape stated for `map` (laws with true stick), if any.
    fn landscape(&self, map: usize) -> Option<Landscape>;
    /// Block `block` of `map` as stored, made ready to be written (`None`: not stored, as
    /// another shard's).
    fn read_block(&self, map: usize, block: usize) -> Result<Option<Self::Block>, Self::Error>;
    /// Writes a block read back into the file.
    fn write_block(&self, block: Self::Block) -> Result<(), Self::Error>;
    /// Writes every map's figures (in map order) and completes the file.
    fn complete(self, figures: &[MapFigures]) -> Result<(), Self::Error>
    where
        Self: Sized;
}

/// The cells of the blocks a finish reads at once, at least (a few tens of MB of cells in
/// memory, twice: one window read while the one before is written).
pub const WINDOW_CELLS: usize = 1 << 18;

/// Finishes the file of `f`: every stored block read back once and written, tallied on the
/// worker threads of the current rayon pool (the next window of blocks read and tallied
/// while the last is written, in block order), then the figures written. Returns each map's
/// checks. The figures are sums over cells: they do not depend on the threads.
pub fn finish<F: Finishing>(f: F) -> Result<Vec<MapChecks>, F::Error> {
    finish_by(f, WINDOW_CELLS)
}

/// [`finish`] reading at least `window_cells` cells at a time.
fn finish_by<F: Finishing>(f: F, window_cells: usize) -> Result<Vec<MapChecks>, F::Error> {
    let figures = tally_and_write(&f, window_cells)?;
    f.complete(&figures)?;
    Ok(figures.iter().map(|m| m.checks).collect())
}

fn tally_and_write<F: Finishing>(f: &F, window_cells: usize) -> Result<Vec<MapFigures>, F::Error> {
    let plan = f.plan();
    let tallies: Vec<MapTally> = (0..plan.maps.len())
        .map(|m| {
            let mut t = MapTally::new(plan, f.cycle(m), f.landscape(m));
            t.withdrawn(&f.withdrawn(m));
            t
        })
        .collect();
    let nb = plan.map.grid.blocks();
    let ids: Vec<(usize, usize)> = (0..plan.maps.len())
        .flat_map(|m| (0..nb).map(move |b| (m, b)))
        .collect();
    // At least two blocks per thread in memory at once, read while the previous window is
    // written: each window ends with the threads waiting for its slowest block, so small
    // blocks are taken up to `window_cells` at a time (a 4096 x 4096 map's finish with two
    // blocks per thread left each of 2 threads idle 10-15% of it: perf).
    let g = &plan.map.grid;
    let block_cells = (g.block_rows * g.x0.count).max(1);
    let window = (2 * rayon::current_num_threads().max(1)).max(window_cells / block_cells);
    let read = |ids: &[(usize, usize)]| -> Result<Vec<F::Block>, F::Error> {
        let got: Vec<Option<F::Block>> = ids
            .par_iter()
            .map(|&(m, b)| {
                let Some(block) = f.read_block(m, b)? else {
                    return Ok(None);
                };
                tallies[m].add_block(plan, b, block.as_ref());
                Ok(Some(block))
            })
            .collect::<Result<_, F::Error>>()?;
        Ok(got.into_iter().flatten().collect())
    };
    let write = |blocks: Vec<F::Block>| -> Result<(), F::Error> {
        blocks.into_iter().try_for_each(|b| f.write_block(b))
    };
    let mut windows = ids.chunks(window);
    let mut last = match windows.next() {
        Some(w) => read(w)?,
        None => Vec::new(),
    };
    for w in windows {
        let (written, next) = rayon::join(|| write(last), || read(w));
        written?;
        last = next?;
    }
    write(last)?;
    // Each map's figures, the maps side by side: the sensitivity's extra runs (its maps at
    // dt and dt / 2 prepared, each a mostly serial section search) fill the threads across
    // maps (bSTAB's 20 maps: 0.7 s one map after the other).
    Ok(tallies
        .into_par_iter()
        .enumerate()
        .map(|(m, t)| {
            let (checks, shares, labels) = t.finish(plan);
            let steady = squeal_core::SteadySlip::of(&plan.maps[m]);
            let sensitivity = Sensitivity::of_map(plan, m, Some(&f.withdrawn(m)), &labels);
            MapFigures {
                checks,
                shares,
                steady,
                sensitivity,
            }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use std::sync::Mutex;

    use super::*;
    use crate::cell::Audit;
    use crate::curve::ClosedCurve;

    /// Stored blocks in memory; the blocks written and the figures handed over are kept.
    struct Memory<'a> {
        plan: &'a Plan,
        cycle: CycleReport,
        written: Mutex<Vec<(usize, usize)>>,
        figures: Mutex<Vec<MapFigures>>,
    }

    struct Block(usize, usize, Vec<Cell>);

    impl AsRef<[Cell]> for Block {
        fn as_ref(&self) -> &[Cell] {
            &self.2
        }
    }

    impl Finishing for &Memory<'_> {
        type Error = String;
        type Block = Block;
        fn plan(&self) -> &Plan {
            self.plan
        }
        fn cycle(&self, map: usize) -> Option<&CycleReport> {
            (map == 0).then_some(&self.cycle)
        }
        fn withdrawn(&self, _: usize) -> Vec<Rules> {
            Vec::new()
        }
        fn landscape(&self, map: usize) -> Option<Landscape> {
            (map == 1).then_some(Landscape::StickSlipOnly)
        }
        fn read_block(&self, map: usize, block: usize) -> Result<Option<Block>, String> {
            Ok(Some(Block(map, block, cells(self.plan, map, block))))
        }
        fn write_block(&self, b: Block) -> Result<(), String> {
            self.written.lock().unwrap().push((b.0, b.1));
            Ok(())
        }
        fn complete(self, figures: &[MapFigures]) -> Result<(), String> {
            *self.figures.lock().unwrap() = figures.to_vec();
            Ok(())
        }
    }

    /// Cells that exercise every count: labels by distance from (1, 0) (some on the wrong
    /// side of the circle of radius 2 around it), audits, reasons and `t_squeal` varying.
    fn cells(plan: &Plan, map: usize, block: usize) -> Vec<Cell> {
        let g = &plan.map.grid;
        let rows = g.block_rows(block);
        let nx = g.x0.count;
        (0..rows.len() * nx)
            .map(|k| {
                let (x, v) = g.state(rows.start + k / nx, k % nx);
                let r = (x - 1.0).hypot(v);
                let i = map * 7 + block * 3 + k;
                let mut c = Cell::fill();
                c.regime = match (r < 2.0) ^ (i % 11 == 0) {
                    _ if i % 13 == 0 => 0,
                    true => 1,
                    false => 2,
                };
                c.reason = (i % 21) as u8;
                c.audit = [
                    Audit::NotAudited,
                    Audit::Agrees,
                    Audit::Disagrees,
                    Audit::Undecided,
                ][i % 4] as u8;
                c.t_squeal = [0.0, 1.5, f64::INFINITY][i % 3];
                c
            })
            .collect()
    }

    /// A located cycle of the first map: a circle of radius 2 around (1, 0), 64 points.
    fn circle_cycle(plan: &Plan) -> CycleReport {
        let n = 64;
        let (xs, vs) = (0..n)
            .map(|i| {
                let a = i as f64 / n as f64 * std::f64::consts::TAU;
                (1.0 + 2.0 * a.cos(), 2.0 * a.sin())
            })
            .unzip();
        CycleReport {
            params: plan.maps[0],
            dt: 0.01,
            r_section: 2.0,
            bracket: [1.999, 2.001],
            period: 6.5,
            omega: 1.0,
            x_range: [-1.0, 3.0],
            v_range: [-2.0, 2.0],
            distance_plus_x: 2.0,
            area: 12.5,
            multiplier: 1.3,
            encloses_origin: true,
            half_dt: None,
            returns: 120,
            solver: Default::default(),
            stable_above: None,
            escape: None,
            curve: ClosedCurve::new(xs, vs),
        }
    }

    /// The figures do not depend on the threads that tally them: the same under pools of
    /// 1, 2 and 3 threads, and the same as one `MapChecks` fed every block in order on one
    /// thread (the tally before blocks were tallied apart and summed). Every block is
    /// written once.
    #[test]
    fn figures_do_not_depend_on_the_threads() {
        let mut plan = Plan::from_toml(
            "version = 1\n[model]\nlaw = \"mcmillan\"\nnu = [1e-3, 2e-3]\n[grid]\n\
             x0 = { min = -3.0, max = 5.0, count = 13 }\nv0 = { min = -4.0, max = 4.0, count = 11 }\n\
             [output]\npath = \"t.h5\"\n",
            "t.toml",
        )
        .unwrap();
        plan.map.grid.block_rows = 1;
        let cycle = circle_cycle(&plan);
        let want: Vec<MapFigures> = (0..2)
            .map(|m| {
                let curve = (m == 0).then_some(&cycle.curve);
                let landscape = (m == 1).then_some(Landscape::StickSlipOnly);
                let mut checks = MapChecks::new(curve, landscape, false);
                let mut labels = Vec::new();
                for b in 0..plan.map.grid.blocks() {
                    let c = cells(&plan, m, b);
                    checks.add_block(&plan, curve, b, &c);
                    labels.extend(c.iter().map(|c| c.regime));
                }
                let shares = GridShares::of(&labels, plan.map.grid.x0.count);
                let steady = squeal_core::SteadySlip::of(&plan.maps[m]);
                let sensitivity = Sensitivity::of_map(&plan, m, Some(&[]), &labels);
                MapFigures {
                    checks,
                    shares,
                    steady,
                    sensitivity,
                }
            })
            .collect();
        assert!(want[0].checks.wrong_side.is_some_and(|w| w.cells > 0));
        assert!(
            want[1]
                .checks
                .landscape
                .is_some_and(|l| l.contradictions > 0)
        );
        assert!(want[0].checks.origin.is_some());
        // Two blocks per thread at a time, and every block at once (the default window
        // holds more cells than this grid).
        for (threads, window_cells) in [1, 2, 3]
            .into_iter()
            .flat_map(|t| [(t, 0), (t, WINDOW_CELLS)])
        {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mem = Memory {
                plan: &plan,
                cycle: cycle.clone(),
                written: Mutex::new(Vec::new()),
                figures: Mutex::new(Vec::new()),
            };
            let checks = pool.install(|| {
                assert_eq!(rayon::current_num_threads(), threads);
                finish_by(&mem, window_cells).unwrap()
            });
            let figures = mem.figures.into_inner().unwrap();
            // Compared as printed: a figure not measured is NaN on both sides.
            assert_eq!(
                format!("{figures:?}"),
                format!("{want:?}"),
                "{threads} thread(s), window {window_cells}"
            );
            assert_eq!(checks, vec![want[0].checks, want[1].checks]);
            let mut written = mem.written.into_inner().unwrap();
            written.sort();
            let all: Vec<_> = (0..2)
                .flat_map(|m| (0..plan.map.grid.blocks()).map(move |b| (m, b)))
                .collect();
            assert_eq!(written, all, "{threads} thread(s), window {window_cells}");
        }
    }
}
