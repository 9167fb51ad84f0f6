//! The files of `squeal trajectory --out`: each column's units in the file, SI columns for a
//! physical system, and a default sampling that suits the run (an explicit `--every` wins).

use crate::cli_core::{ok, squeal, tmp};

/// README's brake (2 kg on 50 kN/m, c = 10 N s/m, 0.05 m/s belt, mu_k 0.35), started
/// 100 um from rest.
const BRAKE: [&str; 16] = [
    "--m", "2", "--k", "5e4", "--c", "10", "--v-belt", "0.05", "--mu-k", "0.35", "--mu-s", "0.45",
    "--tau-s", "1e-3", "--x0", "1e-4",
];

/// The brake's units (README, "Units"): one length unit is mu_k m g / k, one velocity unit
/// mu_k g sqrt(m / k), one time unit sqrt(m / k).
fn brake_units() -> (f64, f64, f64) {
    let (m, k, mu_k, g) = (2.0f64, 5e4f64, 0.35, 9.81);
    (mu_k * m * g / k, mu_k * g * (m / k).sqrt(), (m / k).sqrt())
}

/// A CSV's `#` lines and its rows after the header line.
fn read_csv(path: &std::path::Path) -> (Vec<String>, String, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let notes: Vec<String> = lines
        .by_ref()
        .take_while(|l| l.starts_with('#'))
        .map(String::from)
        .collect();
    // `take_while` consumed the header line too: it is the first line without `#`.
    let header = text.lines().nth(notes.len()).unwrap().to_string();
    let rows = lines
        .map(|l| l.split(',').map(|f| f.parse().unwrap()).collect())
        .collect();
    (notes, header, rows)
}

/// Issue: a physical run's CSV was nondimensional with a bare header, and `--every 1` by
/// default wrote all 200 000 steps of the default t_end 1000 (six seconds of the brake).
/// Now: the time, x and x' in s, m and m/s beside the model's columns, each column's units
/// in a `#` line, and every 12th step (2 pi / (100 dt) = 12.57 with dt = 0.005), stated.
#[test]
fn a_brake_trajectory_csv_is_in_si_with_units_and_a_bounded_sampling() {
    let dir = tmp();
    let mut args = vec!["trajectory"];
    args.extend(BRAKE);
    args.extend(["--out", "run.csv", "--json"]);
    let out = ok(squeal(dir.path(), &args));
    let path = dir.path().join("run.csv");
    let (notes, header, rows) = read_csv(&path);
    let units = notes.iter().find(|n| n.starts_with("# units:")).unwrap();
    for want in ["t_si in s", "x_si in m", "v_si in m/s", "model's units"] {
        assert!(units.contains(want), "{want}: {units}");
    }
    let sampling = notes.iter().find(|n| n.starts_with("# sampling:")).unwrap();
    assert!(
        sampling.contains("every 12 steps of dt = 0.005 (the default"),
        "{sampling}"
    );
    assert_eq!(header, "t,x,v,a,force,t_si,x_si,v_si");
    // 200 000 steps of 0.005 to t_end 1000: the start and every 12th, 16 666 of them.
    assert_eq!(rows.len(), 16_667);
    let (length, velocity, time) = brake_units();
    let near = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1e-300);
    assert!(near(rows[0][6], 1e-4), "x_si at the start: {}", rows[0][6]);
    for (i, r) in rows.iter().enumerate() {
        assert_eq!(r.len(), 8, "row {i}");
        assert!(
            (r[0] - (12 * i) as f64 * 0.005).abs() < 1e-9,
            "row {i}: t {}",
            r[0]
        );
        assert!(near(r[5], r[0] * time), "row {i}: t_si {} t {}", r[5], r[0]);
        assert!(
            near(r[6], r[1] * length),
            "row {i}: x_si {} x {}",
            r[6],
            r[1]
        );
        assert!(
            near(r[7], r[2] * velocity),
            "row {i}: v_si {} v {}",
            r[7],
            r[2]
        );
    }
    // Six seconds of motion: t_end 1000 times sqrt(2 / 5e4) = 6.32 s.
    assert!((rows[16_666][5] - 999.96 * time).abs() < 1e-9);
    let size = std::fs::metadata(&path).unwrap().len();
    assert!(size < 4_000_000, "{size} bytes");
    // The summary says the same.
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["params"]["every"], 12);
    assert_eq!(v["rows"], 16_667);
    let said = v["sampling"].as_str().unwrap();
    assert!(said.contains("the default: at least 100 samples"), "{said}");
}

