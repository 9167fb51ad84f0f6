//! `squeal atlas SPEC.toml`: figures of merit over a design space, regimes, the fold of
//! cycles and the critical damping, into an HDF5 file and a chart.
//!
//! Like make, and by the scan's rule ([`common::up_to_date`]): a rerun of a finished atlas
//! from the same (parsed) spec, with or without `--resume`, draws a missing picture, prints
//! the summary and exits 0; a different spec is refused naming `--force`.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use anyhow::{Context, bail};
use indicatif::{ProgressBar, ProgressDrawTarget};
use serde_json::{Value, json};
use squeal_plot::{Curve, Rgb};
use squeal_scan::atlas::columns::{COLUMNS, Si};
use squeal_scan::atlas::{AtlasPlan, AtlasRegime, BoundaryStatus, Units};
use squeal_store::atlas::{AtlasResults, AtlasWriter, read_atlas};

use super::common;

/// Flags of `squeal atlas`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The atlas spec (TOML; see scans/atlas-*.toml).
    pub spec: PathBuf,
    #[command(flatten)]
    pub run: super::common::RunArgs,
    /// Do not draw the chart.
    #[arg(long)]
    pub no_render: bool,
    /// Print every point's figures as one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Start an atlas estimated to take more than 30 days.
    #[arg(long)]
    pub allow_long: bool,
}

/// Counts finished map blocks on the progress bar (and the plain lines off a terminal).
struct BarObserver<'a>(&'a ProgressBar, &'a Option<common::PlainLines>);

impl squeal_scan::Observer for BarObserver<'_> {
    fn block_done(&self, _map: usize, _block: usize) {
        self.0.inc(1);
        if let Some(p) = self.1 {
            p.inc();
        }
    }
}

/// Runs the atlas.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let plan = AtlasPlan::from_file(&args.spec)?;
    let (out, shard) = args.run.setup(&plan.out)?;
    let png = common::sibling(&out, "", "png");
    let pics = if shard.is_none() && !args.no_render {
        pictures(&plan, &png)
    } else {
        Vec::new()
    };
    let render = !pics.is_empty();
    // Like make (the same rule as the scan's): a finished output of the same parsed spec
    // (and shard) is up to date; a picture missing is drawn again.
    let state = squeal_store::output_state(&out, &plan, shard)?;
    if common::up_to_date(&out, state, &args.run, &pics, || {
        render_atlas(&out, &png, true)
    })? {
        let (plan, res, _) = read_atlas(&out)?;
        report(&args, &plan, &res, &out, Computed::default(), &pics)?;
        return Ok(ExitCode::SUCCESS);
    }
    if !args.run.resume {
        for p in &pics {
            let what = if *p == png {
                "chart of the atlas"
            } else {
                "sheet of basin maps"
            };
            common::check_new(p, args.run.force, what)?;
        }
    }
    squeal_store::OutputLock::check_free(&out)?;
    estimate(&args, &plan)?;
    let prov = common::provenance();
    let writer = if args.run.resume {
        AtlasWriter::resume(&out, &plan, shard, &prov)?
    } else {
        AtlasWriter::create(&out, &plan, shard, &prov, args.run.force)?
    };
    let todo = writer.missing();
    let todo_blocks = writer.missing_blocks().len();

    let stop = Arc::new(AtomicBool::new(false));
    common::install_signals(&stop, "units and map blocks")?;
    let total = (todo.len() + todo_blocks) as u64;
    let bar = progress(total, args.run.quiet);
    let plain = common::PlainLines::new("units and map blocks", "unit", total, args.run.quiet);
    let t0 = Instant::now();
    let result = squeal_store::run_atlas(
        &plan,
        shard,
        writer,
        &stop,
        &|| {
            bar.inc(1);
            if let Some(p) = &plain {
                p.inc();
            }
        },
        &BarObserver(&bar, &plain),
    );
    bar.finish_and_clear();
    let (writer, left) = result?;
    let seconds = t0.elapsed().as_secs_f64();
    if stop.load(Ordering::SeqCst) && left > 0 {
        eprintln!(
            "squeal: interrupted; {left} units and map blocks left. Finish with: {}",
            args.run.resume_command("atlas", &args.spec, &out)
        );
        return Ok(ExitCode::from(common::EXIT_INTERRUPTED));
    }
    let res = writer.finish()?;
    let pictures = if render {
        render_atlas(&out, &png, true)?
    } else {
        Vec::new()
    };
    let computed = Computed {
        seconds,
        units: todo.len(),
        blocks: todo_blocks,
    };
    report(&args, &plan, &res, &out, computed, &pictures)?;
    Ok(ExitCode::SUCCESS)
}

