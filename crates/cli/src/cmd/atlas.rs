//! `squeal atlas SPEC.toml`: figures of merit over a design space, regimes, the fold of
//! cycles and the critical damping, into an HDF5 file and a chart.
//!
//! Like make, and by the scan's rule ([`common::up_to_date`]): a rerun of a finished atlas
//! from the same (parsed) spec, with or without `--resume`, draws a missing picture, prints
//! the summary and exits 0; a different spec is refused naming `--force`.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::Ordering;
use std::time::Instant;

use anyhow::bail;
use indicatif::ProgressBar;
use squeal_scan::atlas::AtlasPlan;
use squeal_scan::atlas::driver::UnitResult;
use squeal_store::atlas::{AtlasResults, AtlasWriter, read_atlas};

use super::common;
use super::progress;

/// Flags of `squeal atlas`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The atlas spec (TOML; see scans/atlas-*.toml).
    pub spec: PathBuf,
    #[command(flatten)]
    pub run: super::common::RunArgs,
    /// Do not draw the chart.
    #[arg(long)]
    pub no_render: bool,
    /// Print every point's figures as one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Start an atlas estimated to take more than 30 days.
    #[arg(long)]
    pub allow_long: bool,
}

/// Counts finished map blocks on the progress bar (and the plain lines off a terminal).
struct BarObserver<'a>(&'a ProgressBar, &'a Option<progress::PlainLines>);

impl squeal_scan::Observer for BarObserver<'_> {
    fn block_done(&self, _map: usize, _block: usize) {
        self.0.inc(1);
        if let Some(p) = self.1 {
            p.inc(0);
        }
    }
}

/// Runs the atlas.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let started = Instant::now();
    let plan = AtlasPlan::from_file(&args.spec)?;
    super::doubts::warn_space(&plan.space);
    let (out, shard) = args.run.setup(&plan.out)?;
    let png = common::sibling(&out, "", "png");
    let pics = if shard.is_none() && !args.no_render {
        pictures(&plan, &png)
    } else {
        Vec::new()
    };
    // Nothing but a regular file at a picture's path, a resume's and a rerun's too (a FIFO
    // there blocked the check of an up-to-date picture, or the drawing after the run).
    for p in &pics {
        squeal_scan::files::refuse_non_regular(p)?;
    }
    // Like make (the same rule as the scan's): a finished output of the same parsed spec
    // (and shard) is up to date; a picture missing is drawn again.
    let state = squeal_store::output_state(&out, &plan, shard)?;
    if common::up_to_date(&out, state, &args.run, &pics, || {
        render_atlas(&out, &png, true)
    })? {
        let (plan, res, _) = read_atlas(&out)?;
        report(&args, &plan, &res, &out, Computed::default(), &pics)?;
        super::report::after_run(&args.run, &out, args.json)?;
        return Ok(ExitCode::SUCCESS);
    }
    if !args.run.resume {
        check_pictures(&pics, &png, args.run.force)?;
    }
    super::report::check_before(&args.run, &out)?;
    // The output's folder and lock before the pilot: an unwritable folder was found only
    // after a 74 s pilot. A signal during the pilot ends the run saying so.
    common::prepare_output(&out)?;
    let signals = super::signals::Signals::install()?;
    let (writer, from_pilot) = open_writer(&args, &plan, &out, shard)?;
    let Some((writer, mut computed)) =
        compute(&args, &plan, shard, writer, &signals, &out, started)?
    else {
        return Ok(ExitCode::from(common::EXIT_INTERRUPTED));
    };
    computed.units += from_pilot;
    signals.finishing(&out, &pics)?;
    let mut phases = super::timings::Phases::start();
    let res = crate::finish_atlas(writer)?;
    phases.end("finish");
    let Some(pictures) = draw(&args, &signals, &out, (&png, &pics))? else {
        return Ok(ExitCode::from(common::EXIT_INTERRUPTED));
    };
    phases.end("picture");
    report(&args, &plan, &res, &out, computed, &pictures)?;
    super::report::after_run(&args.run, &out, args.json)?;
    Ok(ExitCode::SUCCESS)
}

