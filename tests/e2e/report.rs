//! `squeal report` and `--report`: the page is written beside the file, self-contained, and
//! refused where a file would be: over an existing page, onto a FIFO, from a file squeal
//! did not write. What the page shows is checked in a real browser by
//! `scripts/ci/test-report.sh`.

use std::path::Path;
use std::process::{Command, Output};

fn squeal(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the squeal binary runs")
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// A 12 x 8 map at nu = 1e-2 (both basins and the cycle between them), seconds to run.
const SMALL: &str = r#"version = 1
name = "small"
[model]
law = "mcmillan"
nu = 1e-2
[grid]
x0 = { min = -3.0, max = 5.0, count = 12 }
v0 = { min = -4.0, max = 4.0, count = 8 }
[output]
path = "small.h5"
"#;

#[test]
fn a_scan_gets_its_page_beside_it_and_nothing_is_overwritten() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("small.toml"), SMALL).unwrap();
    // --report writes the page once the file is finished, and says where.
    let o = squeal(d, &["scan", "small.toml", "--quiet", "--report"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(
        text(&o.stdout).contains("report: small.html"),
        "{}",
        text(&o.stdout)
    );
    let page = std::fs::read_to_string(d.join("small.html")).unwrap();
    // The data, plotly.js and the page's script are inline; nothing is loaded from a URL.
    assert!(page.contains(r#"<script type="application/json" id="squeal-data">"#));
    assert!(page.contains("plotly.js") && page.contains("Plotly Technologies"));
    assert!(!page.contains("<script src") && !page.contains("<link"));
    assert!(
        page.contains(r#""kind":"scan""#),
        "the data block names the file's kind"
    );
    // `squeal report` refuses the existing page, and writes over it with --force.
    let o = squeal(d, &["report", "small.h5"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o.stderr).contains("exists (use --force"),
        "{}",
        text(&o.stderr)
    );
    let o = squeal(d, &["report", "small.h5", "--force"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    // A second scan with --report over the page is refused before computing.
    let o = squeal(
        d,
        &[
            "scan",
            "small.toml",
            "--quiet",
            "--report",
            "-o",
            "other.h5",
        ],
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    std::fs::remove_file(d.join("other.h5")).unwrap();
    std::fs::remove_file(d.join("other.png")).unwrap();
    let o = squeal(
        d,
        &[
            "scan",
            "small.toml",
            "--quiet",
            "--report",
            "-o",
            "other.h5",
        ],
    );
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains("other.html"),
        "{}",
        text(&o.stderr)
    );
    assert!(!d.join("other.h5").exists(), "nothing computed");
}

#[test]
fn a_page_is_refused_from_a_foreign_file_onto_a_fifo_or_under_another_name() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("notes.h5"), "not hdf5").unwrap();
    let o = squeal(d, &["report", "notes.h5"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o.stderr).contains("not an HDF5 file"),
        "{}",
        text(&o.stderr)
    );
    assert!(!d.join("notes.html").exists());
    let o = squeal(d, &["report", "notes.h5", "-o", "page.png"]);
    assert!(
        text(&o.stderr).contains("expected a file name ending in .html"),
        "{}",
        text(&o.stderr)
    );
    // A FIFO at the page is refused at once (opening it would wait for a reader for ever).
    if Command::new("mkfifo")
        .arg(d.join("p.html"))
        .status()
        .is_ok_and(|s| s.success())
    {
        let o = squeal(d, &["report", "notes.h5", "-o", "p.html", "--force"]);
        assert_eq!(o.status.code(), Some(2));
        assert!(text(&o.stderr).contains("FIFO"), "{}", text(&o.stderr));
    }
}

#[test]
fn a_trajectory_gets_its_page_with_its_si_series() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let o = squeal(
        d,
        &[
            "trajectory",
            "--m",
            "0.8",
            "--k",
            "2e5",
            "--c",
            "20",
            "--v-belt",
            "0.3",
            "--mu-k",
            "0.38",
            "--mu-s",
            "0.48",
            "--tau-s",
            "5e-4",
            "--normal-force",
            "1500",
            "--t-end",
            "20",
            "--out",
            "run.h5",
        ],
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let o = squeal(d, &["report", "run.h5", "-o", "sub/run.html"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let page = std::fs::read_to_string(d.join("sub/run.html")).unwrap();
    assert!(page.contains(r#""kind":"trajectory""#) && page.contains(r#""x_si":"#));
}
