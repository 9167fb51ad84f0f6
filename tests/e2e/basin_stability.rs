//! Basin stability end to end: random samples against the grid on McMillan's
//! law, the sample file read back with the hdf5 crate as a user would, thread independence
//! and resume of a random sample.

use std::path::Path;
use std::process::{Command, Output};

fn squeal(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_squeal"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("run squeal")
}

fn ok(o: &Output) -> String {
    assert!(
        o.status.success(),
        "squeal failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn json(o: &Output) -> serde_json::Value {
    serde_json::from_str(&ok(o)).expect("one JSON object")
}

/// Paper Fig. 10's setting (nu = 1e-2: the cycle encloses the state at rest, so both basins
/// are large) over the paper's region.
const MODEL: &str = r#"version = 1
[model]
law = "mcmillan"
nu = 1e-2
"#;

fn sampled(n: usize, seed: u64, block: usize, out: &str) -> String {
    format!(
        "{MODEL}[sample]\nkind = \"random\"\nn = {n}\nseed = {seed}\nregion = {{ x0 = [-3.0, 5.0], v0 = [-4.0, 4.0] }}\nblock = {block}\n[output]\npath = \"{out}\"\n"
    )
}

#[test]
#[ignore = "long check (a minute or more on 2 cores): run by scripts/ci/long-checks.sh, which .ci/run calls"]
fn random_samples_agree_with_the_grid_within_three_standard_errors() {
    let d = tempfile::tempdir().unwrap();
    let grid = format!(
        "{MODEL}[grid]\nx0 = {{ min = -3.0, max = 5.0, count = 129 }}\nv0 = {{ min = -4.0, max = 4.0, count = 129 }}\n[output]\npath = \"g.h5\"\n"
    );
    std::fs::write(d.path().join("g.toml"), grid).unwrap();
    std::fs::write(d.path().join("s.toml"), sampled(2000, 1, 256, "s.h5")).unwrap();
    let g = json(&squeal(d.path(), &["scan", "g.toml", "--quiet", "--json"]));
    let s = json(&squeal(d.path(), &["scan", "s.toml", "--quiet", "--json"]));
    let (gb, sb) = (
        &g["maps"][0]["basin_stability"],
        &s["maps"][0]["basin_stability"],
    );
    assert_eq!(gb["sampling"], "grid");
    assert_eq!(sb["sampling"], "random");
    assert_eq!(sb["n"], 2000);
    assert!(s["pictures"].as_array().unwrap().is_empty(), "{s}");
    for regime in ["steady_slip", "stick_slip"] {
        let (pg, change) = (
            gb[regime]["p"].as_f64().unwrap(),
            gb[regime]["change"].as_f64().unwrap(),
        );
        let (ps, se) = (
            sb[regime]["p"].as_f64().unwrap(),
            sb[regime]["se"].as_f64().unwrap(),
        );
        // se = sqrt(p (1 - p) / n) of the sample; the grid's error bar is its change from
        // the 2h sub-grid. Both basins hold a sizeable share here, so the test has teeth.
        assert!((se - (ps * (1.0 - ps) / 2000.0).sqrt()).abs() < 1e-15);
        assert!(ps > 0.05 && ps < 0.95, "{regime}: {ps}");
        assert!(
            (pg - ps).abs() <= 3.0 * se + change.abs(),
            "{regime}: grid {pg} (change {change}), sample {ps} +- {se}"
        );
        // The stored counts are the shares' counts.
        assert_eq!(
            s["maps"][0][regime].as_u64().unwrap(),
            sb[regime]["count"].as_u64().unwrap()
        );
    }

    let steady = the_sample_file_is_a_list_over_sample(&d.path().join("s.h5"));

    // `info` reads the same shares back.
    let i = json(&squeal(d.path(), &["info", "s.h5", "--json"]));
    assert_eq!(
        i["basin_stability"][0]["steady_slip"]["p"].as_f64(),
        Some(steady)
    );
    let text = ok(&squeal(d.path(), &["info", "s.h5"]));
    assert!(text.contains("2000 random samples"), "{text}");
}

/// The sampled scan's file `p` (2000 samples, seed 1) as h5py or xarray sees it; its share
/// of steady slip.
fn the_sample_file_is_a_list_over_sample(p: &Path) -> f64 {
    // The file, as h5py or xarray sees it: a list over `sample`, the points in the region,
    // the basin stability per map with long names.
    let f = hdf5::File::open(p).unwrap();
    let attr = |name: &str| -> String {
        let a: hdf5::types::VarLenUnicode = f.attr(name).unwrap().read_scalar().unwrap();
        a.to_string()
    };
    assert_eq!(attr("sampling"), "random");
    let seed: u64 = f.attr("sample_seed").unwrap().read_scalar().unwrap();
    assert_eq!(seed, 1);
    let x0: Vec<f64> = f.dataset("x0").unwrap().read_raw().unwrap();
    let v0: Vec<f64> = f.dataset("v0").unwrap().read_raw().unwrap();
    assert_eq!((x0.len(), v0.len()), (2000, 2000));
    assert!(x0.iter().all(|x| (-3.0..5.0).contains(x)));
    assert!(v0.iter().all(|v| (-4.0..4.0).contains(v)));
    let labels = f.dataset("labels").unwrap();
    assert_eq!(labels.shape(), vec![2000]);
    let l: Vec<u8> = labels.read_raw().unwrap();
    let steady = l.iter().filter(|&&v| v == 1).count() as f64 / 2000.0;
    let bs = f.dataset("basin_stability_steady_slip").unwrap();
    let stored: Vec<f64> = bs.read_raw().unwrap();
    assert_eq!(stored, vec![steady]);
    let long: hdf5::types::VarLenUnicode = bs.attr("long_name").unwrap().read_scalar().unwrap();
    assert!(long.as_str().contains("basin stability"), "{long}");
    let se: Vec<f64> = f
        .dataset("basin_stability_steady_slip_se")
        .unwrap()
        .read_raw()
        .unwrap();
    assert!((se[0] - (steady * (1.0 - steady) / 2000.0).sqrt()).abs() < 1e-15);
    steady
}

#[test]
fn a_random_sample_depends_on_the_seed_only_and_resumes() {
    let d = tempfile::tempdir().unwrap();
    // Slow enough to be killed midway: no early stopping, small blocks.
    let text = sampled(240, 5, 8, "one.h5").replace(
        "[output]",
        "[classifier]\nt_max = 400.0\nearly_stop = \"none\"\n[cycle]\nlocate = false\n[output]",
    );
    std::fs::write(d.path().join("s.toml"), &text).unwrap();
    ok(&squeal(
        d.path(),
        &[
            "scan",
            "s.toml",
            "-o",
            "one.h5",
            "--quiet",
            "--threads",
            "1",
        ],
    ));
    ok(&squeal(
        d.path(),
        &[
            "scan",
            "s.toml",
            "-o",
            "two.h5",
            "--quiet",
            "--threads",
            "2",
        ],
    ));
    let digest = |n: &str| squeal_store::content_digest(&d.path().join(n)).unwrap();
    assert_eq!(digest("one.h5"), digest("two.h5"));

    scan_killed_after_a_block(d.path());
    let out = ok(&squeal(
        d.path(),
        &["scan", "s.toml", "-o", "cut.h5", "--quiet", "--resume"],
    ));
    let computed: usize = out
        .lines()
        .find_map(|l| l.trim().split(" cells in ").next()?.parse().ok())
        .unwrap_or(0);
    assert!(computed < 240, "resume recomputed everything: {out}");
    assert_eq!(digest("one.h5"), digest("cut.h5"));

    // Another seed, another sample.
    std::fs::write(
        d.path().join("s7.toml"),
        text.replace("seed = 5", "seed = 7"),
    )
    .unwrap();
    ok(&squeal(
        d.path(),
        &["scan", "s7.toml", "-o", "seven.h5", "--quiet"],
    ));
    assert_ne!(digest("one.h5"), digest("seven.h5"));
}

/// Runs `s.toml` in `dir` to `cut.h5` on one thread and kills it once a block is in its
/// journal.
fn scan_killed_after_a_block(dir: &Path) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .current_dir(dir)
        .args([
            "scan",
            "s.toml",
            "-o",
            "cut.h5",
            "--quiet",
            "--threads",
            "1",
        ])
        .spawn()
        .unwrap();
    // Journal frames: `SQJR`, a kind byte (`B` for a block), a little-endian u32 length,
    // the payload and an 8-byte checksum (crates/store/src/journal.rs).
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
    for _ in 0..4000 {
        if blocks_in(&journal) > 0 {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    assert!(blocks_in(&journal) > 0, "no block reached the journal");
    child.kill().unwrap();
    child.wait().unwrap();
}
