//! Pieces shared by the subcommands: provenance, output checks, progress, pictures.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use anyhow::{Context, bail};
use squeal_plot::{BasinPanel, Curve, Rgb};

/// Version and git revision recorded in every output.
pub fn provenance() -> squeal_store::Provenance {
    squeal_store::Provenance {
        version: env!("CARGO_PKG_VERSION").to_string(),
        git_revision: env!("SQUEAL_GIT_REV").to_string(),
    }
}

/// Refuses to overwrite `path` unless `force`.
pub fn check_new(path: &Path, force: bool, what: &str) -> anyhow::Result<()> {
    if path.exists() && !force {
        bail!(
            "refusing to overwrite {} ({what}): use --force",
            path.display()
        );
    }
    Ok(())
}

/// Whether `path` holds a whole picture: a file that starts with the PNG signature and
/// ends with the PNG's closing `IEND` chunk (its name and fixed CRC). A full disk left a
/// 0-byte or cut PNG that a rerun reported "up to date"; such a file is drawn again.
pub fn is_drawn(path: &Path) -> bool {
    const SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', b'\r', b'\n', 0x1a, b'\n'];
    const END: [u8; 8] = [b'I', b'E', b'N', b'D', 0xAE, 0x42, 0x60, 0x82];
    std::fs::read(path)
        .is_ok_and(|b| b.len() > 16 && b.starts_with(&SIGNATURE) && b.ends_with(&END))
}

/// Exit code of a run stopped by SIGINT or SIGTERM: resumable with `--resume`.
pub const EXIT_INTERRUPTED: u8 = 130;

/// Sets `stop` on SIGINT, SIGTERM (SLURM's time limit and preemption) and SIGHUP, saying
/// the run stops after the `what` in flight; a second signal exits at once (code 130).
pub fn install_signals(
    stop: &std::sync::Arc<std::sync::atomic::AtomicBool>,
    what: &'static str,
) -> anyhow::Result<()> {
    use std::sync::atomic::Ordering;
    let stop = stop.clone();
    // The "termination" feature of ctrlc routes SIGTERM and SIGHUP here as well as SIGINT.
    ctrlc::set_handler(move || {
        if stop.swap(true, Ordering::SeqCst) {
            std::process::exit(EXIT_INTERRUPTED.into());
        }
        eprintln!("\nsqueal: stopping after the {what} in flight (signal again to quit at once)");
    })
    .context("installing the SIGINT/SIGTERM handler")
}

/// Like make, for scans and atlases alike: decides what a run does with a finished output
/// before it computes anything. Without `--force`, a file made from the same parsed spec
/// (and shard) is up to date, for a rerun and for `--resume` (a requeued job that had
/// finished): any of `pictures` missing is drawn again with `draw`, it says so and returns
/// `true` (nothing to compute). A file of another spec, or not a finished file of this
/// kind, is refused naming `--force`.
/// Anything else (no file, an interrupted run) returns `false`: the writer takes over.
pub fn up_to_date(
    out: &Path,
    state: squeal_store::OutputState,
    run: &RunArgs,
    pictures: &[PathBuf],
    draw: impl FnOnce() -> anyhow::Result<Vec<PathBuf>>,
) -> anyhow::Result<bool> {
    use squeal_store::OutputState;
    if run.force {
        return Ok(false);
    }
    match state {
        OutputState::Complete => {
            let drew = pictures.iter().any(|p| !is_drawn(p));
            if drew {
                draw()?;
            }
            eprintln!(
                "squeal: {} is up to date (made from the same spec){}",
                out.display(),
                if drew {
                    "; drew the missing picture"
                } else {
                    ""
                }
            );
            Ok(true)
        }
        OutputState::Different(key) => bail!(
            "{} exists and was made from a different spec (`{key}` differs): use --force to overwrite it, or -o for another output",
            out.display()
        ),
        OutputState::Foreign(why) => bail!(
            "{} exists and is not a finished file of this spec's kind ({why}): use --force to overwrite it, or -o for another output",
            out.display()
        ),
        OutputState::Absent | OutputState::Interrupted => Ok(false),
    }
}

