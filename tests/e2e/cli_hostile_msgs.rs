//! More hostile input: unbounded searches estimated and refused, physical
//! units that overflowed, a damaged file that panicked `compare`, a plot that hung, and
//! messages that printed 300-digit numbers or blamed the wrong key. Each test failed on
//! 48d225a.

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

fn squeal(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the squeal binary runs")
}

/// Runs squeal until it writes a line of stderr containing `needle` or `limit` passes, then
/// ends it; stderr so far, and whether the needle came (a run that hangs or works silently
/// fails the caller's assertion instead of the test hanging with it).
fn squeal_until(dir: &Path, args: &[&str], needle: &str, limit: Duration) -> (bool, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the squeal binary runs");
    let (tx, rx) = std::sync::mpsc::channel();
    let err = child.stderr.take().unwrap();
    std::thread::spawn(move || {
        for line in BufReader::new(err).lines().map_while(Result::ok) {
            let _ = tx.send(line);
        }
    });
    let t0 = Instant::now();
    let mut text = String::new();
    let mut found = false;
    while let Some(left) = limit.checked_sub(t0.elapsed()) {
        match rx.recv_timeout(left) {
            Ok(line) => {
                found |= line.contains(needle);
                text.push_str(&line);
                text.push('\n');
                if found {
                    break;
                }
            }
            Err(std::sync::mpsc::RecvTimeoutError::Timeout) => break,
            // The run ended: everything it said is in.
            Err(_) => break,
        }
    }
    let _ = child.kill();
    let _ = child.wait();
    (found, text)
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The longest run of digits in `s`.
fn longest_digits(s: &str) -> usize {
    s.split(|c: char| !c.is_ascii_digit())
        .map(str::len)
        .max()
        .unwrap_or(0)
}

const SMALL: &str = r#"version = 1
[model]
law = "mcmillan"
nu = 1e-3
[grid]
x0 = { min = -3.0, max = 5.0, count = 4 }
v0 = { min = -4.0, max = 4.0, count = 3 }
"#;

/// `[cycle] samples = 100000, t_return = 1e6` is about 29 days of cycle search per
/// map (1e5 returns of up to 1e8 steps at 250 ns), and was accepted for a sweep of two maps
/// without `--allow-long` and ran on. It is refused before anything runs, naming the
/// search; on 48d225a nothing was said within the limit.
#[test]
fn an_endless_cycle_search_is_refused_before_it_runs() {
    let d = tempfile::tempdir().unwrap();
    let spec = SMALL.replace("nu = 1e-3", "nu = [1e-3, 2e-3]")
        + "[cycle]\nsamples = 100000\nt_return = 1e6\nr_max = 6.0\n[output]\npath = \"o.h5\"\n";
    std::fs::write(d.path().join("s.toml"), spec).unwrap();
    for quiet in [false, true] {
        let mut args = vec!["scan", "s.toml"];
        if quiet {
            args.push("--quiet");
        }
        let (found, err) = squeal_until(d.path(), &args, "--allow-long", Duration::from_secs(20));
        assert!(found, "quiet {quiet}: not refused: {err}");
        assert!(err.contains("cycle search"), "{err}");
        assert!(!d.path().join("o.h5").exists());
    }
}

/// `samples = 65537` ran a silent 51 s pilot (its cycle search alone is up to
/// 65537 x 2e4 steps). The pilot is skipped where it could itself run long: the estimate,
/// at the documented rates, is printed at once.
#[test]
fn a_pilot_that_could_run_long_is_not_run() {
    let d = tempfile::tempdir().unwrap();
    let spec = SMALL.to_string() + "[cycle]\nsamples = 65537\n[output]\npath = \"o.h5\"\n";
    std::fs::write(d.path().join("s.toml"), spec).unwrap();
    let t0 = Instant::now();
    let (found, err) = squeal_until(
        d.path(),
        &["scan", "s.toml"],
        "documented rates",
        Duration::from_secs(20),
    );
    assert!(found, "no estimate: {err}");
    // Well within the pilot's bound (30 s at the documented rate), and far from 51 s.
    assert!(t0.elapsed() < Duration::from_secs(15), "{:?}", t0.elapsed());
}

/// A system 1e200 times heavier, stiffer and more damped than `m = k = 1, c = [1,
/// 2]` has its nondimensional numbers (nu = 0.5 and 1): its scan stored `damping_unit =
/// inf` (2 sqrt(m k) overflowed).
#[test]
fn a_huge_physical_system_stores_finite_units() {
    let d = tempfile::tempdir().unwrap();
    let spec = |scale: &str| {
        format!(
            "version = 1\n[model]\nlaw = \"mcmillan\"\n[physical]\nm = 1{scale}\nk = 1{scale}\n\
             c = 1{scale}\nv_belt = 0.5\nmu_k = 0.3\nmu_s = 0.4\ntau = 0.1\n\
             [grid]\nx0 = {{ min = -1.0, max = 1.0, count = 2 }}\n\
             v0 = {{ min = -1.0, max = 1.0, count = 2 }}\n[classifier]\nt_max = 50.0\n\
             [cycle]\nlocate = false\n[output]\npath = \"p{}.h5\"\n",
            scale.len()
        )
    };
    let mut units = Vec::new();
    for scale in ["", "e200"] {
        std::fs::write(d.path().join("p.toml"), spec(scale)).unwrap();
        let o = squeal(d.path(), &["scan", "p.toml", "--quiet"]);
        assert!(o.status.success(), "{}", stderr(&o));
        let f = hdf5::File::open(d.path().join(format!("p{}.h5", scale.len()))).unwrap();
        let a = |n: &str| f.attr(n).unwrap().read_scalar::<f64>().unwrap();
        units.push((a("damping_unit"), a("nu")));
    }
    // 2 sqrt(m k) = 2 and 2e200; nu = c / (2 sqrt(m k)) = 0.5 in both.
    assert_eq!(units[0], (2.0, 0.5));
    assert!((units[1].0 / 2e200 - 1.0).abs() < 1e-15, "{units:?}");
    assert!((units[1].1 - 0.5).abs() < 1e-15, "{units:?}");
}

/// A small scan file in `dir`, named `name`.
fn scan_file(dir: &Path, name: &str) {
    let spec = format!("{SMALL}[output]\npath = \"{name}\"\n");
    std::fs::write(dir.join("g.toml"), spec).unwrap();
    let o = squeal(dir, &["scan", "g.toml", "--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// A file whose `labels` do not match its axes made `compare` panic (exit 101,
/// "maps of one grid"); `render` refused it. The shape is checked where a map is read.
#[test]
fn a_file_whose_labels_miss_its_axes_is_refused_by_compare() {
    let d = tempfile::tempdir().unwrap();
    scan_file(d.path(), "good.h5");
    std::fs::copy(d.path().join("good.h5"), d.path().join("bad.h5")).unwrap();
    {
        let f = hdf5::File::open_rw(d.path().join("bad.h5")).unwrap();
        f.unlink("labels").unwrap();
        f.new_dataset::<u8>()
            .shape([2, 2])
            .create("labels")
            .unwrap()
            .write_raw(&[0u8, 1, 2, 1])
            .unwrap();
        // Closed here, every handle with it: the file's lock is released before the
        // commands open it (once in four runs `compare` met "unable to lock file").
        f.close().unwrap();
    }
    for args in [
        ["compare", "bad.h5", "good.h5"],
        ["compare", "good.h5", "bad.h5"],
    ] {
        let o = squeal(d.path(), &args);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(!err.contains("panicked"), "{err}");
        assert!(
            err.contains("bad.h5")
                && err.contains("`labels` holds 4 cells")
                && err.contains("make 12"),
            "{err}"
        );
    }
}

/// An HDF5 file with squeal's schema but no `spec` or `name` attribute gave the
/// library's "can't locate attribute in name index"; it is now called not a squeal file,
/// with its path.
#[test]
fn a_file_without_the_spec_attribute_is_not_a_squeal_file() {
    let d = tempfile::tempdir().unwrap();
    scan_file(d.path(), "good.h5");
    std::fs::copy(d.path().join("good.h5"), d.path().join("nospec.h5")).unwrap();
    {
        let f = hdf5::File::open_rw(d.path().join("nospec.h5")).unwrap();
        f.delete_attr("spec").unwrap();
        f.delete_attr("name").unwrap();
        f.close().unwrap();
    }
    // A scan whose output is there already reads its spec to see whether it is up to date.
    let spec = format!("{SMALL}[output]\npath = \"nospec.h5\"\n");
    std::fs::write(d.path().join("n.toml"), spec).unwrap();
    for args in [vec!["info", "nospec.h5"], vec!["scan", "n.toml"]] {
        let o = squeal(d.path(), &args);
        let err = stderr(&o);
        assert!(!o.status.success(), "{args:?}");
        assert!(
            err.contains("nospec.h5") && err.contains("not a squeal file"),
            "{args:?}: {err}"
        );
        assert!(!err.contains("name index"), "{err}");
    }
}

/// `squeal friction --mu-k 5e307` looped for ever in the plotting library's tick
/// search. The range is refused before anything is written, naming the flag.
#[test]
fn a_friction_range_the_plot_cannot_draw_names_the_flag() {
    let d = tempfile::tempdir().unwrap();
    let (found, err) = squeal_until(
        d.path(),
        &["friction", "--mu-k", "5e307", "--out-dir", "fr"],
        "--mu-k",
        Duration::from_secs(20),
    );
    assert!(found, "no refusal: {err}");
    assert!(err.contains("cannot be drawn"), "{err}");
    assert!(!d.path().join("fr").exists());
    // The material in exponent form (`--tau 1e308` printed 309 digits in the titles).
    let o = squeal(
        d.path(),
        &["friction", "--tau", "1e308", "--out-dir", "fr2"],
    );
    let all = stdout(&o) + &stderr(&o);
    assert!(longest_digits(&all) < 20, "{all}");
}

/// A float for an integer key printed it in full (`count = 1e308`: 309 digits).
#[test]
fn a_float_for_an_integer_key_is_named_as_written() {
    let d = tempfile::tempdir().unwrap();
    let spec = SMALL.replace("count = 4", "count = 1e308") + "[output]\npath = \"o.h5\"\n";
    std::fs::write(d.path().join("s.toml"), spec).unwrap();
    let o = squeal(d.path(), &["scan", "s.toml"]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("1e308") && longest_digits(&err) < 20, "{err}");
}

/// Normal output printed 300-digit numbers: the fixed point of `--mu-d 1e-300`,
/// a start of 1e-320, a damping range up to 1e308.
#[test]
fn normal_output_writes_huge_and_tiny_numbers_in_exponent_form() {
    let d = tempfile::tempdir().unwrap();
    for args in [
        vec![
            "trajectory",
            "--law",
            "stribeck",
            "--mu-d",
            "1e-300",
            "--t-end",
            "20",
        ],
        vec!["critical", "--x0", "1e-320"],
        vec!["critical", "--nu-lo", "1e308"],
    ] {
        let o = squeal(d.path(), &args);
        let all = stdout(&o) + &stderr(&o);
        assert!(!all.contains("panicked"), "{args:?}: {all}");
        assert!(longest_digits(&all) < 30, "{args:?}: {all}");
    }
}

/// A CSV written with a UTF-8 byte-order mark (as spreadsheets write it) was
/// refused: "no column `x0` in the header `x0,v0`".
#[test]
fn classify_reads_a_csv_with_a_byte_order_mark() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("ics.csv"), "\u{feff}x0,v0\n0.5,0.0\n").unwrap();
    let o = squeal(
        d.path(),
        &[
            "classify", "--ics", "ics.csv", "--out", "o.csv", "--t-max", "50",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let out = std::fs::read_to_string(d.path().join("o.csv")).unwrap();
    assert_eq!(out.lines().count(), 2, "{out}");
}

/// `classify` said nothing of the work before it (rows x t_max); it now prints its
/// estimate as scans do.
#[test]
fn classify_estimates_its_work() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("ics.csv"), "x0,v0\n0.5,0.0\n1.0,0.0\n").unwrap();
    let args = [
        "classify", "--ics", "ics.csv", "--out", "o.csv", "--t-max", "50",
    ];
    let o = squeal(d.path(), &args);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("2 initial conditions on") && err.contains("roughly"),
        "{err}"
    );
    std::fs::remove_file(d.path().join("o.csv")).unwrap();
    let o = squeal(d.path(), &[&args[..], &["--quiet"]].concat());
    assert!(
        o.status.success() && !stderr(&o).contains("roughly"),
        "{}",
        stderr(&o)
    );
}

/// `[cycle] r_min = 1e-320` was blamed on `r_max` (r_max / r_min overflowed).
#[test]
fn a_tiny_r_min_is_named() {
    let d = tempfile::tempdir().unwrap();
    let spec = SMALL.to_string() + "[cycle]\nr_min = 1e-320\n[output]\npath = \"o.h5\"\n";
    std::fs::write(d.path().join("s.toml"), spec).unwrap();
    let o = squeal(d.path(), &["scan", "s.toml"]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("`cycle.r_min` = 1e-320"), "{err}");
}