/// The work, estimated from a pilot before anything is created (printed unless quiet); over
/// [`common::LONG_RUN`] it needs `--allow-long`. The whole atlas is estimated, also for a
/// shard or a resume (an upper bound then).
fn estimate(args: &Args, plan: &AtlasPlan) -> anyhow::Result<()> {
    let threads = rayon::current_num_threads();
    let e = squeal_scan::estimate::atlas_pilot(plan)?;
    let secs = e.seconds(plan, threads);
    let maps = plan.map_plan().map_or(String::new(), |mp| {
        format!(", {} map cells", mp.grid.cells() * mp.maps.len())
    });
    let what = format!(
        "{} points, {} boundary searches{maps}",
        plan.n_points(),
        plan.n_boundaries()
    );
    if secs > common::LONG_RUN && !args.allow_long {
        bail!(
            "the atlas ({what}) would take roughly {} on {threads} thread(s): shrink the sweep or the maps, split it with --shard, or pass --allow-long",
            common::duration(secs)
        );
    }
    if !args.run.quiet {
        eprintln!(
            "squeal: atlas of {what} on {threads} thread(s): roughly {} ({secs:.1} s), from a pilot of {} point(s) in {:.1} s",
            common::duration(secs),
            e.points,
            e.pilot_seconds
        );
    }
    Ok(())
}

/// The progress bar over `total` units and map blocks (hidden when quiet or not a terminal).
fn progress(total: u64, quiet: bool) -> ProgressBar {
    ProgressBar::with_draw_target(
        Some(total),
        if common::show_progress(quiet) {
            ProgressDrawTarget::stderr()
        } else {
            ProgressDrawTarget::hidden()
        },
    )
    .with_style(common::bar_style(
        "atlas [{bar:40}] {pos}/{len} units and map blocks  {avg_rate}  ETA {avg_eta}",
        "unit",
    ))
}

/// The pictures of a finished atlas whose chart is `png`: the chart (one or two swept
/// parameters: a bifurcation diagram or a stability chart), then with maps their sheet.
fn pictures(plan: &AtlasPlan, png: &Path) -> Vec<PathBuf> {
    let chartable = matches!(plan.axes().len(), 1 | 2);
    let mut v = Vec::new();
    if chartable {
        v.push(png.to_path_buf());
    }
    if plan.maps.is_some() {
        v.push(sheet_path(png));
    }
    v
}

/// What a run computed (nothing for an output already up to date).
#[derive(Clone, Copy, Debug, Default)]
struct Computed {
    seconds: f64,
    units: usize,
    blocks: usize,
}

/// The summary of a finished atlas, in words or as one JSON object.
fn report(
    args: &Args,
    plan: &AtlasPlan,
    res: &AtlasResults,
    out: &Path,
    computed: Computed,
    pictures: &[PathBuf],
) -> anyhow::Result<()> {
    if args.json {
        let mut v = atlas_json(plan, res);
        v["file"] = out.display().to_string().into();
        v["seconds"] = computed.seconds.into();
        v["units_computed"] = computed.units.into();
        v["map_blocks_computed"] = computed.blocks.into();
        println!("{}", serde_json::to_string(&v)?);
    } else {
        let ran =
            (computed.units + computed.blocks > 0).then_some((computed.seconds, computed.units));
        print_summary(plan, res, out, ran);
        for p in pictures {
            println!("{}", p.display());
        }
    }
    Ok(())
}

fn num(v: f64) -> Value {
    if v.is_finite() { json!(v) } else { Value::Null }
}

