//! What the commands give back for a physical system (SI flags or `[physical]`): the atlas
//! summary words each boundary in both unit systems (the fold's uncertainty beside the value
//! it belongs to, in nu and in N s/m), and a trajectory file says how to read its numbers
//! in SI units.

use crate::physical_clamp::PAD;
use std::process::Command;

/// README's brake (scans/brake.toml) at one dashpot value: the fold only, bisected over a
/// range that brackets it (the README's `squeal critical --fold` puts it at nu = 0.0286).
const BRAKE: &str = r#"
version = 1
name = "brake-one"
[model]
law = "mcmillan"
[physical]
m = 2.0
k = 5.0e4
c = 10.0
v_belt = 0.05
mu_k = 0.35
mu_s = 0.45
tau = 1e-3
[boundaries]
critical = false
nu_lo = 0.01
nu_hi = 0.05
[output]
path = "one.h5"
"#;

/// The number after `key = ` and the one after the `+-` that follows it in `line`.
fn value_and_error(line: &str, key: &str) -> (f64, f64) {
    let rest = &line[line.find(key).unwrap_or_else(|| panic!("{key} in {line}")) + key.len()..];
    let mut words = rest.split_whitespace();
    let value: f64 = words.next().unwrap().parse().unwrap();
    assert_eq!(
        words.next(),
        Some("+-"),
        "{key}'s uncertainty follows it: {line}"
    );
    let error: f64 = words.next().unwrap().trim_end_matches(')').parse().unwrap();
    (value, error)
}

#[test]
#[ignore = "long check (a minute or more on 2 cores): run by scripts/ci/long-checks.sh, which .ci/run calls"]
fn physical_atlas_summary_gives_the_fold_uncertainty_in_both_units() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("one.toml"), BRAKE).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(["atlas", "one.toml", "--quiet", "--no-render"])
        .current_dir(dir.path())
        .output()
        .expect("the squeal binary runs");
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let line = out.lines().find(|l| l.contains("here: fold")).expect(&out);
    let (nu, nu_err) = value_and_error(line, "fold nu = ");
    let (c, c_err) = value_and_error(line, "(c = ");
    assert!(line.contains(&format!("+- {c_err:.4} N s/m)")), "{line}");
    // c = nu 2 sqrt(m k) (README, "Units"): 2 sqrt(2 * 5e4) = 632.456 N s/m per unit of nu,
    // for the value and its uncertainty alike; the printed digits (5 decimals of nu, 4 of c)
    // bound the relative rounding at 0.5e-5 / nu_err < 1%.
    let unit = 2.0 * (2.0f64 * 5.0e4).sqrt();
    assert!((c - nu * unit).abs() <= 1e-3 * c, "{line}");
    assert!(nu_err > 0.0, "{line}");
    assert!((c_err - nu_err * unit).abs() <= 1e-2 * c_err, "{line}");
}

