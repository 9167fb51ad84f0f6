//! How long a scan will take, measured rather than assumed: a pilot prepares a few of the
//! plan's maps (the cycle search and, for laws with true stick, the landscape, as the scan
//! does) and classifies a spread sample of their cells with the scan's own classifier (early
//! stopping, the start rule, the audit). Its time per cell therefore follows the law, each
//! map's landscape and whether early stopping holds there (near the fold of cycles it does
//! not, and cells run to settlement): a fixed "documented rate" was off 50-fold on
//! `scans/nu-sweep.toml` and on `scans/bstab-friction.toml`.
//!
//! `scripts/bench/bench-estimate.sh` checks the estimate against the measured time of shipped
//! specs (docs/history/benchmarks.md, "Scan time estimates").

use std::time::{Duration, Instant};

use crate::atlas::AtlasPlan;
use crate::atlas::driver::{Unit, UnitResult};
use crate::driver::Pending;
use crate::error::ScanError;
use crate::scanner::MapContext;
use crate::spec::Plan;

/// CPU time of the calling thread, in seconds, where the system tells it (Linux:
/// `/proc/thread-self/schedstat`, nanoseconds on the CPU); `None` elsewhere.
pub fn thread_cpu_seconds() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: f64 = text.split_whitespace().next()?.parse().ok()?;
    (ns > 0.0).then_some(ns * 1e-9)
}

/// CPU time of the whole process (every thread), in seconds, where the system tells it
/// (Linux: fields 14 and 15 of `/proc/self/stat`, user and system time in clock ticks of
/// 1/100 s); `None` elsewhere.
fn process_cpu_seconds() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/self/stat").ok()?;
    // The command name (field 2) is in parentheses and may hold spaces: count after it.
    let rest = &text[text.rfind(')')? + 1..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks: f64 = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

/// The share of a core the calling thread got since it was started, over the spans it
/// worked itself: its CPU time over the wall time, where the system tells the CPU time
/// (Linux: `/proc/thread-self/schedstat`, nanoseconds, updated at scheduler ticks, so read
/// only over spans of 0.2 s or more); 1 otherwise. The pilot times its work on the wall
/// clock and scales it by this share, so a busy machine does not inflate the estimate: the
/// estimate is the time on free cores (on a shared machine the wall clock is longer, by a
/// factor no estimate can know). Spans where the thread waits for the pool (a map's
/// preparation runs its census there) are left out ([`CoreShare::excluding`]): waiting is
/// not load, and counted it made an idle machine look busy.
struct CoreShare {
    wall: Instant,
    cpu: Option<f64>,
    /// Wall and CPU seconds of the spans left out.
    excluded: std::cell::Cell<(f64, f64)>,
}

impl CoreShare {
    fn cpu_now() -> Option<f64> {
        thread_cpu_seconds()
    }

    fn start() -> Self {
        CoreShare {
            wall: Instant::now(),
            cpu: Self::cpu_now(),
            excluded: std::cell::Cell::new((0.0, 0.0)),
        }
    }

    /// Runs `work`, leaving its span out of the share.
    fn excluding<T>(&self, work: impl FnOnce() -> T) -> T {
        let (t, cpu0) = (Instant::now(), Self::cpu_now());
        let out = work();
        let cpu = match (cpu0, Self::cpu_now()) {
            (Some(a), Some(b)) => b - a,
            _ => 0.0,
        };
        let (w, c) = self.excluded.get();
        self.excluded.set((w + t.elapsed().as_secs_f64(), c + cpu));
        out
    }

    /// The share so far, in [0.05, 1].
    fn share(&self) -> f64 {
        let (ex_wall, ex_cpu) = self.excluded.get();
        let wall = self.wall.elapsed().as_secs_f64() - ex_wall;
        match (self.cpu, Self::cpu_now()) {
            (Some(a), Some(b)) if wall >= 0.2 => ((b - a - ex_cpu) / wall).clamp(0.05, 1.0),
            _ => 1.0,
        }
    }
}

/// Below this share of a core the pilot's thread got, the machine counts as busy: the
/// estimate (the time on free cores) is then also given at the load the pilot saw
/// ([`at_load`]).
pub const BUSY_SHARE: f64 = 0.8;

/// Longest run started without `allow_long` (the command line's `--allow-long`, Python's
/// `allow_long=True`), scans and atlases alike: 30 days.
pub const LONG_RUN: f64 = 30.0 * 86_400.0;

/// Whether work estimated at `seconds` is refused before anything runs: over [`LONG_RUN`]
/// without `allow_long`. The one rule of every door.
pub fn refused_as_long(seconds: f64, allow_long: bool) -> bool {
    seconds > LONG_RUN && !allow_long
}

/// The wall seconds `secs` (on free cores) take at the load where the pilot's thread got
/// `share` of a core, when that share says the machine is busy ([`BUSY_SHARE`]); `None` on
/// a machine that is not (or where the share is not known: 1). A scan estimated at 66 s took
/// 323 s on a machine at load 8: each thread gets its share of a core there, so
/// the work takes about `secs / share`.
pub fn at_load(secs: f64, share: f64) -> Option<f64> {
    (share.is_finite() && share > 0.0 && share < BUSY_SHARE).then(|| secs / share)
}

/// At most this many maps are prepared by the pilot (evenly spread over a sweep).
pub const PILOT_MAPS: usize = 8;
/// The pilot classifies this many cells, shared among the first maps it prepares ...
pub const PILOT_CELLS: usize = 512;
/// ... or stops classifying a map's cells after its share of this time (at least one cell
/// per map); maps added where the cost jumps get the same share, up to twice this in all.
pub const PILOT_BUDGET: Duration = Duration::from_millis(1500);
/// Audited cells timed per prepared map (the first ones of the map's own audited sample).
pub const AUDIT_SAMPLES: usize = 2;

/// What the pilot measured on one prepared map (seconds on one thread).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapCost {
    /// The map's index in the plan.
    pub map: usize,
    /// Seconds to prepare it (cycle search, landscape, shortcuts).
    pub prepare: f64,
    /// Mean seconds per cell, over the cells the pilot classified in it.
    pub cell: f64,
    /// Cells the pilot classified in it.
    pub cells: usize,
    /// Mean seconds per audited cell (a run to settlement on top of the cell's own run; 0
    /// where the map's audit does not apply).
    pub audit: f64,
}

