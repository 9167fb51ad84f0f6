//! The summary `squeal scan` prints (JSON with `--json`): each map's counts, checks, reasons,
//! transient squeal, cycle, landscape and basin stability.

use std::path::PathBuf;

use squeal_scan::Plan;

use super::common;
use super::map_words::{check_words, escape_words, landscape_json, landscape_words};

/// "256 x 128 cells" or "5000 random samples in [-2, 2] x [0, 2] (seed 1)".
pub fn layout(plan: &Plan) -> String {
    let g = &plan.map.grid;
    match &g.starts {
        squeal_scan::Starts::Sample(s) => format!(
            "{} random samples in x0 [{}, {}] x v0 [{}, {}] (seed {})",
            s.n, g.x0.min, g.x0.max, g.v0.min, g.v0.max, s.seed
        ),
        squeal_scan::Starts::Grid => format!("{} x {} cells", g.x0.count, g.v0.count),
    }
}

/// What the writer counted per map: the stored checks and the cells per reason.
pub struct Tallies<'a> {
    /// Each map's cells per label and basin stability.
    pub maps: &'a [squeal_scan::MapSummary],
    pub checks: &'a [Vec<i64>],
    pub reasons: &'a [[u64; squeal_core::Reason::ALL.len()]],
    /// Steady-slip cells with `t_squeal > 0`, per map.
    pub transient: &'a [u64],
}

/// Each reason's share of a map's cells, largest first ("start_in_region 61.2%, ...").
fn reason_words(counts: &[u64]) -> String {
    let total = counts.iter().sum::<u64>().max(1) as f64;
    let mut named: Vec<_> = squeal_core::Reason::ALL
        .iter()
        .zip(counts)
        .filter(|(_, n)| **n > 0)
        .collect();
    named.sort_by(|a, b| b.1.cmp(a.1));
    let parts: Vec<_> = named
        .iter()
        .map(|(r, n)| format!("{} {:.1}%", r.name(), 100.0 * **n as f64 / total))
        .collect();
    format!("reasons: {}", parts.join(", "))
}

/// Map `i` of a finished scan as one JSON object: its counts, checks, reasons, transient
/// squeal, cycle, landscape and basin stability.
fn map_json(
    plan: &Plan,
    info: &squeal_store::FileInfo,
    tallies: &Tallies,
    i: usize,
) -> anyhow::Result<serde_json::Value> {
    let names = squeal_scan::MapSummary::COUNT_NAMES;
    let (c, checks) = (&tallies.maps[i].counts, tallies.checks);
    let mut o = serde_json::Map::new();
    for (name, vals) in info.sweep.iter().flat_map(|s| &s.keys) {
        o.insert(name.clone(), vals[i].into());
    }
    // A physical scan's swept keys as given, by their `[physical]` names.
    let si: serde_json::Map<_, _> = (info.sweep.iter().flat_map(|s| s.si.iter().flatten()))
        .map(|t| (t.key.clone(), t.values[i].into()))
        .collect();
    if !si.is_empty() {
        o.insert("si".into(), si.into());
    }
    o.insert(
        "steady_slip_stability".into(),
        serde_json::to_value(squeal_core::SteadySlip::of(&plan.maps[i]))?,
    );
    for (k, n) in names.iter().zip(c) {
        o.insert((*k).into(), (*n).into());
    }
    let vals = checks.get(i).cloned().unwrap_or_default();
    let ws = (vals.first().copied().unwrap_or(-1) >= 0)
        .then(|| serde_json::json!({"cells": vals[0], "beyond_pixel": vals[1]}));
    o.insert("wrong_side".into(), serde_json::to_value(ws)?);
    let mut ck = serde_json::Map::new();
    for ((name, _), v) in squeal_scan::checks::CHECK_FIELDS.iter().zip(&vals) {
        ck.insert((*name).into(), (*v).into());
    }
    o.insert("checks".into(), ck.into());
    if let Some(counts) = tallies.reasons.get(i) {
        let by_name: serde_json::Map<_, _> = squeal_core::Reason::ALL
            .iter()
            .zip(counts)
            .map(|(r, n)| (r.name().to_string(), (*n).into()))
            .collect();
        o.insert("reasons".into(), by_name.into());
    }
    if let Some(n) = tallies.transient.get(i) {
        o.insert("transient_squeal_cells".into(), (*n).into());
    }
    if let Some(Some(why)) = info.no_cycle.get(i) {
        o.insert("no_cycle".into(), why.clone().into());
    }
    if let Some(Some(r)) = info.escape.get(i) {
        o.insert("escape".into(), (*r).into());
    }
    if !info.landscapes.is_empty() {
        o.insert(
            "landscape".into(),
            landscape_json(info.landscapes.get(i).and_then(Option::as_ref)),
        );
    }
    if let Some(m) = tallies.maps.get(i) {
        o.insert("basin_stability".into(), common::basin_json(&m.basin));
    }
    if let Some(v) = info.sensitivity.get(i) {
        o.insert("sensitivity".into(), common::sensitivity_json(v));
    }
    Ok(serde_json::Value::Object(o))
}

