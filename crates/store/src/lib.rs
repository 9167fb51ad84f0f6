//! # squeal-store: basin maps in HDF5 (the only squeal crate that links HDF5)
//!
//! * [`ScanWriter`] takes finished blocks ([`squeal_scan::scanner::BlockResult`]) and located
//!   cycles, appends each to a journal `<out>.journal` (fsynced, so an interrupted scan
//!   resumes with [`ScanWriter::resume`] losing at most the block in flight), and at
//!   [`ScanWriter::finish`] writes the HDF5 file `<out>.tmp`, renames it to `<out>` and
//!   removes the journal.
//! * [`Shard`] `K/N` splits a scan over machines ([`shard_owns`]); [`merge`] joins the shard
//!   files into the file a single run writes.
//! * [`atlas`]: atlas files (schema `squeal-atlas/1`): [`atlas::AtlasWriter`] journals
//!   finished units and writes the file, [`atlas::read_atlas`], [`atlas::merge_atlas`].
//! * [`read_info`], [`read_map`], [`map_count`], [`read_cycle_summary`] read files back;
//!   [`content_digest`] hashes a file's content (for "same file" tests).
//!
//! The file is the same whatever the thread count, resumed or not, merged or not: nothing
//! in it depends on wall-clock time or threads.
//!
//! ```
//! use squeal_store::{Provenance, ScanWriter, read_info};
//! let plan = squeal_scan::Plan::from_toml(r#"
//! version = 1
//! [model]
//! law = "mcmillan"
//! nu = 1e-2
//! [grid]
//! x0 = { min = -0.5, max = 0.5, count = 2 }
//! v0 = { min = 0.0, max = 0.0, count = 1 }
//! [cycle]
//! locate = false
//! [output]
//! path = "doc.h5"
//! "#, "doc.toml").unwrap();
//! let dir = tempfile::tempdir().unwrap();
//! let out = dir.path().join("doc.h5");
//! let prov = Provenance { version: "0.1.0".into(), git_revision: "unknown".into() };
//! let mut w = ScanWriter::create(&out, &plan, None, &prov, false).unwrap();
//! let ctx = squeal_scan::scanner::MapContext::prepare(&plan, 0).unwrap();
//! let nobody = squeal_scan::scanner::NoObserver;
//! for b in 0..plan.grid.blocks() {
//!     if !w.is_done(0, b) {
//!         w.write_block(&squeal_scan::scanner::run_block(&plan, &ctx, b, &nobody, None).unwrap()).unwrap();
//!     }
//! }
//! w.finish().unwrap();
//! assert_eq!(read_info(&out).unwrap().counts[0].iter().sum::<u64>(), 2);
//! ```
//!
//! ## HDF5 schema `squeal-basins/1`
//!
//! ```text
//! /                      root attributes:
//!   schema               "squeal-basins/1"
//!   squeal_version, git_revision, spec (the full TOML text), name, law, solver, early_stop
//!                        strings (variable-length UTF-8)
//!   nu, lambda           f64 scalars, except the swept one (then a coordinate, below)
//!   tau, phi, dt, t_max, fp_radius, settle_rtol, trap_margin      f64
//!   max_iter, settle_cycles (u32), block_rows (u64), locate_cycle (u8 0/1)
//!   shard                "K/N", only in shard files
//! coordinates (dimension scales; attrs long_name, units = "1"):
//!   x0 (nx) f64, v0 (nv) f64, and for sweeps nu or lambda (nmaps) f64
//!   map (nmaps) u64 index, only when not swept; block (nblocks) u64 index
//! basin map, shape (v0, x0), or (nu|lambda, v0, x0) for a sweep; chunked one block of
//! rows per chunk, deflate:
//!   labels       u8 enum {undecided=0, steady_slip=1, stick_slip=2, not_computed=255},
//!                fill 255; attrs flag_values, flag_meanings (CF)
//!   reason       u8 enum {time_limit=0, near_fixed_point=1, inside_cycle=2,
//!                outside_cycle=3, settled_stick_slip=4, diverged=5, solver_failure=6,
//!                not_computed=255}, fill 255
//!   t_decision, amplitude, omega, max_residual    f64, fill NaN
//!   quasi_static u8, evaluations u64, fallbacks, multi_root, unconverged u32, fill 0
//! blocks_done    u8 (map|nu|lambda, block): 1 where the block is stored
//! cycle          group /cycle (one map) or /cycles/map_0000, ... (sweep), present when the
//!                scan recorded one: attrs r_section, bracket_lo, bracket_hi, period, omega,
//!                x_min, x_max, v_min, v_max, distance_plus_x, area, multiplier (f64),
//!                encloses_origin (u8), half_dt_r_section, half_dt_shift, stable_above
//!                (f64, when known), returns (u64), wrong_side_cells,
//!                wrong_side_beyond_pixel (u64); datasets x, v (f64, dim point) the closed
//!                curve; or attr error (string) saying why there is none
//! sweeps only:   cycle_r_section, cycle_distance_plus_x, cycle_area, cycle_period,
//!                cycle_multiplier (f64, NaN where none), cycle_encloses_origin (u8)
//! ```
//!
//! Dimensions follow the netCDF-4 / HDF5 dimension-scale convention, so xarray
//! (`engine="h5netcdf"`) and h5py (`ds.dims`) see named dimensions: each coordinate has
//! `CLASS = "DIMENSION_SCALE"`, `NAME` and `REFERENCE_LIST`; each variable has
//! `DIMENSION_LIST` and, for readers without dimension-scale support, a plain
//! `dimensions` string attribute such as `"v0 x0"`.

