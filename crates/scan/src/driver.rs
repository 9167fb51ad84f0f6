//! The scan driver: plan -> per-map preparation -> blocks -> a [`Sink`].
//!
//! The maps with work left are prepared first (each one's section searched once, the cycle
//! located, the census taken), in parallel over the maps and over each census's starts;
//! each map, once prepared, adds its pending `(map, block)` pairs as jobs on the rayon
//! pool, with no barrier between blocks or maps (nor between one map's preparation and
//! another's blocks). Each block is encoded for the sink on the worker that computed
//! it ([`Sink::encode_block`]); finished blocks and located cycles go over a channel to the
//! one thread that called [`drive`], which hands them to the sink (the store's journal and
//! its fsync stay off the workers' path). A
//! result depends only on the plan and the cell, never on the thread count or the order in
//! which blocks finish.

use std::collections::HashSet;
use std::sync::atomic::AtomicBool;
use std::sync::{Mutex, OnceLock};
use std::time::{Duration, Instant};

use crate::cell::Cell;
use crate::error::ScanError;
use crate::executor::{Emit, execute_growing};
use crate::scanner::{BlockResult, MapContext, Observer, Withdrawn, run_block};
use crate::spec::Plan;
use crate::ulc::CycleOutcome;

/// Where finished work goes. One thread calls it (the one that called [`drive`]).
pub trait Sink {
    /// What the sink can fail with.
    type Error;
    /// Whether block `block` of map `map` is already stored (a resumed scan).
    fn is_done(&self, map: usize, block: usize) -> bool;
    /// Whether map `map` is already prepared and its cycle (or its absence) stored.
    fn has_cycle(&self, map: usize) -> bool;
    /// Stores the cycle search of a map: `None` when the plan does not locate cycles.
    fn write_cycle(&mut self, map: usize, cycle: Option<&CycleOutcome>) -> Result<(), Self::Error>;
    /// Stores a finished block (a block stored again replaces the one before: the redo of
    /// [`crate::redo`]).
    fn write_block(&mut self, block: &BlockResult) -> Result<(), Self::Error>;
    /// The record [`Sink::write_encoded`] stores for `block`, made on the worker that
    /// computed the block (encoding and checksumming a 4096 x 4096 map's 1.4 GB of cells on
    /// the sink's one thread held the workers back): `None` for a sink that stores blocks
    /// as they are (then [`Sink::write_block`] gets it).
    fn encode_block(_block: &BlockResult) -> Option<Vec<u8>>
    where
        Self: Sized,
    {
        None
    }
    /// Stores `block`, whose record `record` [`Sink::encode_block`] made.
    fn write_encoded(&mut self, block: &BlockResult, _record: Vec<u8>) -> Result<(), Self::Error> {
        self.write_block(block)
    }
    /// The rule groups recorded as withdrawn from map `map` (by its census or an audit), in
    /// the order recorded; none for a sink that keeps no record.
    fn withdrawn(&mut self, _map: usize) -> Result<Vec<Withdrawn>, Self::Error> {
        Ok(Vec::new())
    }
    /// Records rule groups withdrawn from map `map`: before its cycle record and before any
    /// block decided without them, so that a resumed scan knows them.
    fn write_withdrawn(&mut self, _map: usize, _w: &[Withdrawn]) -> Result<(), Self::Error> {
        Ok(())
    }
    /// The stored cells of block `block` of map `map` (`None`: not stored, or a sink that
    /// cannot read its blocks back; the audit then cannot act on it).
    fn stored_block(
        &mut self,
        _map: usize,
        _block: usize,
    ) -> Result<Option<Vec<Cell>>, Self::Error> {
        Ok(None)
    }
}

/// A sink that two runs share at once (an atlas's units and its maps' blocks, each run by
/// [`execute`] with the sink on its own thread): every call locks it. A poisoned lock (a
/// panic on the other thread) is taken as it is; the panic itself reaches the caller.
pub struct Shared<'a, S>(pub &'a std::sync::Mutex<S>);

impl<S> Shared<'_, S> {
    fn lock(&self) -> std::sync::MutexGuard<'_, S> {
        self.0.lock().unwrap_or_else(|e| e.into_inner())
    }
}

