//! `squeal ulc`: locate the unstable limit cycle as a periodic orbit and report it.

use std::process::ExitCode;

use anyhow::{Context, bail};
use squeal_core::{Physical, Setup};
use squeal_scan::ulc::{self, CycleSettings};

use super::pictures;
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
    let cs = checked_settings(&args)?;
    if let Some(p) = &args.plot {
        super::out_files::regular("--plot", p)?;
        common::check_new(p, args.force, "picture")?;
    }
    let t0 = std::time::Instant::now();
    let bar = super::progress::SearchBar::new("ulc", "r", false);
    let (rep, seconds, samples, rays) = super::progress::searching(bar.as_ref(), || {
        if let Some(b) = &bar {
            b.stage("locating the cycle");
        }
        let rep = ulc::locate(Setup::new(params, plan.dt, plan.solver), &cs)?;
        let seconds = t0.elapsed().as_secs_f64();
        if let Some(b) = &bar {
            b.stage("sampling the section for the report");
        }
        // Every sign change the search's samples show (the same samples as the search's own).
        let samples = {
            let st = Setup::new(params, plan.dt, plan.solver).stepper()?;
            let map = squeal_scan::section::ReturnMap::new(&st, cs.t_return);
            squeal_scan::section::adaptive_samples(&map, &cs, &mut Default::default())
        };
        if let Some(b) = &bar {
            b.stage("checking the rays");
        }
        let rays = match args.verify_rays {
            0 => None,
            n => Some(ulc::verify_rays(&rep, n, args.verify_eps, plan.solver)?),
        };
        anyhow::Ok((rep, seconds, samples, rays))
    })?;
    drop(bar);
    if let Some(p) = &args.plot {
        let fp = params.fixed_point();
        let scale = squeal_plot::StateScale::of_law(params.law.name());
        // A physical system's cycle in metres and m/s, the system in the title (this map's
        // c and v_belt).
        let system = (plan.physical().as_ref()).map(|ph| Physical::from_params(ph, &params));
        let line = system.as_ref().map(pictures::physical_system_line);
        let si = (system.as_ref().zip(line.as_deref()))
            .map(|(ph, line)| (pictures::si_state(&ph.scales()), line));
        let model = pictures::plot_params(&params, plan.dt);
        let curve = (&rep.curve.x[..], &rep.curve.v[..]);
        squeal_plot::cycle_plot(p, curve, (fp.x, fp.v), &model, (scale, si))
            .with_context(|| format!("drawing {}", p.display()))?;
    }
    let found = Found {
        rep: &rep,
        samples: &samples,
        rays: rays.as_ref(),
        seconds,
        r_max: cs.r_max,
        si: plan.physical().map(|ph| rep.si(&ph.scales())),
    };
    if args.json {
        println!("{}", serde_json::to_string(&found.json()?)?);
    } else {
        found.print(plan.dt, plan.solver.kind);
        if let Some(rays) = &rays {
            print_rays(rays);
        }
    }
    Ok(verdict(rays.as_ref()))
}

/// The flags' search settings, checked by the atlas spec's `[cycle]` rules (naming the
/// flags) before any computing.
fn checked_settings(args: &Args) -> anyhow::Result<CycleSettings> {
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
            squeal_core::error::Number(args.verify_eps)
        );
    }
    let cs = CycleSettings {
        r_max: args.r_max,
        rtol: args.rtol,
        check_half_dt: !args.no_half_dt,
        ..Default::default()
    };
    squeal_scan::bounds::cycle_search(
        &cs,
        &|k| super::law_flags::flag(k),
        &|key, value, expected| squeal_scan::ScanError::Invalid {
            path: "command line".into(),
            key: key.into(),
            value,
            expected: expected.into(),
        },
    )?;
    Ok(cs)
}

/// What `squeal ulc` found, for its two reports.
struct Found<'a> {
    rep: &'a ulc::CycleReport,
    samples: &'a squeal_scan::section::SectionSamples,
    rays: Option<&'a ulc::RayVerification>,
    seconds: f64,
    r_max: f64,
    si: Option<ulc::CycleSi>,
}

impl Found<'_> {
    /// The report as one JSON object: the cycle's record and the search's facts.
    fn json(&self) -> anyhow::Result<serde_json::Value> {
        let rep = self.rep;
        let mut v = serde_json::to_value(rep)?;
        v["seconds"] = self.seconds.into();
        v["bracket_width"] = (rep.bracket[1] - rep.bracket[0]).into();
        v["rays"] = serde_json::to_value(self.rays)?;
        v["verified"] = self.rays.map(|r| r.passed()).into();
        v["sign_changes"] = serde_json::json!(
            self.samples
                .sign_changes()
                .iter()
                .map(|&(lo, hi, rising)| serde_json::json!({"lo": lo, "hi": hi, "rising": rising}))
                .collect::<Vec<_>>()
        );
        v["resolution"] = squeal_scan::section::RESOLUTION.into();
        v["unresolved"] = self.samples.unresolved.into();
        v["steady_slip"] = serde_json::to_value(squeal_core::SteadySlip::of(&rep.params))?;
        if let Some(si) = &self.si {
            v["si"] = serde_json::to_value(si)?;
        }
        Ok(v)
    }

    /// The report in words.
    fn print(&self, dt: f64, solver: squeal_core::SolverKind) {
        let (rep, p) = (self.rep, &self.rep.params);
        println!(
            "unstable limit cycle: {} {} = {} {} = {} (dt = {dt}, {solver} solver)",
            p.law,
            p.damping_key(),
            p.nu,
            p.speed_key(),
            p.lambda,
        );
        println!("  {}", squeal_core::SteadySlip::of(p).words(None));
        println!(
            "  section x = {:.6}, x' = {:.10} (bracket width {:.2e})",
            p.fixed_point().x,
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
            match rep.encloses_origin {
                true => "yes: from rest, steady slip",
                false => "no: from rest, squeal",
            }
        );
        if let Some(h) = rep.half_dt {
            println!(
                "  with dt/2: x' at the section {:.8} (shift {:+.2e})",
                h.r_section, h.shift
            );
        }
        if let Some(si) = &self.si {
            println!("  in SI units: {si}");
        }
        println!(
            "  {} section returns, {} friction evaluations, {:.3} s",
            rep.returns, rep.solver.evaluations, self.seconds
        );
        self.print_sign_changes();
    }

    /// Every sign change of the sampled `D`, and the search's resolution.
    fn print_sign_changes(&self) {
        let words: Vec<String> = self
            .samples
            .sign_changes()
            .iter()
            .map(|&(lo, hi, rising)| {
                let kind = if rising { "- to +" } else { "+ to -" };
                format!("{kind} in [{lo:.4}, {hi:.4}]")
            })
            .collect();
        println!(
            "  sign changes of D = P(r) - r sampled up to r = {}: {} ({} samples, refined where a window could hide down to a relative width of {}{})",
            self.r_max,
            words.join(", "),
            self.samples.rs.len(),
            squeal_scan::section::RESOLUTION,
            match self.samples.unresolved {
                0 => String::new(),
                n => format!("; {n} intervals left unrefined: budget spent"),
            }
        );
    }
}

/// The ray checks, one line each.
fn print_rays(rays: &ulc::RayVerification) {
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
