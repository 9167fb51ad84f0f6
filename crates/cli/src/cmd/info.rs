//! `squeal info FILE.h5`: what a file squeal wrote holds: a scan's parameters and label
//! counts, an atlas's parameters, axes, points per regime and boundaries, a trajectory's
//! settings and samples.

use std::fmt::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use squeal_store::FileKind;

use super::common;

/// Flags of `squeal info`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// A file squeal wrote (scan, atlas or trajectory).
    pub file: PathBuf,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
}

/// Prints the file's description: every kind of file squeal writes.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    // The description is written whole at the end: a reader that stops early (`squeal info
    // f.h5 | head`) made the next line's print panic on the closed pipe.
    let mut o = String::new();
    match squeal_store::file_kind(&args.file)? {
        FileKind::Scan => scan(&args, &mut o)?,
        FileKind::Atlas => atlas(&args, &mut o)?,
        FileKind::Trajectory => trajectory(&args, &mut o)?,
    }
    if !args.json {
        friction_table(&squeal_store::friction_tables(&args.file)?, &mut o)?;
    }
    common::print_to_reader(&o)?;
    Ok(ExitCode::SUCCESS)
}

/// Writes the JSON description `v` of `args.file` with the friction table it stores
/// ([`table_json`]): `info --json` says what `info` prints.
fn write_json(mut v: serde_json::Value, args: &Args, o: &mut String) -> anyhow::Result<()> {
    v["friction_table"] = table_json(&squeal_store::friction_tables(&args.file)?);
    writeln!(o, "{}", serde_json::to_string_pretty(&v)?)?;
    Ok(())
}

/// A file's friction table as JSON (`null` for a law without one): `mu` per row, the slip
/// speeds in the model's units (`slip_speed`, absent in a physical atlas, whose points each
/// have their own velocity unit) and in m/s (`slip_speed_si`, a physical system's).
fn table_json((nd, si): &squeal_store::FrictionTables) -> serde_json::Value {
    let Some(t) = si.or(*nd) else {
        return serde_json::Value::Null;
    };
    serde_json::json!({
        "mu": t.coefficients(),
        "slip_speed": nd.map(|t| t.slip_speeds().to_vec()),
        "slip_speed_si": si.map(|t| t.slip_speeds().to_vec()),
    })
}

/// Root attributes as one JSON object.
fn attrs_json(attrs: &[(String, String)]) -> serde_json::Value {
    attrs
        .iter()
        .map(|(k, v)| (k.clone(), v.clone().into()))
        .collect::<serde_json::Map<_, _>>()
        .into()
}

/// Root attributes in words, one a line (the spec's text apart: it is long).
fn print_attrs(o: &mut String, attrs: &[(String, String)]) -> std::fmt::Result {
    for (k, v) in attrs {
        if k != "spec" {
            writeln!(o, "  {k} = {v}")?;
        }
    }
    Ok(())
}

/// Most rows `squeal info` prints of a friction table; a longer one is summarised.
const TABLE_ROWS_SHOWN: usize = 12;

/// The friction table of a table-law file (nothing for the other laws): its rows when few
/// ([`TABLE_ROWS_SHOWN`]), else their count and ranges; slip speeds in the model's units
/// and, for a physical system, in m/s.
fn friction_table((nd, si): &squeal_store::FrictionTables, o: &mut String) -> std::fmt::Result {
    let Some(t) = si.or(*nd) else {
        return Ok(());
    };
    let rows = t.rows().len();
    let mu = t.coefficients();
    let lo = mu.iter().copied().fold(f64::INFINITY, f64::min);
    let speeds = |t: &squeal_core::FrictionTable| t.slip_speeds().to_vec();
    let (nd, si) = (nd.map(speeds), si.map(speeds));
    let columns = match (&nd, &si) {
        (Some(_), Some(_)) => "slip speed in m/s, in the model's units, mu",
        (None, Some(_)) => "slip speed in m/s, mu",
        _ => "slip speed in the model's units, mu",
    };
    // As the error messages write values: a slip speed of 1e300 was written in 301 digits.
    let n = squeal_core::error::Number;
    let last = |s: &Option<Vec<f64>>| s.as_ref().map(|s| n(s[s.len() - 1]));
    if rows > TABLE_ROWS_SHOWN {
        let to = match (last(&si), last(&nd)) {
            (Some(a), Some(b)) => format!("{a} m/s ({b} in the model's units)"),
            (Some(a), None) => format!("{a} m/s"),
            (None, b) => format!("{} (the model's units)", b.unwrap_or(n(0.0))),
        };
        return writeln!(
            o,
            "  friction table: {rows} rows, slip speed 0 to {to}, mu {} at rest, in [{}, {}]",
            n(mu[0]),
            n(lo),
            n(t.max_mu())
        );
    }
    writeln!(o, "  friction table: {rows} rows ({columns}):")?;
    for (i, m) in mu.iter().enumerate() {
        let cells: Vec<String> = [&si, &nd]
            .into_iter()
            .flatten()
            .map(|s| n(s[i]).to_string())
            .chain([n(*m).to_string()])
            .collect();
        writeln!(o, "    {}", cells.join(", "))?;
    }
    Ok(())
}

