//! Unit slips and values out of range, through the binary: a brake's measured curve given
//! in mm/s or in percent is warned of before any run, a belt speed the step cannot resolve
//! is refused by the flag at fault, every refusal names the flag the user gave with its
//! value in the units given, and `critical --fold` raises its own top. Each test fails on
//! d424b26: there the slips ran silently (a curve in mm/s said "steady slip", one in
//! percent a stick-slip with the pad displaced 29 cm), `--normal-force 1e308` reported a
//! "stick-slip" of +-2e304 m/s, `--normal-force 5e-324` was blamed on `--m`, and `--x0 1e3`
//! was reported as 7281199.94.

use std::path::Path;
use std::process::{Command, Output};

fn squeal(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("running squeal")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).to_string()
}

/// scans/data/pad-mu.csv with its slip speeds times `speed` and its mu times `mu` (1000:
/// mm/s; 100: percent), written to `name` in `dir`.
fn pad_curve(dir: &Path, name: &str, speed: f64, mu: f64) -> String {
    let shipped = concat!(env!("CARGO_MANIFEST_DIR"), "/scans/data/pad-mu.csv");
    let mut out = String::new();
    for line in std::fs::read_to_string(shipped).unwrap().lines() {
        match line.split_once(',') {
            Some((s, m)) if s.parse::<f64>().is_ok() => {
                let (s, m): (f64, f64) = (s.parse().unwrap(), m.trim().parse().unwrap());
                out.push_str(&format!("{:?},{:?}\n", s * speed, m * mu));
            }
            _ => out.push_str(&format!("{line}\n")),
        }
    }
    std::fs::write(dir.join(name), out).unwrap();
    name.into()
}

/// The brake of README section 4 on a measured curve (`--law table`), with the flags of a
/// one-cell run.
const BRAKE: [&str; 12] = [
    "--m",
    "0.8",
    "--k",
    "2e5",
    "--c",
    "60",
    "--v-belt",
    "0.3",
    "--normal-force",
    "1500",
    "--law",
    "table",
];

/// A new user's brake on a measured curve given in mm/s or in percent gets a warning on
/// stderr, naming `--friction-csv` and what to do, before any run (`trajectory`, `classify`,
/// and `scan` of a spec naming the same curve); the curve in m/s gets none.
#[test]
fn a_brake_on_a_curve_in_mm_per_s_or_percent_is_warned_before_any_run() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cases = [
        (
            pad_curve(d, "mm.csv", 1000.0, 1.0),
            "its slip speeds run to 2000 m/s",
        ),
        (pad_curve(d, "pct.csv", 1.0, 100.0), "mu reaches 48"),
    ];
    std::fs::write(d.join("ics.csv"), "x0,v0\n0,0\n").unwrap();
    for (csv, words) in &cases {
        let want = format!("warning: --friction-csv {csv}: {words}");
        let mut args = vec!["trajectory", "--t-end", "1", "--friction-csv", csv];
        args.extend(BRAKE);
        let o = squeal(d, &args);
        let err = stderr(&o);
        let out = String::from_utf8_lossy(&o.stdout);
        assert!(o.status.success() && err.starts_with(&want), "{err}{out}");
        let mut args = vec!["classify", "--ics", "ics.csv", "--out", "o.csv", "--force"];
        args.extend(["--t-max", "10", "--friction-csv", csv]);
        args.extend(BRAKE);
        let err = stderr(&squeal(d, &args));
        assert!(err.starts_with(&want), "{err}");
        // A spec: the warning names its key, before the pilot or any work.
        let spec = format!(
            "version = 1\n[model]\nlaw = \"table\"\n[physical]\nm = 0.8\nk = 2e5\nc = 60.0\n\
             v_belt = 0.3\nnormal_force = 1500.0\nfriction_csv = \"{csv}\"\n[grid]\n\
             x0 = {{ min = -1e-3, max = 1e-3, count = 2 }}\nv0 = {{ min = 0.0, max = 0.0, count = 1 }}\n\
             [classifier]\nt_max = 10.0\n[output]\npath = \"s.h5\"\n"
        );
        std::fs::write(d.join("s.toml"), spec).unwrap();
        let o = squeal(d, &["scan", "s.toml", "-o", "s.h5", "--force", "--quiet"]);
        let err = stderr(&o);
        let want = format!("warning: `physical.friction_csv`: {words}");
        assert!(err.starts_with(&want), "{err}");
    }
    let shipped = pad_curve(d, "m.csv", 1.0, 1.0);
    let mut args = vec!["trajectory", "--t-end", "1", "--friction-csv", &shipped];
    args.extend(BRAKE);
    let err = stderr(&squeal(d, &args));
    assert!(!err.contains("--friction-csv m.csv"), "{err}");
}

