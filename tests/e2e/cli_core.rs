//! End-to-end tests of `squeal trajectory` and `squeal friction`: the real binary in a fresh
//! temporary folder, its files reopened, and bad input refused with a message naming the flag;
//! and the helpers `cli_ulc_critical` shares.

use std::path::Path;
use std::process::{Command, Output};

/// Runs `squeal args...` in `dir`.
pub(crate) fn squeal(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the squeal binary runs")
}

pub(crate) fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

pub(crate) fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Asserts success and returns stdout.
pub(crate) fn ok(o: Output) -> String {
    assert!(
        o.status.success(),
        "failed: {}\nstdout: {}",
        stderr(&o),
        stdout(&o)
    );
    stdout(&o)
}

/// Asserts a clean refusal (non-zero exit, no panic) whose message contains `needle`.
pub(crate) fn refused(o: Output, needle: &str) {
    let err = stderr(&o);
    assert!(!o.status.success(), "should fail: {}", stdout(&o));
    assert!(!err.contains("panicked"), "panic: {err}");
    assert!(err.contains(needle), "message should name {needle}: {err}");
}

pub(crate) fn tmp() -> tempfile::TempDir {
    tempfile::tempdir().expect("a temporary folder")
}

/// The force in each row `t,x,v,a,force` is the friction law at that row's slip velocity
/// and acceleration, F = L(x' - lambda, a), evaluated here independently of the stepper
/// (which solves that implicit equation for a: a wrong root or an unconverged solve shows).
/// Paper parameters (Table 1): lambda = 3, nu = 1e-3. Returns the rows on the quasi-static
/// branch.
fn assert_force_is_the_law(rows: &[Vec<f64>]) -> usize {
    let p = squeal_core::Params::paper(squeal_core::FrictionLaw::McMillan, 1e-3);
    let mut quasi_static = 0;
    for (k, r) in rows.iter().enumerate() {
        let law = squeal_core::friction::force(&p, r[2] - p.lambda, r[3]);
        assert!(
            (r[4] - law.force).abs() < 1e-10,
            "row {k}: F = {} but L(x' - lambda, a) = {}",
            r[4],
            law.force
        );
        if law.branch == squeal_core::friction::Branch::QuasiStatic {
            quasi_static += 1;
        }
    }
    quasi_static
}

/// A trajectory CSV without its `#` lines (each column's units, the sampling): the header
/// `t,x,v,a,force` and the rows.
pub(crate) fn samples_csv(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| format!("{l}\n"))
        .collect()
}

#[test]
fn trajectory_writes_csv_rows() {
    let dir = tmp();
    let out = ok(squeal(
        dir.path(),
        &[
            "trajectory",
            "--dt",
            "0.01",
            "--t-end",
            "20",
            "--every",
            "1",
            "--out",
            "traj.csv",
        ],
    ));
    assert!(out.contains("traj.csv"), "{out}");
    let text = samples_csv(&dir.path().join("traj.csv"));
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("t,x,v,a,force"));
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|f| f.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 2001);
    assert!(rows.iter().all(|r| r.len() == 5));
    // From rest: t = 0, x = 0, x' = 0; the force is F(-lambda, a) = a, about 1.
    assert_eq!(&rows[0][..3], &[0.0, 0.0, 0.0]);
    assert!((rows[0][3] - rows[0][4]).abs() < 1e-12 && (rows[0][4] - 1.0).abs() < 0.1);
    for (k, r) in rows.iter().enumerate() {
        assert!((r[0] - k as f64 * 0.01).abs() < 1e-9, "row {k}: {r:?}");
    }
    assert_force_is_the_law(&rows);
    // A start 4 from the fixed point reaches the belt speed (lambda = 3): rows on the
    // quasi-static branch near zero slip too.
    ok(squeal(
        dir.path(),
        &[
            "trajectory",
            "--x0",
            "-3",
            "--t-end",
            "20",
            "--every",
            "1",
            "--out",
            "big.csv",
        ],
    ));
    let text = samples_csv(&dir.path().join("big.csv"));
    let rows: Vec<Vec<f64>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|f| f.parse().unwrap()).collect())
        .collect();
    assert!(
        assert_force_is_the_law(&rows) > 0,
        "no row on the quasi-static branch"
    );
    // The default step (crates/core/src/defaults.rs) over t in [0, 20]: the last row is t = 20.
    let n = (20.0 / squeal_core::defaults::DT).round() as usize;
    assert_eq!(rows.len(), n + 1);
    assert!((rows[n][0] - 20.0).abs() < 1e-9);
}