impl<S: Sink> Sink for Shared<'_, S> {
    type Error = S::Error;
    fn is_done(&self, map: usize, block: usize) -> bool {
        self.lock().is_done(map, block)
    }
    fn has_cycle(&self, map: usize) -> bool {
        self.lock().has_cycle(map)
    }
    fn write_cycle(&mut self, map: usize, cycle: Option<&CycleOutcome>) -> Result<(), S::Error> {
        self.lock().write_cycle(map, cycle)
    }
    fn write_block(&mut self, block: &BlockResult) -> Result<(), S::Error> {
        self.lock().write_block(block)
    }
    fn encode_block(block: &BlockResult) -> Option<Vec<u8>> {
        S::encode_block(block)
    }
    fn write_encoded(&mut self, block: &BlockResult, record: Vec<u8>) -> Result<(), S::Error> {
        self.lock().write_encoded(block, record)
    }
    fn withdrawn(&mut self, map: usize) -> Result<Vec<Withdrawn>, S::Error> {
        self.lock().withdrawn(map)
    }
    fn write_withdrawn(&mut self, map: usize, w: &[Withdrawn]) -> Result<(), S::Error> {
        self.lock().write_withdrawn(map, w)
    }
    fn stored_block(&mut self, map: usize, block: usize) -> Result<Option<Vec<Cell>>, S::Error> {
        self.lock().stored_block(map, block)
    }
}

/// A sink that keeps everything in memory (tests, small scans, examples).
#[derive(Clone, Debug, Default)]
pub struct MemorySink {
    /// Cycle search per map, as written.
    pub cycles: std::collections::BTreeMap<usize, Option<CycleOutcome>>,
    /// Blocks by `(map, block)`.
    pub blocks: std::collections::BTreeMap<(usize, usize), BlockResult>,
    /// Rule groups withdrawn, by map, in the order recorded.
    pub withdrawn: std::collections::BTreeMap<usize, Vec<Withdrawn>>,
}

impl MemorySink {
    /// The cells of map `map`, row-major `(v0, x0)`, if every block is there.
    pub fn map_cells(&self, plan: &Plan, map: usize) -> Option<Vec<crate::Cell>> {
        let mut out = Vec::with_capacity(plan.map.grid.cells());
        for b in 0..plan.map.grid.blocks() {
            out.extend_from_slice(&self.blocks.get(&(map, b))?.cells);
        }
        Some(out)
    }
}

impl Sink for MemorySink {
    type Error = std::convert::Infallible;
    fn is_done(&self, map: usize, block: usize) -> bool {
        self.blocks.contains_key(&(map, block))
    }
    fn has_cycle(&self, map: usize) -> bool {
        self.cycles.contains_key(&map)
    }
    fn write_cycle(&mut self, map: usize, cycle: Option<&CycleOutcome>) -> Result<(), Self::Error> {
        self.cycles.insert(map, cycle.cloned());
        Ok(())
    }
    fn write_block(&mut self, block: &BlockResult) -> Result<(), Self::Error> {
        self.blocks.insert((block.map, block.block), block.clone());
        Ok(())
    }
    fn withdrawn(&mut self, map: usize) -> Result<Vec<Withdrawn>, Self::Error> {
        Ok(self.withdrawn.get(&map).cloned().unwrap_or_default())
    }
    fn write_withdrawn(&mut self, map: usize, w: &[Withdrawn]) -> Result<(), Self::Error> {
        let have = self.withdrawn.entry(map).or_default();
        for x in w {
            if !have.iter().any(|h| h.rules == x.rules) {
                have.push(x.clone());
            }
        }
        Ok(())
    }
    fn stored_block(&mut self, map: usize, block: usize) -> Result<Option<Vec<Cell>>, Self::Error> {
        Ok(self.blocks.get(&(map, block)).map(|b| b.cells.clone()))
    }
}

/// Shard `k` of `n` (1-based), written `K/N`: the blocks whose global index
/// `map * blocks_per_map + block` is `k - 1` modulo `n`.
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
    type Err = ScanError;
    fn from_str(s: &str) -> Result<Shard, ScanError> {
        let bad = || ScanError::Shard(s.to_string());
        let (k, n) = s.split_once('/').ok_or_else(bad)?;
        let k: usize = k.trim().parse().map_err(|_| bad())?;
        let n: usize = n.trim().parse().map_err(|_| bad())?;
        if k == 0 || n == 0 || k > n {
            return Err(bad());
        }
        Ok(Shard { k, n })
    }
}

