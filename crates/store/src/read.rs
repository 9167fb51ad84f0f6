//! Reading squeal files back: checks, summaries, maps and cycles (the content digest is
//! [`crate::digest`]).

use std::path::{Path, PathBuf};

use hdf5::types::{TypeDescriptor, VarLenAscii, VarLenUnicode};
use hdf5::{Attribute, Dataset, File, Group, Location};
use squeal_scan::ClosedCurve;
use squeal_scan::cell::{COLUMNS, Cell};
use squeal_scan::checks::CHECK_FIELDS;
use squeal_scan::column::{Kind, Num};

use crate::error::{H5Ctx, io};
use crate::journal::CycleRecord;
use crate::{SCHEMA, StoreError};
use squeal_core::error::Number;

const HDF5_SIGNATURE: &[u8; 8] = b"\x89HDF\r\n\x1a\n";

/// Opens `path` and checks it is a squeal scan file (HDF5 with our `schema` attribute).
pub(crate) fn open_squeal(path: &Path) -> Result<File, StoreError> {
    open_with_schema(path, SCHEMA)
}

/// The `schema` attribute of a squeal file (scan or trajectory).
pub fn file_schema(path: &Path) -> Result<String, StoreError> {
    open_with_any_schema(path).map(|(_, schema)| schema)
}

/// Opens `path` as HDF5 and reads its `schema` attribute (whichever squeal wrote), refusing
/// a file without one: the file stays open for the caller (`dump` reads it whole).
pub(crate) fn open_with_any_schema(path: &Path) -> Result<(File, String), StoreError> {
    let file = open_hdf5(path)?;
    let schema = str_attr(&file, "schema").map_err(|_| StoreError::NotSquealFile {
        path: path.to_path_buf(),
        why: "an HDF5 file without the `schema` attribute (not written by squeal)".into(),
        advice: None,
    })?;
    Ok((file, schema))
}

/// Every root attribute as text, by name.
pub(crate) fn root_attrs_text(file: &File) -> hdf5::Result<Vec<(String, String)>> {
    let mut attrs = Vec::new();
    for name in file.attr_names()? {
        let text = attr_text(&file.attr(&name)?)?;
        attrs.push((name, text));
    }
    Ok(attrs)
}

/// Opens `path` as HDF5 (with a clear error for other files).
fn open_hdf5(path: &Path) -> Result<File, StoreError> {
    let not = |why: String| StoreError::NotSquealFile {
        path: path.to_path_buf(),
        why,
        advice: None,
    };
    // A FIFO here blocked the open for ever.
    squeal_scan::files::refuse_non_regular(path)?;
    let mut head = [0u8; 8];
    {
        use std::io::Read;
        let mut f = std::fs::File::open(path).map_err(io(path, "cannot open"))?;
        let n = f.read(&mut head).map_err(io(path, "cannot read"))?;
        if n < 8 || &head != HDF5_SIGNATURE {
            return Err(not("not an HDF5 file".into()));
        }
    }
    File::open(path).map_err(|e| {
        not(format!(
            "cannot open it as HDF5 (truncated or damaged?): {e}"
        ))
    })
}

/// Opens `path` and checks its `schema` attribute is `schema`.
pub(crate) fn open_with_schema(path: &Path, schema: &str) -> Result<File, StoreError> {
    let not = |why: String| StoreError::NotSquealFile {
        path: path.to_path_buf(),
        why,
        advice: None,
    };
    let file = open_hdf5(path)?;
    match str_attr(&file, "schema") {
        Ok(s) if s == schema => Ok(file),
        Ok(s) => Err(not(format!("schema is {s:?}, expected {schema:?}"))),
        Err(_) => Err(not(
            "an HDF5 file without the `schema` attribute (not written by squeal)".into(),
        )),
    }
}

