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
#[ignore = "long check (minutes under load): run by scripts/ci/long-checks.sh, which .ci/run calls"]
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
    // `squeal critical --fold` finds the same fold (the same crisis search, over its own
    // range, rtol 1e-4 and 64 coarse steps): each value inside the other's stated
    // uncertainty (issue 17, item 5).
    let cf = json(&ok(squeal(
        dir.path(),
        &[
            "critical", "--fold", "--json", "--nu-lo", "1e-3", "--nu-hi", "5e-2",
        ],
    )));
    let (cn, ce) = (
        cf["nu"].as_f64().unwrap(),
        cf["uncertainty"].as_f64().unwrap(),
    );
    let fe = a["boundaries"][0]["fold"]["uncertainty"].as_f64().unwrap();
    assert!(
        (fold - cn).abs() <= ce.min(fe),
        "{fold} +- {fe} vs {cn} +- {ce}"
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
    // The fold's uncertainty and the coarse scan's count of regime changes, each with its
    // units and long name (issue 17, items 4 and 5).
    for name in ["fold_nu_err", "fold_changes"] {
        let d = f.dataset(name).unwrap();
        let attr = |a: &str| -> String {
            let v: hdf5::types::VarLenUnicode = d.attr(a).unwrap().read_scalar().unwrap();
            v.as_str().to_string()
        };
        assert_eq!(attr("units"), "1", "{name}");
        assert!(!attr("long_name").is_empty(), "{name}");
    }
    let err = f.dataset("fold_nu_err").unwrap().read_raw::<f64>().unwrap();
    assert!(err[0] > 0.0 && err[0] < fold, "{err:?}");
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
    // Issue 21: an SI frequency is called a frequency, and the default disturbance box
    // (no [disturbance]) says it is nondimensional at each point rather than metres.
    let long: hdf5::types::VarLenUnicode = f
        .dataset("stick_omega_mean_si")
        .unwrap()
        .attr("long_name")
        .unwrap()
        .read_scalar()
        .unwrap();
    assert_eq!(long.as_str(), "stick-slip: mean frequency");
    // Issue 34: the block under its own weight presses the belt with m g = 2 * 9.81 N,
    // stored per point in newtons (a normal force given is an axis of its own).
    let n = f.dataset("normal_force").unwrap();
    assert_eq!(n.read_raw::<f64>().unwrap(), vec![2.0 * 9.81]);
    let nu: hdf5::types::VarLenUnicode = n.attr("units").unwrap().read_scalar().unwrap();
    assert_eq!(nu.as_str(), "N");
    let du: hdf5::types::VarLenUnicode = f
        .attr("disturbance_x_units")
        .unwrap()
        .read_scalar()
        .unwrap();
    assert!(du.as_str().starts_with("1 (the default box"), "{du}");
    assert_eq!(p["disturbance"]["x"], serde_json::json!([-2.0, 4.0]));
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

/// Complete records of `kind` in a journal. Frames are `SQJR`, a kind byte (`A` the atlas
/// header, `U` a unit, `B` a map block, `C` a map's cycle search), a little-endian u32
/// length, the payload and an 8-byte checksum (crates/store/src/journal.rs).
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

/// Table 1 at Figs 9 and 10 (nu = 1e-3, 1e-2) with a small basin map per point over the
/// atlas's default disturbance box; no boundary searches (they are not what the test reads,
/// and took 5 of its 18 s of CPU per run).
const MAPS: &str = r#"
version = 1
name = "maps"
[model]
law = "mcmillan"
nu = [1e-3, 1e-2]
[cycle]
half_dt = false
[attractor]
transient = 10
window = 10
[boundaries]
fold = false
critical = false
[grid]
x0 = { min = -2.0, max = 4.0, count = 10 }
v0 = { min = -3.0, max = 3.0, count = 8 }
block_rows = 3
[output]
path = "maps.h5"
"#;

fn read_u8(p: &Path, name: &str) -> Vec<u8> {
    let f = hdf5::File::open(p).unwrap();
    f.dataset(name).unwrap().read_raw::<u8>().unwrap()
}

fn shape(p: &Path, name: &str) -> Vec<usize> {
    hdf5::File::open(p).unwrap().dataset(name).unwrap().shape()
}

fn str_attr(p: &Path, ds: Option<&str>, name: &str) -> String {
    let f = hdf5::File::open(p).unwrap();
    let a = match ds {
        Some(d) => f.dataset(d).unwrap().attr(name).unwrap(),
        None => f.attr(name).unwrap(),
    };
    a.read_scalar::<hdf5::types::VarLenUnicode>()
        .unwrap()
        .as_str()
        .to_string()
}

#[test]
#[ignore = "long check (a minute or more on 2 cores): run by scripts/ci/long-checks.sh, which .ci/run calls"]
fn maps_are_stored_over_the_parameters_with_the_cell_schema() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("maps.toml"), MAPS).unwrap();
    let a = json(&ok(squeal(dir.path(), &["atlas", "maps.toml", "--json"])));
    let h5 = dir.path().join("maps.h5");
    // One map per nu, (nu, v0, x0), every column of the scan's cell schema with its words.
    for col in squeal_scan::cell::COLUMNS {
        let name = format!("map_{}", col.name);
        assert_eq!(shape(&h5, &name), [2, 8, 10], "{name}");
        assert_eq!(str_attr(&h5, Some(&name), "long_name"), col.long_name);
        if !col.units.is_empty() {
            assert_eq!(str_attr(&h5, Some(&name), "units"), col.units);
        }
    }
    assert_eq!(
        str_attr(&h5, Some("map_labels"), "flag_meanings"),
        "undecided steady_slip stick_slip not_computed"
    );
    // Named dimensions: the coordinates are dimension scales, attached in order.
    let f = hdf5::File::open(&h5).unwrap();
    for (c, n) in [("nu", 2), ("v0", 8), ("x0", 10), ("block", 3)] {
        let d = f.dataset(c).unwrap();
        assert_eq!(d.shape(), [n], "{c}");
        assert!(d.attr("CLASS").is_ok(), "{c} is not a dimension scale");
    }
    assert_eq!(
        f.dataset("map_labels")
            .unwrap()
            .attr("DIMENSION_LIST")
            .unwrap()
            .shape(),
        [3]
    );
    assert_eq!(f.dataset("x0").unwrap().read_raw::<f64>().unwrap()[9], 4.0);
    drop(f);
    assert_eq!(read_u8(&h5, "blocks_done"), vec![1; 6]);
    // Every cell decided at these points (the trap of the located cycle decides quickly).
    let labels = read_u8(&h5, "map_labels");
    assert!(labels.iter().all(|&l| l == 1 || l == 2), "{labels:?}");
    assert_eq!(str_attr(&h5, None, "scheme"), "foh");
    assert_eq!(str_attr(&h5, Some("basin_fraction"), "source"), "map");
    // The JSON reports the map's fraction and keeps the cycle's.
    for p in a["points"].as_array().unwrap() {
        assert_eq!(p["basin_fraction_source"], "map");
        assert!((0.0..=1.0).contains(&p["basin_fraction"].as_f64().unwrap()));
        assert!(p["basin_fraction_cycle"].as_f64().is_some());
        assert_eq!(p["map"]["cells"], 80);
    }
    // Fig 10's map shows both attractors; at Fig 9 the unstable cycle (r_section 0.37) is
    // smaller than this grid's cells, so every cell squeals.
    assert!(labels[80..].contains(&1) && labels[80..].contains(&2));
    assert!(labels[..80].iter().all(|&l| l == 2));
    // The chart and the sheet of maps are drawn beside the file.
    assert!(dir.path().join("maps.png").exists());
    assert!(dir.path().join("maps-maps.png").exists());

    // Shards (units and map blocks both split) merge into the single run's file.
    for k in ["1/2", "2/2"] {
        let out = format!("s{}.h5", &k[..1]);
        ok(squeal(
            dir.path(),
            &["atlas", "maps.toml", "--shard", k, "-o", &out],
        ));
    }
    let s1 = read_u8(&dir.path().join("s1.h5"), "blocks_done");
    assert!(s1.contains(&0) && s1.contains(&1), "{s1:?}");
    ok(squeal(
        dir.path(),
        &["merge", "s1.h5", "s2.h5", "-o", "merged.h5"],
    ));
    let merged = dir.path().join("merged.h5");
    assert_eq!(read_u8(&merged, "map_labels"), labels);
    for name in [
        "map_t_decision",
        "basin_fraction",
        "basin_fraction_err",
        "basin_fraction_cycle",
        "map_cycle_x",
        "cycle_r_section",
    ] {
        assert_eq!(read_f64(&h5, name), read_f64(&merged, name), "{name}");
    }
    assert!(dir.path().join("merged-maps.png").exists());
    // render redraws both pictures.
    ok(squeal(
        dir.path(),
        &["render", "merged.h5", "-o", "again.png"],
    ));
    assert!(dir.path().join("again-maps.png").exists());
}

