//! The fuzz family "FIFOs on every path": each command's input and output paths (the files
//! a run writes beside its output, a friction table a spec names, a figure of `friction
//! --out-dir` among them) given a FIFO, with or without `--force`. Each run must be refused
//! within [`LIMIT`], naming the FIFO: a FIFO opened for reading or writing waits for the
//! other end for ever, and seven paths did.

use std::path::Path;
use std::process::Command;
use std::time::Duration;

use super::{Case, Rng, run_within, snapshot, tail};

/// Longest a refusal may take: it comes before anything is opened or computed (a few
/// milliseconds alone; the machine running the fuzz may be shared).
pub const LIMIT: Duration = Duration::from_secs(15);

/// A 3 x 3 scan of a fraction of a second, written to `out.h5`; with `csv`, on the table
/// law with its curve in that file.
fn tiny_scan(csv: Option<&str>) -> String {
    let law = match csv {
        Some(f) => format!("law = \"table\"\nxi = 0.025\nv_d = 0.08\nfriction_csv = \"{f}\""),
        None => "law = \"mcmillan\"\nnu = 1e-2".into(),
    };
    format!(
        "version = 1\n[model]\n{law}\n[grid]\nx0 = {{ min = 0.0, max = 2.0, count = 3 }}\n\
         v0 = {{ min = -1.0, max = 1.0, count = 3 }}\n[classifier]\nt_max = 500.0\n\
         [output]\npath = \"out.h5\"\n"
    )
}

/// An atlas of two points (a chart: a FIFO at `out.png` is a path it writes), written to
/// `out.h5`.
const TINY_ATLAS: &str = "version = 1\n[model]\nlaw = \"mcmillan\"\nnu = [1e-3, 1e-2]\n[boundaries]\n\
    fold = false\ncritical = false\n[output]\npath = \"out.h5\"\n";

/// The figures `friction --out-dir fr` writes (each a CSV and a PNG).
const FIGURES: [&str; 3] = [
    "fig4_5_fixed_acceleration",
    "fig6_loop_w200",
    "fig7_loop_w20",
];

/// The output of a scan or an atlas and what a run writes beside it.
const BESIDE: [&str; 5] = [
    "out.h5",
    "out.h5.lock",
    "out.h5.tmp",
    "out.h5.journal",
    "out.png",
];

/// Command lines reading or writing one file, and that file (made a FIFO).
const ONE_FILE: [(&[&str], &str); 12] = [
    (&["scan", "case.toml"], "case.toml"),
    (
        &["classify", "--ics", "ics.csv", "--out", "l.csv"],
        "ics.csv",
    ),
    (&["classify", "--ics", "ics.csv", "--out", "l.csv"], "l.csv"),
    (&["trajectory", "--t-end", "10", "--out", "t.csv"], "t.csv"),
    (&["trajectory", "--t-end", "10", "--out", "t.h5"], "t.h5"),
    (&["trajectory", "--t-end", "10", "--plot", "t.png"], "t.png"),
    (&["ulc", "--plot", "u.png"], "u.png"),
    (&["render", "good.h5", "-o", "r.png"], "r.png"),
    (&["render", "in.h5"], "in.h5"),
    (&["info", "in.h5"], "in.h5"),
    (&["compare", "good.h5", "in.h5"], "in.h5"),
    (&["merge", "in.h5", "good.h5", "-o", "all.h5"], "in.h5"),
];

/// A command line and the path made a FIFO.
fn pick(rng: &mut Rng) -> (Vec<String>, String) {
    let v = |a: &[&str]| a.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    match rng.below(6) {
        0 => {
            let f = *rng.pick(&BESIDE);
            // The journal is read by a resume only.
            let resume: &[&str] = if f.ends_with("journal") {
                &["--resume"]
            } else {
                &[]
            };
            (v(&[&["scan", "scan.toml"], resume].concat()), f.into())
        }
        1 => (v(&["atlas", "atlas.toml"]), rng.pick(&BESIDE).to_string()),
        2 => (v(&["scan", "table.toml"]), "pad.csv".into()),
        3 => {
            let f = format!("fr/{}.{}", rng.pick(&FIGURES), rng.pick(&["csv", "png"]));
            (v(&["friction", "--out-dir", "fr"]), f)
        }
        4 => (
            v(&["merge", "good.h5", "good.h5", "-o", "all.h5"]),
            "all.h5".into(),
        ),
        _ => {
            let (args, f) = *rng.pick(&ONE_FILE);
            (v(args), f.into())
        }
    }
}

/// A command with one of its paths a FIFO, `--force` in half the cases (the FIFO is no
/// file to overwrite); the files it needs beside.
pub fn fifo_case(rng: &mut Rng, good: &[u8]) -> Case {
    let (mut args, fifo) = pick(rng);
    // `--force` conflicts with `--resume`, and `info`, `compare` take none.
    let forcible = !args
        .iter()
        .any(|a| a == "--resume" || a == "info" || a == "compare");
    if forcible && rng.below(2) == 0 {
        args.push("--force".into());
    }
    let text = |name: &str, t: &str| (name.to_string(), t.as_bytes().to_vec());
    let files = vec![
        text("scan.toml", &tiny_scan(None)),
        text("table.toml", &tiny_scan(Some("pad.csv"))),
        text("atlas.toml", TINY_ATLAS),
        text("case.toml", &tiny_scan(None)),
        text("ics.csv", "x0,v0\n0.5,0.0\n"),
        text("pad.csv", "0,0.48\n0.1,0.43\n1,0.37\n"),
        ("good.h5".to_string(), good.to_vec()),
        text("keep.txt", "keep"),
    ]
    .into_iter()
    .filter(|(n, _)| *n != fifo)
    .collect();
    Case {
        what: format!("a FIFO at {fifo}"),
        args,
        files,
        announces: false,
        fifos: vec![fifo],
        check: None,
    }
}

fn mkfifo(p: &Path) -> bool {
    if let Some(parent) = p.parent() {
        std::fs::create_dir_all(parent).unwrap();
    }
    Command::new("mkfifo")
        .arg(p)
        .status()
        .map(|s| s.success())
        .unwrap_or(false)
}

/// Why a FIFO case failed, if it did: not refused (code 2) within [`LIMIT`] naming a FIFO,
/// a panic, or a file there before the run lost. The files are in `dir` already.
pub fn judge(case: &Case, dir: &Path) -> Result<&'static str, String> {
    for f in &case.fifos {
        if !mkfifo(&dir.join(f)) {
            return Ok("skipped");
        }
    }
    let before = snapshot(dir);
    let r = run_within(dir, &case.args, LIMIT);
    let after = snapshot(dir);
    if r.code == Some(101) || r.output.contains("panicked") {
        return Err(format!("panic: {}", tail(&r.output)));
    }
    if r.timed_out {
        return Err(format!(
            "hang: not refused within {LIMIT:?}: {}",
            tail(&r.output)
        ));
    }
    if r.code != Some(2) || !r.output.contains("FIFO") {
        return Err(format!(
            "not refused naming the FIFO (code {:?}): {}",
            r.code,
            tail(&r.output)
        ));
    }
    if before != after {
        return Err("lost file: a file was changed or removed".into());
    }
    Ok("fifo refused")
}
