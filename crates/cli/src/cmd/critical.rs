//! `squeal critical`: the damping (or, `--in lambda`, the belt speed) above which a given
//! state no longer squeals; `--fold`: above which no start squeals.

use squeal_core::error::Number;
use std::process::ExitCode;

use anyhow::bail;
use squeal_core::Setup;
use squeal_core::State;
use squeal_scan::atlas::{BoundaryParam, PointSettings, boundary};
use squeal_scan::fates::{self, Decided};
use squeal_scan::section::ParamRange;
use squeal_scan::ulc::{self, CycleSettings};

use super::critical_report::{BoundaryFound, CrisisFound, found, report, si_unit, warn_changes};
use super::critical_runs;
use super::progress::{SearchBar, searching};

pub use super::critical_args::Args;

/// Bisects in nu.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let setup = args.setup.setup()?;
    let plan = &setup.plan;
    if !(args.x0.is_finite() && args.v0.is_finite()) {
        bail!("--x0/--v0: expected finite values");
    }
    if !(args.rtol > 0.0 && args.rtol < 1.0) {
        bail!("--rtol {}: expected a value in (0, 1)", Number(args.rtol));
    }
    check_lifetimes(&args, plan.dt)?;
    let t0 = std::time::Instant::now();
    // A physical system: --x0/--v0 are in m and m/s, results also in SI units.
    let scales = plan.physical().map(|ph| ph.scales());
    let given = State {
        x: args.x0,
        v: args.v0,
    };
    let point = scales.map_or(given, |s| s.state(given));
    // The start, in the model's units, within the classifier's escape radius (`--x0 1e300`
    // was bisected for).
    let inv = super::physical::start_invalid("command line".into(), scales.map(|s| (given, s)));
    squeal_scan::bounds::state("--x0", point.x, &inv)?;
    squeal_scan::bounds::state("--v0", point.v, &inv)?;
    let args = in_by_law(args, plan, setup.map)?;
    check_speed_bracket(&args, plan.dt)?;
    args.check_horizon(plan.dt)?;
    if args.crisis {
        return crisis(&args, plan, setup.map, t0);
    }
    let map = setup.map;
    let param = BoundaryParam::from_key(&args.in_).unwrap_or_default();
    let names = names(&args, plan, map, param)?;
    if args.fold || args.in_ == "lambda" {
        return boundary(&args, (plan, map), names, point, t0);
    }
    let cs = CycleSettings::default();
    let (range, _) = args.range(BoundaryParam::Nu)?;
    let key = plan.maps[map].damping_key();
    let bar = SearchBar::new("critical", key, false);
    let setup1 = plan.setup(map);
    let gate = (setup1, BoundaryParam::Nu);
    let d = searching(bar.as_ref(), || -> anyhow::Result<_> {
        // The shortcut: the damping at which the unstable cycle first encloses the start.
        let shortcut = || {
            let rep = ulc::critical_nu(setup1, &cs, point, range)?;
            let changes = ulc::coarse_enclosed(setup1, &cs, point, (range.lo, range.hi))?;
            let bracket = rep.bracket;
            Ok(((rep, changes), Some(bracket)))
        };
        args.decide(gate, &[point], range, shortcut).map_err(|e| {
            let bracket = matches!(e, squeal_scan::ScanError::Bracket { .. });
            let e = anyhow::Error::new(e);
            if bracket {
                e.context("--nu-lo / --nu-hi")
            } else {
                e
            }
        })
    })?;
    drop(bar);
    let names = (BoundaryParam::Nu, names.1, names.2);
    if let Some(((rep, changes), confirmed)) =
        critical_runs::shortcut_or_print(&args, d, plan, names, (point, t0))?
    {
        let seconds = t0.elapsed().as_secs_f64();
        report(
            &args,
            &rep,
            point,
            (key, scales),
            (seconds, confirmed.as_ref()),
            &changes,
        )?;
    }
    Ok(ExitCode::SUCCESS)
}