/// The error of a drawing, with the picture it left removed (a full disk left a 0-byte or
/// cut PNG).
pub fn discard(png: &Path, e: impl Into<anyhow::Error>) -> anyhow::Error {
    let _ = std::fs::remove_file(png);
    e.into().context(format!("drawing {}", png.display()))
}

/// `out` with its extension replaced and an optional suffix on the stem.
pub fn sibling(out: &Path, suffix: &str, ext: &str) -> PathBuf {
    let stem = out
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    out.with_file_name(format!("{stem}{suffix}.{ext}"))
}

/// Whether progress bars should be drawn.
pub fn show_progress(quiet: bool) -> bool {
    !quiet && std::io::stderr().is_terminal()
}

/// The average rate so far, `done` units over `secs` seconds ("-" before the first second:
/// a rate from a few units in a few milliseconds is noise).
pub fn rate_words(done: u64, secs: f64, unit: &str) -> String {
    if secs < 1.0 || done == 0 {
        return "-".into();
    }
    let r = done as f64 / secs;
    if r >= 10.0 {
        format!("{r:.0} {unit}/s")
    } else {
        format!("{:.1} s/{unit}", 1.0 / r)
    }
}

/// The time left at the average rate so far ("estimating" before the first second and the
/// first unit: indicatif's own estimate starts from a few samples and can say hours for a
/// job of a second).
pub fn eta_words(done: u64, total: u64, secs: f64) -> String {
    if secs < 1.0 || done == 0 {
        return "estimating".into();
    }
    let left = total.saturating_sub(done) as f64 * secs / done as f64;
    short_duration(left)
}

/// "45 s", "12 min", "3.2 h".
pub fn short_duration(s: f64) -> String {
    if s < 90.0 {
        format!("{s:.0} s")
    } else if s < 5400.0 {
        format!("{:.0} min", s / 60.0)
    } else {
        format!("{:.1} h", s / 3600.0)
    }
}

/// A bar style whose `{avg_rate}` and `{avg_eta}` are [`rate_words`] and [`eta_words`]
/// (`unit` names what is counted).
pub fn bar_style(template: &str, unit: &'static str) -> indicatif::ProgressStyle {
    use indicatif::ProgressState;
    let secs = |s: &ProgressState| s.elapsed().as_secs_f64();
    indicatif::ProgressStyle::with_template(template)
        .expect("static template")
        .with_key(
            "avg_rate",
            move |s: &ProgressState, w: &mut dyn std::fmt::Write| {
                let _ = w.write_str(&rate_words(s.pos(), secs(s), unit));
            },
        )
        .with_key(
            "avg_eta",
            move |s: &ProgressState, w: &mut dyn std::fmt::Write| {
                let total = s.len().unwrap_or(0);
                let _ = w.write_str(&eta_words(s.pos(), total, secs(s)));
            },
        )
        .progress_chars("=> ")
}

/// [`bar_style`] whose `{avg_eta}` is the time left by `meter` (weighed units) instead of
/// the bar's own count.
pub fn metered_bar_style(
    template: &str,
    unit: &'static str,
    meter: std::sync::Arc<WorkMeter>,
) -> indicatif::ProgressStyle {
    use indicatif::ProgressState;
    bar_style(template, unit).with_key(
        "avg_eta",
        move |s: &ProgressState, w: &mut dyn std::fmt::Write| {
            let _ = w.write_str(&meter.eta_words(s.elapsed().as_secs_f64()));
        },
    )
}

/// The work done so far, each unit weighed by its expected cost: the time left is the rest at
/// the rate so far. A sweep's maps above a fold of cycles cost far more per cell than those
/// below it (`nu-sweep`'s last two maps took about 80 s of its 100 s), so counting cells
/// alone promised "5 s left" 80 s before the end; the scan's pilot gives each map's cost per
/// cell.
pub struct WorkMeter {
    /// Expected cost of one unit of each kind (a map's cells), relative; empty: all alike.
    weights: Vec<f64>,
    total: f64,
    units: u64,
    /// Units done, and their expected cost (f64 bits).
    done: std::sync::atomic::AtomicU64,
    work: std::sync::atomic::AtomicU64,
}

