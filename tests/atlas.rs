//! End-to-end tests of `squeal atlas`: the real binary in a fresh temporary folder, the
//! file reopened with the hdf5 crate, the single-point commands reproduced, physical units,
//! bad input, shards with merge, and resume after a kill.

use std::path::Path;
use std::process::{Command, Output};

use serde_json::Value;

fn squeal(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the squeal binary runs")
}

fn ok(o: Output) -> String {
    let out = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        o.status.success(),
        "failed: {}\nstdout: {out}",
        String::from_utf8_lossy(&o.stderr)
    );
    out
}

fn refused(o: Output, needle: &str) {
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(!o.status.success(), "should fail");
    assert!(!err.contains("panicked"), "panic: {err}");
    assert!(err.contains(needle), "message should name {needle}: {err}");
}

fn json(s: &str) -> Value {
    serde_json::from_str(s.lines().last().unwrap_or("")).expect("one JSON object")
}

/// Table 1 of the paper over three dampings: Fig 9 (1e-3), Fig 10 (1e-2), and 0.05, above
/// the fold (MODEL.md: all squeal vanishes below 0.031).
const PAPER: &str = r#"
version = 1
name = "paper"
[model]
law = "mcmillan"
nu = [1e-3, 1e-2, 5e-2]
[boundaries]
rtol = 1e-4
[output]
path = "paper.h5"
"#;

#[test]
fn atlas_reproduces_the_single_point_commands() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("paper.toml"), PAPER).unwrap();
    let a = json(&ok(squeal(dir.path(), &["atlas", "paper.toml", "--json"])));
    let pts = a["points"].as_array().unwrap();
    let regimes: Vec<&str> = pts.iter().map(|p| p["regime"].as_str().unwrap()).collect();
    // Fig 9: rest squeals; Fig 10: rest is quiet; above the fold nothing squeals.
    assert_eq!(
        regimes,
        ["bistable_squeals", "bistable_quiet", "steady_slip_only"]
    );
    for (k, nu) in ["1e-3", "1e-2"].iter().enumerate() {
        let u = json(&ok(squeal(
            dir.path(),
            &["ulc", "--nu", nu, "--json", "--no-half-dt"],
        )));
        let (ra, ru) = (
            pts[k]["cycle_r_section"].as_f64().unwrap(),
            u["r_section"].as_f64().unwrap(),
        );
        // ulc bisects to 1e-10, the atlas to 1e-9 (relative bracket widths).
        assert!((ra - ru).abs() <= 2e-9 * ru, "nu {nu}: {ra} vs {ru}");
        let (pa, pu) = (
            pts[k]["cycle_period"].as_f64().unwrap(),
            u["period"].as_f64().unwrap(),
        );
        assert!((pa - pu).abs() < 1e-6, "{pa} vs {pu}");
        assert_eq!(
            pts[k]["cycle_encloses_operating_point"].as_f64().unwrap() == 1.0,
            u["encloses_origin"].as_bool().unwrap()
        );
    }
    let c = json(&ok(squeal(
        dir.path(),
        &["critical", "--json", "--nu-lo", "1e-3", "--nu-hi", "5e-2"],
    )));
    let b = &a["boundaries"][0]["critical"];
    assert_eq!(b["status"], "found");
    let (lo, hi) = (
        b["bracket"][0].as_f64().unwrap(),
        b["bracket"][1].as_f64().unwrap(),
    );
    let (clo, chi) = (
        c["bracket"][0].as_f64().unwrap(),
        c["bracket"][1].as_f64().unwrap(),
    );
    // Both bisect the same damping range to rtol = 1e-4: the brackets overlap.
    assert!(lo <= chi && clo <= hi, "[{lo}, {hi}] vs [{clo}, {chi}]");
    let fold = a["boundaries"][0]["fold"]["nu"].as_f64().unwrap();
    assert!(fold > 0.019 && fold < 0.031, "fold {fold}");
    // `squeal critical --fold` finds the same fold (same bisection, its own rtol 1e-4).
    let cf = json(&ok(squeal(
        dir.path(),
        &[
            "critical", "--fold", "--json", "--nu-lo", "1e-3", "--nu-hi", "5e-2",
        ],
    )));
    let (flo, fhi) = (
        cf["bracket"][0].as_f64().unwrap(),
        cf["bracket"][1].as_f64().unwrap(),
    );
    let fb = &a["boundaries"][0]["fold"]["bracket"];
    assert!(
        fb[0].as_f64().unwrap() <= fhi && flo <= fb[1].as_f64().unwrap(),
        "{fb} vs [{flo}, {fhi}]"
    );

    // The file: a coordinate nu (dimension scale, long name, units), datasets over it.
    let f = hdf5::File::open(dir.path().join("paper.h5")).unwrap();
    let nu = f.dataset("nu").unwrap();
    assert_eq!(nu.read_raw::<f64>().unwrap(), vec![1e-3, 1e-2, 5e-2]);
    assert!(nu.attr("CLASS").is_ok() && nu.attr("REFERENCE_LIST").is_ok());
    let r = f.dataset("cycle_r_section").unwrap();
    assert!(r.attr("DIMENSION_LIST").is_ok());
    let reg = f.dataset("regime").unwrap().read_raw::<u8>().unwrap();
    assert_eq!(reg, vec![3, 2, 1]);
    assert!(f.dataset("fold_nu").is_ok() && f.dataset("critical_nu_hi").is_ok());
    assert!(dir.path().join("paper.png").exists());
}