/// `args` with `--in` named as the scan names it: `xi` is `nu` and `v_d` is `lambda`, names
/// refused under a law without true stick.
fn in_by_law(args: Args, plan: &squeal_scan::Plan, map: usize) -> anyhow::Result<Args> {
    let stribeck = plan.maps[map].law.family().has_own_names();
    Ok(match (args.in_.as_str(), stribeck) {
        ("xi" | "v_d", false) => bail!(
            "--in {}: a name under the laws with true stick (stribeck, cubic); with law {} use --in nu or --in lambda",
            args.in_,
            plan.maps[map].law.name()
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
    })
}

/// The bisected parameter (`--in`), its name by the law (the Stribeck law: xi, v_d) and its
/// flags' stem (`nu`, `lambda`).
fn names(
    args: &Args,
    plan: &squeal_scan::Plan,
    map: usize,
    param: BoundaryParam,
) -> anyhow::Result<(BoundaryParam, &'static str, &'static str)> {
    let (_, flag) = args.range(param)?;
    let name = match (param, plan.maps[map].law.family().has_own_names()) {
        (BoundaryParam::Nu, true) => "xi",
        (BoundaryParam::Lambda, true) => "v_d",
        _ => flag,
    };
    Ok((param, name, flag))
}

/// `--fold` or `--in lambda`: bisects with the atlas's boundary searches (crate
/// `squeal_scan::atlas::boundary`), the same the atlas stores.
fn boundary(
    args: &Args,
    (plan, map): (&squeal_scan::Plan, usize),
    (param, name, flag): (BoundaryParam, &'static str, &'static str),
    point: State,
    t0: std::time::Instant,
) -> anyhow::Result<ExitCode> {
    let (range, _) = args.range(param)?;
    let ps = PointSettings {
        operating: point,
        ..PointSettings::default()
    };
    if args.fold && boundary::crisis_applies(plan.maps[map].kind()) {
        let names = (param, name, flag);
        return crisis_report(args, (plan, map), (&ps, range), names, (point, t0));
    }
    let which = match args.fold {
        true => boundary::Which::Fold,
        false => boundary::Which::Critical,
    };
    let (lo, hi) = (range.lo, range.hi);
    let bar = SearchBar::new(command(args), name, false);
    let setup = plan.setup(map);
    let starts = starts(args, setup, param, range, point);
    let d = searching(bar.as_ref(), || -> anyhow::Result<_> {
        // The atlas's shared search: the same bisection as `fold_in` / `critical_in`
        // (test `shared_boundaries_equal_separate_ones`), plus its bracket checked at dt / 2.
        let shortcut = || {
            let asked = [args.fold, !args.fold];
            let [f, c] = boundary::both_in(param, setup, &ps, point, range, asked);
            let b = f.or(c).expect("one boundary asked for")?;
            // Above the range, the runs raise a default top (Boundary::gated).
            let (b, bracket) = b.gated(point, (range, args.ceiling(param, range)))?;
            let changes = boundary::coarse_scan(param, setup, (&ps, point), which, (lo, hi))?;
            Ok(((b, changes), bracket))
        };
        Ok(args.decide((setup, param), &starts, range, shortcut)?)
    })?;
    drop(bar);
    let names = (param, name, flag);
    let Some(((b, changes), confirmed)) =
        critical_runs::shortcut_or_print(args, d, plan, names, (point, t0))?
    else {
        return Ok(ExitCode::SUCCESS);
    };
    let seconds = t0.elapsed().as_secs_f64();
    let found = BoundaryFound {
        confirmed: confirmed.as_ref(),
        b: &b,
        name,
        flag,
        range: (lo, hi),
        seconds,
        changes: &changes,
        si: si_unit(plan, param),
    };
    found.report(args, point)?;
    Ok(ExitCode::SUCCESS)
}

/// The starts a confirmation runs: the spread of the fold ([`squeal_scan::fates::Spread`],
/// of the parameters at the range's lower end, as the runs' fold samples), else the start.
fn starts(
    args: &Args,
    setup: Setup,
    param: BoundaryParam,
    range: ParamRange,
    point: State,
) -> Vec<State> {
    fates::starts(args.fold, (param, setup), range.lo, point)
}

/// The command's words on its progress line.
fn command(args: &Args) -> &'static str {
    match (args.crisis, args.fold) {
        (true, _) => "critical --crisis",
        (false, true) => "critical --fold",
        _ => "critical",
    }
}

/// A bracket in the belt speed (`--in lambda`) reaching below the step `dt` would be
/// refused at its first run (Params::check_step, naming the model's `lambda`); it is
/// refused by its flag before any.
fn check_speed_bracket(args: &Args, dt: f64) -> anyhow::Result<()> {
    if args.in_ == "lambda" && args.lambda_lo < dt {
        bail!(
            "--lambda-lo {}: expected a belt speed of at least the step dt = {} (below it \
             the run chatters about zero slip: crates/core/MODEL.md section 3)",
            Number(args.lambda_lo),
            Number(dt)
        );
    }
    Ok(())
}