impl WorkMeter {
    /// `total` units, all alike.
    pub fn uniform(total: u64) -> Self {
        WorkMeter {
            weights: Vec::new(),
            total: total as f64,
            units: total,
            done: 0.into(),
            work: 0f64.to_bits().into(),
        }
    }

    /// `counts[k]` units of kind `k`, each weighing `weights[k]` (a weight that is not finite
    /// and positive counts as the mean of the others).
    pub fn weighted(weights: Vec<f64>, counts: &[u64]) -> Self {
        let good = |w: &f64| *w > 0.0 && w.is_finite();
        let known: Vec<f64> = weights.iter().copied().filter(good).collect();
        let mean = known.iter().sum::<f64>() / known.len().max(1) as f64;
        let weights: Vec<f64> = weights
            .into_iter()
            .map(|w| {
                if good(&w) {
                    w
                } else {
                    mean.max(f64::MIN_POSITIVE)
                }
            })
            .collect();
        WorkMeter {
            total: counts
                .iter()
                .zip(&weights)
                .map(|(n, w)| *n as f64 * w)
                .sum(),
            units: counts.iter().sum(),
            weights,
            done: 0.into(),
            work: 0f64.to_bits().into(),
        }
    }

    /// Counts one unit of kind `kind`; returns the units done.
    pub fn add(&self, kind: usize) -> u64 {
        use std::sync::atomic::Ordering;
        let w = self.weights.get(kind).copied().unwrap_or(1.0);
        let _ = self
            .work
            .fetch_update(Ordering::Relaxed, Ordering::Relaxed, |b| {
                Some((f64::from_bits(b) + w).to_bits())
            });
        self.done.fetch_add(1, Ordering::Relaxed) + 1
    }

    /// Units done.
    pub fn done(&self) -> u64 {
        self.done.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// Seconds left after `secs` seconds: the expected work left at the rate so far.
    pub fn left_seconds(&self, secs: f64) -> f64 {
        let work = f64::from_bits(self.work.load(std::sync::atomic::Ordering::Relaxed));
        (self.total - work).max(0.0) * secs / work.max(f64::MIN_POSITIVE)
    }

    /// The time left in words ("estimating" before the first second and the first unit).
    pub fn eta_words(&self, secs: f64) -> String {
        if secs < 1.0 || self.done() == 0 {
            return "estimating".into();
        }
        short_duration(self.left_seconds(secs))
    }
}

/// Progress as plain lines on stderr when it is not a terminal (a batch or SLURM log, where
/// a bar draws nothing): one line every 5 % of the work, with the average rate and the time
/// left ([`WorkMeter`]), and at least one a minute; none in the first second (a rate from a
/// few units in a few milliseconds is noise: the line said "19 s left" of a 0.3 s scan).
pub struct PlainLines {
    what: &'static str,
    unit: &'static str,
    meter: std::sync::Arc<WorkMeter>,
    /// The last 5 % step printed, and the elapsed second of the last line.
    printed: std::sync::Mutex<(u64, f64)>,
    started: std::time::Instant,
}

impl PlainLines {
    /// Lines for `total` units of `what` (e.g. "cells"), counted as `unit`; `None` with
    /// `--quiet`, on a terminal (the bar shows it) or for no work.
    pub fn new(what: &'static str, unit: &'static str, total: u64, quiet: bool) -> Option<Self> {
        Self::with_meter(
            what,
            unit,
            std::sync::Arc::new(WorkMeter::uniform(total)),
            quiet,
        )
    }

    /// Lines that read `meter`, which the caller counts ([`WorkMeter::add`], then
    /// [`PlainLines::report`]).
    pub fn with_meter(
        what: &'static str,
        unit: &'static str,
        meter: std::sync::Arc<WorkMeter>,
        quiet: bool,
    ) -> Option<Self> {
        (!quiet && !std::io::stderr().is_terminal() && meter.units > 0).then(|| PlainLines {
            what,
            unit,
            meter,
            printed: std::sync::Mutex::new((0, 0.0)),
            started: std::time::Instant::now(),
        })
    }

