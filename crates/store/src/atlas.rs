//! Atlas files: the journal of finished units, the HDF5 file, reading it back, merging
//! shards.
//!
//! ## Journal `<out>.journal`
//! JSON lines, fsynced after each: a header `{"schema", "spec", "shard"}`, then one line per
//! finished unit (a line of points or a boundary search), the figures as arrays in the
//! order of [`squeal_scan::atlas::columns`] (NaN as `null`). A torn last line (a kill during
//! the write) is dropped on resume. The journal is created exclusively, so two runs never
//! write the same file; `--resume` reopens it.
//!
//! ## HDF5 schema `squeal-atlas/1`
//! ```text
//! /  attrs: schema, squeal_version, git_revision, spec (TOML text), name, law, units
//!           ("nondimensional" | "physical"), solver, dt, every fixed parameter (f64, with
//!           <key>_units), operating_point_x/_v, disturbance_x/_v ([min, max]), shard
//! coordinates (dimension scales, attrs long_name, units): one per swept parameter, in
//!           axis order (nu, lambda, tau, phi | m, k, c, v_belt, mu_k, mu_s, tau, g);
//!           `point` (length 1) when nothing is swept, `boundary` (length 1) when only the
//!           damping is
//! over the swept dims:
//!   regime   u8 enum {undecided=0, steady_slip_only=1, bistable_quiet=2,
//!            bistable_squeals=3, fixed_point_unstable=4, not_computed=255}; CF flag_values,
//!            flag_meanings
//!   cycle_*, stick_*, basin_fraction, basin_fraction_err   f64 (NaN: none), long_name, units
//!   cycle_encloses_operating_point, warm_started           u8 (255: unknown)
//!   returns, evaluations, failures                          u64
//!   <figure>_si    (physical specs) the same figure in SI units (m, m/s, s, Hz, m^2/s)
//!   nu, lambda, tau, phi (physical specs: nondim_nu, ...) the nondimensional parameters
//!   note           string: why a point is undecided, or the caveat of its label
//!   points_done    u8: 1 where computed (shards)
//! over the swept dims except the damping (nu or c):
//!   fold_status, critical_status  u8 enum {found=0, below_range=1, above_range=2,
//!                                 not_computed=255}
//!   fold_nu, fold_nu_lo, fold_nu_hi, critical_nu, critical_nu_lo, critical_nu_hi   f64
//!   fold_c, ..., critical_c_hi    (physical specs) in N s/m
//!   boundary_note                 string: why a search was not computed
//!   boundaries_done               u8
//! ```

use std::collections::HashSet;
use std::io::{BufRead, Seek, Write};
use std::path::{Path, PathBuf};

use hdf5::types::VarLenUnicode;
use hdf5::{Dataset, File, H5Type};
use ndarray::{ArrayD, IxDyn};
use serde_json::{Value, json};
use squeal_scan::atlas::columns::{
    BOUNDARY_COLUMNS, COLUMNS, Kind, Si, empty_boundary, empty_point, finish_point, status_meanings,
};
use squeal_scan::atlas::{
    AtlasPlan, AtlasRegime, BoundaryResult, BoundaryStatus, LineResult, PointResult, Unit,
    UnitResult, Units,
};

use crate::error::{H5Ctx, io};
use crate::h5write::{Dims, class_type, num_attr, str_attr};
use crate::{Provenance, Shard, StoreError};

/// The `schema` attribute of atlas files.
pub const ATLAS_SCHEMA: &str = "squeal-atlas/1";

/// The `regime` enum in files: [`AtlasRegime`] plus `not_computed`.
#[derive(H5Type, Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
enum RegimeH5 {
    #[hdf5(rename = "undecided")]
    Undecided = 0,
    #[hdf5(rename = "steady_slip_only")]
    SteadySlipOnly = 1,
    #[hdf5(rename = "bistable_quiet")]
    BistableQuiet = 2,
    #[hdf5(rename = "bistable_squeals")]
    BistableSqueals = 3,
    #[hdf5(rename = "fixed_point_unstable")]
    FixedPointUnstable = 4,
    #[hdf5(rename = "not_computed")]
    NotComputed = 255,
}

impl RegimeH5 {
    fn from(r: Option<AtlasRegime>) -> RegimeH5 {
        match r {
            None => RegimeH5::NotComputed,
            Some(AtlasRegime::Undecided) => RegimeH5::Undecided,
            Some(AtlasRegime::SteadySlipOnly) => RegimeH5::SteadySlipOnly,
            Some(AtlasRegime::BistableQuiet) => RegimeH5::BistableQuiet,
            Some(AtlasRegime::BistableSqueals) => RegimeH5::BistableSqueals,
            Some(AtlasRegime::FixedPointUnstable) => RegimeH5::FixedPointUnstable,
        }
    }
}

