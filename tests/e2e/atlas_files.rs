//! End-to-end tests of an atlas's files: shards merged into the single run's file, resume
//! after a kill, a finished atlas rerun as up to date, merge's refusals, and `info`.

use std::process::{Command, Output};

use serde_json::Value;

use crate::atlas::{json, ok, read_f64, records_in, refused, squeal, str_attr};

/// 2 x 2 points and two boundary searches (about 15 s of CPU in a release build, nearly all
/// the two critical dampings; with four belt speeds it was 40 s, run six times by the tests
/// below, which check journals, shards and merges, not the figures).
/// Two points of Table 1 (the non-hysteretic law at lambda = 3) and their boundaries in nu:
/// two units (the line of points and its boundary search), about 7 s of CPU in a release
/// build. At lambda = 2 the critical damping comes from runs to t = 20000 (fates.rs), which
/// took 11 s more per run; these tests check journals, shards and merges, not figures.
const GRID: &str = r#"
version = 1
name = "grid"
[model]
law = "mcmillan-nonhysteretic"
nu = [2e-3, 1e-2]
lambda = 3.0
[cycle]
half_dt = false
[attractor]
transient = 10
window = 10
[boundaries]
rtol = 1e-2
[output]
path = "grid.h5"
"#;

#[test]
fn shards_merge_into_the_single_run_file() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("grid.toml"), GRID).unwrap();
    ok(squeal(dir.path(), &["atlas", "grid.toml", "--no-render"]));
    for k in ["1/2", "2/2"] {
        let out = format!("s{}.h5", &k[..1]);
        ok(squeal(
            dir.path(),
            &["atlas", "grid.toml", "--shard", k, "-o", &out],
        ));
    }
    ok(squeal(
        dir.path(),
        &["merge", "s1.h5", "s2.h5", "-o", "merged.h5"],
    ));
    let (one, merged) = (dir.path().join("grid.h5"), dir.path().join("merged.h5"));
    for name in [
        "cycle_r_section",
        "stick_r_mean",
        "basin_fraction",
        "fold_nu",
        "critical_nu",
    ] {
        assert_eq!(read_f64(&one, name), read_f64(&merged, name), "{name}");
    }
    // Incomplete shard sets are refused.
    refused(
        squeal(dir.path(), &["merge", "s1.h5", "-o", "part.h5"]),
        "shards",
    );
    // render redraws the chart of an atlas file.
    ok(squeal(
        dir.path(),
        &["render", "merged.h5", "-o", "again.png"],
    ));
    assert!(dir.path().join("again.png").exists());
}