/// The writer of the run (created, or resumed from its journal), with the units the
/// pilot computed journalled (where this run owns them) and their count. A resume reads
/// its journal before any pilot: with every unit and map block journalled (a run stopped
/// while its file was written) a resume ran a 54 s pilot for nothing, and now runs none.
fn open_writer(
    args: &Args,
    plan: &AtlasPlan,
    out: &Path,
    shard: Option<squeal_store::Shard>,
) -> anyhow::Result<(AtlasWriter, usize)> {
    let prov = common::provenance();
    let resumed = match args.run.resume {
        true => Some(AtlasWriter::resume(out, plan, shard, &prov)?),
        false => None,
    };
    let left = (resumed.as_ref()).map(|w| w.missing().len() + w.missing_blocks().len());
    let piloted = match left {
        Some(0) => {
            eprintln!(
                "squeal: every unit and map block of {} is journalled: writing the file (no pilot)",
                out.display()
            );
            Vec::new()
        }
        _ => estimate(args, plan)?,
    };
    let mut writer = match resumed {
        Some(w) => w,
        None => AtlasWriter::create(out, plan, shard, &prov, args.run.force)?,
    };
    // The pilot's units are the run's own (the same function of the same plan): journalled,
    // not computed again, where this run (its shard, what a resume still lacks) owns them.
    let missing = writer.missing();
    let mut from_pilot = 0;
    for r in piloted.into_iter().filter(|r| missing.contains(&r.unit())) {
        writer.record(r)?;
        from_pilot += 1;
    }
    Ok((writer, from_pilot))
}

/// Computes the units and map blocks `writer` is missing, with a progress bar: the writer
/// to finish and what was computed, or `None` when a signal interrupted the run (what is
/// left, and how to finish it, said).
fn compute(
    args: &Args,
    plan: &AtlasPlan,
    shard: Option<squeal_store::Shard>,
    writer: AtlasWriter,
    signals: &super::signals::Signals,
    out: &Path,
    started: Instant,
) -> anyhow::Result<Option<(AtlasWriter, Computed)>> {
    signals.computing("units and map blocks");
    let todo = writer.missing();
    let todo_blocks = writer.missing_blocks().len();
    let total = (todo.len() + todo_blocks) as u64;
    let bar = progress(total, args.run.quiet);
    let plain = progress::PlainLines::new("units and map blocks", "unit", total, args.run.quiet);
    let t0 = Instant::now();
    // When the last unit reached the sink: the units' phase ends there, the maps' begins.
    let units_done = std::sync::Mutex::new(t0);
    let result = crate::run_atlas(
        plan,
        shard,
        writer,
        signals.stop(),
        &|| {
            if super::timings::on() {
                *units_done.lock().unwrap_or_else(|e| e.into_inner()) = Instant::now();
            }
            bar.inc(1);
            if let Some(p) = &plain {
                p.inc(0);
            }
        },
        &BarObserver(&bar, &plain),
    );
    bar.finish_and_clear();
    let (writer, left) = result?;
    let seconds = t0.elapsed().as_secs_f64();
    let units_done = units_done.into_inner().unwrap_or_else(|e| e.into_inner());
    super::timings::report("start", t0 - started);
    super::timings::report("units", units_done - t0);
    super::timings::report("maps", units_done.elapsed());
    if signals.stop().load(Ordering::SeqCst) && left > 0 {
        eprintln!(
            "squeal: interrupted; {left} units and map blocks left. Finish with: {}",
            args.run.resume_command("atlas", &args.spec, out)
        );
        return Ok(None);
    }
    let computed = Computed {
        seconds,
        units: todo.len(),
        blocks: todo_blocks,
    };
    Ok(Some((writer, computed)))
}