/// The boundary `*_status` enum in files.
#[derive(H5Type, Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
enum StatusH5 {
    #[hdf5(rename = "found")]
    Found = 0,
    #[hdf5(rename = "below_range")]
    BelowRange = 1,
    #[hdf5(rename = "above_range")]
    AboveRange = 2,
    #[hdf5(rename = "not_computed")]
    NotComputed = 255,
}

impl StatusH5 {
    fn from(s: BoundaryStatus) -> StatusH5 {
        match s {
            BoundaryStatus::Found => StatusH5::Found,
            BoundaryStatus::BelowRange => StatusH5::BelowRange,
            BoundaryStatus::AboveRange => StatusH5::AboveRange,
            BoundaryStatus::NotComputed => StatusH5::NotComputed,
        }
    }
}

/// Everything computed so far, by index.
#[derive(Clone, Debug, PartialEq)]
pub struct AtlasResults {
    /// Per point (C order over the swept axes); `None` where not computed.
    pub points: Vec<Option<PointResult>>,
    /// Per boundary search; `None` where not computed.
    pub boundaries: Vec<Option<BoundaryResult>>,
}

impl AtlasResults {
    /// Nothing computed yet.
    pub fn new(plan: &AtlasPlan) -> AtlasResults {
        AtlasResults {
            points: vec![None; plan.n_points()],
            boundaries: vec![None; plan.n_boundaries()],
        }
    }

    /// Stores a finished unit.
    pub fn add(&mut self, plan: &AtlasPlan, r: UnitResult) {
        match r {
            UnitResult::Line(l) => {
                let len = plan.line_len();
                for (k, p) in l.points.into_iter().enumerate() {
                    if let Some(slot) = self.points.get_mut(l.line * len + k) {
                        *slot = Some(p);
                    }
                }
            }
            UnitResult::Boundary(b) => {
                if let Some(slot) = self.boundaries.get_mut(b.index) {
                    *slot = Some(b);
                }
            }
        }
    }

    /// Whether a unit is stored.
    pub fn is_done(&self, plan: &AtlasPlan, u: Unit) -> bool {
        match u {
            Unit::Line(i) => {
                let len = plan.line_len();
                self.points[i * len..(i + 1) * len]
                    .iter()
                    .all(Option::is_some)
            }
            Unit::Boundary(j) => self.boundaries[j].is_some(),
        }
    }
}

/// Whether shard `s` owns the `k`-th unit of [`AtlasPlan::units`].
pub fn atlas_shard_owns(shard: Option<Shard>, k: usize) -> bool {
    shard.is_none_or(|s| k % s.n == s.k - 1)
}

/// The units `shard` owns that are not stored yet.
pub fn missing_units(plan: &AtlasPlan, res: &AtlasResults, shard: Option<Shard>) -> Vec<Unit> {
    plan.units()
        .into_iter()
        .enumerate()
        .filter(|(k, u)| atlas_shard_owns(shard, *k) && !res.is_done(plan, *u))
        .map(|(_, u)| u)
        .collect()
}

fn num(v: f64) -> Value {
    if v.is_finite() { json!(v) } else { Value::Null }
}

fn point_json(p: &PointResult) -> Value {
    json!({
        "regime": p.regime as u8,
        "note": p.note,
        "v": COLUMNS.iter().map(|c| num((c.get)(p))).collect::<Vec<_>>(),
    })
}

fn point_from_json(v: &Value) -> Option<PointResult> {
    let mut p = empty_point();
    p.regime = AtlasRegime::from_u8(v.get("regime")?.as_u64()? as u8)?;
    p.note = v.get("note")?.as_str().map(str::to_string);
    let vals = v.get("v")?.as_array()?;
    if vals.len() != COLUMNS.len() {
        return None;
    }
    for (c, x) in COLUMNS.iter().zip(vals) {
        (c.set)(&mut p, x.as_f64().unwrap_or(f64::NAN));
    }
    finish_point(&mut p);
    Some(p)
}