#[test]
fn map_basin_fraction_agrees_with_the_cycle_at_fig_10() {
    // Fig 10 (nu = 1e-2): the unstable cycle lies inside the box, so the share of the box
    // inside it is computed twice independently: the clipped area of the located cycle
    // (with the dt/2 shift and chord error) and the share of map cells that return to
    // steady slip (with undecided cells and cells within one cell of the cycle). Each
    // value comes with its uncertainty; they must agree within the sum.
    let spec = MAPS
        .replace("nu = [1e-3, 1e-2]", "nu = 1e-2")
        .replace("half_dt = false", "half_dt = true")
        .replace("count = 10", "count = 48")
        .replace("count = 8", "count = 48")
        .replace("block_rows = 3", "block_rows = 16");
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("one.toml"), spec).unwrap();
    let a = json(&ok(squeal(
        dir.path(),
        &["atlas", "one.toml", "--json", "--no-render"],
    )));
    let p = &a["points"][0];
    assert_eq!(p["regime"], "bistable_quiet");
    let (fm, em) = (
        p["basin_fraction"].as_f64().unwrap(),
        p["basin_fraction_err"].as_f64().unwrap(),
    );
    let (fc, ec) = (
        p["basin_fraction_cycle"].as_f64().unwrap(),
        p["basin_fraction_cycle_err"].as_f64().unwrap(),
    );
    assert!(fm > 0.05 && fm < 0.95, "{fm}");
    assert!(
        (fm - fc).abs() <= em + ec,
        "map {fm} +- {em}, cycle {fc} +- {ec}"
    );
    // The bound is informative: well below the fraction itself.
    assert!(em < 0.25 && em > 0.0, "{em}");
    // One point, nothing swept: the maps are over (point, v0, x0).
    assert_eq!(
        shape(&dir.path().join("maps.h5"), "map_labels"),
        [1, 48, 48]
    );
    // Issue 21: a one-point atlas drew no chart without a word and printed "1 points over ,".
    // The make-like rerun (up to date) prints the summary in words.
    let words = ok(squeal(dir.path(), &["atlas", "one.toml", "--no-render"]));
    assert!(
        words.contains("1 parameter point (nothing swept: no chart;"),
        "{words}"
    );
    assert!(!words.contains("points over ,"), "{words}");
}

