//! `squeal scan SPEC.toml`: the basin map(s) of a spec into an HDF5 file and a PNG.
//!
//! Wiring only: the driver is [`squeal_scan::drive`], the sink the store's [`ScanWriter`];
//! here are the flags, the progress bars, the signals and the report.
//!
//! Like make, a rerun of a finished scan from the same (parsed) spec does nothing but
//! draw a missing picture and print the summary; a different spec is refused.
//!
//! Exit codes: 0 done (or already up to date), 2 error, 130 interrupted by SIGINT or
//! SIGTERM (the finished blocks are kept; `--resume` finishes the scan).

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use anyhow::{Context, bail};
use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget};
use squeal_scan::{Observer, Pending, Plan, drive};
use squeal_store::ScanWriter;

use super::common;
use super::{pictures, progress};

/// Flags of `squeal scan`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The scan spec (TOML; see scans/).
    pub spec: PathBuf,
    #[command(flatten)]
    pub run: super::common::RunArgs,
    /// Print the summary as one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Start a scan estimated to take more than 30 days.
    #[arg(long)]
    pub allow_long: bool,
}

struct Bars {
    overall: ProgressBar,
    maps: Vec<ProgressBar>,
    /// The cells done, each weighed by its map's cost per cell (the time left).
    meter: Arc<progress::WorkMeter>,
    plain: Option<progress::PlainLines>,
}

impl Bars {
    /// The terminal bars (the whole scan, and each map of a sweep) and the plain lines off a
    /// terminal for the `pending` cells, the time left weighed by the pilot's cost per cell.
    fn new(
        plan: &Plan,
        pending: &Pending,
        pilot: Option<&squeal_scan::estimate::Estimate>,
        quiet: bool,
    ) -> Bars {
        let multi = MultiProgress::with_draw_target(if progress::show_progress(quiet) {
            ProgressDrawTarget::stderr()
        } else {
            ProgressDrawTarget::hidden()
        });
        let style = progress::bar_style(
            "{prefix:>8} [{bar:40}] {pos}/{len} cells  {avg_rate}  ETA {avg_eta}",
            "cell",
        );
        let counts: Vec<u64> = (0..plan.maps.len())
            .map(|m| pending.cells_of(plan, m) as u64)
            .collect();
        let meter = Arc::new(match pilot {
            // The time left weighs each map's cells by the pilot's cost per cell there.
            Some(e) => progress::WorkMeter::weighted(
                (0..plan.maps.len()).map(|m| e.cell_cost(m)).collect(),
                &counts,
            ),
            None => progress::WorkMeter::uniform(pending.cells as u64),
        });
        let overall = multi.add(
            ProgressBar::new(pending.cells as u64)
                .with_style(progress::metered_bar_style(
                    "{prefix:>8} [{bar:40}] {pos}/{len} cells  {avg_rate}  ETA {avg_eta}",
                    "cell",
                    meter.clone(),
                ))
                .with_prefix("all"),
        );
        let maps = if plan.maps.len() > 1 {
            (0..plan.maps.len())
                .map(|m| {
                    let label = plan
                        .sweep
                        .as_ref()
                        .map_or(String::new(), |s| format!("{}={:.3e}", s.name, s.values[m]));
                    let n = pending.cells_of(plan, m) as u64;
                    if n == 0 {
                        ProgressBar::hidden()
                    } else {
                        multi.add(
                            ProgressBar::new(n)
                                .with_style(style.clone())
                                .with_prefix(label),
                        )
                    }
                })
                .collect()
        } else {
            Vec::new()
        };
        let plain = progress::PlainLines::with_meter("cells", "cell", meter.clone(), quiet);
        Bars {
            overall,
            maps,
            meter,
            plain,
        }
    }
}

impl Observer for Bars {
    fn cell_done(&self, map: usize) {
        self.meter.add(map);
        self.overall.inc(1);
        if let Some(p) = &self.plain {
            p.report();
        }
        if let Some(m) = self.maps.get(map) {
            m.inc(1);
        }
    }
}

/// The pictures a finished scan file has: the map (or sheet) and, for sweeps, the cycle chart;
/// none for random samples (a list of points, not a map).
fn pictures(out: &Path, maps: usize, sample: bool) -> Vec<PathBuf> {
    if sample {
        return Vec::new();
    }
    let png = common::sibling(out, "", "png");
    let mut v = vec![png.clone()];
    if maps > 1 {
        v.push(common::sibling(&png, "-cycle", "png"));
    }
    v
}

