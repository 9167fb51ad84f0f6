//! `squeal info OUT.h5`: parameters and label counts of a scan file.

use std::path::PathBuf;
use std::process::ExitCode;

use super::common;

/// Flags of `squeal info`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// A scan file.
    pub file: PathBuf,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
}

/// Prints the file's description.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    if squeal_store::file_schema(&args.file).ok().as_deref()
        == Some(squeal_store::TRAJECTORY_SCHEMA)
    {
        return trajectory(&args);
    }
    let info = squeal_store::read_info(&args.file)?;
    let names = ["undecided", "steady_slip", "stick_slip", "not_computed"];
    if args.json {
        let attrs: serde_json::Map<String, serde_json::Value> = info
            .attrs
            .iter()
            .map(|(k, v)| (k.clone(), v.clone().into()))
            .collect();
        let counts: Vec<serde_json::Value> = info
            .counts
            .iter()
            .map(|c| {
                names
                    .iter()
                    .zip(c)
                    .map(|(k, n)| ((*k).to_string(), (*n).into()))
                    .collect::<serde_json::Map<_, _>>()
                    .into()
            })
            .collect();
        let v = serde_json::json!({
            "path": info.path,
            "schema": info.schema,
            "squeal_version": info.version,
            "git_revision": info.git_revision,
            "attributes": attrs,
            "sweep": info.sweep.as_ref().map(|(n, v)| serde_json::json!({"name": n, "values": v})),
            "x0": {"min": info.x0.first(), "max": info.x0.last(), "count": info.x0.len()},
            "v0": {"min": info.v0.first(), "max": info.v0.last(), "count": info.v0.len()},
            "counts": counts,
            "checks": info.checks.iter().map(|c| {
                squeal_scan::checks::CHECK_FIELDS
                    .iter()
                    .zip(c)
                    .map(|((n, _), v)| ((*n).to_string(), (*v).into()))
                    .collect::<serde_json::Map<_, _>>()
            }).collect::<Vec<_>>(),
            "no_cycle": info.no_cycle,
            "landscape": info.landscapes.iter().map(|l| super::scan::landscape_json(l.as_ref())).collect::<Vec<_>>(),
            "basin_stability": info.basin.iter().map(super::common::basin_json).collect::<Vec<_>>(),
            "shard": info.shard,
        });
        println!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(ExitCode::SUCCESS);
    }
    println!(
        "{} ({}, squeal {} at {})",
        info.path.display(),
        info.schema,
        info.version,
        info.git_revision
    );
    for (k, v) in &info.attrs {
        if k != "spec" {
            println!("  {k} = {v}");
        }
    }
    let range = |a: &[f64]| match (a.first(), a.last()) {
        (Some(lo), Some(hi)) => format!("{} values in [{lo}, {hi}]", a.len()),
        _ => "no values".to_string(),
    };
    if common::attr(&info, "sampling") == Some("random") {
        println!(
            "  {} random samples (x0, v0 stored per sample)",
            info.x0.len()
        );
    } else {
        println!("  grid: x0 {}, v0 {}", range(&info.x0), range(&info.v0));
    }
    for (i, c) in info.counts.iter().enumerate() {
        let label = info
            .sweep
            .as_ref()
            .map_or(String::new(), |(n, v)| format!("{n} = {:.4e}: ", v[i]));
        println!(
            "  {label}undecided {}  steady_slip {}  stick_slip {}  not_computed {}",
            c[0], c[1], c[2], c[3]
        );
        if let Some(b) = info.basin.get(i) {
            println!("    {}", super::common::basin_words(b));
        }
        if let Some(Some(why)) = info.no_cycle.get(i) {
            println!("    no unstable cycle: {why}");
        }
        if let Some(Some(l)) = info.landscapes.get(i) {
            for w in super::scan::landscape_words(l) {
                println!("    {w}");
            }
        }
        for w in info
            .checks
            .get(i)
            .map(|c| super::scan::check_words(c, common::attr(&info, "sampling") == Some("random")))
            .unwrap_or_default()
        {
            println!("    {w}");
        }
    }
    if let Some(s) = &info.shard {
        println!("  shard {s} (join the shards with squeal merge)");
    }
    Ok(ExitCode::SUCCESS)
}

/// A trajectory file of `squeal trajectory --out X.h5`.
fn trajectory(args: &Args) -> anyhow::Result<ExitCode> {
    let t = squeal_store::read_trajectory_info(&args.file)?;
    if args.json {
        let attrs: serde_json::Map<String, serde_json::Value> = t
            .attrs
            .iter()
            .map(|(k, v)| (k.clone(), v.clone().into()))
            .collect();
        let v = serde_json::json!({
            "path": args.file,
            "attributes": attrs,
            "samples": t.samples,
            "t": t.t_range.map(|(a, b)| [a, b]),
            "variables": t.variables,
        });
        println!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(ExitCode::SUCCESS);
    }
    println!("{} (trajectory)", args.file.display());
    for (k, v) in &t.attrs {
        println!("  {k} = {v}");
    }
    match t.t_range {
        Some((a, b)) => println!("  {} samples, t in [{a}, {b}]", t.samples),
        None => println!("  no samples"),
    }
    println!("  variables over t: {}", t.variables.join(", "));
    Ok(ExitCode::SUCCESS)
}
