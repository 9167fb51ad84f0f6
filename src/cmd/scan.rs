//! `squeal scan SPEC.toml`: the basin map(s) of a spec into an HDF5 file and a PNG.

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use anyhow::{Context, bail};
use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use squeal_scan::Plan;
use squeal_scan::scanner::{MapContext, Observer, run_block};
use squeal_store::{ScanWriter, Shard, shard_owns};

use super::common;

/// Flags of `squeal scan`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The scan spec (TOML; see scans/).
    pub spec: PathBuf,
    /// Output file (.h5); default: the spec's output.path.
    #[arg(short = 'o', long)]
    pub out: Option<PathBuf>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Finish an interrupted scan of the same spec.
    #[arg(long, conflicts_with = "force")]
    pub resume: bool,
    /// Overwrite an existing output (and discard an interrupted scan).
    #[arg(long)]
    pub force: bool,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// Run only shard K of N (1-based): its own file, joined later by `squeal merge`.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,
    /// Print the summary as one JSON object.
    #[arg(long)]
    pub json: bool,
}

struct Bars {
    overall: ProgressBar,
    map: Option<ProgressBar>,
}

impl Observer for Bars {
    fn cell_done(&self) {
        self.overall.inc(1);
        if let Some(m) = &self.map {
            m.inc(1);
        }
    }
}

/// Runs the scan.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let plan = Plan::from_file(&args.spec)?;
    let out = args.out.clone().unwrap_or_else(|| plan.output.clone());
    if out.extension().and_then(|e| e.to_str()) != Some("h5") {
        bail!(
            "output {}: expected a file name ending in .h5",
            out.display()
        );
    }
    let shard: Option<Shard> = args
        .shard
        .as_deref()
        .map(|s| s.parse().with_context(|| format!("--shard {s}")))
        .transpose()?;
    if let Some(n) = args.threads {
        if n == 0 || n > 4096 {
            bail!("--threads {n}: expected 1..=4096");
        }
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()
            .context("--threads")?;
    }
    let png = common::sibling(&out, "", "png");
    let mut pictures = vec![png.clone()];
    if plan.maps.len() > 1 {
        pictures.push(common::sibling(&png, "-cycle", "png"));
    }
    if shard.is_none() && !args.resume {
        for p in &pictures {
            common::check_new(p, args.force, "picture of the scan")?;
        }
    }
    if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("creating the output folder {}", dir.display()))?;
    }
    let prov = common::provenance();
    let mut writer = if args.resume {
        ScanWriter::resume(&out, &plan, shard, &prov)?
    } else {
        ScanWriter::create(&out, &plan, shard, &prov, args.force)?
    };

    let stop = Arc::new(AtomicBool::new(false));
    {
        let stop = stop.clone();
        ctrlc::set_handler(move || {
            if stop.swap(true, Ordering::SeqCst) {
                std::process::exit(130);
            }
            eprintln!(
                "\nsqueal: stopping after the blocks in flight (Ctrl-C again to quit at once)"
            );
        })
        .context("installing the Ctrl-C handler")?;
    }

    let g = plan.grid;
    let nb = g.blocks();
    let owned = |m: usize, b: usize| shard_owns(shard, &plan, m, b);
    let todo_cells: usize = (0..plan.maps.len())
        .flat_map(|m| (0..nb).map(move |b| (m, b)))
        .filter(|&(m, b)| owned(m, b) && !writer.is_done(m, b))
        .map(|(_, b)| g.block_rows(b).len() * g.x0.count)
        .sum();
    let multi = MultiProgress::with_draw_target(if common::show_progress(args.quiet) {
        ProgressDrawTarget::stderr()
    } else {
        ProgressDrawTarget::hidden()
    });
    let style = ProgressStyle::with_template(
        "{prefix:>8} [{bar:40}] {pos}/{len} cells  {per_sec}  ETA {eta}",
    )
    .expect("static template")
    .progress_chars("=> ");
    let overall = multi.add(
        ProgressBar::new(todo_cells as u64)
            .with_style(style.clone())
            .with_prefix("all"),
    );
    let sweep = plan.maps.len() > 1;

    let started = Instant::now();
    let mut computed = 0usize;
    let mut interrupted = false;
    'maps: for m in 0..plan.maps.len() {
        let blocks: Vec<usize> = (0..nb)
            .filter(|&b| owned(m, b) && !writer.is_done(m, b))
            .collect();
        if blocks.is_empty() && writer.has_cycle(m) {
            continue;
        }
        let ctx = MapContext::prepare(&plan, m)?;
        if !writer.has_cycle(m) {
            writer.write_cycle(m, ctx.cycle.as_ref(), ctx.cycle_error.as_deref())?;
        }
        let map_bar = sweep.then(|| {
            let n: usize = blocks
                .iter()
                .map(|&b| g.block_rows(b).len() * g.x0.count)
                .sum();
            let label = plan
                .sweep
                .as_ref()
                .map_or(String::new(), |s| format!("{}={:.3e}", s.name, s.values[m]));
            multi.add(
                ProgressBar::new(n as u64)
                    .with_style(style.clone())
                    .with_prefix(label),
            )
        });
        let bars = Bars {
            overall: overall.clone(),
            map: map_bar,
        };
        for &b in &blocks {
            if stop.load(Ordering::SeqCst) {
                interrupted = true;
                break 'maps;
            }
            match run_block(&plan, &ctx, b, &bars, Some(&stop)) {
                Some(r) => {
                    computed += r.cells.len();
                    writer.write_block(&r)?;
                }
                None => {
                    interrupted = true;
                    break 'maps;
                }
            }
        }
        if let Some(mb) = bars.map {
            mb.finish_and_clear();
        }
    }
    overall.finish_and_clear();
    let secs = started.elapsed().as_secs_f64();
    if interrupted {
        eprintln!(
            "squeal: interrupted; {} of {} blocks are stored. Finish with: squeal scan {} -o {} --resume{}",
            writer.done_blocks(),
            plan.total_blocks(),
            args.spec.display(),
            out.display(),
            args.shard
                .as_deref()
                .map(|s| format!(" --shard {s}"))
                .unwrap_or_default()
        );
        return Ok(ExitCode::from(130));
    }
    let wrong = writer.finish()?;
    let written = if shard.is_none() {
        common::render_file(&out, &png, true)?
    } else {
        Vec::new()
    };
    let info = squeal_store::read_info(&out)?;
    report(&args, &plan, &info, &wrong, &written, computed, secs)?;
    Ok(ExitCode::SUCCESS)
}