impl MapCost {
    /// Seconds (one thread) of one cell, its share of `audited` audited cells in a map of
    /// `cells` included.
    pub fn per_cell(&self, audited: usize, cells: usize) -> f64 {
        self.cell + self.audit * audited as f64 / cells.max(1) as f64
    }
}

/// A pilot's measurements and the estimate they give.
#[derive(Clone, Debug, PartialEq)]
pub struct Estimate {
    /// The maps the pilot prepared, for the run to take instead of preparing them again
    /// ([`crate::driver::drive_prepared`]).
    pub prepared: Shelf,
    /// Cells classified by the pilot.
    pub cells: usize,
    /// Seconds the pilot took.
    pub pilot_seconds: f64,
    /// What it measured, per prepared map (in map order; at least one).
    pub per_map: Vec<MapCost>,
    /// Audited cells per map (the same sample in every map: it depends on the cell index).
    pub audited_per_map: usize,
    /// Cells per map.
    pub cells_per_map: usize,
    /// The share of a core the pilot's thread got (its CPU time over its wall time, in
    /// [0.05, 1]; 1 where the system does not tell): below [`BUSY_SHARE`] the machine is
    /// busy ([`at_load`]).
    pub core_share: f64,
}

/// Maps prepared by a pilot, shared until the run takes them ([`Shelf::take`]). Two shelves
/// compare equal when they hold the same maps.
#[derive(Clone, Default)]
pub struct Shelf(std::sync::Arc<std::sync::Mutex<Vec<(usize, MapContext)>>>);

impl Shelf {
    fn put(&self, map: usize, ctx: MapContext) {
        if let Ok(mut v) = self.0.lock() {
            v.push((map, ctx));
        }
    }

