//! `squeal trajectory`: one run from `(x0, x'0)` to `t_end`, its samples, its phase plane and a
//! summary of where it ended.
//!
//! The run is integrated to `--t-end` whatever happens on the way, so the samples and the
//! phase plane show the whole run. The label ("steady slip", "stick-slip", "not yet settled")
//! is the one `squeal scan` and `classify` give the start
//! ([`squeal_scan::trajectory::run_in`]): decided at the start where the unstable cycle's
//! side decides it, else by the classifier watching the same run (integrated once) with
//! `t_max = t_end`, its verdict taken at its decision while the run goes on to `t_end`.
//!
//! The frequency of the final oscillation is `2 pi / (t_k - t_{k-1})` from the last two
//! crossings of the Poincare section `x = x*, x' > 0` (as in the classifier), absent if the
//! run crossed it fewer than twice.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, bail};
use squeal_core::{State, Stepper};
use squeal_scan::trajectory::{Sampling, Span, default_every};

use super::model::ModelArgs;
use super::out_files::{refuse_existing, write_csv};
use super::trajectory_report::{Classification, RunParams, Summary, print_summary, si_summary};

use squeal_scan::trajectory::MAX_ROWS;
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
    /// Write the samples to FILE: .csv (`#` lines with each column's units and the sampling,
    /// then the header t,x,v,a,force, and t_si,x_si,v_si in s, m, m/s for a physical system)
    /// or .h5 (datasets t, x, v, a, force, and t_si, x_si, v_si for a physical system, each
    /// with its units; the parameters and the sampling as attributes).
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
    /// Write every N-th step to --out and --plot (the first sample is always written).
    /// Default: at least 100 samples per natural period 2 pi, at most 100000 in all.
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    every: Option<u64>,
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

