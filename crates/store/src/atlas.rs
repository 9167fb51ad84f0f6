//! Atlas files: the journal of finished units, the HDF5 file, reading it back, merging
//! shards.
//!
//! ## Journal `<out>.journal`
//! The scan's journal (`crate::journal`: checksummed binary records, fsynced after each,
//! corrupt records skipped with a warning on resume) with an atlas header (kind `A`, the
//! spec text and shard) and one record per finished unit (kind `U`: a line of points or a
//! boundary search as the JSON of [`unit_json`], the figures as arrays in the order of
//! [`squeal_scan::atlas::columns`], NaN as `null`). With maps, also the scan's block (`B`,
//! the map index being the point) and cycle (`C`) records. While a writer lives it holds the
//! [`OutputLock`] `<out>.lock` (as the scan does), so two runs never write the same file; a
//! lock left by a dead process is taken over; `--resume` reopens the journal.
//!
//! ## HDF5 schema `squeal-atlas/1`
//! ```text
//! /  attrs: schema, squeal_version, git_revision, spec (TOML text), name, law, units
//!           ("nondimensional" | "physical"), solver, dt, every fixed parameter (f64, with
//!           <key>_units), operating_point_x/_v, disturbance_x/_v ([min, max]), shard
//! coordinates (dimension scales, attrs long_name, units): one per swept parameter, in
//!           axis order (nu, lambda, tau, phi | m, k, c, v_belt, mu_k, mu_s, tau, g |
//!           xi, v_d, mu_d, mu_sd, v_0, mu_v);
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
//!   landscape      (law = "stribeck") u8 enum {unknown=0, stick_slip_only=1, bistable=2,
//!                  steady_slip_only=3, not_computed=255}; CF flags; with
//!                  fixed_point_damping, stick_cycle_period, stick_cycle_stuck  f64, its
//!                  evidence (squeal_scan::landscape::LANDSCAPE_FIELDS); the stick-slip
//!                  figure stick_quasi_static_share is stored as stick_stuck_share
//!   note           string: why a point is undecided, or the caveat of its label
//!   points_done    u8: 1 where computed (shards)
//! over the swept dims except the damping (nu or c):
//!   fold_status, critical_status  u8 enum {found=0, below_range=1, above_range=2,
//!                                 not_computed=255}
//!   fold_nu, fold_nu_lo, fold_nu_hi, critical_nu, critical_nu_lo, critical_nu_hi   f64
//!                 (bisected in lambda: fold_lambda, ...; law = "stribeck": fold_xi, ... or
//!                 fold_v_d, ...)
//!   fold_half_dt, critical_half_dt  u8 {moves=0, holds=1, not_checked=255}: the
//!                 bracket's predicate again at dt/2 at both ends
//!   fold_nu_err   f64: the fold's uncertainty (McMillan's laws: the crisis of the band,
//!                 the fold is fold_nu -+ fold_nu_err at dt, dt/2 and the longer horizon)
//!   fold_changes  u32: changes of regime the coarse scan found before bisecting (> 1:
//!                 the regime flips along the parameter; the note lists it)
//!   fold_c, ..., critical_c_hi    (physical specs) in N s/m
//!   boundary_note                 string: why a search was not computed
//!   boundaries_done               u8
//! with basin maps (spec [grid]; root attrs also scheme, x0_min/_max, v0_min/_max,
//! block_rows, t_max, fp_radius, settle_cycles, settle_rtol, early_stop, trap_margin,
//! audit_every; coordinates x0, v0, block, cycle_point):
//!   map_<column>  over (swept dims..., v0, x0): every column of squeal_scan::cell::COLUMNS
//!                 (map_labels, map_reason, map_t_decision, ..., map_audit) with its
//!                 long_name, units, fill and CF flags, chunked one block of rows
//!   blocks_done   u8 over (swept dims..., block)
//!   map_<check>   i64 over the swept dims: squeal_scan::checks::CHECK_FIELDS
//!   basin_fraction, basin_fraction_err   from the map (attr source = "map"): steady-slip
//!                 cells over decided cells; err = (undecided cells + decided cells within
//!                 one cell of the located cycle) / cells
//!   basin_fraction_cycle, basin_fraction_cycle_err   the point's own, from its cycle
//!   map_undecided_cells, map_cells_near_cycle        u64, the counts behind err
//!   map_cycle_record  string: the map's cycle search (TOML, as the scan stores it)
//!   map_cycle_x, map_cycle_v  over (swept dims..., cycle_point): the located cycle of
//!                 each map, NaN-padded
//! ```

use std::collections::HashSet;
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

use squeal_scan::atlas::MapFraction;
use squeal_scan::atlas::stribeck::LANDSCAPE_COLUMNS;
use squeal_scan::cell::Cell;
use squeal_scan::ulc::CycleOutcome;

use crate::error::{H5Ctx, io};
use crate::h5write::{Dims, class_type, num_attr, str_attr};
use crate::journal::{
    Header, Journal, KIND_BLOCK, KIND_CYCLE, KIND_UNIT, Owner, decode_block, decode_cycle,
    encode_block, encode_cycle,
};
use crate::{OutputLock, Provenance, Shard, StoreError};

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

/// Everything computed so far (computed in squeal-scan; persisted here).
pub use squeal_scan::atlas::AtlasResults;

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

