//! End-to-end tests of `squeal scan`, `info`, `render`, `classify`, `ulc`, `critical` and
//! `merge`: run the real binary in a fresh temporary folder and reopen the files; and the
//! helpers `scan_laws` shares.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub(crate) fn squeal(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_squeal"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("run squeal")
}

pub(crate) fn ok(o: &Output) -> String {
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "squeal failed: {err}");
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn fails(o: &Output, want: &str) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "expected failure containing '{want}'");
    assert!(!err.contains("panicked"), "panic: {err}");
    assert!(err.contains(want), "expected '{want}' in: {err}");
}

const TINY: &str = r#"version = 1
[model]
law = "mcmillan"
nu = 1e-3
[grid]
x0 = { min = -3.0, max = 5.0, count = 9 }
v0 = { min = -4.0, max = 4.0, count = 7 }
block_rows = 2
[classifier]
t_max = 3000.0
[output]
path = "tiny.h5"
"#;

pub(crate) fn spec(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn digest(p: &Path) -> String {
    squeal_store_digest(p)
}

fn squeal_store_digest(p: &Path) -> String {
    // The store's own content digest: every dataset's values and every attribute.
    squeal_store::content_digest(p).expect("digest")
}

#[test]
fn progress_lines_off_a_terminal_wait_for_the_first_second() {
    // With stderr not a terminal (a batch log), a scan of a fraction of a second
    // printed twenty lines such as "5% (3/63 cells) after 0 s, 3 cell/s, about 19 s left":
    // a rate and a time left from a few cells in a few milliseconds. Lines now start after
    // the first second, so none can say "after 0 s" (a slower run under load may print
    // some, from "after 1 s" on).
    let d = tempfile::tempdir().unwrap();
    spec(d.path(), "tiny.toml", TINY);
    let o = squeal(d.path(), &["scan", "tiny.toml"]);
    ok(&o);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("roughly"), "the estimate is printed: {err}");
    assert!(!err.contains("after 0 s"), "{err}");
}

#[test]
fn tiny_scan_writes_a_self_describing_file() {
    let d = tempfile::tempdir().unwrap();
    spec(d.path(), "tiny.toml", TINY);
    let out = ok(&squeal(
        d.path(),
        &["scan", "tiny.toml", "--quiet", "--json"],
    ));
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(
        v["maps"][0]["stick_slip"].as_u64().unwrap()
            + v["maps"][0]["steady_slip"].as_u64().unwrap()
            + v["maps"][0]["undecided"].as_u64().unwrap(),
        63
    );
    assert!(d.path().join("tiny.png").exists());
    let f = hdf5::File::open(d.path().join("tiny.h5")).unwrap();
    let labels = f.dataset("labels").unwrap();
    assert_eq!(labels.shape(), vec![7, 9]);
    let x0: Vec<f64> = f.dataset("x0").unwrap().read_raw().unwrap();
    assert_eq!(x0.first(), Some(&-3.0));
    assert_eq!(x0.last(), Some(&5.0));
    let dt = labels.dtype().unwrap().to_descriptor().unwrap();
    let txt = format!("{dt:?}");
    assert!(
        txt.contains("steady_slip") && txt.contains("stick_slip") && txt.contains("undecided"),
        "{txt}"
    );
    let spec_attr: hdf5::types::VarLenUnicode = f.attr("spec").unwrap().read_scalar().unwrap();
    assert!(spec_attr.as_str().contains("nu = 1e-3"));
    assert!(
        f.attr("squeal_version").is_ok() && f.attr("git_revision").is_ok() && f.attr("nu").is_ok()
    );
    assert!(f.group("cycle").is_ok());
    // The state at rest squeals at nu = 1e-3 (paper Fig. 9): x0 = 0 is column 3, v0 = 0 row 3.
    let l: Vec<u8> = labels.read_raw().unwrap();
    assert_eq!(l[3 * 9 + 3], 2);
    // Output is never overwritten silently: a different spec is refused...
    spec(
        d.path(),
        "other.toml",
        &TINY.replace("nu = 1e-3", "nu = 2e-3"),
    );
    fails(
        &squeal(
            d.path(),
            &["scan", "other.toml", "-o", "tiny.h5", "--quiet"],
        ),
        "--force",
    );
    // ...and rerunning the same spec (the README's job, run twice) is up to date, like make.
    let before = digest(&d.path().join("tiny.h5"));
    let again = squeal(d.path(), &["scan", "tiny.toml", "--quiet"]);
    ok(&again);
    assert!(String::from_utf8_lossy(&again.stderr).contains("up to date"));
    assert_eq!(digest(&d.path().join("tiny.h5")), before);
    // info and render
    let info = ok(&squeal(d.path(), &["info", "tiny.h5", "--json"]));
    let iv: serde_json::Value = serde_json::from_str(&info).unwrap();
    assert_eq!(iv["counts"][0]["stick_slip"], v["maps"][0]["stick_slip"]);
    ok(&squeal(d.path(), &["render", "tiny.h5", "-o", "again.png"]));
    assert!(d.path().join("again.png").exists());
}