    /// The prepared maps, taken off the shelf (empty once taken).
    pub fn take(&self) -> crate::driver::Prepared {
        crate::driver::Prepared(
            self.0
                .lock()
                .map(|mut v| std::mem::take(&mut *v))
                .unwrap_or_default(),
        )
    }

    fn maps(&self) -> Vec<usize> {
        self.0
            .lock()
            .map(|v| v.iter().map(|(m, _)| *m).collect())
            .unwrap_or_default()
    }
}

impl std::fmt::Debug for Shelf {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Shelf(maps {:?})", self.maps())
    }
}

impl PartialEq for Shelf {
    fn eq(&self, o: &Shelf) -> bool {
        self.maps() == o.maps()
    }
}

impl Estimate {
    /// Maps prepared by the pilot.
    pub fn maps(&self) -> usize {
        self.per_map.len()
    }

    /// The measured costs that stand for map `map`: those of the nearest prepared map (a
    /// sweep's cost changes along the sweep: above a fold of cycles a McMillan cell costs
    /// 20-50 times one below it, so one mean over all maps misleads).
    pub fn cost_of(&self, map: usize) -> &MapCost {
        self.per_map
            .iter()
            .min_by_key(|c| c.map.abs_diff(map))
            .expect("the pilot prepares at least one map")
    }

    /// Expected seconds (one thread) of one cell of map `map`, its share of the map's audits
    /// included.
    pub fn cell_cost(&self, map: usize) -> f64 {
        self.cost_of(map)
            .per_cell(self.audited_per_map, self.cells_per_map)
    }

    /// Wall seconds on `threads` threads for the maps `0..maps`, `cells_of(m)` cells of map
    /// `m` to compute (maps with none are not counted): maps are prepared one at a time; cells and their audits run in
    /// parallel (the audited share of a map's pending cells is its share of all its cells).
    pub fn seconds(&self, maps: usize, cells_of: impl Fn(usize) -> usize, threads: usize) -> f64 {
        self.seconds_after(maps, cells_of, threads, &[])
    }

    /// [`Estimate::seconds`] where the maps `ready` need no preparation (the run takes the
    /// ones the pilot prepared: [`Estimate::prepared`]).
    fn seconds_after(
        &self,
        maps: usize,
        cells_of: impl Fn(usize) -> usize,
        threads: usize,
        ready: &[usize],
    ) -> f64 {
        let per_map = self.cells_per_map.max(1) as f64;
        (0..maps)
            .map(|m| {
                let c = self.cost_of(m);
                let n = cells_of(m) as f64;
                if n == 0.0 {
                    return 0.0;
                }
                let audits = self.audited_per_map as f64 * n / per_map;
                let prepare = if ready.contains(&m) { 0.0 } else { c.prepare };
                prepare + (n * c.cell + audits * c.audit) / threads.max(1) as f64
            })
            .sum()
    }

    /// The estimate of a scan that takes the maps its pilot prepared
    /// ([`crate::driver::drive_prepared`]): their preparation is done, not to come.
    pub fn seconds_reusing(
        &self,
        maps: usize,
        cells_of: impl Fn(usize) -> usize,
        threads: usize,
    ) -> f64 {
        self.seconds_after(maps, cells_of, threads, &self.prepared.maps())
    }
}

/// Wall seconds for the `pending` cells of `plan` on `threads` threads: from the `pilot`
/// (the maps it prepared and the run takes cost no second preparation), or at the
/// documented rate without one ([`documented_seconds`]).
pub fn seconds_for(
    plan: &Plan,
    pilot: Option<&Estimate>,
    pending: &Pending,
    threads: usize,
) -> f64 {
    match pilot {
        Some(e) => e.seconds_reusing(plan.maps.len(), |m| pending.cells_of(plan, m), threads),
        None => documented_seconds(plan, pending, threads),
    }
}

/// Seconds of one integration step at the documented rate: up to about 250 ns per step with
/// the robust solver (docs/history/benchmarks.md, "Time per step").
pub const STEP_SECONDS: f64 = 250e-9;

