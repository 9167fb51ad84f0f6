//! `squeal scan SPEC.toml`: the basin map(s) of a spec into an HDF5 file and a PNG.
//!
//! Wiring only: the driver is [`squeal_scan::drive`], the sink the store's [`ScanWriter`];
//! here are the flags, the signals and the steps of a run; the progress bars are
//! [`super::scan_bars`], the summary [`super::scan_report`].
//!
//! Like make, a rerun of a finished scan from the same (parsed) spec does nothing but
//! draw a missing picture and print the summary; a different spec is refused.
//!
//! Exit codes: 0 done (or already up to date), 2 error, 130 interrupted by SIGINT or
//! SIGTERM (the finished blocks are kept; `--resume` finishes the scan).

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::bail;
use squeal_scan::driver::drive_prepared;
use squeal_scan::estimate::{Estimate, seconds_for};
use squeal_scan::{Pending, Plan};
use squeal_store::ScanWriter;

use super::common;
use super::pictures;
use super::scan_bars::Bars;
use super::scan_report::{Tallies, layout, report};

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

/// The pictures a finished scan file has: the map (or sheet) and, for sweeps, the cycle chart;
/// none for random samples (a list of points, not a map) or a shard (drawn once merged).
fn pictures(out: &Path, maps: usize, sample: bool, shard: bool) -> Vec<PathBuf> {
    if sample || shard {
        return Vec::new();
    }
    let png = common::sibling(out, "", "png");
    let mut v = vec![png.clone()];
    if maps > 1 {
        v.push(common::sibling(&png, "-cycle", "png"));
    }
    v
}

/// Every picture a run with pictures `pics` may draw: those and, where some start squealed
/// before it settled, the map of `t_squeal` beside the first (drawn only then, so not among
/// the pictures a finished file must have). The ones a signal may leave cut or stale.
fn may_draw(pics: &[PathBuf]) -> Vec<PathBuf> {
    let mut v = pics.to_vec();
    if let Some(png) = pics.first() {
        v.push(common::sibling(png, "-t_squeal", "png"));
    }
    v
}

/// Runs the scan.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let mut phases = super::timings::Phases::start();
    let plan = Plan::from_file(&args.spec)?;
    super::doubts::warn_space(&plan.space);
    let (out, shard) = args.run.setup(&plan.output)?;
    let pics = pictures(
        &out,
        plan.maps.len(),
        plan.map.grid.is_sample(),
        shard.is_some(),
    );
    // Nothing but a regular file at a picture's path, a resume's and a rerun's too (a FIFO
    // there blocked the check of an up-to-date picture, or the drawing after the run).
    for p in &may_draw(&pics) {
        squeal_scan::files::refuse_non_regular(p)?;
    }
    if up_to_date(&args, &plan, (&out, shard), &pics)? {
        return Ok(ExitCode::SUCCESS);
    }
    if shard.is_none() && !args.run.resume {
        // Every picture the run may draw, the transient map too (it was overwritten).
        for p in &may_draw(&pics) {
            common::check_new(p, args.run.force, "picture of the scan")?;
        }
    }
    super::report::check_before(&args.run, &out)?;
    common::prepare_output(&out)?;
    // The work, estimated before anything is created or computed; a signal meanwhile ends
    // the run saying so.
    let signals = super::signals::Signals::install()?;
    let threads = rayon::current_num_threads();
    let (mut writer, pilot) = open_writer(&args, &plan, (&out, shard), threads)?;
    signals.computing("blocks");
    let plan = writer.plan().clone();
    if let Some(w) = squeal_core::validated::maps_warning(&plan.maps) {
        eprintln!("{w}");
    }

    let pending = Pending::of(&plan, shard, &writer);
    if !args.run.quiet && pending.cells == 0 {
        eprintln!(
            "squeal: every block of {} is journalled: writing the file (no pilot)",
            out.display()
        );
    } else if !args.run.quiet {
        announce(&plan, pilot.as_ref(), &pending, (shard, threads));
    }
    let bars = Bars::new(&plan, &pending, pilot.as_ref(), args.run.quiet);
    phases.end("start");
    let started = Instant::now();
    let prepared = pilot.map(|e| e.prepared.take()).unwrap_or_default();
    let run = (&bars as &dyn squeal_scan::Observer, signals.stop());
    let done = drive_prepared(&plan, shard, &mut writer, run, prepared).map_err(drive_error)?;
    bars.finish();
    let secs = started.elapsed().as_secs_f64();
    phases.end("cells");
    super::timings::report("prepare", done.prepare);
    super::timings::report("sink", done.sink);
    if done.interrupted {
        eprintln!(
            "squeal: interrupted; {} of {} blocks are stored. Finish with: {}",
            writer.done_blocks(),
            writer.owned_blocks(),
            args.run.resume_command("scan", &args.spec, &out)
        );
        return Ok(ExitCode::from(common::EXIT_INTERRUPTED));
    }
    act_on_audits(&plan, shard, &mut writer, &done.computed)?;
    phases.end("redo");
    signals.finishing(&out, &may_draw(&pics))?;
    finish(
        (&args, &signals, phases),
        &plan,
        writer,
        (&out, &pics),
        (done.cells, secs),
    )
}