/// A unit result as one JSON value (NaN as null), for the journal and `--json`.
pub fn unit_json(r: &UnitResult) -> Value {
    match r {
        UnitResult::Line(l) => json!({
            "line": l.line,
            "points": l.points.iter().map(point_json).collect::<Vec<_>>(),
        }),
        UnitResult::Boundary(b) => json!({
            "boundary": b.index,
            "fold_status": b.fold.status as u8,
            "critical_status": b.critical.status as u8,
            "fold_evaluations": b.fold.evaluations,
            "critical_evaluations": b.critical.evaluations,
            "note": b.note,
            "v": BOUNDARY_COLUMNS.iter().map(|c| num((c.get)(b))).collect::<Vec<_>>(),
        }),
    }
}

fn unit_from_json(v: &Value) -> Option<UnitResult> {
    if let Some(line) = v.get("line") {
        let points = v
            .get("points")?
            .as_array()?
            .iter()
            .map(point_from_json)
            .collect::<Option<Vec<_>>>()?;
        return Some(UnitResult::Line(LineResult {
            line: line.as_u64()? as usize,
            points,
        }));
    }
    let j = v.get("boundary")?.as_u64()? as usize;
    let mut b = empty_boundary(j);
    b.fold.status = BoundaryStatus::from_u8(v.get("fold_status")?.as_u64()? as u8)?;
    b.critical.status = BoundaryStatus::from_u8(v.get("critical_status")?.as_u64()? as u8)?;
    b.fold.evaluations = v.get("fold_evaluations")?.as_u64()? as u32;
    b.critical.evaluations = v.get("critical_evaluations")?.as_u64()? as u32;
    b.note = v.get("note").and_then(|n| n.as_str()).map(str::to_string);
    let vals = v.get("v")?.as_array()?;
    if vals.len() != BOUNDARY_COLUMNS.len() {
        return None;
    }
    for (c, x) in BOUNDARY_COLUMNS.iter().zip(vals) {
        (c.set)(&mut b, x.as_f64().unwrap_or(f64::NAN));
    }
    Some(UnitResult::Boundary(b))
}

fn journal_path(out: &Path) -> PathBuf {
    let mut s = out.as_os_str().to_owned();
    s.push(".journal");
    PathBuf::from(s)
}

/// Journals finished units and writes the atlas file at the end.
pub struct AtlasWriter {
    out: PathBuf,
    journal: PathBuf,
    file: std::fs::File,
    plan: AtlasPlan,
    shard: Option<Shard>,
    prov: Provenance,
    /// What is stored so far.
    pub results: AtlasResults,
}

