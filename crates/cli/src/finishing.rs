//! The end of a run, the same for the command line and the Python package: the engine
//! computes what the stored results add up to (a scan's landscapes, per-map checks and
//! basin stability; an atlas's reconciled folds and map figures) and hands it to the
//! store's writer, which only persists it.

use std::path::{Path, PathBuf};

use squeal_scan::atlas::AtlasResults;
use squeal_scan::{MapChecks, Plan, ScanError};
use squeal_store::atlas::AtlasWriter;
use squeal_store::{Provenance, ScanWriter, StoreError};

/// Why a scan's file could not be finished.
#[derive(Debug, thiserror::Error)]
pub enum FinishError {
    /// A map's landscape could not be computed.
    #[error(transparent)]
    Scan(#[from] ScanError),
    /// The file could not be written.
    #[error(transparent)]
    Store(#[from] StoreError),
}

/// Writes the file of a scan whose blocks are all stored: each map's landscape (laws with
/// true stick) computed, the blocks read back once and tallied on the worker threads
/// ([`squeal_scan::finish::finish`]). Returns each map's checks.
pub fn finish_scan(writer: ScanWriter) -> Result<Vec<MapChecks>, FinishError> {
    let landscapes = squeal_scan::landscape::of_plan(writer.plan())?;
    Ok(squeal_scan::finish::finish(writer.finishing(&landscapes)?)?)
}

/// Joins the shard files of a scan into `out` as [`finish_scan`] writes a scan's file;
/// returns the merged file's plan.
pub fn merge_scan(shards: &[PathBuf], out: &Path, force: bool) -> Result<Plan, StoreError> {
    let file = squeal_store::merging(shards, out, force)?;
    let plan = squeal_scan::Finishing::plan(&file).clone();
    squeal_scan::finish::finish(file)?;
    Ok(plan)
}

/// Writes the file of an atlas whose units and map blocks are all stored: the folds
/// reconciled and each point's map figures computed ([`squeal_scan::atlas::finish`]).
pub fn finish_atlas(mut writer: AtlasWriter) -> Result<AtlasResults, StoreError> {
    let plan = writer.plan().clone();
    let maps = squeal_scan::atlas::finish(&plan, &mut writer.results);
    writer.finish(&maps)
}

/// Joins the shard files of an atlas into `out` as [`finish_atlas`] writes an atlas's file.
pub fn merge_atlas(
    shards: &[PathBuf],
    out: &Path,
    force: bool,
    prov: &Provenance,
) -> Result<(), StoreError> {
    let mut m = squeal_store::atlas::merging_atlas(shards, out, force)?;
    let maps = squeal_scan::atlas::finish(&m.plan, &mut m.results);
    m.finish(&maps, prov)
}
