//! What `squeal critical` prints (JSON with `--json`): the critical damping, a boundary
//! found by the atlas's searches, or the crisis of the stick-slip band, in SI units too for a
//! physical system, with loud warnings where the coarse scan saw more than one change.

use anyhow::bail;
use squeal_core::State;
use squeal_core::error::Number;
use squeal_scan::band::{Crisis, CrisisStatus};
use squeal_scan::lifetime::LifetimeTable;
use squeal_scan::section::{Change, ParamRange};
use squeal_scan::ulc;

use super::critical_args::Args;
use super::critical_runs::Confirmed;
use super::lifetimes;

/// The coarse scan's changes in words, when there is more than one: the bisection assumes a
/// single change of regime, so several are said loudly (on stdout with the result, and on
/// stderr).
pub(super) fn warn_changes(changes: &[Change], name: &str) -> Option<String> {
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
        "WARNING: the regime changes {} times along {name} ({} geometric steps over the range): {}; the bisection found one of them",
        changes.len(),
        squeal_scan::band::COARSE,
        list.join(", ")
    );
    eprintln!("{w}");
    Some(w)
}

/// Prints the critical damping (JSON with `--json`), in SI units too for a physical system.
pub(super) fn report(
    args: &Args,
    rep: &ulc::CriticalReport,
    point: State,
    (key, scales): (&str, Option<squeal_core::Scales>),
    (seconds, confirmed): (f64, Option<&Confirmed>),
    changes: &[Change],
) -> anyhow::Result<()> {
    let warning = warn_changes(changes, key);
    if args.json {
        let mut v = serde_json::to_value(rep)?;
        v["seconds"] = seconds.into();
        v["coarse_changes"] = serde_json::to_value(changes)?;
        Confirmed::put_json(confirmed, &mut v);
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
            Number(point.x),
            Number(point.v),
            key,
            rep.nu,
            rep.bracket[0],
            rep.bracket[1],
            rep.evaluations,
            seconds
        );
        println!(
            "  below it no unstable cycle encloses ({}, {}) (it lies outside the cycle, or the fixed point repels) and the band above does not leak: that start squeals (or, where the band's verdict is marginal, may); above it the start is inside the cycle or the band leaks: steady slip",
            Number(point.x),
            Number(point.v)
        );
        for l in confirmed.map(Confirmed::lines).unwrap_or_default() {
            println!("  {l}");
        }
        if let Some(w) = warning {
            println!("  {w}");
        }
        if let Some(s) = scales {
            println!(
                "  in SI units: c = {:.4} N s/m, bracket [{:.4}, {:.4}] N s/m, for the start x0 = {} m, v0 = {} m/s",
                Number(rep.nu * s.damping),
                Number(rep.bracket[0] * s.damping),
                Number(rep.bracket[1] * s.damping),
                Number(args.x0),
                Number(args.v0)
            );
        }
    }
    Ok(())
}

/// A physical system's name, scale and units for a boundary in `param`: the damping in
/// N s/m (c), the belt speed in m/s (v_belt).
pub(super) fn si_unit(
    plan: &squeal_scan::Plan,
    param: squeal_scan::atlas::BoundaryParam,
) -> Option<(&'static str, f64, &'static str)> {
    plan.physical().map(|ph| {
        let (unit, units) = param.si(&ph.scales());
        (param.physical_key(), unit, units)
    })
}

/// The end `value` of the bracket flag `--{flag}-{end}` in words, with the value of the
/// physical key it stands for where the system was given in SI units (`si`: key, scale,
/// units): "--nu-hi 0.05 (c = 40 N s/m)". A brake given in N s/m was told of `--nu-hi
/// 0.05` alone, a number in units it never used.
pub(super) fn end_words(
    (flag, end): (&str, &str),
    value: f64,
    si: Option<(&'static str, f64, &'static str)>,
) -> String {
    match si {
        Some((key, unit, units)) => format!(
            "--{flag}-{end} {} ({key} = {} {units})",
            Number(value),
            Number(value * unit)
        ),
        None => format!("--{flag}-{end} {}", Number(value)),
    }
}

