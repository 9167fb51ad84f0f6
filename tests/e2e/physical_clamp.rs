//! End-to-end tests of a clamped brake (a normal force instead of the weight): the same
//! system as g's, and a bad normal force refused by name.

use std::process::Command;

/// The disc-brake pad of the README (section 4): 0.8 kg on a 200 kN/m mount, the disc
/// at 0.3 m/s, mu_k 0.38, mu_s 0.48, tau 0.5 ms; its dashpot and load are each test's.
pub(crate) const PAD: [&str; 12] = [
    "--m", "0.8", "--k", "2e5", "--v-belt", "0.3", "--mu-k", "0.38", "--mu-s", "0.48", "--tau-s",
    "5e-4",
];

/// The pad with 20 N s/m, with the trajectory flags after `extra`.
fn pad_trajectory(dir: &std::path::Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec!["trajectory"];
    args.extend(PAD);
    args.extend(["--c", "20", "--t-end", "1"]);
    args.extend(extra);
    Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the squeal binary runs")
}

/// Friction is mu N: the pad clamped with `--normal-force 1500` is the nondimensional
/// system of the g-hack `--g 1875` (= N / m, the only way to state it before the flag), and
/// its file stores the force in newtons. Before the flag, `--normal-force` was unknown.
#[test]
fn a_clamped_brake_is_the_g_hacks_system() {
    let dir = tempfile::tempdir().unwrap();
    let mut json = Vec::new();
    let mut attrs = |extra: &[&str], out: &str| {
        let mut all = extra.to_vec();
        all.extend(["--out", out, "--json"]);
        let o = pad_trajectory(dir.path(), &all);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        json.push(serde_json::from_slice::<serde_json::Value>(&o.stdout).unwrap());
        hdf5::File::open(dir.path().join(out)).unwrap()
    };
    let num = |f: &hdf5::File, k: &str| -> f64 {
        f.attr(k)
            .unwrap_or_else(|e| panic!("attribute {k}: {e}"))
            .read_scalar()
            .unwrap()
    };
    let text = |f: &hdf5::File, k: &str| -> String {
        let v: hdf5::types::VarLenUnicode = f.attr(k).unwrap().read_scalar().unwrap();
        v.as_str().to_string()
    };
    let pad = attrs(&["--normal-force", "1500"], "pad.h5");
    let hack = attrs(&["--g", "1875"], "hack.h5");
    // `--json` gives the force with the SI figures, for both ways of stating it.
    for j in &json {
        assert_eq!(j["si"]["normal_force_n"], 1500.0, "{j}");
    }
    // Closed form (crates/core/MODEL.md, "Units"): omega_0 = sqrt(2e5 / 0.8) = 500 rad/s,
    // sqrt(m k) = 400; nu = c / (2 sqrt(m k)) = 0.025; lambda = v_B sqrt(m k) / (mu_k N)
    // = 120 / 570 = 0.2105; tau' = tau omega_0 / mu_k = 0.25 / 0.38 = 0.6579;
    // phi = arcsin(mu_k / mu_s) = arcsin(0.38 / 0.48) = 0.9135.
    let want = [
        ("nu", 0.025),
        ("lambda", 120.0 / 570.0),
        ("tau", 0.25 / 0.38),
        ("phi", (0.38f64 / 0.48).asin()),
    ];
    for (key, v) in want {
        assert_eq!(num(&pad, key), num(&hack, key), "{key}");
        assert!(
            (num(&pad, key) - v).abs() <= 1e-14,
            "{key}: {}",
            num(&pad, key)
        );
    }
    assert_eq!(num(&pad, "physical_normal_force"), 1500.0);
    assert_eq!(text(&pad, "physical_normal_force_units"), "N");
    assert!(pad.attr("physical_g").is_err(), "g plays no part");
    // The g-hack's weight m g = 0.8 * 1875 N is stored as its normal force too.
    assert_eq!(num(&hack, "physical_normal_force"), 1500.0);
    assert_eq!(num(&hack, "physical_g"), 1875.0);
    // The length unit mu_k N / k = 570 / 2e5 m.
    assert!((num(&pad, "length_unit") - 2.85e-3).abs() <= 1e-16);
    // `info --json` shows it with its units.
    let o = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(["info", "pad.h5", "--json"])
        .current_dir(dir.path())
        .output()
        .expect("the squeal binary runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let info: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let attrs = &info["attributes"];
    assert_eq!(attrs["physical_normal_force_units"], "N", "{info}");
    assert!(
        attrs["physical_normal_force"].to_string().contains("1500"),
        "{info}"
    );
}

/// A normal force <= 0, NaN or infinite is refused naming the flag, before any computing;
/// so is `--g` beside it (N replaces m g in the law).
#[test]
fn a_bad_normal_force_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    // Before the flag, each was refused as an unknown argument (clap's "unexpected
    // argument '--normal-force'"), which says nothing of the range.
    let range = "--normal-force: invalid normal_force = ";
    let both = "--normal-force: given with g, but the normal force N replaces the block's weight";
    for (bad, says) in [
        (vec!["--normal-force", "0"], range),
        (vec!["--normal-force", "-1500"], range),
        (vec!["--normal-force", "NaN"], range),
        (vec!["--normal-force", "inf"], range),
        (vec!["--normal-force", "1500", "--g", "9.81"], both),
    ] {
        let mut extra = bad.clone();
        extra.extend(["--out", "bad.h5"]);
        let o = pad_trajectory(dir.path(), &extra);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{bad:?}: {err}");
        assert!(err.contains(says), "{bad:?}: {err}");
        if says == range {
            assert!(
                err.contains("expected a finite normal force > 0 (N)"),
                "{err}"
            );
        }
        assert!(!dir.path().join("bad.h5").exists(), "{bad:?}");
    }
}
