//! A scan file being finished ([`Assembly`]) from a source of stored blocks and cycles (the
//! journal, or shard files): the store's side of [`squeal_scan::finish::finish`]. It reads
//! each block back and writes it; what the maps add up to (checks, basin stability) is
//! computed by the engine and handed to [`Finishing::complete`], which writes it, the
//! cycles and the rest, and puts the file in place.

use std::path::PathBuf;

use hdf5::File;
use squeal_core::Landscape;
use squeal_scan::cell::{COLUMNS, Cell};
use squeal_scan::census::Rules;
use squeal_scan::scanner::Withdrawn;
use squeal_scan::ulc::CycleReport;
use squeal_scan::{Finishing, MapFigures, Plan};

use crate::cycle::CycleRecord;
use crate::error::H5Ctx;
use crate::h5out::{Dims, Out, Over, class_type, str_attr};
use crate::h5write::{self, CellVars, Meta, Scales, report_of, write_column, write_si_column};
use crate::{LandscapeInfo, OutputLock, StoreError, remove_if_exists};

/// Where a scan file's blocks and cycles come from (read from any thread).
pub(crate) trait Source: Send + Sync {
    /// Whether block `block` of `map` is stored.
    fn stored(&self, map: usize, block: usize) -> bool;
    /// The cells of a block, if stored.
    fn block(&self, map: usize, block: usize) -> Result<Option<Vec<Cell>>, StoreError>;
    /// The recorded cycle of a map, if any.
    fn cycle(&self, map: usize) -> Result<Option<CycleRecord>, StoreError>;
    /// The rule groups withdrawn from a map, each with why.
    fn withdrawn(&self, _map: usize) -> Vec<Withdrawn> {
        Vec::new()
    }
}

/// Where the finished file goes, and what goes with it.
pub(crate) struct Publish {
    /// The output.
    pub out: PathBuf,
    /// An existing `out` is replaced (a merge with `force`).
    pub replace: bool,
    /// The journal the file was made from, removed once the file is in place.
    pub journal: Option<PathBuf>,
    /// The output's lock, held until then.
    pub _lock: OutputLock,
}

/// The temporary file being written: removed when dropped unless it was put in place (a
/// full disk or an interrupted finish leaves no partial file; the journal keeps the work).
struct Tmp {
    path: PathBuf,
    placed: bool,
}