/// Every point and boundary as JSON (nondimensional figures, and SI ones for physical
/// specs), with the coordinates of each.
pub fn atlas_json(plan: &AtlasPlan, res: &AtlasResults) -> Value {
    let axes: Vec<Value> = plan
        .axes()
        .iter()
        .map(|a| json!({"key": a.key, "long_name": a.long_name, "units": a.units, "values": a.values}))
        .collect();
    let fixed: serde_json::Map<String, Value> = plan
        .fixed()
        .iter()
        .map(|(a, v)| (a.key.to_string(), json!({"value": v, "units": a.units})))
        .collect();
    let points: Vec<Value> = res
        .points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let values = plan.values_at(i);
            let coords: serde_json::Map<String, Value> = plan
                .params
                .iter()
                .zip(&values)
                .filter(|(a, _)| a.values.len() > 1)
                .map(|(a, v)| (a.key.to_string(), json!(v)))
                .collect();
            let q = plan.params_at(i);
            let mut o = json!({
                "index": i,
                "coords": coords,
                "params": q.named().iter().map(|n| (n.name.to_string(), json!(n.value))).collect::<serde_json::Map<_, _>>(),
            });
            let Some(p) = p else {
                o["regime"] = "not_computed".into();
                return o;
            };
            o["regime"] = p.regime.name().into();
            o["operating_point_squeals"] = json!(p.regime.operating_point_squeals());
            o["note"] = json!(p.note);
            let scales = plan.physical_at(i).map(|ph| ph.scales());
            let mut si = serde_json::Map::new();
            for c in COLUMNS {
                let v = (c.get)(p);
                o[c.name] = num(v);
                if let (Some(s), true) = (scales, c.si != Si::None) {
                    si.insert(
                        c.name.to_string(),
                        json!({"value": num(c.si.convert(v, &s)), "units": c.si.units()}),
                    );
                }
            }
            if scales.is_some() {
                o["si"] = Value::Object(si);
            }
            if let Some(l) = p.landscape {
                // Laws with true stick: the landscape beside the section search's figures,
                // and the share of time stuck under its own name.
                use squeal_scan::atlas::stribeck::{LANDSCAPE_COLUMNS, STUCK_SHARE};
                let mut e = serde_json::Map::new();
                e.insert(
                    "landscape".into(),
                    l.verdict().map_or("unknown", |v| v.name()).into(),
                );
                for c in LANDSCAPE_COLUMNS {
                    e.insert(c.name.into(), num((c.get)(p)));
                }
                o["landscape"] = Value::Object(e);
                if let Some(v) = o.as_object_mut().and_then(|m| m.remove("stick_quasi_static_share")) {
                    o[STUCK_SHARE.0] = v;
                }
            }
            if plan.maps.is_some() {
                // The reported basin fraction is the map's; the cycle's is kept beside it.
                o["basin_fraction_cycle"] = o["basin_fraction"].clone();
                o["basin_fraction_cycle_err"] = o["basin_fraction_err"].clone();
                let f = res.map_fraction(plan, i);
                o["basin_fraction"] = num(f.map_or(f64::NAN, |f| f.fraction));
                o["basin_fraction_err"] = num(f.map_or(f64::NAN, |f| f.err));
                o["basin_fraction_source"] = "map".into();
                if let Some(f) = f {
                    o["map"] = json!({
                        "cells": f.cells,
                        "steady_slip": f.steady,
                        "stick_slip": f.stick,
                        "undecided": f.undecided,
                        "near_cycle": f.near_cycle,
                        "cycle_r_section": num(res.map_cycle(i).map_or(f64::NAN, |r| r.r_section)),
                    });
                }
            }
            o
        })
        .collect();
    let boundaries: Vec<Value> = res
        .boundaries
        .iter()
        .enumerate()
        .map(|(j, b)| {
            let (i, range) = plan.boundary_setup(j);
            let values = plan.values_at(i);
            let (dkey, _) = plan.boundary_axis();
            let bkey = plan.boundary_key();
            let coords: serde_json::Map<String, Value> = plan
                .params
                .iter()
                .zip(&values)
                .filter(|(a, _)| a.values.len() > 1 && a.key != dkey)
                .map(|(a, v)| (a.key.to_string(), json!(v)))
                .collect();
            let mut o = json!({"index": j, "coords": coords, "in": bkey,
                format!("{bkey}_range"): range});
            if let Some(b) = b {
                o["note"] = json!(b.note);
                for (name, bd) in [("fold", b.fold), ("critical", b.critical)] {
                    let mut e = json!({
                        "status": bd.status.name(),
                        bkey: num(bd.nu),
                        "bracket": [num(bd.bracket[0]), num(bd.bracket[1])],
                        "evaluations": bd.evaluations,
                        "half_dt_holds": bd.half_dt_holds,
                    });
                    if let Some((v, units)) = plan.boundary_si(i, bd.nu) {
                        let si = |x| plan.boundary_si(i, x).map_or(f64::NAN, |(y, _)| y);
                        e[format!("{dkey}_si")] = json!({"value": num(v), "units": units,
                            "bracket": [num(si(bd.bracket[0])), num(si(bd.bracket[1]))]});
                    }
                    o[name] = e;
                }
            }
            o
        })
        .collect();
    json!({
        "schema": squeal_store::atlas::ATLAS_SCHEMA,
        "name": plan.name,
        "law": plan.law.name(),
        "units": plan.units.name(),
        "axes": axes,
        "fixed": fixed,
        "operating_point": {"x": plan.point.operating.x, "v": plan.point.operating.v},
        "disturbance": {"x": plan.point.disturbance.x, "v": plan.point.disturbance.v,
            "x_units": plan.disturbance_units()[0], "v_units": plan.disturbance_units()[1]},
        "points": points,
        "boundaries": boundaries,
        "scheme": plan.solver.scheme.name(),
        "maps": plan.maps.map(|m| json!({
            "x0": {"min": m.grid.x0.min, "max": m.grid.x0.max, "count": m.grid.x0.count},
            "v0": {"min": m.grid.v0.min, "max": m.grid.v0.max, "count": m.grid.v0.count},
            "block_rows": m.grid.block_rows,
            "early_stop": m.early_stop.name(),
        })),
    })
}

