//! # squeal-store: basin maps in HDF5 (the only squeal crate that links HDF5)
//!
//! * [`ScanWriter`] is the scan's [`squeal_scan::Sink`]: it takes finished blocks and cycle
//!   searches from [`squeal_scan::drive`], appends each to a journal `<out>.journal`
//!   (written at once and synced in groups, so an interrupted scan resumes with
//!   [`ScanWriter::resume`] losing at most the blocks in flight, or after a crash of the
//!   machine the blocks since the last sync: `journal`'s overview). [`ScanWriter::finishing`]
//!   then starts the HDF5 file `<out>.tmp` (an [`Assembly`]), which
//!   [`squeal_scan::finish::finish`] completes: the blocks read back once and written, the
//!   maps' checks and basin stability computed by the engine and handed to the file, which
//!   is renamed to `<out>`, and the journal removed. While it lives it holds the
//!   [`OutputLock`] `<out>.lock`, so two runs never write one output.
//! * [`output_state`] says whether an output is absent, interrupted, complete for this plan
//!   or made from another spec (compared as parsed plans, not text), for a scan's plan and
//!   an atlas's alike ([`Recorded`]); [`file_kind`] tells the kinds of file apart.
//! * [`Shard`] `K/N` splits a scan over machines ([`shard_owns`]); [`merging`] joins the shard
//!   files into the file a single run writes (an [`Assembly`], as a scan's).
//! * [`atlas`]: atlas files (schema `squeal-atlas/1`): [`atlas::AtlasWriter`] journals
//!   finished units and, as a [`squeal_scan::Sink`], the blocks of the optional basin maps,
//!   holds the [`OutputLock`], and writes the file (what it is missing is computed above
//!   the store: `squeal_cli::run_atlas`); [`atlas::read_atlas`], [`atlas::merge_atlas`].
//! * [`read_info`], [`map_labels`], [`read_atlas_info`], [`read_trajectory_info`], [`read_map`],
//!   [`map_count`], [`read_cycle_summary`] read files back;
//!   [`content_digest`] hashes a file's content (for "same file" tests).
//!
//! Every per-cell dataset follows [`squeal_scan::cell::COLUMNS`] (name, long name, units,
//! type, fill); the cycle search is written generically from its serde form.
//! The file is the same whatever the thread count, resumed or not, merged or not: nothing
//! in it depends on wall-clock time or threads.
//!
//! ```
//! use std::sync::atomic::AtomicBool;
//! use squeal_store::{Provenance, ScanWriter};
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
//! let stop = AtomicBool::new(false);
//! squeal_scan::drive(&plan, None, &mut w, &squeal_scan::NoObserver, &stop).unwrap();
//! squeal_scan::finish::finish(w.finishing(&[]).unwrap()).unwrap();
//! assert_eq!(squeal_store::map_labels(&out, 0).unwrap().len(), 2);
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
//!   max_iter, settle_cycles (u32), block_rows, audit_every, sensitivity_samples (u64),
//!   locate_cycle (u8 0/1)
//!   shard                "K/N", only in shard files
//! coordinates (dimension scales; attrs long_name, units = "1"):
//!   x0 (nx) f64, v0 (nv) f64, and for sweeps of one key that key (nmaps) f64
//!   map (nmaps) u64 index, when not swept or several keys are swept (each then an f64
//!   auxiliary coordinate over map, listed by the root attribute `swept`); block u64 index
//! basin map, shape (v0, x0), or (nu|lambda, v0, x0) for a sweep; chunked one block of
//! rows per chunk, deflate: the columns of squeal_scan::cell::COLUMNS, each with long_name,
//! units (not on enums), and for enums CF flag_values / flag_meanings
//! blocks_done    u8 (map|nu|lambda, block): 1 where the block is stored
//! per map (map|nu|lambda): the checks, steady slip's stability, the landscape (laws with
//!                true stick), basin stability, the final-state sensitivity. Every per-cell
//!                and per-map dataset is stated once, by the tables that write it, and
//!                printed from them by [`schema::text`] (`cargo run -p squeal-store
//!                --example schema`); docs/hdf5.md is checked against that text
//! cycle          group /cycle (one map) or /cycles/map_0000, ... (sweep), present when the
//!                scan searched: attr record (the search as TOML text, exact), every
//!                scalar of it flattened into attrs (r_section, bracket[2], period, omega,
//!                x_range[2], v_range[2], distance_plus_x, area, multiplier,
//!                encloses_origin (u8), half_dt_r_section, half_dt_shift, returns,
//!                stable_above, params_*, solver_*); datasets x, v (f64, dim point) the
//!                closed curve; or attrs error (text) and no_cycle_* saying why there is none
//! sweeps only:   cycle_r_section, cycle_distance_plus_x, cycle_area, cycle_period,
//!                cycle_multiplier (f64, NaN where none), cycle_encloses_origin (u8)
//! ```
//!
//! Dimensions follow the netCDF-4 / HDF5 dimension-scale convention, so xarray
//! (`engine="h5netcdf"`) and h5py (`ds.dims`) see named dimensions: each coordinate has
//! `CLASS = "DIMENSION_SCALE"`, `NAME` and `REFERENCE_LIST`; each variable has
//! `DIMENSION_LIST`.

