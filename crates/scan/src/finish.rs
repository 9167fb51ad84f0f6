//! A scan's finish: the stored blocks read back once, each written into the file as it comes
//! and tallied into its map's checks and basin stability ([`MapTally`]) on the worker
//! threads, and the per-map figures then handed to the writer. The writer (the store's, a
//! shard merge's) only reads and writes ([`Finishing`]); what the cells add up to is computed
//! here.

use rayon::prelude::*;
use squeal_core::Landscape;

use crate::basin::GridShares;
use crate::cell::Cell;
use crate::census::Rules;
use crate::checks::{MapChecks, MapTally};
use crate::spec::Plan;
use crate::ulc::CycleReport;

/// What one map's cells add up to, as the file stores it per map.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapFigures {
    /// The consistency checks.
    pub checks: MapChecks,
    /// The basin stability.
    pub shares: GridShares,
}

/// A file being finished from stored blocks: the writer's side of [`finish`]. Reading a
/// block and writing one may run at the same time on different threads (the next blocks are
/// read while the last ones are written); writes come from one thread at a time.
pub trait Finishing: Sync {
    /// What reading or writing fails with.
    type Error: Send;
    /// The plan the blocks belong to.
    fn plan(&self) -> &Plan;
    /// The located cycle of `map`, as stored (none: not searched, or none found).
    fn cycle(&self, map: usize) -> Option<&CycleReport>;
    /// The rule groups withdrawn from `map`.
    fn withdrawn(&self, map: usize) -> Vec<Rules>;
    /// The landscape stated for `map` (laws with true stick), if any.
    fn landscape(&self, map: usize) -> Option<Landscape>;
    /// Block `block` of `map` as stored (`None`: not stored, as another shard's).
    fn read_block(&self, map: usize, block: usize) -> Result<Option<Vec<Cell>>, Self::Error>;
    /// Writes a block read back into the file.
    fn write_block(&self, map: usize, block: usize, cells: &[Cell]) -> Result<(), Self::Error>;
    /// Writes every map's figures (in map order) and completes the file.
    fn complete(self, figures: &[MapFigures]) -> Result<(), Self::Error>
    where
        Self: Sized;
}

/// A block read back: its map, its number and its cells.
type Read = (usize, usize, Vec<Cell>);

/// Finishes the file of `f`: every stored block read back once and written, tallied on the
/// worker threads of the current rayon pool (the next window of blocks read and tallied
/// while the last is written, in block order), then the figures written. Returns each map's
/// checks. The figures are sums over cells: they do not depend on the threads.
pub fn finish<F: Finishing>(f: F) -> Result<Vec<MapChecks>, F::Error> {
    let figures = tally_and_write(&f)?;
    f.complete(&figures)?;
    Ok(figures.iter().map(|m| m.checks).collect())
}

fn tally_and_write<F: Finishing>(f: &F) -> Result<Vec<MapFigures>, F::Error> {
    let plan = f.plan();
    let tallies: Vec<MapTally> = (0..plan.maps.len())
        .map(|m| {
            let mut t = MapTally::new(plan, f.cycle(m), f.landscape(m));
            t.withdrawn(&f.withdrawn(m));
            t
        })
        .collect();
    let nb = plan.grid.blocks();
    let ids: Vec<(usize, usize)> = (0..plan.maps.len())
        .flat_map(|m| (0..nb).map(move |b| (m, b)))
        .collect();
    // Two blocks per thread in memory at once, read while the previous window is written.
    let window = 2 * rayon::current_num_threads().max(1);
    let read = |ids: &[(usize, usize)]| -> Result<Vec<Read>, F::Error> {
        let got: Vec<Option<Read>> = ids
            .par_iter()
            .map(|&(m, b)| {
                let Some(cells) = f.read_block(m, b)? else {
                    return Ok(None);
                };
                tallies[m].add_block(plan, b, &cells);
                Ok(Some((m, b, cells)))
            })
            .collect::<Result<_, F::Error>>()?;
        Ok(got.into_iter().flatten().collect())
    };
    let write = |blocks: Vec<Read>| -> Result<(), F::Error> {
        blocks
            .iter()
            .try_for_each(|(m, b, cells)| f.write_block(*m, *b, cells))
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
    Ok(tallies
        .into_iter()
        .map(|t| {
            let (checks, shares) = t.finish(plan);
            MapFigures { checks, shares }
        })
        .collect())
}