/// Attribute `name` of `loc`; missing, an error saying so in words (the library's "can't
/// locate attribute in name index" named neither the attribute nor what it means).
pub(crate) fn attr(loc: &Location, name: &str) -> hdf5::Result<hdf5::Attribute> {
    loc.attr(name).map_err(|e| match loc.attr_names() {
        Ok(names) if !names.iter().any(|n| n == name) => hdf5::Error::from(format!(
            "no attribute `{name}`: not a squeal file, or a damaged one"
        )),
        _ => e,
    })
}

pub(crate) fn str_attr(loc: &Location, name: &str) -> hdf5::Result<String> {
    let a = attr(loc, name)?;
    match a.dtype()?.to_descriptor()? {
        TypeDescriptor::VarLenUnicode => Ok(a.read_scalar::<VarLenUnicode>()?.to_string()),
        TypeDescriptor::VarLenAscii => Ok(a.read_scalar::<VarLenAscii>()?.to_string()),
        other => Err(hdf5::Error::from(format!(
            "attribute {name} is {other}, not a string"
        ))),
    }
}

pub(crate) fn f64_attr(loc: &Location, name: &str) -> hdf5::Result<f64> {
    attr(loc, name)?.read_scalar::<f64>()
}

/// The friction tables a file stores (`None` for a law without one): the model's
/// (nondimensional slip speeds; none in a physical atlas, whose points each have their own
/// velocity unit) and the measured one in m/s (a physical system's), for `squeal info`.
pub fn friction_tables(path: &Path) -> Result<FrictionTables, StoreError> {
    let file = File::open(path).h5(path)?;
    let si = match file.link_exists("friction_table_slip_speed_si") {
        true => stored_table(&file).h5(path)?,
        false => None,
    };
    Ok((friction_table(&file).h5(path)?, si))
}

/// The model's friction table and the measured one in m/s ([`friction_tables`]).
pub type FrictionTables = (
    Option<&'static squeal_core::FrictionTable>,
    Option<&'static squeal_core::FrictionTable>,
);

/// The table a file's spec stands on where its `friction_table` or `friction_csv` is gone:
/// the measured curve in m/s (`friction_table_slip_speed_si`) of a physical spec, which gave
/// it under `[physical]`, else the model's ([`friction_table`]).
pub fn stored_table(file: &File) -> hdf5::Result<Option<&'static squeal_core::FrictionTable>> {
    table_of(file, "friction_table_slip_speed_si")
}

/// The table law's table a file stores (`friction_table_slip_speed` and
/// `friction_table_mu`, [`crate::h5out::friction_table`]); `None` in a file of another law
/// (and in every file of an earlier version).
pub fn friction_table(file: &File) -> hdf5::Result<Option<&'static squeal_core::FrictionTable>> {
    table_of(file, "friction_table_slip_speed")
}

/// The table of the slip speeds `speeds` (the model's or the SI ones) and the rows' `mu`;
/// `None` where `speeds` is not stored, but for the SI ones, which fall back to the model's.
fn table_of(
    file: &File,
    speeds: &str,
) -> hdf5::Result<Option<&'static squeal_core::FrictionTable>> {
    if !file.link_exists(speeds) {
        return match speeds {
            "friction_table_slip_speed" => Ok(None),
            _ => friction_table(file),
        };
    }
    let s: Vec<f64> = file.dataset(speeds)?.read_raw()?;
    let mu: Vec<f64> = file.dataset("friction_table_mu")?.read_raw()?;
    if s.len() != mu.len() {
        return Err(hdf5::Error::from(format!(
            "{speeds} has {} rows, friction_table_mu {}",
            s.len(),
            mu.len()
        )));
    }
    let rows: Vec<(f64, f64)> = s.into_iter().zip(mu).collect();
    squeal_core::FrictionTable::new(&rows)
        .map(Some)
        .map_err(|e| hdf5::Error::from(format!("the stored {e}")))
}

