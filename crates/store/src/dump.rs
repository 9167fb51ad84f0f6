//! A squeal file read whole for a page that shows it (`squeal report`): its kind, every
//! root attribute, and every dataset a reader looks at, as plain typed arrays with their
//! attributes. Nothing here knows what a page draws; it reads what the file holds and
//! thins it where the file is larger than a page can carry:
//!
//! * a basin map (the last two dimensions `(v0, x0)`, or an atlas's `map_*` columns) wider
//!   or taller than [`MAX_MAP_SIDE`] cells is read every `stride`-th row and column, the
//!   grid's coordinates likewise ([`Dump::map_stride`]);
//! * a trajectory longer than [`MAX_SAMPLES`] samples is read every `stride`-th sample
//!   ([`Dump::sample_stride`]);
//! * the solver's per-cell counters (evaluations, fallbacks, residuals) are left out: they
//!   are for `info` and the files, not for looking at.

use std::path::Path;

use hdf5::types::{TypeDescriptor, VarLenAscii, VarLenUnicode};
use hdf5::{Dataset, File, Group};

use crate::error::H5Ctx;
use crate::{ATLAS_SCHEMA, SCHEMA, StoreError, TRAJECTORY_SCHEMA};

/// A map side above this many cells is thinned (a page of a 4096 x 4096 map would carry
/// hundreds of megabytes; 512 x 512 is finer than a screen shows the map at).
pub const MAX_MAP_SIDE: usize = 512;

/// A trajectory above this many samples is thinned (a line of 100 000 points draws at
/// screen resolution with room to zoom).
pub const MAX_SAMPLES: usize = 100_000;

/// Per-cell columns a page does not show (solver counters: `info` and the file have them).
const LEFT_OUT: [&str; 8] = [
    "evaluations",
    "fallbacks",
    "multi_root",
    "unconverged",
    "max_residual",
    "quasi_static",
    "blocks_done",
    "block",
];

/// Which file it is (its `schema` attribute).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// A scan (`squeal-basins/1`).
    Scan,
    /// An atlas (`squeal-atlas/1`).
    Atlas,
    /// One run (`squeal-trajectory/1`).
    Trajectory,
}

/// An attribute's value.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[serde(untagged)]
pub enum Value {
    /// Text.
    Text(String),
    /// Numbers (a scalar is one number); NaN and infinities as they are.
    Numbers(Vec<f64>),
}

/// A dataset's values.
#[derive(Clone, Debug, PartialEq)]
pub enum Data {
    /// Floating-point and integer values, as f64 (counts stay exact below 2^53).
    Float(Vec<f64>),
    /// One-byte values: enum codes (labels, reasons, regimes) and flags.
    Byte(Vec<u8>),
    /// Strings (an atlas's notes).
    Text(Vec<String>),
}

/// A dataset, by its path in the file (`labels`, `cycle/x`, `cycles/map_0002/v`).
#[derive(Clone, Debug, PartialEq)]
pub struct Var {
    /// Its path in the file.
    pub name: String,
    /// Its shape as read (after thinning).
    pub shape: Vec<usize>,
    /// The names of its dimensions (netCDF-4 dimension scales), where the file names them.
    pub dims: Vec<String>,
    /// Its attributes (long name, units, CF flags...).
    pub attrs: Vec<(String, Value)>,
    /// Its values, row-major.
    pub data: Data,
}

/// A file read for a page.
#[derive(Clone, Debug, PartialEq)]
pub struct Dump {
    /// Which file.
    pub kind: Kind,
    /// The root attributes.
    pub attrs: Vec<(String, Value)>,
    /// The datasets.
    pub vars: Vec<Var>,
    /// Every how many rows and columns of each map were read (1: all).
    pub map_stride: usize,
    /// The maps' full size `(rows, columns)` in the file, where it has a grid.
    pub map_size: Option<(usize, usize)>,
    /// Every how many samples of a trajectory were read (1: all).
    pub sample_stride: usize,
    /// The trajectory's sample count in the file.
    pub samples: Option<usize>,
}

impl Dump {
    /// A dataset by its path.
    pub fn var(&self, name: &str) -> Option<&Var> {
        self.vars.iter().find(|v| v.name == name)
    }
}

/// Reads `path` (a scan, atlas or trajectory file; anything else is refused as `info`
/// refuses it) for a page.
pub fn dump(path: &Path) -> Result<Dump, StoreError> {
    let (file, schema) = crate::read::open_with_any_schema(path)?;
    let kind = match schema.as_str() {
        SCHEMA => Kind::Scan,
        ATLAS_SCHEMA => Kind::Atlas,
        TRAJECTORY_SCHEMA => Kind::Trajectory,
        other => {
            return Err(StoreError::NotSquealFile {
                path: path.to_path_buf(),
                why: format!("its schema \"{other}\" is none that squeal writes"),
                advice: None,
            });
        }
    };
    read_all(&file, kind).h5(path)
}