/// Table 1 (Fig 10's damping nu = 1e-2) over belt speeds: the boundaries are bisected in
/// lambda (the only swept axis). The 64 x 64 chart (`scans/atlas-lambda-nu.toml`) puts the
/// critical damping 0.0133 at lambda = 1.63 and 0.0097 at 1.84, so the critical belt speed
/// for rest lies between them; the fold in nu is above 0.017 all along the chart's lambda
/// range (0.5 to 6), so at nu = 1e-2 some start squeals at every lambda here.
const BELT: &str = r#"
version = 1
name = "belt"
[model]
law = "mcmillan"
nu = 1e-2
lambda = [1.0, 2.0, 3.0]
[cycle]
half_dt = false
[boundaries]
rtol = 1e-3
[output]
path = "belt.h5"
"#;

#[test]
fn critical_belt_speed_matches_the_single_point_command() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("belt.toml"), BELT).unwrap();
    let a = json(&ok(squeal(dir.path(), &["atlas", "belt.toml", "--json"])));
    let b = &a["boundaries"][0];
    assert_eq!(b["in"], "lambda");
    assert_eq!(b["lambda_range"], serde_json::json!([1.0, 3.0]));
    let c = &b["critical"];
    assert_eq!(c["status"], "found", "{b}");
    let (lo, hi) = (
        c["bracket"][0].as_f64().unwrap(),
        c["bracket"][1].as_f64().unwrap(),
    );
    assert!(lo > 1.63 && hi < 1.84, "[{lo}, {hi}]");
    // Above the critical belt speed rest is quiet but big starts still squeal
    // (bistable): the fold in lambda lies above the range.
    assert_eq!(b["fold"]["status"], "above_range", "{b}");
    let cli = json(&ok(squeal(
        dir.path(),
        &[
            "critical",
            "--in",
            "lambda",
            "--nu",
            "1e-2",
            "--lambda-lo",
            "1.0",
            "--lambda-hi",
            "3.0",
            "--rtol",
            "1e-3",
            "--json",
        ],
    )));
    assert_eq!(cli["in"], "lambda");
    let (clo, chi) = (
        cli["bracket"][0].as_f64().unwrap(),
        cli["bracket"][1].as_f64().unwrap(),
    );
    // Both bisect [1, 3] to rtol = 1e-3 with the same predicate: the brackets overlap.
    assert!(lo <= chi && clo <= hi, "[{lo}, {hi}] vs [{clo}, {chi}]");
    // The file stores it under the lambda names, with its bracket.
    let f = hdf5::File::open(dir.path().join("belt.h5")).unwrap();
    for name in [
        "critical_lambda",
        "critical_lambda_lo",
        "critical_lambda_hi",
        "fold_lambda",
    ] {
        assert!(f.dataset(name).is_ok(), "{name}");
    }
    assert!(f.dataset("critical_nu").is_err());
    // The labels of the points agree: rest squeals at lambda = 1, is quiet at 2 and 3.
    let regimes: Vec<&str> = a["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["regime"].as_str().unwrap())
        .collect();
    assert_eq!(
        regimes,
        ["bistable_squeals", "bistable_quiet", "bistable_quiet"]
    );
    // `render` redraws it (the curve is a value of the x axis here).
    ok(squeal(
        dir.path(),
        &["render", "belt.h5", "-o", "again.png"],
    ));
}

