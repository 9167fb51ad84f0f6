//! Output files that `trajectory` and `friction` write beside the store's: refused if
//! present without `--force` (checked before any computing, and again atomically when
//! created), and the samples of a run as CSV.

use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Write};
use std::path::Path;

use anyhow::bail;
use squeal_core::{Samples, Scales};

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

/// The samples `cols` to `path` as CSV, synced to disk: the `notes` and each column's units
/// as `#` lines, then the header `t,x,v,a,force` (the model's units) and, for a physical
/// system (`scales`), `t_si,x_si,v_si` beside them in s, m and m/s: the columns of the
/// trajectory's `.h5` under the same names. Read it with `pandas.read_csv(path,
/// comment="#")` or `numpy.loadtxt(path, delimiter=",", skiprows=N)`.
pub fn write_csv(
    path: &Path,
    cols: &Samples,
    force: bool,
    (notes, scales): (&[String], Option<&Scales>),
) -> anyhow::Result<()> {
    let mut w = BufWriter::new(create_file(path, force)?);
    for n in notes {
        writeln!(w, "# {n}")?;
    }
    let model = "t, x, v, a, force in the model's units (nondimensional: time in 1/omega_0, \
                 natural period 2 pi)";
    match scales {
        Some(_) => writeln!(w, "# units: {model}; t_si in s, x_si in m, v_si in m/s")?,
        None => writeln!(w, "# units: {model}")?,
    }
    match scales {
        Some(_) => writeln!(w, "t,x,v,a,force,t_si,x_si,v_si")?,
        None => writeln!(w, "t,x,v,a,force")?,
    }
    for i in 0..cols.len() {
        write!(
            w,
            "{},{},{},{},{}",
            cols.t[i], cols.x[i], cols.v[i], cols.a[i], cols.force[i]
        )?;
        if let Some(s) = scales {
            write!(
                w,
                ",{},{},{}",
                cols.t[i] * s.time,
                cols.x[i] * s.length,
                cols.v[i] * s.velocity
            )?;
        }
        writeln!(w)?;
    }
    w.into_inner().map_err(|e| e.into_error())?.sync_all()?;
    Ok(())
}