#[test]
fn bad_grids_are_refused_before_computing() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (MAPS.replace("count = 10", "count = 0"), "grid.x0.count"),
        (
            MAPS.replace("block_rows = 3", "block_rows = 3\nrows = 2"),
            "rows",
        ),
        (
            MAPS.replace(
                "[grid]",
                "[disturbance]\nx = [-1.0, 1.0]\nv = [-1.0, 1.0]\n[grid]",
            ),
            "disturbance",
        ),
        (
            MAPS.replace("[output]", "[classifier]\nsettle_cycles = 1\n[output]"),
            "classifier.settle_cycles",
        ),
        (
            MAPS.replace("[output]", "[integration]\nscheme = \"rk4\"\n[output]"),
            "scheme",
        ),
    ];
    for (k, (text, key)) in cases.iter().enumerate() {
        let name = format!("bad{k}.toml");
        std::fs::write(dir.path().join(&name), text).unwrap();
        refused(squeal(dir.path(), &["atlas", &name]), key);
        assert!(!dir.path().join("maps.h5").exists());
        assert!(!dir.path().join("maps.h5.journal").exists());
        assert!(!dir.path().join("maps.h5.lock").exists());
    }
}

#[test]
fn killed_maps_resume_to_the_same_file_and_the_output_is_locked() {
    // Slow enough to be killed midway: no early stopping, one thread.
    let spec = MAPS
        .replace("count = 10", "count = 16")
        .replace("count = 8", "count = 12")
        .replace("block_rows = 3", "block_rows = 2")
        .replace(
            "[output]",
            "[classifier]\nt_max = 400.0\nearly_stop = \"none\"\n[output]",
        );
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("slow.toml"), &spec).unwrap();
    ok(squeal(
        dir.path(),
        &["atlas", "slow.toml", "-o", "full.h5", "--no-render"],
    ));
    let mut child = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args([
            "atlas",
            "slow.toml",
            "-o",
            "cut.h5",
            "--threads",
            "1",
            "--no-render",
        ])
        .current_dir(dir.path())
        .spawn()
        .unwrap();
    // Wait for a map block record (kind `B`), then kill without warning.
    let journal = dir.path().join("cut.h5.journal");
    let blocks_in = || records_in(&journal, b'B');
    let t0 = std::time::Instant::now();
    while blocks_in() == 0 && t0.elapsed().as_secs() < 300 {
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    let stored = blocks_in();
    assert!(
        stored > 0,
        "no map block reached the journal before the kill"
    );
    // While it runs, a second run or a resume on the same output is refused, naming it.
    let pid = child.id().to_string();
    for extra in ["--force", "--resume"] {
        let o = squeal(
            dir.path(),
            &["atlas", "slow.toml", "-o", "cut.h5", "--no-render", extra],
        );
        refused(o.clone(), "being written by process");
        assert!(String::from_utf8_lossy(&o.stderr).contains(&pid));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(!dir.path().join("cut.h5").exists(), "killed before the end");
    // SIGKILL leaves the lock; its process is gone, so the resume takes it over.
    assert!(dir.path().join("cut.h5.lock").exists());
    let out = ok(squeal(
        dir.path(),
        &[
            "atlas",
            "slow.toml",
            "-o",
            "cut.h5",
            "--resume",
            "--no-render",
            "--json",
        ],
    ));
    // Only the missing blocks were computed: 2 maps x 6 blocks in all, `stored` of them (or
    // more, written before the kill) kept from the killed run.
    let computed = json(&out)["map_blocks_computed"].as_u64().unwrap() as usize;
    assert!(
        computed <= 12 - stored,
        "{computed} computed, {stored} were stored"
    );
    assert_eq!(blocks_in_file(&dir.path().join("cut.h5")), 12);
    let (a, b) = (dir.path().join("full.h5"), dir.path().join("cut.h5"));
    assert_eq!(read_u8(&a, "map_labels"), read_u8(&b, "map_labels"));
    assert_eq!(read_u8(&a, "map_reason"), read_u8(&b, "map_reason"));
    for name in [
        "map_t_decision",
        "map_amplitude",
        "basin_fraction",
        "basin_fraction_err",
        "map_cycle_x",
        "cycle_r_section",
    ] {
        assert_eq!(read_f64(&a, name), read_f64(&b, name), "{name}");
    }
    assert!(!journal.exists() && !dir.path().join("cut.h5.lock").exists());
}

/// Map blocks stored in a file.
fn blocks_in_file(p: &Path) -> usize {
    read_u8(p, "blocks_done")
        .iter()
        .filter(|&&d| d == 1)
        .count()
}

/// Width and height of a PNG (its IHDR chunk: bytes 16..24, big-endian).
fn png_size(p: &Path) -> (u32, u32) {
    let b = std::fs::read(p).unwrap();
    let be = |k: usize| u32::from_be_bytes(b[k..k + 4].try_into().unwrap());
    (be(16), be(20))
}

#[test]
fn a_2d_atlas_lays_its_maps_out_over_both_parameters() {
    let spec = MAPS
        .replace(
            "nu = [1e-3, 1e-2]",
            "nu = [1e-3, 1e-2]\nlambda = [2.5, 3.0, 3.5]",
        )
        .replace("count = 10", "count = 6")
        .replace("count = 8", "count = 5");
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("two.toml"), spec).unwrap();
    ok(squeal(dir.path(), &["atlas", "two.toml"]));
    let h5 = dir.path().join("maps.h5");
    assert_eq!(shape(&h5, "map_labels"), [2, 3, 5, 6]);
    assert_eq!(shape(&h5, "blocks_done"), [2, 3, 2]);
    // Rows: nu (2), columns: lambda (3); panels 440 x 420 plus a 245-pixel legend
    // (crates/plot/src/lib.rs, basin_sheet).
    let (w, h) = png_size(&dir.path().join("maps-maps.png"));
    assert_eq!(w, 3 * 440 + 245);
    assert!(h > 2 * 420 && h < 3 * 420, "{h}");
    assert!(dir.path().join("maps.png").exists());
}