#[test]
fn trajectory_decimates_and_refuses_to_overwrite() {
    let dir = tmp();
    let args = [
        "trajectory",
        "--dt",
        "0.01",
        "--t-end",
        "20",
        "--every",
        "10",
        "--x0",
        "-1.5",
        "--v0",
        "-0.5",
        "--out",
        "t.csv",
    ];
    ok(squeal(dir.path(), &args));
    let text = samples_csv(&dir.path().join("t.csv"));
    assert_eq!(text.lines().count(), 1 + 201);
    let first: Vec<f64> = text
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .map(|f| f.parse().unwrap())
        .collect();
    assert_eq!(&first[..3], &[0.0, -1.5, -0.5]);
    let second: Vec<f64> = text
        .lines()
        .nth(2)
        .unwrap()
        .split(',')
        .map(|f| f.parse().unwrap())
        .collect();
    assert!((second[0] - 0.1).abs() < 1e-12);
    refused(squeal(dir.path(), &args), "--force");
    let mut forced = args.to_vec();
    forced.push("--force");
    ok(squeal(dir.path(), &forced));
}

#[test]
fn trajectory_json_summary_has_the_fields() {
    let dir = tmp();
    let out = ok(squeal(
        dir.path(),
        &["trajectory", "--dt", "0.01", "--t-end", "500", "--json"],
    ));
    let j: serde_json::Value = serde_json::from_str(&out).expect("one JSON object");
    assert_eq!(j["params"]["law"], "mcmillan");
    assert_eq!(j["params"]["solver"], "robust");
    assert_eq!(j["params"]["nu"], 1e-3);
    assert_eq!(j["steps"], 50_000);
    // nu = 1e-3 from rest: stick-slip (paper Fig 9). Rest lies outside the unstable cycle,
    // whose outside is invariant: labelled at the start, as a scan labels it.
    assert_eq!(j["classification"]["regime"], "stick_slip");
    assert_eq!(j["classification"]["reason"], "start_outside_cycle");
    // The run's own verdict, well before t = 500, by the attractor test: the quasi-periodic
    // band with sticking (the wide-band rule fires first here; the 5% settling rule a
    // few crossings later).
    assert_eq!(j["classification"]["run"]["regime"], "stick_slip");
    let reason = j["classification"]["run"]["reason"].as_str().unwrap();
    assert!(
        ["sticking_band", "settled_stick_slip"].contains(&reason),
        "{reason}"
    );
    let omega = j["oscillation"]["omega"].as_f64().expect("omega");
    assert!((omega - 0.96).abs() < 0.015, "{omega}");
    assert!(j["oscillation"]["crossings"].as_u64().unwrap() > 50);
    assert!(j["oscillation"]["amplitude"].as_f64().unwrap() > 2.0);
    assert_eq!(j["stats"]["solves"], 50_001);
    for key in [
        "evaluations",
        "newton_steps",
        "bisections",
        "expansions",
        "multi_root",
        "discontinuities",
        "failures",
        "iterations",
        "unconverged",
        "sticks",
    ] {
        assert!(j["stats"][key].is_u64(), "stats.{key}");
    }
    assert!(j["max_residual"].as_f64().unwrap() < 1e-12);
    assert_eq!(j["unconverged_steps"], 0);
    assert!((j["final_state"]["t"].as_f64().unwrap() - 500.0).abs() < 1e-9);
    assert_eq!(j["fixed_point"]["x"], 1.0);
    assert!(j["squeal_version"].is_string());
}