/// Runs the scan.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let plan = Plan::from_file(&args.spec)?;
    let (out, shard) = args.run.setup(&plan.output)?;
    let sample = plan.grid.is_sample();
    let pics = pictures(&out, plan.maps.len(), sample);

    // Like make (the same rule as the atlas's): a finished output of the same parsed spec
    // (and shard) is up to date; a picture missing is drawn again.
    let shown = if shard.is_none() {
        pics.clone()
    } else {
        Vec::new()
    };
    let state = squeal_store::output_state(&out, &plan, shard)?;
    if common::up_to_date(&out, state, &args.run, &shown, || {
        pictures::render_file(&out, &pics[0], true)
    })? {
        let info = squeal_store::read_info(&out)?;
        // Nothing computed: the file holds the checks, no per-reason tally.
        let tallies = Tallies {
            checks: &info.checks,
            reasons: &[],
            transient: &[],
        };
        report(&args, &plan, &info, tallies, &shown, 0, 0.0)?;
        return Ok(ExitCode::SUCCESS);
    }
    if shard.is_none() && !args.run.resume {
        for p in &pics {
            common::check_new(p, args.run.force, "picture of the scan")?;
        }
    }
    if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("creating the output folder {}", dir.display()))?;
    }
    squeal_store::OutputLock::check_free(&out)?;
    // The work, estimated before anything is created or computed.
    let threads = rayon::current_num_threads();
    let owned = Pending::of(&plan, shard, &squeal_scan::MemorySink::default());
    let pilot = checked_estimate(&args, &plan, &owned, threads)?;
    let prov = common::provenance();
    let mut writer = if args.run.resume {
        ScanWriter::resume(&out, &plan, shard, &prov)?
    } else {
        ScanWriter::create(&out, &plan, shard, &prov, args.run.force)?
    };
    let plan = writer.plan().clone();

    let stop = Arc::new(AtomicBool::new(false));
    common::install_signals(&stop, "blocks")?;

    let pending = Pending::of(&plan, shard, &writer);
    if !args.run.quiet {
        let secs = seconds_for(&plan, pilot.as_ref(), &pending, threads);
        eprintln!(
            "squeal: {} cells to compute ({} map(s) of {}{}) on {threads} thread(s): roughly {} ({secs:.1} s){}",
            pending.cells,
            plan.maps.len(),
            layout(&plan),
            shard.map(|s| format!(", shard {s}")).unwrap_or_default(),
            common::duration(secs),
            pilot.as_ref().map_or(String::new(), |e| format!(
                ", from a pilot of {} cells over {} map(s) in {:.1} s",
                e.cells,
                e.maps(),
                e.pilot_seconds
            ))
        );
    }

    let bars = Bars::new(&plan, &pending, pilot.as_ref(), args.run.quiet);

    let started = Instant::now();
    let done = drive(&plan, shard, &mut writer, &bars, &stop).map_err(|e| match e {
        squeal_scan::DriveError::Scan(e) => anyhow::Error::new(e),
        squeal_scan::DriveError::Sink(e) => anyhow::Error::new(e),
    })?;
    for b in &bars.maps {
        b.finish_and_clear();
    }
    bars.overall.finish_and_clear();
    let secs = started.elapsed().as_secs_f64();
    if done.interrupted {
        eprintln!(
            "squeal: interrupted; {} of {} blocks are stored. Finish with: {}",
            writer.done_blocks(),
            writer.owned_blocks(),
            args.run.resume_command("scan", &args.spec, &out)
        );
        return Ok(ExitCode::from(common::EXIT_INTERRUPTED));
    }
    // The landscape of each map (laws with true stick) is computed here, before the writer.
    let landscapes = squeal_scan::landscape::of_plan(&plan)?;
    let finished = writer.finish_with(&landscapes)?;
    let checks: Vec<Vec<i64>> = finished.iter().map(|c| c.values().to_vec()).collect();
    let reasons: Vec<_> = finished.iter().map(|c| c.reasons).collect();
    let transient: Vec<_> = finished.iter().map(|c| c.transient).collect();
    let written = if shard.is_none() && !sample {
        pictures::render_file(&out, &pics[0], true)?
    } else {
        Vec::new()
    };
    let info = squeal_store::read_info(&out)?;
    let tallies = Tallies {
        checks: &checks,
        reasons: &reasons,
        transient: &transient,
    };
    report(&args, &plan, &info, tallies, &written, done.cells, secs)?;
    Ok(ExitCode::SUCCESS)
}

