//! A block's cell columns as whole HDF5 chunks, compressed on the thread that read the
//! block back and written by the single writer with HDF5's direct chunk write: the deflate
//! the datasets declare (`h5columns`: level 4, zlib format, HDF5's deflate filter) runs on
//! the workers, and the writer only copies bytes. Used where each block of rows is one
//! chunk (a grid whose blocks are no taller than the rows of a chunk); the last block's
//! chunk is padded with the column's fill value, which no reader sees (it lies past the
//! dataset's end). The values read back are those [`crate::h5columns::write_column`] writes.

use std::io::Write;

use hdf5::Dataset;
use squeal_scan::cell::{Cell, Column};
use squeal_scan::column::{Kind, Num};

use crate::h5columns::membership;

/// The chunk of one column of [`squeal_scan::cell::COLUMNS`] of a block's `cells` (`rows`
/// of `nx`), padded to `chunk_rows` rows: its values as the dataset stores them (native byte
/// order, the width of its kind), deflated. An enum value that is no member of its type is
/// refused, as the typed write refuses it.
pub(crate) fn column_chunk(
    col: &Column,
    cells: &[Cell],
    (chunk_rows, nx): (usize, usize),
) -> hdf5::Result<Vec<u8>> {
    let mut raw = Vec::with_capacity(chunk_rows * nx * width(col.kind));
    let member = membership(col);
    for c in cells {
        let v = (col.get)(c);
        if let Some(is) = member {
            let u = v.as_u64();
            if u > u8::MAX as u64 || !is(u as u8) {
                let why = format!("{}: unknown value {u}", col.name);
                return Err(hdf5::Error::from(why));
            }
        }
        put(&mut raw, col.kind, v);
    }
    for _ in cells.len()..chunk_rows * nx {
        put(&mut raw, col.kind, col.fill);
    }
    deflate(&raw)
}

/// The chunk of a column's SI twin (f64, fill NaN; `crate::h5columns::si_dataset`), as
/// [`column_chunk`].
pub(crate) fn si_chunk(
    col: &Column,
    (cells, s): (&[Cell], &squeal_core::Scales),
    (chunk_rows, nx): (usize, usize),
) -> hdf5::Result<Vec<u8>> {
    let mut raw = Vec::with_capacity(chunk_rows * nx * 8);
    for c in cells {
        raw.extend_from_slice(&col.si_value(c, s).to_ne_bytes());
    }
    for _ in cells.len()..chunk_rows * nx {
        raw.extend_from_slice(&f64::NAN.to_ne_bytes());
    }
    deflate(&raw)
}

/// Bytes per value of a kind, as stored.
fn width(kind: Kind) -> usize {
    match kind {
        Kind::Enum | Kind::U8 => 1,
        Kind::U32 => 4,
        Kind::U64 | Kind::F64 => 8,
    }
}

/// Appends `v` as a value of `kind` is stored (the casts of the typed write).
#[inline]
fn put(raw: &mut Vec<u8>, kind: Kind, v: Num) {
    match kind {
        Kind::Enum | Kind::U8 => raw.push(v.as_u64() as u8),
        Kind::U32 => raw.extend_from_slice(&(v.as_u64() as u32).to_ne_bytes()),
        Kind::U64 => raw.extend_from_slice(&v.as_u64().to_ne_bytes()),
        Kind::F64 => raw.extend_from_slice(&v.as_f64().to_ne_bytes()),
    }
}

/// `raw` compressed as HDF5's deflate filter at level 4 (a zlib stream).
fn deflate(raw: &[u8]) -> hdf5::Result<Vec<u8>> {
    let mut z = flate2::write::ZlibEncoder::new(
        Vec::with_capacity(raw.len() / 4 + 64),
        flate2::Compression::new(4),
    );
    z.write_all(raw)
        .and_then(|_| z.finish())
        .map_err(|e| hdf5::Error::from(format!("deflate: {e}")))
}

pub(crate) use ffi::write_chunk;

/// The one call into HDF5's C API that hdf5-metno 0.15 does not wrap.
#[allow(unsafe_code)]
mod ffi {
    use hdf5::Dataset;

    /// Writes `bytes`, one whole chunk already passed through every filter of `ds`, at the
    /// chunk that starts at `offset` (in elements, one per dimension of `ds`).
    pub(crate) fn write_chunk(ds: &Dataset, offset: &[u64], bytes: &[u8]) -> hdf5::Result<()> {
        if offset.len() != ds.ndim() {
            let why = format!(
                "a chunk offset of {} dimensions for {}",
                offset.len(),
                ds.ndim()
            );
            return Err(hdf5::Error::from(why));
        }
        let id = ds.id();
        let rc = hdf5::sync::sync(|| {
            // SAFETY: `id` names an open dataset (the borrowed `ds` holds it open for the
            // call); `offset` points at `ds.ndim()` values of hsize_t (u64, checked above),
            // as H5Dwrite_chunk reads one per dimension; `bytes` is `bytes.len()` readable
            // bytes, which HDF5 only reads during the call and does not keep; the filter
            // mask 0 says every filter of the dataset was applied (the deflate of
            // `column_chunk`, its only filter); and the library's global lock is held
            // (`hdf5::sync::sync`), as hdf5-metno holds it around each of its own calls, so
            // no other thread is inside HDF5.
            unsafe {
                hdf5_sys::h5d::H5Dwrite_chunk(
                    id,
                    hdf5_sys::h5p::H5P_DEFAULT,
                    0,
                    offset.as_ptr(),
                    bytes.len(),
                    bytes.as_ptr().cast(),
                )
            }
        });
        if rc < 0 {
            return Err(hdf5::Error::from(format!(
                "cannot write the chunk at {offset:?} of {}",
                ds.name()
            )));
        }
        Ok(())
    }
}

/// Whether `ds` is a chunked dataset whose only filter is deflate (what [`column_chunk`]
/// makes): checked before the first chunk is written directly.
pub(crate) fn takes_deflated_chunks(ds: &Dataset) -> bool {
    let filters = ds.filters();
    matches!(filters.as_slice(), [hdf5::filters::Filter::Deflate(4)]) && ds.chunk().is_some()
}