/// The file does not depend on the thread count: 1, 2, 3 and 16 threads (more
/// threads than the machine's cores included) write the same datasets and attributes.
#[test]
fn one_and_many_threads_give_identical_files() {
    let d = tempfile::tempdir().unwrap();
    spec(d.path(), "tiny.toml", TINY);
    let run = |threads: usize| {
        let out = format!("t{threads}.h5");
        let n = threads.to_string();
        ok(&squeal(
            d.path(),
            &["scan", "tiny.toml", "-o", &out, "--threads", &n, "--quiet"],
        ));
        digest(&d.path().join(out))
    };
    let one = run(1);
    for threads in [2, 3, 16] {
        assert_eq!(one, run(threads), "{threads} threads");
    }
}

#[test]
fn killed_sweep_resumes_to_the_same_file() {
    let d = tempfile::tempdir().unwrap();
    // Long enough to be killed midway: no early stopping, a few hundred cells.
    let text = TINY
        .replace("count = 9", "count = 24")
        .replace("count = 7", "count = 16")
        .replace("t_max = 3000.0", "t_max = 400.0\nearly_stop = \"none\"");
    spec(d.path(), "slow.toml", &text);
    ok(&squeal(
        d.path(),
        &["scan", "slow.toml", "-o", "full.h5", "--quiet"],
    ));
    scan_killed_after_a_block_while_locked(d.path());
    assert!(
        !d.path().join("cut.h5").exists(),
        "an interrupted scan must not look complete"
    );
    // SIGKILL leaves the lock behind; it is stale (no such process) and taken over below.
    assert!(d.path().join("cut.h5.lock").exists());
    fails(
        &squeal(d.path(), &["scan", "slow.toml", "-o", "cut.h5", "--quiet"]),
        "--resume",
    );
    let out = ok(&squeal(
        d.path(),
        &["scan", "slow.toml", "-o", "cut.h5", "--quiet", "--resume"],
    ));
    // Resuming computes only what the journal lacks: fewer than the 24 x 16 cells.
    let computed: usize = out
        .lines()
        .find_map(|l| l.trim().split(" cells in ").next()?.parse().ok())
        .unwrap_or(0);
    assert!(computed < 24 * 16, "resume recomputed everything: {out}");
    assert_eq!(
        digest(&d.path().join("full.h5")),
        digest(&d.path().join("cut.h5"))
    );
}