#[test]
fn trajectory_reports_paper_iteration_failures() {
    let dir = tmp();
    let out = ok(squeal(
        dir.path(),
        &[
            "trajectory",
            "--solver",
            "paper",
            "--t-end",
            "300",
            "--json",
        ],
    ));
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    let unconverged = j["unconverged_steps"].as_u64().unwrap();
    assert!(unconverged > 100, "{unconverged}");
    assert_eq!(j["stats"]["unconverged"].as_u64().unwrap(), unconverged);
    let times = j["first_unconverged_times"].as_array().unwrap();
    assert_eq!(times.len(), 5);
    assert!(times.windows(2).all(|w| w[0].as_f64() < w[1].as_f64()));
    // The text summary says it too.
    let text = ok(squeal(
        dir.path(),
        &["trajectory", "--solver", "paper", "--t-end", "300"],
    ));
    assert!(text.contains("unconverged steps:"), "{text}");
}

#[test]
fn steady_slip_and_no_oscillation() {
    let dir = tmp();
    // nu = 1e-2 from rest: steady slip (paper Fig 10).
    let out = ok(squeal(
        dir.path(),
        &["trajectory", "--nu", "1e-2", "--t-end", "2000", "--json"],
    ));
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(j["classification"]["regime"], "steady_slip");
    // At the fixed point nothing moves: no crossing, no frequency.
    let out = ok(squeal(
        dir.path(),
        &["trajectory", "--x0", "1", "--t-end", "10", "--json"],
    ));
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(j["oscillation"]["omega"].is_null());
    assert_eq!(j["oscillation"]["crossings"], 0);
    let text = ok(squeal(
        dir.path(),
        &["trajectory", "--x0", "1", "--t-end", "10"],
    ));
    assert!(text.contains("final oscillation: none"), "{text}");
    assert!(text.contains("ended: steady slip"), "{text}");
}

#[test]
fn trajectory_draws_the_phase_plane() {
    let dir = tmp();
    ok(squeal(
        dir.path(),
        &["trajectory", "--t-end", "100", "--plot", "phase.png"],
    ));
    let png = std::fs::read(dir.path().join("phase.png")).unwrap();
    assert!(png.len() > 1000 && png.starts_with(b"\x89PNG"));
    refused(
        squeal(dir.path(), &["trajectory", "--plot", "phase.png"]),
        "--force",
    );
    refused(
        squeal(dir.path(), &["trajectory", "--plot", "phase.jpg"]),
        "--plot",
    );
}

#[test]
fn trajectory_writes_hdf5() {
    let dir = tmp();
    ok(squeal(
        dir.path(),
        &[
            "trajectory",
            "--law",
            "mcmillan-nonhysteretic",
            "--nu",
            "0.002",
            "--dt",
            "0.01",
            "--t-end",
            "10",
            "--every",
            "2",
            "--out",
            "t.h5",
        ],
    ));
    let f = hdf5::File::open(dir.path().join("t.h5")).unwrap();
    for name in ["t", "x", "v", "a", "force"] {
        let d: Vec<f64> = f.dataset(name).unwrap().read_raw().unwrap();
        assert_eq!(d.len(), 501, "{name}");
    }
    let t: Vec<f64> = f.dataset("t").unwrap().read_raw().unwrap();
    assert!((t[500] - 10.0).abs() < 1e-9 && (t[1] - 0.02).abs() < 1e-12);
    let num = |name: &str| -> f64 { f.attr(name).unwrap().read_scalar().unwrap() };
    assert_eq!(num("nu"), 0.002);
    assert_eq!(num("lambda"), 3.0);
    assert_eq!(num("dt"), 0.01);
    assert_eq!(num("t_end"), 10.0);
    let text = |name: &str| -> String {
        let s: hdf5::types::VarLenUnicode = f.attr(name).unwrap().read_scalar().unwrap();
        s.as_str().to_string()
    };
    assert_eq!(text("law"), "mcmillan-nonhysteretic");
    assert_eq!(text("solver"), "robust");
    assert_eq!(text("squeal_version"), env!("CARGO_PKG_VERSION"));
    drop(f);
    refused(
        squeal(dir.path(), &["trajectory", "--t-end", "1", "--out", "t.h5"]),
        "--force",
    );
}

