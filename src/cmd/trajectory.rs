//! `squeal trajectory`: one run from `(x0, x'0)` to `t_end`, its samples, its phase plane and a
//! summary of where it ended.
//!
//! The run is integrated to `--t-end` whatever happens on the way, so the samples and the
//! phase plane show the whole run. The label ("steady slip", "stick-slip", "not yet settled")
//! comes from [`Classifier::classify`] on the same run with `t_max = t_end`: the classifier
//! stops at its decision, and the two runs are the same step by step (the stepper is
//! deterministic), so the label is that of the samples written.
//!
//! The frequency of the final oscillation is `2 pi / (t_k - t_{k-1})` from the last two
//! crossings of the Poincare section `x = x*, x' > 0` (as in the classifier), absent if the
//! run crossed it fewer than twice.

use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, bail};
use serde::Serialize;
use squeal_core::classify::crossing;
use squeal_core::{Classifier, Sample, SolverKind, SolverStats, State, Stepper};
use squeal_plot::{Curve, Marker, Rgb};

use super::model::ModelArgs;

/// At most this many rows are kept in memory for `--out` and `--plot` (40 bytes each).
const MAX_ROWS: u64 = 20_000_000;
/// At most this many points are drawn in the phase plane (further decimated if more).
const MAX_PLOT_POINTS: usize = 200_000;
/// How many times of unconverged paper-iteration steps are reported.
const FIRST_UNCONVERGED: usize = 5;

/// Flags of `squeal trajectory`.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    model: ModelArgs,
    /// Initial displacement x(0).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    x0: f64,
    /// Initial velocity x'(0).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    v0: f64,
    /// End time of the run (nondimensional; the unforced period is 2 pi).
    #[arg(long, default_value_t = 1000.0, allow_negative_numbers = true)]
    t_end: f64,
    /// Write the samples to FILE: .csv (header t,x,v,a,force) or .h5 (datasets t, x, v, a,
    /// force with the parameters as attributes).
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
    /// Write every N-th sample to --out and --plot (the first sample is always written).
    #[arg(
        long,
        value_name = "N",
        default_value_t = 1,
        allow_negative_numbers = true
    )]
    every: u64,
    /// Draw the phase plane (x against x') with the fixed point marked to FILE.png.
    #[arg(long, value_name = "FILE")]
    plot: Option<PathBuf>,
    /// Overwrite existing output files.
    #[arg(long)]
    force: bool,
    /// Print the summary as one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// Output formats of `--out`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Csv,
    Hdf5,
}

/// The samples kept for output, column by column.
#[derive(Default)]
struct Columns {
    t: Vec<f64>,
    x: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    force: Vec<f64>,
}

impl Columns {
    fn push(&mut self, s: &Sample) {
        self.t.push(s.t);
        self.x.push(s.x);
        self.v.push(s.v);
        self.a.push(s.a);
        self.force.push(s.force);
    }

    fn len(&self) -> usize {
        self.t.len()
    }
}

/// Model and run parameters, as printed and stored.
#[derive(Serialize)]
struct RunParams {
    law: &'static str,
    nu: f64,
    lambda: f64,
    tau: f64,
    phi: f64,
    dt: f64,
    solver: &'static str,
    x0: f64,
    v0: f64,
    t_end: f64,
    every: u64,
}

/// The classifier's verdict on the same run.
#[derive(Serialize)]
struct Classification {
    /// `steady_slip`, `stick_slip` or `undecided`.
    regime: &'static str,
    /// Why the classifier stopped.
    reason: &'static str,
    /// Time of the decision (`t_end` if undecided by the time limit).
    t_decision: f64,
}

/// The final oscillation, from the last section crossings.
#[derive(Serialize)]
struct Oscillation {
    /// Section crossings over the whole run.
    crossings: u64,
    /// `2 pi / (t_k - t_{k-1})` of the last two crossings; `null` if fewer than two.
    omega: Option<f64>,
    /// `x'` at the last crossing; `null` if none.
    amplitude: Option<f64>,
    /// Time of the last crossing; `null` if none.
    t_last_crossing: Option<f64>,
}

/// Everything `squeal trajectory` reports.
#[derive(Serialize)]
struct Summary {
    squeal_version: &'static str,
    params: RunParams,
    steps: u64,
    fixed_point: State,
    classification: Classification,
    final_state: Sample,
    oscillation: Oscillation,
    stats: SolverStats,
    max_residual: f64,
    /// Steps (including the initial solve) whose solve did not converge: the paper's
    /// iteration hitting its cap, or a robust failure.
    unconverged_steps: u64,
    /// Times of the first few of them.
    first_unconverged_times: Vec<f64>,
    /// Rows written to `--out` (and drawn, before any further decimation, in `--plot`).
    rows: u64,
    out: Option<PathBuf>,
    plot: Option<PathBuf>,
}