/// Seconds (one thread) of `returns` section returns that each run their whole `t_return`
/// at step `dt`, at [`STEP_SECONDS`]: a return that never comes (a run decaying onto the
/// fixed point, `nu = 2`) runs that long, so a search is bounded by its samples times
/// `t_return`, not by its typical cost.
fn returns_seconds(returns: f64, t_return: f64, dt: f64) -> f64 {
    returns * (t_return / dt).ceil() * STEP_SECONDS
}

/// Halvings of a bisection to the relative width `rtol` (at most the 200 of
/// [`crate::section::ReturnMap::bisect`]).
fn halvings(rtol: f64) -> f64 {
    (1.0 / rtol).log2().ceil().clamp(1.0, 200.0) + 1.0
}

/// Seconds (one thread) of one cycle search with settings `cs` at step `dt`, at most: its
/// log-spaced samples, the bisection of the crossing and the band's samples above it
/// ([`crate::band::NSAMPLES`], `band_factor` times that many returns at the horizon's
/// longer `t_return` for an atlas's lasting band), each return running its whole
/// `t_return`; with `locate` and the half-step check, the search again at `dt / 2` (twice
/// the steps). `[cycle] samples = 100000, t_return = 1e6` is about 29 days per map, which no
/// estimate may leave out.
pub fn search_seconds(
    cs: &crate::section::CycleSettings,
    dt: f64,
    locate: bool,
    band_factor: f64,
) -> f64 {
    let returns =
        cs.samples as f64 + halvings(cs.rtol) + band_factor * crate::band::NSAMPLES as f64;
    let once = returns_seconds(returns, cs.t_return, dt);
    match locate && cs.check_half_dt {
        true => 3.0 * once,
        false => once,
    }
}

/// Seconds (one thread) of preparing one map of `plan`, at most ([`search_seconds`]): the
/// cycle search where the map needs one (as [`MapContext::prepare`] decides), 0 otherwise.
pub fn prepare_seconds(plan: &Plan) -> f64 {
    match crate::scanner::searches_section(plan, plan.law().family()) {
        true => search_seconds(&plan.cycle.search, plan.dt, plan.cycle.locate, 1.0),
        false => 0.0,
    }
}

/// Wall seconds on `threads` threads for the `pending` work of `plan` at the documented
/// rates, before any pilot: each map to prepare, one after another ([`prepare_seconds`]);
/// the cells ([`Plan::estimate_seconds`]); their audited share, each a run to `t_max`.
pub fn documented_seconds(plan: &Plan, pending: &Pending, threads: usize) -> f64 {
    let maps = pending.maps_to_prepare();
    let audits = match plan.map.early_stop {
        crate::spec::EarlyStop::Cycle if plan.map.audit_every > 0 => {
            // About one cell in `audit_every`, and cell 0 of each map.
            let n = pending.cells as f64 / plan.map.audit_every as f64 + maps as f64;
            n * (plan.map.classifier.t_max / plan.dt).ceil() * STEP_SECONDS / threads.max(1) as f64
        }
        _ => 0.0,
    };
    maps as f64 * prepare_seconds(plan) + plan.estimate_seconds(pending.cells, threads) + audits
}

/// The longest a pilot may take, at the documented rates: a plan whose pilot could take
/// longer is estimated at those rates instead (`[cycle] samples = 65537` ran a silent 51 s
/// pilot; a pilot could run a whole 29-day search).
pub const PILOT_MAX_SECONDS: f64 = 30.0;

/// Seconds (one thread) [`pilot`] may take on `plan`, at most, at the documented rates:
/// its time budget, then one more map (prepared, one cell run to `t_max`, its audited
/// samples run to `t_max`), which it starts before looking at the clock.
pub fn pilot_bound(plan: &Plan) -> f64 {
    let cell = (plan.map.classifier.t_max / plan.dt).ceil() * STEP_SECONDS;
    2.0 * PILOT_BUDGET.as_secs_f64() + prepare_seconds(plan) + (1 + AUDIT_SAMPLES) as f64 * cell
}

/// [`pilot`] where [`pilot_bound`] is within [`PILOT_MAX_SECONDS`]; `None` (estimate at the
/// documented rates) otherwise.
pub fn bounded_pilot(plan: &Plan) -> Result<Option<Estimate>, ScanError> {
    match pilot_bound(plan) <= PILOT_MAX_SECONDS {
        true => pilot(plan).map(Some),
        false => Ok(None),
    }
}

