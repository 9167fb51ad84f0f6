//! `squeal trajectory`: one run from `(x0, x'0)` to `t_end`, its samples, its phase plane and a
//! summary of where it ended.
//!
//! The run is integrated to `--t-end` whatever happens on the way, so the samples and the
//! phase plane show the whole run. The label ("steady slip", "stick-slip", "not yet settled")
//! comes from the classifier watching the same run (integrated once) with `t_max = t_end`:
//! its verdict is taken at its decision and the run goes on to `t_end`.
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
use squeal_core::{Classifier, Named, Sample, Samples, SolverKind, SolverStats, State, Stepper};
use squeal_plot::{Curve, Marker, Rgb};
use squeal_scan::trajectory::{Oscillation, Span, StickPhases};

use super::model::ModelArgs;

/// At most this many rows are kept in memory for `--out` and `--plot` (40 bytes each).
const MAX_ROWS: u64 = 20_000_000;
/// At most this many points are drawn in the phase plane (further decimated if more).
const MAX_PLOT_POINTS: usize = 200_000;

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

/// Model and run parameters, as printed and stored: the law, its own parameters by name
/// (`nu, lambda, tau, phi` or `xi, v_d, mu_d, mu_sd, v_0, mu_v`), then the run's settings.
struct RunParams {
    law: &'static str,
    named: Vec<Named>,
    dt: f64,
    solver: &'static str,
    scheme: &'static str,
    x0: f64,
    v0: f64,
    t_end: f64,
    every: u64,
}

impl Serialize for RunParams {
    fn serialize<S: serde::Serializer>(&self, ser: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = ser.serialize_map(None)?;
        m.serialize_entry("law", self.law)?;
        for n in &self.named {
            m.serialize_entry(n.name, &n.value)?;
        }
        m.serialize_entry("dt", &self.dt)?;
        m.serialize_entry("solver", self.solver)?;
        m.serialize_entry("scheme", self.scheme)?;
        m.serialize_entry("x0", &self.x0)?;
        m.serialize_entry("v0", &self.v0)?;
        m.serialize_entry("t_end", &self.t_end)?;
        m.serialize_entry("every", &self.every)?;
        m.end()
    }
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
    /// Time on stick-slip before the run settled, as a scan stores it per cell
    /// (`squeal_core::classify::t_squeal`; JSON has no infinity, so by kind).
    squeal: squeal_core::Squeal,
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
    /// Stick phases (laws with true stick only).
    #[serde(skip_serializing_if = "Option::is_none")]
    stick: Option<StickPhases>,
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
    /// A physical system (`--m ...`): the start, the end and the oscillation in SI units.
    #[serde(skip_serializing_if = "Option::is_none")]
    si: Option<serde_json::Value>,
}