/// Runs `squeal trajectory`.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let stepper = args.model.stepper()?;
    check_finite("--x0", args.x0)?;
    check_finite("--v0", args.v0)?;
    if !args.t_end.is_finite() || args.t_end <= 0.0 {
        bail!(
            "--t-end: invalid t_end = {}: expected a finite time > 0",
            args.t_end
        );
    }
    if args.every == 0 {
        bail!("--every: invalid every = 0: expected a decimation factor >= 1");
    }
    let steps = (args.t_end / stepper.dt()).ceil() as u64;
    let keep = args.out.is_some() || args.plot.is_some();
    let rows = steps / args.every + 1;
    if keep && rows > MAX_ROWS {
        bail!(
            "--every: {rows} samples would be kept for --out/--plot (at most {MAX_ROWS}): \
             raise --every or lower --t-end"
        );
    }
    let format = match &args.out {
        Some(path) => {
            let format = out_format(path)?;
            refuse_existing("--out", path, args.force)?;
            Some(format)
        }
        None => None,
    };
    if let Some(path) = &args.plot {
        if path.extension().and_then(|e| e.to_str()) != Some("png") {
            bail!(
                "--plot: '{}' has no .png extension (the phase plane is drawn as PNG)",
                path.display()
            );
        }
        refuse_existing("--plot", path, args.force)?;
    }

    let ic = State {
        x: args.x0,
        v: args.v0,
    };
    let p = *stepper.params();
    let fp = p.fixed_point();
    let mut cols = Columns::default();
    let mut stats = SolverStats::default();
    let (mut s, sol) = stepper.initial(ic, &mut stats);
    let mut max_residual = sol.residual;
    let mut unconverged_times = Vec::new();
    let mut unconverged = 0u64;
    if !sol.converged {
        unconverged += 1;
        unconverged_times.push(0.0);
    }
    if keep {
        cols.push(&s);
    }
    let mut crossings = 0u64;
    let (mut t_prev_cross, mut t_last_cross, mut amplitude) = (f64::NAN, f64::NAN, f64::NAN);
    for k in 1..=steps {
        let (mut n, sol) = stepper.step(&s, &mut stats);
        // Time by index, not by accumulated addition.
        n.t = k as f64 * stepper.dt();
        max_residual = max_residual.max(sol.residual);
        if !sol.converged {
            unconverged += 1;
            if unconverged_times.len() < FIRST_UNCONVERGED {
                unconverged_times.push(n.t);
            }
        }
        if let Some(c) = crossing(fp.x, &s, &n) {
            crossings += 1;
            t_prev_cross = t_last_cross;
            t_last_cross = c.t;
            amplitude = c.r;
        }
        if keep && k % args.every == 0 {
            cols.push(&n);
        }
        s = n;
        if !s.x.is_finite() || !s.v.is_finite() {
            break;
        }
    }
    let steps_taken = (s.t / stepper.dt()).round() as u64;

    let classifier = Classifier {
        t_max: args.t_end,
        ..Default::default()
    };
    let outcome = classifier.classify(&stepper, ic);
    let finite = |x: f64| x.is_finite().then_some(x);

    if let (Some(path), Some(format)) = (&args.out, format) {
        let written = match format {
            Format::Csv => write_csv(path, &cols, args.force),
            Format::Hdf5 => write_h5(path, &cols, &run_params(&args, &stepper), args.force),
        };
        written.with_context(|| format!("--out: cannot write {}", path.display()))?;
    }
    if let Some(path) = &args.plot {
        plot_phase_plane(path, &cols, &stepper, ic, fp)
            .with_context(|| format!("--plot: cannot draw {}", path.display()))?;
    }

    let summary = Summary {
        squeal_version: env!("CARGO_PKG_VERSION"),
        params: run_params(&args, &stepper),
        steps: steps_taken,
        fixed_point: fp,
        classification: Classification {
            regime: outcome.regime.name(),
            reason: outcome.reason.name(),
            t_decision: outcome.t_decision,
        },
        final_state: s,
        oscillation: Oscillation {
            crossings,
            omega: finite(std::f64::consts::TAU / (t_last_cross - t_prev_cross)),
            amplitude: finite(amplitude),
            t_last_crossing: finite(t_last_cross),
        },
        stats,
        max_residual,
        unconverged_steps: unconverged,
        first_unconverged_times: unconverged_times,
        rows: if keep { cols.len() as u64 } else { 0 },
        out: args.out.clone(),
        plot: args.plot.clone(),
    };
    if args.json {
        let text = serde_json::to_string_pretty(&summary).context("cannot encode the summary")?;
        println!("{text}");
    } else {
        print_summary(&summary, stepper.solver().kind);
    }
    Ok(ExitCode::SUCCESS)
}