/// The writer of the run (created, or resumed from its journal) and the pilot's estimate,
/// if one ran. A resume reads its journal before any pilot: with every block journalled (a
/// run stopped while its file was written) the pilot timed work that was not to be done,
/// and none runs now.
fn open_writer(
    args: &Args,
    plan: &Plan,
    (out, shard): (&Path, Option<squeal_scan::Shard>),
    threads: usize,
) -> anyhow::Result<(ScanWriter, Option<Estimate>)> {
    let owned = Pending::of(plan, shard, &squeal_scan::MemorySink::default());
    let prov = common::provenance();
    let resumed = match args.run.resume {
        true => Some(ScanWriter::resume(out, plan, shard, &prov)?),
        false => None,
    };
    let left = resumed.as_ref().map(|w| Pending::of(plan, shard, w).cells);
    let pilot = match left {
        Some(0) => None,
        _ => checked_estimate(args, plan, &owned, threads)?,
    };
    let writer = match resumed {
        Some(w) => w,
        None => ScanWriter::create(out, plan, shard, &prov, args.run.force)?,
    };
    Ok((writer, pilot))
}

/// The driver's error, a map's or the store's, with its sources.
fn drive_error(e: squeal_scan::DriveError<squeal_store::StoreError>) -> anyhow::Error {
    match e {
        squeal_scan::DriveError::Scan(e) => anyhow::Error::new(e),
        squeal_scan::DriveError::Sink(e) => anyhow::Error::new(e),
    }
}

/// The audit acts before the file is written: a refuted rule is withdrawn and its cells
/// decided again by runs (journalled: a resume after a signal here redoes what is left).
/// Says how many cells of each map were decided again.
fn act_on_audits(
    plan: &Plan,
    shard: Option<squeal_scan::Shard>,
    writer: &mut ScanWriter,
    computed: &squeal_scan::Computed,
) -> anyhow::Result<()> {
    let acted = squeal_scan::redo::act_on_audits(plan, shard, writer, Some(computed))
        .map_err(drive_error)?;
    for a in &acted {
        eprintln!(
            "squeal: map {}: {} cells decided again by runs, without the rules their audit refuted",
            a.map, a.cells
        );
    }
    Ok(())
}

/// Like make (the same rule as the atlas's): a finished output of the same parsed spec (and
/// shard) is up to date; a picture missing is drawn again, and the summary printed.
fn up_to_date(
    args: &Args,
    plan: &Plan,
    (out, shard): (&Path, Option<squeal_scan::Shard>),
    pics: &[PathBuf],
) -> anyhow::Result<bool> {
    let state = squeal_store::output_state(out, plan, shard)?;
    // `pics` is empty for a shard or a random sample: nothing to draw.
    if !common::up_to_date(out, state, &args.run, pics, || {
        pictures::render_file(out, &pics[0], true)
    })? {
        return Ok(false);
    }
    let info = squeal_store::read_info(out)?;
    // Nothing computed: the file holds the checks, no per-reason tally.
    let maps = super::common::map_summaries(&info)?;
    let tallies = Tallies {
        maps: &maps,
        checks: &info.checks,
        reasons: &[],
        transient: &[],
    };
    report(args.json, plan, &info, tallies, pics, 0, 0.0)?;
    super::report::after_run(&args.run, out, args.json)?;
    Ok(true)
}

/// The work to do, on stderr: the cells, the layout, the threads and the time it will take.
fn announce(
    plan: &Plan,
    pilot: Option<&Estimate>,
    pending: &Pending,
    (shard, threads): (Option<squeal_scan::Shard>, usize),
) {
    let secs = seconds_for(plan, pilot, pending, threads);
    eprintln!(
        "squeal: {} cells to compute ({} map(s) of {}{}) on {threads} thread(s): roughly {} ({secs:.1} s){}",
        pending.cells,
        plan.maps.len(),
        layout(plan),
        shard.map(|s| format!(", shard {s}")).unwrap_or_default(),
        common::duration(secs),
        pilot.map_or(
            ", at the documented rates (cycle searches counted at their longest: a pilot would take too long)".to_string(),
            |e| format!(
                ", from a pilot of {} cells over {} map(s) in {:.1} s{}",
                e.cells,
                e.maps(),
                e.pilot_seconds,
                super::progress::busy_words(secs, e.core_share)
            )
        )
    );
}