impl Drop for Tmp {
    fn drop(&mut self) {
        if !self.placed {
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

/// A block of a scan read back for its file: its cells and, where each block of rows is one
/// chunk, every cell dataset's chunk (the columns, then their SI twins), compressed on the
/// thread that read it.
#[derive(Debug)]
pub struct StoredBlock {
    map: usize,
    block: usize,
    cells: Vec<Cell>,
    chunks: Option<Vec<Vec<u8>>>,
}

impl AsRef<[Cell]> for StoredBlock {
    fn as_ref(&self) -> &[Cell] {
        &self.cells
    }
}

/// A scan file being finished: its root attributes, coordinates and empty cell datasets
/// written, its blocks to be read back and written ([`Finishing::read_block`],
/// [`Finishing::write_block`]), and the maps' figures to be handed to
/// [`Finishing::complete`]. Made by [`crate::ScanWriter::finishing`] and
/// [`crate::merging`]; finish it with [`squeal_scan::finish::finish`]. Dropped unfinished,
/// it leaves no file behind.
pub struct Assembly {
    plan: Plan,
    file: File,
    dims: Dims,
    aux: Vec<(String, String)>,
    scales: Scales,
    vars: CellVars,
    src: Box<dyn Source>,
    cycles: Vec<Option<CycleRecord>>,
    withdrawn: Vec<Vec<Withdrawn>>,
    landscapes: Vec<Option<LandscapeInfo>>,
    /// The rows of a chunk, where each block is one chunk and is written whole
    /// ([`crate::chunks`]); `None`: blocks are written as selections.
    whole_chunks: Option<usize>,
    publish: Publish,
    tmp: Tmp,
}

impl std::fmt::Debug for Assembly {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Assembly")
            .field("tmp", &self.tmp.path)
            .field("out", &self.publish.out)
            .finish()
    }
}

impl Assembly {
    /// Starts the file at `tmp` (which must not exist): root attributes, coordinates, the
    /// cell datasets (empty), and the cycles and withdrawn rules read from `src`.
    pub(crate) fn begin(
        tmp: PathBuf,
        (plan, meta): (Plan, &Meta),
        src: Box<dyn Source>,
        landscapes: Vec<Option<LandscapeInfo>>,
        publish: Publish,
    ) -> Result<Assembly, StoreError> {
        let file = File::create_excl(&tmp).h5(&tmp)?;
        let tmp = Tmp {
            path: tmp,
            placed: false,
        };
        let path = &tmp.path;
        let mut o = Out {
            file: &file,
            dims: Dims::new(class_type(path)?),
            aux: Vec::new(),
        };
        h5write::root_attrs(&file, &plan, meta).h5(path)?;
        let si = plan.physical().and_then(|ph| ph.friction.table());
        crate::h5out::friction_table(&file, &mut o.dims, plan.maps[0].law.table(), si).h5(path)?;
        let scales = h5write::scales(&mut o, &plan).h5(path)?;
        let vars = h5write::cell_vars(&mut o, &plan, &scales).h5(path)?;
        let (dims, aux) = (o.dims, o.aux);
        let n = plan.maps.len();
        let cycles = (0..n).map(|m| src.cycle(m)).collect::<Result<_, _>>()?;
        let withdrawn = (0..n).map(|m| src.withdrawn(m)).collect();
        let whole_chunks = whole_chunks(&plan, &vars);
        Ok(Assembly {
            plan,
            file,
            dims,
            aux,
            scales,
            vars,
            src,
            cycles,
            withdrawn,
            landscapes,
            whole_chunks,
            publish,
            tmp,
        })
    }

    fn bad(&self, why: String) -> StoreError {
        StoreError::BadBlock {
            path: self.tmp.path.clone(),
            why,
        }
    }
}

/// The rows of a chunk where every block of `plan` is one chunk of the cell datasets `vars`
/// (a grid, blocks as tall as a chunk, the last one no taller) and the datasets take chunks
/// deflated as [`crate::chunks`] deflates them.
fn whole_chunks(plan: &Plan, vars: &CellVars) -> Option<usize> {
    let g = &plan.map.grid;
    let rows = vars.chunk_rows;
    let datasets = vars.vars.iter().chain(vars.si.iter().map(|(d, _)| d));
    let deflated = datasets
        .into_iter()
        .all(crate::chunks::takes_deflated_chunks);
    (!g.is_sample() && rows == g.block_rows.min(g.v0.count) && deflated).then_some(rows)
}

impl Finishing for Assembly {
    type Error = StoreError;
    type Block = StoredBlock;

    fn plan(&self) -> &Plan {
        &self.plan
    }

    fn cycle(&self, map: usize) -> Option<&CycleReport> {
        report_of(&self.cycles[map])
    }

    fn withdrawn(&self, map: usize) -> Vec<Rules> {
        self.withdrawn[map].iter().map(|w| w.rules).collect()
    }

    fn landscape(&self, map: usize) -> Option<Landscape> {
        let l = self.landscapes.get(map).and_then(Option::as_ref);
        l.map(|l| l.landscape)
    }

    fn read_block(&self, map: usize, block: usize) -> Result<Option<StoredBlock>, StoreError> {
        let Some(cells) = self.src.block(map, block)? else {
            return Ok(None);
        };
        let want = self.plan.map.grid.block_rows(block).len() * self.plan.map.grid.x0.count;
        if cells.len() != want {
            let n = cells.len();
            return Err(self.bad(format!(
                "map {map} block {block} holds {n} cells, expected {want}"
            )));
        }
        let chunks = match self.whole_chunks {
            Some(rows) => Some(
                self.chunks(&cells, rows)
                    .map_err(|e| self.bad(format!("map {map} block {block}: {e}")))?,
            ),
            None => None,
        };
        Ok(Some(StoredBlock {
            map,
            block,
            cells,
            chunks,
        }))
    }

    fn write_block(&self, b: StoredBlock) -> Result<(), StoreError> {
        let (map, block, cells) = (b.map, b.block, &b.cells[..]);
        let g = &self.plan.map.grid;
        let (rows, nx) = (g.block_rows(block), g.x0.count);
        let prefix: &[usize] = if self.plan.sweep.is_some() {
            &[map]
        } else {
            &[]
        };
        let bad = |e: hdf5::Error| self.bad(format!("map {map} block {block}: {e}"));
        if let Some(chunks) = &b.chunks {
            let offset: Vec<u64> = (prefix.iter().copied())
                .chain([rows.start, 0])
                .map(|i| i as u64)
                .collect();
            let datasets = self
                .vars
                .vars
                .iter()
                .chain(self.vars.si.iter().map(|(d, _)| d));
            for (ds, chunk) in datasets.zip(chunks) {
                crate::chunks::write_chunk(ds, &offset, chunk).map_err(bad)?;
            }
            return Ok(());
        }
        for (ds, col) in self.vars.vars.iter().zip(COLUMNS) {
            write_column(ds, col, cells, prefix, rows.clone(), nx).map_err(bad)?;
        }
        if let Some(s) = &self.vars.scales {
            for (ds, col) in &self.vars.si {
                write_si_column(ds, col, (cells, s), prefix, rows.clone(), nx).map_err(bad)?;
            }
        }
        Ok(())
    }

    fn complete(self, figures: &[MapFigures]) -> Result<(), StoreError> {
        let Assembly {
            plan,
            file,
            dims,
            aux,
            scales: sc,
            vars,
            src,
            cycles,
            withdrawn,
            landscapes,
            publish,
            mut tmp,
            ..
        } = self;
        let path = tmp.path.clone();
        let n = plan.maps.len();
        if figures.len() != n {
            return Err(StoreError::BadBlock {
                path,
                why: format!("figures for {} maps, the plan has {n}", figures.len()),
            });
        }
        let mut o = Out {
            file: &file,
            dims,
            aux,
        };
        // The rules withdrawn from each map, with why: one line per group, `map M: ...`
        // (empty where every rule's premise held and no audit refuted one).
        let lines: Vec<String> = (withdrawn.iter().enumerate())
            .flat_map(|(m, w)| w.iter().map(move |w| format!("map {m}: {}", w.why)))
            .collect();
        str_attr(&file, "rules_withdrawn", &lines.join("\n")).h5(&path)?;
        let over = Over {
            shape: vec![n],
            scales: vec![sc.map.clone()],
        };
        let nb = plan.map.grid.blocks();
        let done: Vec<u8> = (0..n * nb)
            .map(|k| u8::from(src.stored(k / nb, k % nb)))
            .collect();
        let landscape = |m: usize| landscapes.get(m).and_then(Option::as_ref);
        let blocks = (&over, &sc.block);
        h5write::per_map(&mut o, &plan, blocks, (done, figures), &landscape).h5(&path)?;
        let si = (plan.sweep.is_some(), vars.scales.as_ref());
        h5write::write_cycles(&mut o, &over, &cycles, si).h5(&path)?;
        o.dims.finish().h5(&path)?;
        drop((over, vars, sc));
        file.close().h5(&path)?;
        // The journal (or the shard files) closed before the file takes the output's place.
        drop(src);
        publish.place(&mut tmp)
    }
}

impl Assembly {
    /// Every cell dataset's chunk of a block's `cells` (chunks of `rows` rows).
    fn chunks(&self, cells: &[Cell], rows: usize) -> hdf5::Result<Vec<Vec<u8>>> {
        let size = (rows, self.plan.map.grid.x0.count);
        let mut out: Vec<Vec<u8>> = COLUMNS
            .iter()
            .map(|col| crate::chunks::column_chunk(col, cells, size))
            .collect::<hdf5::Result<_>>()?;
        if let Some(s) = &self.vars.scales {
            for (_, col) in &self.vars.si {
                out.push(crate::chunks::si_chunk(col, (cells, s), size)?);
            }
        }
        Ok(out)
    }
}

#[cfg(test)]
impl Assembly {
    /// Whether blocks are written as whole chunks.
    pub(crate) fn writes_whole_chunks(&self) -> bool {
        self.whole_chunks.is_some()
    }

    /// The same file, its blocks written as selections through HDF5's filters.
    pub(crate) fn by_selections(mut self) -> Assembly {
        self.whole_chunks = None;
        self
    }
}

impl Publish {
    /// Puts the finished `tmp` at the output (replacing it where asked), then removes the
    /// journal; the lock goes last.
    fn place(self, tmp: &mut Tmp) -> Result<(), StoreError> {
        if self.replace {
            remove_if_exists(&self.out)?;
        }
        crate::publish(&tmp.path, &self.out)?;
        tmp.placed = true;
        if let Some(j) = &self.journal {
            remove_if_exists(j)?;
        }
        Ok(())
    }
}