#[test]
#[ignore = "long check (a minute or more on 2 cores): run by scripts/ci/long-checks.sh, which .ci/run calls"]
fn resume_after_a_kill_gives_the_same_file() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("grid.toml"), GRID).unwrap();
    ok(squeal(
        dir.path(),
        &["atlas", "grid.toml", "-o", "ref.h5", "--no-render"],
    ));
    let mut child = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(["atlas", "grid.toml", "--threads", "1", "--no-render"])
        .current_dir(dir.path())
        .spawn()
        .unwrap();
    let journal = dir.path().join("grid.h5.journal");
    // Wait for the header and at least one unit, then kill without warning.
    let t0 = std::time::Instant::now();
    loop {
        if records_in(&journal, b'U') >= 1 || t0.elapsed().as_secs() > 120 {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    if dir.path().join("grid.h5").exists() {
        // The run finished before the kill: nothing to resume (machine much faster).
        return;
    }
    // A torn last record, as a kill during a write leaves it.
    use std::io::Write;
    let mut j = std::fs::OpenOptions::new()
        .append(true)
        .open(&journal)
        .unwrap();
    j.write_all(b"SQJRU\x40\x00\x00\x00{\"line\": 1, \"poi")
        .unwrap();
    drop(j);
    // A second run without --resume is refused.
    refused(squeal(dir.path(), &["atlas", "grid.toml"]), "--resume");
    ok(squeal(
        dir.path(),
        &["atlas", "grid.toml", "--resume", "--no-render"],
    ));
    let (a, b) = (dir.path().join("ref.h5"), dir.path().join("grid.h5"));
    for name in ["cycle_r_section", "stick_omega_mean", "fold_nu"] {
        assert_eq!(read_f64(&a, name), read_f64(&b, name), "{name}");
    }
    assert!(!journal.exists());
}

/// A 2 x 2 atlas without boundary searches that takes about a second of CPU (the output
/// rules are what its tests check): no `name`, so it is named after its spec file.
const SMALL: &str = r#"
version = 1
[model]
law = "mcmillan-nonhysteretic"
nu = [2e-3, 1e-2]
lambda = [2.0, 3.0]
[cycle]
half_dt = false
[attractor]
transient = 10
window = 10
[boundaries]
rtol = 1e-2
fold = false
critical = false
[output]
path = "small.h5"
"#;

fn stderr_of(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Like a scan, like make: a finished atlas rerun (a requeued SLURM job, with or without
/// `--resume`) is up to date and exits 0, a missing chart is drawn again, and another spec
/// is refused naming `--force`. (It exited 2, "refusing to overwrite".)
#[test]
fn a_finished_atlas_rerun_is_up_to_date_like_a_scan() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("small.toml"), SMALL).unwrap();
    ok(squeal(d, &["atlas", "small.toml", "--quiet"]));
    let (h5, png) = (d.join("small.h5"), d.join("small.png"));
    let file = std::fs::read(&h5).unwrap();
    for extra in [None, Some("--resume")] {
        let args: Vec<&str> = ["atlas", "small.toml"].into_iter().chain(extra).collect();
        let o = squeal(d, &args);
        assert!(stderr_of(&o).contains("small.h5 is up to date"), "{o:?}");
        let out = ok(o);
        assert!(
            out.contains("4 points over nu (2 values) x lambda (2 values)"),
            "{out}"
        );
    }
    // A chart lost (or cut short by a full disk) is drawn again, the file left as it was.
    std::fs::remove_file(&png).unwrap();
    let o = squeal(d, &["atlas", "small.toml", "--resume"]);
    assert!(stderr_of(&o).contains("drew the missing picture"), "{o:?}");
    ok(o);
    assert!(png.exists());
    assert_eq!(std::fs::read(&h5).unwrap(), file);
    // --json says nothing was computed.
    let v = json(&ok(squeal(d, &["atlas", "small.toml", "--json"])));
    assert_eq!(v["units_computed"], 0);
    assert_eq!(v["points"].as_array().unwrap().len(), 4);
    // A comment is no change; another bracket width is, with or without --resume.
    std::fs::write(d.join("small.toml"), format!("{SMALL}# a comment\n")).unwrap();
    ok(squeal(d, &["atlas", "small.toml"]));
    let other = SMALL.replace("rtol = 1e-2", "rtol = 2e-2");
    std::fs::write(d.join("other.toml"), other).unwrap();
    for extra in [None, Some("--resume")] {
        let args: Vec<&str> = ["atlas", "other.toml", "-o", "small.h5"]
            .into_iter()
            .chain(extra)
            .collect();
        refused(squeal(d, &args), "--force");
        assert_eq!(std::fs::read(&h5).unwrap(), file);
    }
    ok(squeal(
        d,
        &["atlas", "other.toml", "-o", "small.h5", "--force"],
    ));
    assert_ne!(std::fs::read(&h5).unwrap(), file);
}

/// `merge` refuses an input as its output for atlases as for scans, even with --force,
/// by its name or another one (a hard link); it overwrote the shard. The merged file is
/// named as the shards' spec, not after the first shard's file.
#[test]
fn an_atlas_merge_refuses_an_input_as_its_output() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("small.toml"), SMALL).unwrap();
    for k in ["1/2", "2/2"] {
        let out = format!("s{}.h5", &k[..1]);
        ok(squeal(
            d,
            &["atlas", "small.toml", "--shard", k, "-o", &out],
        ));
    }
    let s1 = std::fs::read(d.join("s1.h5")).unwrap();
    std::fs::hard_link(d.join("s1.h5"), d.join("link.h5")).unwrap();
    std::fs::create_dir(d.join("sub")).unwrap();
    for out in ["s1.h5", "./sub/../s1.h5", "link.h5"] {
        let o = squeal(d, &["merge", "s1.h5", "s2.h5", "-o", out, "--force"]);
        refused(o, "one of the inputs");
        assert_eq!(std::fs::read(d.join("s1.h5")).unwrap(), s1, "{out}");
    }
    ok(squeal(d, &["merge", "s1.h5", "s2.h5", "-o", "m.h5"]));
    assert_eq!(str_attr(&d.join("m.h5"), None, "name"), "small");
}

/// `info` reads atlas files (it refused them): parameters, axes, points per regime and the
/// boundaries found, in words and as JSON; a shard says so.
#[test]
fn info_reads_an_atlas_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // SMALL at Table 1's belt speed only, with its critical damping (from the cycle, confirmed
    // by runs: 4 s of CPU; at lambda = 2 it comes from runs, 11 s more).
    let spec = SMALL
        .replace("lambda = [2.0, 3.0]", "lambda = 3.0")
        .replace("critical = false\n", "");
    std::fs::write(d.join("small.toml"), spec).unwrap();
    let run = json(&ok(squeal(
        d,
        &["atlas", "small.toml", "--json", "--quiet"],
    )));
    let text = ok(squeal(d, &["info", "small.h5"]));
    for want in [
        "squeal-atlas/1",
        "law = mcmillan-nonhysteretic",
        "name = small",
        "2 points over nu (2 values)",
        "points: ",
        "boundaries in the damping ratio nu",
        "critical nu = ",
    ] {
        assert!(text.contains(want), "{want:?} in: {text}");
    }
    let v: Value = serde_json::from_str(&ok(squeal(d, &["info", "small.h5", "--json"]))).unwrap();
    assert_eq!(v["attributes"]["law"], "mcmillan-nonhysteretic");
    assert_eq!(v["axes"].as_array().unwrap().len(), 1);
    assert_eq!(v["shard"], Value::Null);
    // The same points and boundaries as the run printed (the file does not keep the
    // boundaries' evaluation counts).
    assert_eq!(v["points"], run["points"]);
    for (a, b) in v["boundaries"]
        .as_array()
        .unwrap()
        .iter()
        .zip(run["boundaries"].as_array().unwrap())
    {
        for (bd, key) in [
            ("critical", "nu"),
            ("critical", "status"),
            ("fold", "status"),
        ] {
            assert_eq!(a[bd][key], b[bd][key], "{bd}.{key}");
        }
    }
    assert_eq!(v["boundaries"].as_array().unwrap().len(), 1);
    ok(squeal(
        d,
        &["atlas", "small.toml", "--shard", "1/2", "-o", "s1.h5"],
    ));
    assert!(ok(squeal(d, &["info", "s1.h5"])).contains("shard 1/2"));
}