    /// Counts one unit (of kind `kind`) on its meter and reports.
    pub fn inc(&self, kind: usize) {
        self.meter.add(kind);
        self.report();
    }

    /// Prints a line at each 5 % step of the meter's units (or after a minute without one),
    /// from the first second on.
    pub fn report(&self) {
        let done = self.meter.done();
        let total = self.meter.units.max(1);
        let step = done * 20 / total;
        let secs = self.started.elapsed().as_secs_f64();
        let Ok(mut last) = self.printed.lock() else {
            return;
        };
        if secs >= 1.0 && (step > last.0 || secs - last.1 >= 60.0) {
            *last = (step, secs);
            eprintln!(
                "squeal: {:.0}% ({done}/{total} {}) after {}, {}, about {} left",
                100.0 * done as f64 / total as f64,
                self.what,
                short_duration(secs),
                rate_words(done, secs, self.unit),
                short_duration(self.meter.left_seconds(secs)),
            );
        }
    }
}

/// The model parameters of map `map` of a file, for picture titles (root attributes, with the
/// swept parameter's value of that map).
pub fn model_params(info: &squeal_store::FileInfo, map: usize) -> squeal_plot::ModelParams {
    let num = |key: &str| -> f64 {
        match &info.sweep {
            Some((name, values)) if name == key => values.get(map).copied().unwrap_or(f64::NAN),
            _ => attr(info, key)
                .and_then(|v| v.parse().ok())
                .unwrap_or(f64::NAN),
        }
    };
    let law = attr(info, "law").unwrap_or("?");
    // The law's own keys (files of an unknown law: McMillan's, as files before the
    // Stribeck law).
    let keys = law
        .parse::<squeal_core::FrictionLaw>()
        .map_or(squeal_core::FrictionLaw::McMillan.keys(), |l| l.keys());
    squeal_plot::ModelParams {
        law: law.to_string(),
        params: keys.iter().map(|k| (k.to_string(), num(k))).collect(),
        dt: num("dt"),
    }
}

/// The parameters of a run for picture titles, by the law's own names.
pub fn plot_params(p: &squeal_core::Params, dt: f64) -> squeal_plot::ModelParams {
    squeal_plot::ModelParams {
        law: p.law.name().into(),
        params: p
            .named()
            .iter()
            .map(|n| (n.name.to_string(), n.value))
            .collect(),
        dt,
    }
}

/// A basin panel for one map of a file, its axes in the law's units (`scale`).
pub fn panel(m: &squeal_store::MapData, scale: squeal_plot::StateScale) -> BasinPanel<'_> {
    let overlays = m
        .cycle
        .iter()
        .map(|(x, v)| squeal_plot::cycle_overlay(x, v))
        .collect();
    BasinPanel {
        axis_labels: Some(scale.initial_labels().map(String::from)),
        title: m.title.clone(),
        x0: &m.x0,
        v0: &m.v0,
        labels: &m.labels,
        overlays,
        markers: squeal_plot::state_markers(m.fixed_point, &m.x0, &m.v0),
    }
}