/// A boundary found by `critical` (the critical value, or the fold of a law without a crisis),
/// for its two reports.
pub(super) struct BoundaryFound<'a> {
    pub(super) b: &'a squeal_scan::atlas::Boundary,
    /// The runs' confirmation at the bracket's ends (`None`: not found).
    pub(super) confirmed: Option<&'a Confirmed>,
    /// The bisected parameter's name and flag.
    pub(super) name: &'a str,
    pub(super) flag: &'a str,
    pub(super) range: (f64, f64),
    pub(super) seconds: f64,
    pub(super) changes: &'a [Change],
    pub(super) si: Option<(&'static str, f64, &'static str)>,
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
        Confirmed::put_json(self.confirmed, &mut v);
        if let Some((key, unit, units)) = self.si {
            v[key] = (b.nu * unit).into();
            v[format!("{key}_bracket")] = serde_json::json!(b.bracket.map(|x| x * unit));
            v[format!("{key}_units")] = units.into();
        }
        Ok(v)
    }

    /// Prints the boundary: JSON with `--json`, else in words.
    pub(super) fn report(&self, args: &Args, point: State) -> anyhow::Result<()> {
        if args.json {
            println!("{}", serde_json::to_string(&self.json()?)?);
            return Ok(());
        }
        self.print(args, point)
    }

    /// The boundary in words; an error naming the flag when it lies outside the range.
    fn print(&self, args: &Args, point: State) -> anyhow::Result<()> {
        use squeal_scan::atlas::BoundaryStatus;
        let (b, name, flag) = (self.b, self.name, self.flag);
        // Exponent form for the flags' huge or tiny values (1e300, not 301 digits).
        let (lo, hi) = (Number(self.range.0), Number(self.range.1));
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
                    Number(point.x),
                    Number(point.v)
                ),
            )
        };
        let nothing = if args.fold {
            "nothing squeals there already".to_string()
        } else {
            format!(
                "({}, {}) is quiet there already",
                Number(point.x),
                Number(point.v)
            )
        };
        let (lo, hi) = (
            end_words((flag, "lo"), lo.0, self.si),
            end_words((flag, "hi"), hi.0, self.si),
        );
        match b.status {
            BoundaryStatus::Found => {}
            BoundaryStatus::BelowRange => bail!("{lo}: {nothing}; lower --{flag}-lo"),
            _ => bail!("{hi}: it still squeals there; raise --{flag}-hi"),
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
        for l in self.confirmed.map(Confirmed::lines).unwrap_or_default() {
            println!("  {l}");
        }
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

/// An error naming the flag of the range's end when the crisis `c` was not found in it.
pub(super) fn found(range: ParamRange, flag: &str, c: &Crisis) -> anyhow::Result<()> {
    let (lo, hi) = (Number(range.lo), Number(range.hi));
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

/// A crisis found by `critical` (`--crisis`, `--fold` of McMillan's laws), for its two
/// reports: the coarse scan's warning and the lifetimes table beside it.
pub(super) struct CrisisFound<'a> {
    pub(super) c: &'a Crisis,
    /// `--fold`: the runs' confirmation at the ends of its interval.
    pub(super) confirmed: Option<&'a Confirmed>,
    /// The bisected parameter's name.
    pub(super) name: &'a str,
    pub(super) seconds: f64,
    pub(super) si: Option<(&'static str, f64, &'static str)>,
    pub(super) warning: Option<String>,
    pub(super) table: Option<LifetimeTable>,
}

impl CrisisFound<'_> {
    /// Prints the crisis (JSON with `--json`): the fold with its uncertainty, the bracket at
    /// dt, whether it held at dt/2 and with the longer horizon, and loudly every change of
    /// regime the coarse scan found when there is more than one.
    pub(super) fn print(&self, json: bool, plan: &squeal_scan::Plan) -> anyhow::Result<()> {
        let CrisisFound {
            c,
            name,
            seconds,
            si,
            ..
        } = *self;
        let (warning, table) = (&self.warning, &self.table);
        if json {
            let mut v = serde_json::to_value(c)?;
            // The bracket at dt under the name `--fold` gave it before (the atlas's fold_nu_lo/hi).
            v["bracket"] = serde_json::to_value(c.interval)?;
            v["in"] = name.into();
            v["seconds"] = seconds.into();
            Confirmed::put_json(self.confirmed, &mut v);
            if let Some(t) = table {
                v["lifetimes"] = lifetimes::json(t, plan)?;
            }
            if let Some((key, unit, units)) = si {
                v["si"] = serde_json::json!({
                    key: c.nu * unit,
                    format!("{key}_uncertainty"): c.uncertainty * unit,
                    "units": units,
                });
            }
            println!("{}", serde_json::to_string(&v)?);
            return Ok(());
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
        for l in self.confirmed.map(Confirmed::lines).unwrap_or_default() {
            println!("  {l}");
        }
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
            lifetimes::print(t, plan);
        }
        Ok(())
    }
}
