//! What the commands give back for a physical system (SI flags or `[physical]`): the atlas
//! summary words each boundary in both unit systems (the fold's uncertainty beside the value
//! it belongs to, in nu and in N s/m), and a trajectory file says how to read its numbers
//! in SI units.

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
        .current_dir(dir.path())
        .output()
        .expect("the squeal binary runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
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
}