#[test]
fn physical_trajectory_file_stores_the_system_and_its_units() {
    let dir = tempfile::tempdir().unwrap();
    brake_trajectory_to_run_h5(dir.path());
    let f = hdf5::File::open(dir.path().join("run.h5")).unwrap();
    let num = |k: &str| -> f64 {
        f.attr(k)
            .unwrap_or_else(|e| panic!("attribute {k}: {e}"))
            .read_scalar()
            .unwrap()
    };
    let text = |k: &str| -> String {
        let v: hdf5::types::VarLenUnicode = f.attr(k).unwrap().read_scalar().unwrap();
        v.as_str().to_string()
    };
    // README, "Units": one length unit is mu_k m g / k = 0.35 * 2 * 9.81 / 5e4 m, one
    // velocity unit mu_k g sqrt(m / k), one time unit sqrt(m / k).
    let length = 0.35 * 2.0 * 9.81 / 5e4;
    let velocity = 0.35 * 9.81 * (2.0f64 / 5e4).sqrt();
    assert!((num("length_unit") - length).abs() <= 1e-12 * length);
    assert_eq!(text("length_unit_units"), "m");
    assert!((num("velocity_unit") - velocity).abs() <= 1e-12 * velocity);
    assert_eq!(text("velocity_unit_units"), "m/s");
    assert!((num("time_unit") - (2.0f64 / 5e4).sqrt()).abs() <= 1e-15);
    assert_eq!(num("physical_c"), 10.0);
    assert_eq!(text("physical_c_units"), "N s/m");
    // The stored start is nondimensional; times the length unit it is the --x0 given in m.
    assert!((num("x0") * num("length_unit") - 1e-4).abs() <= 1e-15);
    // The samples in SI units beside them, the time in seconds an
    // auxiliary coordinate of each (before: t, x, v in the model's units only).
    let f64s = |k: &str| -> Vec<f64> {
        let ds = f.dataset(k).unwrap_or_else(|e| panic!("dataset {k}: {e}"));
        ds.read_raw().unwrap()
    };
    let ds_text = |ds: &str, k: &str| -> String {
        let v: hdf5::types::VarLenUnicode = f
            .dataset(ds)
            .unwrap()
            .attr(k)
            .unwrap()
            .read_scalar()
            .unwrap();
        v.as_str().to_string()
    };
    let (x, x_si, t, t_si) = (f64s("x"), f64s("x_si"), f64s("t"), f64s("t_si"));
    assert!((x_si[0] - 1e-4).abs() <= 1e-15, "{}", x_si[0]);
    for i in 0..x.len() {
        assert_eq!(x_si[i], x[i] * num("length_unit"));
        assert_eq!(t_si[i], t[i] * num("time_unit"));
    }
    for (ds, units) in [("t_si", "s"), ("x_si", "m"), ("v_si", "m/s")] {
        assert_eq!(ds_text(ds, "units"), units, "{ds}");
    }
    for ds in ["x", "v", "a", "force", "x_si", "v_si"] {
        assert_eq!(ds_text(ds, "coordinates"), "t_si", "{ds}");
    }
}

/// `squeal trajectory` of README's brake in `dir`, written to `run.h5`.
fn brake_trajectory_to_run_h5(dir: &std::path::Path) {
    // README's brake at c = 10 N s/m, started 100 um from rest.
    let args = [
        "trajectory",
        "--m",
        "2",
        "--k",
        "5e4",
        "--c",
        "10",
        "--v-belt",
        "0.05",
        "--mu-k",
        "0.35",
        "--mu-s",
        "0.45",
        "--tau-s",
        "1e-3",
        "--x0",
        "1e-4",
        "--t-end",
        "10",
        "--out",
        "run.h5",
    ];
    let o = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the squeal binary runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// README's brake oscillator under Coulomb friction: m, k, c, v_belt, mu_k alone (Coulomb's
/// force has no static peak and no surface time, so no mu_s and no tau), on a 3 x 2 grid.
const COULOMB_SCAN: &str = r#"
version = 1
[model]
law = "coulomb"
[physical]
m = 2.0
k = 5.0e4
c = 10.0
v_belt = 0.05
mu_k = 0.35
[grid]
x0 = { min = -1e-4, max = 2e-4, count = 3 }
v0 = { min = -0.01, max = 0.01, count = 2 }
[output]
path = "coulomb.h5"
"#;

/// The same oscillator as a one-point atlas without boundaries.
const COULOMB_ATLAS: &str = r#"
version = 1
name = "coulomb-one"
[model]
law = "coulomb"
[physical]
m = 2.0
k = 5.0e4
c = 10.0
v_belt = 0.05
mu_k = 0.35
[boundaries]
fold = false
critical = false
[output]
path = "atlas.h5"
"#;

/// The spec as versions before this one required it: McMillan's surfaces given to Coulomb,
/// which read them and then ignored them.
fn with_surfaces(spec: &str) -> String {
    spec.replace("mu_k = 0.35", "mu_k = 0.35\nmu_s = 0.45\ntau = 1e-3")
}

/// `squeal args...` in `dir`: its status and stderr.
pub(crate) fn run(dir: &std::path::Path, args: &[&str]) -> (bool, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the squeal binary runs");
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stderr).into(),
    )
}

/// The root attribute names of an HDF5 file.
fn attr_names(path: &std::path::Path) -> Vec<String> {
    hdf5::File::open(path).unwrap().attr_names().unwrap()
}

