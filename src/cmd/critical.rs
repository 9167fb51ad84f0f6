//! `squeal critical`: the damping (or, `--in lambda`, the belt speed) above which a given
//! state no longer squeals; `--fold`: above which no start squeals.

use std::process::ExitCode;

use anyhow::bail;
use squeal_core::State;
use squeal_scan::section::{Change, ParamRange, coarse_changes};
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
    /// Find the crisis of the stick-slip band instead: the damping above which no start
    /// squeals for good (the band above the unstable cycle leaks), bisected at dt and
    /// dt/2, with an uncertainty that covers both (crates/core/MODEL.md, section 6).
    #[arg(long, conflicts_with = "fold")]
    pub crisis: bool,
    /// With --crisis or --fold (in nu): the mean transient lifetime of the leaking band (t_squeal of starts
    /// spread over the band) at nu_c (1 + f), f from 0.01 by factors 1.25 to 0.075, with its standard
    /// error, and its power law in nu - nu_c (crates/scan/src/lifetime.rs).
    #[arg(long)]
    pub lifetimes: bool,
    /// Starts on the band per damping (--lifetimes).
    #[arg(long, default_value_t = 128)]
    pub starts: usize,
    /// Runs still squealing at this time are censored (--lifetimes; nondimensional).
    #[arg(long, default_value_t = 40_000.0)]
    pub lifetime_t_max: f64,
    /// With --fold or --crisis of McMillan's laws: every verdict with the longer horizon
    /// (twice the band's samples and t_return), the computation whose crisis the stated
    /// uncertainty also covers (scripts/fold-coverage.sh checks it).
    #[arg(long)]
    pub longer_horizon: bool,
    /// The parameter to bisect in: nu (the damping) or lambda (the belt speed); for the
    /// Stribeck law xi and v_d (nu and lambda are taken there too). The bracket flags keep
    /// the names --nu-lo ... --lambda-hi.
    #[arg(long = "in", default_value = "nu", value_parser = ["nu", "lambda", "xi", "v_d"])]
    pub in_: String,
    /// Lower end of the bracket in lambda (with --in lambda).
    #[arg(long, default_value_t = 0.5)]
    pub lambda_lo: f64,
    /// Upper end of the bracket in lambda (with --in lambda).
    #[arg(long, default_value_t = 6.0)]
    pub lambda_hi: f64,
}

impl Args {
    /// The band's budget of the crisis's verdicts at dt and dt/2.
    fn budget(&self) -> squeal_scan::band::Budget {
        match self.longer_horizon {
            true => squeal_scan::band::Budget::Longer,
            false => squeal_scan::band::Budget::Standard,
        }
    }
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
    check_lifetimes(&args)?;
    let t0 = std::time::Instant::now();
    // A physical system: --x0/--v0 are in m and m/s, results also in SI units.
    let scales = plan.physical.map(|ph| ph.scales());
    let given = State {
        x: args.x0,
        v: args.v0,
    };
    let point = scales.map_or(given, |s| s.state(given));
    let stribeck = plan.maps[setup.map].law.has_true_stick();
    let args = match (args.in_.as_str(), stribeck) {
        ("xi" | "v_d", false) => bail!(
            "--in {}: the Stribeck law's name; with law {} use --in nu or --in lambda",
            args.in_,
            plan.maps[setup.map].law.name()
        ),
        ("xi", true) => Args {
            in_: "nu".into(),
            ..args
        },
        ("v_d", true) => Args {
            in_: "lambda".into(),
            ..args
        },
        _ => args,
    };
    if args.crisis {
        return crisis(&args, plan, setup.map, t0);
    }
    if args.fold || args.in_ == "lambda" {
        return boundary(&args, plan, setup.map, point, t0);
    }
    let cs = CycleSettings::default();
    let range = ParamRange {
        lo: args.nu_lo,
        hi: args.nu_hi,
        rtol: args.rtol,
    };
    let rep = ulc::critical_nu(plan.setup(setup.map), &cs, point, range).map_err(|e| {
        let bracket = matches!(e, squeal_scan::ScanError::Bracket { .. });
        let e = anyhow::Error::new(e);
        if bracket {
            e.context("--nu-lo / --nu-hi")
        } else {
            e
        }
    })?;
    let base = plan.setup(setup.map);
    let changes = coarse_changes(
        |nu| {
            let p = squeal_core::Params { nu, ..base.params };
            ulc::point_enclosed(base.with_params(p), &cs, point)
        },
        (args.nu_lo, args.nu_hi),
        COARSE,
    )?;
    let seconds = t0.elapsed().as_secs_f64();
    let key = plan.maps[setup.map].damping_key();
    report(&args, &rep, point, key, scales, seconds, &changes)?;
    Ok(ExitCode::SUCCESS)
}