/// Map `i` of a finished scan in words.
fn print_map(plan: &Plan, info: &squeal_store::FileInfo, tallies: &Tallies, i: usize) {
    let (c, checks) = (&tallies.maps[i].counts, tallies.checks);
    let label = info.sweep.as_ref().map_or(String::new(), |s| {
        let each = (s.keys.iter().zip(&s.si)).map(|((n, v), si)| match si {
            Some(t) => format!("{n} = {:<10.4e} ({}) ", v[i], t.words(i)),
            None => format!("{n} = {:<10.4e} ", v[i]),
        });
        each.collect()
    });
    let mut line = format!(
        "  {label}steady_slip {:>7}  stick_slip {:>7}  undecided {:>5}",
        c[1], c[2], c[0]
    );
    if c[4] > 0 {
        line += &format!("  slip_oscillation {}", c[4]);
    }
    if c[3] > 0 {
        line += &format!("  not_computed {}", c[3]);
    }
    println!("{line}");
    if let Some(m) = tallies.maps.get(i) {
        println!("    {}", common::basin_words(&m.basin));
    }
    if let Some(v) = info.sensitivity.get(i) {
        for w in squeal_scan::sensitivity::words(v) {
            println!("    {w}");
        }
    }
    let time_unit = plan.physical().map(|ph| ph.scales().time);
    println!(
        "    {}",
        squeal_core::SteadySlip::of(&plan.maps[i]).words(time_unit)
    );
    if let Some(Some(why)) = info.no_cycle.get(i) {
        println!("    no unstable cycle: {why}");
    }
    if let Some(Some(r)) = info.escape.get(i) {
        println!("    {}", escape_words(*r));
    }
    if let Some(Some(l)) = info.landscapes.get(i) {
        for w in landscape_words(l) {
            println!("    {w}");
        }
    }
    let sample = plan.map.grid.is_sample();
    for w in checks
        .get(i)
        .map(|c| check_words(c, sample))
        .unwrap_or_default()
    {
        println!("    {w}");
    }
    if let Some(counts) = tallies.reasons.get(i) {
        println!("    {}", reason_words(counts));
    }
    if let Some(n) = tallies.transient.get(i).filter(|n| **n > 0) {
        println!(
            "    transient squeal: {n} steady-slip cells stuck before they settled (t_squeal > 0)"
        );
    }
}

/// Prints the summary of a finished scan: `computed` cells in `secs` seconds (none for a
/// scan already up to date), the `pictures` written.
pub fn report(
    json: bool,
    plan: &Plan,
    info: &squeal_store::FileInfo,
    tallies: Tallies,
    pictures: &[PathBuf],
    computed: usize,
    secs: f64,
) -> anyhow::Result<()> {
    let rate = computed as f64 / secs.max(1e-9);
    // Rules whose premise a census run or an audit refuted, withdrawn from their maps:
    // one line each, `map M: ... withdrawn: why` (the file's `rules_withdrawn`).
    let withdrawn: Vec<&str> = info
        .attrs
        .iter()
        .find(|(k, _)| k == "rules_withdrawn")
        .map_or_else(Vec::new, |(_, v)| v.lines().collect());
    if json {
        let maps: Vec<_> = (0..info.maps)
            .map(|i| map_json(plan, info, &tallies, i))
            .collect::<anyhow::Result<_>>()?;
        let v = serde_json::json!({
            "output": info.path,
            "pictures": pictures,
            "maps": maps,
            "rules_withdrawn": withdrawn,
            "cells_computed": computed,
            "seconds": secs,
            "cells_per_second": rate,
        });
        println!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(());
    }
    println!(
        "{}: {} map(s) of {} -> {}",
        plan.name,
        plan.maps.len(),
        layout(plan),
        info.path.display()
    );
    for i in 0..info.maps {
        print_map(plan, info, &tallies, i);
    }
    for w in &withdrawn {
        println!("  rule withdrawn, its cells decided by runs: {w}");
    }
    if computed > 0 {
        println!("  {computed} cells in {secs:.2} s: {rate:.0} cells/s");
    }
    for p in pictures {
        println!("  picture: {}", p.display());
    }
    Ok(())
}