#[test]
fn a_physical_spec_gives_the_same_figures_scaled() {
    let dir = tempfile::tempdir().unwrap();
    // Table 1 at nu = 1e-2 as a physical system: m = 2 kg, k = 2e4 N/m (omega_0 = 100 rad/s),
    // mu_k = 0.4, g = 9.81: c = 2 nu sqrt(m k) = 4 N s/m, v_B = lambda mu_k g / omega_0,
    // tau = tau' mu_k / omega_0, mu_s = mu_k / sin(Phi).
    let (w0, muk, g) = (100.0f64, 0.4f64, 9.81f64);
    let vel = muk * g / w0;
    let phys = format!(
        r#"
version = 1
[model]
law = "mcmillan"
[physical]
m = 2.0
k = 2.0e4
c = 4.0
v_belt = {}
mu_k = 0.4
mu_s = {}
tau = {}
[boundaries]
fold = false
critical = false
[output]
path = "phys.h5"
"#,
        3.0 * vel,
        muk / 1f64.sin(),
        0.316_227_766_016_837_94 * muk / w0
    );
    let nond = r#"
version = 1
[model]
law = "mcmillan"
nu = 1e-2
[boundaries]
fold = false
critical = false
[output]
path = "nond.h5"
"#;
    std::fs::write(dir.path().join("phys.toml"), phys).unwrap();
    std::fs::write(dir.path().join("nond.toml"), nond).unwrap();
    let p = json(&ok(squeal(dir.path(), &["atlas", "phys.toml", "--json"])));
    let n = json(&ok(squeal(dir.path(), &["atlas", "nond.toml", "--json"])));
    let (pp, np) = (&p["points"][0], &n["points"][0]);
    assert_eq!(pp["regime"], np["regime"]);
    // The nondimensional parameters agree to rounding, so the figures agree to the
    // bisection tolerance.
    let r_p = pp["cycle_r_section"].as_f64().unwrap();
    let r_n = np["cycle_r_section"].as_f64().unwrap();
    assert!((r_p - r_n).abs() <= 2e-9 * r_n, "{r_p} vs {r_n}");
    // SI: velocities scale by mu_k g / omega_0, lengths by mu_k g / omega_0^2, angular
    // frequency 1 is omega_0 / (2 pi) Hz.
    let si = &pp["si"];
    let v_si = si["cycle_r_section"]["value"].as_f64().unwrap();
    assert!((v_si - r_n * vel).abs() <= 1e-8 * v_si, "{v_si}");
    assert_eq!(si["cycle_r_section"]["units"], "m/s");
    let d_si = si["cycle_distance_plus_x"]["value"].as_f64().unwrap();
    let d_n = np["cycle_distance_plus_x"].as_f64().unwrap();
    assert!((d_si - d_n * vel / w0).abs() <= 1e-6 * d_si);
    let hz = si["stick_omega_mean"]["value"].as_f64().unwrap();
    let om = np["stick_omega_mean"].as_f64().unwrap();
    assert!((hz - om * w0 / std::f64::consts::TAU).abs() <= 1e-6 * hz);
    // The file holds the SI figures with units.
    let f = hdf5::File::open(dir.path().join("phys.h5")).unwrap();
    let u: hdf5::types::VarLenUnicode = f
        .dataset("stick_omega_mean_si")
        .unwrap()
        .attr("units")
        .unwrap()
        .read_scalar()
        .unwrap();
    assert_eq!(u.as_str(), "Hz");
}

