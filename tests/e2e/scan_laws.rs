//! End-to-end tests of scans under the Stribeck and cubic laws: the landscape of every map
//! stated, and each law's own keys.

use crate::scan::{ok, spec, squeal};

/// bSTAB's friction case at three belt speeds, one per landscape (closed form: the fixed
/// point repels below v_d = 0.5 ln 10 = 1.151; the stick-slip cycle exists up to between
/// v_d = 1.8 and 2.0, MODEL.md section 8), on a small grid of bSTAB's region.
const STRIBECK_SWEEP: &str = r#"version = 1
[model]
law = "stribeck"
v_d = [1.0, 1.5, 2.2]
[grid]
x0 = { min = -2.0, max = 2.0, count = 4 }
v0 = { min = 0.0, max = 2.0, count = 3 }
[classifier]
t_max = 2000.0
[output]
path = "st.h5"
"#;

/// The cubic law at two belt speeds, one per landscape. Its fixed point's
/// damping is 2 xi + mu'(v_d) = 0.1 - 0.45 + 1.8 v_d^2 at the defaults (closed form): -0.188
/// at v_d = 0.3 (it repels: every start squeals) and 0.1 at v_d = 0.5, where the orbit from
/// breakaway decays (steady slip only; crates/core/tests/model/cubic.rs). The file carries the
/// law's own keys with their words, and none of another law's.
#[test]
fn cubic_scan_states_the_landscape_and_its_own_keys() {
    let d = tempfile::tempdir().unwrap();
    let text = STRIBECK_SWEEP
        .replace("law = \"stribeck\"", "law = \"cubic\"")
        .replace("v_d = [1.0, 1.5, 2.2]", "v_d = [0.3, 0.5]")
        .replace("st.h5", "cu.h5");
    spec(d.path(), "cu.toml", &text);
    let out = ok(&squeal(d.path(), &["scan", "cu.toml", "--quiet", "--json"]));
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    for (m, (want, v_d)) in [("stick_slip_only", 0.3f64), ("steady_slip_only", 0.5)]
        .into_iter()
        .enumerate()
    {
        let map = &v["maps"][m];
        assert_eq!(map["landscape"]["landscape"], want, "map {m}: {map}");
        let damping = map["landscape"]["fixed_point_damping"].as_f64().unwrap();
        assert!(
            (damping - (0.1 - 0.45 + 1.8 * v_d * v_d)).abs() < 1e-12,
            "{damping}"
        );
        assert_eq!(map["checks"]["landscape_contradictions"], 0, "map {m}");
        let regime = if m == 0 { "steady_slip" } else { "stick_slip" };
        assert_eq!(map[regime], 0, "map {m}: {map}");
    }
    let f = hdf5::File::open(d.path().join("cu.h5")).unwrap();
    let num = |k: &str| f.attr(k).unwrap().read_scalar::<f64>().unwrap();
    let text = |k: &str| {
        let s: hdf5::types::VarLenUnicode = f.attr(k).unwrap().read_scalar().unwrap();
        s.as_str().to_string()
    };
    assert_eq!(text("law"), "cubic");
    assert_eq!(
        (num("xi"), num("mu_0"), num("a1"), num("a3")),
        (0.05, 0.4, 0.45, 0.6)
    );
    assert!(text("a1_long_name").contains("mu_0 - a1 s + a3 s^3"));
    let attrs = f.attr_names().unwrap();
    for foreign in ["nu", "lambda", "tau", "phi", "mu_d", "v_0"] {
        assert!(!attrs.iter().any(|a| a == foreign), "{foreign}: {attrs:?}");
    }
}

