//! The atlas run: every unit an [`AtlasWriter`] is missing, then the missing blocks of the
//! atlas's basin maps, journalled as they finish. `squeal atlas` and the Python package
//! both call [`run_atlas`]; they add the progress display, the signals and the report. It
//! lives above the store, which persists what it is handed and computes nothing.

use std::sync::atomic::{AtomicBool, Ordering};

use squeal_scan::atlas::{AtlasPlan, driver};
use squeal_scan::{DriveError, Observer, ScanError, Shard};

use squeal_store::StoreError;
use squeal_store::atlas::AtlasWriter;

/// Why an atlas run failed.
#[derive(Debug, thiserror::Error)]
pub enum AtlasRunError {
    /// A unit could not be computed.
    #[error(transparent)]
    Scan(#[from] ScanError),
    /// The journal refused a record.
    #[error(transparent)]
    Store(#[from] StoreError),
    /// The basin maps failed (the cause follows in the error's chain).
    #[error("basin maps")]
    Maps(#[from] DriveError<StoreError>),
}

/// Computes what `writer` is missing: the units (each handed to `on_unit` once journalled)
/// and then the blocks of the basin maps (reported to `observer`). Stops early when `stop`
/// becomes true (the units and blocks in flight are journalled first). Returns the writer
/// and the number of units and map blocks still missing: 0 means
/// [`AtlasWriter::finish`] can write the file; otherwise a resume continues.
pub fn run_atlas(
    plan: &AtlasPlan,
    shard: Option<Shard>,
    writer: AtlasWriter,
    stop: &AtomicBool,
    on_unit: &(dyn Fn() + Sync),
    observer: &dyn Observer,
) -> Result<(AtlasWriter, usize), AtlasRunError> {
    let todo = writer.missing();
    let mut writer = writer;
    // The sink runs on this thread: the journal's fsyncs stay off the workers.
    driver::run(plan, &todo, stop, |r| -> Result<(), AtlasRunError> {
        // The store's error with its sources: the OS's reason ("No space left on device")
        // is one, and the CLI prints the chain.
        writer.record(r)?;
        on_unit();
        Ok(())
    })?;
    if let Some(mp) = plan
        .map_plan()
        .as_ref()
        .filter(|_| !stop.load(Ordering::SeqCst))
    {
        squeal_scan::drive(mp, shard, &mut writer, observer, stop)?;
    }
    let left = writer.missing().len() + writer.missing_blocks().len();
    Ok((writer, left))
}
