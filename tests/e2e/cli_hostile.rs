//! Hostile and careless command lines (issue "Hostile and careless input"): unbounded runs
//! and flags whose errors did not name them are refused before any computing, and a
//! picture cut short by a full disk is drawn again.

use std::path::Path;
use std::process::{Command, Output};

fn squeal(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the squeal binary runs")
}

fn refused(o: Output, needle: &str) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "should fail: {err}");
    assert!(!err.contains("panicked"), "panic: {err}");
    assert!(
        err.contains(needle),
        "message should contain {needle:?}: {err}"
    );
}

/// `--t-max nan` was written into a generated spec and reported as "TOML parse error at
/// line 16 ... t_max = NaN", never naming the flag.
#[test]
fn a_nan_time_limit_names_the_flag() {
    let d = tempfile::tempdir().unwrap();
    refused(
        squeal(d.path(), &["ulc", "--t-max", "nan"]),
        "--t-max NaN: expected a finite time > 0",
    );
    std::fs::write(d.path().join("ics.csv"), "x0,v0\n0.5,0.0\n").unwrap();
    let o = squeal(
        d.path(),
        &[
            "classify", "--ics", "ics.csv", "--out", "o.csv", "--t-max", "nan",
        ],
    );
    refused(o, "--t-max NaN");
}

/// `ulc --r-max 1e300` reported "no unstable cycle" for Table 1 (which has one): the
/// samples of the section search lay too far apart. The atlas spec's rule, naming the flag.
#[test]
fn an_absurd_search_range_names_the_flag() {
    let d = tempfile::tempdir().unwrap();
    refused(
        squeal(d.path(), &["ulc", "--r-max", "1e300"]),
        "`--r-max` = 1e300",
    );
    refused(
        squeal(d.path(), &["ulc", "--rtol", "0.5"]),
        "`--rtol` = 0.5",
    );
}

/// A huge flag value is named in exponent form: `trajectory --dt 1e300` and `--x0 1e300`
/// were reported as 1 followed by 300 zeros.
#[test]
fn a_huge_flag_value_is_named_in_exponent_form() {
    let d = tempfile::tempdir().unwrap();
    for (args, needle) in [
        (
            &["trajectory", "--dt", "1e300"][..],
            "--dt: invalid dt = 1e300:",
        ),
        (
            &["trajectory", "--x0", "1e300"][..],
            "`--x0` = 1e300: a finite coordinate",
        ),
        (
            &["trajectory", "--a1", "1e300", "--law", "cubic"][..],
            "invalid a1 = 1e300:",
        ),
    ] {
        let o = squeal(d.path(), args);
        let n = o.stderr.len();
        refused(o, needle);
        assert!(n < 300, "{n} bytes of message for {args:?}");
    }
}

/// Refusals of the other commands name a huge value in exponent form too: `friction --tau
/// -1e300`, `critical --rtol 1e300` and `compare --min-agreement 1e300` printed 301 digits.
#[test]
fn other_commands_name_a_huge_value_in_exponent_form() {
    let d = tempfile::tempdir().unwrap();
    for (args, needle) in [
        (
            &["friction", "--tau", "-1e300"][..],
            "--tau: invalid tau = -1e300:",
        ),
        (
            &["critical", "--rtol", "1e300"][..],
            "--rtol 1e300: expected",
        ),
        (
            &["compare", "a.h5", "b.h5", "--min-agreement", "1e300"][..],
            "--min-agreement 1e300: expected",
        ),
    ] {
        let o = squeal(d.path(), args);
        let n = o.stderr.len();
        refused(o, needle);
        assert!(n < 300, "{n} bytes of message for {args:?}");
    }
}

/// Runs with no cap: `--verify-rays 1000000000`, `trajectory --dt 1e-12` or `--t-end 1e15`.
#[test]
fn unbounded_runs_are_refused_before_they_start() {
    let d = tempfile::tempdir().unwrap();
    refused(
        squeal(d.path(), &["ulc", "--verify-rays", "1000000000"]),
        "at most 10000 rays",
    );
    refused(
        squeal(d.path(), &["trajectory", "--dt", "1e-12"]),
        "1.000e15 steps, at most 1e10",
    );
    refused(
        squeal(d.path(), &["trajectory", "--t-end", "1e15"]),
        "2.000e17 steps, at most 1e10",
    );
}

