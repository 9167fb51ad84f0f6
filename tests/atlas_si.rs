//! The atlas summary of a physical system words each boundary in both unit systems: the
//! uncertainty of the fold stands beside the value it belongs to, in nu and in N s/m.

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