/// Seconds for the `p` cells on `threads` threads: from the pilot, or at the documented rate
/// without one (`--quiet`).
fn seconds_for(
    plan: &Plan,
    pilot: Option<&squeal_scan::estimate::Estimate>,
    p: &Pending,
    threads: usize,
) -> f64 {
    match pilot {
        Some(e) => e.seconds(plan.maps.len(), |m| p.cells_of(plan, m), threads),
        None => plan.estimate_seconds(p.cells, threads),
    }
}

/// The pilot (none with `--quiet`), after refusing work estimated over
/// [`common::LONG_RUN`] without `--allow-long`: first at the documented rate (before the
/// pilot runs), then from the pilot, which measures the time per cell with this plan's law,
/// landscape and early stopping ([`squeal_scan::estimate`]).
fn checked_estimate(
    args: &Args,
    plan: &Plan,
    owned: &Pending,
    threads: usize,
) -> anyhow::Result<Option<squeal_scan::estimate::Estimate>> {
    let rough = plan.estimate_seconds(owned.cells, threads);
    if rough > common::LONG_RUN && !args.allow_long {
        bail!(
            "{} cells would take roughly {} on {threads} thread(s) at the documented rate: shrink the grid or the sweep, split it with --shard, or pass --allow-long",
            owned.cells,
            common::duration(rough)
        );
    }
    let pilot = match args.run.quiet {
        true => None,
        false => Some(squeal_scan::estimate::pilot(plan)?),
    };
    let estimate = seconds_for(plan, pilot.as_ref(), owned, threads);
    if estimate > common::LONG_RUN && !args.allow_long {
        bail!(
            "{} cells would take roughly {} on {threads} thread(s): shrink the grid or the sweep, split it with --shard, or pass --allow-long",
            owned.cells,
            common::duration(estimate)
        );
    }
    Ok(pilot)
}

/// "256 x 128 cells" or "5000 random samples in [-2, 2] x [0, 2] (seed 1)".
fn layout(plan: &Plan) -> String {
    let g = &plan.grid;
    match &g.sample {
        Some(s) => format!(
            "{} random samples in x0 [{}, {}] x v0 [{}, {}] (seed {})",
            s.n, g.x0.min, g.x0.max, g.v0.min, g.v0.max, s.seed
        ),
        None => format!("{} x {} cells", g.x0.count, g.v0.count),
    }
}

/// The landscape of a map in words: the verdict, its note and its evidence.
pub fn landscape_words(l: &squeal_store::LandscapeInfo) -> Vec<String> {
    let ev: Vec<String> = l
        .evidence
        .iter()
        .map(|(n, v)| format!("{n} = {v:.6}"))
        .collect();
    vec![
        format!("landscape: {} ({})", l.landscape.name(), l.landscape.note()),
        format!("  evidence: {}", ev.join(", ")),
    ]
}

/// The landscape of a map as JSON (`null` where none is stored).
pub fn landscape_json(l: Option<&squeal_store::LandscapeInfo>) -> serde_json::Value {
    l.map_or(serde_json::Value::Null, |l| {
        let mut o = serde_json::Map::new();
        o.insert("landscape".into(), l.landscape.name().into());
        o.insert("note".into(), l.landscape.note().into());
        for (n, v) in &l.evidence {
            // NaN (no stick-slip cycle) is null in JSON.
            o.insert((*n).into(), serde_json::json!(v.is_finite().then_some(*v)));
        }
        o.into()
    })
}

/// The line for a map whose return map jumps past the cycle from `r` (the scanner's
/// [`squeal_scan::scanner::Outside::Escapes`]).
pub fn escape_words(r: f64) -> String {
    format!(
        "the return map jumps past the cycle (the start r = {r:.4} on the section returns inside): starts outside may end in steady slip, so none is labelled stick-slip for lying outside, and none by its band unless the band above the cycle is trapped (its returns never fall inside)"
    )
}