/// Draws the pictures of a finished scan file: the basin map (one map), or a sheet of the
/// maps and the cycle size against the swept parameter (sweeps). Returns the files written.
pub fn render_file(h5: &Path, png: &Path, force: bool) -> anyhow::Result<Vec<PathBuf>> {
    let n = squeal_store::map_count(h5)?;
    let info = squeal_store::read_info(h5)?;
    let scale = squeal_plot::StateScale::of_law(attr(&info, "law").unwrap_or("?"));
    let name = attr(&info, "name").unwrap_or("squeal");
    if n == 1 {
        check_new(png, force, "picture")?;
        let m = squeal_store::read_map(h5, 0)?;
        let units = physical_units(&info);
        let scaled = units.map(|u| scaled_axes(&m, u));
        let mut one = panel(&m, scale);
        if let (Some(u), Some((xs, vs))) = (units, &scaled) {
            to_si(&mut one, xs, vs, u);
        }
        let system = physical_line(&info);
        one.title = format!(
            "{name}: {}{system}",
            squeal_plot::map_title(&model_params(&info, 0))
        );
        squeal_plot::basin_map(png, &one, &squeal_plot::label_classes())
            .map_err(|e| discard(png, e))?;
        let transient = super::transient::draw(png, force, &info, &m, &one)?;
        return Ok(std::iter::once(png.to_path_buf())
            .chain(transient)
            .collect());
    }
    let size = sibling(png, "-cycle", "png");
    check_new(png, force, "picture")?;
    check_new(&size, force, "picture")?;
    let transient = render_sheet(h5, (png, force), &info, scale)?;
    render_cycle_sizes(h5, &size, &info)?;
    Ok([png.to_path_buf(), size]
        .into_iter()
        .chain(transient)
        .collect())
}

/// The sheet of a sweep's maps, one panel per swept value, and beside it their transient
/// squeal where some start squealed first (returned).
fn render_sheet(
    h5: &Path,
    (png, force): (&Path, bool),
    info: &squeal_store::FileInfo,
    scale: squeal_plot::StateScale,
) -> anyhow::Result<Option<PathBuf>> {
    let n = info.counts.len();
    let maps: Vec<_> = (0..n)
        .map(|i| squeal_store::read_map(h5, i))
        .collect::<Result<_, _>>()?;
    let units = physical_units(info);
    let scaled: Vec<_> = maps
        .iter()
        .map(|m| units.map(|u| scaled_axes(m, u)))
        .collect();
    let param = swept(info);
    let panels: Vec<_> = maps
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let mut p = panel(m, scale);
            if let (Some(u), Some((xs, vs))) = (units, &scaled[i]) {
                to_si(&mut p, xs, vs, u);
            }
            let value = info.sweep.as_ref().map_or(f64::NAN, |s| s.1[i]);
            p.title = squeal_plot::panel_title(&param, value);
            p
        })
        .collect();
    let title = squeal_plot::sheet_title(
        attr(info, "name").unwrap_or("squeal"),
        &model_params(info, 0),
        &param,
    ) + &physical_line(info);
    let ncols = (n as f64).sqrt().ceil() as usize;
    squeal_plot::basin_sheet(png, &title, &panels, &squeal_plot::label_classes(), ncols)
        .map_err(|e| discard(png, e))?;
    super::transient::draw_sheet((png, force), info, &maps, &panels, (&title, ncols))
}

/// The swept parameter of a sweep file.
fn swept(info: &squeal_store::FileInfo) -> String {
    info.sweep
        .as_ref()
        .map(|s| s.0.clone())
        .unwrap_or_else(|| "nu".into())
}

/// The unstable cycle's size against the swept parameter; values without a cycle marked by
/// what the map found instead (every start squeals, none does, or neither).
fn render_cycle_sizes(h5: &Path, size: &Path, info: &squeal_store::FileInfo) -> anyhow::Result<()> {
    let summary = squeal_store::read_cycle_summary(h5)?;
    let xs: Vec<f64> = summary.iter().map(|s| s.0).collect();
    let curves = vec![
        Curve {
            label: "distance from the fixed point along +x".into(),
            xs: xs.clone(),
            ys: summary.iter().map(|s| s.2).collect(),
            color: Rgb(200, 60, 20),
            points_only: false,
        },
        Curve {
            label: "velocity x' where the cycle crosses x = x*".into(),
            xs: xs.clone(),
            ys: summary.iter().map(|s| s.1).collect(),
            color: Rgb(30, 90, 200),
            points_only: false,
        },
    ];
    let param = swept(info);
    let log_x = param == "nu" || param == "xi";
    let missing = squeal_plot::missing_values(&curves, log_x);
    let gaps = cycle_gaps(&missing, &xs, &info.counts);
    let mut shared = squeal_plot::params_line(&model_params(info, 0), Some(&param));
    shared.insert_str(
        0,
        &format!(
            "{}, ",
            squeal_plot::law_title(attr(info, "law").unwrap_or("?"))
        ),
    );
    let name = attr(info, "name").unwrap_or("squeal");
    squeal_plot::sweep_chart(
        size,
        &format!("{name}: unstable limit cycle size against {param}\n{shared}"),
        &format!("{param} (swept parameter)"),
        "size of the unstable cycle (nondimensional)",
        &curves,
        log_x,
        &gaps,
    )
    .map_err(|e| discard(size, e))
}