/// Runs `squeal trajectory`.
pub fn run(mut args: Args) -> anyhow::Result<ExitCode> {
    let stepper = args.model.stepper()?;
    // The stride: `--every N` as given, else one that suits the run (a bounded number of
    // samples per natural period and in all): every step wrote 46 MB for a six-second run.
    let sampling = match args.every {
        Some(_) => Sampling::Given,
        None => Sampling::Default,
    };
    let every = *args
        .every
        .get_or_insert_with(|| default_every(stepper.dt(), args.t_end));
    // A physical system: --x0/--v0 are in m and m/s.
    let physical = args.model.physical()?;
    let scales = physical.map(|ph| ph.scales());
    let given = State {
        x: args.x0,
        v: args.v0,
    };
    let ic = scales.map_or(given, |s| s.state(given));
    let si = scales.map(|s| (given, s));
    let (format, keep) = checked_outputs(&args, &stepper, ic, si)?;
    let span = Span {
        ic,
        t_end: args.t_end,
        every: if keep { every } else { 0 },
    };
    // The map's context (its section searched once, as `squeal classify` prepares it), so
    // the label is the one every path gives this start.
    let plan = args.model.plan(args.t_end, "--t-end")?;
    let ctx = squeal_scan::scanner::MapContext::prepare(&plan, 0)?;
    let t = squeal_scan::trajectory::run_in(&ctx, span, None);
    let fp = t.fixed_point;
    let cols = &t.samples;

    write_outputs(&args, &stepper, (format, span, sampling), &t)?;

    let summary = Summary {
        squeal_version: env!("CARGO_PKG_VERSION"),
        params: run_params(&args, &stepper),
        steps: t.steps,
        fixed_point: fp,
        steady_slip: squeal_core::SteadySlip::of(stepper.params()),
        classification: Classification::of(&t),
        final_state: t.final_state,
        oscillation: t.oscillation,
        lasting: t.lasting,
        validated: squeal_core::Validity::of(stepper.params()),
        stick: t.stick.clone(),
        stats: t.stats,
        max_residual: t.max_residual,
        unconverged_steps: t.unconverged_steps,
        first_unconverged_times: t.first_unconverged_times.clone(),
        rules_withdrawn: ctx.withdrawn.iter().map(|w| w.why.clone()).collect(),
        rows: if keep { cols.len() as u64 } else { 0 },
        out: args.out.clone(),
        plot: args.plot.clone(),
        sampling: keep.then(|| sampling.words(every, stepper.dt())),
        si: None,
    };
    let mut summary = summary;
    summary.params.x0 = ic.x;
    summary.params.v0 = ic.v;
    if let Some(ph) = physical {
        summary.si = Some(si_summary(&summary, &ph));
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

/// The run's flags checked before any computing: the start, the end, the decimation and
/// the output files (refused if present without `--force`); the `--out` format and whether
/// samples are kept.
fn checked_outputs(
    args: &Args,
    stepper: &Stepper,
    ic: State,
    si: Option<(State, squeal_core::Scales)>,
) -> anyhow::Result<(Option<Format>, bool)> {
    // The library's checks of a run (the Python `squeal.trajectory` makes the same), the
    // start in the model's units: `--x0 1e6` metres was 7e9 units for a 2 kg brake.
    let inv = super::physical::start_invalid("command line".into(), si);
    let every = args.every.unwrap_or(1);
    let span = Span {
        ic,
        t_end: args.t_end,
        every,
    };
    span.check(stepper.dt(), ["--x0", "--v0", "--t-end"], &inv)?;
    if every == 0 {
        bail!("--every: invalid every = 0: expected a decimation factor >= 1");
    }
    let steps = (args.t_end / stepper.dt()).ceil() as u64;
    let keep = args.out.is_some() || args.plot.is_some();
    let rows = steps / every + 1;
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
    Ok((format, keep))
}

/// The samples to `--out` (CSV or HDF5) and the phase plane to `--plot`, as asked.
fn write_outputs(
    args: &Args,
    stepper: &Stepper,
    (format, span, sampling): (Option<Format>, Span, Sampling),
    t: &squeal_scan::trajectory::Trajectory,
) -> anyhow::Result<()> {
    let cols = &t.samples;
    if let (Some(path), Some(format)) = (&args.out, format) {
        let every = args.every.unwrap_or(1);
        let physical = args.model.physical()?;
        let written = match format {
            Format::Csv => {
                let notes = [
                    format!(
                        "squeal {} trajectory, law {}",
                        env!("CARGO_PKG_VERSION"),
                        stepper.params().kind().name()
                    ),
                    format!("sampling: {}", sampling.words(every, stepper.dt())),
                ];
                let scales = physical.as_ref().map(|ph| ph.scales());
                write_csv(path, cols, args.force, (&notes, scales.as_ref()))
            }
            Format::Hdf5 => squeal_store::write_run_sampled(
                path,
                args.force,
                &super::common::provenance(),
                stepper,
                (Span { every, ..span }, sampling),
                t,
                physical.as_ref(),
            )
            .map_err(anyhow::Error::from),
        };
        written.with_context(|| format!("--out: cannot write {}", path.display()))?;
    }
    if let Some(path) = &args.plot {
        let t_end = *cols.t.last().unwrap_or(&0.0);
        let (ic, fp) = (span.ic, t.fixed_point);
        let model = super::pictures::plot_params(stepper.params(), stepper.dt());
        // A physical system's run in metres, m/s and seconds, the system in the title.
        let system = args.model.physical()?;
        let line = system.as_ref().map(super::pictures::physical_system_line);
        let si = (system.as_ref().zip(line.as_deref()))
            .map(|(ph, line)| (super::pictures::si_state(&ph.scales()), line));
        squeal_plot::trajectory_plot(
            path,
            (&cols.x, &cols.v),
            t_end,
            ((ic.x, ic.v), (fp.x, fp.v)),
            (&model, si),
        )
        .with_context(|| format!("--plot: cannot draw {}", path.display()))?;
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
        every: args.every.unwrap_or(1),
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
