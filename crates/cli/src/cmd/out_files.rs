//! Output files that `trajectory` and `friction` write beside the store's: refused if
//! present without `--force` (checked before any computing, and again atomically when
//! created), and the samples of a run as CSV.

use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Write};
use std::path::Path;

use anyhow::bail;
use squeal_core::Samples;

/// Refuses `path`, given to `flag`, where something other than a regular file is there
/// (the store's check, [`squeal_scan::files::refuse_non_regular`], in the flag's words):
/// a FIFO blocked the open for ever, and a device was read or written until killed.
pub fn regular(flag: &str, path: &Path) -> anyhow::Result<()> {
    squeal_scan::files::refuse_non_regular(path).map_err(|e| anyhow::anyhow!("{flag}: {e}"))
}

/// Refuses to overwrite `path` unless `force`, and anything but a regular file there even
/// with `force` ([`regular`]).
pub fn refuse_existing(flag: &str, path: &Path, force: bool) -> anyhow::Result<()> {
    regular(flag, path)?;
    if !force && path.exists() {
        bail!(
            "{flag}: '{}' exists (use --force to overwrite it)",
            path.display()
        );
    }
    Ok(())
}

/// Opens `path` for writing; without `force` it must not exist (checked atomically).
pub fn create_file(path: &Path, force: bool) -> std::io::Result<File> {
    let mut o = OpenOptions::new();
    o.write(true);
    if force {
        o.create(true).truncate(true);
    } else {
        o.create_new(true);
    }
    o.open(path)
}

/// The samples `cols` to `path` as CSV (header `t,x,v,a,force`), synced to disk.
pub fn write_csv(path: &Path, cols: &Samples, force: bool) -> anyhow::Result<()> {
    let mut w = BufWriter::new(create_file(path, force)?);
    writeln!(w, "t,x,v,a,force")?;
    for i in 0..cols.len() {
        writeln!(
            w,
            "{},{},{},{},{}",
            cols.t[i], cols.x[i], cols.v[i], cols.a[i], cols.force[i]
        )?;
    }
    w.into_inner().map_err(|e| e.into_error())?.sync_all()?;
    Ok(())
}