/// One line per check that found something, in words (`sample`: random initial conditions,
/// where a cell, and so "beyond a pixel", does not exist).
pub fn check_words(values: &[i64], sample: bool) -> Vec<String> {
    let v = |name: &str| {
        squeal_scan::checks::CHECK_FIELDS
            .iter()
            .position(|(n, _)| *n == name)
            .and_then(|i| values.get(i).copied())
            .unwrap_or(-1)
    };
    let mut out = Vec::new();
    if v("wrong_side_cells") >= 0 && sample {
        out.push(format!(
            "wrong side of cycle: {} samples",
            v("wrong_side_cells")
        ));
    } else if v("wrong_side_cells") >= 0 {
        out.push(format!(
            "wrong side of cycle: {} ({} beyond a pixel)",
            v("wrong_side_cells"),
            v("wrong_side_beyond_pixel")
        ));
    }
    if v("audit_cells") > 0 {
        out.push(format!(
            "audit (run to settlement) of {} cells: {} agree, {} disagree, {} undecided",
            v("audit_cells"),
            v("audit_agrees"),
            v("audit_disagrees"),
            v("audit_undecided")
        ));
    }
    let (steady, stick) = (v("settled_steady_slip"), v("settled_stick_slip"));
    if steady > 0 || stick > 0 {
        // Why: no certified shortcut reached these runs (crates/core/MODEL.md section 9).
        out.push(format!(
            "runs to settlement: {steady} steady slip within fp_radius (no certified region, \
             or the run never entered it), {stick} stick-slip by a settled band or a second \
             stick (no located cycle or known orbit from breakaway decided them)"
        ));
    }
    if v("origin_disagrees") == 1 {
        out.push(
            "DISAGREEMENT: the label at (0, 0) contradicts whether the cycle encloses (0, 0)"
                .into(),
        );
    }
    if v("landscape_contradictions") >= 0 {
        out.push(format!(
            "against the landscape: {} decided cells labelled otherwise",
            v("landscape_contradictions")
        ));
    }
    if v("landscape_contradictions") > 0 {
        out.push(format!(
            "DISAGREEMENT: {} decided cells are labelled against the landscape",
            v("landscape_contradictions")
        ));
    }
    if v("audit_disagrees") > 0 {
        out.push(
            "DISAGREEMENT: the early-stopping rule and runs to settlement label some cells differently"
                .into(),
        );
    }
    out
}

/// What the writer counted per map: the stored checks and the cells per reason.
struct Tallies<'a> {
    checks: &'a [Vec<i64>],
    reasons: &'a [[u64; squeal_core::Reason::ALL.len()]],
    /// Steady-slip cells with `t_squeal > 0`, per map.
    transient: &'a [u64],
}

/// Each reason's share of a map's cells, largest first ("start_in_region 61.2%, ...").
fn reason_words(counts: &[u64]) -> String {
    let total = counts.iter().sum::<u64>().max(1) as f64;
    let mut named: Vec<_> = squeal_core::Reason::ALL
        .iter()
        .zip(counts)
        .filter(|(_, n)| **n > 0)
        .collect();
    named.sort_by(|a, b| b.1.cmp(a.1));
    let parts: Vec<_> = named
        .iter()
        .map(|(r, n)| format!("{} {:.1}%", r.name(), 100.0 * **n as f64 / total))
        .collect();
    format!("reasons: {}", parts.join(", "))
}

/// Map `i` of a finished scan as one JSON object: its counts, checks, reasons, transient
/// squeal, cycle, landscape and basin stability.
fn map_json(
    info: &squeal_store::FileInfo,
    tallies: &Tallies,
    i: usize,
) -> anyhow::Result<serde_json::Value> {
    let names = ["undecided", "steady_slip", "stick_slip", "not_computed"];
    let (c, checks) = (&info.counts[i], tallies.checks);
    let mut o = serde_json::Map::new();
    if let Some((name, vals)) = &info.sweep {
        o.insert(name.clone(), vals[i].into());
    }
    for (k, n) in names.iter().zip(c) {
        o.insert((*k).into(), (*n).into());
    }
    let vals = checks.get(i).cloned().unwrap_or_default();
    let ws = (vals.first().copied().unwrap_or(-1) >= 0)
        .then(|| serde_json::json!({"cells": vals[0], "beyond_pixel": vals[1]}));
    o.insert("wrong_side".into(), serde_json::to_value(ws)?);
    let mut ck = serde_json::Map::new();
    for ((name, _), v) in squeal_scan::checks::CHECK_FIELDS.iter().zip(&vals) {
        ck.insert((*name).into(), (*v).into());
    }
    o.insert("checks".into(), ck.into());
    if let Some(counts) = tallies.reasons.get(i) {
        let by_name: serde_json::Map<_, _> = squeal_core::Reason::ALL
            .iter()
            .zip(counts)
            .map(|(r, n)| (r.name().to_string(), (*n).into()))
            .collect();
        o.insert("reasons".into(), by_name.into());
    }
    if let Some(n) = tallies.transient.get(i) {
        o.insert("transient_squeal_cells".into(), (*n).into());
    }
    if let Some(Some(why)) = info.no_cycle.get(i) {
        o.insert("no_cycle".into(), why.clone().into());
    }
    if let Some(Some(r)) = info.escape.get(i) {
        o.insert("escape".into(), (*r).into());
    }
    if !info.landscapes.is_empty() {
        o.insert(
            "landscape".into(),
            landscape_json(info.landscapes.get(i).and_then(Option::as_ref)),
        );
    }
    if let Some(b) = info.basin.get(i) {
        o.insert("basin_stability".into(), common::basin_json(b));
    }
    Ok(serde_json::Value::Object(o))
}