/// A Coulomb system runs without mu_s and tau (before, both were required: `missing field
/// mu_s`), and its file carries no physical_mu_s or physical_tau; given, either is refused
/// by name with the law, before anything is written.
#[test]
fn a_coulomb_system_takes_no_surfaces() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("c.toml"), COULOMB_SCAN).unwrap();
    let (ok, err) = run(d, &["scan", "c.toml", "--quiet"]);
    assert!(ok, "{err}");
    let names = attr_names(&d.join("coulomb.h5"));
    assert!(names.iter().any(|n| n == "physical_mu_k"), "{names:?}");
    assert!(
        !names
            .iter()
            .any(|n| n.starts_with("physical_mu_s") || n.starts_with("physical_tau")),
        "{names:?}"
    );
    for (key, text) in [
        (
            "mu_s",
            COULOMB_SCAN.replace("mu_k = 0.35", "mu_k = 0.35\nmu_s = 0.45"),
        ),
        (
            "tau",
            COULOMB_SCAN.replace("mu_k = 0.35", "mu_k = 0.35\ntau = 1e-3"),
        ),
    ] {
        std::fs::write(d.join("bad.toml"), text).unwrap();
        let (ok, err) = run(d, &["scan", "bad.toml", "--quiet", "-o", "bad.h5"]);
        assert!(
            !ok && err.contains(&format!("`physical.{key}`")) && err.contains("\"coulomb\""),
            "{err}"
        );
        assert!(!d.join("bad.h5").exists());
    }
}

/// The flags follow the same rule: `--law coulomb` runs without `--mu-s --tau-s` and
/// refuses either by name; McMillan's law without one of them names it.
#[test]
fn the_physical_flags_take_the_laws_surfaces() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let system = [
        "--m", "2", "--k", "5e4", "--c", "10", "--v-belt", "0.05", "--mu-k", "0.35",
    ];
    let traj = |extra: &[&str]| {
        let mut a = vec!["trajectory", "--x0", "1e-4", "--t-end", "1"];
        a.extend(system);
        a.extend(extra);
        run(d, &a)
    };
    let (ok, err) = traj(&["--law", "coulomb", "--out", "run.h5"]);
    assert!(ok, "{err}");
    let names = attr_names(&d.join("run.h5"));
    assert!(names.iter().any(|n| n == "physical_c"), "{names:?}");
    assert!(
        !names
            .iter()
            .any(|n| n == "physical_mu_s" || n == "physical_tau"),
        "{names:?}"
    );
    for (extra, flag, law) in [
        (
            &["--law", "coulomb", "--mu-s", "0.45"][..],
            "--mu-s",
            "coulomb",
        ),
        (
            &["--law", "coulomb", "--tau-s", "1e-3"][..],
            "--tau-s",
            "coulomb",
        ),
        (&["--mu-s", "0.45"][..], "--tau-s", "mcmillan"),
        (
            &["--law", "mcmillan-nonhysteretic", "--tau-s", "1e-3"][..],
            "--mu-s",
            "mcmillan-nonhysteretic",
        ),
    ] {
        let (ok, err) = traj(extra);
        assert!(
            !ok && err.contains(&format!("{flag}:")) && err.contains(&format!("law {law} ")),
            "{extra:?}: {err}"
        );
    }
}

/// Replaces the `spec` attribute of `path` by `text`: a file as an older squeal wrote it,
/// whose stored spec gave Coulomb the mu_s and tau it required.
pub(crate) fn store_spec(path: &std::path::Path, text: &str) {
    let f = hdf5::File::open_rw(path).unwrap();
    f.delete_attr("spec").unwrap();
    let v: hdf5::types::VarLenUnicode = text.parse().unwrap();
    f.new_attr::<hdf5::types::VarLenUnicode>()
        .create("spec")
        .unwrap()
        .write_scalar(&v)
        .unwrap();
}

