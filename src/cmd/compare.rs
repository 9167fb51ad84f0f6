//! `squeal compare A.h5 B.h5`: cell-by-cell agreement of two scans of the same grid (a scan
//! against a reference at a smaller step, or run to settlement).

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::bail;
use squeal_scan::compare::Agreement;

/// Flags of `squeal compare`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The scan to check.
    pub first: PathBuf,
    /// The reference scan (same grid and maps).
    pub second: PathBuf,
    /// Exit with status 1 when any map's share of agreeing cells is below this (0 to 1).
    #[arg(long)]
    pub min_agreement: Option<f64>,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
}

/// Compares the two files map by map.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    if let Some(m) = args.min_agreement {
        if !(0.0..=1.0).contains(&m) {
            bail!("--min-agreement {m}: expected a share between 0 and 1");
        }
    }
    let n = squeal_store::map_count(&args.first)?;
    let n2 = squeal_store::map_count(&args.second)?;
    if n != n2 {
        bail!(
            "{} has {n} map(s), {} has {n2}: not scans of the same plan",
            args.first.display(),
            args.second.display()
        );
    }
    let mut maps = Vec::new();
    let mut pass = true;
    for m in 0..n {
        let a = squeal_store::read_map(&args.first, m)?;
        let b = squeal_store::read_map(&args.second, m)?;
        for (name, p, q) in [("x0", &a.x0, &b.x0), ("v0", &a.v0, &b.v0)] {
            let same = p.len() == q.len()
                && p.iter()
                    .zip(q.iter())
                    .all(|(s, t)| (s - t).abs() <= 1e-12 * s.abs().max(t.abs()).max(1.0));
            if !same {
                bail!(
                    "map {m}: the {name} axes of {} and {} differ: not the same grid",
                    args.first.display(),
                    args.second.display()
                );
            }
        }
        let g = Agreement::of(&a.labels, &b.labels);
        let nx = a.x0.len();
        let listed: Vec<[f64; 2]> = g
            .first_disagreements
            .iter()
            .map(|&k| [a.x0[k % nx], a.v0[k / nx]])
            .collect();
        pass &= args.min_agreement.is_none_or(|m| g.share() >= m);
        maps.push((a.title, g, listed));
    }
    if args.json {
        let v: Vec<serde_json::Value> = maps
            .iter()
            .map(|(title, g, listed)| {
                let mut o = serde_json::to_value(g).expect("serialisable");
                o["title"] = title.clone().into();
                o["share"] = g.share().into();
                o["disagreeing_starts"] = serde_json::to_value(listed).expect("serialisable");
                o
            })
            .collect();
        println!("{}", serde_json::json!({ "maps": v, "pass": pass }));
    } else {
        println!(
            "{} against {}:",
            args.first.display(),
            args.second.display()
        );
        for (title, g, listed) in &maps {
            println!(
                "  {title}: {} of {} cells agree ({:.4}%), {} disagree; undecided: {} in the first only, {} in the second only, {} in both; {} not computed",
                g.agree,
                g.cells,
                100.0 * g.share(),
                g.disagree,
                g.undecided_first,
                g.undecided_second,
                g.undecided_both,
                g.not_computed
            );
            for [x, v] in listed {
                println!("    disagrees at x0 = {x}, v0 = {v}");
            }
        }
        if let Some(m) = args.min_agreement {
            println!(
                "  {} (every map at least {:.4}% agreeing)",
                if pass { "pass" } else { "FAIL" },
                100.0 * m
            );
        }
    }
    Ok(if pass {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}
