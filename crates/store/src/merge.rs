//! Joining shard files into the file a single run would have written (`squeal merge`): the
//! shards as the source of an [`Assembly`].

use std::path::{Path, PathBuf};

use squeal_scan::Plan;
use squeal_scan::scanner::Cell;

use crate::assembly::{Assembly, Publish, Source};
use crate::error::H5Ctx;
use crate::h5write::Meta;
use crate::journal::CycleRecord;
use crate::{
    OutputLock, Shard, StoreError, read, refuse_input_as_output, remove_if_exists, shard_owns,
    tmp_path,
};

struct ShardSource {
    plan: Plan,
    files: Vec<ShardFile>,
}

impl ShardSource {
    /// The shard that holds block `block` of `map`, if one does.
    fn holder(&self, map: usize, block: usize) -> Option<&ShardFile> {
        let nb = self.plan.map.grid.blocks();
        (self.files.iter()).find(|(_, _, s, done)| {
            shard_owns(Some(*s), &self.plan, map, block) && done[map * nb + block] == 1
        })
    }
}

impl Source for ShardSource {
    fn stored(&self, map: usize, block: usize) -> bool {
        self.holder(map, block).is_some()
    }

    fn block(&self, map: usize, block: usize) -> Result<Option<Vec<Cell>>, StoreError> {
        let Some((path, f, _, _)) = self.holder(map, block) else {
            return Ok(None);
        };
        let rows = self.plan.map.grid.block_rows(block);
        let sweep = self.plan.sweep.is_some();
        read::read_block(f, sweep, map, rows).h5(path).map(Some)
    }

    fn cycle(&self, map: usize) -> Result<Option<CycleRecord>, StoreError> {
        let sweep = self.plan.sweep.is_some();
        for (path, f, _, _) in &self.files {
            if let Some(c) = read::read_cycle(f, sweep, map).h5(path)? {
                return Ok(Some(c));
            }
        }
        Ok(None)
    }
}

/// What a shard file states about the scan it belongs to; every shard of one scan states
/// the same.
struct ShardHeader {
    path: PathBuf,
    spec: String,
    n: usize,
    name: String,
    version: String,
    git: String,
}

/// An open shard: its path, file, shard and `blocks_done`.
type ShardFile = (PathBuf, hdf5::File, Shard, Vec<u8>);

/// Opens shard `p`, refusing a file without a `shard` attribute.
fn open_shard(p: &Path) -> Result<(ShardHeader, ShardFile), StoreError> {
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
    let header = ShardHeader {
        path: p.to_path_buf(),
        spec: read::str_attr(&f, "spec").h5(p)?,
        n: s.n,
        name: read::str_attr(&f, "name").h5(p)?,
        version: read::str_attr(&f, "squeal_version").h5(p)?,
        git: read::str_attr(&f, "git_revision").h5(p)?,
    };
    let done: Vec<u8> = f.dataset("blocks_done").h5(p)?.read_raw().h5(p)?;
    Ok((header, (p.to_path_buf(), f, s, done)))
}

/// Refuses two shards of different scans or builds.
fn belong_together(a: &ShardHeader, b: &ShardHeader) -> Result<(), StoreError> {
    let why = if a.spec != b.spec {
        "different spec text"
    } else if a.n != b.n {
        "different shard counts"
    } else if a.name != b.name {
        "different scan names"
    } else if a.version != b.version || a.git != b.git {
        "written by different squeal builds"
    } else {
        return Ok(());
    };
    Err(StoreError::Shards(format!(
        "{} and {} do not belong together: {why}",
        a.path.display(),
        b.path.display()
    )))
}

