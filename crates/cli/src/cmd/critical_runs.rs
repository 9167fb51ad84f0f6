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
use squeal_scan::sensitivity::StepShare;

use super::critical_args::Args;

/// The runs' confirmation of a shortcut's answer as the reports print it: their line and
/// the step sensitivity of the starts at the bracket's ends.
pub(super) struct Confirmed {
    /// The runs in words ([`squeal_scan::fates::Confirmation::line`]).
    pub(super) line: String,
    /// The starts whose fate moves at dt/2.
    pub(super) step: Option<StepShare>,
}

impl Confirmed {
    /// The line, then the step sensitivity's (with its warning where not small).
    pub(super) fn lines(&self) -> Vec<String> {
        let mut out = vec![self.line.clone()];
        out.extend(step_lines(self.step));
        out
    }

    /// `confirmed_by_runs` and the step sensitivity's figures in `v` (null without `c`).
    pub(super) fn put_json(c: Option<&Confirmed>, v: &mut serde_json::Value) {
        v["confirmed_by_runs"] = c.map(|c| c.line.clone()).into();
        step_json(v, c.and_then(|c| c.step));
    }
}

/// The gate's answer `d`: where it is the runs', printed (`None`); else the shortcut's
/// answer and its runs' confirmation, for the caller's report.
pub(super) fn shortcut_or_print<T>(
    args: &Args,
    d: Decided<T>,
    plan: &squeal_scan::Plan,
    names: (BoundaryParam, &str, &str),
    (point, t0): (State, std::time::Instant),
) -> anyhow::Result<Option<(T, Option<Confirmed>)>> {
    match d {
        Decided::Runs { boundary, why } => {
            let boundary = &*boundary;
            let seconds = t0.elapsed().as_secs_f64();
            let si = super::critical_report::si_unit(plan, names.0);
            let about = About::of(plan, boundary);
            print(args, (boundary, &why, &about), names, point, si, seconds)?;
            Ok(None)
        }
        Decided::Shortcut { answer, confirmed } => Ok(Some((
            answer,
            confirmed.map(|c| Confirmed {
                line: c.line,
                step: Some(c.step),
            }),
        ))),
    }
}