pub mod atlas;
mod error;
mod h5types;
mod h5write;
mod journal;
mod read;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use squeal_scan::Plan;
use squeal_scan::scanner::{BlockResult, Cell};
use squeal_scan::ulc::CycleReport;

pub use error::StoreError;
pub use read::{
    FileInfo, MapData, content_digest, map_count, read_cycle_summary, read_info, read_map,
};

use error::{H5Ctx, io};
use h5write::{Meta, Source};
use journal::{CycleData, CycleRecord, Header, Journal, Rec};

/// The `schema` attribute of files this crate writes.
pub const SCHEMA: &str = "squeal-basins/1";

/// What produced a file.
#[derive(Clone, Debug)]
pub struct Provenance {
    /// The squeal version.
    pub version: String,
    /// The git revision of the build.
    pub git_revision: String,
}

/// Shard `k` of `n` (1-based), written `K/N`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// Which shard, `1..=n`.
    pub k: usize,
    /// How many shards.
    pub n: usize,
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.k, self.n)
    }
}

impl std::str::FromStr for Shard {
    type Err = StoreError;
    fn from_str(s: &str) -> Result<Shard, StoreError> {
        let bad = || {
            StoreError::Shards(format!(
                "bad shard {s:?}: expected K/N with 1 <= K <= N, e.g. 2/4"
            ))
        };
        let (k, n) = s.split_once('/').ok_or_else(bad)?;
        let k: usize = k.trim().parse().map_err(|_| bad())?;
        let n: usize = n.trim().parse().map_err(|_| bad())?;
        if k == 0 || n == 0 || k > n {
            return Err(bad());
        }
        Ok(Shard { k, n })
    }
}

/// Global block id = map * plan.grid.blocks() + block; shard k owns ids with id % n == k - 1.
pub fn shard_owns(shard: Option<Shard>, plan: &Plan, map: usize, block: usize) -> bool {
    match shard {
        None => true,
        Some(s) => (map * plan.grid.blocks() + block) % s.n == s.k - 1,
    }
}

/// Decided cells on the wrong side of the located cycle (steady slip outside it, stick-slip
/// inside it), and those of them farther than one cell diagonal from the curve.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct WrongSide {
    /// Cells on the wrong side.
    pub cells: u64,
    /// Of those, cells farther than one cell diagonal from the curve.
    pub beyond_pixel: u64,
}

fn journal_path(out: &Path) -> PathBuf {
    let mut s = out.as_os_str().to_owned();
    s.push(".journal");
    PathBuf::from(s)
}

fn tmp_path(out: &Path) -> PathBuf {
    let mut s = out.as_os_str().to_owned();
    s.push(".tmp");
    PathBuf::from(s)
}