/// Whether `shard` (None: the whole scan) owns block `block` of map `map`.
pub fn shard_owns(shard: Option<Shard>, plan: &Plan, map: usize, block: usize) -> bool {
    match shard {
        None => true,
        Some(s) => (map * plan.map.grid.blocks() + block) % s.n == s.k - 1,
    }
}

/// The work left: owned blocks not yet in the sink.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Pending {
    /// `(map, block)` pairs to compute.
    pub blocks: Vec<(usize, usize)>,
    /// Maps that need preparing although none of their blocks is pending (the cycle is
    /// recorded by every shard that sees the map).
    pub prepare_only: Vec<usize>,
    /// Cells in the pending blocks.
    pub cells: usize,
}

impl Pending {
    /// The work left for `shard` of `plan`, given what `sink` holds.
    pub fn of<S: Sink + ?Sized>(plan: &Plan, shard: Option<Shard>, sink: &S) -> Pending {
        let g = &plan.map.grid;
        let mut p = Pending::default();
        for m in 0..plan.maps.len() {
            let before = p.blocks.len();
            for b in 0..g.blocks() {
                if shard_owns(shard, plan, m, b) && !sink.is_done(m, b) {
                    p.blocks.push((m, b));
                    p.cells += g.block_rows(b).len() * g.x0.count;
                }
            }
            if p.blocks.len() == before && !sink.has_cycle(m) {
                p.prepare_only.push(m);
            }
        }
        p
    }

    /// Maps to prepare: those with pending blocks and those prepared only for their cycle.
    pub fn maps_to_prepare(&self) -> usize {
        let mut maps: Vec<usize> = self.blocks.iter().map(|&(m, _)| m).collect();
        maps.extend(&self.prepare_only);
        maps.sort_unstable();
        maps.dedup();
        maps.len()
    }

    /// Pending cells of map `map`.
    pub fn cells_of(&self, plan: &Plan, map: usize) -> usize {
        let g = &plan.map.grid;
        self.blocks
            .iter()
            .filter(|(m, _)| *m == map)
            .map(|&(_, b)| g.block_rows(b).len() * g.x0.count)
            .sum()
    }
}

/// What a drive did.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct DriveReport {
    /// Blocks computed and handed to the sink.
    pub blocks: usize,
    /// Cells in those blocks.
    pub cells: usize,
    /// Whether `stop` was raised before the work was done (the finished blocks are in the
    /// sink; the rest is pending).
    pub interrupted: bool,
    /// Wall time from the start until the last map was prepared (blocks of the maps
    /// prepared before run meanwhile).
    pub prepare: Duration,
    /// Time the sink's thread spent in the sink (the rest of the drive it waits).
    pub sink: Duration,
    /// The blocks this drive computed, and which of them hold a cell whose audit disagrees
    /// with its label ([`crate::redo::act_on_audits`] reads only those of the computed ones).
    pub computed: Computed,
}

/// The `(map, block)` pairs a drive computed and handed to the sink.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Computed {
    /// Every block computed.
    pub blocks: HashSet<(usize, usize)>,
    /// Those with a cell whose run to settlement disagrees with its label
    /// ([`crate::cell::Audit::Disagrees`]).
    pub disagreeing: HashSet<(usize, usize)>,
}

/// Why a drive failed.
#[derive(Debug, thiserror::Error)]
pub enum DriveError<E> {
    /// A map could not be prepared.
    #[error(transparent)]
    Scan(ScanError),
    /// The sink refused a record.
    #[error(transparent)]
    Sink(E),
}

impl<E> From<ScanError> for DriveError<E> {
    fn from(e: ScanError) -> Self {
        DriveError::Scan(e)
    }
}

enum Msg {
    Prepared,
    Cycle(usize, Box<Option<CycleOutcome>>, Vec<Withdrawn>),
    /// A block, the sink's record of it ([`Sink::encode_block`]) and whether an audit of
    /// its cells disagrees.
    Block(BlockResult, Option<Vec<u8>>, bool),
}