#[test]
fn trajectory_refuses_bad_input() {
    let dir = tmp();
    for (args, flag) in [
        (&["--nu", "-1"][..], "--nu"),
        (&["--nu", "NaN"], "--nu"),
        (&["--tau", "0"], "--tau"),
        (&["--phi", "2"], "--phi"),
        (&["--dt", "0"], "--dt"),
        (&["--dt", "inf"], "--dt"),
        (&["--law", "bogus"], "--law"),
        (&["--solver", "magic"], "--solver"),
        (&["--lambda", "NaN"], "--lambda"),
        (&["--x0", "NaN"], "--x0"),
        (&["--v0", "inf"], "--v0"),
        (&["--t-end", "-5"], "--t-end"),
        (&["--t-end", "0"], "--t-end"),
        (&["--every", "0"], "--every"),
        (&["--every", "-3"], "--every"),
        (&["--out", "t.txt"], "--out"),
        (&["--out", "noext"], "--out"),
        (&["--out", "missing/dir/t.csv", "--t-end", "1"], "--out"),
    ] {
        let mut all = vec!["trajectory"];
        all.extend_from_slice(args);
        refused(squeal(dir.path(), &all), flag);
    }
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn friction_writes_its_files() {
    let dir = tmp();
    let out = ok(squeal(dir.path(), &["friction", "--out-dir", "fr"]));
    let stems = [
        "fig4_5_fixed_acceleration",
        "fig6_loop_w200",
        "fig7_loop_w20",
    ];
    for stem in stems {
        assert!(out.contains(stem), "{out}");
        let png = std::fs::read(dir.path().join("fr").join(format!("{stem}.png"))).unwrap();
        assert!(png.starts_with(b"\x89PNG"), "{stem}");
        let csv =
            std::fs::read_to_string(dir.path().join("fr").join(format!("{stem}.csv"))).unwrap();
        assert!(csv.lines().count() > 1000, "{stem}");
    }
    // Figs 4-5: F/mg = mu_k F2(0) = +-1 at zero slip for x'' = +-2, and -sgn(v) mu_k far out.
    let csv = std::fs::read_to_string(dir.path().join("fr/fig4_5_fixed_acceleration.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("v_m_per_s,f_over_mg_accel_plus2,f_over_mg_accel_minus2")
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|f| f.parse().unwrap()).collect())
        .collect();
    let mid = &rows[rows.len() / 2];
    assert!(mid[0].abs() < 1e-15, "{mid:?}");
    assert!(
        (mid[1] - 1.0).abs() < 1e-9 && (mid[2] + 1.0).abs() < 1e-9,
        "{mid:?}"
    );
    assert!((rows[0][0] + 0.01).abs() < 1e-15 && rows[0][1] > 0.5);
    // The loops cover one period: the first and last rows are the same state.
    let csv = std::fs::read_to_string(dir.path().join("fr/fig6_loop_w200.csv")).unwrap();
    let first: Vec<f64> = csv
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .map(|f| f.parse().unwrap())
        .collect();
    let last: Vec<f64> = csv
        .lines()
        .last()
        .unwrap()
        .split(',')
        .map(|f| f.parse().unwrap())
        .collect();
    assert!((last[0] - std::f64::consts::TAU / 200.0).abs() < 1e-15);
    assert!((first[2] - 1e-4).abs() < 1e-15 && (last[2] - 1e-4).abs() < 1e-12);

    refused(
        squeal(dir.path(), &["friction", "--out-dir", "fr"]),
        "--force",
    );
    ok(squeal(
        dir.path(),
        &["friction", "--out-dir", "fr", "--force"],
    ));
}

#[test]
fn friction_refuses_bad_material() {
    let dir = tmp();
    for (args, flag) in [
        (&["--mu-k", "0"][..], "--mu-k"),
        (&["--mu-k", "NaN"], "--mu-k"),
        (&["--tau", "-0.001"], "--tau"),
        // clap takes "-1e-3" for a flag; the `=` form passes it as a value.
        (&["--tau=-1e-3"], "--tau"),
        (&["--phi", "2"], "--phi"),
        (&["--phi", "0"], "--phi"),
    ] {
        let mut all = vec!["friction", "--out-dir", "fr"];
        all.extend_from_slice(args);
        refused(squeal(dir.path(), &all), flag);
    }
    assert!(!dir.path().join("fr").exists());
}

/// A small scan spec at nu = 1e-3 (paper Fig. 9's model).
const SPEC: &str = "version = 1\n[model]\nlaw = \"mcmillan\"\nnu = 1e-3\n\
    [grid]\nx0 = { min = -3.0, max = 5.0, count = 4 }\nv0 = { min = -4.0, max = 4.0, count = 3 }\n\
    [output]\npath = \"x.h5\"\n";

#[test]
fn spec_and_explicit_model_flags_are_refused_together() {
    // Before: `--spec` silently won and `--nu 1e-2` was ignored.
    let dir = tmp();
    std::fs::write(dir.path().join("s.toml"), SPEC).unwrap();
    std::fs::write(dir.path().join("ics.csv"), "x0,v0\n0,0\n").unwrap();
    let cases: [(&[&str], &str); 10] = [
        (
            &[
                "classify", "--ics", "ics.csv", "--out", "o.csv", "--nu", "1e-2",
            ],
            "--nu",
        ),
        (
            &[
                "classify", "--ics", "ics.csv", "--out", "o.csv", "--law", "coulomb",
            ],
            "--law",
        ),
        (
            &[
                "classify", "--ics", "ics.csv", "--out", "o.csv", "--t-max", "50",
            ],
            "--t-max",
        ),
        (&["ulc", "--nu", "1e-2"], "--nu"),
        (&["ulc", "--lambda", "2"], "--lambda"),
        (&["ulc", "--tau", "0.5"], "--tau"),
        (&["ulc", "--dt", "0.005"], "--dt"),
        (&["critical", "--phi", "1.2"], "--phi"),
        (&["critical", "--solver", "paper"], "--solver"),
        // Even a value equal to the default: it was typed, so it must not be ignored.
        (&["critical", "--nu", "1e-3"], "--nu"),
    ];
    for (args, flag) in cases {
        let mut all = args.to_vec();
        all.extend_from_slice(&["--spec", "s.toml"]);
        let o = squeal(dir.path(), &all);
        assert_eq!(o.status.code(), Some(2), "{all:?}: {}", stdout(&o));
        refused(o, flag);
        let o = squeal(dir.path(), &all);
        assert!(stderr(&o).contains("--spec"), "{all:?}: {}", stderr(&o));
    }
    // The refusal names the flag given, not every flag --spec refuses (the law flags are
    // made from the laws' keys, crates/cli/src/cmd/law_flags.rs; as a group they were all
    // listed).
    let o = squeal(dir.path(), &["ulc", "--mu-0", "0.3", "--spec", "s.toml"]);
    let e = stderr(&o);
    assert!(e.contains("'--mu-0 <MU_0>'") && !e.contains("--nu"), "{e}");
    assert!(!dir.path().join("o.csv").exists());
    // The spec alone, and the flags alone, still work.
    ok(squeal(
        dir.path(),
        &[
            "classify", "--spec", "s.toml", "--ics", "ics.csv", "--out", "o.csv",
        ],
    ));
    let labels = std::fs::read_to_string(dir.path().join("o.csv")).unwrap();
    // From rest at nu = 1e-3: stick-slip (paper Fig. 9).
    assert!(
        labels.lines().nth(1).unwrap().contains("stick_slip"),
        "{labels}"
    );
}

#[test]
fn stribeck_trajectory_names_its_parameters_and_stick_phases() {
    let dir = tmp();
    // Start stuck at x = 0 with the belt (x' = v_d = 1.5, bSTAB's defaults xi = 0.05,
    // mu_s = mu_d mu_sd = 1): the holding force x + 2 xi v_d grows as v_d t, so the first
    // breakaway is at t = (mu_s - 2 xi v_d) / v_d = 0.85 / 1.5 (closed form, MODEL.md 8).
    let args = [
        "trajectory",
        "--law",
        "stribeck",
        "--v0",
        "1.5",
        "--t-end",
        "100",
    ];
    let j: serde_json::Value =
        serde_json::from_str(&ok(squeal(dir.path(), &[&args[..], &["--json"]].concat()))).unwrap();
    let p = &j["params"];
    assert_eq!(p["xi"], 0.05);
    assert_eq!(p["v_d"], 1.5);
    assert_eq!(p["mu_sd"], 2.0);
    assert!(p.get("nu").is_none() && p.get("lambda").is_none(), "{p}");
    let st = &j["stick"];
    let tb = st["first_breakaways"][0].as_f64().unwrap();
    assert!((tb - 0.85 / 1.5).abs() < 1e-12, "{tb}");
    // From the breakaway state the orbit is the stick-slip cycle (v_d = 1.5 is bistable):
    // it sticks again, once per period.
    let onsets = st["onsets"].as_u64().unwrap();
    let breaks = st["breakaways"].as_u64().unwrap();
    assert!(onsets >= 2 && breaks.abs_diff(onsets) <= 1, "{st}");
    assert_eq!(j["stats"]["stick_onsets"].as_u64(), Some(onsets));
    // Labelled at the start as a scan labels it (outside the unstable cycle);
    // the run's own verdict: it stuck again after a breakaway.
    assert_eq!(j["classification"]["reason"], "start_outside_cycle");
    assert_eq!(j["classification"]["run"]["reason"], "stick_cycle");
    // Text: the law's names, the stick phases.
    let text = ok(squeal(dir.path(), &args));
    assert!(
        text.contains("xi=0.05") && text.contains("mu_v=0"),
        "{text}"
    );
    assert!(!text.contains("nu=") && !text.contains("lambda="), "{text}");
    assert!(
        text.contains(&format!("stick phases: {onsets} onsets")),
        "{text}"
    );
    assert!(text.contains("breakaways at t = 0.566667"), "{text}");
    // A McMillan run has no stick section.
    let m: serde_json::Value = serde_json::from_str(&ok(squeal(
        dir.path(),
        &["trajectory", "--t-end", "1", "--json"],
    )))
    .unwrap();
    assert!(m.get("stick").is_none() && m["params"]["nu"] == 1e-3);
    // The file records the law's parameters with long names and units, and the counts.
    ok(squeal(
        dir.path(),
        &[&args[..], &["--out", "s.h5"]].concat(),
    ));
    let f = hdf5::File::open(dir.path().join("s.h5")).unwrap();
    let num = |name: &str| -> f64 { f.attr(name).unwrap().read_scalar().unwrap() };
    for (k, v) in [
        ("xi", 0.05),
        ("v_d", 1.5),
        ("mu_d", 0.5),
        ("mu_sd", 2.0),
        ("v_0", 0.5),
        ("mu_v", 0.0),
    ] {
        assert_eq!(num(k), v, "{k}");
        for suffix in ["_long_name", "_units"] {
            assert!(f.attr(&format!("{k}{suffix}")).is_ok(), "{k}{suffix}");
        }
    }
    assert!(f.attr("nu").is_err() && f.attr("lambda").is_err());
    let count = |name: &str| -> u64 { f.attr(name).unwrap().read_scalar().unwrap() };
    assert_eq!(count("stick_onsets"), onsets);
    assert_eq!(count("breakaways"), breaks);
}

/// The label `squeal classify` gives each start of `ics` (CSV text) with the model `flags`.
fn classify_labels(dir: &Path, ics: &str, flags: &[&str]) -> Vec<(String, String)> {
    std::fs::write(dir.join("ics.csv"), ics).unwrap();
    let mut args = vec!["classify", "--ics", "ics.csv", "--out", "o.csv", "--force"];
    args.extend_from_slice(flags);
    ok(squeal(dir, &args));
    let text = std::fs::read_to_string(dir.join("o.csv")).unwrap();
    text.lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[2].to_string(), f[3].to_string())
        })
        .collect()
}

