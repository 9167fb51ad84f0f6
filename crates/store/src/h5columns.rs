//! One per-cell column of [`squeal_scan::cell::COLUMNS`] in a file: its dataset with CF
//! attributes, and the writing and selecting of a block's rows (grids over `(.., v0, x0)`,
//! random samples over `(.., sample)`); and the typed read of a column of any table
//! ([`read_nums`]).

use hdf5::{Dataset, File, H5Type};
use ndarray::{Array1, Array2, IxDyn};
use squeal_scan::cell::{Cell, Column};
use squeal_scan::column::{Kind, Num};

use crate::h5out::str_attr;
use crate::h5types::{AuditH5, EnumColumn, Label, ReasonH5, YesNoH5};

/// An empty chunked, compressed dataset of a column, filled with `fill` until written.
fn chunked<T: H5Type>(
    file: &File,
    name: &str,
    shape: &[usize],
    chunk: &[usize],
    fill: T,
) -> hdf5::Result<Dataset> {
    file.new_dataset_builder()
        .obj_track_times(false)
        .empty::<T>()
        .shape(shape)
        .chunk(chunk)
        .deflate(4)
        .fill_value(fill)
        .create(name)
}

/// Creates the dataset of one column of [`COLUMNS`] with its CF attributes (also the atlas's
/// maps, with the parameter dimensions in front).
pub(crate) fn column_dataset(
    file: &File,
    col: &Column,
    name: &str,
    shape: &[usize],
    chunk: &[usize],
) -> hdf5::Result<Dataset> {
    let (f, n) = (col.fill, name);
    let bad = || hdf5::Error::from(format!("{n}: fill value is not a member"));
    let ds = match (EnumColumn::of(col), col.kind) {
        (Some(EnumColumn::Label), _) => chunked(
            file,
            n,
            shape,
            chunk,
            Label::from_u8(f.as_u64() as u8).ok_or_else(bad)?,
        )?,
        (Some(EnumColumn::Reason), _) => chunked(
            file,
            n,
            shape,
            chunk,
            ReasonH5::from_u8(f.as_u64() as u8).ok_or_else(bad)?,
        )?,
        (Some(EnumColumn::Audit), _) => chunked(
            file,
            n,
            shape,
            chunk,
            AuditH5::from_u8(f.as_u64() as u8).ok_or_else(bad)?,
        )?,
        (Some(EnumColumn::YesNo), _) => chunked(
            file,
            n,
            shape,
            chunk,
            YesNoH5::from_u8(f.as_u64() as u8).ok_or_else(bad)?,
        )?,
        (None, Kind::U8 | Kind::Enum) => chunked(file, n, shape, chunk, f.as_u64() as u8)?,
        (None, Kind::U32) => chunked(file, n, shape, chunk, f.as_u64() as u32)?,
        (None, Kind::U64) => chunked(file, n, shape, chunk, f.as_u64())?,
        (None, Kind::F64) => chunked(file, n, shape, chunk, f.as_f64())?,
    };
    str_attr(&ds, "long_name", col.long_name)?;
    if !col.units.is_empty() {
        str_attr(&ds, "units", col.units)?;
    }
    if col.kind == Kind::Enum {
        let values: Vec<u8> = col.flags.iter().map(|(v, _)| *v).collect();
        ds.new_attr::<u8>()
            .shape(values.len())
            .create("flag_values")?
            .write_raw(&values)?;
        let names: Vec<&str> = col.flags.iter().map(|(_, n)| *n).collect();
        str_attr(&ds, "flag_meanings", &names.join(" "))?;
    }
    Ok(ds)
}

/// Creates the SI twin `<name>_si` of a column with an SI notion ([`Column::si_twin`]): f64,
/// fill NaN, its own long name and SI units (a physical scan's cells).
pub(crate) fn si_dataset(
    file: &File,
    col: &Column,
    shape: &[usize],
    chunk: &[usize],
) -> hdf5::Result<Option<Dataset>> {
    let Some((si, long)) = col.si_twin() else {
        return Ok(None);
    };
    let ds = chunked(file, &format!("{}_si", col.name), shape, chunk, f64::NAN)?;
    str_attr(&ds, "long_name", &long)?;
    str_attr(&ds, "units", si.units())?;
    Ok(Some(ds))
}

/// Writes the SI twin of one column ([`si_dataset`]) of a block's cells, by the scales `s`,
/// as [`write_column`] writes the column.
pub(crate) fn write_si_column(
    ds: &Dataset,
    col: &Column,
    (cells, s): (&[Cell], &squeal_core::Scales),
    prefix: &[usize],
    rows: std::ops::Range<usize>,
    nx: usize,
) -> hdf5::Result<()> {
    let v = cells.iter().map(|c| col.si_value(c, s)).collect();
    write_rows(ds, v, prefix, rows, nx)
}