/// A piece of a drive's work.
enum Job {
    /// Prepare map `m`, write its cycle if the sink lacks it, and add its pending blocks.
    Prepare(usize),
    /// Compute block `b` of the prepared map `m`.
    Block(usize, usize),
}

/// Runs the pending work of `shard` of `plan` into `sink` through the one executor
/// ([`crate::executor::execute_growing`]: workers on the rayon pool, the sink on this
/// thread). Raising `stop` hands out no further work: the blocks in flight are finished and
/// go to the sink (a signal lost them before: one 48-row block interrupted after 15 s left
/// nothing for the resume), then the drive returns with `interrupted`.
pub fn drive<S: Sink>(
    plan: &Plan,
    shard: Option<Shard>,
    sink: &mut S,
    observer: &dyn Observer,
    stop: &AtomicBool,
) -> Result<DriveReport, DriveError<S::Error>> {
    drive_prepared(plan, shard, sink, (observer, stop), Prepared::default())
}

/// [`drive`], with maps already prepared (by the pilot, [`crate::estimate::Estimate`]): a
/// map found there is not prepared again, unless the sink recorded withdrawals for it (a
/// resume decides its blocks without them, [`MapContext::prepare_without`]).
pub fn drive_prepared<S: Sink>(
    plan: &Plan,
    shard: Option<Shard>,
    sink: &mut S,
    (observer, stop): (&dyn Observer, &AtomicBool),
    prepared: Prepared,
) -> Result<DriveReport, DriveError<S::Error>> {
    let pending = Pending::of(plan, shard, &*sink);
    let mut report = DriveReport::default();
    let cycles_missing = run_maps(
        plan,
        (&pending, prepared),
        sink,
        observer,
        stop,
        &mut report,
    )?;
    report.interrupted = report.blocks < pending.blocks.len() || cycles_missing;
    Ok(report)
}

/// Prepares every map with pending work (in parallel over the maps, and each map's census
/// in parallel over its starts), writes the cycles the sink lacks and computes the pending
/// blocks: whether a wanted cycle was not written (`stop` raised). The maps' preparations
/// are the first jobs of the queue; each one, when done, adds its map's blocks to the end
/// of the queue, so blocks of the maps already prepared keep the threads busy while the
/// last maps are prepared. Before, every block waited for every map's preparation (and,
/// before that, the first block of a map prepared it behind a `OnceLock` while the other
/// workers waited on the lock: the 4096 x 4096 map's 7.7 s of preparation ran on one of
/// two threads). A map's cycle (and the rule groups its census withdrew) reaches the sink
/// before any of its blocks: the preparation emits them before it adds the blocks.
fn run_maps<S: Sink>(
    plan: &Plan,
    (pending, prepared): (&Pending, Prepared),
    sink: &mut S,
    observer: &dyn Observer,
    stop: &AtomicBool,
    report: &mut DriveReport,
) -> Result<bool, DriveError<S::Error>> {
    // The groups an audit withdrew before a resume: the map's blocks still to compute are
    // decided without them (a census withdraws its own again when the map is prepared).
    let recorded = (0..plan.maps.len())
        .map(|m| sink.withdrawn(m))
        .collect::<Result<Vec<_>, _>>()
        .map_err(DriveError::Sink)?;
    let need_cycle: Vec<bool> = (0..plan.maps.len()).map(|m| !sink.has_cycle(m)).collect();
    let mut maps: Vec<usize> = pending
        .prepare_only
        .iter()
        .copied()
        .chain(pending.blocks.iter().map(|&(m, _)| m))
        .collect();
    maps.sort_unstable();
    maps.dedup();
    let cycles_wanted = maps.iter().filter(|&&m| need_cycle[m]).count();
    let mut shared = Maps::new(
        plan,
        observer,
        pending,
        (recorded, need_cycle),
        S::encode_block,
    );
    shared.seed(prepared);
    let (mut cycles_written, mut prepared) = (0usize, 0usize);
    let started = Instant::now();
    let work = |job: Job, emit: &dyn Fn(Emit<Msg, ScanError>), more: &dyn Fn(Vec<Job>)| {
        shared.run(job, emit, more)
    };
    let jobs = maps.iter().map(|&m| Job::Prepare(m)).collect();
    execute_growing(jobs, stop, work, |msg| {
        let t = Instant::now();
        let r = match msg {
            Msg::Prepared => {
                prepared += 1;
                if prepared == maps.len() {
                    report.prepare = started.elapsed();
                }
                Ok(())
            }
            Msg::Cycle(m, c, w) => {
                cycles_written += 1;
                if !w.is_empty() {
                    sink.write_withdrawn(m, &w).map_err(DriveError::Sink)?;
                }
                sink.write_cycle(m, (*c).as_ref()).map_err(DriveError::Sink)
            }
            Msg::Block(r, record, disagrees) => {
                report.blocks += 1;
                report.cells += r.cells.len();
                report.computed.blocks.insert((r.map, r.block));
                if disagrees {
                    report.computed.disagreeing.insert((r.map, r.block));
                }
                match record {
                    Some(bytes) => sink.write_encoded(&r, bytes),
                    None => sink.write_block(&r),
                }
                .map_err(DriveError::Sink)
            }
        };
        report.sink += t.elapsed();
        r
    })?;
    if prepared < maps.len() {
        report.prepare = started.elapsed();
    }
    Ok(cycles_written < cycles_wanted)
}

