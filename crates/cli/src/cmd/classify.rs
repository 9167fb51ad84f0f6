//! `squeal classify --ics FILE.csv --out FILE.csv`: labels for arbitrary initial conditions.

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, bail};
use rayon::prelude::*;
use squeal_core::State;
use squeal_scan::scanner::MapContext;

use super::{common, model::SetupArgs, progress};

/// Flags of `squeal classify`.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    pub setup: SetupArgs,
    /// Initial conditions: CSV with a header holding columns x0 and v0 (in m and m/s for a
    /// physical system: --m ... or a spec with [physical]).
    #[arg(long)]
    pub ics: PathBuf,
    /// Labels: CSV with columns x0,v0,label and the diagnostics.
    #[arg(long)]
    pub out: PathBuf,
    /// Overwrite an existing output.
    #[arg(long)]
    pub force: bool,
    /// No estimate or progress on stderr.
    #[arg(long)]
    pub quiet: bool,
    /// Start a run estimated to take more than 30 days.
    #[arg(long)]
    pub allow_long: bool,
}

/// Largest initial-conditions file read: 1 GiB, some 25 million rows of two numbers written
/// in full (about 40 bytes a row). `--ics /dev/zero` was read until memory ran out.
const MAX_ICS_BYTES: u64 = 1 << 30;

/// The initial conditions of the file and the line each is on.
fn read_ics(path: &PathBuf) -> anyhow::Result<Vec<(usize, State)>> {
    use std::io::Read;
    // A FIFO blocked the read for ever, and `/dev/zero` was read for 2 s (a GiB) before
    // being refused: only a regular file is read.
    super::out_files::regular("--ics", path)?;
    let reading = || format!("reading {}", path.display());
    let mut text = String::new();
    std::fs::File::open(path)
        .with_context(reading)?
        .take(MAX_ICS_BYTES + 1)
        .read_to_string(&mut text)
        .with_context(reading)?;
    if text.len() as u64 > MAX_ICS_BYTES {
        bail!(
            "{}: longer than 1 GiB (about 25 million initial conditions): not an initial \
             conditions file, or split it",
            path.display()
        );
    }
    // A byte-order mark (spreadsheets write one) is not part of the first column's name.
    let text = text.strip_prefix('\u{feff}').unwrap_or(&text);
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let (_, header) = lines
        .next()
        .with_context(|| format!("{}: empty file", path.display()))?;
    let cols: Vec<&str> = header.split(',').map(str::trim).collect();
    let find = |name: &str| {
        cols.iter().position(|c| *c == name).with_context(|| {
            format!(
                "{}: no column `{name}` in the header `{header}`",
                path.display()
            )
        })
    };
    let (ix, iv) = (find("x0")?, find("v0")?);
    let mut out = Vec::new();
    for (n, line) in lines {
        let at = format!("{}:{}", path.display(), n + 1);
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        // A row of more values than the header's columns had its extra ones dropped
        // without a word (a friction CSV's row of three numbers is refused).
        if f.len() != cols.len() {
            bail!(
                "{at}: `{}` holds {} value(s) where the header `{header}` names {} column(s)",
                line.trim(),
                f.len(),
                cols.len()
            );
        }
        let state = State {
            x: ic_value(&at, &f, (ix, "x0"))?,
            v: ic_value(&at, &f, (iv, "v0"))?,
        };
        out.push((n + 1, state));
    }
    Ok(out)
}

/// The number in column `i` (named `name`) of the fields `f` of the line `at`.
fn ic_value(at: &str, f: &[&str], (i, name): (usize, &str)) -> anyhow::Result<f64> {
    let s = f
        .get(i)
        .with_context(|| format!("{at}: missing `{name}`"))?;
    let v: f64 = s
        .parse()
        .with_context(|| format!("{at}: `{name}` = `{s}` is not a number"))?;
    if !v.is_finite() {
        bail!("{at}: `{name}` = {v} is not finite");
    }
    Ok(v)
}

/// A start within the classifier's escape radius, in the model's units: a start at
/// `x0 = 1e300` was labelled stick-slip by the start rule (outside the cycle) with no run.
fn check_start(
    path: &std::path::Path,
    line: usize,
    s: State,
    si: Option<(State, squeal_core::Scales)>,
) -> anyhow::Result<()> {
    let inv = super::physical::start_invalid(format!("{}:{line}", path.display()), si);
    squeal_scan::bounds::state("x0", s.x, &inv)?;
    squeal_scan::bounds::state("v0", s.v, &inv)?;
    Ok(())
}