/// `squeal trajectory --json` from `(x0, v0)` to `t_end` with the model `flags`.
fn trajectory_json(
    dir: &Path,
    (x0, v0): (&str, &str),
    t_end: &str,
    flags: &[&str],
) -> serde_json::Value {
    let (x0, v0) = (format!("--x0={x0}"), format!("--v0={v0}"));
    let mut args = vec!["trajectory", &x0, &v0, "--t-end", t_end, "--json"];
    args.extend_from_slice(flags);
    serde_json::from_str(&ok(squeal(dir, &args))).expect("one JSON object")
}

/// At lambda = 0.5, nu = 0.0197 the run from (0, 1) has its last
/// section crossing at t = 3001.7 and ends at the fixed point (`squeal trajectory ... --t-end
/// 20000` on 48d225a: final state x = 1, x' = 0). There, 48d225a's `trajectory` labelled it
/// stick_slip (sticking_band at t = 153.85, its band rules set from a section search of
/// its own) while `classify` said steady_slip (inside_cycle at t = 1447.9): two answers, and
/// one of them contradicted by its own run. Now both go one path (the map's context) and
/// the label is where the run ends.
#[test]
fn trajectory_and_classify_agree_and_the_run_keeps_its_label() {
    let dir = tmp();
    let model = ["--lambda", "0.5", "--nu", "0.0197"];
    let j = trajectory_json(dir.path(), ("0", "1"), "5000", &model);
    let c = &j["classification"];
    let f = &j["final_state"];
    let at_fp =
        (f["x"].as_f64().unwrap() - 1.0).abs() < 1e-3 && f["v"].as_f64().unwrap().abs() < 1e-3;
    assert!(at_fp, "the run ends at the fixed point: {f}");
    assert_eq!(c["regime"], "steady_slip", "{c}");
    let labels = classify_labels(dir.path(), "x0,v0\n0,1\n", &model);
    assert_eq!(labels[0].0, "steady_slip", "{labels:?}");
    assert_eq!(c["reason"].as_str().unwrap(), labels[0].1, "{c} {labels:?}");
}

