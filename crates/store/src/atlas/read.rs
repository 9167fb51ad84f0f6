//! Reads an atlas file back (the inverse of [`super::write`]), and merges shard files.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use hdf5::File;
use hdf5::types::VarLenUnicode;
use squeal_scan::atlas::columns::{
    BOUNDARY_COLUMNS, COLUMNS, empty_boundary, empty_point, finish_point,
};
use squeal_scan::atlas::true_stick::LANDSCAPE_COLUMNS;
use squeal_scan::atlas::{
    AtlasPlan, AtlasRegime, AtlasResults, BoundaryResult, BoundaryStatus, PointMap, PointResult,
};
use squeal_scan::column::Column;

use super::schema::{
    BOUNDARIES_DONE, BOUNDARY_NOTE, BOUNDARY_NOTE_KIND, FOLD_CHANGES, LANDSCAPE_NOT_COMPUTED, NOTE,
    NOTE_KIND, Named, POINTS_DONE, REGIME, SEARCHES, half_dt_of, note_of, set_landscape,
    stored_name,
};
use super::{ATLAS_SCHEMA, maps, missing_blocks, missing_units, write_atlas};
use crate::error::H5Ctx;
use crate::read::{rd_n, rd_new_n, rd_nums_n};
use crate::{OutputLock, Provenance, Shard, StoreError};