fn shard_text(shard: Option<Shard>) -> String {
    shard.map(|s| s.to_string()).unwrap_or_default()
}

fn remove_if_exists(path: &Path) -> Result<(), StoreError> {
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(io(path, "cannot remove")(e)),
        _ => Ok(()),
    }
}

/// Writes a scan: blocks and cycles go to the journal, [`ScanWriter::finish`] writes the file.
pub struct ScanWriter {
    out: PathBuf,
    plan: Plan,
    shard: Option<Shard>,
    prov: Provenance,
    journal: Journal,
    blocks: BTreeMap<(usize, usize), Rec>,
    cycles: BTreeMap<usize, Rec>,
}

impl std::fmt::Debug for ScanWriter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ScanWriter")
            .field("out", &self.out)
            .field("shard", &self.shard)
            .field("done_blocks", &self.blocks.len())
            .finish()
    }
}

impl ScanWriter {
    /// New scan into `out` (.h5). Refuses if `out` or its journal exists unless `force`
    /// (which removes both). The parent folder must exist and be writable.
    pub fn create(
        out: &Path,
        plan: &Plan,
        shard: Option<Shard>,
        prov: &Provenance,
        force: bool,
    ) -> Result<ScanWriter, StoreError> {
        let jpath = journal_path(out);
        if !force {
            if out.exists() {
                return Err(StoreError::Exists {
                    path: out.to_path_buf(),
                });
            }
            if jpath.exists() {
                return Err(StoreError::Interrupted { path: jpath });
            }
        } else {
            remove_if_exists(out)?;
            remove_if_exists(&jpath)?;
            remove_if_exists(&tmp_path(out))?;
        }
        let journal = Journal::create(
            &jpath,
            &Header {
                spec: plan.spec_text.clone(),
                shard: shard_text(shard),
            },
        )?;
        Ok(ScanWriter {
            out: out.to_path_buf(),
            plan: plan.clone(),
            shard,
            prov: prov.clone(),
            journal,
            blocks: BTreeMap::new(),
            cycles: BTreeMap::new(),
        })
    }

    /// Continues an interrupted scan from its journal (same spec text and shard required);
    /// a torn last record is dropped.
    pub fn resume(
        out: &Path,
        plan: &Plan,
        shard: Option<Shard>,
        prov: &Provenance,
    ) -> Result<ScanWriter, StoreError> {
        let jpath = journal_path(out);
        if jpath.exists() && out.exists() && read::open_squeal(out).is_ok() {
            // Killed between publishing the file and removing the journal.
            remove_if_exists(&jpath)?;
            return Err(StoreError::AlreadyComplete {
                path: out.to_path_buf(),
            });
        }
        if !jpath.exists() {
            if out.exists() {
                read::open_squeal(out)?;
                return Err(StoreError::AlreadyComplete {
                    path: out.to_path_buf(),
                });
            }
            return Err(StoreError::NothingToResume {
                path: out.to_path_buf(),
            });
        }
        let (mut journal, header, recs) = Journal::open(&jpath)?;
        if header.spec != plan.spec_text {
            return Err(StoreError::SpecMismatch {
                path: jpath,
                why: "the journal was written for another spec text".into(),
            });
        }
        if header.shard != shard_text(shard) {
            let show = |s: &str| {
                if s.is_empty() {
                    "no shard".to_string()
                } else {
                    format!("shard {s}")
                }
            };
            return Err(StoreError::SpecMismatch {
                path: jpath,
                why: format!(
                    "the journal is for {}, not {}",
                    show(&header.shard),
                    show(&shard_text(shard))
                ),
            });
        }
        let mut blocks = BTreeMap::new();
        let mut cycles = BTreeMap::new();
        let corrupt = |why: String| StoreError::NotSquealFile {
            path: jpath.clone(),
            why,
        };
        for r in recs {
            let payload = journal.read(&r)?;
            match r.kind {
                journal::KIND_BLOCK => {
                    let (m, b, cells) = journal::decode_block(&payload)
                        .ok_or_else(|| corrupt("a malformed block record".into()))?;
                    check_block(plan, shard, m, b, cells.len()).map_err(|why| {
                        corrupt(format!("a recorded block does not fit the plan: {why}"))
                    })?;
                    blocks.insert((m, b), r);
                }
                journal::KIND_CYCLE => {
                    let (m, _) = journal::decode_cycle(&payload)
                        .ok_or_else(|| corrupt("a malformed cycle record".into()))?;
                    if m >= plan.maps.len() {
                        return Err(corrupt(format!(
                            "a cycle for map {m} of {}",
                            plan.maps.len()
                        )));
                    }
                    cycles.insert(m, r);
                }
                k => return Err(corrupt(format!("an unknown record kind {k}"))),
            }
        }
        Ok(ScanWriter {
            out: out.to_path_buf(),
            plan: plan.clone(),
            shard,
            prov: prov.clone(),
            journal,
            blocks,
            cycles,
        })
    }