/// The atlas in words: its axes, the points per regime, the maps and the boundaries found,
/// then the file. `computed` is what this run computed (none: the line says nothing of it).
pub fn print_summary(
    plan: &AtlasPlan,
    res: &AtlasResults,
    out: &Path,
    computed: Option<(f64, usize)>,
) {
    let axes = plan.axes();
    let over = if axes.is_empty() {
        "1 parameter point (nothing swept: no chart; the figures are below and in the file)"
            .to_string()
    } else {
        format!(
            "{} points over {}",
            plan.n_points(),
            axes.iter()
                .map(|a| format!("{} ({} values)", a.key, a.values.len()))
                .collect::<Vec<_>>()
                .join(" x ")
        )
    };
    println!(
        "atlas {}: {} law, {over}{}",
        plan.name,
        plan.law,
        computed.map_or(String::new(), |(seconds, units)| format!(
            ", {units} units computed in {seconds:.1} s"
        ))
    );
    for r in AtlasRegime::ALL {
        let n = res
            .points
            .iter()
            .filter(|p| p.as_ref().is_some_and(|p| p.regime == r))
            .count();
        if n > 0 {
            println!("  {:>6} points: {}", n, r.description());
        }
    }
    if let Some(m) = &plan.maps {
        println!(
            "  basin maps: {} x {} cells per point; basin fraction of steady slip from the maps",
            m.grid.x0.count, m.grid.v0.count
        );
    }
    let (dkey, _) = plan.boundary_axis();
    let bkey = plan.boundary_key();
    let shown = res.boundaries.len().min(12);
    if shown > 0 {
        println!(
            "  boundaries in the {} (first {shown} of {}):",
            plan.boundary_words(),
            res.boundaries.len()
        );
    }
    for (j, b) in res.boundaries.iter().enumerate().take(shown) {
        let Some(b) = b else { continue };
        let (i, _) = plan.boundary_setup(j);
        let at: Vec<String> = plan
            .params
            .iter()
            .zip(plan.values_at(i))
            .filter(|(a, _)| a.values.len() > 1 && a.key != dkey)
            .map(|(a, v)| {
                format!(
                    "{} = {v:.4} {}",
                    a.key,
                    if a.units == "1" { "" } else { a.units }
                )
            })
            .collect();
        let show = |bd: &squeal_scan::atlas::Boundary| {
            let half = match bd.half_dt_holds {
                Some(true) => "",
                Some(false) => " [moves at dt/2]",
                None => " [dt/2 not checked]",
            };
            match bd.status {
                BoundaryStatus::Found => match plan.boundary_si(i, bd.nu) {
                    Some((v, u)) => {
                        format!("{bkey} = {:.5} ({dkey} = {v:.4} {u}){half}", bd.nu)
                    }
                    None => format!("{bkey} = {:.5}{half}", bd.nu),
                },
                s => s.name().to_string(),
            }
        };
        println!(
            "    {}: fold {}, critical {}",
            if at.is_empty() {
                "here".into()
            } else {
                at.join(", ")
            },
            show(&b.fold),
            show(&b.critical)
        );
    }
    println!("{}", out.display());
}

/// Regime colours, in the order of the enum, and `not computed`.
pub fn regime_classes() -> Vec<(u8, &'static str, Rgb)> {
    vec![
        (
            AtlasRegime::FixedPointUnstable as u8,
            AtlasRegime::FixedPointUnstable.description(),
            Rgb(200, 40, 40),
        ),
        (
            AtlasRegime::BistableSqueals as u8,
            AtlasRegime::BistableSqueals.description(),
            squeal_plot::STICK,
        ),
        (
            AtlasRegime::BistableQuiet as u8,
            AtlasRegime::BistableQuiet.description(),
            Rgb(140, 190, 235),
        ),
        (
            AtlasRegime::SteadySlipOnly as u8,
            AtlasRegime::SteadySlipOnly.description(),
            squeal_plot::STEADY,
        ),
        (
            AtlasRegime::Undecided as u8,
            AtlasRegime::Undecided.description(),
            squeal_plot::UNDECIDED,
        ),
        (255, "not computed", squeal_plot::NOT_COMPUTED),
    ]
}