impl AtlasWriter {
    /// Starts a new atlas at `out`. Refuses an existing output or journal unless `force`.
    pub fn create(
        out: &Path,
        plan: &AtlasPlan,
        shard: Option<Shard>,
        prov: &Provenance,
        force: bool,
    ) -> Result<AtlasWriter, StoreError> {
        let journal = journal_path(out);
        if !force {
            if journal.exists() {
                return Err(StoreError::Interrupted { path: journal });
            }
            if out.exists() {
                return Err(StoreError::Exists {
                    path: out.to_path_buf(),
                });
            }
        } else if journal.exists() {
            std::fs::remove_file(&journal).map_err(io(&journal, "cannot remove"))?;
        }
        if let Some(d) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(d).map_err(io(d, "cannot create folder"))?;
        }
        // Exclusive: a second run on the same output fails here.
        let mut file = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&journal)
            .map_err(io(&journal, "cannot create (another run on this output?)"))?;
        let header = json!({
            "schema": ATLAS_SCHEMA,
            "spec": plan.spec_text,
            "shard": shard.map(|s| s.to_string()),
        });
        writeln!(file, "{header}").map_err(io(&journal, "cannot write"))?;
        file.sync_all().map_err(io(&journal, "cannot sync"))?;
        Ok(AtlasWriter {
            out: out.to_path_buf(),
            journal,
            file,
            plan: plan.clone(),
            shard,
            prov: prov.clone(),
            results: AtlasResults::new(plan),
        })
    }

    /// Reopens the journal of an interrupted atlas.
    pub fn resume(
        out: &Path,
        plan: &AtlasPlan,
        shard: Option<Shard>,
        prov: &Provenance,
    ) -> Result<AtlasWriter, StoreError> {
        let journal = journal_path(out);
        if !journal.exists() {
            return Err(if out.exists() {
                StoreError::AlreadyComplete {
                    path: out.to_path_buf(),
                }
            } else {
                StoreError::NothingToResume {
                    path: out.to_path_buf(),
                }
            });
        }
        let f = std::fs::File::open(&journal).map_err(io(&journal, "cannot open"))?;
        let mut reader = std::io::BufReader::new(f);
        let mut results = AtlasResults::new(plan);
        let mut good = 0u64;
        let mut first = true;
        loop {
            let mut line = String::new();
            let n = reader
                .read_line(&mut line)
                .map_err(io(&journal, "cannot read"))?;
            if n == 0 || !line.ends_with('\n') {
                break;
            }
            let Ok(v) = serde_json::from_str::<Value>(&line) else {
                break;
            };
            if first {
                let mismatch = |why: &str| StoreError::SpecMismatch {
                    path: journal.clone(),
                    why: why.to_string(),
                };
                if v["schema"] != ATLAS_SCHEMA {
                    return Err(StoreError::NotSquealFile {
                        path: journal.clone(),
                        why: "not an atlas journal".into(),
                    });
                }
                if v["spec"] != plan.spec_text.as_str() {
                    return Err(mismatch("different spec text"));
                }
                if v["shard"] != json!(shard.map(|s| s.to_string())) {
                    return Err(mismatch("different --shard"));
                }
                first = false;
            } else {
                let Some(r) = unit_from_json(&v) else { break };
                results.add(plan, r);
            }
            good += n as u64;
        }
        if first {
            return Err(StoreError::NotSquealFile {
                path: journal.clone(),
                why: "the journal has no header".into(),
            });
        }
        let mut file = std::fs::OpenOptions::new()
            .write(true)
            .open(&journal)
            .map_err(io(&journal, "cannot open"))?;
        // Drop a torn last line.
        file.set_len(good)
            .map_err(io(&journal, "cannot truncate"))?;
        file.seek(std::io::SeekFrom::End(0))
            .map_err(io(&journal, "cannot seek"))?;
        Ok(AtlasWriter {
            out: out.to_path_buf(),
            journal,
            file,
            plan: plan.clone(),
            shard,
            prov: prov.clone(),
            results,
        })
    }

    /// The units still to compute.
    pub fn missing(&self) -> Vec<Unit> {
        missing_units(&self.plan, &self.results, self.shard)
    }

    /// Journals a finished unit (fsynced) and keeps it.
    pub fn record(&mut self, r: UnitResult) -> Result<(), StoreError> {
        let line = unit_json(&r);
        writeln!(self.file, "{line}").map_err(io(&self.journal, "cannot write"))?;
        self.file
            .sync_data()
            .map_err(io(&self.journal, "cannot sync"))?;
        self.results.add(&self.plan, r);
        Ok(())
    }

    /// Writes the HDF5 file (via `<out>.tmp`, renamed) and removes the journal. Every owned
    /// unit must be stored.
    pub fn finish(self) -> Result<AtlasResults, StoreError> {
        let missing = self.missing();
        if !missing.is_empty() {
            return Err(StoreError::Incomplete {
                path: self.out.clone(),
                missing: missing.len(),
                total: self.plan.units().len(),
            });
        }
        write_atlas(&self.out, &self.plan, &self.results, &self.prov, self.shard)?;
        std::fs::remove_file(&self.journal).map_err(io(&self.journal, "cannot remove"))?;
        Ok(self.results)
    }
}

#[allow(clippy::too_many_arguments)] // one call per dataset: name, shape, data, words, units, dims
fn put<T: H5Type>(
    file: &File,
    dims: &mut Dims,
    name: &str,
    shape: &[usize],
    data: Vec<T>,
    long_name: &str,
    units: Option<&str>,
    scales: &[Dataset],
) -> hdf5::Result<Dataset> {
    let a = ArrayD::from_shape_vec(IxDyn(shape), data)
        .map_err(|e| hdf5::Error::from(format!("{name}: {e}")))?;
    let ds = file
        .new_dataset_builder()
        .obj_track_times(false)
        .with_data(&a)
        .create(name)?;
    str_attr(&ds, "long_name", long_name)?;
    if let Some(u) = units {
        str_attr(&ds, "units", u)?;
    }
    let refs: Vec<&Dataset> = scales.iter().collect();
    dims.attach(file, &ds, &refs)?;
    Ok(ds)
}

fn flags(ds: &Dataset, meanings: &str, values: &[u8]) -> hdf5::Result<()> {
    str_attr(ds, "flag_meanings", meanings)?;
    ds.new_attr::<u8>()
        .shape(values.len())
        .create("flag_values")?
        .write_raw(values)
}

fn u8_of(v: f64) -> u8 {
    if v.is_nan() { 255 } else { v as u8 }
}