    /// Whether block `block` of map `map` is stored.
    pub fn is_done(&self, map: usize, block: usize) -> bool {
        self.blocks.contains_key(&(map, block))
    }

    /// Blocks stored so far.
    pub fn done_blocks(&self) -> usize {
        self.blocks.len()
    }

    /// Blocks this shard owns in all.
    pub fn owned_blocks(&self) -> usize {
        let nb = self.plan.grid.blocks();
        (0..self.plan.maps.len())
            .map(|m| {
                (0..nb)
                    .filter(|&b| shard_owns(self.shard, &self.plan, m, b))
                    .count()
            })
            .sum()
    }

    /// Appends the block to the journal and syncs it before returning.
    pub fn write_block(&mut self, b: &BlockResult) -> Result<(), StoreError> {
        check_block(&self.plan, self.shard, b.map, b.block, b.cells.len()).map_err(|why| {
            StoreError::BadBlock {
                path: self.out.clone(),
                why,
            }
        })?;
        let rec = self.journal.append(
            journal::KIND_BLOCK,
            &journal::encode_block(b.map, b.block, &b.cells),
        )?;
        self.blocks.insert((b.map, b.block), rec);
        Ok(())
    }

    /// Whether the cycle of `map` was already recorded.
    pub fn has_cycle(&self, map: usize) -> bool {
        self.cycles.contains_key(&map)
    }

    /// Records the located cycle of a map (or why there is none).
    pub fn write_cycle(
        &mut self,
        map: usize,
        cycle: Option<&CycleReport>,
        error: Option<&str>,
    ) -> Result<(), StoreError> {
        if map >= self.plan.maps.len() {
            return Err(StoreError::BadBlock {
                path: self.out.clone(),
                why: format!(
                    "a cycle for map {map}, but the plan has {} maps",
                    self.plan.maps.len()
                ),
            });
        }
        let rec = CycleRecord {
            report: cycle.map(CycleData::from_report),
            error: error.map(str::to_string),
        };
        let r = self
            .journal
            .append(journal::KIND_CYCLE, &journal::encode_cycle(map, &rec))?;
        self.cycles.insert(map, r);
        Ok(())
    }

    /// Writes the HDF5 file once every owned block is stored; returns per-map wrong-side
    /// counts (None where no cycle was recorded).
    pub fn finish(mut self) -> Result<Vec<Option<WrongSide>>, StoreError> {
        let total = self.owned_blocks();
        if self.blocks.len() < total {
            return Err(StoreError::Incomplete {
                path: self.out.clone(),
                missing: total - self.blocks.len(),
                total,
            });
        }
        let tmp = tmp_path(&self.out);
        remove_if_exists(&tmp)?;
        let meta = Meta {
            version: &self.prov.version,
            git_revision: &self.prov.git_revision,
            shard: self.shard.map(|s| s.to_string()),
        };
        let plan = self.plan.clone();
        let mut src = JournalSource {
            journal: &mut self.journal,
            blocks: &self.blocks,
            cycles: &self.cycles,
        };
        let wrong = match h5write::assemble(&tmp, &plan, &meta, &mut src) {
            Ok(w) => w,
            Err(e) => {
                let _ = std::fs::remove_file(&tmp);
                return Err(e);
            }
        };
        publish(&tmp, &self.out)?;
        let jpath = self.journal.path.clone();
        drop(self);
        remove_if_exists(&jpath)?;
        Ok(wrong)
    }
}