fn read_all(file: &File, kind: Kind) -> hdf5::Result<Dump> {
    let len = |name: &str| -> hdf5::Result<Option<usize>> {
        Ok(if file.link_exists(name) {
            let ds = file.dataset(name)?;
            (ds.ndim() == 1).then(|| ds.shape()[0])
        } else {
            None
        })
    };
    let map_size = match (len("v0")?, len("x0")?) {
        // A random sample's x0 and v0 are over `sample`, not a grid.
        (Some(r), Some(c)) if !file.link_exists("sample") => Some((r, c)),
        _ => None,
    };
    let map_stride = map_size.map_or(1, |(r, c)| r.max(c).div_ceil(MAX_MAP_SIDE));
    let samples = if kind == Kind::Trajectory {
        len("t")?
    } else {
        None
    };
    let sample_stride = samples.map_or(1, |n| n.div_ceil(MAX_SAMPLES).max(1));
    let thin = Thin {
        map_size,
        map_stride,
        samples,
        sample_stride,
    };
    let mut vars = Vec::new();
    read_group(file, "", &thin, &mut vars)?;
    Ok(Dump {
        kind,
        attrs: attrs_of(file)?,
        vars,
        map_stride,
        map_size,
        sample_stride,
        samples,
    })
}

/// How datasets are thinned.
struct Thin {
    map_size: Option<(usize, usize)>,
    map_stride: usize,
    samples: Option<usize>,
    sample_stride: usize,
}

impl Thin {
    /// The stride along each dimension of a dataset of `shape` named `name`.
    fn strides(&self, name: &str, shape: &[usize]) -> Vec<usize> {
        let mut s = vec![1; shape.len()];
        let base = name.rsplit('/').next().unwrap_or(name);
        if let Some((r, c)) = self.map_size {
            let n = shape.len();
            if n >= 2 && shape[n - 2] == r && shape[n - 1] == c {
                s[n - 2] = self.map_stride;
                s[n - 1] = self.map_stride;
            } else if n == 1 && (base.starts_with("x0") || base.starts_with("v0")) {
                s[0] = self.map_stride;
            }
        }
        if let Some(t) = self.samples
            && shape.len() == 1
            && shape[0] == t
        {
            s[0] = self.sample_stride;
        }
        s
    }
}

fn read_group(g: &Group, prefix: &str, thin: &Thin, vars: &mut Vec<Var>) -> hdf5::Result<()> {
    for name in g.member_names()? {
        let path = format!("{prefix}{name}");
        let base = name.strip_prefix("map_").unwrap_or(&name);
        if LEFT_OUT.contains(&base) {
            continue;
        }
        if let Ok(sub) = g.group(&name) {
            read_group(&sub, &format!("{path}/"), thin, vars)?;
        } else if let Ok(ds) = g.dataset(&name)
            && let Some(v) = read_var(&ds, &path, thin)?
        {
            vars.push(v);
        }
    }
    Ok(())
}

fn read_var(ds: &Dataset, name: &str, thin: &Thin) -> hdf5::Result<Option<Var>> {
    let shape = ds.shape();
    let strides = thin.strides(name, &shape);
    let kept: Vec<usize> = shape
        .iter()
        .zip(&strides)
        .map(|(n, s)| n.div_ceil(*s))
        .collect();
    let data = match ds.dtype()?.to_descriptor()? {
        TypeDescriptor::Float(_) | TypeDescriptor::Integer(_) => {
            Data::Float(every(ds.read_raw::<f64>()?, &shape, &strides))
        }
        TypeDescriptor::Unsigned(_) if ds.dtype()?.size() > 1 => {
            Data::Float(every(ds.read_raw::<f64>()?, &shape, &strides))
        }
        TypeDescriptor::Unsigned(_) | TypeDescriptor::Enum(_) | TypeDescriptor::Boolean => {
            Data::Byte(every(ds.read_raw::<u8>()?, &shape, &strides))
        }
        TypeDescriptor::VarLenUnicode => Data::Text(
            ds.read_raw::<VarLenUnicode>()?
                .iter()
                .map(|s| s.to_string())
                .collect(),
        ),
        TypeDescriptor::VarLenAscii => Data::Text(
            ds.read_raw::<VarLenAscii>()?
                .iter()
                .map(|s| s.to_string())
                .collect(),
        ),
        // Nothing squeal writes; a page has no use for it.
        _ => return Ok(None),
    };
    Ok(Some(Var {
        name: name.to_string(),
        shape: kept,
        dims: dims_of(ds).unwrap_or_default(),
        attrs: attrs_of(ds)?,
        data,
    }))
}

