//! `squeal critical --crisis --lifetimes`: the transient lifetimes of the leaking band above
//! the crisis (library: `squeal_scan::lifetime`), in words and JSON.

use squeal_scan::band::Crisis;
use squeal_scan::lifetime::{DISTANCE_FACTORS, LifetimeSettings, LifetimeTable, lifetime_table};
use squeal_scan::ulc::CycleSettings;

use super::critical_args::Args;

/// The table at the crisis `c` of map `map`.
pub fn table(
    args: &Args,
    plan: &squeal_scan::Plan,
    map: usize,
    c: &Crisis,
) -> anyhow::Result<LifetimeTable> {
    let ls = LifetimeSettings {
        starts: args.starts,
        t_max: args.lifetime_t_max,
        ..LifetimeSettings::default()
    };
    Ok(lifetime_table(
        plan.setup(map),
        &CycleSettings::default(),
        &ls,
        (c.nu, c.uncertainty),
        &DISTANCE_FACTORS,
    )?)
}

/// The seconds of one nondimensional time unit of a physical system.
fn time_unit(plan: &squeal_scan::Plan) -> Option<f64> {
    plan.physical().map(|ph| ph.scales().time)
}

/// The table as JSON (times nondimensional; `time_unit_s` for a physical system).
pub fn json(t: &LifetimeTable, plan: &squeal_scan::Plan) -> anyhow::Result<serde_json::Value> {
    let mut v = serde_json::to_value(t)?;
    v["time_units"] = "nondimensional (natural period 2 pi)".into();
    if let Some(s) = time_unit(plan) {
        v["time_unit_s"] = s.into();
    }
    Ok(v)
}

/// The table in words.
pub fn print(t: &LifetimeTable, plan: &squeal_scan::Plan) {
    println!(
        "transient lifetimes above the crisis (t_squeal of {} starts spread over the band above the unstable cycle; nondimensional time, natural period 2 pi):",
        t.rows
            .first()
            .map_or(0, |r| r.lifetime.exits + r.lifetime.censored)
    );
    println!("  nu            nu - nu_c     mean lifetime   +- se        exits  censored  range");
    for r in &t.rows {
        let l = &r.lifetime;
        let num = |x: Option<f64>| x.map_or("-".to_string(), |v| format!("{v:.4e}"));
        let range = l
            .range
            .map_or("-".into(), |[a, b]| format!("[{a:.1}, {b:.1}]"));
        println!(
            "  {:.6e}  {:.3e}     {:<14}  {:<11}  {:>5}  {:>8}  {range}",
            r.nu,
            r.nu - t.nu_c,
            num(l.mean),
            num(l.se),
            l.exits,
            l.censored
        );
    }
    for (nu, why) in &t.skipped {
        println!("  {nu:.6e}  skipped: {why}");
    }
    match &t.fit {
        Some(f) => {
            let ends = t
                .exponent_at_crisis_ends
                .map(|e| e.map_or("-".into(), |g| format!("{g:.3}")));
            println!(
                "  power law <t> ~ (nu - nu_c)^(-gamma), fitted where <t> > {} periods: gamma = {:.3} +- {:.3} ({} points); with nu_c at the ends of its uncertainty ({:.6e}, {:.6e}): gamma = {}, {}",
                squeal_scan::lifetime::FIT_MIN_PERIODS,
                f.exponent,
                f.se,
                f.points,
                t.nu_c - t.nu_c_uncertainty,
                t.nu_c + t.nu_c_uncertainty,
                ends[0],
                ends[1]
            );
        }
        None => println!("  power law: fewer than two dampings with a mean lifetime, no fit"),
    }
    if let Some(s) = time_unit(plan) {
        println!("  one time unit is {s:.4e} s");
    }
}