/// Moves the finished `tmp` to `out`, refusing if `out` appeared meanwhile.
fn publish(tmp: &Path, out: &Path) -> Result<(), StoreError> {
    if out.exists() {
        let _ = std::fs::remove_file(tmp);
        return Err(StoreError::Exists {
            path: out.to_path_buf(),
        });
    }
    std::fs::rename(tmp, out).map_err(io(out, "cannot rename the finished file to"))?;
    Ok(())
}

fn check_block(
    plan: &Plan,
    shard: Option<Shard>,
    map: usize,
    block: usize,
    n: usize,
) -> Result<(), String> {
    let g = &plan.grid;
    if map >= plan.maps.len() || block >= g.blocks() {
        return Err(format!(
            "map {map} block {block} is outside the plan ({} maps of {} blocks)",
            plan.maps.len(),
            g.blocks()
        ));
    }
    let want = g.block_rows(block).len() * g.x0.count;
    if n != want {
        return Err(format!(
            "map {map} block {block} holds {n} cells, expected {want}"
        ));
    }
    if !shard_owns(shard, plan, map, block) {
        return Err(format!("map {map} block {block} belongs to another shard"));
    }
    Ok(())
}

struct JournalSource<'a> {
    journal: &'a mut Journal,
    blocks: &'a BTreeMap<(usize, usize), Rec>,
    cycles: &'a BTreeMap<usize, Rec>,
}

impl Source for JournalSource<'_> {
    fn block(&mut self, map: usize, block: usize) -> Result<Option<Vec<Cell>>, StoreError> {
        let Some(r) = self.blocks.get(&(map, block)) else {
            return Ok(None);
        };
        let p = self.journal.read(r)?;
        let (_, _, cells) = journal::decode_block(&p).ok_or_else(|| StoreError::NotSquealFile {
            path: self.journal.path.clone(),
            why: "a block record changed on disk".into(),
        })?;
        Ok(Some(cells))
    }

    fn cycle(&mut self, map: usize) -> Result<Option<CycleRecord>, StoreError> {
        let Some(r) = self.cycles.get(&map) else {
            return Ok(None);
        };
        let p = self.journal.read(r)?;
        let (_, rec) = journal::decode_cycle(&p).ok_or_else(|| StoreError::NotSquealFile {
            path: self.journal.path.clone(),
            why: "a cycle record changed on disk".into(),
        })?;
        Ok(Some(rec))
    }
}

struct ShardSource {
    plan: Plan,
    files: Vec<(PathBuf, hdf5::File, Shard, Vec<u8>)>,
}

impl Source for ShardSource {
    fn block(&mut self, map: usize, block: usize) -> Result<Option<Vec<Cell>>, StoreError> {
        let nb = self.plan.grid.blocks();
        let sweep = self.plan.sweep.is_some();
        for (path, f, s, done) in &self.files {
            if shard_owns(Some(*s), &self.plan, map, block) && done[map * nb + block] == 1 {
                let rows = self.plan.grid.block_rows(block);
                return read::read_block(f, sweep, map, rows).h5(path).map(Some);
            }
        }
        Ok(None)
    }

    fn cycle(&mut self, map: usize) -> Result<Option<CycleRecord>, StoreError> {
        let sweep = self.plan.sweep.is_some();
        for (path, f, _, _) in &self.files {
            if let Some(c) = read::read_cycle(f, sweep, map).h5(path)? {
                return Ok(Some(c));
            }
        }
        Ok(None)
    }
}