/// The swept keys of a sweep file, each with its value at every map (in map order).
#[derive(Clone, Debug, PartialEq)]
pub struct Swept {
    /// Each swept key (the model's: `nu`, `lambda`, `tau`, ...) and its value at each map.
    pub keys: Vec<(String, Vec<f64>)>,
    /// Each swept key's SI twin in a physical scan's file (`None` in others, and in
    /// files before twins of every key; same order as `keys`).
    pub si: Vec<Option<SweptSi>>,
}

/// The SI twin of a swept key in a file ([`squeal_scan::space::si_twin`]): the
/// `[physical]` key, its units and its value at each map.
#[derive(Clone, Debug, PartialEq)]
pub struct SweptSi {
    /// The physical key (`c`, `v_belt`, `mu_s`, `tau`).
    pub key: String,
    /// Its `units` attribute.
    pub units: String,
    /// Its value at each map.
    pub values: Vec<f64>,
}

impl SweptSi {
    /// Its units as shown: `None` for a ratio (`mu_s`, units "1") or none stored.
    pub fn shown_units(&self) -> Option<&str> {
        Some(self.units.as_str()).filter(|u| !u.is_empty() && *u != "1")
    }

    /// Its value at map `map` in words: `c = 5 N s/m`, `mu_s = 0.45` (a ratio: no units).
    pub fn words(&self, map: usize) -> String {
        let units = self
            .shown_units()
            .map_or(String::new(), |u| format!(" {u}"));
        match self.values.get(map) {
            Some(&x) => format!("{} = {}{units}", self.key, Number(x)),
            None => format!("{} = ?", self.key),
        }
    }
}

impl Swept {
    /// The value of key `name` at map `map`, if `name` is swept.
    pub fn value(&self, name: &str, map: usize) -> Option<f64> {
        let (_, v) = self.keys.iter().find(|(k, _)| k == name)?;
        v.get(map).copied()
    }

    /// The single swept key and its values, if only one key is swept.
    pub fn single(&self) -> Option<(&str, &[f64])> {
        match self.keys.as_slice() {
            [(k, v)] => Some((k, v)),
            _ => None,
        }
    }

    /// The names of the swept keys.
    pub fn names(&self) -> Vec<&str> {
        self.keys.iter().map(|(k, _)| k.as_str()).collect()
    }