/// An atlas file: its parameters, axes, points per regime and boundaries found, in the
/// words (and JSON) of `squeal atlas`.
fn atlas(args: &Args, o: &mut String) -> anyhow::Result<()> {
    let a = squeal_store::read_atlas_info(&args.file)?;
    let attr = |k: &str| a.attrs.iter().find(|(n, _)| n == k).map(|(_, v)| v.clone());
    if args.json {
        let mut v = crate::atlas_json::atlas_json(&a.plan, &a.results);
        v["path"] = args.file.display().to_string().into();
        v["squeal_version"] = attr("squeal_version").into();
        v["git_revision"] = attr("git_revision").into();
        v["attributes"] = attrs_json(&a.attrs);
        v["shard"] = a.shard.map(|s| s.to_string()).into();
        write_json(v, args, o)?;
        return Ok(());
    }
    writeln!(
        o,
        "{} ({}, squeal {} at {})",
        args.file.display(),
        squeal_store::atlas::ATLAS_SCHEMA,
        attr("squeal_version").unwrap_or_default(),
        attr("git_revision").unwrap_or_default()
    )?;
    print_attrs(o, &a.attrs)?;
    super::atlas_words::print_summary(&a.plan, &a.results, &args.file, None);
    if let Some(s) = a.shard {
        writeln!(o, "  shard {s} (join the shards with squeal merge)")?;
    }
    Ok(())
}

/// A scan file: parameters, grid, label counts and checks per map.
fn scan(args: &Args, o: &mut String) -> anyhow::Result<()> {
    let info = squeal_store::read_info(&args.file)?;
    let maps = common::map_summaries(&info)?;
    if args.json {
        let v = scan_json(&info, &maps);
        write_json(v, args, o)?;
        return Ok(());
    }
    writeln!(
        o,
        "{} ({}, squeal {} at {})",
        info.path.display(),
        info.schema,
        info.version,
        info.git_revision
    )?;
    print_attrs(o, &info.attrs)?;
    // As the error messages write values: `1e-7`, not `0.0000001`.
    let range = |a: &[f64]| match (a.first(), a.last()) {
        (Some(&lo), Some(&hi)) => format!(
            "{} values in [{}, {}]",
            a.len(),
            squeal_core::error::Number(lo),
            squeal_core::error::Number(hi)
        ),
        _ => "no values".to_string(),
    };
    if common::attr(&info, "sampling") == Some("random") {
        writeln!(
            o,
            "  {} random samples (x0, v0 stored per sample)",
            info.x0.len()
        )?;
    } else {
        writeln!(o, "  grid: x0 {}, v0 {}", range(&info.x0), range(&info.v0))?;
    }
    for i in 0..maps.len() {
        map_lines(&info, &maps, i, o)?;
    }
    if let Some(s) = &info.shard {
        writeln!(o, "  shard {s} (join the shards with squeal merge)")?;
    }
    Ok(())
}