/// bSTAB's friction case (the Stribeck law's defaults) at v_d = 1.0, 1.5 (bSTAB's case 1)
/// and 2.2, each with a 64 x 32 map
/// whose cells tile exactly bSTAB's region x in [-2, 2], x' in [0, 2] (spacing 4/64 and
/// 2/32, first and last values half a spacing inside).
const STRIBECK_MAP: &str = r#"
version = 1
name = "bstab-one"
[model]
law = "stribeck"
v_d = [1.0, 1.5, 2.2]
[boundaries]
fold = false
critical = false
[grid]
x0 = { min = -1.96875, max = 1.96875, count = 64 }
v0 = { min = 0.03125, max = 1.96875, count = 32 }
[output]
path = "bstab.h5"
"#;

#[test]
fn stribeck_basin_fraction_agrees_with_bstab_and_the_map() {
    // tests/data/bstab_friction_published.json, case1 (the MATLAB bSTAB run kept in
    // pyBasin's repository): steady slip ("FP") 0.304, standard error 0.0065, N = 5000.
    let doc: Value = serde_json::from_str(
        &std::fs::read_to_string(
            Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/bstab_friction_published.json"),
        )
        .unwrap(),
    )
    .unwrap();
    let (bs, se) = (
        doc["case1"]["bs_FP"].as_f64().unwrap(),
        doc["case1"]["se_FP"].as_f64().unwrap(),
    );
    assert_eq!(doc["case1"]["v_d"].as_f64(), Some(1.5));
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("b.toml"), STRIBECK_MAP).unwrap();
    let a = json(&ok(squeal(
        dir.path(),
        &["atlas", "b.toml", "--json", "--no-render"],
    )));
    assert_eq!(a["disturbance"]["x"], serde_json::json!([-2.0, 2.0]));
    assert_eq!(a["disturbance"]["v"], serde_json::json!([0.0, 2.0]));
    let p = &a["points"][1];
    assert_eq!(p["landscape"]["landscape"], "bistable");
    assert!(p["regime"].as_str().unwrap().starts_with("bistable"), "{p}");
    // The map (squeal's own grid scan of the box, the scan's spine) and the cycle (the
    // clipped area of the located unstable cycle), each with its stated uncertainty.
    let (fm, em) = (
        p["basin_fraction"].as_f64().unwrap(),
        p["basin_fraction_err"].as_f64().unwrap(),
    );
    let (fc, ec) = (
        p["basin_fraction_cycle"].as_f64().unwrap(),
        p["basin_fraction_cycle_err"].as_f64().unwrap(),
    );
    assert!(
        (fm - fc).abs() <= em + ec,
        "map {fm} +- {em}, cycle {fc} +- {ec}"
    );
    for (what, f, e) in [("map", fm, em), ("cycle", fc, ec)] {
        assert!(
            (f - bs).abs() <= 3.0 * se + e,
            "{what} {f} +- {e} vs published {bs} +- {se}"
        );
    }
    // Every cell of the map decided.
    assert_eq!(p["map"]["undecided"], 0);
    // Where the landscape states the regime of every start (v_d = 1.0: the fixed point
    // repels; 2.2: no stick-slip cycle), every cell of the map ends there: fractions 0 and
    // 1 from the map, as the atlas states them, and no cell labelled against the landscape
    // (-1 where it states none: bistable).
    for (k, want) in [(0, 0.0), (2, 1.0)] {
        let q = &a["points"][k];
        assert_eq!(q["basin_fraction"].as_f64(), Some(want), "{q}");
        assert_eq!(q["basin_fraction_cycle"].as_f64(), Some(want), "{q}");
        assert_eq!(q["map"]["undecided"], 0, "{q}");
    }
    let contradictions: Vec<i64> = hdf5::File::open(dir.path().join("bstab.h5"))
        .unwrap()
        .dataset("map_landscape_contradictions")
        .unwrap()
        .read_raw()
        .unwrap();
    assert_eq!(contradictions, [0, -1, 0]);
}