/// The map blocks `(point, block)` that `shard` owns and that are not stored yet (none
/// without a `[grid]`). Ownership is the scan's ([`squeal_scan::shard_owns`]).
pub fn missing_blocks(
    plan: &AtlasPlan,
    res: &AtlasResults,
    shard: Option<Shard>,
) -> Vec<(usize, usize)> {
    let Some(mp) = plan.map_plan() else {
        return Vec::new();
    };
    let nb = mp.grid.blocks();
    (0..mp.maps.len())
        .flat_map(|m| (0..nb).map(move |b| (m, b)))
        .filter(|&(m, b)| {
            squeal_scan::shard_owns(shard, &mp, m, b) && !res.blocks.contains_key(&(m, b))
        })
        .collect()
}

fn num(v: f64) -> Value {
    if v.is_finite() { json!(v) } else { Value::Null }
}

fn point_json(p: &PointResult) -> Value {
    let mut o = json!({
        "regime": p.regime as u8,
        "note": p.note,
        "v": COLUMNS.iter().map(|c| num((c.get)(p))).collect::<Vec<_>>(),
    });
    if let Some(l) = p.landscape {
        // Laws with true stick: the landscape and the numbers it rests on.
        let mut v = vec![json!(l.landscape)];
        v.extend(LANDSCAPE_COLUMNS.iter().map(|c| num((c.get)(p))));
        o["l"] = Value::Array(v);
    }
    o
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
    if let Some(l) = v.get("l") {
        let l = l.as_array()?;
        if l.len() != LANDSCAPE_COLUMNS.len() + 1 {
            return None;
        }
        for (c, x) in LANDSCAPE_COLUMNS.iter().zip(&l[1..]) {
            (c.set)(&mut p, x.as_f64().unwrap_or(f64::NAN));
        }
        stribeck_landscape(&mut p, l[0].as_u64()? as u8);
    }
    finish_point(&mut p);
    Some(p)
}

/// Sets the stored landscape verdict of a point (laws with true stick).
fn stribeck_landscape(p: &mut PointResult, v: u8) {
    if let Some(l) = p.landscape.as_mut() {
        l.landscape = v;
    } else {
        p.landscape = Some(squeal_scan::atlas::stribeck::LandscapeRecord {
            landscape: v,
            damping: f64::NAN,
            cycle_period: f64::NAN,
            cycle_stuck: f64::NAN,
        });
    }
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
            "fold_half_dt": b.fold.half_dt_holds,
            "critical_half_dt": b.critical.half_dt_holds,
            "fold_changes": b.fold.changes,
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
    b.fold.half_dt_holds = v.get("fold_half_dt").and_then(Value::as_bool);
    b.critical.half_dt_holds = v.get("critical_half_dt").and_then(Value::as_bool);
    b.fold.changes = v.get("fold_changes").and_then(Value::as_u64).unwrap_or(0) as u32;
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

/// Adds one journal record to `results`: a unit, or a map's block or cycle search. A record
/// that checks out but does not fit the plan is an error (not a torn write).
fn add_record(
    plan: &AtlasPlan,
    results: &mut AtlasResults,
    kind: u8,
    payload: &[u8],
) -> Result<(), String> {
    let grid = plan.maps.as_ref().map(|m| m.grid);
    match (kind, grid) {
        (KIND_UNIT, _) => {
            let unit = serde_json::from_slice::<Value>(payload)
                .ok()
                .and_then(|v| unit_from_json(&v))
                .ok_or("a malformed unit record")?;
            results.add(plan, unit);
        }
        (KIND_BLOCK, Some(g)) => {
            let (m, b, cells) = decode_block(payload).ok_or("a malformed block record")?;
            if !(m < plan.n_points()
                && b < g.blocks()
                && cells.len() == g.block_rows(b).len() * g.x0.count)
            {
                return Err("a map block that does not fit the spec".into());
            }
            results.blocks.insert((m, b), cells);
        }
        (KIND_CYCLE, Some(_)) => {
            let (m, c) = decode_cycle(payload).ok_or("a malformed cycle record")?;
            if m >= plan.n_points() {
                return Err("a map cycle that does not fit the spec".into());
            }
            results.map_cycles.insert(m, c);
        }
        (k, _) => return Err(format!("a record of kind {k} that an atlas does not write")),
    }
    Ok(())
}

fn journal_path(out: &Path) -> PathBuf {
    let mut s = out.as_os_str().to_owned();
    s.push(".journal");
    PathBuf::from(s)
}

/// Journals finished units and writes the atlas file at the end.
pub struct AtlasWriter {
    out: PathBuf,
    journal: Journal,
    plan: AtlasPlan,
    shard: Option<Shard>,
    prov: Provenance,
    /// What is stored so far.
    pub results: AtlasResults,
    _lock: OutputLock,
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
        if let Some(d) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(d).map_err(io(d, "cannot create folder"))?;
        }
        // Two runs never write one output: the lock first, then the checks.
        let lock = OutputLock::acquire(out)?;
        let path = journal_path(out);
        if !force {
            if path.exists() {
                return Err(StoreError::Interrupted { path });
            }
            if out.exists() {
                return Err(StoreError::Exists {
                    path: out.to_path_buf(),
                });
            }
        } else if path.exists() {
            std::fs::remove_file(&path).map_err(io(&path, "cannot remove"))?;
        }
        let journal = Journal::create(
            &path,
            &Header {
                owner: Owner::Atlas,
                spec: plan.spec_text.clone(),
                shard: shard.map(|s| s.to_string()).unwrap_or_default(),
            },
        )?;
        Ok(AtlasWriter {
            out: out.to_path_buf(),
            journal,
            plan: plan.clone(),
            shard,
            prov: prov.clone(),
            results: AtlasResults::new(plan),
            _lock: lock,
        })
    }

    /// Reopens the journal of an interrupted atlas (a spec that computes the same and the
    /// same shard required, as a scan's).
    pub fn resume(
        out: &Path,
        plan: &AtlasPlan,
        shard: Option<Shard>,
        prov: &Provenance,
    ) -> Result<AtlasWriter, StoreError> {
        let lock = OutputLock::acquire(out)?;
        let path = journal_path(out);
        if !path.exists() {
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
        let (mut journal, header, recs) = Journal::open(&path, Owner::Atlas)?;
        let mismatch = |why: &str| StoreError::SpecMismatch {
            path: path.clone(),
            why: why.to_string(),
        };
        // As a scan's: what the spec means, not its bytes (a comment edit does not block a
        // resume); the file then records the spec text the atlas started with.
        let plan = &crate::output::started_plan(&path, &header.spec, plan, &plan.spec_text)?;
        if header.shard != shard.map(|s| s.to_string()).unwrap_or_default() {
            return Err(mismatch("different --shard"));
        }
        let mut results = AtlasResults::new(plan);
        for r in recs {
            let payload = journal.read(&r)?;
            add_record(plan, &mut results, r.kind, &payload).map_err(|why| {
                StoreError::NotSquealFile {
                    path: path.clone(),
                    why,
                }
            })?;
        }
        Ok(AtlasWriter {
            out: out.to_path_buf(),
            journal,
            plan: plan.clone(),
            shard,
            prov: prov.clone(),
            results,
            _lock: lock,
        })
    }

    /// The plan being written (after a resume: the one the atlas started with).
    pub fn plan(&self) -> &AtlasPlan {
        &self.plan
    }

    /// The units still to compute.
    pub fn missing(&self) -> Vec<Unit> {
        missing_units(&self.plan, &self.results, self.shard)
    }

    /// The map blocks still to compute.
    pub fn missing_blocks(&self) -> Vec<(usize, usize)> {
        missing_blocks(&self.plan, &self.results, self.shard)
    }

    /// Journals a finished unit (fsynced) and keeps it.
    pub fn record(&mut self, r: UnitResult) -> Result<(), StoreError> {
        self.journal
            .append(KIND_UNIT, unit_json(&r).to_string().as_bytes())?;
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
        let blocks = self.missing_blocks();
        if !blocks.is_empty() {
            return Err(StoreError::Incomplete {
                path: self.out.clone(),
                missing: blocks.len(),
                total: self.plan.map_plan().map_or(0, |p| p.total_blocks()),
            });
        }
        write_atlas(&self.out, &self.plan, &self.results, &self.prov, self.shard)?;
        let path = self.journal.path.clone();
        std::fs::remove_file(&path).map_err(io(&path, "cannot remove"))?;
        Ok(self.results)
    }
}

