//! Atlas files: the journal of finished units, the HDF5 file, reading it back, merging
//! shards.
//!
//! Here: the [`AtlasWriter`] (create, resume, record, finish) and what is missing. Its
//! parts: `record` (the journal's records), `schema` (the datasets that are not rows of the
//! scan crate's column tables: names, long names, stored enums, the two boundary searches),
//! `write` (root attributes, coordinates, points, boundaries), `maps` (the basin maps,
//! written and read), `read` (reading back, merging shards). A new figure of a point or a
//! boundary is a row of [`squeal_scan::atlas::columns`]: the writer, the reader and the
//! journal walk those tables.
//!
//! ## Journal `<out>.journal`
//! The scan's journal (`crate::journal`: checksummed binary records, units synced at once
//! and map blocks in groups,
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
//!           axis order (nu, lambda, tau, phi | m, k, c, v_belt, mu_k, mu_s, tau, g or
//!           normal_force, with no mu_s, tau under Coulomb |
//!           xi, v_d, mu_d, mu_sd, v_0, mu_v);
//!           `point` (length 1) when nothing is swept, `boundary` (length 1) when only the
//!           damping is
//! over the swept dims:
//!   regime   u8 enum {undecided=0, steady_slip_only=1, bistable_quiet=2,
//!            bistable_squeals=3, fixed_point_unstable=4, not_computed=255}; CF flag_values,
//!            flag_meanings
//!   the point's columns (cycle_*, stick_*, basin_fraction(_err), warm_started, steady
//!            slip's stability, counters): stated once, in their table, and printed from it
//!            with type, fill, units and long name by crate::schema::atlas_text
//!            (`cargo run -p squeal-store --example schema`)
//!   <figure>_si    (physical specs) the same figure in SI units (m, m/s, s, Hz, m^2/s)
//!   nu, lambda, tau, phi (physical specs: nondim_nu, ...) the nondimensional parameters
//!   normal_force   (physical specs with g) the normal force m g at each point (N)
//!   landscape      (law = "stribeck") u8 enum {unknown=0, stick_slip_only=1, bistable=2,
//!                  steady_slip_only=3, not_computed=255}; CF flags; with its evidence
//!                  (atlas_text); the stick-slip figure stick_quasi_static_share is
//!                  stored as stick_stuck_share
//!   note           string: why a point is undecided, or the caveat of its label
//!   points_done    u8: 1 where computed (shards)
//! over the swept dims except the damping (nu or c):
//!   fold_status, critical_status  u8 enum {found=0, below_range=1, above_range=2,
//!                                 not_computed=255}
//!   the boundary's columns (fold_nu(_lo, _hi, _err), the transient lifetimes above the
//!                 fold, critical_nu(_lo, _hi)), printed by atlas_text (bisected in
//!                 lambda: fold_lambda, ...; law = "stribeck": fold_xi, ... or fold_v_d, ...)
//!   fold_half_dt, critical_half_dt  u8 {moves=0, holds=1, not_checked=255}: the
//!                 bracket's predicate again at dt/2 at both ends
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

mod maps;
mod read;
mod record;
mod schema;
mod write;

use std::path::{Path, PathBuf};

use squeal_scan::atlas::{AtlasPlan, PointMap, Unit, UnitResult};
use squeal_scan::ulc::CycleOutcome;

use crate::error::io;
use crate::journal::{Header, Journal, KIND_CYCLE, KIND_UNIT, Owner, block_record, encode_cycle};
use crate::{OutputLock, Provenance, Shard, StoreError};

pub use maps::{MapSensitivity, read_map_sensitivity};
pub use read::{AtlasInfo, AtlasMerge, is_atlas_file, merging_atlas, read_atlas, read_atlas_info};
pub use record::unit_json;
pub use schema::map_name;
pub use write::write_atlas;