/// The maps the pilot prepares: all of them, or [`PILOT_MAPS`] spread over the sweep with
/// both ends.
fn picked_maps(n: usize) -> Vec<usize> {
    if n <= PILOT_MAPS {
        (0..n).collect()
    } else {
        (0..PILOT_MAPS)
            .map(|i| i * (n - 1) / (PILOT_MAPS - 1))
            .collect()
    }
}

/// Cell `idx` of a map (row-major) as `(row, col)`.
fn cell_at(plan: &Plan, idx: usize) -> (usize, usize) {
    (idx / plan.map.grid.x0.count, idx % plan.map.grid.x0.count)
}

/// Runs the pilot on `plan` (single-threaded): the maps of [`picked_maps`], then more
/// maps between neighbours whose cost per cell differs more than twofold (a fold of cycles
/// crossed by the sweep), while the budget lasts.
pub fn pilot(plan: &Plan) -> Result<Estimate, ScanError> {
    let t0 = Instant::now();
    let core = CoreShare::start();
    let per_map = plan.map.grid.cells();
    let audited: Vec<usize> = (0..per_map)
        .filter(|&i| crate::scanner::audited(i as u64, plan.map.audit_every))
        .collect();
    let first = picked_maps(plan.maps.len());
    let shelf = Shelf::default();
    let budget = PILOT_BUDGET / first.len() as u32;
    let cells = (PILOT_CELLS / first.len()).max(1);
    let mut costs = Vec::with_capacity(2 * first.len());
    for m in first {
        // Maps whose preparation is slow (long cycle searches) are sampled fewer.
        if !costs.is_empty() && t0.elapsed() >= 2 * PILOT_BUDGET {
            break;
        }
        costs.push(measure(
            plan,
            m,
            (cells, budget),
            (&audited, &core),
            &shelf,
        )?);
    }
    while costs.len() < 2 * PILOT_MAPS && t0.elapsed() < 2 * PILOT_BUDGET {
        let per_cell = |c: &MapCost| c.per_cell(audited.len(), per_map);
        let jump = costs
            .windows(2)
            .filter(|w| w[1].map - w[0].map > 1)
            .map(|w| {
                let (a, b) = (per_cell(&w[0]), per_cell(&w[1]));
                (a.max(b) / a.min(b).max(1e-12), (w[0].map + w[1].map) / 2)
            })
            .filter(|&(ratio, _)| ratio > 2.0)
            .max_by(|a, b| a.0.total_cmp(&b.0));
        let Some((_, mid)) = jump else { break };
        let at = costs.partition_point(|c| c.map < mid);
        costs.insert(
            at,
            measure(plan, mid, (cells, budget), (&audited, &core), &shelf)?,
        );
    }
    let share = core.share();
    for c in &mut costs {
        // The preparation is timed in CPU seconds already (a busy machine does not inflate
        // them); only where the system gives no CPU time is it the wall clock.
        if process_cpu_seconds().is_none() {
            c.prepare *= share;
        }
        c.cell *= share;
        c.audit *= share;
    }
    // The audit samples each rule group apart ([`crate::scanner::AuditRates`]): up to
    // AUDIT_PER_RULE cells for each of the start rule's groups and as many run-decided cells,
    // beside the plan's own interval. Counted at that bound.
    let groups = crate::census::Rules::ALL.len() + 1;
    let audited_per_map = match plan.map.audit_every {
        0 => 0,
        _ => audited
            .len()
            .max(per_map.min(groups * crate::scanner::AUDIT_PER_RULE)),
    };
    Ok(Estimate {
        prepared: shelf,
        cells: costs.iter().map(|c| c.cells).sum(),
        pilot_seconds: t0.elapsed().as_secs_f64(),
        per_map: costs,
        audited_per_map,
        cells_per_map: per_map,
        core_share: share,
    })
}

