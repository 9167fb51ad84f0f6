//! The tabulated law through the binary: `--law table --friction-csv`
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

/// The clamped pad on its measured curve (`pad.csv` of [`pad_curves`]): 0.8 kg on a
/// 200 kN/m mount, the disc at 0.3 m/s, clamped with 1500 N; the dashpot is each test's.
const PAD_CURVE: [&str; 12] = [
    "--law",
    "table",
    "--friction-csv",
    "pad.csv",
    "--m",
    "0.8",
    "--k",
    "2e5",
    "--v-belt",
    "0.3",
    "--normal-force",
    "1500",
];

/// The shipped pad curve (`scans/data/pad-mu.csv`, slip speed in m/s) copied into `dir`,
/// and the same curve in the model's units written beside it (`nd.csv`): the law is
/// written in the normal load (crates/core/MODEL.md section 8), so for the clamped pad
/// below, m = 0.8 kg, k = 2e5 N/m, N = 1500 N, the velocity unit is N / sqrt(m k) =
/// 1500 / 400 = 3.75 m/s and each slip speed is divided by it (mu as measured).
fn pad_curves(dir: &Path) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scans/data/pad-mu.csv");
    let text = std::fs::read_to_string(root).unwrap();
    std::fs::write(dir.join("pad.csv"), &text).unwrap();
    let mut nd = String::from("s,mu\n");
    for line in text.lines().filter(|l| !l.starts_with('#')).skip(1) {
        let (s, mu) = line.split_once(',').unwrap();
        let s: f64 = s.trim().parse().unwrap();
        nd.push_str(&format!("{:?},{}\n", s / 3.75, mu.trim()));
    }
    std::fs::write(dir.join("nd.csv"), nd).unwrap();
}

/// The README's disc brake stated as an engineer states it: 0.8 kg on a 200 kN/m mount, disc
/// at 0.3 m/s, clamped with `--normal-force 1500`, and a measured curve in m/s. It is the
/// nondimensional table law with xi = c / (2 sqrt(m k)) = c / 800, v_d = v_B sqrt(m k) /
/// N = 0.3 * 400 / 1500 = 0.08 and the curve's speeds over 3.75 m/s (`pad_curves`); starts
/// in m and m/s are x0 / (N / k) = x0 / 7.5 mm and v0 / 3.75 m/s there. Same labels and
/// reasons at c = 150 N s/m (xi = 0.1875: bistable, both labels occur), the same lasting
/// oscillation at c = 20 N s/m (xi = 0.025) from rest, its frequency in Hz the model's
/// omega times omega_0 / (2 pi) = 500 / (2 pi); and the g-hack g = N / m = 1875 gives the
/// same files byte for byte. Fails on fdec01a: `--law table` refused the physical flags.
#[test]
fn a_clamped_pad_with_a_measured_curve_is_its_nondimensional_model() {
    let dir = tempfile::tempdir().unwrap();
    pad_curves(dir.path());
    write_pad_starts(dir.path());
    let pad = |c: &str, load: [&'static str; 2]| {
        let mut a = vec!["--law", "table", "--friction-csv", "pad.csv", "--m", "0.8"];
        a.extend(["--k", "2e5", "--v-belt", "0.3", load[0], load[1], "--c"]);
        a.push(Box::leak(c.to_string().into_boxed_str()));
        a
    };
    let labels = |model: Vec<&str>, ics: &str, out: &str| {
        let mut args = vec!["classify", "--ics", ics, "--out", out];
        args.extend(model);
        let (ok, text) = squeal(dir.path(), &args);
        assert!(ok, "{text}");
        let csv = std::fs::read_to_string(dir.path().join(out)).unwrap();
        let rows: Vec<String> = csv
            .lines()
            .skip(1)
            .map(|l| l.split(',').skip(2).take(2).collect::<Vec<_>>().join(","))
            .collect();
        (rows, csv)
    };
    let clamp = ["--normal-force", "1500"];
    let (si_labels, si_csv) = labels(pad("150", clamp), "si.csv", "si-out.csv");
    let nd_model = |xi: &'static str| {
        vec![
            "--law",
            "table",
            "--friction-csv",
            "nd.csv",
            "--xi",
            xi,
            "--v-d",
            "0.08",
        ]
    };
    let (nd_labels, _) = labels(nd_model("0.1875"), "nd-ics.csv", "nd-out.csv");
    assert_eq!(si_labels, nd_labels);
    for label in ["stick_slip", "steady_slip"] {
        assert!(
            si_labels.iter().any(|l| l.starts_with(label)),
            "{si_labels:?}"
        );
    }
    let (_, hack_csv) = labels(pad("150", ["--g", "1875"]), "si.csv", "hack-out.csv");
    assert_eq!(si_csv, hack_csv);
    // From rest at c = 20 N s/m: the lasting oscillation, in Hz from the SI run and in the
    // model's units from the nondimensional one.
    let run = |model: Vec<&str>| {
        let mut args = vec!["trajectory", "--t-end", "3000"];
        args.extend(model);
        let (ok, text) = squeal(dir.path(), &args);
        assert!(ok, "{text}");
        text
    };
    let si_run = run(pad("20", clamp));
    let field = |text: &str, key: &str| -> f64 {
        let at = text.find(key).unwrap_or_else(|| panic!("{key}: {text}")) + key.len();
        let rest = text[at..].trim_start_matches([' ', '=', ':', '"', '[']);
        let end = rest.find([',', ' ', ']', '}', '\n']).unwrap();
        rest[..end].parse().unwrap()
    };
    let hz = field(&si_run, "\"lasting_frequency_hz\"");
    let omega = field(&run(nd_model("0.025")), "lasting oscillation: omega");
    let want = omega * 500.0 / std::f64::consts::TAU;
    // omega is printed to 6 significant digits.
    assert!((hz - want).abs() < 2e-6 * want, "{hz} Hz vs {want} Hz");
    // The stick-slip of a pad on this curve: about 66.4 Hz (measured with this test's run,
    // README section 4).
    assert!((hz - 66.36).abs() < 0.01, "{hz}");
    assert_eq!(si_run, run(pad("20", ["--g", "1875"])));
}