mod assembly;
pub mod atlas;
mod chunks;
mod cycle;
mod digest;
pub mod dump;
mod error;
mod h5columns;
mod h5out;
mod h5types;
mod h5write;
mod journal;
mod lock;
mod merge;
mod output;
mod read;
pub mod schema;
mod trajectory;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use squeal_scan::Plan;
use squeal_scan::scanner::{BlockResult, Cell};
pub use squeal_scan::{Shard, WrongSide, shard_owns};

pub use assembly::{Assembly, StoredBlock};
pub use atlas::{AtlasInfo, read_atlas_info};
pub use digest::content_digest;
pub use error::{Advice, Plain, Remedy, StoreError, Words};
pub use lock::{LockOwner, OutputLock, hostname, lock_path};
pub use merge::merging;
pub use output::{
    FileKind, OutputState, Recorded, check_output, create_parent, file_kind, output_state,
    refuse_existing, refuse_input_as_output,
};
pub use read::{
    FileInfo, FrictionTables, LandscapeInfo, MapData, Swept, SweptSi, file_schema, friction_tables,
    map_count, map_labels, read_cycle_summary, read_info, read_map,
};
pub use trajectory::{
    RunAttrs, TRAJECTORY_SCHEMA, TrajectoryInfo, read_trajectory_info, write_run,
    write_run_sampled, write_samples, write_trajectory,
};

use assembly::{Publish, Source};
use error::io;
use h5write::Meta;
use journal::{CycleRecord, Header, Journal, Rec};
use squeal_scan::ulc::CycleOutcome;

/// The `schema` attribute of files this crate writes.
pub const SCHEMA: &str = "squeal-basins/1";

/// The `schema` attribute of atlas files.
pub const ATLAS_SCHEMA: &str = "squeal-atlas/1";

/// What produced a file.
#[derive(Clone, Debug)]
pub struct Provenance {
    /// The squeal version.
    pub version: String,
    /// The git revision of the build.
    pub git_revision: String,
}

pub(crate) fn journal_path(out: &Path) -> PathBuf {
    let mut s = out.as_os_str().to_owned();
    s.push(".journal");
    PathBuf::from(s)
}