/// Every `strides[d]`-th element along each dimension `d` of a row-major array.
fn every<T: Copy>(all: Vec<T>, shape: &[usize], strides: &[usize]) -> Vec<T> {
    if strides.iter().all(|&s| s == 1) {
        return all;
    }
    let mut out = Vec::new();
    let mut index = vec![0usize; shape.len()];
    // Row-major offsets of each dimension.
    let mut step = vec![1usize; shape.len()];
    for d in (0..shape.len().saturating_sub(1)).rev() {
        step[d] = step[d + 1] * shape[d + 1];
    }
    'cells: loop {
        out.push(all[index.iter().zip(&step).map(|(i, s)| i * s).sum::<usize>()]);
        for d in (0..shape.len()).rev() {
            index[d] += strides[d];
            if index[d] < shape[d] {
                continue 'cells;
            }
            index[d] = 0;
        }
        break;
    }
    out
}

/// The dimension scales attached to `ds`, by name (none where it has no `DIMENSION_LIST`).
fn dims_of(ds: &Dataset) -> hdf5::Result<Vec<String>> {
    use hdf5::types::VarLenArray;
    use hdf5::{ObjectReference1, ReferencedObject};
    if !ds.attr_names()?.iter().any(|n| n == "DIMENSION_LIST") {
        return Ok(Vec::new());
    }
    let list = ds
        .attr("DIMENSION_LIST")?
        .read_raw::<VarLenArray<ObjectReference1>>()?;
    let mut names = Vec::new();
    for refs in &list {
        let name = match refs.first().map(|r| ds.dereference(r)).transpose()? {
            Some(ReferencedObject::Dataset(d)) => d.name().trim_start_matches('/').to_string(),
            _ => String::new(),
        };
        names.push(name);
    }
    Ok(names)
}

fn attrs_of(loc: &hdf5::Location) -> hdf5::Result<Vec<(String, Value)>> {
    let mut out = Vec::new();
    for name in loc.attr_names()? {
        // netCDF's bookkeeping (dimension lists and scales) says nothing to a reader.
        if matches!(
            name.as_str(),
            "DIMENSION_LIST" | "REFERENCE_LIST" | "CLASS" | "NAME" | "_Netcdf4Dimid"
        ) {
            continue;
        }
        let a = loc.attr(&name)?;
        let v = match a.dtype()?.to_descriptor()? {
            TypeDescriptor::VarLenUnicode if a.is_scalar() => {
                Value::Text(a.read_scalar::<VarLenUnicode>()?.to_string())
            }
            TypeDescriptor::VarLenAscii if a.is_scalar() => {
                Value::Text(a.read_scalar::<VarLenAscii>()?.to_string())
            }
            TypeDescriptor::Float(_) | TypeDescriptor::Integer(_) | TypeDescriptor::Unsigned(_) => {
                Value::Numbers(a.read_raw::<f64>()?)
            }
            _ => continue,
        };
        out.push((name, v));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::{Thin, every};

    /// A 1500 x 1100 map is read every third row and column (1500 / 512 rounded up): its
    /// per-cell columns over (map, v0, x0), the grid's coordinates and their SI twins; a
    /// trajectory of 250 000 samples every third sample; other datasets whole.
    #[test]
    fn big_maps_and_long_runs_are_thinned_and_nothing_else() {
        let t = Thin {
            map_size: Some((1500, 1100)),
            map_stride: 1500usize.div_ceil(super::MAX_MAP_SIDE),
            samples: None,
            sample_stride: 1,
        };
        assert_eq!(t.strides("labels", &[4, 1500, 1100]), vec![1, 3, 3]);
        assert_eq!(t.strides("x0_si", &[1100]), vec![3]);
        assert_eq!(t.strides("v0", &[1500]), vec![3]);
        assert_eq!(t.strides("nu", &[4]), vec![1]);
        assert_eq!(t.strides("cycles/map_0001/x", &[1100]), vec![1]);
        let run = Thin {
            map_size: None,
            map_stride: 1,
            samples: Some(250_000),
            sample_stride: 250_000usize.div_ceil(super::MAX_SAMPLES),
        };
        assert_eq!(run.strides("x_si", &[250_000]), vec![3]);
        assert_eq!(run.strides("x_si", &[7]), vec![1]);
    }

    /// Every second row and column of a 3 x 5 array: rows 0 and 2, columns 0, 2 and 4.
    #[test]
    fn every_other_row_and_column() {
        let a: Vec<u32> = (0..15).collect();
        assert_eq!(
            every(a.clone(), &[3, 5], &[2, 2]),
            vec![0, 2, 4, 10, 12, 14]
        );
        assert_eq!(every(a.clone(), &[3, 5], &[1, 1]), a);
        // A leading map dimension kept whole.
        let b: Vec<u32> = (0..12).collect();
        assert_eq!(every(b, &[2, 2, 3], &[1, 2, 2]), vec![0, 2, 6, 8]);
    }
}