fn is_log(v: &[f64]) -> bool {
    v.len() > 2 && v.iter().all(|&x| x > 0.0) && {
        let r0 = v[1] / v[0];
        let d0 = v[1] - v[0];
        let geo = v
            .windows(2)
            .all(|w| ((w[1] / w[0]) / r0 - 1.0).abs() < 1e-6);
        let lin = v
            .windows(2)
            .all(|w| ((w[1] - w[0]) / d0 - 1.0).abs() < 1e-6);
        geo && !lin
    }
}

fn axis_label(a: &squeal_scan::atlas::AtlasAxis) -> String {
    if a.units == "1" {
        a.long_name.to_string()
    } else {
        format!("{} ({})", a.long_name, a.units)
    }
}

fn title(plan: &AtlasPlan, what: Option<&str>) -> String {
    let fixed: Vec<String> = plan
        .fixed()
        .iter()
        .map(|(a, v)| {
            let u = if a.units == "1" {
                String::new()
            } else {
                format!(" {}", a.units)
            };
            format!("{} = {}{u}", a.key, squeal_plot::fmt_value(*v))
        })
        .collect();
    // The spec's name first (docs/atlas-spec.md: "used in titles").
    match what {
        Some(w) => format!("{}: {} law, {w}; {}", plan.name, plan.law, fixed.join(", ")),
        None => format!("{}: {} law; {}", plan.name, plan.law, fixed.join(", ")),
    }
}

/// The sheet of basin maps of an atlas whose chart is `png`: `<stem>-maps.png`.
pub fn sheet_path(png: &Path) -> PathBuf {
    common::sibling(png, "-maps", "png")
}

/// Draws the pictures of an atlas file: a stability chart (2-D), a bifurcation diagram
/// (1-D), and with maps a sheet of them ([`sheet_path`]). Returns the files written.
pub fn render_atlas(h5: &Path, png: &Path, force: bool) -> anyhow::Result<Vec<PathBuf>> {
    let (plan, res, _) = read_atlas(h5)?;
    let chartable = matches!(plan.axes().len(), 1 | 2);
    if !chartable && plan.maps.is_none() {
        bail!(
            "{}: {} swept parameters; charts are drawn for 1 (bifurcation diagram) or 2 (stability chart); read the file with h5py/xarray",
            h5.display(),
            plan.axes().len()
        )
    }
    let mut drawn = Vec::new();
    if chartable {
        common::check_new(png, force, "chart")?;
        // A chart cut short (a full disk) is removed, so no later run takes it as drawn.
        draw_chart(&plan, &res, png).map_err(|e| common::discard(png, e))?;
        drawn.push(png.to_path_buf());
    }
    if plan.maps.is_some() {
        let sheet = sheet_path(png);
        common::check_new(&sheet, force, "sheet of basin maps")?;
        draw_sheet(&plan, &res, &sheet).map_err(|e| common::discard(&sheet, e))?;
        drawn.push(sheet);
    }
    Ok(drawn)
}

/// Panels per axis of a sheet of maps at most (1-D: `MAX_PANELS_1D` in all).
const MAX_PANELS_AXIS: usize = 6;
const MAX_PANELS_1D: usize = 24;

/// `m` indices of `0..n`, evenly spread, first and last included.
fn pick(n: usize, m: usize) -> Vec<usize> {
    if n <= m {
        return (0..n).collect();
    }
    let mut v: Vec<usize> = (0..m)
        .map(|k| ((k * (n - 1)) as f64 / (m - 1) as f64).round() as usize)
        .collect();
    v.dedup();
    v
}

fn value_text(a: &squeal_scan::atlas::AtlasAxis, v: f64) -> String {
    let u = if a.units == "1" {
        String::new()
    } else {
        format!(" {}", a.units)
    };
    format!("{} = {}{u}", a.key, squeal_plot::fmt_number(v))
}