/// The atlas's maps come from the scan's driver ([`squeal_scan::drive`] on
/// [`AtlasPlan::map_plan`]): each finished block and cycle search is journalled (fsynced).
impl squeal_scan::Sink for AtlasWriter {
    type Error = StoreError;
    fn is_done(&self, map: usize, block: usize) -> bool {
        self.results.blocks.contains_key(&(map, block))
    }
    fn has_cycle(&self, map: usize) -> bool {
        self.results.map_cycles.contains_key(&map)
    }
    fn write_cycle(&mut self, map: usize, cycle: Option<&CycleOutcome>) -> Result<(), StoreError> {
        self.journal
            .append(KIND_CYCLE, &encode_cycle(map, &cycle.cloned()))?;
        self.results.map_cycles.insert(map, cycle.cloned());
        Ok(())
    }
    fn write_block(&mut self, b: &squeal_scan::BlockResult) -> Result<(), StoreError> {
        let g = self.plan.maps.as_ref().map(|m| m.grid);
        let fits = g.is_some_and(|g| {
            b.map < self.plan.n_points()
                && b.block < g.blocks()
                && b.cells.len() == g.block_rows(b.block).len() * g.x0.count
        });
        if !fits {
            return Err(StoreError::BadBlock {
                path: self.out.clone(),
                why: format!("map {} block {} does not fit the atlas", b.map, b.block),
            });
        }
        self.journal
            .append(KIND_BLOCK, &encode_block(b.map, b.block, &b.cells))?;
        self.results
            .blocks
            .insert((b.map, b.block), b.cells.clone());
        Ok(())
    }
}