fn check_finite(flag: &str, value: f64) -> anyhow::Result<()> {
    if !value.is_finite() || value.abs() > 1e6 {
        bail!("{flag}: invalid value {value}: expected a finite number with |value| <= 1e6");
    }
    Ok(())
}

fn run_params(args: &Args, stepper: &Stepper) -> RunParams {
    let p = stepper.params();
    RunParams {
        law: p.law.name(),
        nu: p.nu,
        lambda: p.lambda,
        tau: p.tau,
        phi: p.phi,
        dt: stepper.dt(),
        solver: stepper.solver().kind.name(),
        x0: args.x0,
        v0: args.v0,
        t_end: args.t_end,
        every: args.every,
    }
}

/// The format from the file name's extension.
fn out_format(path: &Path) -> anyhow::Result<Format> {
    match path.extension().and_then(|e| e.to_str()) {
        Some("csv") => Ok(Format::Csv),
        Some("h5" | "hdf5") => Ok(Format::Hdf5),
        Some(other) => bail!(
            "--out: unknown extension '.{other}' of '{}': expected .csv or .h5",
            path.display()
        ),
        None => bail!(
            "--out: '{}' has no extension: expected .csv or .h5",
            path.display()
        ),
    }
}

/// Refuses to overwrite `path` unless `force`.
pub(crate) fn refuse_existing(flag: &str, path: &Path, force: bool) -> anyhow::Result<()> {
    if !force && path.exists() {
        bail!(
            "{flag}: '{}' exists (use --force to overwrite it)",
            path.display()
        );
    }
    Ok(())
}

/// Opens `path` for writing; without `force` it must not exist (checked atomically).
pub(crate) fn create_file(path: &Path, force: bool) -> std::io::Result<File> {
    let mut o = OpenOptions::new();
    o.write(true);
    if force {
        o.create(true).truncate(true);
    } else {
        o.create_new(true);
    }
    o.open(path)
}

fn write_csv(path: &Path, cols: &Columns, force: bool) -> anyhow::Result<()> {
    let mut w = BufWriter::new(create_file(path, force)?);
    writeln!(w, "t,x,v,a,force")?;
    for i in 0..cols.len() {
        writeln!(
            w,
            "{},{},{},{},{}",
            cols.t[i], cols.x[i], cols.v[i], cols.a[i], cols.force[i]
        )?;
    }
    w.into_inner().map_err(|e| e.into_error())?.sync_all()?;
    Ok(())
}

fn write_h5(path: &Path, cols: &Columns, rp: &RunParams, force: bool) -> anyhow::Result<()> {
    use hdf5::types::VarLenUnicode;
    let file = if force {
        hdf5::File::create(path)?
    } else {
        hdf5::File::create_excl(path)?
    };
    for (name, data) in [
        ("t", &cols.t),
        ("x", &cols.x),
        ("v", &cols.v),
        ("a", &cols.a),
        ("force", &cols.force),
    ] {
        file.new_dataset_builder()
            .with_data(data.as_slice())
            .create(name)
            .with_context(|| format!("dataset {name}"))?;
    }
    let text = |name: &str, value: &str| -> anyhow::Result<()> {
        let value: VarLenUnicode = value.parse().with_context(|| format!("attribute {name}"))?;
        file.new_attr::<VarLenUnicode>()
            .shape(())
            .create(name)?
            .write_scalar(&value)?;
        Ok(())
    };
    text("squeal_version", env!("CARGO_PKG_VERSION"))?;
    text("law", rp.law)?;
    text("solver", rp.solver)?;
    for (name, value) in [
        ("nu", rp.nu),
        ("lambda", rp.lambda),
        ("tau", rp.tau),
        ("phi", rp.phi),
        ("dt", rp.dt),
        ("x0", rp.x0),
        ("v0", rp.v0),
        ("t_end", rp.t_end),
    ] {
        file.new_attr::<f64>()
            .shape(())
            .create(name)?
            .write_scalar(&value)?;
    }
    file.new_attr::<u64>()
        .shape(())
        .create("every")?
        .write_scalar(&rp.every)?;
    file.close()?;
    Ok(())
}