/// Writes the atlas file `out` (through `<out>.tmp`, then renamed).
pub fn write_atlas(
    out: &Path,
    plan: &AtlasPlan,
    res: &AtlasResults,
    prov: &Provenance,
    shard: Option<Shard>,
) -> Result<(), StoreError> {
    let mut tmp = out.as_os_str().to_owned();
    tmp.push(".tmp");
    let tmp = PathBuf::from(tmp);
    let file = File::create(&tmp).h5(&tmp)?;
    let mut dims = Dims {
        scales: Vec::new(),
        class_type: class_type(&tmp)?,
    };
    write_all(&file, &mut dims, plan, res, prov, shard).h5(&tmp)?;
    dims.finish().h5(&tmp)?;
    file.close().h5(&tmp)?;
    std::fs::rename(&tmp, out).map_err(io(out, "cannot rename the finished file to"))?;
    Ok(())
}

fn write_all(
    file: &File,
    dims: &mut Dims,
    plan: &AtlasPlan,
    res: &AtlasResults,
    prov: &Provenance,
    shard: Option<Shard>,
) -> hdf5::Result<()> {
    str_attr(file, "schema", ATLAS_SCHEMA)?;
    str_attr(file, "squeal_version", &prov.version)?;
    str_attr(file, "git_revision", &prov.git_revision)?;
    str_attr(file, "spec", &plan.spec_text)?;
    str_attr(file, "name", &plan.name)?;
    str_attr(file, "law", plan.law.name())?;
    str_attr(file, "units", plan.units.name())?;
    str_attr(file, "solver", plan.solver.kind.name())?;
    num_attr(file, "dt", plan.dt)?;
    for (a, v) in plan.fixed() {
        num_attr(file, a.key, v)?;
        str_attr(file, &format!("{}_units", a.key), a.units)?;
    }
    let ps = &plan.point;
    num_attr(file, "operating_point_x", ps.operating.x)?;
    num_attr(file, "operating_point_v", ps.operating.v)?;
    for (k, r) in [
        ("disturbance_x", ps.disturbance.x),
        ("disturbance_v", ps.disturbance.v),
    ] {
        file.new_attr::<f64>().shape(2).create(k)?.write_raw(&r)?;
    }
    if let Some(s) = shard {
        str_attr(file, "shard", &s.to_string())?;
    }

    // Coordinates.
    let axes = plan.axes();
    let mut scales = Vec::new();
    for a in &axes {
        let ds = file
            .new_dataset_builder()
            .obj_track_times(false)
            .with_data(&a.values)
            .create(a.key)?;
        str_attr(&ds, "long_name", a.long_name)?;
        str_attr(&ds, "units", a.units)?;
        dims.scale(&ds, a.key)?;
        scales.push(ds);
    }
    let index_coord = |dims: &mut Dims, name: &str, long: &str| -> hdf5::Result<Dataset> {
        let ds = file
            .new_dataset_builder()
            .obj_track_times(false)
            .with_data(&[0u64])
            .create(name)?;
        str_attr(&ds, "long_name", long)?;
        dims.scale(&ds, name)?;
        Ok(ds)
    };
    let (shape, pscales) = if axes.is_empty() {
        (
            vec![1],
            vec![index_coord(dims, "point", "the single parameter point")?],
        )
    } else {
        (plan.shape(), scales.clone())
    };
    let n = plan.n_points();

    // Points.
    let regimes: Vec<RegimeH5> = res
        .points
        .iter()
        .map(|p| RegimeH5::from(p.as_ref().map(|p| p.regime)))
        .collect();
    let ds = put(
        file,
        dims,
        "regime",
        &shape,
        regimes,
        "regime of the parameter point",
        None,
        &pscales,
    )?;
    let meanings: Vec<&str> = AtlasRegime::ALL.iter().map(|r| r.name()).collect();
    flags(
        &ds,
        &format!("{} not_computed", meanings.join(" ")),
        &[0, 1, 2, 3, 4, 255],
    )?;
    let scales_at: Vec<Option<squeal_core::Scales>> = (0..n)
        .map(|i| plan.physical_at(i).map(|p| p.scales()))
        .collect();
    for c in COLUMNS {
        let vals: Vec<f64> = res
            .points
            .iter()
            .map(|p| p.as_ref().map_or(f64::NAN, |p| (c.get)(p)))
            .collect();
        let units = if c.si == Si::Frequency {
            "1 (angular frequency, nondimensional)"
        } else {
            "1"
        };
        match c.kind {
            Kind::Real => {
                put(
                    file,
                    dims,
                    c.name,
                    &shape,
                    vals.clone(),
                    c.long_name,
                    Some(units),
                    &pscales,
                )?;
            }
            Kind::Flag => {
                let v: Vec<u8> = vals.iter().map(|&v| u8_of(v)).collect();
                let ds = put(file, dims, c.name, &shape, v, c.long_name, None, &pscales)?;
                flags(&ds, "no yes unknown", &[0, 1, 255])?;
            }
            Kind::Count => {
                let v: Vec<u64> = vals
                    .iter()
                    .map(|&v| if v.is_nan() { 0 } else { v as u64 })
                    .collect();
                put(file, dims, c.name, &shape, v, c.long_name, None, &pscales)?;
            }
        }
        if plan.units == Units::Physical && c.si != Si::None {
            let si: Vec<f64> = vals
                .iter()
                .zip(&scales_at)
                .map(|(&v, s)| s.map_or(f64::NAN, |s| c.si.convert(v, &s)))
                .collect();
            let long = format!("{} (SI)", c.long_name);
            put(
                file,
                dims,
                &format!("{}_si", c.name),
                &shape,
                si,
                &long,
                Some(c.si.units()),
                &pscales,
            )?;
        }
    }
    if plan.units == Units::Physical {
        let nd = squeal_scan::atlas::spec::NONDIMENSIONAL;
        let ps: Vec<squeal_core::Params> = (0..n).map(|i| plan.params_at(i)).collect();
        let getters: [fn(&squeal_core::Params) -> f64; 4] =
            [|p| p.nu, |p| p.lambda, |p| p.tau, |p| p.phi];
        for ((key, long, units), g) in nd.iter().zip(getters) {
            let v: Vec<f64> = ps.iter().map(g).collect();
            put(
                file,
                dims,
                &format!("nondim_{key}"),
                &shape,
                v,
                long,
                Some(units),
                &pscales,
            )?;
        }
    }
    let notes = note_strings(
        res.points
            .iter()
            .map(|p| p.as_ref().and_then(|p| p.note.as_deref())),
    )?;
    put(
        file,
        dims,
        "note",
        &shape,
        notes,
        "why a point is undecided, or the caveat its label rests on (empty: none)",
        None,
        &pscales,
    )?;
    let done: Vec<u8> = res.points.iter().map(|p| u8::from(p.is_some())).collect();
    put(
        file,
        dims,
        "points_done",
        &shape,
        done,
        "1 where the point is computed",
        None,
        &pscales,
    )?;

    // Boundaries.
    if plan.n_boundaries() > 0 {
        let (_, d) = plan.boundary_axis();
        let bscales_all: Vec<Dataset> = scales
            .iter()
            .enumerate()
            .filter(|(k, _)| Some(*k) != d)
            .map(|(_, s)| s.clone())
            .collect();
        let (bshape, bscales) = if bscales_all.is_empty() {
            (
                vec![1],
                vec![index_coord(dims, "boundary", "the single boundary search")?],
            )
        } else {
            (plan.boundary_shape(), bscales_all)
        };
        let bs = &res.boundaries;
        for (name, long, get) in [
            (
                "fold_status",
                "fold of cycles: how the bisection ended",
                (|b: &BoundaryResult| b.fold.status) as fn(&BoundaryResult) -> BoundaryStatus,
            ),
            (
                "critical_status",
                if plan.boundary_in == squeal_scan::atlas::BoundaryParam::Lambda {
                    "critical belt speed: how the bisection ended"
                } else {
                    "critical damping: how the bisection ended"
                },
                |b: &BoundaryResult| b.critical.status,
            ),
        ] {
            let v: Vec<StatusH5> = bs
                .iter()
                .map(|b| StatusH5::from(b.as_ref().map_or(BoundaryStatus::NotComputed, get)))
                .collect();
            let ds = put(file, dims, name, &bshape, v, long, None, &bscales)?;
            flags(&ds, &status_meanings(), &[0, 1, 2, 255])?;
        }
        for c in BOUNDARY_COLUMNS {
            let v: Vec<f64> = bs
                .iter()
                .map(|b| b.as_ref().map_or(f64::NAN, |b| (c.get)(b)))
                .collect();
            let (name, long) = plan.boundary_dataset(c.name, c.long_name);
            put(
                file,
                dims,
                &name,
                &bshape,
                v.clone(),
                &long,
                Some("1"),
                &bscales,
            )?;
            if plan.units == Units::Physical {
                let mut units = "";
                let si: Vec<f64> = v
                    .iter()
                    .enumerate()
                    .map(|(j, &x)| {
                        let (i, _) = plan.boundary_setup(j);
                        plan.boundary_si(i, x).map_or(f64::NAN, |(y, u)| {
                            units = u;
                            y
                        })
                    })
                    .collect();
                let (key, _) = plan.boundary_axis();
                let long = match plan.boundary_in {
                    squeal_scan::atlas::BoundaryParam::Nu => {
                        format!("{long} (damping coefficient)")
                    }
                    squeal_scan::atlas::BoundaryParam::Lambda => format!("{long} (belt speed)"),
                };
                put(
                    file,
                    dims,
                    &name.replace(&format!("_{}", plan.boundary_in.key()), &format!("_{key}")),
                    &bshape,
                    si,
                    &long,
                    Some(units),
                    &bscales,
                )?;
            }
        }
        let notes = note_strings(
            bs.iter()
                .map(|b| b.as_ref().and_then(|b| b.note.as_deref())),
        )?;
        put(
            file,
            dims,
            "boundary_note",
            &bshape,
            notes,
            "why a boundary search was not computed (empty: none)",
            None,
            &bscales,
        )?;
        let done: Vec<u8> = bs.iter().map(|b| u8::from(b.is_some())).collect();
        put(
            file,
            dims,
            "boundaries_done",
            &bshape,
            done,
            "1 where the boundary search is computed",
            None,
            &bscales,
        )?;
    }
    Ok(())
}