/// Files whose spec gave Coulomb mu_s and tau (every Coulomb physical file before this
/// version) still read where the spec is read back: an atlas file's `info` and a scan's
/// shards' `merge`.
#[test]
fn old_coulomb_files_with_surfaces_still_read() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("a.toml"), COULOMB_ATLAS).unwrap();
    let (ok, err) = run(d, &["atlas", "a.toml", "--quiet", "--no-render"]);
    assert!(ok, "{err}");
    // The new atlas file stores its fixed parameters as attributes: mu_k, but no mu_s, tau.
    let names = attr_names(&d.join("atlas.h5"));
    assert!(names.iter().any(|n| n == "mu_k"), "{names:?}");
    assert!(
        !names
            .iter()
            .any(|n| n.starts_with("mu_s") || n.starts_with("tau")),
        "{names:?}"
    );
    store_spec(&d.join("atlas.h5"), &with_surfaces(COULOMB_ATLAS));
    let (ok, err) = run(d, &["info", "atlas.h5"]);
    assert!(ok, "{err}");
    std::fs::write(d.join("c.toml"), COULOMB_SCAN).unwrap();
    for k in ["1/2", "2/2"] {
        let name = format!("s{}.h5", &k[..1]);
        let (ok, err) = run(d, &["scan", "c.toml", "-o", &name, "--shard", k, "--quiet"]);
        assert!(ok, "{err}");
        store_spec(&d.join(&name), &with_surfaces(COULOMB_SCAN));
    }
    let (ok, err) = run(d, &["merge", "s1.h5", "s2.h5", "-o", "m.h5", "--no-render"]);
    assert!(ok, "{err}");
    let (ok, err) = run(d, &["info", "m.h5"]);
    assert!(ok, "{err}");
}

/// A stored spec that reads back to another number of points than the file holds is
/// refused, not zipped short: an older squeal's Coulomb atlas that swept mu_s (each value a
/// point: 2 x 2 here) now reads to the points without the sweep, and the file's figures
/// would land on the wrong points. Before, `info` read a 3-point spec over this 2-point file
/// and the swept mu_s was dropped without a word.
#[test]
fn a_stored_spec_of_another_size_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let two = COULOMB_ATLAS.replace("c = 10.0", "c = [5.0, 10.0]");
    std::fs::write(d.join("a.toml"), &two).unwrap();
    let (ok, err) = run(d, &["atlas", "a.toml", "--quiet", "--no-render"]);
    assert!(ok, "{err}");
    let file = d.join("atlas.h5");
    store_spec(&file, &two.replace("[5.0, 10.0]", "[5.0, 10.0, 20.0]"));
    let (ok, err) = run(d, &["info", "atlas.h5"]);
    assert!(
        !ok && err.contains("holds 2 values where its stored spec has 3"),
        "{err}"
    );
    let swept = two.replace("mu_k = 0.35", "mu_k = 0.35\nmu_s = [0.45, 0.5]\ntau = 1e-3");
    store_spec(&file, &swept);
    let (ok, err) = run(d, &["info", "atlas.h5"]);
    assert!(
        !ok && err.contains("`physical.mu_s`") && err.contains("older squeal"),
        "{err}"
    );
}

