//! bSTAB's friction benchmark: the published basin-stability values, the
//! independent plain-numpy computation by bSTAB's approach, and squeal against both.
//!
//! * `tests/data/bstab_friction_published.json`: MATLAB bSTAB's values as kept in pyBasin's
//!   repository (two runs, A and B, with their repositories, paths and commits; see
//!   tests/data/README.md).
//! * `tests/data/bstab_friction_reference.json`: written by `scripts/tools/bstab_reference.py`
//!   (5000 uniform random samples per belt speed, seed 1, RK4 with true stick, t = 500,
//!   bSTAB's rule max |x'| over t > 400 above 0.2), the command is inside the file.
//! * `scans/bstab-friction.toml` run by squeal: switched on once the Stribeck law is merged.

use std::path::Path;
use std::process::Command;

use serde_json::Value;

fn load(name: &str) -> Value {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name);
    let text = std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    serde_json::from_str(&text).unwrap()
}

fn f(v: &Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("no number `{key}` in {v}"))
}

/// One published run: (v_d, bs_FP, se_FP) per belt speed.
fn run(doc: &Value, name: &str) -> Vec<(f64, f64, f64)> {
    let r = doc["v_study"]["runs"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["name"] == name)
        .unwrap();
    r["values"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| (f(v, "v_d"), f(v, "bs_FP"), f(v, "se_FP")))
        .collect()
}

/// The belt speeds of the study: numpy.linspace(0.8, 2.225, 20).
fn study() -> Vec<f64> {
    (0..20).map(|i| 0.8 + 1.425 * i as f64 / 19.0).collect()
}

/// Regime of a basin-stability value of steady slip (FP): 0 stick-slip only, 1 bistable,
/// 2 steady slip only.
fn regime(p_fp: f64) -> u8 {
    if p_fp == 0.0 {
        0
    } else if p_fp == 1.0 {
        2
    } else {
        1
    }
}

#[test]
fn the_published_values_are_binomial_shares_of_5000_and_the_two_runs_agree() {
    let doc = load("bstab_friction_published.json");
    let n = f(&doc, "N");
    assert_eq!(n, 5000.0);
    let c1 = &doc["case1"];
    assert_eq!(f(c1, "n_FP") + f(c1, "n_LC"), n);
    assert!((f(c1, "se_FP") - (0.304f64 * 0.696 / n).sqrt()).abs() < 1e-15);
    let (a, b) = (run(&doc, "A"), run(&doc, "B"));
    for ((va, pa, sa), (vb, pb, sb)) in a.iter().zip(&b) {
        assert!((va - vb).abs() < 1e-12);
        // se = sqrt(p (1 - p) / N) and p N is a count.
        for (p, s) in [(pa, sa), (pb, sb)] {
            assert!(
                (s - (p * (1.0 - p) / n).sqrt()).abs() < 1e-12,
                "{va}: {p} {s}"
            );
            assert!((p * n - (p * n).round()).abs() < 1e-6, "{va}: {p}");
        }
        // Two independent samples of one share differ by less than 3 combined errors.
        let comb = sa.hypot(*sb);
        assert!((pa - pb).abs() <= 3.0 * comb, "{va}: {pa} vs {pb}");
        assert_eq!(regime(*pa), regime(*pb), "{va}");
    }
    let vd: Vec<f64> = a.iter().map(|r| r.0).collect();
    for (x, y) in vd.iter().zip(study()) {
        assert!((x - y).abs() < 1e-12);
    }
}

#[test]
fn the_plain_script_agrees_with_the_published_values() {
    let doc = load("bstab_friction_published.json");
    let ours = load("bstab_friction_reference.json");
    let rows = ours["results"].as_array().unwrap();
    assert_eq!(rows.len(), 20, "the script's file covers the whole study");
    for name in ["A", "B"] {
        for ((vd, p, se), r) in run(&doc, name).into_iter().zip(rows) {
            assert!((f(r, "v_d") - vd).abs() < 1e-9);
            let (q, sq) = (f(r, "bs_FP"), f(r, "se"));
            assert!(
                (p - q).abs() <= 3.0 * se.hypot(sq),
                "run {name}, v_d = {vd}: published {p} +- {se}, script {q} +- {sq}"
            );
            assert_eq!(regime(p), regime(q), "run {name}, v_d = {vd}");
        }
    }
}

/// squeal's grid shares of `scans/bstab-friction.toml` against both published runs: within 3
/// of their standard errors (plus the grid's own change from its 2h sub-grid) at every belt
/// speed, and the same regime (stick-slip only, bistable, steady slip only) at every one.
///
/// squeal's basin stability of steady slip over bSTAB's belt-speed study (scans/bstab-friction.toml,
/// 256 x 128 grid per belt speed, runs to settlement or early-stopped on the located cycle)
/// against both published MATLAB runs: within 3 of their standard errors plus the grid's
/// own error bar (the change to the nested half-resolution grid), and in the same regime.
///
/// One exception, measured and kept in the repository: at v_d = 1.175 the fixed point is
/// barely stable (damping 2 xi + mu'(v_d) = 0.0046), so runs that settle on steady slip
/// still swing above bSTAB's threshold at t = 400-500 and bSTAB's rule calls them
/// stick-slip. The same 5000 samples (seed 1) integrated by `scripts/tools/bstab_reference.py` to
/// t = 500 give 67 steady-slip samples (0.0134, tests/data/bstab_friction_reference.json),
/// to t = 2500 give 76 (0.0152 +- 0.0017,
/// tests/data/bstab_friction_reference_vd1.175_t2500.json): the published 0.0132 / 0.0126
/// undercount steady slip there. At that belt speed squeal is compared with the t = 2500
/// reference instead (the claim does not hold there; the closing note says so).
#[test]
#[ignore = "long physics check (minutes): run by scripts/ci/long-checks.sh, which .ci/run calls"]
fn squeal_matches_the_published_basin_stability() {
    let dir = tempfile::tempdir().unwrap();
    let spec = Path::new(env!("CARGO_MANIFEST_DIR")).join("scans/bstab-friction.toml");
    let out = dir.path().join("bstab.h5");
    let o = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(["scan", spec.to_str().unwrap(), "-o", out.to_str().unwrap()])
        .args(["--quiet", "--json"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    let maps = v["maps"].as_array().unwrap();
    assert_eq!(maps.len(), 20);
    let doc = load("bstab_friction_published.json");
    let long = load("bstab_friction_reference_vd1.175_t2500.json");
    let long = &long["results"][0];
    let (long_vd, long_p, long_se) = (f(long, "v_d"), f(long, "bs_FP"), f(long, "se"));
    assert_eq!(long_vd, 1.175);
    for name in ["A", "B"] {
        for ((vd, p, se), m) in run(&doc, name).into_iter().zip(maps) {
            let (p, se) = if (vd - long_vd).abs() < 1e-9 {
                (long_p, long_se)
            } else {
                (p, se)
            };
            assert!((f(m, "v_d") - vd).abs() < 1e-9, "{m}");
            let b = &m["basin_stability"];
            assert_eq!(
                f(&b["undecided"], "count"),
                0.0,
                "v_d = {vd}: undecided cells"
            );
            let q = f(&b["steady_slip"], "p");
            let grid = f(&b["steady_slip"], "change").abs();
            assert!(
                (p - q).abs() <= 3.0 * se + grid,
                "run {name}, v_d = {vd}: published {p} +- {se}, squeal {q} (grid change {grid})"
            );
            assert_eq!(
                regime(p),
                regime(q),
                "run {name}, v_d = {vd}: published {p}, squeal {q}"
            );
        }
    }
}