fn report(
    args: &Args,
    plan: &Plan,
    info: &squeal_store::FileInfo,
    wrong: &[Option<squeal_store::WrongSide>],
    pictures: &[PathBuf],
    computed: usize,
    secs: f64,
) -> anyhow::Result<()> {
    let names = ["undecided", "steady_slip", "stick_slip", "not_computed"];
    let rate = computed as f64 / secs.max(1e-9);
    if args.json {
        let maps: Vec<_> = info
            .counts
            .iter()
            .enumerate()
            .map(|(i, c)| {
                let mut o = serde_json::Map::new();
                if let Some((name, vals)) = &info.sweep {
                    o.insert(name.clone(), vals[i].into());
                }
                for (k, n) in names.iter().zip(c) {
                    o.insert((*k).into(), (*n).into());
                }
                o.insert(
                    "wrong_side".into(),
                    serde_json::to_value(wrong.get(i).copied().flatten())?,
                );
                Ok(serde_json::Value::Object(o))
            })
            .collect::<anyhow::Result<_>>()?;
        let v = serde_json::json!({
            "output": info.path,
            "pictures": pictures,
            "maps": maps,
            "cells_computed": computed,
            "seconds": secs,
            "cells_per_second": rate,
        });
        println!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(());
    }
    println!(
        "{}: {} map(s) of {} x {} cells -> {}",
        plan.name,
        plan.maps.len(),
        plan.grid.x0.count,
        plan.grid.v0.count,
        info.path.display()
    );
    for (i, c) in info.counts.iter().enumerate() {
        let label = info
            .sweep
            .as_ref()
            .map_or(String::new(), |(n, v)| format!("{n} = {:<10.4e} ", v[i]));
        let mut line = format!(
            "  {label}steady_slip {:>7}  stick_slip {:>7}  undecided {:>5}",
            c[1], c[2], c[0]
        );
        if c[3] > 0 {
            line += &format!("  not_computed {}", c[3]);
        }
        if let Some(Some(w)) = wrong.get(i) {
            line += &format!(
                "  wrong side of cycle: {} ({} beyond a pixel)",
                w.cells, w.beyond_pixel
            );
        }
        println!("{line}");
    }
    println!("  {computed} cells in {secs:.2} s: {rate:.0} cells/s");
    for p in pictures {
        println!("  picture: {}", p.display());
    }
    Ok(())
}