/// What the jobs of one drive share: each map's recorded withdrawals, whether its cycle is
/// wanted, its pending blocks and, once prepared, its context; and the sink's encoding of a
/// block ([`Sink::encode_block`]).
struct Maps<'a> {
    plan: &'a Plan,
    observer: &'a dyn Observer,
    recorded: Vec<Vec<Withdrawn>>,
    need_cycle: Vec<bool>,
    blocks_of: Vec<Vec<usize>>,
    ctxs: Vec<OnceLock<MapContext>>,
    /// Contexts prepared before the drive (by the pilot), taken by the map's preparation.
    seeded: Vec<Mutex<Option<MapContext>>>,
    encode: fn(&BlockResult) -> Option<Vec<u8>>,
}

/// Maps prepared before a drive, by index ([`drive_prepared`]).
#[derive(Default)]
pub struct Prepared(pub Vec<(usize, MapContext)>);

impl std::fmt::Debug for Prepared {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let maps: Vec<usize> = self.0.iter().map(|(m, _)| *m).collect();
        write!(f, "Prepared(maps {maps:?})")
    }
}

impl<'a> Maps<'a> {
    fn new(
        plan: &'a Plan,
        observer: &'a dyn Observer,
        pending: &Pending,
        (recorded, need_cycle): (Vec<Vec<Withdrawn>>, Vec<bool>),
        encode: fn(&BlockResult) -> Option<Vec<u8>>,
    ) -> Self {
        let mut blocks_of: Vec<Vec<usize>> = vec![Vec::new(); plan.maps.len()];
        for &(m, b) in &pending.blocks {
            blocks_of[m].push(b);
        }
        Maps {
            plan,
            observer,
            recorded,
            need_cycle,
            blocks_of,
            ctxs: (0..plan.maps.len()).map(|_| OnceLock::new()).collect(),
            seeded: (0..plan.maps.len()).map(|_| Mutex::new(None)).collect(),
            encode,
        }
    }

    /// Hands the maps `prepared` before the drive to their preparation jobs, where the sink
    /// recorded no withdrawal for them (a resume prepares those without the groups).
    fn seed(&mut self, prepared: Prepared) {
        for (m, ctx) in prepared.0 {
            if m < self.plan.maps.len() && self.recorded[m].is_empty() {
                self.seeded[m] = Mutex::new(Some(ctx));
            }
        }
    }