/// The swept values without a cycle (`missing`), grouped by what map `i` (at `xs[i]`, cell
/// counts `[undecided, steady, stick, not computed]`) found: only stick-slip, only steady
/// slip, or neither alone. Each group has its own glyph (issue 21: one triangle for "every
/// start squeals" and "no start squeals" could not be told apart).
pub fn cycle_gaps(missing: &[f64], xs: &[f64], counts: &[[u64; 4]]) -> Vec<squeal_plot::Gap> {
    use squeal_plot::{Gap, Glyph};
    let mut gaps = [
        (
            "no unstable cycle: every start squeals",
            Glyph::TriangleUp,
            Rgb(200, 40, 40),
        ),
        (
            "no unstable cycle: no start squeals",
            Glyph::TriangleDown,
            squeal_plot::STEADY,
        ),
        (
            "no unstable cycle located (both basins or undecided)",
            Glyph::Diamond,
            squeal_plot::MISSING,
        ),
    ]
    .map(|(label, glyph, color)| Gap {
        label: label.into(),
        xs: Vec::new(),
        glyph,
        color,
    });
    for &x in missing {
        let c = xs.iter().position(|&v| v == x).and_then(|i| counts.get(i));
        let group = match c {
            Some([_, 0, stick, _]) if *stick > 0 => 0,
            Some([_, steady, 0, _]) if *steady > 0 => 1,
            _ => 2,
        };
        gaps[group].xs.push(x);
    }
    gaps.into_iter().filter(|g| !g.xs.is_empty()).collect()
}

/// Micrometres and mm/s per nondimensional length and velocity unit of a physical scan file
/// (its `length_unit`, `velocity_unit` attributes); `None` for nondimensional files.
fn physical_units(info: &squeal_store::FileInfo) -> Option<(f64, f64)> {
    let num = |k: &str| attr(info, k).and_then(|v| v.parse::<f64>().ok());
    Some((num("length_unit")? * 1e6, num("velocity_unit")? * 1e3))
}

/// The physical system of a physical scan file as a title line ("\nm = 2 kg, k = ..."; empty
/// for nondimensional files), from its `physical_<key>` and `physical_<key>_units` attributes.
fn physical_line(info: &squeal_store::FileInfo) -> String {
    let parts: Vec<String> = squeal_scan::atlas::spec::PHYSICAL
        .iter()
        .filter_map(|(key, _, _)| {
            let v: f64 = attr(info, &format!("physical_{key}"))?.parse().ok()?;
            let u = attr(info, &format!("physical_{key}_units")).unwrap_or("1");
            let u = if u == "1" {
                String::new()
            } else {
                format!(" {u}")
            };
            Some(format!("{key} = {}{u}", squeal_plot::fmt_value(v)))
        })
        .collect();
    if parts.is_empty() {
        String::new()
    } else {
        format!("\n{}", parts.join(", "))
    }
}

/// A map's grid in um and mm/s.
fn scaled_axes(m: &squeal_store::MapData, (l, v): (f64, f64)) -> (Vec<f64>, Vec<f64>) {
    (
        m.x0.iter().map(|x| x * l).collect(),
        m.v0.iter().map(|y| y * v).collect(),
    )
}

/// A panel of a physical scan drawn in um and mm/s: the grid `xs`, `vs` (from
/// [`scaled_axes`]), the overlays and markers scaled alike, the axes saying so.
fn to_si<'a>(p: &mut BasinPanel<'a>, xs: &'a [f64], vs: &'a [f64], (l, v): (f64, f64)) {
    p.x0 = xs;
    p.v0 = vs;
    for c in &mut p.overlays {
        c.xs.iter_mut().for_each(|x| *x *= l);
        c.ys.iter_mut().for_each(|y| *y *= v);
    }
    for m in &mut p.markers {
        m.x *= l;
        m.y *= v;
    }
    p.axis_labels = Some([
        "initial displacement x0 (um)".into(),
        "initial velocity x'0 (mm/s)".into(),
    ]);
}