/// Every shard holds all of its own blocks of `plan` and none of another's, in cells of the
/// plan's shape: a file whose stored spec now reads to another grid or map count would have
/// its blocks read as the wrong rows or maps.
fn check_owned_blocks(files: &[ShardFile], plan: &Plan) -> Result<(), StoreError> {
    let g = &plan.map.grid;
    let nb = g.blocks();
    // The cells' dimensions as written (h5write's cell_vars): (map, v0, x0), without the
    // map for one map and without x0 for random samples.
    let shape: Vec<usize> = [
        plan.sweep.as_ref().map(|_| plan.maps.len()),
        Some(g.v0.count),
        (!g.is_sample()).then_some(g.x0.count),
    ]
    .into_iter()
    .flatten()
    .collect();
    for (p, f, s, done) in files {
        let labels = f.dataset("labels").h5(p)?.shape();
        if done.len() != plan.maps.len() * nb || labels != shape {
            return Err(StoreError::NotSquealFile {
                path: p.clone(),
                why: format!(
                    "its cells ({labels:?}, {} blocks done) do not match its stored spec's \
                     grid ({shape:?}, {} blocks)",
                    done.len(),
                    plan.maps.len() * nb
                ),
                advice: None,
            });
        }
        let (mut missing, mut total) = (0, 0);
        for (id, &d) in done.iter().enumerate() {
            if shard_owns(Some(*s), plan, id / nb, id % nb) {
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
    Ok(())
}

/// Opens every shard, checks that they belong together, that none repeats another and that
/// all `n` are there; the first one's header and the files.
fn open_shards(shards: &[PathBuf]) -> Result<(ShardHeader, Vec<ShardFile>), StoreError> {
    let mut first: Option<ShardHeader> = None;
    let mut files: Vec<ShardFile> = Vec::new();
    for p in shards {
        let (header, file) = open_shard(p)?;
        match &first {
            None => first = Some(header),
            Some(h0) => belong_together(h0, &header)?,
        }
        let s = file.2;
        if let Some((q, ..)) = files.iter().find(|(_, _, t, _)| t.k == s.k) {
            return Err(StoreError::Shards(format!(
                "{} and {} overlap: both are shard {s}",
                q.display(),
                p.display()
            )));
        }
        files.push(file);
    }
    let first = first.ok_or_else(|| StoreError::Shards("no shard files given".into()))?;
    let n = first.n;
    if let Some(k) = (1..=n).find(|&k| !files.iter().any(|(_, _, s, _)| s.k == k)) {
        return Err(StoreError::Shards(format!(
            "missing shard {k}/{n} (have {} of {n} files)",
            files.len()
        )));
    }
    Ok((first, files))
}

/// Starts joining shard files into the file a single run would have written (the same
/// datasets and attributes, without `shard`; provenance is taken from the shards, which
/// must agree): finish it with [`squeal_scan::finish::finish`], as a scan's file. Its plan
/// ([`squeal_scan::Finishing::plan`]) says what the caller draws, or not: random samples
/// are no map.
pub fn merging(shards: &[PathBuf], out: &Path, force: bool) -> Result<Assembly, StoreError> {
    if shards.is_empty() {
        return Err(StoreError::Shards("no shard files given".into()));
    }
    crate::check_output(out)?;
    refuse_input_as_output(shards, out)?;
    if out.exists() && !force {
        return Err(StoreError::Exists {
            path: out.to_path_buf(),
        });
    }
    crate::create_parent(out)?;
    let lock = OutputLock::acquire(out)?;
    let (h, files) = open_shards(shards)?;
    let table = read::stored_table(&files[0].1).h5(&files[0].0)?;
    let mut plan = Plan::from_stored_toml_table(&h.spec, &format!("{}.toml", h.name), table)
        .map_err(|e| StoreError::NotSquealFile {
            path: h.path.clone(),
            why: e.to_string(),
            advice: None,
        })?;
    plan.name = h.name.clone();
    check_owned_blocks(&files, &plan)?;
    // The landscapes as the shards stored them (one plan: the same in every shard).
    let (p0, f0) = (&files[0].0, &files[0].1);
    let landscapes = read::read_landscapes(f0, plan.maps.len()).h5(p0)?;
    let tmp = tmp_path(out);
    remove_if_exists(&tmp)?;
    let meta = Meta {
        version: &h.version,
        git_revision: &h.git,
        shard: None,
    };
    let src = ShardSource {
        plan: plan.clone(),
        files,
    };
    // The output is replaced only once the merged file is complete: a failed merge leaves
    // it as it was, and no temporary file behind.
    let publish = Publish {
        out: out.to_path_buf(),
        replace: force,
        journal: None,
        _lock: lock,
    };
    Assembly::begin(tmp, (plan, &meta), Box::new(src), landscapes, publish)
}