/// The cubic law's atlas (issue 16, item 6) over the belt speed. At the defaults the fixed
/// point's damping 2 xi + mu'(v_d) = 0.1 - 0.45 + 1.8 v_d^2 vanishes at
/// v_d = sqrt(0.35 / 1.8) = 0.44096 (closed form): below it the fixed point repels, above it
/// the orbit from breakaway decays (no bistable belt speed, crates/core/tests/model/cubic.rs), so
/// the fold (no start squeals above) and the critical speed of the operating point both lie
/// at that loss of stability, within their brackets. Before, the chart refused to draw an
/// atlas with no unstable cycle beside stick-slip ("curve ... has no drawable point").
#[test]
fn a_cubic_atlas_finds_its_fold_at_the_loss_of_stability() {
    let spec = r#"
version = 1
name = "cubic-vd"
[model]
law = "cubic"
v_d = [0.3, 0.5]
[boundaries]
rtol = 1e-2
[output]
path = "c.h5"
"#;
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("c.toml"), spec).unwrap();
    let a = json(&ok(squeal(dir.path(), &["atlas", "c.toml", "--json"])));
    let regimes: Vec<&str> = a["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["regime"].as_str().unwrap())
        .collect();
    assert_eq!(regimes, ["fixed_point_unstable", "steady_slip_only"]);
    let hopf = (0.35f64 / 1.8).sqrt();
    for which in ["fold", "critical"] {
        let b = &a["boundaries"][0][which];
        assert_eq!(b["status"], "found", "{which}: {b}");
        let (lo, hi) = (
            b["bracket"][0].as_f64().unwrap(),
            b["bracket"][1].as_f64().unwrap(),
        );
        assert!(lo <= hopf && hopf <= hi, "{which}: {b}");
    }
    let f = dir.path().join("c.h5");
    assert_eq!(read_u8(&f, "landscape"), [1, 3]);
    // The fixed parameters are root attributes under the law's own names.
    assert_eq!(str_attr(&f, None, "law"), "cubic");
    let h = hdf5::File::open(&f).unwrap();
    let num = |k: &str| h.attr(k).unwrap().read_scalar::<f64>().unwrap();
    assert_eq!(
        (num("xi"), num("mu_0"), num("a1"), num("a3")),
        (0.05, 0.4, 0.45, 0.6)
    );
    assert!(dir.path().join("c.png").exists());
}