pub(crate) fn tmp_path(out: &Path) -> PathBuf {
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

/// The journal's block records by `(map, block)`.
type Blocks = BTreeMap<(usize, usize), Rec>;

/// Writes a scan: blocks and cycles go to the journal, [`ScanWriter::finishing`] starts the file.
pub struct ScanWriter {
    out: PathBuf,
    plan: Plan,
    shard: Option<Shard>,
    prov: Provenance,
    journal: Journal,
    blocks: Blocks,
    cycles: BTreeMap<usize, Rec>,
    /// Rule groups withdrawn, by map, in the order recorded.
    withdrawn: Withdrawals,
    _lock: OutputLock,
}

/// Rule groups withdrawn from each map, in the order recorded.
type Withdrawals = BTreeMap<usize, Vec<squeal_scan::scanner::Withdrawn>>;

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
    /// New scan into `out` (.h5, checked by [`check_output`]). Refuses if `out` or its
    /// journal exists unless `force` (which removes both). The parent folder must exist and
    /// be writable.
    pub fn create(
        out: &Path,
        plan: &Plan,
        shard: Option<Shard>,
        prov: &Provenance,
        force: bool,
    ) -> Result<ScanWriter, StoreError> {
        check_output(out)?;
        create_parent(out)?;
        let lock = OutputLock::acquire(out)?;
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
        preflight(out, plan, shard, prov)?;
        let journal = Journal::create(
            &jpath,
            &Header {
                owner: journal::Owner::Scan,
                spec: plan.spec_text.clone(),
                shard: shard_text(shard),
                table: Some(journal::table_text(<Plan as output::Recorded>::spec_table(
                    plan,
                ))),
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
            withdrawn: BTreeMap::new(),
            _lock: lock,
        })
    }

    /// Continues an interrupted scan from its journal (a spec that computes the same and the
    /// same shard required, as an atlas's); a torn last record is dropped.
    pub fn resume(
        out: &Path,
        plan: &Plan,
        shard: Option<Shard>,
        prov: &Provenance,
    ) -> Result<ScanWriter, StoreError> {
        check_output(out)?;
        let lock = OutputLock::acquire(out)?;
        let jpath = journal_path(out);
        resumable(out, &jpath)?;
        let (mut journal, header, recs) = Journal::open(&jpath, journal::Owner::Scan)?;
        // Compare what the spec means, not its bytes: a comment edit does not block a
        // resume. The file then records the spec text the scan started with.
        let plan = output::started_plan(&jpath, &header, plan, &plan.spec_text)?;
        preflight(out, &plan, shard, prov)?;
        same_shard(&jpath, &header.shard, shard)?;
        let (blocks, cycles, withdrawn) = index_records(&mut journal, recs, &plan, shard)?;
        Ok(ScanWriter {
            out: out.to_path_buf(),
            plan,
            shard,
            prov: prov.clone(),
            journal,
            blocks,
            cycles,
            withdrawn,
            _lock: lock,
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
        let nb = self.plan.map.grid.blocks();
        (0..self.plan.maps.len())
            .map(|m| {
                (0..nb)
                    .filter(|&b| shard_owns(self.shard, &self.plan, m, b))
                    .count()
            })
            .sum()
    }

    /// Appends the block to the journal (synced with its group of blocks).
    pub fn write_block(&mut self, b: &BlockResult) -> Result<(), StoreError> {
        squeal_scan::Sink::write_encoded(self, b, journal::block_record(b))
    }

    /// Refuses a block that is not this shard's or does not fit the plan.
    fn check_block(&self, b: &BlockResult) -> Result<(), StoreError> {
        check_block(&self.plan, self.shard, b.map, b.block, b.cells.len()).map_err(|why| {
            StoreError::BadBlock {
                path: self.out.clone(),
                why,
            }
        })
    }

    /// Whether the cycle of `map` was already recorded.
    pub fn has_cycle(&self, map: usize) -> bool {
        self.cycles.contains_key(&map)
    }

    /// Records the cycle search of a map (`None` when the plan does not locate cycles).
    pub fn write_cycle(
        &mut self,
        map: usize,
        cycle: Option<&CycleOutcome>,
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
        let rec: CycleRecord = cycle.cloned();
        let r = self
            .journal
            .append(journal::KIND_CYCLE, &journal::encode_cycle(map, &rec))?;
        self.cycles.insert(map, r);
        Ok(())
    }

    /// The plan being written (after a resume: the one the scan started with).
    pub fn plan(&self) -> &Plan {
        &self.plan
    }

    /// Starts the HDF5 file once every owned block is stored, with the landscape of each map
    /// (laws with true stick: [`squeal_scan::landscape::of_plan`], computed by the caller:
    /// the writer runs no model; none for McMillan's laws): finish it with
    /// [`squeal_scan::finish::finish`], which reads the blocks back once, writes them,
    /// tallies each map's checks and basin stability and hands them to the file, which then
    /// takes the output's place (the journal removed).
    pub fn finishing(
        self,
        landscapes: &[Option<squeal_core::LandscapeEvidence>],
    ) -> Result<Assembly, StoreError> {
        let stated = self
            .plan
            .maps
            .iter()
            .all(|p| !p.law.family().has_landscape())
            || landscapes.len() == self.plan.maps.len();
        if !stated {
            return Err(StoreError::Landscape {
                path: self.out.clone(),
                why: format!(
                    "{} landscapes given for {} maps of a law with true stick",
                    landscapes.len(),
                    self.plan.maps.len()
                ),
            });
        }
        let landscapes: Vec<Option<LandscapeInfo>> = landscapes
            .iter()
            .map(|l| l.as_ref().map(LandscapeInfo::of))
            .collect();
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
        let ScanWriter {
            out,
            plan,
            journal,
            blocks,
            cycles,
            withdrawn,
            _lock,
            ..
        } = self;
        let publish = Publish {
            out,
            replace: false,
            journal: Some(journal.path.clone()),
            _lock,
        };
        let src = JournalSource {
            journal,
            blocks,
            cycles,
            withdrawn,
        };
        Assembly::begin(tmp, (plan, &meta), Box::new(src), landscapes, publish)
    }
}

impl squeal_scan::Sink for ScanWriter {
    type Error = StoreError;
    fn is_done(&self, map: usize, block: usize) -> bool {
        ScanWriter::is_done(self, map, block)
    }
    fn has_cycle(&self, map: usize) -> bool {
        ScanWriter::has_cycle(self, map)
    }
    fn write_cycle(&mut self, map: usize, cycle: Option<&CycleOutcome>) -> Result<(), StoreError> {
        ScanWriter::write_cycle(self, map, cycle)
    }
    fn write_block(&mut self, block: &BlockResult) -> Result<(), StoreError> {
        ScanWriter::write_block(self, block)
    }
    fn encode_block(b: &BlockResult) -> Option<Vec<u8>> {
        Some(journal::block_record(b))
    }
    fn write_encoded(&mut self, b: &BlockResult, record: Vec<u8>) -> Result<(), StoreError> {
        self.check_block(b)?;
        let rec = self.journal.append_framed(&record)?;
        self.blocks.insert((b.map, b.block), rec);
        Ok(())
    }
    fn withdrawn(
        &mut self,
        map: usize,
    ) -> Result<Vec<squeal_scan::scanner::Withdrawn>, StoreError> {
        Ok(self.withdrawn.get(&map).cloned().unwrap_or_default())
    }
    fn write_withdrawn(
        &mut self,
        map: usize,
        w: &[squeal_scan::scanner::Withdrawn],
    ) -> Result<(), StoreError> {
        self.journal
            .append(journal::KIND_WITHDRAWN, &journal::encode_withdrawn(map, w))?;
        add_withdrawn(self.withdrawn.entry(map).or_default(), w);
        Ok(())
    }
    fn stored_block(&mut self, map: usize, block: usize) -> Result<Option<Vec<Cell>>, StoreError> {
        let Some(r) = self.blocks.get(&(map, block)) else {
            return Ok(None);
        };
        let p = self.journal.read(r)?;
        let (_, _, cells) = journal::decode_block(&p).ok_or_else(|| StoreError::NotSquealFile {
            path: self.journal.path.clone(),
            why: "a block record changed on disk".into(),
            advice: None,
        })?;
        Ok(Some(cells))
    }
}

impl ScanWriter {
    /// The rule groups withdrawn from each map so far, one line each with why:
    /// `(map, line)` in map order.
    pub fn withdrawn_lines(&self) -> Vec<(usize, String)> {
        self.withdrawn
            .iter()
            .flat_map(|(m, w)| w.iter().map(move |x| (*m, x.why.clone())))
            .collect()
    }
}

/// Everything the final write needs from the plan, tried before any computing.
fn preflight(
    out: &Path,
    plan: &Plan,
    shard: Option<Shard>,
    prov: &Provenance,
) -> Result<(), StoreError> {
    let meta = Meta {
        version: &prov.version,
        git_revision: &prov.git_revision,
        shard: shard.map(|s| s.to_string()),
    };
    h5write::preflight(out, plan, &meta)
}

/// Moves the finished `tmp` to `out`, refusing if `out` appeared meanwhile.
fn publish(tmp: &Path, out: &Path) -> Result<(), StoreError> {
    if out.exists() {
        let _ = std::fs::remove_file(tmp);
        return Err(StoreError::Exists {
            path: out.to_path_buf(),
        });
    }
    if let Err(e) = std::fs::rename(tmp, out) {
        let _ = std::fs::remove_file(tmp);
        return Err(io(out, "cannot rename the finished file to")(e));
    }
    Ok(())
}

fn check_block(
    plan: &Plan,
    shard: Option<Shard>,
    map: usize,
    block: usize,
    n: usize,
) -> Result<(), String> {
    let g = &plan.map.grid;
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

/// Whether there is a journal to resume at `jpath` for `out`: not when the scan finished
/// (a journal left beside a finished file, killed before removing it, is removed).
fn resumable(out: &Path, jpath: &Path) -> Result<(), StoreError> {
    let complete = || StoreError::AlreadyComplete {
        path: out.to_path_buf(),
    };
    if jpath.exists() && out.exists() && read::open_squeal(out).is_ok() {
        // Killed between publishing the file and removing the journal.
        remove_if_exists(jpath)?;
        return Err(complete());
    }
    if !jpath.exists() {
        if out.exists() {
            read::open_squeal(out)?;
            return Err(complete());
        }
        return Err(StoreError::NothingToResume {
            path: out.to_path_buf(),
        });
    }
    Ok(())
}

/// Refuses a journal written for another shard (`recorded`, as [`shard_text`]).
fn same_shard(jpath: &Path, recorded: &str, shard: Option<Shard>) -> Result<(), StoreError> {
    if recorded == shard_text(shard) {
        return Ok(());
    }
    let show = |s: &str| {
        if s.is_empty() {
            "no shard".to_string()
        } else {
            format!("shard {s}")
        }
    };
    Err(StoreError::SpecMismatch {
        path: jpath.to_path_buf(),
        why: format!(
            "the journal is for {}, not {}",
            show(recorded),
            show(&shard_text(shard))
        ),
        advice: None,
    })
}

/// The journal's block and cycle records by `(map, block)` and by map, each checked
/// against the plan.
fn index_records(
    journal: &mut Journal,
    recs: Vec<Rec>,
    plan: &Plan,
    shard: Option<Shard>,
) -> Result<(Blocks, BTreeMap<usize, Rec>, Withdrawals), StoreError> {
    let mut blocks = BTreeMap::new();
    let mut cycles = BTreeMap::new();
    let mut withdrawn = Withdrawals::new();
    let path = journal.path.clone();
    let corrupt = |why: String| StoreError::NotSquealFile {
        path: path.clone(),
        why,
        advice: None,
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
            journal::KIND_WITHDRAWN => {
                let (m, w) = journal::decode_withdrawn(&payload)
                    .ok_or_else(|| corrupt("a malformed record of withdrawn rules".into()))?;
                if m >= plan.maps.len() {
                    return Err(corrupt(format!(
                        "withdrawn rules for map {m} of {}",
                        plan.maps.len()
                    )));
                }
                add_withdrawn(withdrawn.entry(m).or_default(), &w);
            }
            k => return Err(corrupt(format!("an unknown record kind {k}"))),
        }
    }
    Ok((blocks, cycles, withdrawn))
}

/// Adds the groups of `w` not yet in `have`.
fn add_withdrawn(
    have: &mut Vec<squeal_scan::scanner::Withdrawn>,
    w: &[squeal_scan::scanner::Withdrawn],
) {
    for x in w {
        if !have.iter().any(|h| h.rules == x.rules) {
            have.push(x.clone());
        }
    }
}

/// A scan's journal as the source of its file: the records by block and by map.
struct JournalSource {
    journal: Journal,
    blocks: Blocks,
    cycles: BTreeMap<usize, Rec>,
    withdrawn: Withdrawals,
}

impl JournalSource {
    fn changed(&self, what: &str) -> StoreError {
        StoreError::JournalChanged {
            path: self.journal.path.clone(),
            what: what.into(),
        }
    }
}

impl Source for JournalSource {
    fn stored(&self, map: usize, block: usize) -> bool {
        self.blocks.contains_key(&(map, block))
    }

    fn block(&self, map: usize, block: usize) -> Result<Option<Vec<Cell>>, StoreError> {
        let Some(r) = self.blocks.get(&(map, block)) else {
            return Ok(None);
        };
        let p = self.journal.read_at(r)?;
        let (_, _, cells) = journal::decode_block(&p).ok_or_else(|| self.changed("block"))?;
        Ok(Some(cells))
    }

    fn cycle(&self, map: usize) -> Result<Option<CycleRecord>, StoreError> {
        let Some(r) = self.cycles.get(&map) else {
            return Ok(None);
        };
        let p = self.journal.read_at(r)?;
        let (_, rec) = journal::decode_cycle(&p).ok_or_else(|| self.changed("cycle"))?;
        Ok(Some(rec))
    }

    fn withdrawn(&self, map: usize) -> Vec<squeal_scan::scanner::Withdrawn> {
        self.withdrawn.get(&map).cloned().unwrap_or_default()
    }
}

#[cfg(test)]
mod tests;