/// Prints the runs' boundary (JSON with `--json`); an error naming the flag when it lies
/// outside the range.
fn print(
    args: &Args,
    (rb, why, about): (&RunBoundary, &Why, &About),
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
        return print_json((rb, why, about), name, si, seconds);
    }
    print_heading(args, (rb, about), (name, point), seconds);
    println!("  by runs because {}", why.words());
    print_ends(args, rb, name, about);
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
    for line in step_lines(rb.step) {
        println!("  {line}");
    }
    if rb.undecided > 0 {
        println!(
            "  {} of {} runs were undecided by t = {} (neither quiet nor squealing identifiably){}",
            rb.undecided,
            rb.runs,
            rb.horizon,
            match about.upper_bound {
                true => ": the lower end of the bracket is one of them",
                false => "; neither end of the bracket rests on one",
            }
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

/// The answer's first lines: steady slip's stability at it, and the value (or the bound).
fn print_heading(
    args: &Args,
    (rb, about): (&RunBoundary, &About),
    (name, point): (&str, State),
    seconds: f64,
) {
    println!(
        "{name} = {:.6e}: {}",
        rb.value(),
        about.steady.words(about.time_unit)
    );
    if !about.steady.stability.attracts() {
        println!(
            "  so a start ends on an oscillation, and the question is which: the answer below is \
             where the squeal (the sticking oscillation) stops"
        );
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
    match about.upper_bound {
        false => println!(
            "{what}: {name} = {:.6e}, interval [{:.6e}, {:.6e}] from runs ({} runs to t = {}, {:.2} s)",
            rb.value(),
            rb.interval[0],
            rb.interval[1],
            rb.runs,
            rb.horizon,
            seconds
        ),
        true => println!(
            "{what}: {name} <= {:.6e}, an upper bound from runs ({} runs to t = {}, {:.2} s): \
             below it a run was undecided by the horizon, not seen squealing",
            rb.interval[1], rb.runs, rb.horizon, seconds
        ),
    }
}

/// The runs' boundary as one JSON object.
fn print_json(
    (rb, why, about): (&RunBoundary, &Why, &About),
    name: &str,
    si: Option<(&'static str, f64, &'static str)>,
    seconds: f64,
) -> anyhow::Result<()> {
    let mut v = serde_json::to_value(rb)?;
    v["in"] = name.into();
    v[name] = rb.value().into();
    v["by"] = "runs".into();
    v["why_runs"] = why.words().into();
    v["about"] = "the sticking oscillation (the squeal)".into();
    v["upper_bound_only"] = about.upper_bound.into();
    v["steady_slip"] = serde_json::to_value(about.steady)?;
    v["slip_oscillation_above"] = serde_json::to_value(&about.slip)?;
    v["seconds"] = seconds.into();
    step_json(&mut v, rb.step);
    if let Some((key, unit, units)) = si {
        v[key] = (rb.value() * unit).into();
        v[format!("{key}_interval")] = serde_json::json!(rb.interval.map(|x| x * unit));
        v[format!("{key}_units")] = units.into();
    }
    println!("{}", serde_json::to_string(&v)?);
    Ok(())
}

/// The step sensitivity of the starts at the bracket's ends ([`RunBoundary::step`]) in
/// words, with [`squeal_scan::sensitivity::StepShare::warning`] where it is not small.
fn step_lines(step: Option<StepShare>) -> Vec<String> {
    let Some(s) = step else {
        return Vec::new();
    };
    let mut out = vec![format!(
        "step sensitivity near the answer: {} of {} starts at the bracket's ends change fate at dt/2 ({:.1}% +- {:.1}%)",
        s.changed,
        s.compared,
        100.0 * s.share,
        100.0 * s.se
    )];
    out.extend(s.warning(squeal_scan::sensitivity::StepOf::Answer));
    out
}

/// The step sensitivity's figures in `v` (null where not checked at dt/2): the share, its
/// standard error, and the starts changed and compared, as Python's `critical()` names them.
fn step_json(v: &mut serde_json::Value, s: Option<StepShare>) {
    v["step_sensitivity"] = s.map(|s| s.share).into();
    v["step_sensitivity_se"] = s.map(|s| s.se).into();
    v["step_sensitivity_changed"] = s.map(|s| s.changed).into();
    v["step_sensitivity_compared"] = s.map(|s| s.compared).into();
}

/// What the answer is about: steady slip's stability at it, the slip oscillation that
/// the start ends on above it (where steady slip does not attract), and whether the bracket's
/// lower end rests on an undecided run (then the answer is an upper bound).
struct About {
    steady: squeal_core::SteadySlip,
    time_unit: Option<f64>,
    slip: Option<SlipOscillation>,
    upper_bound: bool,
}

/// The small slip oscillation about an unstable steady slip, as a run ended on it.
#[derive(serde::Serialize)]
struct SlipOscillation {
    /// The value of the parameter.
    value: f64,
    /// Its angular frequency (units of the natural frequency).
    omega: f64,
    /// Half the range of `x` (nondimensional).
    half_range_x: f64,
    /// Its range of `x'`.
    v_range: [f64; 2],
    /// In a physical system: the frequency (Hz) and the half-range of `x` (m).
    frequency_hz: Option<f64>,
    half_range_x_m: Option<f64>,
}

impl About {
    fn of(plan: &squeal_scan::Plan, rb: &RunBoundary) -> About {
        let params = rb.param.with(plan.maps[0], rb.value());
        let scales = plan.physical().map(|ph| ph.scales());
        let slip = rb.above.as_ref().and_then(|a| {
            let (_, f) = a.first_slip_oscillation()?;
            let Fate::SlipOscillation {
                lasting: Some(l), ..
            } = f
            else {
                return None;
            };
            let half = 0.5 * (l.x_range[1] - l.x_range[0]);
            Some(SlipOscillation {
                value: a.value,
                omega: l.omega,
                half_range_x: half,
                v_range: l.v_range,
                frequency_hz: scales.map(|s| s.hz(l.omega)),
                half_range_x_m: scales.map(|s| half * s.length),
            })
        });
        let upper_bound = rb
            .below
            .as_ref()
            .and_then(|b| b.first_unsettled())
            .is_some_and(|(_, f)| matches!(f, Fate::Undecided));
        About {
            steady: squeal_core::SteadySlip::of(&params),
            time_unit: scales.map(|s| s.time),
            slip,
            upper_bound,
        }
    }
}

/// The runs at the bracket's two ends: what lasts below it (and the lasting oscillation's
/// shape), what ends quiet above it (the fixed point, or the slip oscillation about an
/// unstable steady slip, with its size and frequency).
fn print_ends(args: &Args, rb: &RunBoundary, name: &str, about: &About) {
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
        let quiet = match a.first_slip_oscillation() {
            Some(_) => "ends quiet (at the fixed point, or on the small slip oscillation about it)",
            None => "reaches the fixed point",
        };
        println!(
            "  at {name} = {:.6e} {lasting}; at {:.6e} {starts} {quiet}",
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
        if let Some(sl) = &about.slip {
            let si = match (sl.frequency_hz, sl.half_range_x_m) {
                (Some(f), Some(x)) => format!(" ({} Hz, half-range {} m)", Number(f), Number(x)),
                _ => String::new(),
            };
            println!(
                "  the slip oscillation above: omega = {:.4}, half-range of x {:.4e}, x' in [{:.4e}, {:.4e}]{si}; it never sticks: not the squeal",
                sl.omega, sl.half_range_x, sl.v_range[0], sl.v_range[1]
            );
        }
    }
}