/// Map `i` of a finished scan in words.
fn print_map(plan: &Plan, info: &squeal_store::FileInfo, tallies: &Tallies, i: usize) {
    let (c, checks) = (&info.counts[i], tallies.checks);
    let label = info
        .sweep
        .as_ref()
        .map_or(String::new(), |(n, v)| format!("{n} = {:<10.4e} ", v[i]));
    let mut line = format!(
        "  {label}steady_slip {:>7}  stick_slip {:>7}  undecided {:>5}",
        c[1], c[2], c[0]
    );
    if c[3] > 0 {
        line += &format!("  not_computed {}", c[3]);
    }
    println!("{line}");
    if let Some(b) = info.basin.get(i) {
        println!("    {}", common::basin_words(b));
    }
    if let Some(Some(why)) = info.no_cycle.get(i) {
        println!("    no unstable cycle: {why}");
    }
    if let Some(Some(r)) = info.escape.get(i) {
        println!("    {}", escape_words(*r));
    }
    if let Some(Some(l)) = info.landscapes.get(i) {
        for w in landscape_words(l) {
            println!("    {w}");
        }
    }
    let sample = plan.grid.is_sample();
    for w in checks
        .get(i)
        .map(|c| check_words(c, sample))
        .unwrap_or_default()
    {
        println!("    {w}");
    }
    if let Some(counts) = tallies.reasons.get(i) {
        println!("    {}", reason_words(counts));
    }
    if let Some(n) = tallies.transient.get(i).filter(|n| **n > 0) {
        println!(
            "    transient squeal: {n} steady-slip cells stuck before they settled (t_squeal > 0)"
        );
    }
}

fn report(
    args: &Args,
    plan: &Plan,
    info: &squeal_store::FileInfo,
    tallies: Tallies,
    pictures: &[PathBuf],
    computed: usize,
    secs: f64,
) -> anyhow::Result<()> {
    let rate = computed as f64 / secs.max(1e-9);
    if args.json {
        let maps: Vec<_> = (0..info.counts.len())
            .map(|i| map_json(info, &tallies, i))
            .collect::<anyhow::Result<_>>()?;
        let v = serde_json::json!({
            "output": info.path,
            "pictures": pictures,
            "maps": maps,
            "cells_computed": computed,
            "seconds": secs,
            "cells_per_second": rate,
        });
        println!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(());
    }
    println!(
        "{}: {} map(s) of {} -> {}",
        plan.name,
        plan.maps.len(),
        layout(plan),
        info.path.display()
    );
    for i in 0..info.counts.len() {
        print_map(plan, info, &tallies, i);
    }
    if computed > 0 {
        println!("  {computed} cells in {secs:.2} s: {rate:.0} cells/s");
    }
    for p in pictures {
        println!("  picture: {}", p.display());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::check_words;

    /// Issue 21: "wrong side of cycle: N (M beyond a pixel)" was printed for random samples,
    /// where there is no pixel. The values follow `checks::CHECK_FIELDS`: 3 wrong-side cells,
    /// 1 of them beyond a pixel, every other check -1 (not applicable).
    #[test]
    fn random_samples_have_no_pixel() {
        let fields = squeal_scan::checks::CHECK_FIELDS;
        let values: Vec<i64> = fields
            .iter()
            .map(|(name, _)| match *name {
                "wrong_side_cells" => 3,
                "wrong_side_beyond_pixel" => 1,
                _ => -1,
            })
            .collect();
        let grid = check_words(&values, false).join("\n");
        assert!(
            grid.contains("wrong side of cycle: 3 (1 beyond a pixel)"),
            "{grid}"
        );
        let sample = check_words(&values, true).join("\n");
        assert!(
            sample.contains("wrong side of cycle: 3 samples"),
            "{sample}"
        );
        assert!(!sample.contains("pixel"), "{sample}");
    }
}
