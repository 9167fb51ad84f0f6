//! What `squeal critical` prints when the answer is the runs' ([`squeal_scan::fates::decide`]):
//! where the model lies outside the region its shortcuts were checked in (crates/core/MODEL.md
//! section 11), or where a run at the ends of the shortcut's bracket contradicted it. Each
//! end of the printed bracket is a run (below it a start does not settle, above it every
//! start does), and the interval covers the boundary at dt / 2.

use anyhow::bail;
use squeal_core::State;
use squeal_core::error::Number;
use squeal_scan::atlas::{BoundaryParam, BoundaryStatus};
use squeal_scan::fates::{Decided, Fate, RunBoundary, Why};

use super::critical_args::Args;

/// The gate's answer `d`: where it is the runs', printed (`None`); else the shortcut's
/// answer and its runs' confirmation line, for the caller's report.
pub(super) fn shortcut_or_print<T>(
    args: &Args,
    d: Decided<T>,
    plan: &squeal_scan::Plan,
    names: (BoundaryParam, &str, &str),
    (point, t0): (State, std::time::Instant),
) -> anyhow::Result<Option<(T, Option<String>)>> {
    match d {
        Decided::Runs { boundary, why } => {
            let seconds = t0.elapsed().as_secs_f64();
            let si = super::critical_report::si_unit(plan, names.0);
            print(args, (&boundary, &why), names, point, si, seconds)?;
            Ok(None)
        }
        Decided::Shortcut { answer, confirmed } => Ok(Some((answer, confirmed.map(|c| c.line)))),
    }
}

/// Prints the runs' boundary (JSON with `--json`); an error naming the flag when it lies
/// outside the range.
fn print(
    args: &Args,
    (rb, why): (&RunBoundary, &Why),
    (param, name, flag): (BoundaryParam, &str, &str),
    point: State,
    si: Option<(&'static str, f64, &'static str)>,
    seconds: f64,
) -> anyhow::Result<()> {
    let (range, _) = args.range(param)?;
    let end = super::critical_report::end_words;
    let (lo, hi) = (
        end((flag, "lo"), range.lo, si),
        end((flag, "hi"), rb.bracket[1], si),
    );
    match rb.status {
        BoundaryStatus::Found => {}
        BoundaryStatus::BelowRange => {
            bail!(
                "{lo}: every start settles there already (runs to t = {}); lower --{flag}-lo",
                rb.horizon
            )
        }
        _ => bail!(
            "{hi}: a start still does not settle there (runs to t = {}); raise --{flag}-hi",
            rb.horizon
        ),
    }
    if args.json {
        return print_json((rb, why), name, si, seconds);
    }
    let what = if args.fold {
        "fold (no sampled start squeals above it)".to_string()
    } else {
        format!(
            "critical value for ({}, {})",
            Number(point.x),
            Number(point.v)
        )
    };
    println!(
        "{what}: {name} = {:.6e}, interval [{:.6e}, {:.6e}] from runs ({} runs to t = {}, {:.2} s)",
        rb.value(),
        rb.interval[0],
        rb.interval[1],
        rb.runs,
        rb.horizon,
        seconds
    );
    println!("  by runs because {}", why.words());
    print_ends(args, rb, name);
    println!(
        "  {}",
        match (rb.half_dt_holds, rb.half_dt_bracket) {
            (Some(true), _) =>
                "at dt/2 the bracket holds (the same verdicts at both ends)".to_string(),
            (Some(false), Some([l, h])) =>
                format!("at dt/2 the boundary lies in [{l:.6e}, {h:.6e}]: the interval covers both"),
            _ => "at dt/2 the boundary lies beyond the range's end: the interval reaches it".into(),
        }
    );
    if rb.undecided > 0 {
        println!(
            "  {} of {} runs were undecided by t = {} (counted as not settling)",
            rb.undecided, rb.runs, rb.horizon
        );
    }
    if let Some((key, unit, units)) = si {
        println!(
            "  in SI units: {key} = {:.4} {units}, interval [{:.4}, {:.4}] {units}",
            Number(rb.value() * unit),
            Number(rb.interval[0] * unit),
            Number(rb.interval[1] * unit)
        );
    }
    Ok(())
}

/// The runs' boundary as one JSON object.
fn print_json(
    (rb, why): (&RunBoundary, &Why),
    name: &str,
    si: Option<(&'static str, f64, &'static str)>,
    seconds: f64,
) -> anyhow::Result<()> {
    let mut v = serde_json::to_value(rb)?;
    v["in"] = name.into();
    v[name] = rb.value().into();
    v["by"] = "runs".into();
    v["why_runs"] = why.words().into();
    v["seconds"] = seconds.into();
    if let Some((key, unit, units)) = si {
        v[key] = (rb.value() * unit).into();
        v[format!("{key}_interval")] = serde_json::json!(rb.interval.map(|x| x * unit));
        v[format!("{key}_units")] = units.into();
    }
    println!("{}", serde_json::to_string(&v)?);
    Ok(())
}

/// The runs at the bracket's two ends: what lasts below it (and the lasting oscillation's
/// shape), what settles above it.
fn print_ends(args: &Args, rb: &RunBoundary, name: &str) {
    let starts = if args.fold {
        "every start of the spread (rest and 12 around the fixed point)"
    } else {
        "the start"
    };
    if let (Some(b), Some(a)) = (&rb.below, &rb.above) {
        let lasting = match b.first_unsettled() {
            Some((i, f)) => format!("start {i} {}", f.words(rb.horizon)),
            None => "no start settles".into(),
        };
        println!(
            "  at {name} = {:.6e} {lasting}; at {:.6e} {starts} reaches the fixed point",
            b.value, a.value
        );
        if let Some((
            i,
            Fate::Lasts {
                lasting: Some(l), ..
            },
        )) = b.first_lasting()
        {
            println!(
                "  the lasting oscillation below: omega = {:.4} (in units of the natural frequency), x in [{:.4}, {:.4}], x' in [{:.4}, {:.4}]{}{} (start {i})",
                l.omega,
                l.x_range[0],
                l.x_range[1],
                l.v_range[0],
                l.v_range[1],
                if l.reversed {
                    ", overtakes the belt"
                } else {
                    ""
                },
                if l.stuck { ", sticks" } else { "" },
            );
        }
    }
}