/// The README's clamped disc brake at c = 300 N s/m (nu = c / 800 = 0.375, lambda 0.21053, tau
/// 0.65789, phi 0.91353). On 48d225a `classify` labelled these starts stick_slip by
/// start_outside_cycle while each run ends quiet. Quiet is not steady slip there: with
/// `k = (1 - 2/pi) tau / lambda = 1.1355 > 1` steady slip repels (crates/core/MODEL.md
/// section 5), and the runs end on a slip oscillation about it that never sticks (`squeal
/// trajectory ... --x0 0 --v0 0 --t-end 5000`: half-range of x 1.64e-4, omega 1.745, the same
/// at t = 500 and 5000; on d424b26 that was "near_fixed_point at t = 35.8", a radius
/// crossing). The truth here is each trajectory's own run to t = 2000: it ends within 1e-3
/// of the fixed point (the oscillation is that small) and on no sticking turn; every command
/// must label it slip_oscillation, none stick_slip or steady_slip.
#[test]
fn brake_starts_that_end_quiet_are_labelled_slip_oscillation_by_every_command() {
    let dir = tmp();
    let model = [
        "--nu", "0.375", "--lambda", "0.21053", "--tau", "0.65789", "--phi", "0.91353",
    ];
    let starts = [("0", "0"), ("2", "0.5"), ("-1", "-0.5")];
    let ics: String = std::iter::once("x0,v0".to_string())
        .chain(starts.iter().map(|(x, v)| format!("{x},{v}")))
        .collect::<Vec<_>>()
        .join("\n");
    let mut flags = model.to_vec();
    flags.extend_from_slice(&["--t-max", "2000"]);
    let labels = classify_labels(dir.path(), &ics, &flags);
    for (s, label) in starts.iter().zip(&labels) {
        let j = trajectory_json(dir.path(), *s, "2000", &model);
        let f = &j["final_state"];
        let near =
            (f["x"].as_f64().unwrap() - 1.0).abs() < 1e-3 && f["v"].as_f64().unwrap().abs() < 1e-3;
        assert!(near, "{s:?}: the run ends near the fixed point: {f}");
        let l = &j["lasting"];
        assert_eq!(l["stuck"], false, "{s:?}: the last turns do not stick: {l}");
        assert_eq!(j["steady_slip"]["stability"], "repels", "{s:?}: {j}");
        assert_eq!(
            j["classification"]["regime"], "slip_oscillation",
            "{s:?}: {j}"
        );
        assert_eq!(label.0, "slip_oscillation", "{s:?}: {label:?}");
    }
}