/// Steps of the coarse scan along the parameter before the bisection is trusted (the
/// crisis's own, [`squeal_scan::band::COARSE`]).
const COARSE: usize = squeal_scan::band::COARSE;

/// The coarse scan's changes in words, when there is more than one: the bisection assumes a
/// single change of regime, so several are said loudly (on stdout with the result, and on
/// stderr).
fn warn_changes(changes: &[Change], name: &str) -> Option<String> {
    if changes.len() < 2 {
        return None;
    }
    let list: Vec<String> = changes
        .iter()
        .map(|c| {
            format!(
                "{} in [{:.6e}, {:.6e}]",
                if c.to { "quiet" } else { "squeals" },
                c.lo,
                c.hi
            )
        })
        .collect();
    let w = format!(
        "WARNING: the regime changes {} times along {name} ({COARSE} geometric steps over the range): {}; the bisection found one of them",
        changes.len(),
        list.join(", ")
    );
    eprintln!("{w}");
    Some(w)
}

/// Prints the critical damping (JSON with `--json`), in SI units too for a physical system.
fn report(
    args: &Args,
    rep: &ulc::CriticalReport,
    point: State,
    key: &str,
    scales: Option<squeal_core::Scales>,
    seconds: f64,
    changes: &[Change],
) -> anyhow::Result<()> {
    let warning = warn_changes(changes, key);
    if args.json {
        let mut v = serde_json::to_value(rep)?;
        v["seconds"] = seconds.into();
        v["coarse_changes"] = serde_json::to_value(changes)?;
        if let Some(s) = scales {
            v["c"] = (rep.nu * s.damping).into();
            v["c_bracket"] = serde_json::json!(rep.bracket.map(|b| b * s.damping));
            v["c_units"] = "N s/m".into();
            v["x0_m"] = args.x0.into();
            v["v0_m_per_s"] = args.v0.into();
        }
        println!("{}", serde_json::to_string(&v)?);
    } else {
        println!(
            "critical damping for ({}, {}): {} = {:.6e}, bracket [{:.6e}, {:.6e}] ({} cycle locations, {:.2} s)",
            point.x, point.v, key, rep.nu, rep.bracket[0], rep.bracket[1], rep.evaluations, seconds
        );
        println!(
            "  below it the unstable cycle leaves ({}, {}) outside and the band above the cycle does not leak: that start squeals (or, where the band's verdict is marginal, may); above it the start is inside the cycle or the band leaks: steady slip",
            point.x, point.v
        );
        if let Some(w) = warning {
            println!("  {w}");
        }
        if let Some(s) = scales {
            println!(
                "  in SI units: c = {:.4} N s/m, bracket [{:.4}, {:.4}] N s/m, for the start x0 = {} m, v0 = {} m/s",
                rep.nu * s.damping,
                rep.bracket[0] * s.damping,
                rep.bracket[1] * s.damping,
                args.x0,
                args.v0
            );
        }
    }
    Ok(())
}