    /// Map `map`'s swept values in words: `nu = 0.001, lambda = 2`; a physical scan's
    /// with the keys given: `nu = 0.007906 (c = 5 N s/m)`.
    pub fn words(&self, map: usize) -> String {
        let word = |((k, v), si): (&(String, Vec<f64>), &Option<SweptSi>)| {
            let twin = si
                .as_ref()
                .map_or(String::new(), |t| format!(" ({})", t.words(map)));
            match v.get(map) {
                Some(&x) => format!("{k} = {}{twin}", Number(x)),
                None => format!("{k} = ?"),
            }
        };
        (self.keys.iter().zip(&self.si))
            .map(word)
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// The swept keys, if the file holds a sweep: those its `swept` attribute lists (each a
/// dataset over the maps), or, in files before sweeps of every key, the one of `nu`,
/// `lambda`, `xi` and `v_d` stored as the maps' dimension.
pub(crate) fn sweep_of(file: &File) -> hdf5::Result<Option<Swept>> {
    let names: Vec<String> = match str_attr(file, "swept") {
        Ok(list) => list.split_whitespace().map(str::to_string).collect(),
        Err(_) => ["nu", "lambda", "xi", "v_d"]
            .into_iter()
            .find(|n| file.link_exists(n))
            .map(str::to_string)
            .into_iter()
            .collect(),
    };
    if names.is_empty() {
        return Ok(None);
    }
    let keys: Vec<(String, Vec<f64>)> = (names.into_iter())
        .map(|n| Ok((n.clone(), file.dataset(&n)?.read_raw::<f64>()?)))
        .collect::<hdf5::Result<_>>()?;
    let si = (keys.iter())
        .map(|(n, v)| swept_si(file, n, v.len()))
        .collect::<hdf5::Result<_>>()?;
    Ok(Some(Swept { keys, si }))
}

/// The SI twin of the swept key `name` over `maps` maps, where the file holds one.
fn swept_si(file: &File, name: &str, maps: usize) -> hdf5::Result<Option<SweptSi>> {
    let Some((key, dataset)) = squeal_scan::space::si_twin(name) else {
        return Ok(None);
    };
    if !file.link_exists(&dataset) {
        return Ok(None);
    }
    let ds = file.dataset(&dataset)?;
    let values = ds.read_raw::<f64>()?;
    let units = str_attr(&ds, "units").unwrap_or_default();
    Ok((values.len() == maps).then(|| SweptSi {
        key: key.to_string(),
        units,
        values,
    }))
}

/// A summary of a squeal file for `squeal info`.
#[derive(Clone, Debug)]
pub struct FileInfo {
    /// The file.
    pub path: PathBuf,
    /// The `schema` attribute.
    pub schema: String,
    /// `squeal_version`.
    pub version: String,
    /// `git_revision`.
    pub git_revision: String,
    /// The spec text.
    pub spec: String,
    /// Every root attribute as text, by name.
    pub attrs: Vec<(String, String)>,
    /// The swept parameter and its values.
    pub sweep: Option<Swept>,
    /// `x0` values.
    pub x0: Vec<f64>,
    /// `v0` values.
    pub v0: Vec<f64>,
    /// The number of maps.
    pub maps: usize,
    /// Whether the starts are random samples (a list over `sample`), not a grid.
    pub sample: bool,
    /// `K/N` in shard files.
    pub shard: Option<String>,
    /// Per map: the values of [`squeal_scan::checks::CHECK_FIELDS`] (-1: not applicable).
    pub checks: Vec<Vec<i64>>,
    /// Per map: the values of [`squeal_scan::sensitivity::SENSITIVITY_FIELDS`] (NaN: not
    /// measured, or a file written before them).
    pub sensitivity: Vec<Vec<f64>>,
    /// Per map: why no cycle was located, where the search found none.
    pub no_cycle: Vec<Option<String>>,
    /// Per map: the sampled start outside the located cycle that returns inside, where the
    /// return map jumps past the cycle ([`squeal_scan::section::escape_above`]).
    pub escape: Vec<Option<f64>>,
    /// Per map: the landscape and its evidence, for laws with true stick (empty otherwise).
    pub landscapes: Vec<Option<LandscapeInfo>>,
}

/// A map's stored landscape ([`squeal_scan::landscape`]).
#[derive(Clone, Debug, PartialEq)]
pub struct LandscapeInfo {
    /// The verdict.
    pub landscape: squeal_core::Landscape,
    /// The values of [`squeal_scan::landscape::LANDSCAPE_FIELDS`], by name.
    pub evidence: Vec<(&'static str, f64)>,
}

impl LandscapeInfo {
    /// A computed landscape as stored: its verdict and [`squeal_scan::landscape::LANDSCAPE_FIELDS`].
    pub fn of(e: &squeal_core::LandscapeEvidence) -> LandscapeInfo {
        LandscapeInfo {
            landscape: e.landscape,
            evidence: squeal_scan::landscape::LANDSCAPE_FIELDS
                .iter()
                .map(|(name, _, _, get)| (*name, get(e)))
                .collect(),
        }
    }
}

/// The stored landscapes of a file's maps (empty for files without them).
pub(crate) fn read_landscapes(
    file: &File,
    nmaps: usize,
) -> hdf5::Result<Vec<Option<LandscapeInfo>>> {
    let (name, _) = squeal_scan::landscape::LANDSCAPE;
    if !file.link_exists(name) {
        return Ok(Vec::new());
    }
    let verdicts: Vec<u8> = file.dataset(name)?.read_raw()?;
    let fields = squeal_scan::landscape::LANDSCAPE_FIELDS
        .iter()
        .map(|(n, ..)| Ok((*n, file.dataset(n)?.read_raw::<f64>()?)))
        .collect::<hdf5::Result<Vec<_>>>()?;
    Ok((0..nmaps)
        .map(|m| {
            let landscape = squeal_core::Landscape::from_u8(*verdicts.get(m)?)?;
            Some(LandscapeInfo {
                landscape,
                evidence: fields
                    .iter()
                    .map(|(n, v)| (*n, v.get(m).copied().unwrap_or(f64::NAN)))
                    .collect(),
            })
        })
        .collect())
}

fn attr_text(a: &Attribute) -> hdf5::Result<String> {
    let d = a.dtype()?.to_descriptor()?;
    let scalar = a.is_scalar();
    Ok(match d {
        TypeDescriptor::VarLenUnicode if scalar => a.read_scalar::<VarLenUnicode>()?.to_string(),
        TypeDescriptor::VarLenAscii if scalar => a.read_scalar::<VarLenAscii>()?.to_string(),
        // Exponent form for a huge or tiny value: `nu = 1e-300` was shown with 300 zeros.
        TypeDescriptor::Float(_) => join(a.read_raw::<f64>()?.into_iter().map(Number).collect()),
        TypeDescriptor::Integer(_) => join(a.read_raw::<i64>()?),
        TypeDescriptor::Unsigned(_) => join(a.read_raw::<u64>()?),
        other => format!("<{other}>"),
    })
}

fn join<T: std::fmt::Display>(v: Vec<T>) -> String {
    v.iter()
        .map(|x| x.to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

/// The values of dataset `name` (C order).
pub(crate) fn rd<T: hdf5::H5Type>(
    file: &File,
    path: &Path,
    name: &str,
) -> Result<Vec<T>, StoreError> {
    file.dataset(name).and_then(|d| d.read_raw()).h5(path)
}

/// [`rd`] of a dataset holding one value for each of the `n` entries (points, boundary
/// searches) of the plan its file's stored spec reads back to: any other length is refused.
/// Zipped with the plan instead, a file whose spec now reads to a plan of another size (an
/// older squeal's spec) would have its values attached to the wrong entries, silently.
pub(crate) fn rd_n<T: hdf5::H5Type>(
    file: &File,
    path: &Path,
    name: &str,
    n: usize,
) -> Result<Vec<T>, StoreError> {
    let v = rd(file, path, name)?;
    check_n(path, name, v.len(), n)?;
    Ok(v)
}

/// [`rd_n`] of a column stored as `kind`, as [`Num`]s ([`crate::h5columns::read_nums`]).
pub(crate) fn rd_nums_n(
    file: &File,
    path: &Path,
    (name, kind): (&str, Kind),
    n: usize,
) -> Result<Vec<Num>, StoreError> {
    let v = (file.dataset(name))
        .and_then(|ds| crate::h5columns::read_nums(&ds, kind, None))
        .h5(path)?;
    check_n(path, name, v.len(), n)?;
    Ok(v)
}

/// Refuses a dataset `name` of `len` values where its stored spec has `n` entries.
fn check_n(path: &Path, name: &str, len: usize, n: usize) -> Result<(), StoreError> {
    if len != n {
        return Err(StoreError::NotSquealFile {
            path: path.to_path_buf(),
            why: format!(
                "dataset {name} holds {} values where its stored spec has {n}: the file was \
                 written for another spec, or by a version that read the spec differently",
                len
            ),
            advice: None,
        });
    }
    Ok(())
}

/// [`rd_n`] of a dataset files written before it lack (then empty).
pub(crate) fn rd_new_n<T: hdf5::H5Type>(
    file: &File,
    path: &Path,
    name: &str,
    n: usize,
) -> Result<Vec<T>, StoreError> {
    match file.link_exists(name) {
        true => rd_n(file, path, name, n),
        false => Ok(Vec::new()),
    }
}

/// Opens and checks a squeal file and summarises it.
pub fn read_info(path: &Path) -> Result<FileInfo, StoreError> {
    let file = open_squeal(path)?;
    (|| -> hdf5::Result<FileInfo> {
        let attrs = root_attrs_text(&file)?;
        let sweep = sweep_of(&file)?;
        let is_sweep = sweep.is_some();
        let labels = file.dataset("labels")?;
        let shape = labels.shape();
        let nmaps = if is_sweep { shape[0] } else { 1 };
        let sample = is_sample(&file);
        Ok(FileInfo {
            path: path.to_path_buf(),
            schema: str_attr(&file, "schema")?,
            version: str_attr(&file, "squeal_version")?,
            git_revision: str_attr(&file, "git_revision")?,
            spec: str_attr(&file, "spec")?,
            attrs,
            sweep,
            x0: file.dataset("x0")?.read_raw()?,
            v0: file.dataset("v0")?.read_raw()?,
            checks: (0..nmaps)
                .map(|m| {
                    CHECK_FIELDS
                        .iter()
                        .map(|(name, _)| {
                            // Files written before a check was added lack its dataset.
                            if !file.link_exists(name) {
                                return Ok(-1);
                            }
                            let v: Vec<i64> = file.dataset(name)?.read_raw()?;
                            Ok(v.get(m).copied().unwrap_or(-1))
                        })
                        .collect::<hdf5::Result<Vec<i64>>>()
                })
                .collect::<hdf5::Result<_>>()?,
            sensitivity: (0..nmaps)
                .map(|m| {
                    squeal_scan::sensitivity::SENSITIVITY_FIELDS
                        .iter()
                        .map(|(name, ..)| {
                            if !file.link_exists(name) {
                                return Ok(f64::NAN);
                            }
                            let v: Vec<f64> = file.dataset(name)?.read_raw()?;
                            Ok(v.get(m).copied().unwrap_or(f64::NAN))
                        })
                        .collect::<hdf5::Result<Vec<f64>>>()
                })
                .collect::<hdf5::Result<_>>()?,
            no_cycle: (0..nmaps)
                .map(|m| {
                    Ok(read_cycle(&file, is_sweep, m)?
                        .flatten()
                        .and_then(|r| r.err())
                        .map(|e| e.to_string()))
                })
                .collect::<hdf5::Result<_>>()?,
            escape: (0..nmaps)
                .map(|m| {
                    Ok(read_cycle(&file, is_sweep, m)?
                        .flatten()
                        .and_then(|r| r.ok())
                        .and_then(|r| r.escape))
                })
                .collect::<hdf5::Result<_>>()?,
            landscapes: read_landscapes(&file, nmaps)?,
            maps: nmaps,
            sample,
            shard: str_attr(&file, "shard").ok(),
        })
    })()
    .h5(path)
}

/// The labels of map `map` of a scan file, row-major `(v0, x0)` (a random sample's: a list).
pub fn map_labels(path: &Path, map: usize) -> Result<Vec<u8>, StoreError> {
    let file = open_squeal(path)?;
    (|| {
        let sweep = sweep_of(&file)?.is_some();
        read_labels(&file.dataset("labels")?, map, sweep)
    })()
    .h5(path)
}

fn read_labels(labels: &Dataset, map: usize, sweep: bool) -> hdf5::Result<Vec<u8>> {
    read_cells(labels, map, sweep)
}

/// One map's values of a per-cell dataset, row-major.
fn read_cells<T: hdf5::H5Type>(ds: &Dataset, map: usize, sweep: bool) -> hdf5::Result<Vec<T>> {
    let rows = 0..ds.shape().get(sweep as usize).copied().unwrap_or(0);
    if !sweep {
        ds.read_raw::<T>()
    } else if crate::h5write::is_list(ds, 1) {
        Ok(ds
            .read_slice_1d::<T, _>(crate::h5write::sel(&[map], rows, true))?
            .into_iter()
            .collect())
    } else {
        Ok(ds
            .read_slice_2d::<T, _>(crate::h5write::sel(&[map], rows, false))?
            .into_iter()
            .collect())
    }
}

/// Whether a file holds random samples (root attribute `sampling = "random"`).
fn is_sample(file: &File) -> bool {
    str_attr(file, "sampling").is_ok_and(|s| s == "random")
}

/// One basin map, ready to draw.
#[derive(Clone, Debug)]
pub struct MapData {
    /// A title, e.g. "mcmillan nu = 0.001".
    pub title: String,
    /// `x0` values (columns).
    pub x0: Vec<f64>,
    /// `v0` values (rows).
    pub v0: Vec<f64>,
    /// Labels, row-major `(v0, x0)`; 255 = not computed.
    pub labels: Vec<u8>,
    /// The `t_squeal` column in the same order (`None` in files written before it).
    pub t_squeal: Option<Vec<f64>>,
    /// The located cycle's curve `(x, v)`.
    pub cycle: Option<(Vec<f64>, Vec<f64>)>,
    /// The steady-slip fixed point `(x*, 0)`.
    pub fixed_point: (f64, f64),
}

/// Number of maps in a squeal file.
pub fn map_count(path: &Path) -> Result<usize, StoreError> {
    let file = open_squeal(path)?;
    let shape = file.dataset("labels").h5(path)?.shape();
    let sweep = sweep_of(&file).h5(path)?.is_some();
    Ok(if sweep { shape[0] } else { 1 })
}

fn cycle_group(file: &File, sweep: bool, map: usize) -> Option<Group> {
    if sweep {
        file.group(&format!("cycles/map_{map:04}")).ok()
    } else {
        file.group("cycle").ok()
    }
}

/// Reads map `map` of a squeal file.
pub fn read_map(path: &Path, map: usize) -> Result<MapData, StoreError> {
    let file = open_squeal(path)?;
    let count = map_count(path)?;
    if map >= count {
        return Err(StoreError::NoSuchMap {
            path: path.to_path_buf(),
            map,
            count,
        });
    }
    (|| -> hdf5::Result<MapData> {
        if is_sample(&file) {
            return Err(hdf5::Error::from(
                "the file holds random samples, a list of points, not a map to draw".to_string(),
            ));
        }
        let sweep = sweep_of(&file)?;
        let law_name = str_attr(&file, "law")?;
        let law: squeal_core::FrictionLaw = law_name
            .parse()
            .map_err(|e: squeal_core::CoreError| hdf5::Error::from(e.to_string()))?;
        let value = |name: &str| -> Option<f64> {
            (sweep.as_ref().and_then(|s| s.value(name, map))).or_else(|| f64_attr(&file, name).ok())
        };
        let params = squeal_core::Params::from_named_table(law, friction_table(&file)?, value)
            .map_err(|k| hdf5::Error::from(format!("attribute {k} is missing")))?;
        // Exponent form for a huge or tiny value (`nu = 1e-300` had 300 zeros).
        let title = match &sweep {
            Some(s) => format!("{law_name} {}", s.words(map)),
            None => format!(
                "{law_name} {} = {}",
                params.damping_key(),
                Number(params.nu)
            ),
        };
        let cycle = match cycle_group(&file, sweep.is_some(), map) {
            Some(g) if g.link_exists("x") => {
                Some((g.dataset("x")?.read_raw()?, g.dataset("v")?.read_raw()?))
            }
            _ => None,
        };
        let fp = params.fixed_point();
        let data = MapData {
            title,
            x0: file.dataset("x0")?.read_raw()?,
            v0: file.dataset("v0")?.read_raw()?,
            labels: read_labels(&file.dataset("labels")?, map, sweep.is_some())?,
            t_squeal: match file.dataset("t_squeal") {
                Ok(ds) => Some(read_cells(&ds, map, sweep.is_some())?),
                Err(_) => None,
            },
            cycle,
            fixed_point: (fp.x, fp.v),
        };
        // A map's columns hold one value per cell of its axes: every reader of a map
        // (render, compare) may then index them by the axes (`compare` would panic on a file
        // whose labels had another shape).
        let cells = data.x0.len() * data.v0.len();
        let columns = [
            ("labels", Some(data.labels.len())),
            ("t_squeal", data.t_squeal.as_ref().map(Vec::len)),
        ];
        for (name, len) in columns {
            if let Some(n) = len.filter(|&n| n != cells) {
                return Err(hdf5::Error::from(format!(
                    "`{name}` holds {n} cells for map {map}, but the axes x0 ({}) and v0 ({}) \
                     make {cells}: a damaged file",
                    data.x0.len(),
                    data.v0.len()
                )));
            }
        }
        Ok(data)
    })()
    .h5(path)
}

/// One map's cycle for the sweep plot: (sweep value, r_section, distance_plus_x, area,
/// encloses_origin), NaN and false where there is no cycle.
pub type CycleSummary = (f64, f64, f64, f64, bool);

/// Per map: (sweep value, r_section, distance_plus_x, area, encloses_origin), NaN where no cycle.
pub fn read_cycle_summary(path: &Path) -> Result<Vec<CycleSummary>, StoreError> {
    let file = open_squeal(path)?;
    let n = map_count(path)?;
    (|| -> hdf5::Result<Vec<CycleSummary>> {
        let sweep = sweep_of(&file)?;
        let mut out = Vec::with_capacity(n);
        for m in 0..n {
            // The first swept key's value (the chart is drawn for one swept key).
            let value = match &sweep {
                Some(s) => s.keys[0].1[m],
                None => f64_attr(&file, "nu").or_else(|_| f64_attr(&file, "xi"))?,
            };
            let rec = read_cycle(&file, sweep.is_some(), m)?;
            out.push(match rec.flatten().and_then(Result::ok) {
                Some(c) => (
                    value,
                    c.r_section,
                    c.distance_plus_x,
                    c.area,
                    c.encloses_origin,
                ),
                None => (value, f64::NAN, f64::NAN, f64::NAN, false),
            });
        }
        Ok(out)
    })()
    .h5(path)
}

/// The stored cycle record of a map, if any (`None`: no group, nothing recorded).
pub(crate) fn read_cycle(
    file: &File,
    sweep: bool,
    map: usize,
) -> hdf5::Result<Option<CycleRecord>> {
    let Some(g) = cycle_group(file, sweep, map) else {
        return Ok(None);
    };
    let curve = if g.link_exists("x") {
        Some(ClosedCurve::new(
            g.dataset("x")?.read_raw()?,
            g.dataset("v")?.read_raw()?,
        ))
    } else {
        None
    };
    let text = str_attr(&g, "record")?;
    crate::cycle::from_text(&text, curve)
        .map(Some)
        .map_err(|e| hdf5::Error::from(format!("{}: attribute record: {e}", g.name())))
}

/// Reads the cells of one block back from a file, column by column.
pub(crate) fn read_block(
    file: &File,
    sweep: bool,
    map: usize,
    rows: std::ops::Range<usize>,
) -> hdf5::Result<Vec<Cell>> {
    let m: &[usize] = if sweep {
        std::slice::from_ref(&map)
    } else {
        &[]
    };
    let mut cells: Vec<Cell> = Vec::new();
    for col in COLUMNS {
        // A column newer than the file (a file of an earlier version): its fill value, as
        // for a cell not computed.
        if !file.link_exists(col.name) && !cells.is_empty() {
            for c in cells.iter_mut() {
                (col.set)(c, col.fill);
            }
            continue;
        }
        let ds = file.dataset(col.name)?;
        let sel = crate::h5write::sel(m, rows.clone(), crate::h5write::is_list(&ds, m.len()));
        let vals = crate::h5columns::read_nums(&ds, col.kind, Some(sel))?;
        if cells.is_empty() {
            cells = vec![Cell::fill(); vals.len()];
        }
        if vals.len() != cells.len() {
            return Err(hdf5::Error::from(format!("{}: wrong shape", col.name)));
        }
        for (c, v) in cells.iter_mut().zip(vals) {
            (col.set)(c, v);
        }
    }
    Ok(cells)
}