#[test]
fn a_stribeck_atlas_stores_its_boundaries_and_landscape_in_its_own_words() {
    let spec = r#"
version = 1
name = "stribeck-vd"
[model]
law = "stribeck"
v_d = [1.0, 1.5, 2.2]
[boundaries]
rtol = 1e-2
[output]
path = "s.h5"
"#;
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.toml"), spec).unwrap();
    let a = json(&ok(squeal(dir.path(), &["atlas", "s.toml", "--json"])));
    let regimes: Vec<&str> = a["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["regime"].as_str().unwrap())
        .collect();
    assert_eq!(regimes[0], "fixed_point_unstable");
    assert!(regimes[1].starts_with("bistable"));
    assert_eq!(regimes[2], "steady_slip_only");
    assert_eq!(a["boundaries"][0]["in"], "v_d");
    let f = dir.path().join("s.h5");
    // Bisected in v_d (the swept axis): datasets named by the law's key, with words.
    for name in ["fold_v_d", "fold_v_d_lo", "critical_v_d_hi"] {
        assert_eq!(shape(&f, name), [1], "{name}");
    }
    assert!(str_attr(&f, Some("fold_v_d"), "long_name").contains("stick-slip cycle ends"));
    assert!(str_attr(&f, Some("critical_v_d"), "long_name").contains("belt speed v_d"));
    assert_eq!(str_attr(&f, Some("v_d"), "long_name"), "belt speed v_d");
    // The landscape per point (stick_slip_only = 1, bistable = 2, steady_slip_only = 3).
    assert_eq!(read_u8(&f, "landscape"), [1, 2, 3]);
    assert!(str_attr(&f, Some("stick_stuck_share"), "long_name").contains("stuck"));
    assert!(hdf5::File::open(&f).unwrap().dataset("nu").is_err());
    // `render` reads it back and redraws.
    ok(squeal(dir.path(), &["render", "s.h5", "-o", "again.png"]));
    assert!(dir.path().join("again.png").exists());
    // A McMillan key in a Stribeck spec is refused before computing, naming the key.
    std::fs::write(
        dir.path().join("bad.toml"),
        spec.replace("v_d = [", "nu = 0.01\nv_d = ["),
    )
    .unwrap();
    refused(squeal(dir.path(), &["atlas", "bad.toml"]), "model.nu");
}

#[test]
fn stribeck_atlas_matches_bstabs_belt_speed_study() {
    // Both published runs of bSTAB's belt-speed study (tests/data/bstab_friction_published.json,
    // v_d = numpy.linspace(0.8, 2.225, 20), 5000 random starts each) against the atlas over
    // the same belt speeds: the same regime at every v_d (stick-slip only <-> basin
    // stability of steady slip 0, steady slip only <-> 1, bistable between) and the basin
    // fraction from the unstable cycle within 3 standard errors plus the atlas's stated
    // uncertainty. At v_d = 1.175 the published values undercount steady slip (bSTAB's
    // t = 500 is too short there, tests/e2e/bstab_friction.rs): the atlas is compared with the
    // t = 2500 reference by bSTAB's approach (tests/data/bstab_friction_reference_vd1.175_t2500.json,
    // made by scripts/tools/bstab_reference.py).
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let load = |name: &str| -> Value {
        serde_json::from_str(&std::fs::read_to_string(data.join(name)).unwrap()).unwrap()
    };
    let doc = load("bstab_friction_published.json");
    let long = load("bstab_friction_reference_vd1.175_t2500.json");
    let long = &long["results"][0];
    let vds: Vec<f64> = (0..20).map(|i| 0.8 + 1.425 * i as f64 / 19.0).collect();
    let list = vds
        .iter()
        .map(|v| format!("{v:?}"))
        .collect::<Vec<_>>()
        .join(", ");
    let spec = format!(
        "version = 1\n[model]\nlaw = \"stribeck\"\nv_d = [{list}]\n[disturbance]\nx = [-2.0, 2.0]\nv = [0.0, 2.0]\n[boundaries]\nfold = false\ncritical = false\n[output]\npath = \"study.h5\"\n"
    );
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("study.toml"), spec).unwrap();
    let a = json(&ok(squeal(
        dir.path(),
        &["atlas", "study.toml", "--json", "--no-render"],
    )));
    let pts = a["points"].as_array().unwrap();
    assert_eq!(pts.len(), 20);
    for run in doc["v_study"]["runs"].as_array().unwrap() {
        for (v, p) in run["values"].as_array().unwrap().iter().zip(pts) {
            let vd = v["v_d"].as_f64().unwrap();
            assert!((p["coords"]["v_d"].as_f64().unwrap() - vd).abs() < 1e-9);
            let (bs, se) = if (vd - 1.175).abs() < 1e-9 {
                (
                    long["bs_FP"].as_f64().unwrap(),
                    long["se"].as_f64().unwrap(),
                )
            } else {
                (v["bs_FP"].as_f64().unwrap(), v["se_FP"].as_f64().unwrap())
            };
            let regime = p["regime"].as_str().unwrap();
            let want = if bs == 0.0 {
                "fixed_point_unstable"
            } else if bs == 1.0 {
                "steady_slip_only"
            } else {
                "bistable"
            };
            assert!(
                regime.starts_with(want),
                "v_d = {vd}: {regime}, published {bs}"
            );
            let (f, e) = (
                p["basin_fraction"].as_f64().unwrap(),
                p["basin_fraction_err"].as_f64().unwrap(),
            );
            assert!(
                (f - bs).abs() <= 3.0 * se + e,
                "run {}, v_d = {vd}: atlas {f} +- {e}, published {bs} +- {se}",
                run["name"]
            );
        }
    }
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

/// Issue 16: every atlas prints its work estimate before it starts, and one estimated above
/// 30 days is refused without `--allow-long`, before any file is made. 1000 dampings with a
/// 4096 x 4096 basin map each, every cell run to settlement (`early_stop = "none"`), are
/// 1.7e10 runs of hundreds of time units: at the fastest settled rate measured
/// (BENCHMARKS.md, issue 18: about 2,000 cells/s on 2 threads) that is 98 days, so the
/// estimate is above 30 days on any machine of ours; the old code started it without a word.
#[test]
fn an_atlas_estimates_its_work_and_refuses_a_huge_one() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("paper.toml"), PAPER).unwrap();
    // The estimate is said after the pilot and before the run: read stderr up to it and stop
    // the run there (the run itself, its fold from runs, took 20 s of CPU).
    let mut child = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(["atlas", "paper.toml", "--no-render"])
        .current_dir(dir.path())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let said = {
        use std::io::BufRead;
        let lines = std::io::BufReader::new(child.stderr.take().unwrap()).lines();
        let mut said = String::new();
        for line in lines.map_while(Result::ok) {
            said.push_str(&line);
            said.push('\n');
            if line.starts_with("squeal: atlas of") {
                break;
            }
        }
        said
    };
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(
        said.lines()
            .any(|l| l.starts_with("squeal: atlas of 3 points, 1 boundary searches")),
        "{said}"
    );
    let huge = r#"