/// `critical --x0 1e300` bisected for a start far beyond the escape radius (and printed it
/// with 300 digits), and `--starts` and `--lifetime-t-max` had no bound (1e8 lifetime runs
/// per damping; 2e302 steps per run).
#[test]
fn critical_refuses_a_start_beyond_the_escape_radius_and_endless_lifetimes() {
    let d = tempfile::tempdir().unwrap();
    refused(
        squeal(d.path(), &["critical", "--x0", "1e300"]),
        "`--x0` = 1e300: a finite coordinate with |value| <= 1e6",
    );
    refused(
        squeal(d.path(), &["critical", "--v0", "-2e6"]),
        "`--v0` = -2000000.0",
    );
    refused(
        squeal(
            d.path(),
            &["critical", "--fold", "--lifetimes", "--starts", "100000000"],
        ),
        "--starts 100000000: expected 2 to 4096 starts",
    );
    refused(
        squeal(
            d.path(),
            &[
                "critical",
                "--fold",
                "--lifetimes",
                "--lifetime-t-max",
                "1e300",
            ],
        ),
        "--lifetime-t-max 1e300 with dt 0.005: 2.000e302 steps per run, at most 1e10",
    );
}

/// `trajectory --tau 1e-300` echoed the run's parameters with 300 zeros.
#[test]
fn a_run_echoes_tiny_values_in_exponent_form() {
    let d = tempfile::tempdir().unwrap();
    let o = squeal(d.path(), &["trajectory", "--tau", "1e-300", "--t-end", "1"]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(out.contains(" tau=1e-300 "), "{out}");
    assert!(out.lines().all(|l| l.len() < 300), "{out}");
}

/// `classify` labelled a start at `x0 = 1e300` stick-slip (the start rule, outside the
/// cycle, with no run); a start beyond the escape radius is refused naming its line.
#[test]
fn classify_refuses_a_start_beyond_the_escape_radius() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("ics.csv"), "x0,v0\n0.5,0.0\n\n1e300,0.0\n").unwrap();
    refused(
        squeal(
            d.path(),
            &["classify", "--ics", "ics.csv", "--out", "o.csv"],
        ),
        "ics.csv:4: `x0` = 1e300: a finite coordinate with |value| <= 1e6",
    );
    assert!(!d.path().join("o.csv").exists());
}

/// `trajectory --x0 1e6` of a physical system (metres: 7.3e9 units for the brake below,
/// whose length unit is mu_k g m / k = 137 um) ran from beyond the escape radius. It is
/// refused in the units given (1e6 m, the bound 137.34 m), the model's value after them
/// (it was reported as "`--x0` = 7281199941.75", a number the user never wrote).
#[test]
fn a_physical_start_is_checked_in_the_models_units() {
    let d = tempfile::tempdir().unwrap();
    let brake = [
        "--m", "2", "--k", "5e4", "--c", "5", "--v-belt", "0.05", "--mu-k", "0.35", "--mu-s",
        "0.45", "--tau-s", "1e-3",
    ];
    let args = [&["trajectory", "--t-end", "1", "--x0", "1e6"][..], &brake].concat();
    refused(squeal(d.path(), &args), "`--x0` = 1000000 m:");
    refused(
        squeal(d.path(), &args),
        "a finite coordinate with |value| <= 1e6 (the classifier's escape radius), in the model's units: at most 137.34",
    );
    refused(squeal(d.path(), &args), "where 1000000 m is 7281199941.75");
}