/// Runs `slow.toml` in `dir` to `cut.h5` on one thread, checks that a second scan or a
/// resume is refused while it runs, and kills it once a block is in its journal.
fn scan_killed_after_a_block_while_locked(dir: &Path) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .current_dir(dir)
        .args([
            "scan",
            "slow.toml",
            "-o",
            "cut.h5",
            "--quiet",
            "--threads",
            "1",
        ])
        .spawn()
        .unwrap();
    // Wait until a block record is in the journal, then kill hard. Journal frames are
    // `SQJR`, a kind byte (`H`eader, `C`ycle, `B`lock), a little-endian u32 length, the
    // payload and an 8-byte checksum (crates/store/src/journal.rs); the cycle record comes
    // first and is large, so the file's size alone says nothing about blocks.
    let journal = dir.join("cut.h5.journal");
    let blocks_in = |p: &Path| -> usize {
        let b = std::fs::read(p).unwrap_or_default();
        let (mut at, mut n) = (0usize, 0usize);
        while at + 9 <= b.len() && &b[at..at + 4] == b"SQJR" {
            let len = u32::from_le_bytes(b[at + 5..at + 9].try_into().unwrap()) as usize;
            if at + 9 + len + 8 > b.len() {
                break;
            }
            n += (b[at + 4] == b'B') as usize;
            at += 9 + len + 8;
        }
        n
    };
    for _ in 0..2000 {
        if blocks_in(&journal) > 0 {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    // The kill must come after at least one block was stored, or resuming proves nothing.
    let stored = blocks_in(&journal);
    assert!(stored > 0, "no block reached the journal before the kill");
    // While it runs, a second scan or resume of the same output is refused, naming it.
    let pid = child.id().to_string();
    for extra in ["--force", "--resume"] {
        let o = squeal(
            dir,
            &["scan", "slow.toml", "-o", "cut.h5", "--quiet", extra],
        );
        fails(&o, "being written by process");
        assert!(String::from_utf8_lossy(&o.stderr).contains(&pid));
    }
    child.kill().unwrap();
    child.wait().unwrap();
}

#[test]
fn shards_merge_into_the_single_run_file() {
    let d = tempfile::tempdir().unwrap();
    let sweep = TINY.replace("nu = 1e-3", "nu = [1e-3, 1e-2]");
    spec(d.path(), "sw.toml", &sweep);
    ok(&squeal(
        d.path(),
        &["scan", "sw.toml", "-o", "single.h5", "--quiet"],
    ));
    assert!(d.path().join("single.png").exists() && d.path().join("single-cycle.png").exists());
    for k in ["1/3", "2/3", "3/3"] {
        let name = format!("s{}.h5", &k[..1]);
        ok(&squeal(
            d.path(),
            &["scan", "sw.toml", "-o", &name, "--shard", k, "--quiet"],
        ));
    }
    // A requeued shard that had finished is up to date (SLURM reruns whole tasks)...
    let again = squeal(
        d.path(),
        &[
            "scan", "sw.toml", "-o", "s1.h5", "--shard", "1/3", "--quiet",
        ],
    );
    ok(&again);
    assert!(String::from_utf8_lossy(&again.stderr).contains("up to date"));
    // ...but not as another shard.
    fails(
        &squeal(
            d.path(),
            &[
                "scan", "sw.toml", "-o", "s1.h5", "--shard", "2/3", "--quiet",
            ],
        ),
        "--force",
    );
    fails(
        &squeal(d.path(), &["merge", "s1.h5", "s2.h5", "-o", "m.h5"]),
        "missing shard 3/3",
    );
    fails(
        &squeal(
            d.path(),
            &["merge", "s1.h5", "s1.h5", "s2.h5", "-o", "m.h5"],
        ),
        "s1.h5",
    );
    // The output may not be one of the inputs, even with --force.
    let s1 = std::fs::read(d.path().join("s1.h5")).unwrap();
    fails(
        &squeal(
            d.path(),
            &["merge", "s1.h5", "s2.h5", "s3.h5", "-o", "s1.h5", "--force"],
        ),
        "one of the inputs",
    );
    assert_eq!(std::fs::read(d.path().join("s1.h5")).unwrap(), s1);
    ok(&squeal(
        d.path(),
        &["merge", "s1.h5", "s2.h5", "s3.h5", "-o", "m.h5"],
    ));
    assert_eq!(
        digest(&d.path().join("single.h5")),
        digest(&d.path().join("m.h5"))
    );
    let f = hdf5::File::open(d.path().join("single.h5")).unwrap();
    assert_eq!(f.dataset("labels").unwrap().shape(), vec![2, 7, 9]);
    let nu: Vec<f64> = f.dataset("nu").unwrap().read_raw().unwrap();
    assert_eq!(nu, vec![1e-3, 1e-2]);
}

#[test]
fn bad_input_gives_clear_errors() {
    let d = tempfile::tempdir().unwrap();
    spec(d.path(), "bad.toml", &TINY.replace("[model]", "[model\n"));
    fails(&squeal(d.path(), &["scan", "bad.toml"]), "line");
    spec(
        d.path(),
        "unknown.toml",
        &TINY.replace("nu = 1e-3", "nu = 1e-3\nzeta = 1"),
    );
    fails(&squeal(d.path(), &["scan", "unknown.toml"]), "zeta");
    spec(
        d.path(),
        "inv.toml",
        &TINY.replace("min = -3.0, max = 5.0", "min = 5.0, max = -3.0"),
    );
    fails(&squeal(d.path(), &["scan", "inv.toml"]), "grid.x0");
    spec(
        d.path(),
        "zero.toml",
        &TINY.replace("count = 9", "count = 0"),
    );
    fails(&squeal(d.path(), &["scan", "zero.toml"]), "grid.x0.count");
    spec(
        d.path(),
        "nonmono.toml",
        &TINY.replace("nu = 1e-3", "nu = [1e-3, 1e-3]"),
    );
    fails(&squeal(d.path(), &["scan", "nonmono.toml"]), "monotone");
    spec(
        d.path(),
        "empty.toml",
        &TINY.replace("nu = 1e-3", "nu = []"),
    );
    fails(&squeal(d.path(), &["scan", "empty.toml"]), "non-empty");
    spec(d.path(), "tiny.toml", TINY);
    fails(
        &squeal(d.path(), &["scan", "tiny.toml", "-o", "/proc/nope/x.h5"]),
        "/proc/nope",
    );
    fails(&squeal(d.path(), &["scan", "missing.toml"]), "missing.toml");
    fails(
        &squeal(d.path(), &["scan", "tiny.toml", "--shard", "4/3"]),
        "--shard",
    );
    std::fs::write(d.path().join("foreign.h5"), b"not an hdf5 file at all").unwrap();
    fails(&squeal(d.path(), &["info", "foreign.h5"]), "foreign.h5");
    fails(&squeal(d.path(), &["render", "foreign.h5"]), "foreign.h5");
    fails(&squeal(d.path(), &["info", "absent.h5"]), "absent.h5");
    fails(
        &squeal(
            d.path(),
            &["scan", "tiny.toml", "-o", "foreign.h5", "--resume"],
        ),
        "foreign.h5",
    );
    // A truncated scan file.
    ok(&squeal(
        d.path(),
        &["scan", "tiny.toml", "-o", "t.h5", "--quiet"],
    ));
    let bytes = std::fs::read(d.path().join("t.h5")).unwrap();
    std::fs::write(d.path().join("trunc.h5"), &bytes[..bytes.len() / 2]).unwrap();
    fails(&squeal(d.path(), &["info", "trunc.h5"]), "trunc.h5");
    // The foreign file is still there, untouched.
    assert_eq!(
        std::fs::read(d.path().join("foreign.h5")).unwrap(),
        b"not an hdf5 file at all"
    );
}

#[test]
fn classify_labels_a_csv_of_initial_conditions() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("ics.csv"), "x0,v0\n0,0\n1.1,0\n-2.5,0\n").unwrap();
    ok(&squeal(
        d.path(),
        &[
            "classify", "--ics", "ics.csv", "--out", "l.csv", "--nu", "1e-3",
        ],
    ));
    let text = std::fs::read_to_string(d.path().join("l.csv")).unwrap();
    let rows: Vec<&str> = text.lines().collect();
    assert!(rows[0].starts_with("x0,v0,labels,reason,"));
    assert!(rows[1].contains(",stick_slip,"), "{}", rows[1]);
    assert!(rows[2].contains(",steady_slip,"), "{}", rows[2]);
    assert!(rows[3].contains(",stick_slip,"), "{}", rows[3]);
    std::fs::write(d.path().join("bad.csv"), "x0,v0\n0,zz\n").unwrap();
    fails(
        &squeal(
            d.path(),
            &["classify", "--ics", "bad.csv", "--out", "l2.csv"],
        ),
        "bad.csv:2",
    );
}