/// The README's clamped disc brake (the pad of `physical_clamp.rs` with `--normal-force
/// 1500`), `squeal critical` with `extra`, as JSON.
fn brake_critical(extra: &[&str]) -> serde_json::Value {
    let mut args = vec!["critical"];
    args.extend(PAD);
    args.extend([
        "--normal-force",
        "1500",
        "--c",
        "10",
        "--rtol",
        "1e-3",
        "--json",
    ]);
    args.extend(extra);
    let o = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(args)
        .output()
        .expect("the squeal binary runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).unwrap()
}

/// At the brake (lambda 0.21, outside the checked region) the critical damping of rest and
/// the fold come from runs, and agree with runs: from rest the run at dt = 0.005 still lasts
/// at c = 140 N s/m and reaches the fixed point at 150 (`squeal trajectory ... --c 140
/// --t-end 3000`, crates/core/MODEL.md section 13), at dt/2 it lasts up to about 160. The
/// unstable cycle's answer was 13.77 N s/m, ten times too low: the interval
/// must hold c = 150 and lie within 140-175, and the fold must not lie below it.
#[test]
#[ignore = "long check against long runs (a minute or more on 2 cores): run by scripts/ci/long-checks.sh, which .ci/run calls"]
fn the_brakes_critical_damping_and_fold_agree_with_runs() {
    let c = brake_critical(&["--horizon", "3000"]);
    assert_eq!(c["by"], "runs", "{c}");
    let iv = |j: &serde_json::Value| -> [f64; 2] {
        let a = j["c_interval"].as_array().unwrap();
        [a[0].as_f64().unwrap(), a[1].as_f64().unwrap()]
    };
    let [lo, hi] = iv(&c);
    assert!(
        140.0 < lo && lo <= 150.0 && hi < 175.0,
        "c in [{lo}, {hi}]: {c}"
    );
    // Each end is a run: below it the start from rest squeals, above it it ends quiet. Steady
    // slip repels at this brake (k = (1 - 2/pi) tau / lambda = 1.1355 > 1, crates/core/MODEL.md
    // section 5): quiet is the slip oscillation about it, which never sticks (measured here,
    // 2026-12-07: half-range 1.16e-6 m at 122.6 Hz, certified with multiplier -0.594 at dt and
    // -0.591 at dt/2; c in [149.8, 159.5] N s/m). Before fates by attractor, "settles" meant
    // coming within fp_radius of the point.
    assert_eq!(c["below"]["fates"][0]["fate"], "lasts", "{c}");
    assert_eq!(c["steady_slip"]["stability"], "repels", "{c}");
    assert_eq!(c["above"]["fates"][0]["fate"], "slip_oscillation", "{c}");
    let half = c["slip_oscillation_above"]["half_range_x_m"]
        .as_f64()
        .unwrap();
    assert!(half > 0.0 && half < 1e-5, "a small oscillation: {c}");
    let f = brake_critical(&["--fold", "--horizon", "3000"]);
    assert_eq!(f["by"], "runs", "{f}");
    let [flo, fhi] = iv(&f);
    assert!(
        flo >= lo - 1.0 && fhi >= hi && fhi < 180.0,
        "fold [{flo}, {fhi}], critical [{lo}, {hi}]"
    );
}

/// A scan's file says which attractor each cell reached. At the clamped
/// brake with c = 100 N s/m (a 4 x 4 grid around the fixed point) the runs that squeal are
/// on the lasting oscillation of crates/core/MODEL.md section 13: it sticks and overtakes
/// the disc, at about 247 Hz with x' within +-0.403 m/s (the one-point atlas's note; the
/// README's run at c = 20 swings within -0.43 and +0.42 m/s). Before, the file had no
/// `sticks`, `reverses`, `x_amplitude` or `v_amplitude`.
#[test]
fn a_brake_scan_stores_the_attractor_each_cell_reached() {
    let dir = tempfile::tempdir().unwrap();
    let spec = r#"
version = 1
name = "pad"
[model]
law = "mcmillan"
[physical]
m = 0.8
k = 2.0e5
c = 100.0
v_belt = 0.3
mu_k = 0.38
mu_s = 0.48
tau = 5e-4
normal_force = 1500.0
[grid]
x0 = { min = -2e-3, max = 6e-3, count = 4 }
v0 = { min = -0.5, max = 0.5, count = 4 }
[output]
path = "pad.h5"
"#;
    std::fs::write(dir.path().join("pad.toml"), spec).unwrap();
    let (ok, out) = run(dir.path(), &["scan", "pad.toml", "--quiet"]);
    assert!(ok, "{out}");
    let f = hdf5::File::open(dir.path().join("pad.h5")).unwrap();
    let u8s = |k: &str| f.dataset(k).unwrap().read_raw::<u8>().unwrap();
    let f64s = |k: &str| f.dataset(k).unwrap().read_raw::<f64>().unwrap();
    let attr = |k: &str| -> f64 { f.attr(k).unwrap().read_scalar().unwrap() };
    let (labels, sticks, reverses) = (u8s("labels"), u8s("sticks"), u8s("reverses"));
    let (omega, v_amp) = (f64s("omega"), f64s("v_amplitude"));
    let (time, velocity) = (attr("time_unit"), attr("velocity_unit"));
    let mut squealing = 0;
    for i in 0..labels.len() {
        // stick_slip = 2, steady_slip = 1 (the labels' flag_values).
        if labels[i] == 2 && sticks[i] != 255 {
            squealing += 1;
            assert_eq!((sticks[i], reverses[i]), (1, 1), "cell {i}");
            let hz = omega[i] / (2.0 * std::f64::consts::PI * time);
            assert!((220.0..280.0).contains(&hz), "cell {i}: {hz} Hz");
            let v = v_amp[i] * velocity;
            assert!((0.35..0.45).contains(&v), "cell {i}: +-{v} m/s");
        } else if labels[i] == 1 {
            assert_eq!(sticks[i], 255, "cell {i}: steady slip has no oscillation");
            assert!(v_amp[i].is_nan(), "cell {i}");
        }
    }
    assert!(squealing >= 8, "{squealing} of 16 cells on the oscillation");
}

/// README's brake swept over two dashpots, on a 2 x 2 grid in metres and m/s.
const BRAKE_SWEEP: &str = r#"
version = 1
name = "brake-sweep"
[model]
law = "mcmillan"
[physical]
m = 2.0
k = 5.0e4
c = [0.5, 4.0]
v_belt = 0.05
mu_k = 0.35
mu_s = 0.45
tau = 1e-3
[grid]
x0 = { min = -2e-4, max = 4e-4, count = 2 }
v0 = { min = -0.05, max = 0.05, count = 2 }
[output]
path = "sweep.h5"
"#;

/// A physical scan's file carries its coordinates in SI units beside the
/// nondimensional ones, as CF auxiliary coordinates (`x0_si` in m, `v0_si` in m/s, the
/// swept `c` in N s/m over `nu`, named in each variable's `coordinates`), and the cells'
/// times, frequencies and amplitudes as `<name>_si`. Before, the Dataset of a physical
/// scan had x0, v0 and nu in the model's units only. A nondimensional scan's file is
/// unchanged: no `_si` dataset, no `coordinates` attribute.
#[test]
fn a_physical_scan_stores_its_coordinates_in_si_units() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("sweep.toml"), BRAKE_SWEEP).unwrap();
    let (ok, out) = run(dir.path(), &["scan", "sweep.toml", "--quiet"]);
    assert!(ok, "{out}");
    let f = hdf5::File::open(dir.path().join("sweep.h5")).unwrap();
    let f64s = |k: &str| -> Vec<f64> {
        let ds = f.dataset(k).unwrap_or_else(|e| panic!("dataset {k}: {e}"));
        ds.read_raw().unwrap()
    };
    let text = |ds: &str, k: &str| -> String {
        let a = f.dataset(ds).unwrap().attr(k);
        let a = a.unwrap_or_else(|e| panic!("{ds}.{k}: {e}"));
        let v: hdf5::types::VarLenUnicode = a.read_scalar().unwrap();
        v.as_str().to_string()
    };
    // The grid as the spec gives it, in metres and m/s (to rounding of the scaling).
    let close = |a: &[f64], b: &[f64]| {
        a.len() == b.len()
            && a.iter()
                .zip(b)
                .all(|(x, y)| (x - y).abs() <= 1e-12 * y.abs())
    };
    assert!(close(&f64s("x0_si"), &[-2e-4, 4e-4]), "{:?}", f64s("x0_si"));
    assert!(close(&f64s("v0_si"), &[-0.05, 0.05]), "{:?}", f64s("v0_si"));
    assert!(close(&f64s("c"), &[0.5, 4.0]), "{:?}", f64s("c"));
    for (ds, units) in [("x0_si", "m"), ("v0_si", "m/s"), ("c", "N s/m")] {
        assert_eq!(text(ds, "units"), units, "{ds}");
        assert!(!text(ds, "long_name").is_empty(), "{ds}");
    }
    // Each cell variable names them; the per-map ones the swept c.
    assert_eq!(text("labels", "coordinates"), "x0_si v0_si c");
    assert_eq!(text("t_squeal_si", "coordinates"), "x0_si v0_si c");
    assert_eq!(text("basin_stability_steady_slip", "coordinates"), "c");
    // The cells' figures in SI: x_amplitude in m, omega in Hz, t_decision in s.
    let attr = |k: &str| -> f64 { f.attr(k).unwrap().read_scalar().unwrap() };
    let (length, time) = (attr("length_unit"), attr("time_unit"));
    let (xa, xa_si) = (f64s("x_amplitude"), f64s("x_amplitude_si"));
    let (td, td_si) = (f64s("t_decision"), f64s("t_decision_si"));
    for i in 0..xa.len() {
        assert!(xa_si[i].is_nan() && xa[i].is_nan() || xa_si[i] == xa[i] * length);
        assert_eq!(td_si[i], td[i] * time, "cell {i}");
    }
    assert_eq!(text("x_amplitude_si", "units"), "m");
    assert_eq!(text("omega_si", "units"), "Hz");
    assert_eq!(text("t_squeal_si", "units"), "s");

    // The same brake in the model's units (nu, lambda, tau, phi as the sweep's first map
    // stores them): no SI dataset, no coordinates attribute.
    let nd = format!(
        "version = 1\n[model]\nlaw = \"mcmillan\"\nnu = {}\nlambda = {}\ntau = {}\nphi = {}\n\
         [grid]\nx0 = {{ min = -1, max = 2, count = 2 }}\nv0 = {{ min = -2, max = 2, count = 2 }}\n\
         [output]\npath = \"nd.h5\"\n",
        f64s("nu")[0],
        attr("lambda"),
        attr("tau"),
        attr("phi")
    );
    std::fs::write(dir.path().join("nd.toml"), nd).unwrap();
    let (ok, out) = run(dir.path(), &["scan", "nd.toml", "--quiet"]);
    assert!(ok, "{out}");
    let g = hdf5::File::open(dir.path().join("nd.h5")).unwrap();
    let names = g.member_names().unwrap();
    assert!(!names.iter().any(|n| n.ends_with("_si")), "{names:?}");
    for n in names {
        if let Ok(ds) = g.dataset(&n) {
            let attrs = ds.attr_names().unwrap();
            assert!(!attrs.iter().any(|a| a == "coordinates"), "{n}: {attrs:?}");
        }
    }
}

