//! The atlas run: every unit an [`AtlasWriter`] is missing, then the missing blocks of the
//! atlas's basin maps, journalled as they finish. `squeal atlas` and the Python package
//! both call [`run_atlas`]; they add the progress display, the signals and the report. It
//! lives above the store, which persists what it is handed and computes nothing.

use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

use squeal_scan::atlas::{AtlasPlan, driver};
use squeal_scan::{DriveError, Observer, ScanError, Shard, Shared};

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
/// and the blocks of the basin maps (reported to `observer`), side by side on the one
/// thread pool, so that the maps fill the cores the last long units leave idle (a map
/// needs nothing from the units: it locates its own cycle). Each run journals through the
/// shared writer ([`squeal_scan::Shared`]). Stops early when `stop` becomes true (the
/// units and blocks in flight are journalled first; a failure of either raises it).
/// Returns the writer and the number of units and map blocks still missing: 0 means
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
    let shared = Mutex::new(writer);
    let map_plan = plan.map_plan();
    let (units, maps) = std::thread::scope(|scope| {
        // The maps' driver on a thread of its own (its sink, the journal, stays off the
        // workers, as the units' does on this one).
        let maps = scope.spawn(|| match &map_plan {
            Some(mp) if !stop.load(Ordering::SeqCst) => {
                let mut sink = Shared(&shared);
                let done = squeal_scan::drive(mp, shard, &mut sink, observer, stop);
                if done.is_err() {
                    stop.store(true, Ordering::SeqCst);
                }
                done.map(|_| ())
            }
            _ => Ok(()),
        });
        let units = driver::run(plan, &todo, stop, |r| -> Result<(), AtlasRunError> {
            // The store's error with its sources: the OS's reason ("No space left on
            // device") is one, and the CLI prints the chain.
            shared.lock().unwrap_or_else(|e| e.into_inner()).record(r)?;
            on_unit();
            Ok(())
        });
        let maps = maps
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        (units, maps)
    });
    units?;
    maps?;
    let writer = shared.into_inner().unwrap_or_else(|e| e.into_inner());
    let left = writer.missing().len() + writer.missing_blocks().len();
    Ok((writer, left))
}