/// Writes one column of a block's cells at `prefix` (the indices of the leading dimensions:
/// none for one map, the map of a sweep, an atlas point's indices).
pub(crate) fn write_column(
    ds: &Dataset,
    col: &Column,
    cells: &[Cell],
    prefix: &[usize],
    rows: std::ops::Range<usize>,
    nx: usize,
) -> hdf5::Result<()> {
    let u = || cells.iter().map(|c| (col.get)(c).as_u64());
    fn enum_of<T>(col: &Column, cells: &[Cell], f: fn(u8) -> Option<T>) -> hdf5::Result<Vec<T>> {
        cells
            .iter()
            .map(|c| {
                let v = (col.get)(c).as_u64();
                f(v as u8)
                    .filter(|_| v <= u8::MAX as u64)
                    .ok_or_else(|| hdf5::Error::from(format!("{}: unknown value {v}", col.name)))
            })
            .collect()
    }
    match (EnumColumn::of(col), col.kind) {
        (Some(EnumColumn::Label), _) => {
            write_rows(ds, enum_of(col, cells, Label::from_u8)?, prefix, rows, nx)
        }
        (Some(EnumColumn::Reason), _) => write_rows(
            ds,
            enum_of(col, cells, ReasonH5::from_u8)?,
            prefix,
            rows,
            nx,
        ),
        (Some(EnumColumn::Audit), _) => {
            write_rows(ds, enum_of(col, cells, AuditH5::from_u8)?, prefix, rows, nx)
        }
        (Some(EnumColumn::YesNo), _) => {
            write_rows(ds, enum_of(col, cells, YesNoH5::from_u8)?, prefix, rows, nx)
        }
        (None, Kind::U8 | Kind::Enum) => {
            write_rows(ds, u().map(|v| v as u8).collect(), prefix, rows, nx)
        }
        (None, Kind::U32) => write_rows(ds, u().map(|v| v as u32).collect(), prefix, rows, nx),
        (None, Kind::U64) => write_rows(ds, u().collect(), prefix, rows, nx),
        (None, Kind::F64) => write_rows(
            ds,
            cells.iter().map(|c| (col.get)(c).as_f64()).collect(),
            prefix,
            rows,
            nx,
        ),
    }
}

/// Whether a value is a member of an enum column's stored type, for the columns whose type
/// is an enum (`None`: any value is stored as is), as the typed write of [`write_column`]
/// tells them.
pub(crate) fn membership(col: &Column) -> Option<fn(u8) -> bool> {
    Some(match EnumColumn::of(col)? {
        EnumColumn::Label => |b| Label::from_u8(b).is_some(),
        EnumColumn::Reason => |b| ReasonH5::from_u8(b).is_some(),
        EnumColumn::Audit => |b| AuditH5::from_u8(b).is_some(),
        EnumColumn::YesNo => |b| YesNoH5::from_u8(b).is_some(),
    })
}

/// The rows `rows` after the leading indices `prefix` (a sweep's map, an atlas point's
/// parameter indices; none for a single map): a hyperslab over `(.., v0, x0)`, or over
/// `(.., sample)` for a `list` (random samples).
pub(crate) fn sel(prefix: &[usize], rows: std::ops::Range<usize>, list: bool) -> hdf5::Hyperslab {
    let mut v: Vec<hdf5::SliceOrIndex> = prefix.iter().map(|&i| i.into()).collect();
    v.push(rows.into());
    if !list {
        v.push((..).into());
    }
    hdf5::Hyperslab::from(v)
}

/// Whether `ds` is a list over random samples: after its `leading` indices (sweep or
/// parameter dimensions) one dimension, where a grid variable has two.
pub(crate) fn is_list(ds: &Dataset, leading: usize) -> bool {
    ds.ndim() == leading + 1
}

/// The values of a column of any table stored as `kind` in `ds` (at `sel`; all of it where
/// `None`), read as its stored type, in C order.
pub(crate) fn read_nums(
    ds: &Dataset,
    kind: Kind,
    sel: Option<hdf5::Hyperslab>,
) -> hdf5::Result<Vec<Num>> {
    fn rd<T: H5Type + Clone>(ds: &Dataset, sel: Option<hdf5::Hyperslab>) -> hdf5::Result<Vec<T>> {
        match sel {
            None => ds.read_raw(),
            Some(s) => Ok(ds.read_slice::<T, _, IxDyn>(s)?.into_iter().collect()),
        }
    }
    let u = |v: Vec<u64>| v.into_iter().map(Num::U).collect();
    Ok(match kind {
        Kind::Enum | Kind::U8 => u(rd::<u8>(ds, sel)?.into_iter().map(u64::from).collect()),
        Kind::U32 => u(rd::<u32>(ds, sel)?.into_iter().map(u64::from).collect()),
        Kind::U64 => u(rd::<u64>(ds, sel)?),
        Kind::F64 => rd::<f64>(ds, sel)?.into_iter().map(Num::F).collect(),
    })
}

fn write_rows<T: H5Type>(
    ds: &Dataset,
    data: Vec<T>,
    prefix: &[usize],
    rows: std::ops::Range<usize>,
    nx: usize,
) -> hdf5::Result<()> {
    if is_list(ds, prefix.len()) {
        return ds.write_slice(&Array1::from(data), sel(prefix, rows, true));
    }
    let a = Array2::from_shape_vec((rows.len(), nx), data)
        .map_err(|e| hdf5::Error::from(e.to_string()))?;
    ds.write_slice(&a, sel(prefix, rows, false))
}