/// The work, estimated at the documented rates before anything runs (the map's cycle
/// search at its longest, each start up to its run to `t_max`: a file of many rows with a
/// long `t_max` ran with no word), printed unless quiet; over [`squeal_scan::estimate::LONG_RUN`] it needs
/// `--allow-long`.
fn estimate(args: &Args, plan: &squeal_scan::Plan, starts: usize) -> anyhow::Result<()> {
    let threads = rayon::current_num_threads();
    let secs =
        squeal_scan::estimate::prepare_seconds(plan) + plan.estimate_seconds(starts, threads);
    if squeal_scan::estimate::refused_as_long(secs, args.allow_long) {
        bail!(
            "{starts} initial conditions would take roughly {} on {threads} thread(s) at the documented rate (t_max = {}, the cycle search included): split {}, shorten t_max, or pass --allow-long",
            common::duration(secs),
            squeal_core::error::Number(plan.map.classifier.t_max),
            args.ics.display()
        );
    }
    if !args.quiet {
        eprintln!(
            "squeal: {starts} initial conditions on {threads} thread(s): roughly {} ({secs:.1} s) at the documented rate",
            common::duration(secs)
        );
    }
    Ok(())
}

/// Labels the initial conditions.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let setup = args.setup.setup()?;
    super::out_files::regular("--out", &args.out)?;
    let lines = read_ics(&args.ics)?;
    // A physical system: the file's x0, v0 are in m and m/s (written back as given).
    let scales = setup.plan.physical().map(|ph| ph.scales());
    let mut given = Vec::with_capacity(lines.len());
    let mut ics = Vec::with_capacity(lines.len());
    for &(line, ic) in &lines {
        let state = scales.map_or(ic, |s| s.state(ic));
        check_start(&args.ics, line, state, scales.map(|s| (ic, s)))?;
        given.push(ic);
        ics.push(state);
    }
    if args.out.extension().is_some_and(|e| e == "h5") {
        bail!(
            "--out {}: classify writes CSV text; use a name ending in .csv (an .h5 name would hold CSV)",
            args.out.display()
        );
    }
    common::check_new(&args.out, args.force, "labels")?;
    if let Some(w) = squeal_core::Validity::of(&setup.plan.maps[setup.map]).warning() {
        eprintln!("{w}");
    }
    estimate(&args, &setup.plan, ics.len())?;
    let ctx = MapContext::prepare(&setup.plan, setup.map)?;
    for w in &ctx.withdrawn {
        eprintln!(
            "squeal: rule withdrawn for this model, its starts decided by runs: {}",
            w.why
        );
    }
    let total = ics.len() as u64;
    let bar = progress::bar(
        total,
        args.quiet,
        "classify [{bar:40}] {pos}/{len} initial conditions  {avg_rate}  ETA {avg_eta}",
        "start",
    );
    let plain = progress::PlainLines::new("initial conditions", "start", total, args.quiet);
    let outcomes: Vec<_> = ics
        .par_iter()
        .map(|&ic| {
            let o = ctx.classify(ic);
            bar.inc(1);
            if let Some(p) = &plain {
                p.inc(0);
            }
            o
        })
        .collect();
    bar.finish_and_clear();
    let mut w = std::io::BufWriter::new(
        std::fs::File::create(&args.out)
            .with_context(|| format!("creating {}", args.out.display()))?,
    );
    // The columns are the scan file's (squeal_scan::cell::COLUMNS), in the same order.
    let header: Vec<&str> = squeal_scan::COLUMNS.iter().map(|c| c.name).collect();
    writeln!(w, "x0,v0,{}", header.join(","))?;
    let mut counts = [0usize; squeal_core::Regime::ALL.len()];
    for (ic, o) in given.iter().zip(&outcomes) {
        counts[o.regime as usize] += 1;
        let cell = squeal_scan::Cell::from(o);
        let cols: Vec<String> = squeal_scan::COLUMNS.iter().map(|c| c.text(&cell)).collect();
        writeln!(w, "{:?},{:?},{}", ic.x, ic.v, cols.join(","))?;
    }
    w.flush()?;
    eprintln!("{} -> {}", counts_words(&counts), args.out.display());
    Ok(ExitCode::SUCCESS)
}

/// "N initial conditions: steady_slip A, stick_slip B, undecided C" (and the slip
/// oscillation's count where there is one), from counts indexed by the regime's value.
fn counts_words(counts: &[usize]) -> String {
    let slip = match counts[squeal_core::Regime::SlipOscillation as usize] {
        0 => String::new(),
        n => format!(", slip_oscillation {n}"),
    };
    format!(
        "{} initial conditions: steady_slip {}, stick_slip {}, undecided {}{slip}",
        counts.iter().sum::<usize>(),
        counts[1],
        counts[2],
        counts[0]
    )
}