/// The pictures of a finished atlas file `out` (none where `pics` is empty: a shard or
/// `--no-render`); `None` if a signal came before the drawing. From here on a signal ends
/// the run at once, saying the file is complete ([`super::signals`]).
fn draw(
    args: &Args,
    signals: &super::signals::Signals,
    out: &Path,
    (png, pics): (&Path, &[PathBuf]),
) -> anyhow::Result<Option<Vec<PathBuf>>> {
    if pics.is_empty() {
        return Ok(Some(Vec::new()));
    }
    let redraw = args.run.resume_command("atlas", &args.spec, out);
    let note = super::signals::drawing_note(out, &redraw);
    if !signals.drawing(note.clone(), pics) {
        eprintln!("squeal: {note}");
        return Ok(None);
    }
    let drawn = render_atlas(out, png, true)?;
    signals.done();
    Ok(Some(drawn))
}

/// Refuses to start a run over existing pictures without `--force` (the chart `png`, the
/// sheet of maps, the picture of their final-state sensitivity, the lifetimes).
fn check_pictures(pics: &[PathBuf], png: &Path, force: bool) -> anyhow::Result<()> {
    for p in pics {
        let what = if p == png {
            "chart of the atlas"
        } else if *p == squeal_plot::sensitivity_path(png) {
            SENSITIVITY
        } else if *p == sheet_path(png) {
            "sheet of basin maps"
        } else {
            "chart of lifetimes"
        };
        common::check_new(p, force, what)?;
    }
    Ok(())
}

/// What the picture of final-state sensitivity is called in messages.
const SENSITIVITY: &str = "picture of the maps' final-state sensitivity";

/// The work, estimated from a pilot before anything is created (printed unless quiet); over
/// [`squeal_scan::estimate::LONG_RUN`] it needs `--allow-long`. The whole atlas is estimated, also for a
/// shard or a resume (an upper bound then). Returns the units the pilot computed.
fn estimate(args: &Args, plan: &AtlasPlan) -> anyhow::Result<Vec<UnitResult>> {
    use squeal_scan::estimate::{atlas_documented_seconds, bounded_atlas_pilot};
    let threads = rayon::current_num_threads();
    let maps = plan.map_plan().map_or(String::new(), |mp| {
        format!(", {} map cells", mp.map.grid.cells() * mp.maps.len())
    });
    let what = format!(
        "{} points, {} boundary searches{maps}",
        plan.space.n_points(),
        plan.n_boundaries()
    );
    let refuse = |secs: f64, how: &str| -> anyhow::Result<()> {
        if squeal_scan::estimate::refused_as_long(secs, args.allow_long) {
            bail!(
                "the atlas ({what}) would take roughly {} on {threads} thread(s){how}: shrink the sweep, the maps or the cycle search ([cycle] samples x t_return), split it with --shard, or pass --allow-long",
                common::duration(secs)
            );
        }
        Ok(())
    };
    // Every kind of work at the documented rates first (cycle searches at their longest):
    // no pilot runs for an atlas refused on those alone.
    let rough = atlas_documented_seconds(plan, threads);
    refuse(rough, " at the documented rate")?;
    if let Some(words) = pilot_words(plan).filter(|_| !args.run.quiet) {
        eprintln!("squeal: {words}");
    }
    let mut pilot = bounded_atlas_pilot(plan)?;
    let units = pilot
        .as_mut()
        .map_or_else(Vec::new, |e| std::mem::take(&mut e.units));
    let secs = pilot.as_ref().map_or(rough, |e| e.seconds(plan, threads));
    refuse(secs, "")?;
    if !args.run.quiet {
        let how = pilot.map_or(
            "at the documented rates (cycle searches counted at their longest: a pilot would take too long)".to_string(),
            |e| {
                format!(
                    "from a pilot of {} point(s) in {:.1} s{}",
                    e.points,
                    e.pilot_seconds,
                    super::progress::busy_words(secs, e.core_share)
                )
            },
        );
        eprintln!(
            "squeal: atlas of {what} on {threads} thread(s): roughly {} ({secs:.1} s), {how}",
            common::duration(secs),
        );
    }
    Ok(units)
}

