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
    /// Exit with status 1 when any map's share of agreeing cells (over the cells decided in
    /// either file) is below this, or no cell is decided (0 to 1).
    #[arg(long)]
    pub min_agreement: Option<f64>,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
}

/// One map's comparison: its title, the agreement and the first disagreeing starts.
struct MapAgreement {
    title: String,
    agreement: Agreement,
    listed: Vec<[f64; 2]>,
}

/// Compares the two files map by map.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    if let Some(m) = args.min_agreement {
        if !(0.0..=1.0).contains(&m) {
            bail!(
                "--min-agreement {}: expected a share between 0 and 1",
                squeal_core::error::Number(m)
            );
        }
    }
    for f in [&args.first, &args.second] {
        scan_file(f)?;
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
    let maps = (0..n)
        .map(|m| compare_map(&args, m))
        .collect::<anyhow::Result<Vec<_>>>()?;
    let pass = args
        .min_agreement
        .is_none_or(|min| maps.iter().all(|m| m.agreement.share() >= min));
    if args.json {
        print_json(&maps, pass);
    } else {
        print_words(&args, &maps, pass);
    }
    Ok(if pass {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}

/// Refuses a file squeal wrote that is not a scan, saying what it is: a trajectory or an
/// atlas was called "not a squeal file".
fn scan_file(f: &std::path::Path) -> anyhow::Result<()> {
    use squeal_store::FileKind;
    let is = match squeal_store::file_kind(f)? {
        FileKind::Scan => return Ok(()),
        FileKind::Atlas => "an atlas (written by `squeal atlas`)",
        FileKind::Trajectory => "a trajectory (written by `squeal trajectory --out`)",
    };
    bail!(
        "{} is {is}: compare takes two scans of the same grid (written by `squeal scan` or \
         `squeal merge`)",
        f.display()
    )
}

/// Map `m` of both files, refused unless their grids are the same.
fn compare_map(args: &Args, m: usize) -> anyhow::Result<MapAgreement> {
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
    let agreement = Agreement::of(&a.labels, &b.labels);
    let nx = a.x0.len();
    let listed = agreement
        .first_disagreements
        .iter()
        .map(|&k| [a.x0[k % nx], a.v0[k / nx]])
        .collect();
    Ok(MapAgreement {
        title: a.title,
        agreement,
        listed,
    })
}

/// The comparison as one JSON object.
fn print_json(maps: &[MapAgreement], pass: bool) {
    let v: Vec<serde_json::Value> = maps
        .iter()
        .map(|m| {
            let mut o = serde_json::to_value(&m.agreement).expect("serialisable");
            o["title"] = m.title.clone().into();
            o["decided"] = m.agreement.decided().into();
            o["share"] = m.agreement.share().into();
            o["disagreeing_starts"] = serde_json::to_value(&m.listed).expect("serialisable");
            o
        })
        .collect();
    println!("{}", serde_json::json!({ "maps": v, "pass": pass }));
}

/// The comparison in words, one line per map and one per listed disagreement.
fn print_words(args: &Args, maps: &[MapAgreement], pass: bool) {
    println!(
        "{} against {}:",
        args.first.display(),
        args.second.display()
    );
    for m in maps {
        let g = &m.agreement;
        let agreement = if g.decided() == 0 {
            "no cell decided in either file".to_string()
        } else {
            format!(
                "{} of {} decided cells agree ({:.4}%), {} disagree, undecided in one only: \
                 {} in the first, {} in the second",
                g.agree,
                g.decided(),
                100.0 * g.share(),
                g.disagree,
                g.undecided_first,
                g.undecided_second
            )
        };
        println!(
            "  {}: {agreement}; {} undecided in both; {} not computed",
            m.title, g.undecided_both, g.not_computed
        );
        for [x, v] in &m.listed {
            println!("    disagrees at x0 = {x}, v0 = {v}");
        }
    }
    if let Some(min) = args.min_agreement {
        println!(
            "  {} (every map at least {:.4}% agreeing)",
            if pass { "pass" } else { "FAIL" },
            100.0 * min
        );
    }
}
