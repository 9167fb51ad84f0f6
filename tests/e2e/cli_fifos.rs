//! A FIFO or a device at every path a command reads or writes besides the scan's and the
//! atlas's (those are `cli_files`): `classify --ics/--out`, `trajectory --out/--plot`,
//! `ulc --plot`, `render -o` and a file `friction --out-dir` writes. Each blocked until
//! killed (`classify --ics /dev/zero` read for 2 s); each is refused naming what is there,
//! before anything is opened or computed. The binary runs under a time limit, so a hang
//! fails the test instead of blocking it.

use std::path::Path;
use std::process::{Command, Output};
use std::time::{Duration, Instant};

/// Longest a refusal may take: it comes before any computing (each case runs in well
/// under a second alone; the limit leaves room for a machine shared by other builds).
const LIMIT: Duration = Duration::from_secs(30);

/// Runs squeal in `dir` with `args`, killed after [`LIMIT`] (`cli_files`' runner): its
/// output and the seconds it took, or `None` if it had to be killed.
fn squeal_within(dir: &Path, args: &[&str]) -> Option<(Output, f64)> {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_squeal"));
    cmd.args(args).current_dir(dir);
    let t0 = Instant::now();
    super::cli_files::squeal_within(&mut cmd, LIMIT).map(|o| (o, t0.elapsed().as_secs_f64()))
}

fn mkfifo(p: &Path) -> bool {
    Command::new("mkfifo")
        .arg(p)
        .status()
        .map(|s| s.success())
        .unwrap_or(false)
}

/// `args` run in `dir` is refused (code 2, no panic) within [`LIMIT`], its message holding
/// every one of `needles`; the seconds it took.
fn refused(dir: &Path, args: &[&str], needles: &[&str]) -> f64 {
    let (o, secs) = squeal_within(dir, args)
        .unwrap_or_else(|| panic!("blocked (killed after {LIMIT:?}): {args:?}"));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(
        o.status.code(),
        Some(2),
        "{args:?} should fail with code 2: {err}"
    );
    assert!(!err.contains("panicked"), "{args:?}: panic: {err}");
    for n in needles {
        assert!(
            err.contains(n),
            "{args:?}: the message should hold {n:?}: {err}"
        );
    }
    secs
}

/// A 3 x 3 scan file `good.h5` for `render`.
fn good_scan(dir: &Path) {
    let spec = "version = 1\n[model]\nlaw = \"mcmillan\"\nnu = 1e-2\n[grid]\n\
         x0 = { min = 0.0, max = 2.0, count = 3 }\nv0 = { min = -1.0, max = 1.0, count = 3 }\n\
         [classifier]\nt_max = 500.0\n[output]\npath = \"good.h5\"\n";
    std::fs::write(dir.join("good.toml"), spec).unwrap();
    let (o, _) = squeal_within(dir, &["scan", "good.toml", "--quiet"]).expect("the tiny scan ends");
    assert!(
        dir.join("good.h5").is_file(),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Every output path of `classify`, `trajectory`, `ulc`, `render` and `friction` given a
/// FIFO, with and without `--force`, and the input of `classify`: each blocked for ever
/// before (with `--force`, or as an input); without `--force` an output FIFO was called a
/// file that "exists (use --force to overwrite it)", which then blocked.
#[test]
fn a_fifo_at_any_commands_path_is_refused_naming_what_it_is() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    if !mkfifo(&dir.join("probe")) {
        eprintln!("skipping: mkfifo did not run");
        return;
    }
    std::fs::write(dir.join("ics.csv"), "x0,v0\n0.5,0.0\n").unwrap();
    good_scan(dir);
    std::fs::create_dir(dir.join("fr")).unwrap();
    let fifo = "a FIFO (named pipe), not a regular file";
    // The command line, the path made a FIFO, the flag named ("" where the path is not a
    // flag's), and whether `--force` is tried too.
    let cases: [(&str, &[&str], &str, bool); 9] = [
        (
            "in.csv",
            &["classify", "--ics", "in.csv", "--out", "l.csv"],
            "--ics",
            true,
        ),
        (
            "l.csv",
            &["classify", "--ics", "ics.csv", "--out", "l.csv"],
            "--out",
            true,
        ),
        (
            "t.csv",
            &["trajectory", "--t-end", "10", "--out", "t.csv"],
            "--out",
            true,
        ),
        (
            "t.h5",
            &["trajectory", "--t-end", "10", "--out", "t.h5"],
            "--out",
            true,
        ),
        (
            "t.png",
            &["trajectory", "--t-end", "10", "--plot", "t.png"],
            "--plot",
            true,
        ),
        ("u.png", &["ulc", "--plot", "u.png"], "--plot", true),
        ("r.png", &["render", "good.h5", "-o", "r.png"], "-o", true),
        (
            "fr/fig6_loop_w200.png",
            &["friction", "--out-dir", "fr"],
            "--out-dir",
            true,
        ),
        // A resume draws its picture at the end: the FIFO was met after the whole run.
        ("good.png", &["scan", "good.toml", "--resume"], "", false),
    ];
    for (name, args, flag, force) in cases {
        let p = dir.join(name);
        let _ = std::fs::remove_file(&p);
        assert!(mkfifo(&p));
        let forced: Vec<&str> = args.iter().copied().chain(["--force"]).collect();
        for a in [args, &forced[..]].into_iter().take(1 + usize::from(force)) {
            refused(dir, a, &[flag, name, fifo]);
        }
        std::fs::remove_file(&p).unwrap();
    }
    // Nothing was written beside them: every refusal came before any output.
    for f in ["l.csv", "t.csv", "t.h5", "t.png", "u.png", "r.png"] {
        assert!(!dir.join(f).exists(), "{f} was written");
    }
    assert_eq!(std::fs::read_dir(dir.join("fr")).unwrap().count(), 0);
}

/// `classify --ics /dev/zero` read a GiB of zeros (2 s) before refusing it as too long; a
/// character device is refused at once, as a FIFO is, naming what it is. (The CLI reads no
/// initial conditions from standard input: `-` is a file name like any other.)
#[test]
fn a_device_as_the_initial_conditions_is_refused_at_once() {
    let d = tempfile::tempdir().unwrap();
    if !Path::new("/dev/zero").exists() {
        eprintln!("skipping: no /dev/zero");
        return;
    }
    // Refused before reading (by what is there, not as a file over 1 GiB after reading
    // one).
    let secs = refused(
        d.path(),
        &["classify", "--ics", "/dev/zero", "--out", "l.csv"],
        &[
            "--ics",
            "/dev/zero is a character device, not a regular file",
        ],
    );
    eprintln!("refused in {secs:.2} s");
    assert!(!d.path().join("l.csv").exists());
}