/// Map `i` of a scan file in words: its counts, basin stability, final-state
/// sensitivity, cycle, landscape and checks.
fn map_lines(
    info: &squeal_store::FileInfo,
    maps: &[squeal_scan::MapSummary],
    i: usize,
    o: &mut String,
) -> anyhow::Result<()> {
    let c = maps[i].counts;
    let label = info.sweep.as_ref().map_or(String::new(), |s| {
        // A physical scan's key as given beside the model's: `nu = 7.9057e-3 (c = 5 N s/m)`.
        let each: Vec<_> = (s.keys.iter().zip(&s.si))
            .map(|((n, v), si)| match si {
                Some(t) => format!("{n} = {:.4e} ({})", v[i], t.words(i)),
                None => format!("{n} = {:.4e}", v[i]),
            })
            .collect();
        each.join(", ") + ": "
    });
    let slip = (c[4] > 0).then(|| format!("  slip_oscillation {}", c[4]));
    let [u, st, sk, nc] = [c[0], c[1], c[2], c[3]];
    let line = format!("undecided {u}  steady_slip {st}  stick_slip {sk}  not_computed {nc}");
    writeln!(o, "  {label}{line}{}", slip.unwrap_or_default())?;
    if let Some(b) = maps.get(i).map(|m| &m.basin) {
        writeln!(o, "    {}", super::common::basin_words(b))?;
    }
    for w in info
        .sensitivity
        .get(i)
        .map(|v| squeal_scan::sensitivity::words(v))
        .unwrap_or_default()
    {
        writeln!(o, "    {w}")?;
    }
    if let Some(Some(why)) = info.no_cycle.get(i) {
        writeln!(o, "    no unstable cycle: {why}")?;
    }
    if let Some(Some(l)) = info.landscapes.get(i) {
        for w in super::map_words::landscape_words(l) {
            writeln!(o, "    {w}")?;
        }
    }
    for w in info
        .checks
        .get(i)
        .map(|c| super::map_words::check_words(c, common::attr(info, "sampling") == Some("random")))
        .unwrap_or_default()
    {
        writeln!(o, "    {w}")?;
    }
    Ok(())
}

/// A trajectory file of `squeal trajectory --out X.h5`.
fn trajectory(args: &Args, o: &mut String) -> anyhow::Result<()> {
    let t = squeal_store::read_trajectory_info(&args.file)?;
    if args.json {
        let attrs = attrs_json(&t.attrs);
        let v = serde_json::json!({
            "path": args.file,
            "attributes": attrs,
            "samples": t.samples,
            "t": t.t_range.map(|(a, b)| [a, b]),
            "variables": t.variables,
        });
        write_json(v, args, o)?;
        return Ok(());
    }
    writeln!(o, "{} (trajectory)", args.file.display())?;
    for (k, v) in &t.attrs {
        writeln!(o, "  {k} = {v}")?;
    }
    match t.t_range {
        Some((a, b)) => writeln!(
            o,
            "  {} samples, t in [{}, {}]",
            t.samples,
            squeal_core::error::Number(a),
            squeal_core::error::Number(b)
        )?,
        None => writeln!(o, "  no samples")?,
    }
    writeln!(o, "  variables over t: {}", t.variables.join(", "))?;
    Ok(())
}

/// A scan file as one JSON object.
fn scan_json(info: &squeal_store::FileInfo, maps: &[squeal_scan::MapSummary]) -> serde_json::Value {
    let names = squeal_scan::MapSummary::COUNT_NAMES;
    let attrs = attrs_json(&info.attrs);
    let counts: Vec<serde_json::Value> = maps
        .iter()
        .map(|m| &m.counts)
        .map(|c| {
            names
                .iter()
                .zip(c)
                .map(|(k, n)| ((*k).to_string(), (*n).into()))
                .collect::<serde_json::Map<_, _>>()
                .into()
        })
        .collect();
    serde_json::json!({
        "path": info.path,
        "schema": info.schema,
        "squeal_version": info.version,
        "git_revision": info.git_revision,
        "attributes": attrs,
        // One swept key: its name and values (as before sweeps of every key); several:
        // each key with its value at every map. A physical scan's keys carry the
        // `[physical]` key each stands for, as given (`si`: key, units, values).
        "sweep": info.sweep.as_ref().map(|s| {
            let key = |(n, v): &(String, Vec<f64>), si: &Option<squeal_store::SweptSi>| {
                let mut k = serde_json::json!({"name": n, "values": v});
                if let Some(t) = si {
                    k["si"] = serde_json::json!({"key": t.key, "units": t.units, "values": t.values});
                }
                k
            };
            match s.keys.as_slice() {
                [one] => key(one, &s.si[0]),
                all => serde_json::json!({"keys": all.iter().zip(&s.si)
                    .map(|(k, si)| key(k, si)).collect::<Vec<_>>()}),
            }
        }),
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
        "landscape": info.landscapes.iter().map(|l| super::map_words::landscape_json(l.as_ref())).collect::<Vec<_>>(),
        "basin_stability": maps.iter().map(|m| super::common::basin_json(&m.basin)).collect::<Vec<_>>(),
        "sensitivity": info.sensitivity.iter().map(|v| super::common::sensitivity_json(v)).collect::<Vec<_>>(),
        "shard": info.shard,
    })
}