/// A trajectory's file says what the squeal is, in SI for a physical
/// system. The pad clamped with 1.5 kN at c = 100 N s/m, from rest to t = 3000: the run
/// ends on the lasting oscillation at about 247 Hz, x' within -0.43..+0.37 m/s (`squeal
/// trajectory ... --c 100 --t-end 3000`: "lasting_frequency_hz":246.9,
/// "lasting_v_range_m_per_s":[-0.434,0.372]). Before, the file had no lasting_* figures.
#[test]
fn a_brake_trajectory_file_stores_its_squeal_in_si_units() {
    let dir = tempfile::tempdir().unwrap();
    let mut args = vec!["trajectory"];
    args.extend(PAD);
    args.extend([
        "--c",
        "100",
        "--normal-force",
        "1500",
        "--t-end",
        "3000",
        "--every",
        "1000",
        "--out",
        "pad.h5",
    ]);
    let (ok, out) = run(dir.path(), &args);
    assert!(ok, "{out}");
    let f = hdf5::File::open(dir.path().join("pad.h5")).unwrap();
    let attr = |k: &str| -> f64 { f.attr(k).unwrap().read_scalar().unwrap() };
    let units = |k: &str| -> String {
        f.attr(&format!("{k}_units"))
            .unwrap()
            .read_scalar::<hdf5::types::VarLenUnicode>()
            .unwrap()
            .to_string()
    };
    let hz = attr("lasting_omega_si");
    assert!((240.0..255.0).contains(&hz), "{hz} Hz");
    assert_eq!(units("lasting_omega_si"), "Hz");
    // omega / (2 pi) in cycles per model time unit, over the time unit in seconds.
    let from_model = attr("lasting_omega") / (2.0 * std::f64::consts::PI * attr("time_unit"));
    assert!((hz - from_model).abs() < 1e-9 * hz, "{hz} vs {from_model}");
    let (v_lo, v_hi) = (attr("lasting_v_min_si"), attr("lasting_v_max_si"));
    assert!(
        (-0.47..-0.40).contains(&v_lo) && (0.33..0.41).contains(&v_hi),
        "{v_lo} {v_hi}"
    );
    assert_eq!(units("lasting_v_max_si"), "m/s");
    let (x_lo, x_hi) = (attr("lasting_x_min_si"), attr("lasting_x_max_si"));
    // About 1.79 and 2.21 mm, around the fixed point x* = mu_k N / k = 2.85 mm.
    assert!(
        1.5e-3 < x_lo && x_lo < x_hi && x_hi < 2.85e-3,
        "{x_lo} {x_hi}"
    );
    assert_eq!(units("lasting_x_min_si"), "m");
}