/// `--fold` or `--in lambda`: bisects with the atlas's boundary searches (crate
/// `squeal_scan::atlas::boundary`), the same the atlas stores.
fn boundary(
    args: &Args,
    plan: &squeal_scan::Plan,
    map: usize,
    point: State,
    t0: std::time::Instant,
) -> anyhow::Result<ExitCode> {
    use squeal_scan::atlas::{BoundaryParam, PointSettings, boundary};
    let param = BoundaryParam::from_key(&args.in_).unwrap_or_default();
    let (lo, hi, flag) = match param {
        BoundaryParam::Nu => (args.nu_lo, args.nu_hi, "nu"),
        BoundaryParam::Lambda => (args.lambda_lo, args.lambda_hi, "lambda"),
    };
    if !(lo > 0.0 && hi > lo && hi.is_finite()) {
        bail!("--{flag}-lo {lo} / --{flag}-hi {hi}: expected 0 < lo < hi");
    }
    // The bisected parameter by the law's own name (the Stribeck law: xi, v_d).
    let name = match (param, plan.maps[map].law.has_true_stick()) {
        (BoundaryParam::Nu, true) => "xi",
        (BoundaryParam::Lambda, true) => "v_d",
        _ => flag,
    };
    let ps = PointSettings {
        operating: point,
        ..PointSettings::default()
    };
    if args.fold && boundary::crisis_applies(plan.maps[map].law) {
        let range = ParamRange {
            lo,
            hi,
            rtol: args.rtol,
        };
        let c = boundary::fold_crisis(param, plan.setup(map), &ps, range, (COARSE, args.budget()))?;
        return crisis_report(args, (plan, map), (param, name, flag), &c, t0);
    }
    // The atlas's shared search: the same bisection as `fold_in` / `critical_in`
    // (test `shared_boundaries_equal_separate_ones`), plus its bracket checked at dt / 2.
    let range = ParamRange {
        lo,
        hi,
        rtol: args.rtol,
    };
    let [f, c] = boundary::both_in(
        param,
        plan.setup(map),
        &ps,
        point,
        range,
        [args.fold, !args.fold],
    );
    let b = match f.or(c) {
        Some(r) => r?,
        None => bail!("no boundary asked for"),
    };
    let base = plan.setup(map);
    let changes = coarse_changes(
        |v| {
            let setup = base.with_params(param.with(base.params, v));
            match args.fold {
                true => boundary::quiet_everywhere(setup, &ps),
                false => boundary::point_quiet(setup, &ps, point),
            }
        },
        (lo, hi),
        COARSE,
    )?;
    let found = BoundaryFound {
        b: &b,
        name,
        flag,
        range: (lo, hi),
        seconds: t0.elapsed().as_secs_f64(),
        changes: &changes,
        si: si_unit(plan, param),
    };
    if args.json {
        println!("{}", serde_json::to_string(&found.json()?)?);
        return Ok(ExitCode::SUCCESS);
    }
    found.print(args, point)?;
    Ok(ExitCode::SUCCESS)
}

/// A physical system's name, scale and units for a boundary in `param`: the damping in
/// N s/m (c), the belt speed in m/s (v_belt).
fn si_unit(
    plan: &squeal_scan::Plan,
    param: squeal_scan::atlas::BoundaryParam,
) -> Option<(&'static str, f64, &'static str)> {
    use squeal_scan::atlas::BoundaryParam;
    plan.physical.map(|ph| {
        let s = ph.scales();
        match param {
            BoundaryParam::Nu => ("c", s.damping, "N s/m"),
            BoundaryParam::Lambda => ("v_belt", s.velocity, "m/s"),
        }
    })
}

/// A boundary found by `critical` (the critical value, or the fold of a law without a crisis),
/// for its two reports.
struct BoundaryFound<'a> {
    b: &'a squeal_scan::atlas::Boundary,
    /// The bisected parameter's name and flag.
    name: &'a str,
    flag: &'a str,
    range: (f64, f64),
    seconds: f64,
    changes: &'a [Change],
    si: Option<(&'static str, f64, &'static str)>,
}