/// A run in the model's units: its CSV says so, and has no SI columns; `--every` wins over
/// the default and the file says it was asked for.
#[test]
fn a_model_trajectory_csv_states_its_units_and_an_explicit_every_wins() {
    let dir = tmp();
    let args = [
        "trajectory",
        "--dt",
        "0.01",
        "--t-end",
        "20",
        "--every",
        "1",
        "--out",
        "m.csv",
    ];
    let out = ok(squeal(dir.path(), &args));
    assert!(
        out.contains("(2001 rows: one sample every 1 steps"),
        "{out}"
    );
    let (notes, header, rows) = read_csv(&dir.path().join("m.csv"));
    assert_eq!(header, "t,x,v,a,force");
    assert_eq!(rows.len(), 2001);
    let units = notes.iter().find(|n| n.starts_with("# units:")).unwrap();
    assert!(
        units.contains("nondimensional") && !units.contains("_si"),
        "{units}"
    );
    assert!(notes.iter().any(|n| n.ends_with("(as asked)")), "{notes:?}");
    // Without --every: 2 pi / (100 * 0.01) = 6.28, every 6th of the 2000 steps.
    let args = [
        "trajectory",
        "--dt",
        "0.01",
        "--t-end",
        "20",
        "--out",
        "d.csv",
    ];
    ok(squeal(dir.path(), &args));
    let (_, _, rows) = read_csv(&dir.path().join("d.csv"));
    assert_eq!(rows.len(), 2000 / 6 + 1);
}

/// The `.h5` of a physical run: the SI columns with their units (as before), and the stride
/// with how it was chosen (`every`, `sampling`): the default, or `--every` as asked.
#[test]
fn a_trajectory_h5_states_its_sampling() {
    let dir = tmp();
    let read = |name: &str| {
        let f = hdf5::File::open(dir.path().join(name)).unwrap();
        let every: u64 = f.attr("every").unwrap().read_scalar().unwrap();
        let s: hdf5::types::VarLenUnicode = f.attr("sampling").unwrap().read_scalar().unwrap();
        let t: Vec<f64> = f.dataset("t").unwrap().read_raw().unwrap();
        let units: hdf5::types::VarLenUnicode = f
            .dataset("x_si")
            .unwrap()
            .attr("units")
            .unwrap()
            .read_scalar()
            .unwrap();
        (
            every,
            s.as_str().to_string(),
            t.len(),
            units.as_str().to_string(),
        )
    };
    let mut args = vec!["trajectory", "--t-end", "100", "--out", "d.h5"];
    args.extend(BRAKE);
    ok(squeal(dir.path(), &args));
    // 20 000 steps of 0.005: the start and every 12th, 1666 of them.
    let (every, sampling, n, units) = read("d.h5");
    assert_eq!((every, n, units.as_str()), (12, 1667, "m"));
    assert!(
        sampling.contains("(the default: at least 100"),
        "{sampling}"
    );
    args.extend(["--every", "5"]);
    args[4] = "g.h5";
    ok(squeal(dir.path(), &args));
    let (every, sampling, n, _) = read("g.h5");
    assert_eq!((every, n), (5, 4001));
    assert!(sampling.ends_with("(as asked)"), "{sampling}");
}