/// A full disk left a 0-byte picture; a rerun said "up to date ... picture: b.png" and
/// left it empty.
#[test]
fn an_empty_picture_is_drawn_again() {
    let d = tempfile::tempdir().unwrap();
    let spec = r#"version = 1
[model]
law = "mcmillan"
nu = 1e-2
[grid]
x0 = { min = 0.0, max = 2.0, count = 3 }
v0 = { min = -1.0, max = 1.0, count = 3 }
[classifier]
t_max = 500.0
[output]
path = "b.h5"
"#;
    std::fs::write(d.path().join("b.toml"), spec).unwrap();
    let o = squeal(d.path(), &["scan", "b.toml", "--quiet"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let png = d.path().join("b.png");
    assert!(std::fs::metadata(&png).unwrap().len() > 8);
    let whole = std::fs::read(&png).unwrap();
    // Empty, and cut short (as a full disk left them): both are drawn again.
    for broken in [&whole[..0], &whole[..whole.len() / 2]] {
        std::fs::write(&png, broken).unwrap();
        let o = squeal(d.path(), &["scan", "b.toml", "--quiet"]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            o.status.success() && err.contains("drew the missing picture"),
            "{err}"
        );
        assert_eq!(std::fs::read(&png).unwrap(), whole, "not redrawn: {err}");
    }
}

/// A tiny damping is printed in exponent form by `scan` (its no-cycle note), by `info` (the
/// stored attribute) and in a map's title (`compare`): `nu = 1e-300` was written out as 300
/// zeros and a 1.
#[test]
fn a_tiny_damping_is_printed_in_exponent_form() {
    let d = tempfile::tempdir().unwrap();
    let spec = r#"version = 1
[model]
law = "mcmillan"
nu = 1e-300
[grid]
x0 = { min = 0.0, max = 2.0, count = 2 }
v0 = { min = -1.0, max = 1.0, count = 2 }
[classifier]
t_max = 100.0
[output]
path = "t.h5"
"#;
    std::fs::write(d.path().join("t.toml"), spec).unwrap();
    let o = squeal(d.path(), &["scan", "t.toml", "--quiet"]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(out.contains("(nu = 1e-300)"), "{out}");
    let o = squeal(d.path(), &["info", "t.h5"]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("\n  nu = 1e-300\n"), "{out}");
    assert!(!out.contains("0000000000"), "{out}");
    // The map's title (compare's lines, the pictures).
    let o = squeal(d.path(), &["compare", "t.h5", "t.h5"]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("  mcmillan nu = 1e-300: "), "{out}");
}

/// Complete records of `kind` in a journal: `SQJR`, kind byte, u32 length (little endian),
/// payload, 8-byte checksum (crates/store/src/journal.rs).
fn records_in(journal: &Path, kind: u8) -> usize {
    let b = std::fs::read(journal).unwrap_or_default();
    let (mut at, mut n) = (0usize, 0usize);
    while at + 9 <= b.len() && &b[at..at + 4] == b"SQJR" {
        let len = u32::from_le_bytes(b[at + 5..at + 9].try_into().unwrap()) as usize;
        if at + 9 + len + 8 > b.len() {
            break;
        }
        n += (b[at + 4] == kind) as usize;
        at += 9 + len + 8;
    }
    n
}

/// SIGINT in the middle of a scan's only block threw the block away (0 of 1 blocks kept,
/// the resume computed all of it), though the message said the blocks in flight are kept.
#[test]
fn a_signal_in_mid_block_keeps_the_block() {
    let d = tempfile::tempdir().unwrap();
    // One block of 12 cells; the stick-slip ones never gather 100000 settled crossings and
    // run to t_max: about 6 s on one thread of the debug build, so the signal lands inside
    // the block.
    let spec = r#"version = 1
[model]
law = "mcmillan"
nu = 1e-3
[grid]
x0 = { min = -3.0, max = 5.0, count = 4 }
v0 = { min = -4.0, max = 4.0, count = 3 }
block_rows = 3
[classifier]
t_max = 5000.0
early_stop = "none"
settle_cycles = 100000
[output]
path = "one.h5"
"#;
    std::fs::write(d.path().join("one.toml"), spec).unwrap();
    let child = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .current_dir(d.path())
        .args(["scan", "one.toml", "--quiet", "--threads", "1"])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let journal = d.path().join("one.h5.journal");
    // The cycle record is written once the map is prepared, before its block starts: a
    // signal right after it can land before the block is in flight (then nothing is in
    // flight to keep, and 0 of 1 stored is right; under load it did, about 1 run in 4). A
    // second later the block (about 6 s) is running.
    for _ in 0..3000 {
        if records_in(&journal, b'C') > 0 {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    std::thread::sleep(std::time::Duration::from_secs(1));
    let st = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(st.success());
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    if o.status.success() {
        // The block finished before the signal (a much faster machine): nothing to test.
        return;
    }
    assert_eq!(o.status.code(), Some(130), "{err}");
    if d.path().join("one.h5").exists() {
        // The block in flight was the last: kept, the file finished, and the signal stops
        // the run before its picture (it ended with the picture drawn and exit 0 before).
        assert!(err.contains("the data file one.h5 is complete"), "{err}");
        assert!(!d.path().join("one.png").exists(), "{err}");
        return;
    }
    assert_eq!(
        records_in(&journal, b'B'),
        1,
        "the block in flight is journalled: {err}"
    );
    assert!(err.contains("1 of 1 blocks are stored"), "{err}");
}

/// `--phi 1e-300` ran and labelled every start outside the unstable cycle "diverged" (the
/// stick-slip orbit, reaching |x| about 1.43 / sin(phi), lay beyond the escape radius 1e6:
/// `squeal_core::law::MIN_PHI`); `--mu-s 1e300` is the same Phi in SI units, and
/// `friction --phi` takes the same bound.
#[test]
fn a_static_peak_beyond_the_escape_radius_names_the_flag() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("ics.csv"), "x0,v0\n0.5,0.0\n").unwrap();
    let physical = [
        "trajectory",
        "--m",
        "2",
        "--k",
        "5e4",
        "--c",
        "5",
        "--v-belt",
        "0.05",
        "--mu-k",
        "0.35",
        "--mu-s",
        "1e300",
        "--tau-s",
        "1e-3",
    ];
    for (args, needle) in [
        (
            &["trajectory", "--phi", "1e-300"][..],
            "--phi: invalid phi = 1e-300",
        ),
        (
            &[
                "classify", "--ics", "ics.csv", "--out", "o.csv", "--phi", "1e-6",
            ],
            "--phi: invalid phi = 1e-6: expected an angle in [1e-5, pi/2]",
        ),
        (&["friction", "--out-dir", "fr", "--phi", "1e-300"], "--phi"),
        (&physical, "--mu-s: invalid mu_s = 1e300"),
    ] {
        refused(squeal(d.path(), args), needle);
    }
    assert!(!d.path().join("o.csv").exists() && !d.path().join("fr").exists());
}

/// `squeal info`'s `grid:` line wrote the stored axes as Rust's plain `{}` does: a grid
/// from 1e-7 to 3e-7 read `[0.0000001, 0.0000003]` (and a value of 1e300 would be 301
/// digits); it now writes them as the error messages do (`squeal_core::error::Number`).
#[test]
fn info_writes_the_grid_in_exponent_form() {
    let d = tempfile::tempdir().unwrap();
    // Two cells per axis near x = 0 (outside Table 1's unstable cycle, decided at the start).
    std::fs::write(
        d.path().join("s.toml"),
        "version = 1\n[model]\nlaw = \"mcmillan\"\nnu = 1e-3\n[grid]\n\
         x0 = { min = 1e-7, max = 3e-7, count = 2 }\nv0 = { min = -2e-7, max = 0.0, count = 2 }\n\
         [output]\npath = \"s.h5\"\n",
    )
    .unwrap();
    let o = squeal(d.path(), &["scan", "s.toml", "--quiet"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = squeal(d.path(), &["info", "s.h5"]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains("grid: x0 2 values in [1e-7, 3e-7], v0 2 values in [-2e-7, 0]"),
        "{out}"
    );
}

/// SIGTERM once a scan's data file was finished, while its pictures were drawn, only
/// printed "stopping after the blocks in flight" (there were none) and the drawing went on
/// to the end (exit 0). Now it ends the run at once (code 130), saying the data file is
/// complete and how to draw the pictures, and leaves no cut picture. The signal is sent the
/// moment the finished file appears and the journal is gone (`squeal_scan::finish::finish`
/// publishes the file, then removes the journal; the drawing follows, about 0.2 s for these
/// 12 maps in the debug build).
#[test]
fn a_signal_while_drawing_stops_the_drawing() {
    let d = tempfile::tempdir().unwrap();
    let spec = "version = 1\n[model]\nlaw = \"mcmillan\"\n\
                nu = [1e-3, 2e-3, 3e-3, 4e-3, 5e-3, 6e-3, 7e-3, 8e-3, 9e-3, 1e-2, 1.1e-2, 1.2e-2]\n\
                [grid]\nx0 = { min = -3.0, max = 5.0, count = 2 }\n\
                v0 = { min = -4.0, max = 4.0, count = 2 }\n[classifier]\nt_max = 300.0\n\
                [output]\npath = \"d.h5\"\n";
    // (t_max = 300 bounds each map's census runs: 4 s of CPU for the 12 maps in a release
    // build against 44 s at the default; the labels are not what is tested.)
    let old_pictures = pictures_of_an_older_spec(d.path(), spec);
    std::fs::write(d.path().join("d.toml"), spec).unwrap();
    let child = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .current_dir(d.path())
        .args(["scan", "d.toml", "--quiet", "--force"])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let (out, journal) = (d.path().join("d.h5"), d.path().join("d.h5.journal"));
    for _ in 0..120_000 {
        if out.exists() && !journal.exists() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    assert!(out.exists(), "the scan finished its file");
    let st = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(st.success());
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !err.contains("stopping after the blocks in flight"),
        "the signal was taken for one while computing: {err}"
    );
    if o.status.success() {
        // The drawing ended before the signal (a much faster machine): nothing to test.
        return;
    }
    assert_eq!(o.status.code(), Some(130), "{err}");
    assert!(
        err.contains("the data file") && err.contains("d.h5 is complete"),
        "{err}"
    );
    assert!(err.contains("squeal scan d.toml -o d.h5 --resume"), "{err}");
    // Any picture left is whole (signature and closing IEND chunk) and this run's, not the
    // earlier spec's.
    for (png, old) in &old_pictures {
        if let Ok(b) = std::fs::read(d.path().join(png)) {
            assert!(
                b.starts_with(b"\x89PNG") && b.ends_with(b"IEND\xAE\x42\x60\x82"),
                "{png}"
            );
            assert!(&b != old, "{png} is the earlier spec's picture");
        }
    }
    // The rerun draws what is missing: every picture is then this spec's.
    let o = squeal(d.path(), &["scan", "d.toml", "--resume", "--quiet"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for (png, old) in &old_pictures {
        let b = std::fs::read(d.path().join(png)).unwrap();
        assert!(&b != old, "{png} is still the earlier spec's picture");
    }
}

/// The pictures (name, bytes) that a scan of a smaller version of `spec` leaves in `dir`, its
/// data file removed.
fn pictures_of_an_older_spec(dir: &Path, spec: &str) -> Vec<(&'static str, Vec<u8>)> {
    // An earlier run of another spec (2 maps on 3 x 3 cells) left its pictures: the run
    // below overwrites them with --force. A signal that stopped its drawing used to leave
    // them beside the new data, and the rerun called them up to date.
    let older = spec
        .replace(
            "nu = [1e-3, 2e-3, 3e-3, 4e-3, 5e-3, 6e-3, 7e-3, 8e-3, 9e-3, 1e-2, 1.1e-2, 1.2e-2]",
            "nu = [1e-3, 2e-3]",
        )
        .replace("count = 2", "count = 3");
    std::fs::write(dir.join("d.toml"), older).unwrap();
    let o = squeal(dir, &["scan", "d.toml", "--quiet"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let old_pictures: Vec<(&'static str, Vec<u8>)> = ["d.png", "d-cycle.png"]
        .into_iter()
        .map(|p| (p, std::fs::read(dir.join(p)).unwrap()))
        .collect();
    std::fs::remove_file(dir.join("d.h5")).unwrap();
    old_pictures
}

/// `squeal info f.h5 | head`: a reader that stops early ends the output quietly. Every line
/// after the reader had gone panicked ("failed printing to stdout: Broken pipe", exit 101).
#[test]
fn info_to_a_reader_that_stops_early_ends_quietly() {
    let d = tempfile::tempdir().unwrap();
    let spec = "version = 1\n[model]\nlaw = \"mcmillan\"\nnu = 1e-3\n[grid]\n\
                x0 = { min = -3.0, max = 5.0, count = 2 }\n\
                v0 = { min = -4.0, max = 4.0, count = 2 }\n[output]\npath = \"i.h5\"\n";
    std::fs::write(d.path().join("i.toml"), spec).unwrap();
    let o = squeal(d.path(), &["scan", "i.toml", "--quiet"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut child = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .current_dir(d.path())
        .args(["info", "i.h5"])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // The reader goes before the description is written (reading the file comes first).
    drop(child.stdout.take());
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!err.contains("panicked"), "{err}");
    assert!(o.status.success(), "{:?}: {err}", o.status);
}

/// Shards of a random-sample scan merge into one file and end with code 0: the merge used to
/// go on to draw the file, a list of points and not a map, and end with "error: ... not a
/// map to draw" (code 2) after writing it.
#[test]
fn random_sample_shards_merge_without_drawing() {
    let d = tempfile::tempdir().unwrap();
    let spec = "version = 1\n[model]\nlaw = \"mcmillan\"\nnu = 1e-3\n[sample]\nkind = \"random\"\n\
                n = 40\nseed = 1\nregion = { x0 = [-2.0, 2.0], v0 = [0.0, 2.0] }\n\
                [output]\npath = \"m.h5\"\n";
    std::fs::write(d.path().join("m.toml"), spec).unwrap();
    for (k, out) in [("1/2", "s1.h5"), ("2/2", "s2.h5")] {
        let o = squeal(
            d.path(),
            &["scan", "m.toml", "--shard", k, "-o", out, "--quiet"],
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let o = squeal(d.path(), &["merge", "s1.h5", "s2.h5", "-o", "m.h5"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(d.path().join("m.h5").exists() && !d.path().join("m.png").exists());
}