fn plot_phase_plane(
    path: &Path,
    cols: &Columns,
    stepper: &Stepper,
    ic: State,
    fp: State,
) -> anyhow::Result<()> {
    let stride = cols.len().div_ceil(MAX_PLOT_POINTS).max(1);
    let (mut xs, mut ys): (Vec<f64>, Vec<f64>) = cols
        .x
        .iter()
        .zip(&cols.v)
        .step_by(stride)
        .map(|(x, v)| (*x, *v))
        .unzip();
    if let (Some(x), Some(v)) = (cols.x.last(), cols.v.last()) {
        xs.push(*x);
        ys.push(*v);
    }
    let p = stepper.params();
    let title = squeal_plot::phase_title(
        &format!(
            "Trajectory from (x0, x'0) = ({}, {})",
            squeal_plot::fmt_number(ic.x),
            squeal_plot::fmt_number(ic.v)
        ),
        &squeal_plot::ModelParams {
            law: p.law.name().into(),
            nu: p.nu,
            lambda: p.lambda,
            tau: p.tau,
            phi: p.phi,
            dt: stepper.dt(),
        },
    );
    let curves = [Curve {
        label: format!("trajectory, t in [0, {}]", cols.t.last().unwrap_or(&0.0)),
        xs,
        ys,
        color: Rgb(49, 110, 198),
        points_only: false,
    }];
    let markers = [
        Marker {
            label: format!("fixed point ({}, 0)", fp.x),
            x: fp.x,
            y: fp.v,
            color: squeal_plot::FIXED_POINT,
        },
        Marker {
            label: "start".to_string(),
            x: ic.x,
            y: ic.v,
            color: Rgb(238, 118, 22),
        },
    ];
    squeal_plot::phase_plot(path, &title, &curves, &markers)?;
    Ok(())
}

fn print_summary(s: &Summary, kind: SolverKind) {
    let p = &s.params;
    println!(
        "run: {} nu={} lambda={} tau={} phi={} dt={} solver={} from (x0, x'0) = ({}, {}) to t = {} ({} steps)",
        p.law, p.nu, p.lambda, p.tau, p.phi, p.dt, p.solver, p.x0, p.v0, p.t_end, s.steps
    );
    let c = &s.classification;
    let label = match c.regime {
        "steady_slip" => "steady slip",
        "stick_slip" => "stick-slip",
        _ => "not yet settled",
    };
    println!(
        "ended: {label} (classifier: {}, {} at t = {:.6})",
        c.regime, c.reason, c.t_decision
    );
    let f = &s.final_state;
    println!(
        "final state: t = {} x = {:.9} x' = {:.9} x'' = {:.9} F = {:.9}",
        f.t, f.x, f.v, f.a, f.force
    );
    let o = &s.oscillation;
    match (o.omega, o.amplitude) {
        (Some(w), Some(r)) => println!(
            "final oscillation: omega = {w:.6} (last revolution), section amplitude x' = {r:.6} \
             at t = {:.4}, {} crossings of x = {}",
            o.t_last_crossing.unwrap_or(f64::NAN),
            o.crossings,
            s.fixed_point.x
        ),
        _ => println!(
            "final oscillation: none ({} crossings of x = {}, x' > 0)",
            o.crossings, s.fixed_point.x
        ),
    }
    let st = &s.stats;
    println!(
        "solver: solves={} evaluations={} newton_steps={} bisections={} expansions={} \
         multi_root={} discontinuities={} failures={} iterations={} unconverged={} sticks={}",
        st.solves,
        st.evaluations,
        st.newton_steps,
        st.bisections,
        st.expansions,
        st.multi_root,
        st.discontinuities,
        st.failures,
        st.iterations,
        st.unconverged,
        st.sticks
    );
    println!("max residual |G(F)| = {:.3e}", s.max_residual);
    if kind == SolverKind::Paper || s.unconverged_steps > 0 {
        let times: Vec<String> = s
            .first_unconverged_times
            .iter()
            .map(|t| format!("{}", (t * 1e9).round() / 1e9))
            .collect();
        println!(
            "unconverged steps: {} of {} ({:.2}%){}",
            s.unconverged_steps,
            st.solves,
            100.0 * s.unconverged_steps as f64 / st.solves.max(1) as f64,
            if times.is_empty() {
                String::new()
            } else {
                format!(", first at t = {}", times.join(", "))
            }
        );
    }
    if let Some(out) = &s.out {
        println!("wrote {} ({} rows)", out.display(), s.rows);
    }
    if let Some(plot) = &s.plot {
        println!("wrote {}", plot.display());
    }
}