#[test]
fn bad_specs_are_refused_before_computing() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (PAPER.replace("nu = [", "nux = 1\nnu = ["), "nux"),
        (PAPER.replace("nu = [1e-3, 1e-2, 5e-2]", "nu = []"), "model.nu"),
        (
            PAPER.replace("nu = [1e-3, 1e-2, 5e-2]", "nu = { from = 1e-3, to = 1e-2, count = 0 }"),
            "model.nu.count",
        ),
        (
            PAPER.replace(
                "[boundaries]",
                "[physical]\nm = 1.0\nk = 1e4\nc = 1.0\nv_belt = 0.1\nmu_k = 0.3\nmu_s = 0.4\ntau = 1e-3\n[boundaries]",
            ),
            "model.nu",
        ),
        (
            PAPER.replace("nu = [1e-3, 1e-2, 5e-2]", "").replace(
                "[boundaries]",
                "[physical]\nm = -1.0\nk = 1e4\nc = 1.0\nv_belt = 0.1\nmu_k = 0.3\nmu_s = 0.4\ntau = 1e-3\n[boundaries]",
            ),
            "physical.m",
        ),
        (
            PAPER.replace("nu = [1e-3, 1e-2, 5e-2]", "").replace(
                "[boundaries]",
                "[physical]\nm = 1.0\nk = 1e4\nc = 1.0\nv_belt = 0.1\nmu_k = 0.3\nmu_s = 0.3\ntau = 1e-3\n[boundaries]",
            ),
            "physical.mu_s",
        ),
    ];
    for (k, (text, key)) in cases.iter().enumerate() {
        let name = format!("bad{k}.toml");
        std::fs::write(dir.path().join(&name), text).unwrap();
        refused(squeal(dir.path(), &["atlas", &name]), key);
        assert!(!dir.path().join("paper.h5").exists());
        assert!(!dir.path().join("paper.h5.journal").exists());
    }
    // Output is never silently overwritten.
    std::fs::write(dir.path().join("paper.h5"), b"x").unwrap();
    let small = PAPER.replace("nu = [1e-3, 1e-2, 5e-2]", "nu = 1e-2");
    std::fs::write(dir.path().join("s.toml"), small).unwrap();
    refused(squeal(dir.path(), &["atlas", "s.toml"]), "--force");
}

const GRID: &str = r#"
version = 1
name = "grid"
[model]
law = "mcmillan-nonhysteretic"
nu = [2e-3, 1e-2]
lambda = [2.0, 2.5, 3.0, 3.5]
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

fn read_f64(p: &Path, name: &str) -> Vec<u64> {
    let f = hdf5::File::open(p).unwrap();
    f.dataset(name)
        .unwrap()
        .read_raw::<f64>()
        .unwrap()
        .into_iter()
        .map(f64::to_bits)
        .collect()
}

#[test]
fn shards_merge_into_the_single_run_file() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("grid.toml"), GRID).unwrap();
    ok(squeal(dir.path(), &["atlas", "grid.toml", "--no-render"]));
    for k in ["1/3", "2/3", "3/3"] {
        let out = format!("s{}.h5", &k[..1]);
        ok(squeal(
            dir.path(),
            &["atlas", "grid.toml", "--shard", k, "-o", &out],
        ));
    }
    ok(squeal(
        dir.path(),
        &["merge", "s1.h5", "s2.h5", "s3.h5", "-o", "merged.h5"],
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
        squeal(dir.path(), &["merge", "s1.h5", "s2.h5", "-o", "part.h5"]),
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
        let lines = std::fs::read_to_string(&journal)
            .map(|s| s.lines().count())
            .unwrap_or(0);
        if lines >= 2 || t0.elapsed().as_secs() > 120 {
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
    j.write_all(b"{\"line\": 1, \"poi").unwrap();
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