impl BoundaryFound<'_> {
    /// The boundary as one JSON object.
    fn json(&self) -> anyhow::Result<serde_json::Value> {
        let (b, name) = (self.b, self.name);
        let mut v = serde_json::to_value(b)?;
        v["in"] = name.into();
        v[name] = v["nu"].clone();
        v["seconds"] = self.seconds.into();
        v["coarse_changes"] = serde_json::to_value(self.changes)?;
        if let Some((key, unit, units)) = self.si {
            v[key] = (b.nu * unit).into();
            v[format!("{key}_bracket")] = serde_json::json!(b.bracket.map(|x| x * unit));
            v[format!("{key}_units")] = units.into();
        }
        Ok(v)
    }

    /// The boundary in words; an error naming the flag when it lies outside the range.
    fn print(&self, args: &Args, point: State) -> anyhow::Result<()> {
        use squeal_scan::atlas::BoundaryStatus;
        let (b, name, flag) = (self.b, self.name, self.flag);
        let (lo, hi) = self.range;
        let (what, meaning) = if args.fold {
            (
                "fold of cycles",
                "below it a stick-slip oscillation exists beside steady slip; above it no start squeals"
                    .to_string(),
            )
        } else {
            (
                "critical value",
                format!(
                    "below it ({}, {}) squeals; above it, steady slip",
                    point.x, point.v
                ),
            )
        };
        let nothing = if args.fold {
            "nothing squeals there already".to_string()
        } else {
            format!("({}, {}) is quiet there already", point.x, point.v)
        };
        match b.status {
            BoundaryStatus::Found => {}
            BoundaryStatus::BelowRange => bail!("--{flag}-lo {lo}: {nothing}; lower --{flag}-lo"),
            _ => bail!("--{flag}-hi {hi}: it still squeals there; raise --{flag}-hi"),
        }
        println!(
            "{what}: {name} = {:.6e}, bracket [{:.6e}, {:.6e}] ({} evaluations, {:.2} s)\n  {meaning}\n  {}",
            b.nu,
            b.bracket[0],
            b.bracket[1],
            b.evaluations,
            self.seconds,
            match b.half_dt_holds {
                Some(true) => "at dt/2 the bracket holds (the predicate is the same at both ends)",
                Some(false) =>
                    "at dt/2 the boundary moves out of the bracket: its error is larger than the bracket",
                None => "at dt/2: not checked (a run failed)",
            }
        );
        if let Some(w) = warn_changes(self.changes, name) {
            println!("  {w}");
        }
        if let Some((key, unit, units)) = self.si {
            println!(
                "  in SI units: {key} = {:.4} {units}, bracket [{:.4}, {:.4}] {units}",
                b.nu * unit,
                b.bracket[0] * unit,
                b.bracket[1] * unit
            );
        }
        Ok(())
    }
}

/// The `--lifetimes` flags, checked before any computing: the lifetimes follow the crisis in
/// the damping (`--crisis`, or `--fold` in nu).
fn check_lifetimes(args: &Args) -> anyhow::Result<()> {
    if !args.lifetimes {
        return Ok(());
    }
    if !(args.crisis || (args.fold && args.in_ == "nu")) {
        bail!("--lifetimes: with --crisis or --fold in the damping (--in nu)");
    }
    if args.starts < 2 {
        bail!("--starts {}: expected at least 2 starts", args.starts);
    }
    if !(args.lifetime_t_max.is_finite() && args.lifetime_t_max > 0.0) {
        bail!(
            "--lifetime-t-max {}: expected a finite time > 0",
            args.lifetime_t_max
        );
    }
    Ok(())
}

/// `--crisis`: where squeal stops lasting, in the damping: the fold of `--fold`.
fn crisis(
    args: &Args,
    plan: &squeal_scan::Plan,
    map: usize,
    t0: std::time::Instant,
) -> anyhow::Result<ExitCode> {
    use squeal_scan::atlas::{BoundaryParam, PointSettings, boundary};
    if args.in_ != "nu" {
        bail!("--crisis: only in the damping (--in nu); --fold --in lambda bisects the belt speed");
    }
    if !squeal_scan::atlas::boundary::crisis_applies(plan.maps[map].law) {
        bail!(
            "--crisis: McMillan's hysteretic law only (a law with true stick has no band to leak; for the non-hysteretic law the section map misses a stick-slip orbit that runs keep, see crates/core/MODEL.md)"
        );
    }
    if !(args.nu_lo > 0.0 && args.nu_hi > args.nu_lo && args.nu_hi.is_finite()) {
        bail!(
            "--nu-lo {} / --nu-hi {}: expected 0 < lo < hi",
            args.nu_lo,
            args.nu_hi
        );
    }
    let range = ParamRange {
        lo: args.nu_lo,
        hi: args.nu_hi,
        rtol: args.rtol,
    };
    let ps = PointSettings::default();
    let c = boundary::fold_crisis(
        BoundaryParam::Nu,
        plan.setup(map),
        &ps,
        range,
        (COARSE, args.budget()),
    )?;
    crisis_report(args, (plan, map), (BoundaryParam::Nu, "nu", "nu"), &c, t0)
}