/// Prepares map `map` as the scan does and classifies a spread sample of up to `cells` of
/// its cells with the scan's own rule, within `budget` (at least one cell), then times its
/// audit ([`audit_seconds`]). The preparation is left out of `core`'s share.
fn measure(
    plan: &Plan,
    map: usize,
    (cells, budget): (usize, Duration),
    (audited, core): (&[usize], &CoreShare),
    shelf: &Shelf,
) -> Result<MapCost, ScanError> {
    // The preparation runs its census (crate::census) on the whole pool: its cost is the
    // process's CPU time over it (the calling thread mostly waits), taken as seconds of one
    // thread; the wall clock where the system tells no CPU time.
    let t = Instant::now();
    let cpu0 = process_cpu_seconds();
    let ctx = core.excluding(|| MapContext::prepare(plan, map))?;
    let prepare = match (cpu0, process_cpu_seconds()) {
        // Ticks of 1/100 s: a preparation shorter than one may read 0; the wall clock then.
        (Some(a), Some(b)) if b > a => b - a,
        _ => t.elapsed().as_secs_f64(),
    };
    let per_map = plan.map.grid.cells() as u64;
    let t1 = Instant::now();
    let mut done = 0usize;
    for j in 0..per_map.min(cells as u64) {
        // A spread sample: Fibonacci hashing (the top bits of j * 2^64 / phi) over the cells.
        let idx = ((j.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 32) % per_map) as usize;
        let (row, col) = cell_at(plan, idx);
        let (x, v) = plan.map.grid.state(row, col);
        ctx.classify(squeal_core::State { x, v });
        done += 1;
        if t1.elapsed() >= budget {
            break;
        }
    }
    let cost = MapCost {
        map,
        prepare,
        cell: t1.elapsed().as_secs_f64() / done.max(1) as f64,
        cells: done,
        audit: audit_seconds(plan, &ctx, audited),
    };
    shelf.put(map, ctx);
    Ok(cost)
}

/// Mean seconds of one audited cell of `ctx`'s map (its run to settlement; 0 where the
/// map's audit does not apply), timed on the first [`AUDIT_SAMPLES`] cells of the map's own
/// audited sample `audited`. Audited cells are too rare for the spread sample to meet them,
/// and each can cost as much as thousands of early-stopped cells (a start near the unstable
/// cycle runs long before it settles).
fn audit_seconds(plan: &Plan, ctx: &MapContext, audited: &[usize]) -> f64 {
    if !ctx.audits() || audited.is_empty() {
        return 0.0;
    }
    let t = Instant::now();
    let n = audited.len().min(AUDIT_SAMPLES);
    for &idx in &audited[..n] {
        let (row, col) = cell_at(plan, idx);
        let (x, v) = plan.map.grid.state(row, col);
        let ic = squeal_core::State { x, v };
        ctx.settle(ic, &ctx.classify(ic));
    }
    t.elapsed().as_secs_f64() / n as f64
}

/// At most this many atlas points are computed by an atlas's pilot (spread over the points).
pub const ATLAS_PILOT_POINTS: usize = 4;

/// An atlas's pilot: a few of its points computed as the atlas computes them (cold: no
/// neighbour's crossing, so a little slower than a line's warm-started points), and the scan
/// pilot of its basin maps, if it has any.
#[derive(Clone, Debug, PartialEq)]
pub struct AtlasEstimate {
    /// Points computed by the pilot.
    pub points: usize,
    /// Mean seconds per point (one thread).
    pub point_seconds: f64,
    /// Seconds of the one boundary unit measured (one thread; 0 without boundaries).
    pub boundary_seconds: f64,
    /// The boundary units the pilot computed, whole: the run journals these rather than
    /// computing them again (a unit can take minutes: on the 4 x 4 chart of
    /// `scans/atlas-lambda-nu.toml` the pilot, its points stopping after about 1.5 s, took
    /// 26 s of an 87 s run on 2 threads, docs/history/benchmarks.md, "The 64 x 64 atlas against
    /// 48d225a").
    pub units: Vec<UnitResult>,
    /// Seconds the pilot took (points and maps).
    pub pilot_seconds: f64,
    /// The pilot of the basin maps.
    pub maps: Option<Estimate>,
    /// The share of a core the pilot's thread got over its points ([`Estimate::core_share`]).
    pub core_share: f64,
}