#[test]
fn ulc_and_critical_report_the_paper_findings() {
    let d = tempfile::tempdir().unwrap();
    let get = |nu: &str, law: &str| -> serde_json::Value {
        let o = ok(&squeal(
            d.path(),
            &["ulc", "--nu", nu, "--law", law, "--json"],
        ));
        serde_json::from_str(&o).unwrap()
    };
    let a = get("1e-3", "mcmillan");
    let b = get("1e-2", "mcmillan");
    let c = get("1e-3", "mcmillan-nonhysteretic");
    assert_eq!(a["encloses_origin"], false);
    assert_eq!(b["encloses_origin"], true);
    let (ra, rb, rc) = (
        a["r_section"].as_f64().unwrap(),
        b["r_section"].as_f64().unwrap(),
        c["r_section"].as_f64().unwrap(),
    );
    assert!(rb > 3.0 * ra, "the cycle grows with damping: {ra} -> {rb}");
    // Hysteretic and non-hysteretic cycles nearly the same size (measured: 0.3649 vs 0.3661).
    assert!((ra - rc).abs() < 0.02 * ra, "{ra} vs {rc}");
    assert!(a["multiplier"].as_f64().unwrap() > 1.0);
    assert!(a["bracket_width"].as_f64().unwrap() < 1e-8);
    assert!(a["half_dt"]["shift"].as_f64().unwrap().abs() < 5e-3);
    let crit = ok(&squeal(d.path(), &["critical", "--json", "--rtol", "1e-3"]));
    let cv: serde_json::Value = serde_json::from_str(&crit).unwrap();
    let nu = cv["nu"].as_f64().unwrap();
    assert!(nu > 1e-3 && nu < 1e-2, "critical nu {nu}");
    fails(
        &squeal(
            d.path(),
            &["critical", "--nu-lo", "2e-2", "--nu-hi", "5e-2"],
        ),
        "--nu-lo",
    );
}

