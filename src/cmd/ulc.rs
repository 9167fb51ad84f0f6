//! `squeal ulc`: locate the unstable limit cycle as a periodic orbit and report it.

use std::process::ExitCode;

use anyhow::{Context, bail};
use squeal_core::Setup;
use squeal_plot::{Curve, Marker};
use squeal_scan::ulc::{self, CycleSettings};

use super::{common, model::SetupArgs};

/// Flags of `squeal ulc`.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    pub setup: SetupArgs,
    /// Largest section amplitude searched: at most 1e6, and close enough to 0.01 that the
    /// 96 log-spaced samples lie within a factor 1.25 of each other (docs/atlas-spec.md).
    #[arg(long, default_value_t = 6.0)]
    pub r_max: f64,
    /// Relative bracket width at which the bisection stops.
    #[arg(long, default_value_t = 1e-10)]
    pub rtol: f64,
    /// Check the curve on this many rays from the fixed point (0: skip): a start just inside
    /// must move inward, one just outside outward; exits with status 1 if any ray disagrees.
    #[arg(long, default_value_t = 0)]
    pub verify_rays: usize,
    /// Relative offset inside/outside the cycle of the ray checks.
    #[arg(long, default_value_t = 0.05)]
    pub verify_eps: f64,
    /// Skip the dt/2 accuracy check.
    #[arg(long)]
    pub no_half_dt: bool,
    /// Phase-plane picture of the cycle.
    #[arg(long)]
    pub plot: Option<std::path::PathBuf>,
    /// Overwrite an existing picture.
    #[arg(long)]
    pub force: bool,
    /// Print the report (curve included) as one JSON object.
    #[arg(long)]
    pub json: bool,
}

/// Locates and reports the cycle.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let setup = args.setup.setup()?;
    let plan = &setup.plan;
    let params = plan.maps[setup.map];
    if args.verify_rays > squeal_scan::bounds::MAX_RAYS {
        bail!(
            "--verify-rays {}: expected at most {} rays (one every 0.036 degrees, finer than \
             the curve's samples)",
            args.verify_rays,
            squeal_scan::bounds::MAX_RAYS
        );
    }
    if !(args.verify_eps > 0.0 && args.verify_eps < 0.5) {
        bail!(
            "--verify-eps {}: expected a value in (0, 0.5)",
            args.verify_eps
        );
    }
    if let Some(p) = &args.plot {
        common::check_new(p, args.force, "picture")?;
    }
    let cs = CycleSettings {
        r_max: args.r_max,
        rtol: args.rtol,
        check_half_dt: !args.no_half_dt,
        ..Default::default()
    };
    // The atlas spec's `[cycle]` rules, naming the flags.
    squeal_scan::bounds::cycle_search(
        &cs,
        &|k| format!("--{}", k.replace('_', "-")),
        &|key, value, expected| squeal_scan::ScanError::Invalid {
            path: "command line".into(),
            key: key.into(),
            value,
            expected: expected.into(),
        },
    )?;
    let t0 = std::time::Instant::now();
    let rep = ulc::locate(Setup::new(params, plan.dt, plan.solver), &cs)?;
    let seconds = t0.elapsed().as_secs_f64();
    // Every sign change the search's samples show (the same samples as the search's own).
    let samples = {
        let st = Setup::new(params, plan.dt, plan.solver).stepper()?;
        let map = squeal_scan::section::ReturnMap::new(&st, cs.t_return);
        squeal_scan::section::adaptive_samples(&map, &cs, &mut Default::default())
    };
    let changes = samples.sign_changes();
    let rays = if args.verify_rays > 0 {
        Some(ulc::verify_rays(
            &rep,
            args.verify_rays,
            args.verify_eps,
            plan.solver,
        )?)
    } else {
        None
    };
    if let Some(p) = &args.plot {
        let fp = params.fixed_point();
        let mut xs = rep.curve.x.clone();
        let mut vs = rep.curve.v.clone();
        xs.push(xs[0]);
        vs.push(vs[0]);
        let curve = Curve {
            label: "unstable limit cycle".into(),
            xs,
            ys: vs,
            color: squeal_plot::CYCLE,
            points_only: false,
        };
        let marks = [
            Marker {
                label: "fixed point".into(),
                x: fp.x,
                y: fp.v,
                color: squeal_plot::FIXED_POINT,
            },
            Marker {
                label: "rest (0, 0)".into(),
                x: 0.0,
                y: 0.0,
                color: squeal_plot::STICK,
            },
        ];
        let title = squeal_plot::phase_title(
            "Unstable limit cycle",
            &super::common::plot_params(&params, plan.dt),
        );
        let scale = squeal_plot::StateScale::of_law(params.law.name());
        squeal_plot::phase_plot(p, &title, scale, &[curve], &marks)
            .with_context(|| format!("drawing {}", p.display()))?;
    }
    if args.json {
        let mut v = serde_json::to_value(&rep)?;
        v["seconds"] = seconds.into();
        v["bracket_width"] = (rep.bracket[1] - rep.bracket[0]).into();
        v["rays"] = serde_json::to_value(&rays)?;
        v["verified"] = rays.as_ref().map(|r| r.passed()).into();
        v["sign_changes"] = serde_json::json!(
            changes
                .iter()
                .map(|&(lo, hi, rising)| serde_json::json!({"lo": lo, "hi": hi, "rising": rising}))
                .collect::<Vec<_>>()
        );
        v["resolution"] = squeal_scan::section::RESOLUTION.into();
        v["unresolved"] = samples.unresolved.into();
        if let Some(ph) = plan.physical {
            v["si"] = si_json(&rep, &ph.scales());
        }
        println!("{}", serde_json::to_string(&v)?);
        return Ok(verdict(rays.as_ref()));
    }
    println!(
        "unstable limit cycle: {} {} = {} {} = {} (dt = {}, {} solver)",
        params.law,
        params.damping_key(),
        params.nu,
        params.speed_key(),
        params.lambda,
        plan.dt,
        plan.solver.kind
    );
    println!(
        "  section x = {:.6}, x' = {:.10} (bracket width {:.2e})",
        params.fixed_point().x,
        rep.r_section,
        rep.bracket[1] - rep.bracket[0]
    );
    println!(
        "  period {:.6}, angular frequency {:.6}",
        rep.period, rep.omega
    );
    println!(
        "  extent x in [{:.6}, {:.6}], x' in [{:.6}, {:.6}]",
        rep.x_range[0], rep.x_range[1], rep.v_range[0], rep.v_range[1]
    );
    println!(
        "  distance from the fixed point along +x {:.6}, enclosed area {:.6}",
        rep.distance_plus_x, rep.area
    );
    println!(
        "  Floquet multiplier (growth per revolution) {:.6}",
        rep.multiplier
    );
    println!(
        "  encloses the state at rest (0, 0): {}",
        if rep.encloses_origin {
            "yes: from rest, steady slip"
        } else {
            "no: from rest, squeal"
        }
    );
    if let Some(h) = rep.half_dt {
        println!(
            "  with dt/2: x' at the section {:.8} (shift {:+.2e})",
            h.r_section, h.shift
        );
    }
    if let Some(ph) = plan.physical {
        println!("{}", si_words(&rep, &ph.scales()));
    }
    println!(
        "  {} section returns, {} friction evaluations, {:.3} s",
        rep.returns, rep.solver.evaluations, seconds
    );
    let words: Vec<String> = changes
        .iter()
        .map(|&(lo, hi, rising)| {
            let kind = if rising { "- to +" } else { "+ to -" };
            format!("{kind} in [{lo:.4}, {hi:.4}]")
        })
        .collect();
    println!(
        "  sign changes of D = P(r) - r sampled up to r = {}: {} ({} samples, refined where a window could hide down to a relative width of {}{})",
        cs.r_max,
        words.join(", "),
        samples.rs.len(),
        squeal_scan::section::RESOLUTION,
        match samples.unresolved {
            0 => String::new(),
            n => format!("; {n} intervals left unrefined: budget spent"),
        }
    );
    if let Some(rays) = &rays {
        println!(
            "  rays: {} of {} have the start just inside moving inward and the one just outside \
             moving outward (eps {}; a deviation must grow {}-fold within {} revolutions, \
             from the one-sided multipliers {:.6} inside and {:.6} outside)",
            rays.agreeing(),
            rays.rays.len(),
            rays.eps,
            rays.growth,
            rays.revolutions_max,
            rays.multipliers[0],
            rays.multipliers[1]
        );
        for r in &rays.rays {
            let show = |s: &ulc::RayStart| match s.drift {
                ulc::Drift::Inward => format!("inward after {} revolutions", s.revolutions),
                ulc::Drift::Outward => format!("outward after {} revolutions", s.revolutions),
                ulc::Drift::Undecided => format!("UNDECIDED after {} revolutions", s.revolutions),
            };
            println!(
                "    angle {:6.3} radius {:.5}: inside {}, outside {}{}",
                r.angle,
                r.radius,
                show(&r.inner),
                show(&r.outer),
                if r.agrees() { "" } else { "  <- disagrees" }
            );
        }
    }
    Ok(verdict(rays.as_ref()))
}