/// A root attribute of a file, as text.
pub fn attr<'a>(info: &'a squeal_store::FileInfo, key: &str) -> Option<&'a str> {
    info.attrs
        .iter()
        .find(|(k, _)| k == key)
        .map(|(_, v)| v.as_str())
}

/// Output, threads and restart flags shared by `scan` and `atlas` (long jobs that write one
/// journalled file).
#[derive(clap::Args, Debug)]
pub struct RunArgs {
    /// Output file (.h5); default: the spec's output.path.
    #[arg(short = 'o', long)]
    pub out: Option<std::path::PathBuf>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Finish an interrupted run of the same spec.
    #[arg(long, conflicts_with = "force")]
    pub resume: bool,
    /// Overwrite an existing output (and discard an interrupted run).
    #[arg(long)]
    pub force: bool,
    /// No progress bar (and for `scan` no work estimate).
    #[arg(long)]
    pub quiet: bool,
    /// Run only shard K of N (1-based): its own file, joined later by `squeal merge`.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,
}

impl RunArgs {
    /// The command that finishes an interrupted run: `squeal CMD SPEC -o OUT --resume`
    /// (and its `--shard`).
    pub fn resume_command(&self, cmd: &str, spec: &Path, out: &Path) -> String {
        format!(
            "squeal {cmd} {} -o {} --resume{}",
            spec.display(),
            out.display(),
            self.shard
                .as_deref()
                .map(|s| format!(" --shard {s}"))
                .unwrap_or_default()
        )
    }

    /// Checks the flags before any computing and sets the worker threads: the output file
    /// (`--out`, else the spec's `default_out`; it must end in .h5) and the shard, if any.
    pub fn setup(
        &self,
        default_out: &Path,
    ) -> anyhow::Result<(PathBuf, Option<squeal_scan::Shard>)> {
        let out = self
            .out
            .clone()
            .unwrap_or_else(|| default_out.to_path_buf());
        if out.extension().and_then(|e| e.to_str()) != Some("h5") {
            bail!(
                "output {}: expected a file name ending in .h5",
                out.display()
            );
        }
        let shard = self
            .shard
            .as_deref()
            .map(|s| s.parse().with_context(|| format!("--shard {s}")))
            .transpose()?;
        if let Some(n) = self.threads {
            if n == 0 || n > 4096 {
                bail!("--threads {n}: expected 1..=4096");
            }
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build_global()
                .context("--threads")?;
        }
        Ok((out, shard))
    }
}

/// Basin stability of one map as JSON: per regime the share `p` of the computed cells, its
/// binomial `se`, the shares on the nested `2h` and `4h` sub-grids and the change
/// `p_h - p_2h` (the grid error bar); `n` is the number of computed cells.
pub fn basin_json(b: &squeal_scan::GridShares) -> serde_json::Value {
    let mut o = serde_json::Map::new();
    o.insert(
        "sampling".into(),
        if b.random { "random" } else { "grid" }.into(),
    );
    o.insert("n".into(), b.h.n.into());
    o.insert("n_2h".into(), b.h2.n.into());
    o.insert("n_4h".into(), b.h4.n.into());
    for (i, r) in squeal_scan::basin::REGIMES.iter().enumerate() {
        let s = b.h.shares[i];
        o.insert(
            r.name().into(),
            serde_json::json!({
                "count": s.count,
                "p": s.p,
                "se": s.se,
                "p_2h": b.h2.shares[i].p,
                "p_4h": b.h4.shares[i].p,
                "change": b.change(i),
            }),
        );
    }
    o.into()
}