/// A scan slow enough to interrupt: no early stopping, one thread.
fn start_slow(dir: &Path, out: &str) -> std::process::Child {
    let text = TINY
        .replace("count = 9", "count = 24")
        .replace("count = 7", "count = 16")
        .replace("t_max = 3000.0", "t_max = 2000.0\nearly_stop = \"none\"");
    spec(dir, "slow.toml", &text);
    let child = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .current_dir(dir)
        .args(["scan", "slow.toml", "-o", out, "--quiet", "--threads", "1"])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let journal = dir.join(format!("{out}.journal"));
    for _ in 0..1000 {
        if journal.metadata().map(|m| m.len() > 4096).unwrap_or(false) {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    assert!(
        journal.metadata().map(|m| m.len() > 4096).unwrap_or(false),
        "no block stored in time"
    );
    child
}

#[test]
fn sigint_and_sigterm_keep_finished_blocks_and_exit_130() {
    let d = tempfile::tempdir().unwrap();
    for (sig, out) in [("-INT", "int.h5"), ("-TERM", "term.h5")] {
        let child = start_slow(d.path(), out);
        let stored = std::fs::metadata(d.path().join(format!("{out}.journal")))
            .unwrap()
            .len();
        let st = Command::new("kill")
            .args([sig, &child.id().to_string()])
            .status()
            .unwrap();
        assert!(st.success());
        let o = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(130), "{sig}: {err}");
        assert!(err.contains("--resume"), "{sig}: {err}");
        assert!(!d.path().join(out).exists());
        // The blocks stored before the signal are still in the journal, and the lock is gone.
        let kept = std::fs::metadata(d.path().join(format!("{out}.journal")))
            .unwrap()
            .len();
        assert!(kept >= stored, "{sig}: {kept} < {stored}");
        assert!(!d.path().join(format!("{out}.lock")).exists(), "{sig}");
    }
}

#[test]
fn bad_specs_are_refused_before_any_computing() {
    let d = tempfile::tempdir().unwrap();
    // A NUL in the name used to pass, compute everything, and fail at the final write.
    spec(
        d.path(),
        "nul.toml",
        &TINY.replace("version = 1", "version = 1\nname = \"a\\u0000b\""),
    );
    fails(&squeal(d.path(), &["scan", "nul.toml"]), "`name`");
    assert!(!d.path().join("tiny.h5.journal").exists());
    // A word where a number belongs says which key and what is accepted.
    spec(
        d.path(),
        "word.toml",
        &TINY.replace("nu = 1e-3", "nu = \"small\""),
    );
    let o = squeal(d.path(), &["scan", "word.toml"]);
    fails(&o, "a list of numbers");
    assert!(String::from_utf8_lossy(&o.stderr).contains("nu = \"small\""));
    // A 6.7e11-cell sweep is refused with the estimate, before any file appears.
    spec(
        d.path(),
        "huge.toml",
        &TINY
            .replace(
                "nu = 1e-3",
                "nu = { from = 1e-3, to = 1e-2, count = 10000 }",
            )
            .replace("count = 9", "count = 8192")
            .replace("count = 7", "count = 8192"),
    );
    fails(&squeal(d.path(), &["scan", "huge.toml"]), "--allow-long");
    assert!(!d.path().join("tiny.h5.journal").exists());
}

#[test]
fn a_finished_scan_redraws_a_missing_picture() {
    let d = tempfile::tempdir().unwrap();
    spec(d.path(), "tiny.toml", TINY);
    ok(&squeal(d.path(), &["scan", "tiny.toml", "--quiet"]));
    let png = d.path().join("tiny.png");
    // Killed after the file appeared, before the picture: resume draws it.
    std::fs::remove_file(&png).unwrap();
    ok(&squeal(
        d.path(),
        &["scan", "tiny.toml", "--quiet", "--resume"],
    ));
    assert!(png.exists());
    // So does a plain rerun; and a comment-only edit of the spec is still up to date.
    std::fs::remove_file(&png).unwrap();
    spec(d.path(), "tiny.toml", &format!("# the same scan\n{TINY}"));
    let o = squeal(d.path(), &["scan", "tiny.toml", "--quiet"]);
    ok(&o);
    assert!(String::from_utf8_lossy(&o.stderr).contains("up to date"));
    assert!(png.exists());
    // Another spec is refused naming --force, with --resume too (as for an atlas; it said
    // "already complete: nothing to resume"), and the file is left as it was.
    let file = std::fs::read(d.path().join("tiny.h5")).unwrap();
    spec(
        d.path(),
        "tiny.toml",
        &TINY.replace("nu = 1e-3", "nu = 2e-3"),
    );
    for extra in [&[][..], &["--resume"][..]] {
        let args: Vec<&str> = ["scan", "tiny.toml", "--quiet"]
            .iter()
            .chain(extra)
            .copied()
            .collect();
        fails(&squeal(d.path(), &args), "--force");
    }
    assert_eq!(std::fs::read(d.path().join("tiny.h5")).unwrap(), file);
}

#[test]
fn files_and_messages_are_plain() {
    let d = tempfile::tempdir().unwrap();
    spec(d.path(), "tiny.toml", TINY);
    ok(&squeal(d.path(), &["scan", "tiny.toml", "--quiet"]));
    let info = ok(&squeal(d.path(), &["info", "tiny.h5"]));
    assert!(info.contains("x0 9 values in [-3, 5]"), "{info}");
    assert!(!info.contains("Some("), "{info}");
    // The audit of early stopping against runs to settlement is in the file and the summary.
    let j: serde_json::Value =
        serde_json::from_str(&ok(&squeal(d.path(), &["info", "tiny.h5", "--json"]))).unwrap();
    let c = &j["checks"][0];
    let n = c["audit_cells"].as_i64().unwrap();
    assert!(n >= 1, "{c}");
    assert_eq!(
        c["audit_agrees"].as_i64().unwrap()
            + c["audit_disagrees"].as_i64().unwrap()
            + c["audit_undecided"].as_i64().unwrap(),
        n
    );
    assert!(c["wrong_side_cells"].as_i64().unwrap() >= 0);
    assert!(info.contains("audit (run to settlement)"), "{info}");
    let f = hdf5::File::open(d.path().join("tiny.h5")).unwrap();
    let reason = f.dataset("reason").unwrap();
    assert!(reason.attr("flag_values").is_ok() && reason.attr("flag_meanings").is_ok());
    for v in ["t_decision", "amplitude", "omega"] {
        let ds = f.dataset(v).unwrap();
        assert!(
            ds.attr("units").is_ok() && ds.attr("long_name").is_ok(),
            "{v}"
        );
        assert!(ds.attr("dimensions").is_err(), "{v}");
    }
    // An error's cause is printed once.
    let o = squeal(d.path(), &["info", "absent.h5"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.matches("os error 2").count(), 1, "{err}");
    // classify does not write CSV into a .h5 name.
    std::fs::write(d.path().join("ics.csv"), "x0,v0\n0,0\n").unwrap();
    fails(
        &squeal(d.path(), &["classify", "--ics", "ics.csv", "--out", "o.h5"]),
        ".csv",
    );
    assert!(!d.path().join("o.h5").exists());
}

#[test]
fn trajectory_files_describe_themselves_and_info_reads_them() {
    let d = tempfile::tempdir().unwrap();
    ok(&squeal(
        d.path(),
        &["trajectory", "--t-end", "5", "--out", "traj.h5"],
    ));
    let f = hdf5::File::open(d.path().join("traj.h5")).unwrap();
    let t = f.dataset("t").unwrap();
    // t is a dimension scale (a coordinate) and x is attached to it.
    assert!(t.attr("CLASS").is_ok() && t.attr("units").is_ok());
    let x = f.dataset("x").unwrap();
    assert!(x.attr("DIMENSION_LIST").is_ok() && x.attr("units").is_ok());
    for a in ["schema", "squeal_version", "nu", "lambda", "dt", "law"] {
        assert!(f.attr(a).is_ok(), "{a}");
    }
    let info = ok(&squeal(d.path(), &["info", "traj.h5"]));
    assert!(
        info.contains("trajectory") && info.contains("t in [0, "),
        "{info}"
    );
}