impl AtlasEstimate {
    /// Wall seconds for the whole `plan` on `threads` threads (a lower bound: the writing of
    /// very large maps is not counted): its points; its boundary units, each costed as the
    /// one the pilot ran; and its maps.
    pub fn seconds(&self, plan: &AtlasPlan, threads: usize) -> f64 {
        let boundaries = plan.n_boundaries() as f64 * self.boundary_seconds;
        // A line's points run one after another (each warm-starts the next), and so does a
        // boundary unit: neither is shared between threads.
        let line = plan.line_len() as f64 * self.point_seconds;
        let units = ((plan.space.n_points() as f64 * self.point_seconds + boundaries)
            / threads.max(1) as f64)
            .max(line)
            .max(self.boundary_seconds);
        let maps = match (&self.maps, plan.map_plan()) {
            (Some(e), Some(mp)) => e.seconds(mp.maps.len(), |_| mp.map.grid.cells(), threads),
            _ => 0.0,
        };
        units + maps
    }
}

/// Mean CPU seconds (one thread's worth) of up to three boundary units spread over the plan's (the
/// middle, the first and the last), run as the atlas runs them, stopping once
/// [`PILOT_BUDGET`] is spent (at least one); 0 without boundaries. A unit's cost varies
/// with its crisis's coarse scan and checks far more than a point's, so it is measured,
/// not costed in points. The units' results come back too: the same function of the same
/// plan as the run's ([`crate::atlas::driver::run_unit`]), so the run journals them
/// instead of computing them again.
fn boundary_pilot(plan: &AtlasPlan) -> Result<(f64, Vec<UnitResult>), ScanError> {
    let nb = plan.n_boundaries();
    if nb == 0 {
        return Ok((0.0, Vec::new()));
    }
    let (t0, cpu0) = (Instant::now(), process_cpu_seconds());
    let mut picks = Vec::new();
    for j in [nb / 2, 0, nb - 1] {
        if !picks.contains(&j) {
            picks.push(j);
        }
    }
    let mut units = Vec::new();
    for j in picks {
        units.push(crate::atlas::driver::run_unit(plan, Unit::Boundary(j))?);
        if t0.elapsed() >= PILOT_BUDGET {
            break;
        }
    }
    // A unit's runs spread over the pool (the fates of its starts, the crisis's verdicts):
    // its one-thread cost is the process's CPU time over it, not the pilot thread's share
    // of the wall clock (that share read 2 s for the 74 s of the 8 x 8 chart).
    let spent = match (cpu0, process_cpu_seconds()) {
        (Some(a), Some(b)) if b > a => b - a,
        _ => t0.elapsed().as_secs_f64(),
    };
    Ok((spent / units.len() as f64, units))
}

/// Runs an atlas's pilot (single-threaded): up to [`ATLAS_PILOT_POINTS`] spread points,
/// stopping early once [`PILOT_BUDGET`] is spent (at least one point); its boundary units
/// ([`boundary_pilot`]); then the scan pilot of its basin maps.
pub fn atlas_pilot(plan: &AtlasPlan) -> Result<AtlasEstimate, ScanError> {
    let t0 = Instant::now();
    let core = CoreShare::start();
    let n = plan.space.n_points();
    let k = ATLAS_PILOT_POINTS.min(n).max(1);
    let mut points = 0usize;
    for j in 0..k {
        let i = if k == 1 { 0 } else { j * (n - 1) / (k - 1) };
        crate::atlas::driver::compute_at(plan, i, None);
        points += 1;
        if t0.elapsed() >= PILOT_BUDGET {
            break;
        }
    }
    let core_share = core.share();
    let point_seconds = t0.elapsed().as_secs_f64() * core_share / points as f64;
    let (boundary_seconds, units) = boundary_pilot(plan)?;
    let maps = plan.map_plan().map(|mp| pilot(&mp)).transpose()?;
    Ok(AtlasEstimate {
        points,
        point_seconds,
        boundary_seconds,
        units,
        pilot_seconds: t0.elapsed().as_secs_f64(),
        maps,
        core_share,
    })
}