/// Whether `path` is an atlas file (HDF5 with schema `squeal-atlas/...`).
pub fn is_atlas_file(path: &Path) -> bool {
    if squeal_scan::files::refuse_non_regular(path).is_err() {
        return false;
    }
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

/// The `n` notes read back from their words and kinds: `None` where empty ([`note_of`]).
fn notes(
    file: &File,
    path: &Path,
    (name, _): Named,
    (kind_name, _): Named,
    n: usize,
) -> Result<Vec<Option<squeal_scan::atlas::Note>>, StoreError> {
    let v: Vec<VarLenUnicode> = rd_n(file, path, name, n)?;
    let kinds: Vec<u8> = rd_new_n(file, path, kind_name, n)?;
    Ok(v.into_iter()
        .enumerate()
        .map(|(i, n)| note_of(Some(n.as_str().to_string()), kinds.get(i).copied()))
        .collect())
}

/// Reads an atlas file back: its plan (from the stored spec), results and shard.
pub fn read_atlas(path: &Path) -> Result<(AtlasPlan, AtlasResults, Option<Shard>), StoreError> {
    let not = |why: String| StoreError::NotSquealFile {
        path: path.to_path_buf(),
        why,
        advice: None,
    };
    squeal_scan::files::refuse_non_regular(path)?;
    if !is_atlas_file(path) {
        return Err(not(format!("not an atlas file (schema {ATLAS_SCHEMA})")));
    }
    let file = File::open(path).h5(path)?;
    let spec = crate::read::str_attr(&file, "spec").h5(path)?;
    let table = crate::read::stored_table(&file).h5(path)?;
    let mut plan = AtlasPlan::from_stored_toml_table(&spec, &path.display().to_string(), table)
        .map_err(|e| not(e.to_string()))?;
    // A spec without `name` is named after its own file, not this one (a shard `s1.h5`).
    plan.name = crate::read::str_attr(&file, "name").h5(path)?;
    let shard = crate::read::str_attr(&file, "shard")
        .ok()
        .and_then(|s| s.parse().ok());
    let mut res = AtlasResults::new(&plan);
    read_points(&file, path, &plan, &mut res)?;
    if plan.maps.is_some() {
        maps::read_maps(&file, path, &plan, &mut res)?;
    }
    if plan.n_boundaries() > 0 {
        read_boundaries(&file, path, &plan, &mut res)?;
    }
    Ok((plan, res, shard))
}

/// The computed points: every column of the point tables, the regime and the note. Each
/// dataset holds one value per point of the stored spec's plan ([`rd_n`]).
fn read_points(
    file: &File,
    path: &Path,
    plan: &AtlasPlan,
    res: &mut AtlasResults,
) -> Result<(), StoreError> {
    let n = plan.space.n_points();
    let mut pts: Vec<PointResult> = (0..n).map(|_| empty_point()).collect();
    let stored = |c: &_| Some(stored_name(plan, c).0);
    read_columns(file, path, COLUMNS.iter().map(|c| (c, stored(c))), &mut pts)?;
    if plan.space.law.family().has_landscape() {
        let named = LANDSCAPE_COLUMNS
            .iter()
            .map(|c| (c, Some(c.name.to_string())));
        read_columns(file, path, named, &mut pts)?;
        let (name, _) = squeal_scan::landscape::LANDSCAPE;
        for (p, v) in pts.iter_mut().zip(rd_n::<u8>(file, path, name, n)?) {
            if v == LANDSCAPE_NOT_COMPUTED {
                p.landscape = None;
            } else {
                set_landscape(p, v);
            }
        }
    }
    let done: Vec<u8> = rd_n(file, path, POINTS_DONE.0, n)?;
    let regime: Vec<u8> = rd_n(file, path, REGIME.0, n)?;
    let mut notes = notes(file, path, NOTE, NOTE_KIND, n)?.into_iter();
    for (i, mut p) in pts.into_iter().enumerate() {
        let note = notes.next().flatten();
        if done.get(i) == Some(&1) {
            p.note = note;
            p.regime = AtlasRegime::from_u8(regime[i]).unwrap_or(AtlasRegime::Undecided);
            finish_point(&mut p);
            res.points[i] = Some(p);
        }
    }
    Ok(())
}

/// The computed boundary searches. Datasets that files written before them lack read as
/// not checked (`*_half_dt`), none (`fold_changes`) or NaN (`fold_nu_err`).
fn read_boundaries(
    file: &File,
    path: &Path,
    plan: &AtlasPlan,
    res: &mut AtlasResults,
) -> Result<(), StoreError> {
    let n = plan.n_boundaries();
    let done: Vec<u8> = rd_n(file, path, BOUNDARIES_DONE.0, n)?;
    let status: Vec<Vec<u8>> = (SEARCHES.iter())
        .map(|s| rd_n(file, path, &s.status_name(), n))
        .collect::<Result<_, _>>()?;
    let half_dt: Vec<Vec<u8>> = (SEARCHES.iter())
        .map(|s| rd_new_n(file, path, &s.half_dt_name(), n))
        .collect::<Result<_, _>>()?;
    let changes: Vec<u32> = rd_new_n(file, path, FOLD_CHANGES.0, n)?;
    let mut notes = notes(file, path, BOUNDARY_NOTE, BOUNDARY_NOTE_KIND, n)?.into_iter();
    let mut bs: Vec<BoundaryResult> = (0..n).map(empty_boundary).collect();
    // A figure files written before it lack (or not measured) reads as its fill.
    let named = BOUNDARY_COLUMNS.iter().map(|c| {
        let (name, _) = plan.boundary_dataset(c.name, c.long_name);
        (c, file.link_exists(&name).then_some(name))
    });
    read_columns(file, path, named, &mut bs)?;
    for (j, mut b) in bs.into_iter().enumerate() {
        let note = notes.next().flatten();
        if done.get(j) != Some(&1) {
            continue;
        }
        for (k, s) in SEARCHES.iter().enumerate() {
            let d = (s.get_mut)(&mut b);
            d.status = BoundaryStatus::from_u8(status[k][j]).unwrap_or(BoundaryStatus::NotComputed);
            d.half_dt_holds = half_dt_of(half_dt[k].get(j));
        }
        b.fold.changes = changes.get(j).copied().unwrap_or(0);
        b.note = note;
        res.boundaries[j] = Some(b);
    }
    Ok(())
}

/// Every column of a table into `rows` (one record per entry of the stored spec's plan:
/// [`rd_nums_n`]), each from the dataset named beside it; `None`: not in the file, the fill.
fn read_columns<'c, R: 'c>(
    file: &File,
    path: &Path,
    cols: impl Iterator<Item = (&'c Column<R>, Option<String>)>,
    rows: &mut [R],
) -> Result<(), StoreError> {
    for (c, name) in cols {
        let vals = match name {
            Some(name) => rd_nums_n(file, path, (&name, c.kind), rows.len())?,
            None => vec![c.fill; rows.len()],
        };
        for (r, v) in rows.iter_mut().zip(vals) {
            (c.set)(r, v);
        }
    }
    Ok(())
}

/// Atlas shard files (all `N` shards of one spec) being joined into the file one run writes:
/// their plan and everything they hold together, which the engine makes ready
/// ([`squeal_scan::atlas::finish`]: a point and its fold may come from different shards)
/// before [`AtlasMerge::finish`] writes the file. Holds the output's lock.
#[derive(Debug)]
pub struct AtlasMerge {
    /// The shards' plan.
    pub plan: AtlasPlan,
    /// Everything the shards hold.
    pub results: AtlasResults,
    out: PathBuf,
    _lock: OutputLock,
}

/// Starts joining atlas shard files into `out` ([`AtlasMerge`]): refuses an existing `out`
/// without `force`, and shards that miss units or map blocks.
pub fn merging_atlas(
    shards: &[PathBuf],
    out: &Path,
    force: bool,
) -> Result<AtlasMerge, StoreError> {
    crate::check_output(out)?;
    crate::refuse_input_as_output(shards, out)?;
    crate::create_parent(out)?;
    let lock = OutputLock::acquire(out)?;
    if out.exists() && !force {
        return Err(StoreError::Exists {
            path: out.to_path_buf(),
        });
    }
    let (plan, results) = read_shards(shards)?;
    let missing = missing_units(&plan, &results, None);
    if !missing.is_empty() {
        return Err(StoreError::Incomplete {
            path: out.to_path_buf(),
            missing: missing.len(),
            total: plan.units().len(),
        });
    }
    let blocks = missing_blocks(&plan, &results, None);
    if !blocks.is_empty() {
        return Err(StoreError::Incomplete {
            path: out.to_path_buf(),
            missing: blocks.len(),
            total: plan.map_plan().map_or(0, |p| p.total_blocks()),
        });
    }
    Ok(AtlasMerge {
        plan,
        results,
        out: out.to_path_buf(),
        _lock: lock,
    })
}

impl AtlasMerge {
    /// Writes the joined file, with each point's map figures `maps` (computed by the engine
    /// from [`AtlasMerge::results`]; none without maps).
    pub fn finish(self, maps: &[PointMap], prov: &Provenance) -> Result<(), StoreError> {
        write_atlas(&self.out, &self.plan, (&self.results, maps), prov, None)
    }
}

/// The plan of the shards and everything they hold together: each of `1..=N` once, all of
/// one spec.
fn read_shards(shards: &[PathBuf]) -> Result<(AtlasPlan, AtlasResults), StoreError> {
    let mut acc: Option<(AtlasPlan, AtlasResults)> = None;
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
        let Some((p0, all)) = acc.as_mut() else {
            acc = Some((pl, r));
            continue;
        };
        if p0.spec_text != pl.spec_text {
            return Err(StoreError::SpecMismatch {
                path: p.clone(),
                why: "different spec text".into(),
                advice: None,
            });
        }
        add_shard(all, r);
    }
    let Some(acc) = acc else {
        return Err(StoreError::Shards("no shard files given".into()));
    };
    if seen.len() != n_shards.unwrap_or(0) {
        return Err(StoreError::Shards(format!(
            "{} of {} shards given",
            seen.len(),
            n_shards.unwrap_or(0)
        )));
    }
    Ok(acc)
}

/// Adds what a shard computed to `all`.
fn add_shard(all: &mut AtlasResults, r: AtlasResults) {
    for (a, b) in all.points.iter_mut().zip(r.points) {
        if b.is_some() {
            *a = b;
        }
    }
    for (a, b) in all.boundaries.iter_mut().zip(r.boundaries) {
        if b.is_some() {
            *a = b;
        }
    }
    all.blocks.extend(r.blocks);
    for (m, c) in r.map_cycles {
        all.map_cycles.entry(m).or_insert(c);
    }
}

/// An atlas file for `squeal info`: its root attributes (provenance, name, law, the fixed
/// parameters...) and what [`read_atlas`] reads (the plan of its stored spec,
/// every point and boundary, its shard).
#[derive(Clone, Debug)]
pub struct AtlasInfo {
    /// Root attributes as text, by name.
    pub attrs: Vec<(String, String)>,
    /// The plan of the stored spec (named as the file says).
    pub plan: squeal_scan::atlas::AtlasPlan,
    /// The points, boundaries and maps stored.
    pub results: AtlasResults,
    /// The shard of a shard file.
    pub shard: Option<squeal_scan::Shard>,
}

/// Opens and checks an atlas file and reads it for a summary.
pub fn read_atlas_info(path: &Path) -> Result<AtlasInfo, StoreError> {
    let (plan, results, shard) = read_atlas(path)?;
    let file = crate::read::open_with_schema(path, ATLAS_SCHEMA)?;
    let attrs = crate::read::root_attrs_text(&file).h5(path)?;
    Ok(AtlasInfo {
        attrs,
        plan,
        results,
        shard,
    })
}