version = 1
name = "huge"
[model]
law = "mcmillan"
nu = { from = 1e-3, to = 1e-2, count = 1000, spacing = "log" }
[boundaries]
fold = false
critical = false
[classifier]
early_stop = "none"
[grid]
x0 = { min = -3.0, max = 5.0, count = 4096 }
v0 = { min = -4.0, max = 4.0, count = 4096 }
[output]
path = "huge.h5"
"#;
    std::fs::write(dir.path().join("huge.toml"), huge).unwrap();
    refused(
        squeal(dir.path(), &["atlas", "huge.toml", "--quiet"]),
        "--allow-long",
    );
    assert!(!dir.path().join("huge.h5").exists());
    assert!(!dir.path().join("huge.h5.journal").exists());
}

/// Issue 17, item 3: the mean transient lifetime above each fold as an atlas figure, with
/// its scaling. Two belt speeds at Table 1's tau and phi, 8 band starts per damping: each
/// fold gets the table `squeal critical --fold --lifetimes` prints (`lifetime_table`),
/// stored as its nearest row with a mean (`fold_lifetime_nu = (1 + f) fold_nu`, `f` one of
/// `DISTANCE_FACTORS`, 1% to 7.5%), and the fitted exponent; the summary states them and the
/// two charts are drawn. Without `lifetime_starts` nothing is measured, stored or drawn.
/// About 100 s on a loaded 2-core machine, so a long check.
#[test]
#[ignore = "long physics check (minutes): run by scripts/ci/long-checks.sh, which .ci/run calls"]
fn an_atlas_measures_transient_lifetimes_above_each_fold() {
    let dir = tempfile::tempdir().unwrap();
    let spec = |starts: &str, out: &str| {
        format!(
            "version = 1\nname = \"life\"\n[model]\nlaw = \"mcmillan\"\nnu = [0.02, 0.03]\nlambda = [2.5, 3.0]\n[boundaries]\ncritical = false\n{starts}[output]\npath = \"{out}\"\n"
        )
    };
    std::fs::write(
        dir.path().join("l.toml"),
        spec("lifetime_starts = 8\n", "l.h5"),
    )
    .unwrap();
    let text = ok(squeal(dir.path(), &["atlas", "l.toml", "--threads", "2"]));
    assert_eq!(
        text.matches("transient squeal at nu = ").count(),
        2,
        "{text}"
    );
    let h5 = dir.path().join("l.h5");
    let get = |name: &str| -> Vec<f64> {
        read_f64(&h5, name)
            .into_iter()
            .map(f64::from_bits)
            .collect()
    };
    let (fold, at) = (get("fold_nu"), get("fold_lifetime_nu"));
    let (mean, se, gamma) = (
        get("fold_lifetime"),
        get("fold_lifetime_err"),
        get("fold_lifetime_exponent"),
    );
    for j in 0..2 {
        let f = at[j] / fold[j] - 1.0;
        let factors = squeal_scan::lifetime::DISTANCE_FACTORS;
        assert!(
            factors.iter().any(|d| (d - f).abs() < 1e-12),
            "{at:?} {fold:?}"
        );
        // Past the crisis every band start leaves (at Table 1, 1% above it, after about
        // 2000 time units with 128 starts: README's table), well within t_max = 40000.
        assert!(
            mean[j] > 6.3 && mean[j] < 40_000.0 && se[j] > 0.0,
            "{mean:?} {se:?}"
        );
        // Lifetimes grow towards the crisis: a positive exponent.
        assert!(gamma[j] > 0.0, "{gamma:?}");
    }
    for p in ["l-lifetimes.png", "l-lifetime-exponent.png"] {
        assert!(dir.path().join(p).exists(), "{p}");
    }
    std::fs::write(dir.path().join("n.toml"), spec("", "n.h5")).unwrap();
    ok(squeal(dir.path(), &["atlas", "n.toml", "--threads", "2"]));
    // Not measured: not stored.
    let f = hdf5::File::open(dir.path().join("n.h5")).unwrap();
    assert!(f.dataset("fold_lifetime").is_err());
    assert!(f.dataset("fold_nu").is_ok());
    assert!(!dir.path().join("n-lifetimes.png").exists());
}