#[test]
fn stribeck_scan_states_the_landscape_of_every_map() {
    let d = tempfile::tempdir().unwrap();
    spec(d.path(), "st.toml", STRIBECK_SWEEP);
    let out = ok(&squeal(d.path(), &["scan", "st.toml", "--quiet", "--json"]));
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let want = ["stick_slip_only", "bistable", "steady_slip_only"];
    for (m, w) in want.iter().enumerate() {
        let map = &v["maps"][m];
        assert_eq!(map["landscape"]["landscape"], *w, "map {m}: {map}");
        // Closed form of the fixed point's damping: 2 xi - e^{-v_d / v_0} (mu_d (mu_sd - 1)
        // / v_0 = 1).
        let v_d = [1.0, 1.5, 2.2f64][m];
        let damping = map["landscape"]["fixed_point_damping"].as_f64().unwrap();
        assert!(
            (damping - (0.1 - (-v_d / 0.5).exp())).abs() < 1e-12,
            "{damping}"
        );
        // The map agrees with the landscape where it states one regime (never overwritten:
        // the labels come from runs).
        let contra = map["checks"]["landscape_contradictions"].as_i64().unwrap();
        assert_eq!(contra, if m == 1 { -1 } else { 0 }, "map {m}");
        let (steady, stick) = (
            map["steady_slip"].as_u64().unwrap(),
            map["stick_slip"].as_u64().unwrap(),
        );
        match m {
            0 => assert_eq!(steady, 0),
            2 => assert_eq!(stick, 0),
            _ => {}
        }
    }
    assert!(
        v["maps"][1]["landscape"]["stick_cycle_period"]
            .as_f64()
            .unwrap()
            > 0.0
    );
    assert!(v["maps"][2]["landscape"]["stick_cycle_period"].is_null());
    // Text summary and info say it in words; the cycle notes name xi, never nu.
    let text = ok(&squeal(d.path(), &["scan", "st.toml", "--quiet"]));
    assert!(text.contains("landscape: stick_slip_only"), "{text}");
    assert!(text.contains("landscape: steady_slip_only"), "{text}");
    assert!(!text.contains("nu ="), "{text}");
    let info = ok(&squeal(d.path(), &["info", "st.h5"]));
    assert!(info.contains("landscape: bistable"), "{info}");
    assert!(!info.contains("nu ="), "{info}");
    let ij: serde_json::Value =
        serde_json::from_str(&ok(&squeal(d.path(), &["info", "st.h5", "--json"]))).unwrap();
    assert_eq!(ij["landscape"][0]["landscape"], "stick_slip_only");
    the_stribeck_file_states_its_landscapes(&d.path().join("st.h5"));
}

/// The Stribeck sweep's file `p`: its landscapes, their evidence, and the law's own names.
fn the_stribeck_file_states_its_landscapes(p: &std::path::Path) {
    // The file: an enum per map with CF flags and a long name, and its evidence.
    let f = hdf5::File::open(p).unwrap();
    let ds = f.dataset("landscape").unwrap();
    let vals: Vec<u8> = ds.read_raw().unwrap();
    assert_eq!(vals, vec![1, 2, 3]);
    let s = |ds: &hdf5::Dataset, n: &str| -> String {
        let s: hdf5::types::VarLenUnicode = ds.attr(n).unwrap().read_scalar().unwrap();
        s.as_str().to_string()
    };
    assert!(s(&ds, "long_name").contains("stick_slip_only"));
    assert!(s(&ds, "flag_meanings").contains("steady_slip_only"));
    let c: Vec<i64> = f
        .dataset("landscape_contradictions")
        .unwrap()
        .read_raw()
        .unwrap();
    assert_eq!(c, vec![0, -1, 0]);
    let period: Vec<f64> = f.dataset("stick_cycle_period").unwrap().read_raw().unwrap();
    assert!(period[1] > 0.0 && period[2].is_nan());
    // No attribute or dataset of a Stribeck file carries McMillan's damping name.
    let names = f.member_names().unwrap();
    assert!(
        !names.iter().any(|n| n == "nu" || n == "lambda"),
        "{names:?}"
    );
    for g in ["cycles/map_0000", "cycles/map_0001", "cycles/map_0002"] {
        let attrs = f.group(g).unwrap().attr_names().unwrap();
        for a in [
            "no_cycle_nu",
            "params_nu",
            "params_lambda",
            "params_stribeck_mu_d",
        ] {
            assert!(!attrs.iter().any(|x| x == a), "{g}: {attrs:?}");
        }
    }
    // The bistable map's located cycle records the law's parameters by their names.
    let attrs = f.group("cycles/map_0001").unwrap().attr_names().unwrap();
    assert!(attrs.iter().any(|x| x == "params_xi"), "{attrs:?}");
}
