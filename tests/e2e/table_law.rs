//! The tabulated law through the binary (issue 34, item 2): `--law table --friction-csv`
//! on the commands that take the model, the shipped CSV in a scan spec, and the table stored
//! in the scan's and the trajectory's file. New flags and law: each test fails on the code
//! before (there `--law table` was an unknown law and `--friction-csv` an unknown flag).

use std::path::Path;
use std::process::Command;

fn squeal(dir: &Path, args: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("running squeal");
    let text =
        String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    (out.status.success(), text)
}

/// bSTAB's Stribeck law (`mu_d = 0.5`, `mu_sd = 2`, `v_0 = 0.5`, `mu_v = 0`) written as a
/// CSV of 2001 rows, `s = 0, 0.01, ..., 20`, with a header and a comment.
fn fine_csv(dir: &Path) -> String {
    let mut t = String::from("# bSTAB's Stribeck law\nslip_speed,mu\n");
    for i in 0..=2000 {
        let s = i as f64 * 20.0 / 2000.0;
        t.push_str(&format!("{s:?},{:?}\n", 0.5 + 0.5 * (-s / 0.5).exp()));
    }
    std::fs::write(dir.join("fine.csv"), t).unwrap();
    "fine.csv".into()
}

/// `squeal classify` labels the same starts alike under the Stribeck formula and under its
/// fine table (the core's 24 x 24 map says so too: crates/core/tests/model/table.rs), and the
/// trajectory's file stores the table's rows.
#[test]
fn the_tabulated_stribeck_law_classifies_and_stores_its_table() {
    let dir = tempfile::tempdir().unwrap();
    let csv = fine_csv(dir.path());
    std::fs::write(
        dir.path().join("ics.csv"),
        "x0,v0\n-1.0,0.5\n0.5,0.1\n1.8,1.9\n-2.0,0.0\n",
    )
    .unwrap();
    let labels = |law: &[&str], out: &str| {
        let mut args = vec!["classify", "--ics", "ics.csv", "--out", out];
        args.extend(law);
        let (ok, text) = squeal(dir.path(), &args);
        assert!(ok, "{text}");
        let csv = std::fs::read_to_string(dir.path().join(out)).unwrap();
        csv.lines()
            .skip(1)
            .map(|l| l.split(',').nth(2).unwrap().to_string())
            .collect::<Vec<_>>()
    };
    let formula = labels(&["--law", "stribeck"], "a.csv");
    let table = labels(&["--law", "table", "--friction-csv", &csv], "b.csv");
    assert_eq!(formula, table);
    // Both labels occur among the four starts (bSTAB's case 1 is bistable).
    assert!(formula.contains(&"stick_slip".into()) && formula.contains(&"steady_slip".into()));
    let (ok, text) = squeal(
        dir.path(),
        &[
            "trajectory",
            "--law",
            "table",
            "--friction-csv",
            &csv,
            "--t-end",
            "20",
            "--out",
            "run.h5",
        ],
    );
    assert!(ok, "{text}");
    let f = hdf5::File::open(dir.path().join("run.h5")).unwrap();
    let s: Vec<f64> = f
        .dataset("friction_table_slip_speed")
        .unwrap()
        .read_raw()
        .unwrap();
    let mu: Vec<f64> = f.dataset("friction_table_mu").unwrap().read_raw().unwrap();
    assert_eq!((s.len(), s[2000], mu[0]), (2001, 20.0, 1.0));
}

/// The shipped spec (`scans/table-stribeck.toml`, its CSV beside it in `data/`) cut to an
/// 8 x 6 grid scans, and its file stores the table (45 rows) with units; the flag is
/// refused by name with another law and missing with this one.
#[test]
fn the_shipped_table_spec_scans_and_stores_its_table() {
    let dir = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scans");
    std::fs::create_dir(dir.path().join("data")).unwrap();
    std::fs::copy(
        root.join("data/stribeck-mu.csv"),
        dir.path().join("data/stribeck-mu.csv"),
    )
    .unwrap();
    let spec = std::fs::read_to_string(root.join("table-stribeck.toml"))
        .unwrap()
        .replace("count = 128", "count = 8")
        .replace("count = 64", "count = 6");
    std::fs::write(dir.path().join("t.toml"), spec).unwrap();
    let (ok, text) = squeal(dir.path(), &["scan", "t.toml"]);
    assert!(ok, "{text}");
    let f = hdf5::File::open(dir.path().join("out/table-stribeck.h5")).unwrap();
    let mu = f.dataset("friction_table_mu").unwrap();
    let v: Vec<f64> = mu.read_raw().unwrap();
    assert_eq!((v.len(), v[0], v[44]), (45, 1.0, 0.5));
    let units: hdf5::types::VarLenUnicode = mu.attr("units").unwrap().read_scalar().unwrap();
    assert_eq!(units.as_str(), "1");
    // The file holds the curve: shards merge with the CSV gone, and the merged file
    // stores the same table.
    for k in ["1/2", "2/2"] {
        let out = format!("s{}.h5", &k[..1]);
        let (ok, text) = squeal(dir.path(), &["scan", "t.toml", "--shard", k, "-o", &out]);
        assert!(ok, "{text}");
    }
    std::fs::rename(
        dir.path().join("data/stribeck-mu.csv"),
        dir.path().join("gone.csv"),
    )
    .unwrap();
    let (ok, text) = squeal(dir.path(), &["merge", "s1.h5", "s2.h5", "--out", "m.h5"]);
    assert!(ok, "{text}");
    let m = hdf5::File::open(dir.path().join("m.h5")).unwrap();
    let merged: Vec<f64> = m.dataset("friction_table_mu").unwrap().read_raw().unwrap();
    assert_eq!(merged, v);
    std::fs::rename(
        dir.path().join("gone.csv"),
        dir.path().join("data/stribeck-mu.csv"),
    )
    .unwrap();
    for (args, words) in [
        (
            vec![
                "trajectory",
                "--law",
                "cubic",
                "--friction-csv",
                "data/stribeck-mu.csv",
            ],
            "--friction-csv: not a flag of --law cubic",
        ),
        (
            vec!["ulc", "--law", "table"],
            "--friction-csv: missing: --law table needs",
        ),
        (
            vec![
                "critical",
                "--law",
                "table",
                "--friction-csv",
                "nowhere.csv",
            ],
            "--friction-csv: cannot read nowhere.csv",
        ),
    ] {
        let (ok, text) = squeal(dir.path(), &args);
        assert!(!ok && text.contains(words), "{args:?}: {text}");
    }
}