/// `--v-belt 300` (mm/s typed as m/s) on the curve that ends at 2 m/s is warned of with
/// the value given and its reading in mm/s.
#[test]
fn a_belt_speed_beyond_the_curve_is_warned_of() {
    let dir = tempfile::tempdir().unwrap();
    let csv = pad_curve(dir.path(), "m.csv", 1.0, 1.0);
    let mut args = vec!["trajectory", "--t-end", "1", "--friction-csv", &csv];
    args.extend(BRAKE);
    let i = args.iter().position(|a| *a == "--v-belt").unwrap();
    args[i + 1] = "300";
    let err = stderr(&squeal(dir.path(), &args));
    assert!(
        err.starts_with(
            "warning: --v-belt = 300 m/s is beyond the friction curve's last slip speed, 2 m/s"
        ) && err.lines().next().unwrap().ends_with("give 0.3 m/s"),
        "{err}"
    );
}

/// The brake of scans/brake.toml (2 kg, 50 kN/m, 10 N s/m, 0.05 m/s, mu_k 0.35, mu_s 0.45, 1 ms).
const MCMILLAN: [&str; 14] = [
    "--m", "2", "--k", "5e4", "--c", "10", "--v-belt", "0.05", "--mu-k", "0.35", "--mu-s", "0.45",
    "--tau-s", "1e-3",
];

/// `MCMILLAN` with `flag value` in place of its own (or added).
fn with(flag: &'static str, value: &'static str) -> Vec<&'static str> {
    let mut args: Vec<&str> = MCMILLAN.to_vec();
    match args.iter().position(|a| *a == flag) {
        Some(i) => args[i + 1] = value,
        None => args.extend([flag, value]),
    }
    args
}

/// A belt speed the step cannot resolve (lambda = 4.5e-307 under a clamp of 1e308 N) is
/// refused before any run, naming the flag at fault with its value; the model's own
/// `--lambda 1e-9` names `--lambda`. On d424b26 each ran and reported a "stick-slip".
#[test]
fn a_belt_speed_below_the_step_is_refused_by_the_flag_at_fault() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (
            with("--normal-force", "1e308"),
            "error: --normal-force: invalid normal_force = 1e308",
        ),
        (with("--g", "1e308"), "error: --g: invalid g = 1e308"),
        (
            with("--v-belt", "1e-12"),
            "error: --v-belt: invalid v_belt = 1e-12",
        ),
        (
            vec!["--lambda", "1e-9"],
            "error: --lambda: invalid lambda = 1e-9",
        ),
    ];
    for (model, head) in cases {
        for cmd in ["trajectory", "critical", "ulc"] {
            let mut args = vec![cmd];
            args.extend(&model);
            let o = squeal(dir.path(), &args);
            let err = stderr(&o);
            assert!(
                !o.status.success() && err.starts_with(head) && err.contains("dt = 0.005"),
                "{cmd} {model:?}: {err}"
            );
            assert!(o.stdout.is_empty(), "{cmd}: nothing runs");
        }
    }
}