/// Joins shard files into the file a single run would have written (the same datasets and
/// attributes, without `shard`; provenance is taken from the shards, which must agree).
/// `prov` is accepted for symmetry and not stored.
pub fn merge(
    shards: &[PathBuf],
    out: &Path,
    force: bool,
    _prov: &Provenance,
) -> Result<(), StoreError> {
    if shards.is_empty() {
        return Err(StoreError::Shards("no shard files given".into()));
    }
    if out.exists() && !force {
        return Err(StoreError::Exists {
            path: out.to_path_buf(),
        });
    }
    let mut first: Option<(PathBuf, String, usize, String, String, String)> = None;
    let mut files: Vec<(PathBuf, hdf5::File, Shard, Vec<u8>)> = Vec::new();
    for p in shards {
        let f = read::open_squeal(p)?;
        let text = read::str_attr(&f, "shard").map_err(|_| {
            StoreError::Shards(format!(
                "{} is not a shard file (no `shard` attribute)",
                p.display()
            ))
        })?;
        let s: Shard = text.parse().map_err(|_| {
            StoreError::Shards(format!("{}: bad shard attribute {text:?}", p.display()))
        })?;
        let spec = read::str_attr(&f, "spec").h5(p)?;
        let name = read::str_attr(&f, "name").h5(p)?;
        let ver = read::str_attr(&f, "squeal_version").h5(p)?;
        let git = read::str_attr(&f, "git_revision").h5(p)?;
        match &first {
            None => first = Some((p.clone(), spec, s.n, name, ver, git)),
            Some((p0, spec0, n0, name0, ver0, git0)) => {
                let why = if *spec0 != spec {
                    Some("different spec text")
                } else if *n0 != s.n {
                    Some("different shard counts")
                } else if *name0 != name {
                    Some("different scan names")
                } else if *ver0 != ver || *git0 != git {
                    Some("written by different squeal builds")
                } else {
                    None
                };
                if let Some(why) = why {
                    return Err(StoreError::Shards(format!(
                        "{} and {} do not belong together: {why}",
                        p0.display(),
                        p.display()
                    )));
                }
            }
        }
        if let Some((q, ..)) = files.iter().find(|(_, _, t, _)| t.k == s.k) {
            return Err(StoreError::Shards(format!(
                "{} and {} overlap: both are shard {s}",
                q.display(),
                p.display()
            )));
        }
        let done: Vec<u8> = f.dataset("blocks_done").h5(p)?.read_raw().h5(p)?;
        files.push((p.clone(), f, s, done));
    }
    let Some((p0, spec, n, name, ver, git)) = first else {
        return Err(StoreError::Shards("no shard files given".into()));
    };
    for k in 1..=n {
        if !files.iter().any(|(_, _, s, _)| s.k == k) {
            return Err(StoreError::Shards(format!(
                "missing shard {k}/{n} (have {} of {n} files)",
                files.len()
            )));
        }
    }
    let mut plan =
        Plan::from_toml(&spec, &format!("{name}.toml")).map_err(|e| StoreError::NotSquealFile {
            path: p0.clone(),
            why: format!("its spec no longer validates: {e}"),
        })?;
    plan.name = name;
    let nb = plan.grid.blocks();
    for (p, _, s, done) in &files {
        if done.len() != plan.maps.len() * nb {
            return Err(StoreError::NotSquealFile {
                path: p.clone(),
                why: "blocks_done does not match the spec's grid".into(),
            });
        }
        let mut missing = 0;
        let mut total = 0;
        for (id, &d) in done.iter().enumerate() {
            let owns = shard_owns(Some(*s), &plan, id / nb, id % nb);
            if owns {
                total += 1;
                missing += (d == 0) as usize;
            } else if d != 0 {
                return Err(StoreError::Shards(format!(
                    "{} overlaps another shard: it holds block {id} of shard {}",
                    p.display(),
                    id % s.n + 1
                )));
            }
        }
        if missing > 0 {
            return Err(StoreError::Incomplete {
                path: p.clone(),
                missing,
                total,
            });
        }
    }
    let tmp = tmp_path(out);
    remove_if_exists(&tmp)?;
    let meta = Meta {
        version: &ver,
        git_revision: &git,
        shard: None,
    };
    let mut src = ShardSource {
        plan: plan.clone(),
        files,
    };
    if let Err(e) = h5write::assemble(&tmp, &plan, &meta, &mut src) {
        let _ = std::fs::remove_file(&tmp);
        return Err(e);
    }
    drop(src);
    if force {
        remove_if_exists(out)?;
    }
    publish(&tmp, out)
}

#[cfg(test)]
mod tests;