/// Seconds (one thread) of one atlas point of `plan`, at most, at the documented rates: its
/// cycle search with the lasting band's longer horizon (twice the samples at twice
/// `t_return`: four bands' worth), the tangency refinements, and the attractor's
/// `transient + window` revolutions, each return running its whole `t_return`.
fn point_bound(plan: &AtlasPlan) -> f64 {
    let ps = &plan.point;
    let cs = &ps.cycle;
    let revolutions = (ps.tangency_iters + ps.transient + ps.window) as f64;
    search_seconds(cs, plan.dt, true, 4.0) + returns_seconds(revolutions, cs.t_return, plan.dt)
}

/// Seconds (one thread) of one boundary unit of `plan`, at most: a point's search at each
/// step of the coarse scan and of the bisections of the fold and the critical damping, and
/// the transient lifetimes above the fold (each start a run to the lifetimes' `t_max` at
/// each distance of the table).
fn boundary_bound(plan: &AtlasPlan) -> f64 {
    let searches = plan.boundary_coarse as f64 + 2.0 * halvings(plan.boundary_rtol);
    let lifetimes = (plan.lifetime_starts * crate::lifetime::DISTANCE_FACTORS.len()) as f64
        * (crate::lifetime::LifetimeSettings::default().t_max / plan.dt).ceil()
        * STEP_SECONDS;
    searches * point_bound(plan) + lifetimes
}

/// Wall seconds on `threads` threads for the whole atlas `plan` at the documented rates,
/// before any pilot: every kind of its work at most ([`point_bound`], [`boundary_bound`],
/// the basin maps' [`documented_seconds`]), shared among threads as
/// [`AtlasEstimate::seconds`] shares it.
pub fn atlas_documented_seconds(plan: &AtlasPlan, threads: usize) -> f64 {
    let t = threads.max(1) as f64;
    let (point, unit) = (point_bound(plan), boundary_bound(plan));
    let units = ((plan.space.n_points() as f64 * point + plan.n_boundaries() as f64 * unit) / t)
        .max(plan.line_len() as f64 * point)
        .max(if plan.n_boundaries() > 0 { unit } else { 0.0 });
    let maps = plan.map_plan().map_or(0.0, |mp| {
        let all = Pending::of(&mp, None, &crate::MemorySink::default());
        documented_seconds(&mp, &all, threads)
    });
    units + maps
}

/// Seconds (one thread) the longest single computation of [`atlas_pilot`] on `plan` may
/// take, at the documented rates: a point (one cycle search and its attractor; a boundary
/// unit is a series of such searches, each bounded alike), or the maps' [`pilot_bound`].
pub fn atlas_pilot_bound(plan: &AtlasPlan) -> f64 {
    let maps = plan.map_plan().map_or(0.0, |mp| pilot_bound(&mp));
    (PILOT_BUDGET.as_secs_f64() + point_bound(plan)).max(maps)
}

/// Seconds (one thread) [`atlas_pilot`]'s points and maps may take on `plan`, at most, at
/// the documented rates: its points' budget and one more point, then the maps' pilot
/// ([`pilot_bound`]); its boundary units ([`boundary_pilot`]) are not counted (each is a
/// whole unit, bounded only by [`boundary_bound`], far above what one takes).
pub fn atlas_pilot_points_bound(plan: &AtlasPlan) -> f64 {
    let maps = plan.map_plan().map_or(0.0, |mp| pilot_bound(&mp));
    PILOT_BUDGET.as_secs_f64() + point_bound(plan) + maps
}

/// [`atlas_pilot`] where [`atlas_pilot_bound`] is within [`PILOT_MAX_SECONDS`]; `None`
/// (estimate at the documented rates) otherwise.
pub fn bounded_atlas_pilot(plan: &AtlasPlan) -> Result<Option<AtlasEstimate>, ScanError> {
    match atlas_pilot_bound(plan) <= PILOT_MAX_SECONDS {
        true => atlas_pilot(plan).map(Some),
        false => Ok(None),
    }
}

#[cfg(test)]
mod tests;