/// A bracket in the belt speed reaching below the step is refused by its flag before any
/// run (it was refused at its first run, naming the model's `lambda`, a flag not given).
#[test]
fn a_lambda_bracket_below_the_step_is_refused_by_its_flag() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "critical",
        "--in",
        "lambda",
        "--lambda-lo",
        "0.001",
        "--rtol",
        "1e-2",
    ];
    let err = stderr(&squeal(dir.path(), &args));
    assert!(
        err.starts_with(
            "error: --lambda-lo 0.001: expected a belt speed of at least the step dt = 0.005"
        ),
        "{err}"
    );
}

/// A figure made of several keys out of range names the flag whose value is at fault:
/// `--normal-force 5e-324` (was `--m`), `--m 1e-300` (was `--c`), `--k 1e300` (was
/// `--v-belt`) on the README's McMillan brake (0.8 kg, 200 kN/m, 1.5 kN).
#[test]
fn a_figure_out_of_range_names_the_flag_at_fault() {
    let dir = tempfile::tempdir().unwrap();
    let pad = [
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
    ];
    for (flag, value) in [
        ("--normal-force", "5e-324"),
        ("--m", "1e-300"),
        ("--k", "1e300"),
    ] {
        let mut args = vec!["trajectory"];
        args.extend(pad);
        let i = args.iter().position(|a| *a == flag).unwrap();
        args[i + 1] = value;
        let err = stderr(&squeal(dir.path(), &args));
        let key = flag.trim_start_matches("--").replace('-', "_");
        let head = format!("error: {flag}: invalid {key} = {value}: it makes ");
        assert!(err.starts_with(&head), "{flag}: {err}");
    }
}

/// A start out of the escape radius given in metres is reported as given, `--x0 1e3` as
/// 1000 m (the model's 7281199.94 after it), by `trajectory`, `critical` and `classify`.
#[test]
fn a_start_out_of_range_is_reported_in_the_units_given() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("ics.csv"), "x0,v0\n1e3,0\n").unwrap();
    for cmd in [
        vec!["trajectory", "--x0", "1e3"],
        vec!["critical", "--x0", "1e3"],
        vec!["classify", "--ics", "ics.csv", "--out", "o.csv"],
    ] {
        let mut args = cmd.clone();
        args.extend(MCMILLAN);
        let err = stderr(&squeal(dir.path(), &args));
        // One length unit is mu_k g m / k = 0.35 9.81 2 / 5e4 = 1.3734e-4 m.
        assert!(
            err.contains("x0` = 1000 m:") && err.contains("at most 137.34"),
            "{cmd:?}: {err}"
        );
    }
}

/// `critical --fold` of the brake on its measured curve (c = 60 N s/m): the shortcut finds
/// a start still squealing at the default top nu = 0.05 (c = 40 N s/m), and the runs raise
/// it as plain `critical` does (d424b26: "--nu-hi 0.05: it still squeals there; raise
/// --nu-hi"). Given by the flag, the top is kept, and the refusal says c too.
#[test]
fn critical_fold_raises_its_own_top_and_speaks_in_c() {
    let dir = tempfile::tempdir().unwrap();
    let csv = pad_curve(dir.path(), "m.csv", 1.0, 1.0);
    let mut args = vec![
        "critical",
        "--fold",
        "--nu-hi",
        "0.05",
        "--friction-csv",
        &csv,
    ];
    args.extend(BRAKE);
    let err = stderr(&squeal(dir.path(), &args));
    // 2 sqrt(m k) = 2 sqrt(0.8 * 2e5) = 800 N s/m: nu = 0.05 is c = 40 N s/m.
    assert!(
        err.contains("--nu-hi 0.05 (c = 40 N s/m)") && err.contains("raise --nu-hi"),
        "{err}"
    );
    args.drain(2..4);
    let o = squeal(dir.path(), &args);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success() && out.contains("from runs") && out.contains("in SI units: c = "),
        "{out}{}",
        stderr(&o)
    );
}