/// The sheet of basin maps laid out over the parameter grid: one row of panels per value
/// of the first swept parameter and one column per value of the second (1-D: the values in
/// reading order), at most 6 per axis (24 in 1-D), evenly spread with both ends; further
/// axes at their first value. The title says which were drawn.
fn draw_sheet(plan: &AtlasPlan, res: &AtlasResults, png: &Path) -> anyhow::Result<()> {
    let Some(m) = &plan.maps else {
        return Ok(());
    };
    let g = m.grid;
    let axes = plan.axes();
    let shape = plan.shape();
    // The drawn indices per axis.
    let picks: Vec<Vec<usize>> = shape
        .iter()
        .enumerate()
        .map(|(k, &n)| match (axes.len(), k) {
            (1, _) => pick(n, MAX_PANELS_1D),
            (_, 0 | 1) => pick(n, MAX_PANELS_AXIS),
            _ => vec![0],
        })
        .collect();
    let mut points: Vec<Vec<usize>> = vec![vec![]];
    for p in &picks {
        points = points
            .into_iter()
            .flat_map(|pre| {
                p.iter().map(move |&i| {
                    let mut v = pre.clone();
                    v.push(i);
                    v
                })
            })
            .collect();
    }
    let flat = |idx: &[usize]| idx.iter().zip(&shape).fold(0, |acc, (i, n)| acc * n + i);
    let x0 = g.x0.values();
    let v0 = g.v0.values();
    let scale = squeal_plot::StateScale::of_law(plan.law.name());
    let data: Vec<(usize, Vec<u8>)> = points
        .iter()
        .map(|idx| {
            let i = flat(idx);
            let labels = res.map_cells(plan, i).map_or_else(
                || vec![squeal_scan::cell::NOT_COMPUTED; g.cells()],
                |c| c.iter().map(|c| c.regime).collect(),
            );
            (i, labels)
        })
        .collect();
    let panels: Vec<squeal_plot::BasinPanel> = data
        .iter()
        .map(|(i, labels)| {
            let values = plan.values_at(*i);
            let swept: Vec<(&squeal_scan::atlas::AtlasAxis, f64)> = plan
                .params
                .iter()
                .zip(&values)
                .filter(|(a, _)| a.values.len() > 1)
                .map(|(a, &v)| (a, v))
                .collect();
            // Only the parameters that differ between panels (axes 0 and 1).
            let title = swept
                .iter()
                .enumerate()
                .filter(|(k, _)| picks[*k].len() > 1)
                .map(|(_, (a, v))| value_text(a, *v))
                .collect::<Vec<_>>()
                .join(", ");
            let overlays = res
                .map_cycle(*i)
                .map(|r| squeal_plot::cycle_overlay(&r.curve.x, &r.curve.v))
                .into_iter()
                .collect();
            let fp = plan.params_at(*i).fixed_point();
            squeal_plot::BasinPanel {
                axis_labels: Some(scale.initial_labels().map(String::from)),
                title: if title.is_empty() {
                    plan.name.clone()
                } else {
                    title
                },
                x0: &x0,
                v0: &v0,
                labels,
                overlays,
                markers: squeal_plot::state_markers((fp.x, fp.v), &x0, &v0),
            }
        })
        .collect();
    let drawn: Vec<String> = axes
        .iter()
        .zip(&picks)
        .map(|(a, p)| {
            let n = a.values.len();
            if p.len() == n {
                format!("{}: all {n} values", a.key)
            } else if p.len() == 1 {
                format!(
                    "{} at its first value {}",
                    a.key,
                    squeal_plot::fmt_number(a.values[0])
                )
            } else {
                format!("{}: {} of {n} values, evenly spread", a.key, p.len())
            }
        })
        .collect();
    let layout = match axes.len() {
        0 | 1 => String::new(),
        _ => format!("; rows: {}, columns: {}", axes[0].key, axes[1].key),
    };
    let title = format!(
        "{}: basins of attraction, {}, one map per parameter point\n{}, dt = {}, scheme {}\npanels: {}{layout}",
        plan.name,
        squeal_plot::law_title(plan.law.name()),
        title(plan, None)
            .split_once(": ")
            .map_or(String::new(), |(_, f)| f.to_string()),
        squeal_plot::fmt_number(plan.dt),
        plan.solver.scheme.name(),
        drawn.join("; "),
    );
    let ncols = match axes.len() {
        0 => 1,
        1 => (panels.len() as f64).sqrt().ceil() as usize,
        _ => picks[1].len(),
    };
    squeal_plot::basin_sheet(png, &title, &panels, &common::classes(), ncols)
        .with_context(|| format!("drawing {}", png.display()))?;
    Ok(())
}