/// Whether `path` is an atlas file (HDF5 with schema `squeal-atlas/...`).
pub fn is_atlas_file(path: &Path) -> bool {
    let Ok(mut f) = std::fs::File::open(path) else {
        return false;
    };
    let mut head = [0u8; 8];
    if std::io::Read::read_exact(&mut f, &mut head).is_err() || &head != b"\x89HDF\r\n\x1a\n" {
        return false;
    }
    File::open(path)
        .ok()
        .and_then(|f| crate::read::str_attr(&f, "schema").ok())
        .is_some_and(|s| s.starts_with("squeal-atlas/"))
}

/// Reads an atlas file back: its plan (from the stored spec), results and shard.
pub fn read_atlas(path: &Path) -> Result<(AtlasPlan, AtlasResults, Option<Shard>), StoreError> {
    if !is_atlas_file(path) {
        return Err(StoreError::NotSquealFile {
            path: path.to_path_buf(),
            why: format!("not an atlas file (schema {ATLAS_SCHEMA})"),
        });
    }
    let file = File::open(path).h5(path)?;
    let spec = crate::read::str_attr(&file, "spec").h5(path)?;
    let plan = AtlasPlan::from_toml(&spec, &path.display().to_string()).map_err(|e| {
        StoreError::NotSquealFile {
            path: path.to_path_buf(),
            why: format!("its spec does not validate: {e}"),
        }
    })?;
    let shard = crate::read::str_attr(&file, "shard")
        .ok()
        .and_then(|s| s.parse().ok());
    let mut res = AtlasResults::new(&plan);
    let n = plan.n_points();
    let rd_f64 = |name: &str| -> Result<Vec<f64>, StoreError> {
        let v: Vec<f64> = file.dataset(name).and_then(|d| d.read_raw()).h5(path)?;
        Ok(v)
    };
    let rd_u8 = |name: &str| -> Result<Vec<u8>, StoreError> {
        let v: Vec<u8> = file.dataset(name).and_then(|d| d.read_raw()).h5(path)?;
        Ok(v)
    };
    let done = rd_u8("points_done")?;
    let regime = rd_u8("regime")?;
    let mut pts: Vec<PointResult> = (0..n).map(|_| empty_point()).collect();
    for c in COLUMNS {
        let vals: Vec<f64> = match c.kind {
            Kind::Real => rd_f64(c.name)?,
            Kind::Flag => rd_u8(c.name)?
                .into_iter()
                .map(|v| if v == 255 { f64::NAN } else { v as f64 })
                .collect(),
            Kind::Count => {
                let v: Vec<u64> = file.dataset(c.name).and_then(|d| d.read_raw()).h5(path)?;
                v.into_iter().map(|v| v as f64).collect()
            }
        };
        for (p, v) in pts.iter_mut().zip(vals) {
            (c.set)(p, v);
        }
    }
    let notes: Vec<VarLenUnicode> = file.dataset("note").and_then(|d| d.read_raw()).h5(path)?;
    for (i, mut p) in pts.into_iter().enumerate() {
        if done.get(i) == Some(&1) {
            p.note = notes
                .get(i)
                .map(|n| n.as_str().to_string())
                .filter(|n| !n.is_empty());
            p.regime = AtlasRegime::from_u8(regime[i]).unwrap_or(AtlasRegime::Undecided);
            finish_point(&mut p);
            res.points[i] = Some(p);
        }
    }
    if plan.n_boundaries() > 0 {
        let done = rd_u8("boundaries_done")?;
        let fs = rd_u8("fold_status")?;
        let cs = rd_u8("critical_status")?;
        let bnotes: Vec<VarLenUnicode> = file
            .dataset("boundary_note")
            .and_then(|d| d.read_raw())
            .h5(path)?;
        let cols: Vec<Vec<f64>> = BOUNDARY_COLUMNS
            .iter()
            .map(|c| rd_f64(&plan.boundary_dataset(c.name, c.long_name).0))
            .collect::<Result<_, _>>()?;
        for j in 0..plan.n_boundaries() {
            if done.get(j) != Some(&1) {
                continue;
            }
            let mut b = empty_boundary(j);
            b.fold.status = BoundaryStatus::from_u8(fs[j]).unwrap_or(BoundaryStatus::NotComputed);
            b.critical.status =
                BoundaryStatus::from_u8(cs[j]).unwrap_or(BoundaryStatus::NotComputed);
            for (c, v) in BOUNDARY_COLUMNS.iter().zip(&cols) {
                (c.set)(&mut b, v[j]);
            }
            b.note = bnotes
                .get(j)
                .map(|n| n.as_str().to_string())
                .filter(|n| !n.is_empty());
            res.boundaries[j] = Some(b);
        }
    }
    Ok((plan, res, shard))
}