/// The pad's starts in `dir`: `si.csv` in m and m/s, `nd-ics.csv` the same starts in the
/// model's units (x0 / 7.5 mm, v0 / 3.75 m/s).
fn write_pad_starts(dir: &Path) {
    let si_starts = [
        (0.003, 0.0),
        (0.0, 0.0),
        (0.003, 0.05),
        (-0.01, 0.0),
        (0.003, -0.3),
        (0.003, 0.2),
        (0.01, -1.0),
    ];
    let mut si = String::from("x0,v0\n");
    let mut nd = String::from("x0,v0\n");
    for (x, v) in si_starts {
        si.push_str(&format!("{x:?},{v:?}\n"));
        nd.push_str(&format!("{:?},{:?}\n", x / 7.5e-3, v / 3.75));
    }
    std::fs::write(dir.join("si.csv"), si).unwrap();
    std::fs::write(dir.join("nd-ics.csv"), nd).unwrap();
}

/// The pad's run stores its curve in m/s with units beside the model's speeds, and
/// `squeal info` prints the table: its rows when few, else their count and ranges (before,
/// fdec01a printed none, and listed the table's datasets among the variables over t). A
/// curve in m/s with a negative speed, and `--mu-k` beside a curve, are refused by flag.
#[test]
fn the_pads_curve_is_stored_in_si_and_shown_by_info() {
    let dir = tempfile::tempdir().unwrap();
    pad_curves(dir.path());
    let pad = [&PAD_CURVE[..], &["--c", "20"]].concat();
    let mut args = vec!["trajectory", "--t-end", "10", "--out", "run.h5"];
    args.extend(&pad);
    let (ok, text) = squeal(dir.path(), &args);
    assert!(ok, "{text}");
    let f = hdf5::File::open(dir.path().join("run.h5")).unwrap();
    let si = f.dataset("friction_table_slip_speed_si").unwrap();
    let s: Vec<f64> = si.read_raw().unwrap();
    let units: hdf5::types::VarLenUnicode = si.attr("units").unwrap().read_scalar().unwrap();
    assert_eq!((s.len(), s[7], units.as_str()), (8, 2.0, "m/s"));
    let nd: Vec<f64> = f
        .dataset("friction_table_slip_speed")
        .unwrap()
        .read_raw()
        .unwrap();
    // The model's speeds are the measured ones over N / sqrt(m k) = 3.75 m/s.
    assert!((nd[7] - 2.0 / 3.75).abs() < 1e-15, "{}", nd[7]);
    let (ok, info) = squeal(dir.path(), &["info", "run.h5"]);
    assert!(ok, "{info}");
    assert!(
        info.contains("friction table: 8 rows (slip speed in m/s, in the model's units, mu):")
            && info.contains("    2, 0.5333333333333333, 0.36"),
        "{info}"
    );
    let vars = info
        .lines()
        .find(|l| l.contains("variables over t"))
        .unwrap();
    assert!(!vars.contains("friction_table"), "{vars}");
    // `info --json` holds the same table (before, it had none): mu and both speeds.
    let (ok, json) = squeal(dir.path(), &["info", "run.h5", "--json"]);
    assert!(ok, "{json}");
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let t = &v["friction_table"];
    let at = |key: &str| t[key][7].as_f64().unwrap();
    assert_eq!(t["mu"].as_array().map(Vec::len), Some(8), "{t}");
    assert_eq!((at("slip_speed_si"), at("mu")), (2.0, 0.36), "{t}");
    assert!((at("slip_speed") - 2.0 / 3.75).abs() < 1e-15, "{t}");
    a_long_table_is_summarised_by_info(dir.path());
    // Refusals by flag: a speed below zero in m/s (the CSV's line named), `--mu-k`.
    std::fs::write(dir.path().join("bad.csv"), "s,mu\n0,0.48\n-0.1,0.45\n").unwrap();
    let mut bad = pad.to_vec();
    bad[3] = "bad.csv";
    let mut args = vec!["trajectory"];
    args.extend(&bad);
    let (ok, text) = squeal(dir.path(), &args);
    assert!(
        !ok && text.contains("--friction-csv") && text.contains("line 3"),
        "{text}"
    );
    let mut args = vec![
        "classify", "--ics", "x.csv", "--out", "o.csv", "--mu-k", "0.4",
    ];
    args.extend(&pad);
    let (ok, text) = squeal(dir.path(), &args);
    assert!(
        !ok && text.contains("--mu-k") && text.contains("does not use"),
        "{text}"
    );
}