/// Draws the chart: a stability chart (2-D) or a bifurcation diagram (1-D).
fn draw_chart(plan: &AtlasPlan, res: &AtlasResults, png: &Path) -> anyhow::Result<()> {
    let plan = plan.clone();
    let axes = plan.axes();
    let (dkey, dpos) = plan.boundary_axis();
    let bvals =
        |f: fn(&squeal_scan::atlas::BoundaryResult) -> squeal_scan::atlas::Boundary| -> Vec<f64> {
            res.boundaries
                .iter()
                .enumerate()
                .map(|(j, b)| {
                    b.as_ref().map_or(f64::NAN, |b| {
                        let bd = f(b);
                        if bd.status != BoundaryStatus::Found {
                            return f64::NAN;
                        }
                        plan.boundary_si(plan.boundary_setup(j).0, bd.nu)
                            .map_or(bd.nu, |(v, _)| v)
                    })
                })
                .collect()
        };
    match axes.len() {
        2 => {
            let (ya, xa) = (axes[0], axes[1]);
            let classes: Vec<u8> = res
                .points
                .iter()
                .map(|p| p.as_ref().map_or(255, |p| p.regime as u8))
                .collect();
            // Contours inside the bistable region only: elsewhere the fraction is 0 or 1 by
            // the regime, and contours would crowd along its edge. With maps, the map's.
            let field: Vec<f64> = res
                .points
                .iter()
                .enumerate()
                .map(|(i, p)| match p {
                    Some(p)
                        if matches!(
                            p.regime,
                            AtlasRegime::BistableQuiet | AtlasRegime::BistableSqueals
                        ) =>
                    {
                        res.basin_fraction(&plan, i).0
                    }
                    _ => f64::NAN,
                })
                .collect();
            let mut curves = Vec::new();
            let mut marks = Vec::new();
            if dpos.is_some() {
                for (label, color, bs) in [
                    (
                        "fold: above it no start squeals",
                        Rgb(0, 0, 0),
                        bvals(|b| b.fold),
                    ),
                    (
                        "critical: above it the operating point is quiet",
                        Rgb(120, 0, 160),
                        bvals(|b| b.critical),
                    ),
                ] {
                    // The boundary is a value of the y axis over x (bisected in the y
                    // parameter) or of the x axis over y.
                    if !bs.iter().any(|v| v.is_finite()) {
                        continue;
                    }
                    let (xs, ys) = if dpos == Some(0) {
                        (xa.values.clone(), bs)
                    } else {
                        (bs, ya.values.clone())
                    };
                    {
                        curves.push(Curve {
                            label: label.into(),
                            xs,
                            ys,
                            color,
                            points_only: false,
                        });
                    }
                }
                // Fold values whose bracket does not hold at dt / 2, marked.
                let fold = bvals(|b| b.fold);
                let moved: Vec<f64> = fold
                    .iter()
                    .zip(&res.boundaries)
                    .map(|(v, b)| match b {
                        Some(b) if b.fold.half_dt_holds == Some(false) => *v,
                        _ => f64::NAN,
                    })
                    .collect();
                if moved.iter().any(|v| v.is_finite()) {
                    let (xs, ys) = if dpos == Some(0) {
                        (xa.values.clone(), moved)
                    } else {
                        (moved, ya.values.clone())
                    };
                    // A diamond, not a line: the fold's own line runs under these points.
                    marks.push(squeal_plot::Marks {
                        label: "fold: bracket moves at dt/2".into(),
                        xs,
                        ys,
                        glyph: squeal_plot::Glyph::Diamond,
                        fill: Rgb(250, 220, 0),
                    });
                }
            }
            let op = plan.point.operating;
            let d = plan.point.disturbance;
            let (units, box_units) = match (plan.units, plan.disturbance_nondimensional) {
                (Units::Physical, false) => (" (m, m/s)", " (m, m/s)"),
                (Units::Physical, true) => (
                    " (m, m/s)",
                    " (nondimensional at each point: the default box)",
                ),
                _ => ("", ""),
            };
            let chart = squeal_plot::StabilityChart {
                title: title(&plan, Some("stability chart")),
                subtitle: format!(
                    "operating point ({}, {}){units}; basin fraction of steady slip over x in [{}, {}], x' in [{}, {}]{box_units}",
                    op.x, op.v, d.x[0], d.x[1], d.v[0], d.v[1]
                ),
                x_label: axis_label(xa),
                y_label: axis_label(ya),
                xs: &xa.values,
                ys: &ya.values,
                log_x: is_log(&xa.values),
                log_y: is_log(&ya.values),
                classes: &classes,
                palette: regime_classes(),
                field: Some(&field),
                levels: vec![0.25, 0.5, 0.75, 0.9],
                field_name: "basin fraction of steady slip".into(),
                curves,
                marks,
            };
            squeal_plot::stability_chart(png, &chart)
                .with_context(|| format!("drawing {}", png.display()))?;
        }
        1 => {
            let a = axes[0];
            let xs = a.values.clone();
            let phys = plan.units == Units::Physical;
            let scale = |i: usize, v: f64| match plan.physical_at(i) {
                Some(ph) => v * ph.scales().velocity,
                None => v,
            };
            let pick = |f: &dyn Fn(&squeal_scan::atlas::PointResult) -> f64| -> Vec<f64> {
                res.points
                    .iter()
                    .enumerate()
                    .map(|(i, p)| p.as_ref().map_or(f64::NAN, |p| scale(i, f(p))))
                    .collect()
            };
            let cyc = pick(&|p| p.cycle.map_or(f64::NAN, |c| c.r_section));
            let smin = pick(&|p| p.stick_slip.map_or(f64::NAN, |s| s.r_band[0]));
            let smean = pick(&|p| p.stick_slip.map_or(f64::NAN, |s| s.r_band[1]));
            let smax = pick(&|p| p.stick_slip.map_or(f64::NAN, |s| s.r_band[2]));
            let none: Vec<f64> = res
                .points
                .iter()
                .map(|p| match p {
                    Some(p) if p.cycle.is_none() => 0.0,
                    _ => f64::NAN,
                })
                .collect();
            let top = smax
                .iter()
                .chain(&cyc)
                .copied()
                .filter(|v| v.is_finite())
                .fold(0.0f64, f64::max);
            // Where no stick-slip oscillation exists beside it (steady slip only) the
            // unstable cycle bounds no basin: drawn apart, as grey dots.
            let only_steady = |i: usize| {
                res.points[i]
                    .as_ref()
                    .is_some_and(|p| p.regime == AtlasRegime::SteadySlipOnly)
            };
            let split = |keep: bool| -> Vec<f64> {
                cyc.iter()
                    .enumerate()
                    .map(|(i, &v)| if only_steady(i) == keep { v } else { f64::NAN })
                    .collect()
            };
            let (cyc_alone, cyc) = (split(true), split(false));
            let mut curves = vec![
                Curve {
                    label: "unstable cycle (basin boundary)".into(),
                    xs: xs.clone(),
                    ys: cyc,
                    color: Rgb(0, 0, 0),
                    points_only: false,
                },
                Curve {
                    label: "stick-slip: band max".into(),
                    xs: xs.clone(),
                    ys: smax,
                    color: squeal_plot::STICK,
                    points_only: false,
                },
                Curve {
                    label: "stick-slip: mean".into(),
                    xs: xs.clone(),
                    ys: smean,
                    color: Rgb(170, 70, 0),
                    points_only: true,
                },
                Curve {
                    label: "stick-slip: band min".into(),
                    xs: xs.clone(),
                    ys: smin,
                    color: squeal_plot::STICK,
                    points_only: false,
                },
            ];
            if cyc_alone.iter().any(|v| v.is_finite()) {
                curves.push(Curve {
                    label: "unstable cycle, no stick-slip beside it (no basin boundary)".into(),
                    xs: xs.clone(),
                    ys: cyc_alone,
                    color: Rgb(150, 150, 150),
                    points_only: true,
                });
            }
            if none.iter().any(|v| v.is_finite()) {
                curves.push(Curve {
                    label: "no unstable cycle (at 0)".into(),
                    xs: xs.clone(),
                    ys: none,
                    color: squeal_plot::STEADY,
                    points_only: true,
                });
            }
            if a.key == dkey {
                for (label, color, v) in [
                    (
                        "fold (no start squeals above)",
                        Rgb(0, 120, 0),
                        bvals(|b| b.fold),
                    ),
                    (
                        "critical (operating point quiet above)",
                        Rgb(120, 0, 160),
                        bvals(|b| b.critical),
                    ),
                ] {
                    if let Some(&x) = v.first().filter(|x| x.is_finite()) {
                        curves.push(Curve {
                            label: format!(
                                "{label}: {}{}",
                                squeal_plot::fmt_value(x),
                                if a.units == "1" {
                                    String::new()
                                } else {
                                    format!(" {}", a.units)
                                }
                            ),
                            xs: vec![x, x],
                            ys: vec![0.0, 1.05 * top.max(1e-12)],
                            color,
                            points_only: false,
                        });
                    }
                }
            }
            let y_label = if phys {
                "x' at the section x = x* (m/s)"
            } else {
                "x' at the section x = x* (nondimensional)"
            };
            squeal_plot::line_plot(
                png,
                &title(&plan, None),
                &axis_label(a),
                y_label,
                &curves,
                &[],
                is_log(&xs),
            )
            .with_context(|| format!("drawing {}", png.display()))?;
        }
        _ => {}
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::pick;

    #[test]
    fn sheet_panels_are_spread_evenly_with_both_ends() {
        assert_eq!(pick(4, 6), vec![0, 1, 2, 3]);
        // round(k * 47 / 5): 0, 9.4, 18.8, 28.2, 37.6, 47.
        assert_eq!(pick(48, 6), vec![0, 9, 19, 28, 38, 47]);
        assert_eq!(pick(7, 2), vec![0, 6]);
    }
}