/// The `--lifetimes` flags, checked before any computing: the lifetimes follow the crisis in
/// the damping (`--crisis`, or `--fold` in nu).
fn check_lifetimes(args: &Args, dt: f64) -> anyhow::Result<()> {
    if !args.lifetimes {
        return Ok(());
    }
    if !(args.crisis || (args.fold && args.in_ == "nu")) {
        bail!("--lifetimes: with --crisis or --fold in the damping (--in nu)");
    }
    if !(2..=squeal_scan::bounds::MAX_LIFETIME_STARTS).contains(&args.starts) {
        bail!(
            "--starts {}: expected 2 to {} starts",
            args.starts,
            squeal_scan::bounds::MAX_LIFETIME_STARTS
        );
    }
    if !(args.lifetime_t_max.is_finite() && args.lifetime_t_max > 0.0) {
        bail!(
            "--lifetime-t-max {}: expected a finite time > 0",
            Number(args.lifetime_t_max)
        );
    }
    // A censored start runs to the end: the bound of any one run (`--lifetime-t-max 1e300`
    // asked for 2e302 steps per start).
    let steps = args.lifetime_t_max / dt;
    if steps > squeal_scan::bounds::MAX_STEPS {
        bail!(
            "--lifetime-t-max {} with dt {dt:?}: {steps:.3e} steps per run, at most 1e10 (about \
             40 minutes at 250 ns per step)",
            squeal_core::error::Number(args.lifetime_t_max)
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
    if args.in_ != "nu" {
        bail!("--crisis: only in the damping (--in nu); --fold --in lambda bisects the belt speed");
    }
    if !squeal_scan::atlas::boundary::crisis_applies(plan.maps[map].kind()) {
        bail!(
            "--crisis: McMillan's laws only (a law with true stick has no band to leak: its fold is --fold)"
        );
    }
    let (range, _) = args.range(BoundaryParam::Nu)?;
    let ps = PointSettings::default();
    crisis_report(
        args,
        (plan, map),
        (&ps, range),
        (BoundaryParam::Nu, "nu", "nu"),
        (State { x: 0.0, v: 0.0 }, t0),
    )
}

/// The crisis of the stick-slip band in `param` (by its `name` and `flag`) over `range`
/// (`--crisis`, `--fold` of McMillan's hysteretic law): an error naming the flag when it lies
/// outside the range, else the lifetimes above it (`--lifetimes`) and the report.
fn crisis_report(
    args: &Args,
    (plan, map): (&squeal_scan::Plan, usize),
    (ps, range): (&PointSettings, ParamRange),
    (param, name, flag): (BoundaryParam, &'static str, &'static str),
    (point, t0): (State, std::time::Instant),
) -> anyhow::Result<ExitCode> {
    let budget = (squeal_scan::band::COARSE, args.budget());
    let bar = SearchBar::new(command(args), name, false);
    let setup = plan.setup(map);
    // `--fold`: the crisis confirmed by runs of the spread at the ends of its interval, or
    // the runs' fold; `--crisis` is the band's crisis itself, not confirmed.
    let starts = starts(args, setup, param, range, point);
    let d = searching(bar.as_ref(), || -> anyhow::Result<_> {
        let shortcut = || {
            let c = boundary::fold_crisis(param, setup, ps, range, budget)?;
            let ends = [c.nu - c.uncertainty, c.nu + c.uncertainty];
            let found = c.status == squeal_scan::band::CrisisStatus::Found;
            Ok((c, (found && args.fold).then_some(ends)))
        };
        if !args.fold {
            return Ok(Decided::Shortcut {
                answer: shortcut()?.0,
                confirmed: None,
            });
        }
        Ok(args.decide((setup, param), &starts, range, shortcut)?)
    })?;
    let names = (param, name, flag);
    let Some((c, confirmed)) = critical_runs::shortcut_or_print(args, d, plan, names, (point, t0))?
    else {
        return Ok(ExitCode::SUCCESS);
    };
    let c = &c;
    found(range, flag, c)?;
    let warning = warn_changes(&c.changes, name);
    // The band's transient lifetimes above the crisis (in the damping only).
    let table = match args.lifetimes {
        true => {
            if let Some(b) = &bar {
                b.stage("lifetimes above the crisis");
            }
            Some(super::lifetimes::table(args, plan, map, c)?)
        }
        false => None,
    };
    drop(bar);
    let report = CrisisFound {
        confirmed: confirmed.as_ref(),
        c,
        name,
        seconds: t0.elapsed().as_secs_f64(),
        // A physical system: the fold in N s/m (c) or m/s (v_belt) too.
        si: si_unit(plan, param),
        warning,
        table,
    };
    report.print(args.json, plan)?;
    Ok(ExitCode::SUCCESS)
}