    /// Runs one job on a worker: a map's preparation (its cycle to the sink, then its
    /// blocks to the queue) or a block of a prepared map.
    fn run(&self, job: Job, emit: &dyn Fn(Emit<Msg, ScanError>), more: &dyn Fn(Vec<Job>)) {
        match job {
            Job::Prepare(m) => match self.seeded[m]
                .lock()
                .ok()
                .and_then(|mut s| s.take())
                .map_or_else(
                    || MapContext::prepare_without(self.plan, m, &self.recorded[m]),
                    Ok,
                ) {
                Ok(ctx) => {
                    self.observer.map_prepared(m);
                    let cycle = Box::new(ctx.cycle.clone());
                    let withdrawn = ctx.withdrawn.clone();
                    emit(Emit::Done(Msg::Prepared));
                    if self.need_cycle[m] {
                        emit(Emit::Done(Msg::Cycle(m, cycle, withdrawn)));
                    }
                    let _ = self.ctxs[m].set(ctx);
                    more(
                        self.blocks_of[m]
                            .iter()
                            .map(|&b| Job::Block(m, b))
                            .collect(),
                    );
                }
                Err(e) => emit(Emit::Failed(e)),
            },
            Job::Block(m, b) => {
                let Some(ctx) = self.ctxs[m].get() else {
                    return;
                };
                // No stop inside the block: once started it is finished and journalled.
                if let Some(r) = run_block(self.plan, ctx, b, self.observer, None) {
                    self.observer.block_done(m, b);
                    // The sink's record of the block made here, on the worker, not on the
                    // sink's one thread.
                    let record = (self.encode)(&r);
                    let disagrees = r.cells.iter().any(crate::redo::disagrees);
                    emit(Emit::Done(Msg::Block(r, record, disagrees)));
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::Ordering;

    fn tiny() -> Plan {
        Plan::from_toml(
            r#"version = 1
[model]
law = "mcmillan"
nu = [1e-3, 1e-2]
[grid]
x0 = { min = -1.0, max = 2.0, count = 5 }
v0 = { min = -1.0, max = 1.0, count = 5 }
block_rows = 1
[classifier]
t_max = 2000.0
[output]
path = "t.h5"
"#,
            "t.toml",
        )
        .unwrap()
    }

    /// Records, on the worker that finished each block, how many threads its pool has and
    /// which of them it is: the premise of the thread-independence test.
    #[derive(Default)]
    struct Workers(std::sync::Mutex<Vec<(usize, Option<usize>)>>);
    impl crate::Observer for Workers {
        fn block_done(&self, _map: usize, _block: usize) {
            let seen = (rayon::current_num_threads(), rayon::current_thread_index());
            self.0.lock().unwrap().push(seen);
        }
    }

    /// One, two, three and sixteen threads for real: the executor runs its jobs with the installed
    /// pool's count (`executor::tests::jobs_run_with_the_threads_of_the_installed_pool`), and
    /// each run checks that its blocks were computed on a pool of that size. With a result
    /// made to depend on the worker's index (`+ rayon::current_thread_index()` on each
    /// cell's time), the two- and three-thread runs differ from the one-thread run and the
    /// test fails.
    #[test]
    fn results_do_not_depend_on_threads_and_shards_partition_the_work() {
        let plan = tiny();
        let run = |threads: usize, shard: Option<Shard>| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut sink = MemorySink::default();
            let workers = Workers::default();
            let r = pool
                .install(|| drive(&plan, shard, &mut sink, &workers, &AtomicBool::new(false)))
                .unwrap();
            assert!(!r.interrupted);
            let seen = workers.0.into_inner().unwrap();
            assert_eq!(seen.len(), sink.blocks.len());
            assert!(
                seen.iter()
                    .all(|&(n, i)| n == threads && i.is_some_and(|i| i < threads)),
                "{threads} threads asked, blocks computed on {seen:?}"
            );
            sink
        };
        // Bit-identical, NaN included: compare the printed records.
        let same = |a: &BlockResult, b: &BlockResult| format!("{a:?}") == format!("{b:?}");
        let one = run(1, None);
        assert_eq!(one.blocks.len(), plan.total_blocks());
        for threads in [2, 3, 16] {
            let many = run(threads, None);
            assert_eq!(one.blocks.len(), many.blocks.len());
            for (k, v) in &many.blocks {
                assert!(same(&one.blocks[k], v), "{threads} threads, block {k:?}");
            }
        }
        let (a, b) = (
            run(2, Some(Shard { k: 1, n: 2 })),
            run(1, Some(Shard { k: 2, n: 2 })),
        );
        assert_eq!(a.blocks.len() + b.blocks.len(), plan.total_blocks());
        for (k, v) in a.blocks.iter().chain(&b.blocks) {
            assert!(same(&one.blocks[k], v), "{k:?}");
        }
        // A resumed drive computes only what is missing.
        let mut part = one.clone();
        part.blocks.remove(&(1, 2));
        let r = drive(
            &plan,
            None,
            &mut part,
            &crate::NoObserver,
            &AtomicBool::new(false),
        )
        .unwrap();
        assert_eq!(r.blocks, 1);
        assert!(same(&part.blocks[&(1, 2)], &one.blocks[&(1, 2)]));
    }

    /// A sink that refuses a block of a map whose cycle (and withdrawn rules) it has not
    /// been given: what a resume relies on (the journal's cycle record before the map's
    /// blocks).
    #[derive(Default)]
    struct InOrder(MemorySink);
    impl Sink for InOrder {
        type Error = String;
        fn is_done(&self, map: usize, block: usize) -> bool {
            self.0.is_done(map, block)
        }
        fn has_cycle(&self, map: usize) -> bool {
            self.0.has_cycle(map)
        }
        fn write_cycle(&mut self, map: usize, c: Option<&CycleOutcome>) -> Result<(), String> {
            self.0.cycles.insert(map, c.cloned());
            Ok(())
        }
        fn write_block(&mut self, b: &BlockResult) -> Result<(), String> {
            if !self.0.cycles.contains_key(&b.map) {
                return Err(format!(
                    "block {} of map {} before its cycle",
                    b.block, b.map
                ));
            }
            self.0.blocks.insert((b.map, b.block), b.clone());
            Ok(())
        }
    }

    /// Each map's blocks are added to the queue when the map is prepared (no
    /// barrier between one map's preparation and another's blocks), after its cycle went to
    /// the sink: on 1, 2, 3 and 16 threads every block reaches the sink after its map's
    /// cycle, and every block is there.
    #[test]
    fn a_maps_cycle_reaches_the_sink_before_its_blocks() {
        let plan = tiny();
        assert!(plan.maps.len() > 1);
        for threads in [1, 2, 3, 16] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut sink = InOrder::default();
            let stop = AtomicBool::new(false);
            let r = pool
                .install(|| drive(&plan, None, &mut sink, &crate::NoObserver, &stop))
                .unwrap_or_else(|e| panic!("{threads} threads: {e}"));
            assert!(!r.interrupted);
            assert_eq!(sink.0.blocks.len(), plan.total_blocks());
            assert_eq!(sink.0.cycles.len(), plan.maps.len());
        }
    }

    #[test]
    fn a_raised_stop_computes_nothing_and_says_interrupted() {
        let plan = tiny();
        let mut sink = MemorySink::default();
        let r = drive(
            &plan,
            None,
            &mut sink,
            &crate::NoObserver,
            &AtomicBool::new(true),
        )
        .unwrap();
        assert!(r.interrupted);
        assert!(sink.blocks.is_empty());
    }

    /// Raises the stop when the first chunk of cells of any block is done: a signal in
    /// mid-block.
    struct StopInBlock<'a>(&'a AtomicBool);
    impl crate::Observer for StopInBlock<'_> {
        fn cells_done(&self, _map: usize, _n: u64) {
            self.0.store(true, Ordering::SeqCst);
        }
    }

    #[test]
    fn a_stop_in_mid_block_keeps_the_blocks_in_flight() {
        let plan = tiny();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let stop = AtomicBool::new(false);
        let mut sink = MemorySink::default();
        let r = pool
            .install(|| drive(&plan, None, &mut sink, &StopInBlock(&stop), &stop))
            .unwrap();
        assert!(r.interrupted);
        // The blocks running when the stop came are finished and in the sink, whole (the
        // old driver threw them away: 0 blocks). More than one can be in flight even on one
        // thread: while it waits inside a block's parallel cells, rayon lets it start
        // another block.
        let n = sink.blocks.len();
        assert!(
            n >= 1 && n < plan.total_blocks(),
            "{:?}",
            sink.blocks.keys()
        );
        for (&(m, b), block) in &sink.blocks {
            assert_eq!(
                block.cells.len(),
                plan.map.grid.block_rows(b).len() * 5,
                "map {m}"
            );
        }
    }

    #[test]
    fn shard_parsing() {
        assert_eq!("2/4".parse::<Shard>().unwrap(), Shard { k: 2, n: 4 });
        for bad in ["0/3", "4/3", "x", "1/0", ""] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
    }
}