/// A scan whose blocks are all stored: the landscape of each map (laws with true stick)
/// computed before the writer finishes the file, the picture drawn, the summary printed.
/// A signal once the file is finished stops the drawing (code 130), saying the file is
/// complete.
fn finish(
    (args, signals, mut phases): (&Args, &super::signals::Signals, super::timings::Phases),
    plan: &Plan,
    writer: ScanWriter,
    (out, pics): (&Path, &[PathBuf]),
    (computed, secs): (usize, f64),
) -> anyhow::Result<ExitCode> {
    let finished = crate::finish_scan(writer)?;
    phases.end("finish");
    let redraw = args.run.resume_command("scan", &args.spec, out);
    let note = super::signals::drawing_note(out, &redraw);
    if !pics.is_empty() && !signals.drawing(note.clone(), &may_draw(pics)) {
        eprintln!("squeal: {note}");
        return Ok(ExitCode::from(common::EXIT_INTERRUPTED));
    }
    let checks: Vec<Vec<i64>> = finished.iter().map(|c| c.values().to_vec()).collect();
    let reasons: Vec<_> = finished.iter().map(|c| c.reasons).collect();
    let transient: Vec<_> = finished.iter().map(|c| c.transient).collect();
    let written = match pics.first() {
        Some(png) => pictures::render_file(out, png, true)?,
        None => Vec::new(),
    };
    phases.end("picture");
    signals.done();
    let info = squeal_store::read_info(out)?;
    let maps = super::common::map_summaries(&info)?;
    let tallies = Tallies {
        maps: &maps,
        checks: &checks,
        reasons: &reasons,
        transient: &transient,
    };
    report(args.json, plan, &info, tallies, &written, computed, secs)?;
    super::report::after_run(&args.run, out, args.json)?;
    Ok(ExitCode::SUCCESS)
}

/// The pilot (none with `--quiet`, nor where it could itself run over
/// [`squeal_scan::estimate::PILOT_MAX_SECONDS`]), after refusing work estimated over
/// [`squeal_scan::estimate::LONG_RUN`] without `--allow-long`: first at the documented rates, every kind of
/// work counted (the maps' cycle searches bounded by their samples times `t_return`, the
/// cells, their audits) before the pilot runs, then from the pilot, which measures the time
/// per cell with this plan's law, landscape and early stopping ([`squeal_scan::estimate`]).
fn checked_estimate(
    args: &Args,
    plan: &Plan,
    owned: &Pending,
    threads: usize,
) -> anyhow::Result<Option<Estimate>> {
    let rough = squeal_scan::estimate::documented_seconds(plan, owned, threads);
    if squeal_scan::estimate::refused_as_long(rough, args.allow_long) {
        bail!(
            "{} cells and {} cycle search(es) of up to {} each ([cycle] samples x t_return) would take roughly {} on {threads} thread(s) at the documented rate: shrink the grid, the sweep or the search, split it with --shard, or pass --allow-long",
            owned.cells,
            owned.maps_to_prepare(),
            common::duration(squeal_scan::estimate::prepare_seconds(plan)),
            common::duration(rough)
        );
    }
    let bound = squeal_scan::estimate::pilot_bound(plan);
    // Announced only where the pilot runs (a longer one is skipped: documented rates).
    if !args.run.quiet
        && bound > common::PILOT_NOTICE
        && bound <= squeal_scan::estimate::PILOT_MAX_SECONDS
    {
        eprintln!(
            "squeal: timing a pilot first (up to {} at the documented rate) ...",
            common::duration(bound)
        );
    }
    // The maps it prepares are the run's own: the run takes them (drive_prepared).
    let pilot = match args.run.quiet {
        true => None,
        false => squeal_scan::estimate::bounded_pilot(plan)?,
    };
    let estimate = seconds_for(plan, pilot.as_ref(), owned, threads);
    if squeal_scan::estimate::refused_as_long(estimate, args.allow_long) {
        bail!(
            "{} cells would take roughly {} on {threads} thread(s): shrink the grid or the sweep, split it with --shard, or pass --allow-long",
            owned.cells,
            common::duration(estimate)
        );
    }
    Ok(pilot)
}