/// Joins atlas shard files (all `N` shards of one spec) into the file one run writes.
pub fn merge_atlas(
    shards: &[PathBuf],
    out: &Path,
    force: bool,
    prov: &Provenance,
) -> Result<(), StoreError> {
    if out.exists() && !force {
        return Err(StoreError::Exists {
            path: out.to_path_buf(),
        });
    }
    let mut plan: Option<AtlasPlan> = None;
    let mut res: Option<AtlasResults> = None;
    let mut seen = HashSet::new();
    let mut n_shards = None;
    for p in shards {
        let (pl, r, s) = read_atlas(p)?;
        let s = s.ok_or_else(|| {
            StoreError::Shards(format!(
                "{} is not a shard file (no `shard` attribute)",
                p.display()
            ))
        })?;
        if *n_shards.get_or_insert(s.n) != s.n || !seen.insert(s.k) {
            return Err(StoreError::Shards(format!(
                "{}: shard {s} repeats or does not match the others",
                p.display()
            )));
        }
        match (&plan, &mut res) {
            (Some(p0), Some(acc)) => {
                if p0.spec_text != pl.spec_text {
                    return Err(StoreError::SpecMismatch {
                        path: p.clone(),
                        why: "different spec text".into(),
                    });
                }
                for (a, b) in acc.points.iter_mut().zip(r.points) {
                    if b.is_some() {
                        *a = b;
                    }
                }
                for (a, b) in acc.boundaries.iter_mut().zip(r.boundaries) {
                    if b.is_some() {
                        *a = b;
                    }
                }
            }
            _ => {
                plan = Some(pl);
                res = Some(r);
            }
        }
    }
    let (Some(plan), Some(res)) = (plan, res) else {
        return Err(StoreError::Shards("no shard files given".into()));
    };
    if seen.len() != n_shards.unwrap_or(0) {
        return Err(StoreError::Shards(format!(
            "{} of {} shards given",
            seen.len(),
            n_shards.unwrap_or(0)
        )));
    }
    let missing = missing_units(&plan, &res, None);
    if !missing.is_empty() {
        return Err(StoreError::Incomplete {
            path: out.to_path_buf(),
            missing: missing.len(),
            total: plan.units().len(),
        });
    }
    write_atlas(out, &plan, &res, prov, None)
}

/// Per-point (or per-boundary) notes as HDF5 strings, empty where there is none.
fn note_strings<'a>(
    notes: impl Iterator<Item = Option<&'a str>>,
) -> hdf5::Result<Vec<VarLenUnicode>> {
    notes
        .map(|n| {
            n.unwrap_or_default()
                .parse::<VarLenUnicode>()
                .map_err(|e| hdf5::Error::from(format!("note: {e}")))
        })
        .collect()
}