/// `squeal info` of a run in `dir` on a long table (2001 rows) gives its count and ranges.
fn a_long_table_is_summarised_by_info(dir: &Path) {
    // A long table is summarised: bSTAB's Stribeck law at 2001 rows (`fine_csv`).
    let csv = fine_csv(dir);
    let (ok, text) = squeal(
        dir,
        &[
            "trajectory",
            "--law",
            "table",
            "--friction-csv",
            &csv,
            "--t-end",
            "1",
            "--out",
            "f.h5",
        ],
    );
    assert!(ok, "{text}");
    let (_, info) = squeal(dir, &["info", "f.h5"]);
    assert!(
        info.contains(
            "friction table: 2001 rows, slip speed 0 to 20 (the model's units), mu 1 at rest"
        ),
        "{info}"
    );
}

/// The shipped atlas of the pad on its measured curve (`scans/brake-curve.toml`, cut to 4
/// values of c) runs with its boundaries and stores them in SI: the critical damping
/// `critical_c` in N s/m beside the model's `critical_xi`, and the curve in m/s. Before
/// the boundary's SI twin was named after the law's key, it took the model's own name
/// (`critical_xi` twice) and the write failed with an HDF5 error; on fdec01a the spec was
/// refused (`friction_csv` unknown under `[physical]`).
#[test]
fn the_shipped_pad_atlas_stores_its_boundaries_in_si() {
    let dir = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scans");
    std::fs::create_dir(dir.path().join("data")).unwrap();
    std::fs::copy(
        root.join("data/pad-mu.csv"),
        dir.path().join("data/pad-mu.csv"),
    )
    .unwrap();
    let spec = std::fs::read_to_string(root.join("brake-curve.toml"))
        .unwrap()
        .replace("count = 12", "count = 4");
    std::fs::write(dir.path().join("b.toml"), spec).unwrap();
    let (ok, text) = squeal(dir.path(), &["atlas", "b.toml", "--no-render", "--quiet"]);
    assert!(ok, "{text}");
    let f = hdf5::File::open(dir.path().join("out/brake-curve.h5")).unwrap();
    let c = f.dataset("critical_c").unwrap();
    let units: hdf5::types::VarLenUnicode = c.attr("units").unwrap().read_scalar().unwrap();
    assert_eq!(units.as_str(), "N s/m");
    let xi: Vec<f64> = f.dataset("critical_xi").unwrap().read_raw().unwrap();
    let c: Vec<f64> = c.read_raw().unwrap();
    // c = 2 sqrt(m k) xi = 800 xi; `squeal critical` from rest finds c = 208.68 N s/m
    // (README section 4).
    assert!(
        (c[0] - 800.0 * xi[0]).abs() < 1e-9 * c[0],
        "{c:?} vs {xi:?}"
    );
    assert!((c[0] - 208.7).abs() < 1.0, "{c:?}");
    let s: Vec<f64> = f
        .dataset("friction_table_slip_speed_si")
        .unwrap()
        .read_raw()
        .unwrap();
    assert_eq!(s.last(), Some(&2.0));
    // `info` labelled the default box "units of mu_k g / omega_0^2", but a measured curve
    // has no mu_k: its units are those of the normal force (crates/core/MODEL.md section 8).
    let (ok, info) = squeal(dir.path(), &["info", "out/brake-curve.h5"]);
    assert!(ok, "{info}");
    let line = |key: &str| info.lines().find(|l| l.contains(key)).unwrap_or_default();
    let (x, v) = (line("disturbance_x_units"), line("disturbance_v_units"));
    assert!(x.contains("units of N / k") && !x.contains("mu_k"), "{x}");
    assert!(
        v.contains("units of N / sqrt(m k)") && !v.contains("mu_k"),
        "{v}"
    );
}