/// An error naming the flag of the range's end when the crisis `c` was not found in it.
fn found(
    args: &Args,
    (param, flag): (squeal_scan::atlas::BoundaryParam, &str),
    c: &squeal_scan::band::Crisis,
) -> anyhow::Result<()> {
    use squeal_scan::atlas::BoundaryParam;
    use squeal_scan::band::CrisisStatus;
    let (lo, hi) = match param {
        BoundaryParam::Nu => (args.nu_lo, args.nu_hi),
        BoundaryParam::Lambda => (args.lambda_lo, args.lambda_hi),
    };
    match c.status {
        CrisisStatus::Found => Ok(()),
        CrisisStatus::BelowRange => {
            bail!("--{flag}-lo {lo}: squeal lasts nowhere in the range; lower --{flag}-lo")
        }
        CrisisStatus::AboveRange => bail!(
            "--{flag}-hi {hi}: squeal still lasts there (or never turns quiet above it); raise --{flag}-hi"
        ),
    }
}

/// Prints the crisis `c` (`--crisis`, `--fold` of McMillan's laws): the fold with its
/// uncertainty, the bracket at dt, whether it held at dt/2 and with the longer horizon, and
/// loudly every change of regime the coarse scan found when there is more than one.
fn crisis_report(
    args: &Args,
    (plan, map): (&squeal_scan::Plan, usize),
    (param, name, flag): (squeal_scan::atlas::BoundaryParam, &str, &str),
    c: &squeal_scan::band::Crisis,
    t0: std::time::Instant,
) -> anyhow::Result<ExitCode> {
    found(args, (param, flag), c)?;
    let warning = warn_changes(&c.changes, name);
    // The band's transient lifetimes above the crisis (in the damping only).
    let table = match args.lifetimes {
        true => Some(super::lifetimes::table(args, plan, map, c)?),
        false => None,
    };
    let seconds = t0.elapsed().as_secs_f64();
    // A physical system: the fold in N s/m (c) or m/s (v_belt) too.
    let si = si_unit(plan, param);
    if args.json {
        let mut v = serde_json::to_value(c)?;
        // The bracket at dt under the name `--fold` gave it before (the atlas's fold_nu_lo/hi).
        v["bracket"] = serde_json::to_value(c.interval)?;
        v["in"] = name.into();
        v["seconds"] = seconds.into();
        if let Some(t) = &table {
            v["lifetimes"] = super::lifetimes::json(t, plan)?;
        }
        if let Some((key, unit, units)) = si {
            v["si"] = serde_json::json!({
                key: c.nu * unit,
                format!("{key}_uncertainty"): c.uncertainty * unit,
                "units": units,
            });
        }
        println!("{}", serde_json::to_string(&v)?);
        return Ok(ExitCode::SUCCESS);
    }
    let holds = |h: bool| {
        if h {
            "holds"
        } else {
            "moves (the uncertainty was widened)"
        }
    };
    println!(
        "fold (crisis of the stick-slip band): {name} = {:.6e} +- {:.2e} ({} verdicts, {:.2} s)",
        c.nu, c.uncertainty, c.evaluations, seconds
    );
    println!(
        "  at dt squeal lasts up to {name} = {:.6e} and no start squeals for good from {:.6e} (between them the band's verdict is marginal: undecided); that bracket {} at dt/2 and {} with the longer horizon; the uncertainty covers all three",
        c.interval[0],
        c.interval[1],
        holds(c.half_dt_holds),
        holds(c.longer_holds)
    );
    if let Some(w) = warning {
        println!("  {w}");
    }
    if let Some((key, unit, units)) = si {
        println!(
            "  in SI units: {key} = {:.4} +- {:.4} {units} (squeal lasts up to {:.4}, none for good from {:.4} {units} at dt)",
            c.nu * unit,
            c.uncertainty * unit,
            c.interval[0] * unit,
            c.interval[1] * unit
        );
    }
    if let Some(t) = &table {
        super::lifetimes::print(t, plan);
    }
    Ok(ExitCode::SUCCESS)
}
