//! `squeal critical`: the damping above which a given state no longer squeals.

use std::process::ExitCode;

use anyhow::bail;
use squeal_core::State;
use squeal_scan::ulc::{self, CycleSettings};

use super::model::SetupArgs;

/// Flags of `squeal critical`.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    pub setup: SetupArgs,
    /// The state that must lie inside the cycle: x.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub x0: f64,
    /// ... and x'.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub v0: f64,
    /// Lower end of the bracket in nu (cycle must not enclose the state there).
    #[arg(long, default_value_t = 1e-3)]
    pub nu_lo: f64,
    /// Upper end (cycle must enclose the state there).
    #[arg(long, default_value_t = 5e-2)]
    pub nu_hi: f64,
    /// Relative width of the final bracket.
    #[arg(long, default_value_t = 1e-4)]
    pub rtol: f64,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Find the fold of cycles instead: the damping above which no start squeals.
    #[arg(long)]
    pub fold: bool,
}

/// Bisects in nu.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let setup = args.setup.setup()?;
    let plan = &setup.plan;
    if !(args.x0.is_finite() && args.v0.is_finite()) {
        bail!("--x0/--v0: expected finite values");
    }
    if !(args.rtol > 0.0 && args.rtol < 1.0) {
        bail!("--rtol {}: expected a value in (0, 1)", args.rtol);
    }
    let t0 = std::time::Instant::now();
    let point = State {
        x: args.x0,
        v: args.v0,
    };
    if args.fold {
        return fold(&args, plan, setup.map, t0);
    }
    let cs = CycleSettings::default();
    let rep = ulc::critical_nu(
        plan.maps[setup.map],
        plan.dt,
        plan.solver,
        &cs,
        point,
        args.nu_lo,
        args.nu_hi,
        args.rtol,
    )
    .map_err(|e| {
        let bracket = matches!(e, squeal_scan::ScanError::Bracket { .. });
        let e = anyhow::Error::new(e);
        if bracket {
            e.context("--nu-lo / --nu-hi")
        } else {
            e
        }
    })?;
    let seconds = t0.elapsed().as_secs_f64();
    if args.json {
        let mut v = serde_json::to_value(&rep)?;
        v["seconds"] = seconds.into();
        println!("{}", serde_json::to_string(&v)?);
    } else {
        println!(
            "critical damping for ({}, {}): {} = {:.6e}, bracket [{:.6e}, {:.6e}] ({} cycle locations, {:.2} s)",
            point.x,
            point.v,
            plan.maps[setup.map].damping_key(),
            rep.nu,
            rep.bracket[0],
            rep.bracket[1],
            rep.evaluations,
            seconds
        );
        println!(
            "  below it the unstable cycle leaves ({}, {}) outside: that start squeals; above it, steady slip",
            point.x, point.v
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// `--fold`: bisects in nu for the fold of cycles (crate `squeal_scan::atlas::boundary`).
fn fold(
    args: &Args,
    plan: &squeal_scan::Plan,
    map: usize,
    t0: std::time::Instant,
) -> anyhow::Result<ExitCode> {
    use squeal_scan::atlas::{BoundaryStatus, PointSettings, boundary};
    let b = boundary::fold_nu(
        plan.maps[map],
        plan.dt,
        plan.solver,
        &PointSettings::default(),
        args.nu_lo,
        args.nu_hi,
        args.rtol,
    )?;
    let seconds = t0.elapsed().as_secs_f64();
    if args.json {
        let mut v = serde_json::to_value(b)?;
        v["seconds"] = seconds.into();
        println!("{}", serde_json::to_string(&v)?);
        return Ok(ExitCode::SUCCESS);
    }
    match b.status {
        BoundaryStatus::Found => println!(
            "fold of cycles: nu = {:.6e}, bracket [{:.6e}, {:.6e}] ({} evaluations, {:.2} s)\n  below it a stick-slip oscillation exists beside steady slip; above it no start squeals",
            b.nu, b.bracket[0], b.bracket[1], b.evaluations, seconds
        ),
        BoundaryStatus::BelowRange => bail!(
            "--nu-lo {}: nothing squeals there already; lower --nu-lo",
            args.nu_lo
        ),
        _ => bail!(
            "--nu-hi {}: some start still squeals there; raise --nu-hi",
            args.nu_hi
        ),
    }
    Ok(ExitCode::SUCCESS)
}