/// Exit status: 1 when a ray check was asked for and did not pass.
fn verdict(rays: Option<&ulc::RayVerification>) -> ExitCode {
    match rays {
        Some(r) if !r.passed() => {
            eprintln!(
                "squeal ulc: verification failed: {} of {} rays disagree with the located cycle",
                r.rays.len() - r.agreeing(),
                r.rays.len()
            );
            ExitCode::from(1)
        }
        _ => ExitCode::SUCCESS,
    }
}

/// The cycle's figures in SI units (a physical system): lengths in m, velocities in m/s,
/// the period in s and the frequency in Hz.
fn si_json(rep: &ulc::CycleReport, s: &squeal_core::Scales) -> serde_json::Value {
    serde_json::json!({
        "r_section_m_per_s": rep.r_section * s.velocity,
        "x_range_m": rep.x_range.map(|x| x * s.length),
        "v_range_m_per_s": rep.v_range.map(|v| v * s.velocity),
        "distance_plus_x_m": rep.distance_plus_x * s.length,
        "period_s": rep.period * s.time,
        "frequency_hz": s.hz(rep.omega),
        "area_m2_per_s": rep.area * s.area(),
    })
}

/// [`si_json`] in words.
fn si_words(rep: &ulc::CycleReport, s: &squeal_core::Scales) -> String {
    format!(
        "  in SI units: section x' = {:.4e} m/s; extent x in [{:.4e}, {:.4e}] m, x' in \
         [{:.4e}, {:.4e}] m/s; {:.4e} m beyond the fixed point along +x; period {:.4e} s \
         ({:.2} Hz)",
        rep.r_section * s.velocity,
        rep.x_range[0] * s.length,
        rep.x_range[1] * s.length,
        rep.v_range[0] * s.velocity,
        rep.v_range[1] * s.velocity,
        rep.distance_plus_x * s.length,
        rep.period * s.time,
        s.hz(rep.omega)
    )
}