/// `squeal critical` of the clamped pad on its measured curve, with the default bracket
/// (nu up to 0.05): the unstable cycle encloses rest only above that top, and the command
/// refused with "raise it" where the runs would raise the top themselves (as they do for
/// McMillan's laws outside the checked region). It now answers from runs, saying why, and
/// two trajectories 1% either side of the answer (an independent door) squeal below it
/// and settle above it.
#[test]
fn critical_on_a_measured_curve_raises_the_default_top() {
    let dir = tempfile::tempdir().unwrap();
    pad_curves(dir.path());
    let pad = PAD_CURVE;
    let mut args = vec!["critical", "--c", "20", "--horizon", "3000", "--json"];
    args.extend(pad);
    let (ok, text) = squeal(dir.path(), &args);
    assert!(ok, "{text}");
    let v = first_json(&text);
    assert_eq!(v["by"], "runs", "{v}");
    assert!(
        v["why_runs"]
            .as_str()
            .unwrap()
            .contains("no answer in the range"),
        "{v}"
    );
    let c = v["c"].as_f64().unwrap();
    // Above the default top: c = 0.05 * 2 sqrt(m k) = 40 N s/m.
    assert!(c > 40.0, "{v}");
    for (factor, regime) in [(0.99, "stick_slip"), (1.01, "steady_slip")] {
        let c = format!("{}", c * factor);
        let mut args = vec!["trajectory", "--c", &c, "--t-end", "3000", "--json"];
        args.extend(pad);
        let (ok, text) = squeal(dir.path(), &args);
        assert!(ok, "{text}");
        let t = first_json(&text);
        assert_eq!(t["classification"]["regime"], regime, "c = {c}: {t}");
    }
}

/// The first JSON value of a command's output (stdout, then stderr's words).
fn first_json(text: &str) -> serde_json::Value {
    let at = text.find('{').expect("a JSON object");
    let mut values = serde_json::Deserializer::from_str(&text[at..]).into_iter();
    values.next().expect("a value").expect("valid JSON")
}