fn put<T: H5Type>(
    file: &File,
    dims: &mut Dims,
    (name, long_name, units): (&str, &str, Option<&str>),
    shape: &[usize],
    data: Vec<T>,
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

/// Long names of the boundaries' dt/2 checks.
const HALF_DT_FOLD: &str = "fold of cycles: 1 if at dt/2 the predicate still holds at both ends of the bracket (the fold at dt/2 lies in it), 0 if it moved out, 255 not checked";
const HALF_DT_CRITICAL: &str = "critical value: 1 if at dt/2 the operating point still squeals at the lower end and is quiet at the upper, 0 if the boundary moved out, 255 not checked";

const FOLD_CHANGES: &str = "fold: changes of regime (squeal lasting or not) the coarse scan found along the bisected parameter before bisecting; more than 1: the regime flips back and forth and the fold is the last change (0: no coarse scan)";

/// The stored value of a dt/2 check.
fn half_dt_u8(h: Option<bool>) -> u8 {
    match h {
        Some(true) => 1,
        Some(false) => 0,
        None => 255,
    }
}

fn u8_of(v: f64) -> u8 {
    if v.is_nan() { 255 } else { v as u8 }
}

/// The stored `landscape` of a point not computed.
const LANDSCAPE_NOT_COMPUTED: u8 = 255;

/// The CF flag values and meanings of the per-point `landscape` enum.
fn landscape_flags() -> (Vec<u8>, String) {
    let mut values: Vec<u8> = squeal_core::Landscape::ALL
        .iter()
        .map(|l| *l as u8)
        .collect();
    let mut names: Vec<&str> = squeal_core::Landscape::ALL
        .iter()
        .map(|l| l.name())
        .collect();
    values.push(LANDSCAPE_NOT_COMPUTED);
    names.push("not_computed");
    (values, names.join(" "))
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
    let written = (|| {
        let file = File::create(&tmp).h5(&tmp)?;
        let mut dims = Dims {
            scales: Vec::new(),
            class_type: class_type(&tmp)?,
        };
        write_all(&file, &mut dims, plan, res, prov, shard).h5(&tmp)?;
        dims.finish().h5(&tmp)?;
        file.close().h5(&tmp)
    })();
    if let Err(e) = written {
        // A full disk: leave no partial file; the journal keeps the work for a resume.
        let _ = std::fs::remove_file(&tmp);
        return Err(e);
    }
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
    str_attr(file, "scheme", plan.solver.scheme.name())?;
    num_attr(file, "dt", plan.dt)?;
    for (a, v) in plan.fixed() {
        num_attr(file, a.key, v)?;
        str_attr(file, &format!("{}_units", a.key), a.units)?;
    }
    let ps = &plan.point;
    num_attr(file, "operating_point_x", ps.operating.x)?;
    num_attr(file, "operating_point_v", ps.operating.v)?;
    let (xu, vu) = if plan.units == Units::Physical {
        ("m", "m/s")
    } else {
        ("1", "1")
    };
    str_attr(file, "operating_point_x_units", xu)?;
    str_attr(file, "operating_point_v_units", vu)?;
    let du = plan.disturbance_units();
    for ((k, r), u) in [
        ("disturbance_x", ps.disturbance.x),
        ("disturbance_v", ps.disturbance.v),
    ]
    .into_iter()
    .zip(du)
    {
        file.new_attr::<f64>().shape(2).create(k)?.write_raw(&r)?;
        str_attr(file, &format!("{k}_units"), u)?;
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
        ("regime", "regime of the parameter point", None),
        &shape,
        regimes,
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
        // With maps the reported basin fraction is the map's; the cycle's is kept beside it.
        let (name, long) = stored_name(plan, c);
        match c.kind {
            Kind::Real => {
                put(
                    file,
                    dims,
                    (&name, &long, Some(units)),
                    &shape,
                    vals.clone(),
                    &pscales,
                )?;
            }
            Kind::Flag => {
                let v: Vec<u8> = vals.iter().map(|&v| u8_of(v)).collect();
                let ds = put(file, dims, (c.name, c.long_name, None), &shape, v, &pscales)?;
                flags(&ds, "no yes unknown", &[0, 1, 255])?;
            }
            Kind::Count => {
                let v: Vec<u64> = vals
                    .iter()
                    .map(|&v| if v.is_nan() { 0 } else { v as u64 })
                    .collect();
                put(file, dims, (c.name, c.long_name, None), &shape, v, &pscales)?;
            }
        }
        if plan.units == Units::Physical && c.si != Si::None {
            let si: Vec<f64> = vals
                .iter()
                .zip(&scales_at)
                .map(|(&v, s)| s.map_or(f64::NAN, |s| c.si.convert(v, &s)))
                .collect();
            let long = c.si.long_name(c.long_name);
            put(
                file,
                dims,
                (&format!("{}_si", c.name), &long, Some(c.si.units())),
                &shape,
                si,
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
                (&format!("nondim_{key}"), long, Some(units)),
                &shape,
                v,
                &pscales,
            )?;
        }
    }
    if plan.law.has_true_stick() {
        // The landscape of each point (as `squeal scan` stores per map) and its evidence.
        let v: Vec<u8> = res
            .points
            .iter()
            .map(|p| {
                p.as_ref()
                    .and_then(|p| p.landscape)
                    .map_or(LANDSCAPE_NOT_COMPUTED, |l| l.landscape)
            })
            .collect();
        let (name, long) = squeal_scan::landscape::LANDSCAPE;
        let ds = put(file, dims, (name, long, None), &shape, v, &pscales)?;
        let (values, meanings) = landscape_flags();
        flags(&ds, &meanings, &values)?;
        for c in LANDSCAPE_COLUMNS {
            let vals: Vec<f64> = res
                .points
                .iter()
                .map(|p| p.as_ref().map_or(f64::NAN, |p| (c.get)(p)))
                .collect();
            put(
                file,
                dims,
                (c.name, c.long_name, Some("1")),
                &shape,
                vals,
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
        (
            "note",
            "why a point is undecided, or the caveat its label rests on (empty: none)",
            None,
        ),
        &shape,
        notes,
        &pscales,
    )?;
    if plan.maps.is_some() {
        write_maps(file, dims, plan, res, &shape, &pscales)?;
    }
    let done: Vec<u8> = res.points.iter().map(|p| u8::from(p.is_some())).collect();
    put(
        file,
        dims,
        ("points_done", "1 where the point is computed", None),
        &shape,
        done,
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
            let ds = put(file, dims, (name, long, None), &bshape, v, &bscales)?;
            flags(&ds, &status_meanings(), &[0, 1, 2, 255])?;
        }
        for (name, long, get) in [
            (
                "fold_half_dt",
                HALF_DT_FOLD,
                (|b: &BoundaryResult| b.fold.half_dt_holds) as fn(&BoundaryResult) -> Option<bool>,
            ),
            (
                "critical_half_dt",
                HALF_DT_CRITICAL,
                |b: &BoundaryResult| b.critical.half_dt_holds,
            ),
        ] {
            let v: Vec<u8> = bs
                .iter()
                .map(|b| half_dt_u8(b.as_ref().and_then(get)))
                .collect();
            let ds = put(file, dims, (name, long, None), &bshape, v, &bscales)?;
            flags(&ds, "moves holds not_checked", &[0, 1, 255])?;
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
                (&name, &long, Some("1")),
                &bshape,
                v.clone(),
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
                        long.replace("damping ratio", "damping coefficient c")
                    }
                    squeal_scan::atlas::BoundaryParam::Lambda => {
                        long.replace("belt speed lambda", "belt speed v_belt")
                    }
                };
                put(
                    file,
                    dims,
                    (
                        &name.replace(&format!("_{}", plan.boundary_in.key()), &format!("_{key}")),
                        &long,
                        Some(units),
                    ),
                    &bshape,
                    si,
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
            (
                "boundary_note",
                "why a boundary search was not computed (empty: none)",
                None,
            ),
            &bshape,
            notes,
            &bscales,
        )?;
        let changes: Vec<u32> = bs
            .iter()
            .map(|b| b.as_ref().map_or(0, |b| b.fold.changes))
            .collect();
        put(
            file,
            dims,
            ("fold_changes", FOLD_CHANGES, Some("1")),
            &bshape,
            changes,
            &bscales,
        )?;
        let done: Vec<u8> = bs.iter().map(|b| u8::from(b.is_some())).collect();
        put(
            file,
            dims,
            (
                "boundaries_done",
                "1 where the boundary search is computed",
                None,
            ),
            &bshape,
            done,
            &bscales,
        )?;
    }
    Ok(())
}

/// The dataset name and long name of a point column: with maps, `basin_fraction` and
/// `basin_fraction_err` are the map's, and the point's own (from the cycle) are stored as
/// `basin_fraction_cycle` and `basin_fraction_cycle_err`.
fn stored_name(plan: &AtlasPlan, c: &squeal_scan::atlas::columns::Column) -> (String, String) {
    if plan.law.has_true_stick() && c.name == "stick_quasi_static_share" {
        let (name, long) = squeal_scan::atlas::stribeck::STUCK_SHARE;
        return (name.into(), long.into());
    }
    match (plan.maps.is_some(), c.name) {
        (true, "basin_fraction") => (
            "basin_fraction_cycle".into(),
            format!("{} (from the unstable cycle)", c.long_name),
        ),
        (true, "basin_fraction_err") => (
            "basin_fraction_cycle_err".into(),
            format!("{} (from the unstable cycle)", c.long_name),
        ),
        _ => (c.name.to_string(), c.long_name.to_string()),
    }
}

/// The dataset of a per-cell column (or a per-map check) in an atlas file: `map_` and its
/// name in [`squeal_scan::cell::COLUMNS`] (a point's own columns such as `evaluations`
/// keep their names).
pub fn map_name(column: &str) -> String {
    format!("map_{column}")
}

/// The basin maps: every column of [`squeal_scan::cell::COLUMNS`] over (the swept
/// parameters..., v0, x0), the per-map checks and cycles, and the basin fraction read off
/// each map.
fn write_maps(
    file: &File,
    dims: &mut Dims,
    plan: &AtlasPlan,
    res: &AtlasResults,
    shape: &[usize],
    pscales: &[Dataset],
) -> hdf5::Result<()> {
    let Some(mp) = plan.map_plan() else {
        return Ok(());
    };
    let g = mp.grid;
    let (nx, nv) = (g.x0.count, g.v0.count);
    let coord = |dims: &mut Dims, name: &str, values: &[f64], long: &str| {
        let ds = file
            .new_dataset_builder()
            .obj_track_times(false)
            .with_data(values)
            .create(name)?;
        str_attr(&ds, "long_name", long)?;
        str_attr(&ds, "units", "1")?;
        dims.scale(&ds, name)?;
        Ok::<_, hdf5::Error>(ds)
    };
    let x0 = coord(dims, "x0", &g.x0.values(), "initial displacement x(0)")?;
    let v0 = coord(dims, "v0", &g.v0.values(), "initial velocity x'(0)")?;
    let blocks: Vec<u64> = (0..g.blocks() as u64).collect();
    let block_dim = file
        .new_dataset_builder()
        .obj_track_times(false)
        .with_data(&blocks)
        .create("block")?;
    str_attr(&block_dim, "long_name", "block of grid rows")?;
    dims.scale(&block_dim, "block")?;
    for (k, v) in [
        ("x0_min", g.x0.min),
        ("x0_max", g.x0.max),
        ("v0_min", g.v0.min),
        ("v0_max", g.v0.max),
    ] {
        num_attr(file, k, v)?;
    }
    num_attr(file, "block_rows", g.block_rows as u64)?;
    num_attr(file, "t_max", mp.classifier.t_max)?;
    num_attr(file, "fp_radius", mp.classifier.fp_radius)?;
    num_attr(file, "settle_cycles", mp.classifier.settle_cycles)?;
    num_attr(file, "settle_rtol", mp.classifier.settle_rtol)?;
    str_attr(file, "early_stop", mp.early_stop.name())?;
    num_attr(file, "trap_margin", mp.trap_margin)?;
    num_attr(file, "audit_every", mp.audit_every)?;

    let mut mshape = shape.to_vec();
    mshape.extend([nv, nx]);
    let rows_per_chunk = g.block_rows.min(nv).min((1usize << 24) / nx.max(1)).max(1);
    let mut chunk = vec![1; shape.len()];
    chunk.extend([rows_per_chunk, nx]);
    let mut mdims: Vec<&Dataset> = pscales.iter().collect();
    mdims.extend([&v0, &x0]);
    let vars: Vec<Dataset> = squeal_scan::cell::COLUMNS
        .iter()
        .map(|col| crate::h5write::column_dataset(file, col, &map_name(col.name), &mshape, &chunk))
        .collect::<hdf5::Result<_>>()?;
    for v in &vars {
        dims.attach(file, v, &mdims)?;
    }
    let n = plan.n_points();
    let nb = g.blocks();
    let mut done = vec![0u8; n * nb];
    let mut checks = Vec::with_capacity(n);
    for i in 0..n {
        let prefix = if plan.axes().is_empty() {
            vec![0]
        } else {
            plan.unravel(i)
        };
        let curve = res.map_cycle(i).map(|r| &r.curve);
        let escapes = res.map_cycle(i).is_some_and(|r| r.escape.is_some());
        // Laws with true stick: the map's cells are checked against the point's landscape
        // (every cell steady slip, or every cell stick-slip, where it says so).
        let landscape = res.points[i]
            .as_ref()
            .and_then(|p| p.landscape)
            .and_then(|l| l.verdict());
        let mut ck = squeal_scan::MapChecks::new(curve, landscape, escapes);
        for b in 0..nb {
            let Some(cells) = res.blocks.get(&(i, b)) else {
                continue;
            };
            done[i * nb + b] = 1;
            ck.add_block(&mp, curve, b, cells);
            for (ds, col) in vars.iter().zip(squeal_scan::cell::COLUMNS) {
                crate::h5write::write_column(ds, col, cells, &prefix, g.block_rows(b), nx)?;
            }
        }
        checks.push(ck);
    }
    let mut bshape = shape.to_vec();
    bshape.push(nb);
    let mut bdims = pscales.to_vec();
    bdims.push(block_dim.clone());
    put(
        file,
        dims,
        (
            "blocks_done",
            "1 where the block of map rows is stored",
            None,
        ),
        &bshape,
        done,
        &bdims,
    )?;
    for (k, (name, long)) in squeal_scan::checks::CHECK_FIELDS.iter().enumerate() {
        let v: Vec<i64> = checks.iter().map(|c| c.values()[k]).collect();
        put(
            file,
            dims,
            (&map_name(name), long, Some("1")),
            shape,
            v,
            pscales,
        )?;
    }

    // The basin fraction read off each map.
    let fr: Vec<Option<MapFraction>> = (0..n).map(|i| res.map_fraction(plan, i)).collect();
    let real = |f: fn(&MapFraction) -> f64| -> Vec<f64> {
        fr.iter().map(|x| x.as_ref().map_or(f64::NAN, f)).collect()
    };
    let count = |f: fn(&MapFraction) -> u64| -> Vec<u64> {
        fr.iter().map(|x| x.as_ref().map_or(0, f)).collect()
    };
    let ds = put(
        file,
        dims,
        (
            "basin_fraction",
            "share of the grid box that returns to steady slip, from the basin map: steady-slip cells over decided cells",
            Some("1"),
        ),
        shape,
        real(|f| f.fraction),
        pscales,
    )?;
    str_attr(&ds, "source", "map")?;
    put(
        file,
        dims,
        (
            "basin_fraction_err",
            "uncertainty of basin_fraction: (undecided cells + decided cells within one cell of the located cycle) over all cells",
            Some("1"),
        ),
        shape,
        real(|f| f.err),
        pscales,
    )?;
    put(
        file,
        dims,
        (
            "map_undecided_cells",
            "cells of the map left undecided (or not computed)",
            Some("1"),
        ),
        shape,
        count(|f| f.undecided),
        pscales,
    )?;
    put(
        file,
        dims,
        (
            "map_cells_near_cycle",
            "decided cells within one cell of the located cycle",
            Some("1"),
        ),
        shape,
        count(|f| f.near_cycle),
        pscales,
    )?;

    // Each map's cycle search: the record (TOML, exact) and the closed curve, NaN-padded.
    let recs: Vec<Option<&Option<CycleOutcome>>> = (0..n).map(|i| res.map_cycles.get(&i)).collect();
    let texts: Vec<String> = recs
        .iter()
        .map(|r| r.map_or(String::new(), |c| crate::cycle::to_text(c, false)))
        .collect();
    let notes = note_strings(texts.iter().map(|t| Some(t.as_str())))?;
    put(
        file,
        dims,
        (
            "map_cycle_record",
            "cycle search of the map (TOML; empty: not recorded)",
            None,
        ),
        shape,
        notes,
        pscales,
    )?;
    let len = (0..n)
        .filter_map(|i| res.map_cycle(i).map(|r| r.curve.x.len()))
        .max()
        .unwrap_or(0);
    if len > 0 {
        let pts: Vec<u64> = (0..len as u64).collect();
        let pdim = file
            .new_dataset_builder()
            .obj_track_times(false)
            .with_data(&pts)
            .create("cycle_point")?;
        str_attr(&pdim, "long_name", "step along the closed curve")?;
        dims.scale(&pdim, "cycle_point")?;
        let mut cshape = shape.to_vec();
        cshape.push(len);
        let mut cdims = pscales.to_vec();
        cdims.push(pdim);
        for (name, long, get) in [
            (
                "map_cycle_x",
                "displacement x on the located cycle of the map (NaN-padded)",
                (|r: &squeal_scan::ulc::CycleReport| &r.curve.x) as fn(&_) -> &Vec<f64>,
            ),
            (
                "map_cycle_v",
                "velocity x' on the located cycle of the map (NaN-padded)",
                |r: &squeal_scan::ulc::CycleReport| &r.curve.v,
            ),
        ] {
            let mut v = vec![f64::NAN; n * len];
            for i in 0..n {
                if let Some(r) = res.map_cycle(i) {
                    let c = get(r);
                    v[i * len..i * len + c.len()].copy_from_slice(c);
                }
            }
            put(file, dims, (name, long, Some("1")), &cshape, v, &cdims)?;
        }
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
    let mut plan = AtlasPlan::from_toml(&spec, &path.display().to_string()).map_err(|e| {
        StoreError::NotSquealFile {
            path: path.to_path_buf(),
            why: format!("its spec does not validate: {e}"),
        }
    })?;
    // A spec without `name` is named after its own file, not this one (a shard `s1.h5`).
    plan.name = crate::read::str_attr(&file, "name").h5(path)?;
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
        let (name, _) = stored_name(&plan, c);
        let vals: Vec<f64> = match c.kind {
            Kind::Real => rd_f64(&name)?,
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
    if plan.law.has_true_stick() {
        for c in LANDSCAPE_COLUMNS {
            for (p, v) in pts.iter_mut().zip(rd_f64(c.name)?) {
                (c.set)(p, v);
            }
        }
        let (name, _) = squeal_scan::landscape::LANDSCAPE;
        for (p, v) in pts.iter_mut().zip(rd_u8(name)?) {
            if v == LANDSCAPE_NOT_COMPUTED {
                p.landscape = None;
            } else {
                stribeck_landscape(p, v);
            }
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
    if plan.maps.is_some() {
        read_maps(&file, path, &plan, &mut res)?;
    }
    if plan.n_boundaries() > 0 {
        let done = rd_u8("boundaries_done")?;
        let fs = rd_u8("fold_status")?;
        let cs = rd_u8("critical_status")?;
        // Files written before the dt/2 check lack these: not checked.
        let half = |name: &str| -> Result<Vec<u8>, StoreError> {
            if file.link_exists(name) {
                rd_u8(name)
            } else {
                Ok(Vec::new())
            }
        };
        let (fh, ch) = (half("fold_half_dt")?, half("critical_half_dt")?);
        // Files written before the coarse scan lack it: 0, none.
        let fold_changes: Vec<u32> = if file.link_exists("fold_changes") {
            file.dataset("fold_changes")
                .and_then(|d| d.read_raw())
                .h5(path)?
        } else {
            Vec::new()
        };
        let holds = |v: &[u8], j: usize| match v.get(j) {
            Some(1) => Some(true),
            Some(0) => Some(false),
            _ => None,
        };
        let bnotes: Vec<VarLenUnicode> = file
            .dataset("boundary_note")
            .and_then(|d| d.read_raw())
            .h5(path)?;
        // Files written before the fold's uncertainty lack fold_nu_err: NaN, not estimated.
        let cols: Vec<Vec<f64>> = BOUNDARY_COLUMNS
            .iter()
            .map(|c| {
                let name = plan.boundary_dataset(c.name, c.long_name).0;
                match file.link_exists(&name) {
                    true => rd_f64(&name),
                    false => Ok(vec![f64::NAN; plan.n_boundaries()]),
                }
            })
            .collect::<Result<_, _>>()?;
        for j in 0..plan.n_boundaries() {
            if done.get(j) != Some(&1) {
                continue;
            }
            let mut b = empty_boundary(j);
            b.fold.status = BoundaryStatus::from_u8(fs[j]).unwrap_or(BoundaryStatus::NotComputed);
            b.critical.status =
                BoundaryStatus::from_u8(cs[j]).unwrap_or(BoundaryStatus::NotComputed);
            b.fold.half_dt_holds = holds(&fh, j);
            b.critical.half_dt_holds = holds(&ch, j);
            b.fold.changes = fold_changes.get(j).copied().unwrap_or(0);
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

/// Reads the stored map blocks and cycle searches of an atlas file with maps.
fn read_maps(
    file: &File,
    path: &Path,
    plan: &AtlasPlan,
    res: &mut AtlasResults,
) -> Result<(), StoreError> {
    use squeal_scan::cell::{COLUMNS as CELLS, Kind as CellKind, Num};
    let Some(g) = plan.maps.as_ref().map(|m| m.grid) else {
        return Ok(());
    };
    let n = plan.n_points();
    let (nx, nv, nb) = (g.x0.count, g.v0.count, g.blocks());
    let done: Vec<u8> = file
        .dataset("blocks_done")
        .and_then(|d| d.read_raw())
        .h5(path)?;
    if done.len() != n * nb {
        return Err(StoreError::NotSquealFile {
            path: path.to_path_buf(),
            why: format!(
                "blocks_done holds {} values, expected {}",
                done.len(),
                n * nb
            ),
        });
    }
    let mut maps: Vec<Vec<Cell>> = Vec::new();
    let any = done.contains(&1);
    if any {
        maps = vec![vec![Cell::fill(); nx * nv]; n];
        for col in CELLS {
            let name = map_name(col.name);
            let ds = file.dataset(&name).h5(path)?;
            let vals: Vec<Num> = match col.kind {
                CellKind::Enum | CellKind::U8 => {
                    let v: Vec<u8> = ds.read_raw().h5(path)?;
                    v.into_iter().map(|x| Num::U(x as u64)).collect()
                }
                CellKind::U32 => {
                    let v: Vec<u32> = ds.read_raw().h5(path)?;
                    v.into_iter().map(|x| Num::U(x as u64)).collect()
                }
                CellKind::U64 => {
                    let v: Vec<u64> = ds.read_raw().h5(path)?;
                    v.into_iter().map(Num::U).collect()
                }
                CellKind::F64 => {
                    let v: Vec<f64> = ds.read_raw().h5(path)?;
                    v.into_iter().map(Num::F).collect()
                }
            };
            if vals.len() != n * nx * nv {
                return Err(StoreError::NotSquealFile {
                    path: path.to_path_buf(),
                    why: format!(
                        "{name} holds {} values, expected {}",
                        vals.len(),
                        n * nx * nv
                    ),
                });
            }
            for (k, v) in vals.into_iter().enumerate() {
                (col.set)(&mut maps[k / (nx * nv)][k % (nx * nv)], v);
            }
        }
    }
    for i in 0..n {
        for b in 0..nb {
            if done[i * nb + b] == 1 {
                let rows = g.block_rows(b);
                res.blocks
                    .insert((i, b), maps[i][rows.start * nx..rows.end * nx].to_vec());
            }
        }
    }
    let recs: Vec<VarLenUnicode> = file
        .dataset("map_cycle_record")
        .and_then(|d| d.read_raw())
        .h5(path)?;
    let curves = match (file.dataset("map_cycle_x"), file.dataset("map_cycle_v")) {
        (Ok(x), Ok(v)) => {
            let x: Vec<f64> = x.read_raw().h5(path)?;
            let v: Vec<f64> = v.read_raw().h5(path)?;
            Some((x, v))
        }
        _ => None,
    };
    for (i, r) in recs.iter().enumerate().take(n) {
        if r.as_str().is_empty() {
            continue;
        }
        let curve = curves.as_ref().and_then(|(x, v)| {
            let len = x.len() / n.max(1);
            let xs: Vec<f64> = x[i * len..(i + 1) * len]
                .iter()
                .copied()
                .take_while(|a| !a.is_nan())
                .collect();
            let vs: Vec<f64> = v[i * len..(i + 1) * len][..xs.len()].to_vec();
            (!xs.is_empty()).then_some(squeal_scan::ClosedCurve { x: xs, v: vs })
        });
        let rec =
            crate::cycle::from_text(r.as_str(), curve).map_err(|e| StoreError::NotSquealFile {
                path: path.to_path_buf(),
                why: format!("map_cycle_record of point {i}: {e}"),
            })?;
        res.map_cycles.insert(i, rec);
    }
    Ok(())
}

/// Joins atlas shard files (all `N` shards of one spec) into the file one run writes.
pub fn merge_atlas(
    shards: &[PathBuf],
    out: &Path,
    force: bool,
    prov: &Provenance,
) -> Result<(), StoreError> {
    crate::refuse_input_as_output(shards, out)?;
    let _lock = OutputLock::acquire(out)?;
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
                acc.blocks.extend(r.blocks);
                for (m, c) in r.map_cycles {
                    acc.map_cycles.entry(m).or_insert(c);
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
    let blocks = missing_blocks(&plan, &res, None);
    if !blocks.is_empty() {
        return Err(StoreError::Incomplete {
            path: out.to_path_buf(),
            missing: blocks.len(),
            total: plan.map_plan().map_or(0, |p| p.total_blocks()),
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
