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
    let write =
        |blocks: Vec<F::Block>| -> Result<(), F::Error> { blocks.into_iter().try_for_each(|b| f.write_block(b)) };
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