/// The start, final state and final oscillation in SI units (lengths in m, velocities in
/// m/s, times in s, frequencies in Hz).
fn si_summary(s: &Summary, sc: &squeal_core::Scales) -> serde_json::Value {
    let f = &s.final_state;
    serde_json::json!({
        "x0_m": s.params.x0 * sc.length,
        "v0_m_per_s": s.params.v0 * sc.velocity,
        "t_end_s": s.params.t_end * sc.time,
        "final_t_s": f.t * sc.time,
        "final_x_m": f.x * sc.length,
        "final_v_m_per_s": f.v * sc.velocity,
        "fixed_point_x_m": s.fixed_point.x * sc.length,
        "frequency_hz": s.oscillation.omega.map(|w| sc.hz(w)),
        "amplitude_m_per_s": s.oscillation.amplitude.map(|r| r * sc.velocity),
        // Only a finite time on stick-slip has seconds (0 too); `classification.squeal`
        // says which kind it is.
        "t_squeal_s": match s.classification.squeal {
            squeal_core::Squeal::Never => Some(0.0),
            squeal_core::Squeal::Transient { t_squeal } => Some(t_squeal * sc.time),
            _ => None,
        },
        "length_unit_m": sc.length,
        "velocity_unit_m_per_s": sc.velocity,
        "time_unit_s": sc.time,
    })
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
    if args.t_end / stepper.dt() > squeal_scan::bounds::MAX_STEPS {
        bail!(
            "--t-end {:?} with --dt {:?}: {:.3e} steps, at most 1e10 (about 40 minutes at 250 ns \
             per step): lower --t-end or raise --dt",
            args.t_end,
            stepper.dt(),
            args.t_end / stepper.dt()
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

    // A physical system: --x0/--v0 are in m and m/s.
    let scales = args.model.physical()?.map(|ph| ph.scales());
    let ic = match scales {
        Some(s) => State {
            x: args.x0 / s.length,
            v: args.v0 / s.velocity,
        },
        None => State {
            x: args.x0,
            v: args.v0,
        },
    };
    let span = Span {
        ic,
        t_end: args.t_end,
        every: if keep { args.every } else { 0 },
    };
    let t = squeal_scan::trajectory::run(&stepper, &Classifier::default(), span, None);
    let fp = t.fixed_point;
    let cols = &t.samples;

    if let (Some(path), Some(format)) = (&args.out, format) {
        let written = match format {
            Format::Csv => write_csv(path, cols, args.force),
            Format::Hdf5 => squeal_store::write_run(
                path,
                args.force,
                &super::common::provenance(),
                &stepper,
                Span {
                    every: args.every,
                    ..span
                },
                &t,
            )
            .map_err(anyhow::Error::from),
        };
        written.with_context(|| format!("--out: cannot write {}", path.display()))?;
    }
    if let Some(path) = &args.plot {
        plot_phase_plane(path, cols, &stepper, ic, fp)
            .with_context(|| format!("--plot: cannot draw {}", path.display()))?;
    }

    let summary = Summary {
        squeal_version: env!("CARGO_PKG_VERSION"),
        params: run_params(&args, &stepper),
        steps: t.steps,
        fixed_point: fp,
        classification: Classification {
            regime: t.outcome.regime.name(),
            reason: t.outcome.reason.name(),
            t_decision: t.outcome.t_decision,
            squeal: squeal_core::Squeal::of(t.outcome.t_squeal),
        },
        final_state: t.final_state,
        oscillation: t.oscillation,
        stick: t.stick.clone(),
        stats: t.stats,
        max_residual: t.max_residual,
        unconverged_steps: t.unconverged_steps,
        first_unconverged_times: t.first_unconverged_times.clone(),
        rows: if keep { cols.len() as u64 } else { 0 },
        out: args.out.clone(),
        plot: args.plot.clone(),
        si: None,
    };
    let mut summary = summary;
    summary.params.x0 = ic.x;
    summary.params.v0 = ic.v;
    if let Some(sc) = scales {
        summary.si = Some(si_summary(&summary, &sc));
    }
    if args.json {
        let text = serde_json::to_string_pretty(&summary).context("cannot encode the summary")?;
        println!("{text}");
    } else {
        print_summary(&summary, stepper.solver().kind);
        if let Some(si) = &summary.si {
            println!("in SI units: {si}");
        }
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
        named: p.named(),
        dt: stepper.dt(),
        solver: stepper.solver().kind.name(),
        scheme: stepper.scheme().name(),
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

fn write_csv(path: &Path, cols: &Samples, force: bool) -> anyhow::Result<()> {
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

fn plot_phase_plane(
    path: &Path,
    cols: &Samples,
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
        &super::pictures::plot_params(p, stepper.dt()),
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
    let scale = squeal_plot::StateScale::of_law(p.law.name());
    squeal_plot::phase_plot(path, &title, scale, &curves, &markers)?;
    Ok(())
}

fn print_summary(s: &Summary, kind: SolverKind) {
    let p = &s.params;
    let named: Vec<String> = p
        .named
        .iter()
        .map(|n| format!("{}={}", n.name, n.value))
        .collect();
    println!(
        "run: {} {} dt={} solver={} scheme={} from (x0, x'0) = ({}, {}) to t = {} ({} steps)",
        p.law,
        named.join(" "),
        p.dt,
        p.solver,
        p.scheme,
        p.x0,
        p.v0,
        p.t_end,
        s.steps
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
    println!("squeal: {}", c.squeal.words());
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
    if let Some(sp) = &s.stick {
        let times = |v: &[f64]| {
            v.iter()
                .map(|t| format!("{t:.6}"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let last = |t: Option<f64>| t.map_or("none".to_string(), |t| format!("{t:.6}"));
        println!(
            "stick phases: {} onsets, {} breakaways, {} passages through zero slip without sticking; {} at the end",
            sp.onsets,
            sp.breakaways,
            sp.reversals,
            if sp.stuck_at_end { "stuck" } else { "slipping" }
        );
        if sp.onsets + sp.breakaways > 0 {
            println!(
                "  onsets at t = {}{}; last at t = {}",
                times(&sp.first_onsets),
                if sp.onsets as usize > sp.first_onsets.len() {
                    ", ..."
                } else {
                    ""
                },
                last(sp.last_onset)
            );
            println!(
                "  breakaways at t = {}{}; last at t = {}",
                times(&sp.first_breakaways),
                if sp.breakaways as usize > sp.first_breakaways.len() {
                    ", ..."
                } else {
                    ""
                },
                last(sp.last_breakaway)
            );
        }
    }
    let st = &s.stats;
    println!(
        "solver: solves={} evaluations={} newton_steps={} bisections={} expansions={} \
         multi_root={} discontinuities={} failures={} iterations={} unconverged={} sticks={} \
         bracket_fallbacks={}",
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
        st.sticks,
        st.fallbacks
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