/// Basin stability of one map in words: each decided regime's share, with its change from
/// the `2h` sub-grid.
pub fn basin_words(b: &squeal_scan::GridShares) -> String {
    let parts: Vec<String> = squeal_scan::basin::REGIMES
        .iter()
        .enumerate()
        .filter(|(i, r)| **r != squeal_core::Regime::Undecided || b.h.shares[*i].count > 0)
        .map(|(i, r)| {
            let s = b.h.shares[i];
            if b.random {
                format!("{} {:.4} +- {:.4}", r.name(), s.p, s.se)
            } else {
                format!(
                    "{} {:.4} (2h {:.4}, change {:+.4})",
                    r.name(),
                    s.p,
                    b.h2.shares[i].p,
                    b.change(i)
                )
            }
        })
        .collect();
    if b.random {
        format!(
            "basin stability of {} random samples (+- one standard error): {}",
            b.h.n,
            parts.join("  ")
        )
    } else {
        format!("basin stability of {} cells: {}", b.h.n, parts.join("  "))
    }
}

/// Longest run started without `--allow-long` (scans and atlases alike).
pub const LONG_RUN: f64 = 30.0 * 86_400.0;

/// A duration in the unit that reads best.
pub fn duration(secs: f64) -> String {
    if secs < 120.0 {
        format!("{secs:.0} s")
    } else if secs < 7200.0 {
        format!("{:.0} min", secs / 60.0)
    } else if secs < 2.0 * 86_400.0 {
        format!("{:.1} h", secs / 3600.0)
    } else {
        format!("{:.0} days", secs / 86_400.0)
    }
}

#[cfg(test)]
mod tests {
    use super::WorkMeter;
    use super::cycle_gaps;
    use squeal_plot::Glyph;

    #[test]
    fn time_left_weighs_each_maps_cells_by_their_cost() {
        // Two maps of 100 cells, the second 20 times dearer per cell (above a fold): after
        // the first map in 10 s, 20 times that is left, not as much again.
        let m = WorkMeter::weighted(vec![1.0, 20.0], &[100, 100]);
        for _ in 0..100 {
            m.add(0);
        }
        assert_eq!(m.done(), 100);
        assert!((m.left_seconds(10.0) - 200.0).abs() < 1e-9);
        // Unweighted, the same progress promises 10 s.
        let u = WorkMeter::uniform(200);
        for _ in 0..100 {
            u.add(0);
        }
        assert!((u.left_seconds(10.0) - 10.0).abs() < 1e-9);
        // A weight the pilot could not measure counts as the mean of the others.
        let m = WorkMeter::weighted(vec![2.0, f64::NAN, 4.0], &[100, 100, 100]);
        assert!((m.total - 900.0).abs() < 1e-9);
        // No estimate before the first second.
        assert_eq!(m.eta_words(0.5), "estimating");
    }

    /// Issue 21: a sweep's values without a cycle were one triangle whatever the map found.
    /// Counts are `[undecided, steady, stick, not computed]` per map (as `FileInfo::counts`).
    #[test]
    fn values_without_a_cycle_are_grouped_by_what_the_map_found() {
        let xs = [0.8, 1.0, 1.5, 2.0, 2.2];
        let counts = [
            [0, 0, 100, 0], // stick-slip only: the fixed point repels
            [3, 0, 97, 0],  // stick-slip and undecided cells: still no steady start
            [0, 40, 60, 0], // both basins (has a cycle: not among `missing`)
            [0, 100, 0, 0], // steady slip only: above the fold
            [10, 45, 45, 0],
        ];
        let missing = [0.8, 1.0, 2.0, 2.2];
        let gaps = cycle_gaps(&missing, &xs, &counts);
        let of = |g: Glyph| gaps.iter().find(|x| x.glyph == g).map(|x| x.xs.clone());
        assert_eq!(of(Glyph::TriangleUp), Some(vec![0.8, 1.0]));
        assert_eq!(of(Glyph::TriangleDown), Some(vec![2.0]));
        assert_eq!(of(Glyph::Diamond), Some(vec![2.2]));
        assert!(gaps[0].label.contains("every start squeals"));
        assert!(gaps[1].label.contains("no start squeals"));
    }
}