pub use crate::ATLAS_SCHEMA;

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
    let nb = mp.map.grid.blocks();
    (0..mp.maps.len())
        .flat_map(|m| (0..nb).map(move |b| (m, b)))
        .filter(|&(m, b)| {
            squeal_scan::shard_owns(shard, &mp, m, b) && !res.blocks.contains_key(&(m, b))
        })
        .collect()
}

/// Whether block `b` of map `m` holding `cells` cells fits the plan's maps.
fn block_fits(plan: &AtlasPlan, m: usize, b: usize, cells: usize) -> bool {
    plan.maps.as_ref().map(|p| p.grid).is_some_and(|g| {
        m < plan.space.n_points() && b < g.blocks() && cells == g.block_rows(b).len() * g.x0.count
    })
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
        crate::check_output(out)?;
        crate::create_parent(out)?;
        // Two runs never write one output: the lock first, then the checks.
        let lock = OutputLock::acquire(out)?;
        let path = crate::journal_path(out);
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
                table: Some(crate::journal::table_text(
                    <AtlasPlan as crate::output::Recorded>::spec_table(plan),
                )),
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
        crate::check_output(out)?;
        let lock = OutputLock::acquire(out)?;
        let path = crate::journal_path(out);
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
            advice: None,
        };
        // As a scan's: what the spec means, not its bytes (a comment edit does not block a
        // resume); the file then records the spec text the atlas started with.
        let plan = &crate::output::started_plan(&path, &header, plan, &plan.spec_text)?;
        if header.shard != shard.map(|s| s.to_string()).unwrap_or_default() {
            return Err(mismatch("different shard"));
        }
        let mut results = AtlasResults::new(plan);
        for r in recs {
            let payload = journal.read(&r)?;
            record::add_record(plan, &mut results, r.kind, &payload).map_err(|(why, advice)| {
                StoreError::NotSquealFile {
                    path: path.clone(),
                    why,
                    advice,
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

    /// Journals a finished unit (synced at once) and keeps it.
    pub fn record(&mut self, r: UnitResult) -> Result<(), StoreError> {
        self.journal
            .append(KIND_UNIT, unit_json(&r).to_string().as_bytes())?;
        self.results.add(&self.plan, r);
        Ok(())
    }

    /// Writes the HDF5 file (via `<out>.tmp`, renamed) and removes the journal. Every owned
    /// unit must be stored, and [`AtlasWriter::results`] made ready by the engine
    /// ([`squeal_scan::atlas::finish`]: the folds reconciled), which also computed `maps`,
    /// each point's map figures.
    pub fn finish(self, maps: &[PointMap]) -> Result<AtlasResults, StoreError> {
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
        let res = (&self.results, maps);
        write_atlas(&self.out, &self.plan, res, &self.prov, self.shard)?;
        let path = self.journal.path.clone();
        std::fs::remove_file(&path).map_err(io(&path, "cannot remove"))?;
        Ok(self.results)
    }
}

/// The atlas's maps come from the scan's driver ([`squeal_scan::drive`] on
/// [`AtlasPlan::map_plan`]): each finished block and cycle search is journalled (cycles
/// synced at once, blocks in groups: `crate::journal`).
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
        self.write_encoded(b, block_record(b))
    }
    /// The block's record, deflated on the worker that made it (as a scan's).
    fn encode_block(b: &squeal_scan::BlockResult) -> Option<Vec<u8>> {
        Some(block_record(b))
    }
    fn write_encoded(
        &mut self,
        b: &squeal_scan::BlockResult,
        record: Vec<u8>,
    ) -> Result<(), StoreError> {
        if !block_fits(&self.plan, b.map, b.block, b.cells.len()) {
            return Err(StoreError::BadBlock {
                path: self.out.clone(),
                why: format!("map {} block {} does not fit the atlas", b.map, b.block),
            });
        }
        self.journal.append_framed(&record)?;
        self.results
            .blocks
            .insert((b.map, b.block), b.cells.clone());
        Ok(())
    }
}