/// What the atlas's pilot is announced as, where it runs and may take a while: its points
/// and maps, up to a bound at the documented rate
/// ([`squeal_scan::estimate::atlas_pilot_points_bound`]), and one to three of its boundary
/// searches, run whole (and kept by the run), which no bound worth giving covers: a resume
/// announced as "up to 12 s" took 54 s. `None` for a pilot that is skipped (the documented
/// rates instead) or short.
fn pilot_words(plan: &AtlasPlan) -> Option<String> {
    use squeal_scan::estimate::{PILOT_MAX_SECONDS, atlas_pilot_bound, atlas_pilot_points_bound};
    let bound = atlas_pilot_points_bound(plan);
    let nb = plan.n_boundaries();
    if atlas_pilot_bound(plan) > PILOT_MAX_SECONDS || (bound <= common::PILOT_NOTICE && nb == 0) {
        return None;
    }
    let points = format!(
        "its points and maps up to {} at the documented rate",
        common::duration(bound)
    );
    Some(match nb {
        0 => format!("timing a pilot of the atlas first ({points}) ..."),
        _ => format!(
            "timing a pilot of the atlas first: {points}, then {} of its {nb} boundary \
             search(es), each run whole (as long as the run takes for one; the run keeps \
             them) ...",
            match nb.min(3) {
                1 => "1".to_string(),
                k => format!("1 to {k}"),
            }
        ),
    })
}

/// The progress bar over `total` units and map blocks (hidden when quiet or not a terminal).
fn progress(total: u64, quiet: bool) -> ProgressBar {
    progress::bar(
        total,
        quiet,
        "atlas [{bar:40}] {pos}/{len} units and map blocks  {avg_rate}  ETA {avg_eta}",
        "unit",
    )
}

/// The pictures of a finished atlas whose chart is `png`: the chart (one or two swept
/// parameters: a bifurcation diagram or a stability chart), then with maps their sheet and
/// (one or two swept parameters) their final-state sensitivity.
fn pictures(plan: &AtlasPlan, png: &Path) -> Vec<PathBuf> {
    let chartable = matches!(plan.space.axes().len(), 1 | 2);
    let mut v = Vec::new();
    if chartable {
        v.push(png.to_path_buf());
    }
    if plan.maps.is_some() {
        v.push(sheet_path(png));
    }
    if squeal_plot::has_sensitivity(plan) {
        v.push(squeal_plot::sensitivity_path(png));
    }
    if squeal_plot::has_fold_lifetimes(plan) {
        v.extend(squeal_plot::fold_lifetime_paths(png));
    }
    v
}

/// What a run computed (nothing for an output already up to date).
#[derive(Clone, Copy, Debug, Default)]
struct Computed {
    seconds: f64,
    units: usize,
    blocks: usize,
}

/// The summary of a finished atlas, in words or as one JSON object.
fn report(
    args: &Args,
    plan: &AtlasPlan,
    res: &AtlasResults,
    out: &Path,
    computed: Computed,
    pictures: &[PathBuf],
) -> anyhow::Result<()> {
    if args.json {
        let mut v = crate::atlas_json::atlas_json(plan, res);
        v["file"] = out.display().to_string().into();
        v["seconds"] = computed.seconds.into();
        v["units_computed"] = computed.units.into();
        v["map_blocks_computed"] = computed.blocks.into();
        println!("{}", serde_json::to_string(&v)?);
    } else {
        let ran =
            (computed.units + computed.blocks > 0).then_some((computed.seconds, computed.units));
        super::atlas_words::print_summary(plan, res, out, ran);
        for p in pictures {
            println!("{}", p.display());
        }
    }
    Ok(())
}

/// The sheet of basin maps of an atlas whose chart is `png`: `<stem>-maps.png`.
pub fn sheet_path(png: &Path) -> PathBuf {
    common::sibling(png, "-maps", "png")
}

/// Draws the pictures of an atlas file: a stability chart (2-D), a bifurcation diagram
/// (1-D), and with maps a sheet of them ([`sheet_path`]) and their final-state sensitivity
/// ([`render_sensitivity`]). Returns the files written.
pub fn render_atlas(h5: &Path, png: &Path, force: bool) -> anyhow::Result<Vec<PathBuf>> {
    let (plan, res, _) = read_atlas(h5)?;
    let chartable = matches!(plan.space.axes().len(), 1 | 2);
    if !chartable && plan.maps.is_none() {
        bail!(
            "{}: {} swept parameters; charts are drawn for 1 (bifurcation diagram) or 2 (stability chart); read the file with h5py/xarray",
            h5.display(),
            plan.space.axes().len()
        )
    }
    let mut drawn = Vec::new();
    if chartable {
        common::check_new(png, force, "chart")?;
        // A chart cut short (a full disk) is removed, so no later run takes it as drawn.
        squeal_plot::atlas_chart(&plan, &res, png).map_err(|e| common::discard(png, e))?;
        drawn.push(png.to_path_buf());
    }
    if plan.maps.is_some() {
        let sheet = sheet_path(png);
        common::check_new(&sheet, force, "sheet of basin maps")?;
        squeal_plot::atlas_sheet(&plan, &res, &sheet).map_err(|e| common::discard(&sheet, e))?;
        drawn.push(sheet);
    }
    drawn.extend(render_sensitivity(h5, &plan, png, force)?);
    if squeal_plot::has_fold_lifetimes(&plan) {
        let paths = squeal_plot::fold_lifetime_paths(png);
        for p in &paths {
            common::check_new(p, force, "chart of lifetimes")?;
        }
        let [a, b] = [&paths[0], &paths[1]];
        squeal_plot::fold_lifetime_charts(&plan, &res, [a, b]).map_err(|e| {
            let _ = std::fs::remove_file(b);
            common::discard(a, e)
        })?;
        drawn.extend(paths);
    }
    Ok(drawn)
}

/// The final-state sensitivity of the maps of the atlas file `h5` (of the stored `plan`),
/// read from the file's `map_` datasets, beside its chart `png`
/// ([`squeal_plot::sensitivity_path`]): the picture where some point was measured (none
/// for a file written before the sensitivity was stored, or where no map was measured).
fn render_sensitivity(
    h5: &Path,
    plan: &AtlasPlan,
    png: &Path,
    force: bool,
) -> anyhow::Result<Option<PathBuf>> {
    if !squeal_plot::has_sensitivity(plan) {
        return Ok(None);
    }
    let path = squeal_plot::sensitivity_path(png);
    common::check_new(&path, force, SENSITIVITY)?;
    let Some(s) = squeal_store::atlas::read_map_sensitivity(h5, plan)? else {
        return Ok(None);
    };
    let drawn = squeal_plot::atlas_sensitivity(plan, &s.values, &s.log2_test, &path)
        .map_err(|e| common::discard(&path, e))?;
    Ok(drawn.then_some(path))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The atlas's pilot runs 1 to 3 of its boundary searches whole, which the documented
    /// rate does not bound: it was announced as "up to 12 s" and took 54 s. With boundary
    /// searches the announcement says so; without, its bound covers the points and maps.
    #[test]
    fn the_pilot_is_announced_with_what_bounds_it() {
        let spec = |b: &str| {
            format!(
                "version = 1\n[model]\nlaw = \"mcmillan\"\nnu = [1e-3, 1e-2, 5e-2]\n\
                 [cycle]\nhalf_dt = false\n[attractor]\ntransient = 10\nwindow = 10\n\
                 [boundaries]\n{b}\n[output]\npath = \"x.h5\"\n"
            )
        };
        let with = AtlasPlan::from_toml(&spec("rtol = 1e-2"), "x.toml").unwrap();
        let words = pilot_words(&with).expect("a pilot of boundary searches is announced");
        assert!(
            words.contains("then 1 of its 1 boundary search(es), each run whole"),
            "{words}"
        );
        let none = AtlasPlan::from_toml(&spec("fold = false\ncritical = false"), "x.toml").unwrap();
        assert_eq!(none.n_boundaries(), 0);
        let bound = squeal_scan::estimate::atlas_pilot_points_bound(&none);
        match pilot_words(&none) {
            Some(w) => assert!(w.contains(&common::duration(bound)) && !w.contains("boundary")),
            None => assert!(bound <= common::PILOT_NOTICE, "{bound}"),
        }
    }
}
