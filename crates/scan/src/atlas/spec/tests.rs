use super::*;
use crate::spec::EarlyStop;
use squeal_core::{FrictionLaw, Load};

/// docs/atlas-spec.md states the range of `[attractor] transient` and `window`, the one
/// the parser holds (not only the default): both ends taken, one past
/// either refused naming the key.
#[test]
fn the_attractor_counts_are_documented_with_their_range() {
    let doc = include_str!("../../../../../docs/atlas-spec.md");
    let range = &parse::ATTRACTOR_REVOLUTIONS;
    let words = format!("`{}..={}`", range.start(), range.end());
    for key in ["transient", "window"] {
        let row = doc
            .lines()
            .find(|l| l.starts_with(&format!("| `{key}` |")))
            .unwrap_or_else(|| panic!("no row for {key}"));
        assert!(row.contains(&words), "{row}");
        let spec = |v: i64| format!("{GOOD}[attractor]\n{key} = {v}\n");
        for v in [*range.start(), *range.end()] {
            AtlasPlan::from_toml(&spec(v), "a.toml").unwrap();
        }
        for v in [range.start() - 1, range.end() + 1] {
            let e = AtlasPlan::from_toml(&spec(v), "a.toml")
                .unwrap_err()
                .to_string();
            assert!(e.contains(&format!("attractor.{key}")), "{e}");
        }
    }
}

/// `m = k = 1e200, c = [1e200, 2e200]` is `m = k = 1, c = [1, 2]` scaled:
/// nu = 0.5 and 1 at both (it stored `nondim_nu = [0, 0]`: 2 sqrt(m k) overflowed).
#[test]
fn a_huge_physical_system_has_the_nondimensional_numbers_of_its_scaled_one() {
    let nus = |scale: &str| {
        let text = PHYS
            .replace("m = 1.0", &format!("m = 1{scale}"))
            .replace("k = 1.0e4", &format!("k = 1{scale}"))
            .replace("c = [2.0, 4.0]", &format!("c = [1{scale}, 2{scale}]"));
        let p = AtlasPlan::from_toml(&text, "p.toml").unwrap();
        (0..p.space.n_points())
            .map(|i| p.space.params_at(i).nu)
            .collect::<Vec<_>>()
    };
    let (one, big) = (nus(".0"), nus("e200"));
    assert_eq!(one, [0.5, 1.0]);
    for (a, b) in one.iter().zip(&big) {
        assert!((a - b).abs() <= 4.0 * f64::EPSILON, "{one:?} vs {big:?}");
    }
}

const GOOD: &str = r#"
version = 1
[model]
law = "mcmillan"
nu = { from = 1e-3, to = 4e-2, count = 3, spacing = "log" }
lambda = [2.0, 3.0]
[output]
path = "a.h5"
"#;

const PHYS: &str = r#"
version = 1
[model]
law = "mcmillan"
[physical]
m = 1.0
k = 1.0e4
c = [2.0, 4.0]
v_belt = 0.1
mu_k = 0.3
mu_s = 0.4
tau = 3e-3
[output]
path = "p.h5"
"#;

fn err(text: &str) -> String {
    AtlasPlan::from_toml(text, "t.toml")
        .unwrap_err()
        .to_string()
}

#[test]
fn cartesian_product_in_c_order() {
    let p = AtlasPlan::from_toml(GOOD, "t.toml").unwrap();
    assert_eq!(p.space.shape(), vec![3, 2]);
    assert_eq!(p.space.n_points(), 6);
    // Point 3 = (nu index 1, lambda index 1).
    let q = p.space.params_at(3);
    assert!((q.nu - (1e-3f64 * 4e-2).sqrt()).abs() < 1e-15);
    assert_eq!(q.lambda, 3.0);
    assert_eq!(q.law.surface().unwrap().tau, squeal_core::defaults::TAU);
    // Boundaries over lambda, bisected over nu's range.
    assert_eq!(p.boundary_shape(), vec![2]);
    let (i, r) = p.boundary_setup(1);
    assert_eq!(p.space.params_at(i).lambda, 3.0);
    assert!((r[0] - 1e-3).abs() < 1e-15 && (r[1] - 4e-2).abs() < 1e-15);
}

/// A Coulomb system has no mu_s and tau (its force has neither): its axes are the
/// other six, mu_s or tau given is refused by name (before, both were required and then
/// ignored), and an old file's spec with them still reads back.
#[test]
fn a_coulomb_atlas_has_no_surface_axes() {
    let coulomb = PHYS
        .replace("\"mcmillan\"", "\"coulomb\"")
        .replace("mu_s = 0.4\ntau = 3e-3\n", "");
    let p = AtlasPlan::from_toml(&coulomb, "c.toml").unwrap();
    let keys: Vec<&str> = p.space.params.iter().map(|a| a.key).collect();
    assert_eq!(keys, ["m", "k", "c", "v_belt", "mu_k", "g"]);
    assert_eq!(p.space.physical_at(0).unwrap().friction.surface(), None);
    // nu = c / (2 sqrt(m k)) = 2 / 200, as under McMillan's law (physical_spec_converts).
    assert!((p.space.params_at(0).nu - 0.01).abs() < 1e-15);
    let old = coulomb.replace("mu_k = 0.3", "mu_k = 0.3\ntau = 3e-3");
    let e = err(&old);
    assert!(
        e.contains("`physical.tau`") && e.contains("\"coulomb\""),
        "{e}"
    );
    let stored = AtlasPlan::from_stored_toml(&old, "c.toml").unwrap();
    assert_eq!(stored.differs_from(&p), None);
}

#[test]
fn physical_spec_converts() {
    let p = AtlasPlan::from_toml(PHYS, "p.toml").unwrap();
    assert_eq!(p.space.units, Units::Physical);
    assert_eq!(p.space.shape(), vec![2]);
    // nu = c / (2 sqrt(m k)) = 2 / 200.
    assert!((p.space.params_at(0).nu - 0.01).abs() < 1e-15);
    assert_eq!(p.damping_axis(), ("c", Some(0)));
    assert_eq!(p.n_boundaries(), 1);
    // Its points' notes speak SI: the settings carry the point's scales.
    let scales = p.space.physical_at(1).unwrap().scales();
    assert_eq!(p.settings_at(1).units, Some(scales));
    assert!(p.settings_at(1).time_words(2.0, 1).ends_with(" s"));
}

/// `normal_force` is an axis of its own (in N) where `g` was: swept, each point's
/// system is pressed by its force (friction mu N, so lambda = v_B sqrt(m k) / (mu_k N));
/// with `g` beside it, or bisecting in lambda while it is swept, refused by name.
#[test]
fn a_physical_atlas_takes_the_normal_force() {
    let text = PHYS
        .replace("c = [2.0, 4.0]", "c = 2.0")
        .replace("tau = 3e-3", "tau = 3e-3\nnormal_force = [10.0, 20.0]");
    let p = AtlasPlan::from_toml(&text, "p.toml").unwrap();
    let keys: Vec<_> = p.space.params.iter().map(|a| (a.key, a.units)).collect();
    assert_eq!(keys.last(), Some(&("normal_force", "N")));
    assert!(!keys.iter().any(|(k, _)| *k == "g"), "{keys:?}");
    assert_eq!(p.space.shape(), vec![2]);
    for (i, n) in [10.0, 20.0].into_iter().enumerate() {
        let ph = p.space.physical_at(i).unwrap();
        assert_eq!(ph.load, Load::NormalForce(n));
        // lambda = v_B sqrt(m k) / (mu_k N) = 0.1 * 100 / (0.3 N).
        assert!((p.space.params_at(i).lambda - 10.0 / (0.3 * n)).abs() < 1e-13);
    }
    let both = text.replace("tau = 3e-3", "tau = 3e-3\ng = 9.81");
    assert!(
        err(&both).contains("`physical.normal_force`"),
        "{}",
        err(&both)
    );
    let in_lambda = text.replace("[output]", "[boundaries]\nin = \"lambda\"\n[output]");
    let e = err(&in_lambda);
    assert!(e.contains("normal_force is swept too"), "{e}");
}

#[test]
fn physical_default_disturbance_scales_with_the_system() {
    // Were the default box [-2, 4] x [-3, 3] taken as metres and m/s, a brake's basin
    // fraction would come out 1.5e-8. Without [disturbance] it stays
    // nondimensional at each point; a [disturbance] in SI is converted.
    let p = AtlasPlan::from_toml(PHYS, "p.toml").unwrap();
    assert!(p.disturbance_nondimensional);
    let d = p.settings_at(0).disturbance;
    assert_eq!(d, PointSettings::default().disturbance);
    assert_eq!(p.disturbance_units()[0].split(' ').next(), Some("1"));
    let given = PHYS.replace(
        "[output]",
        "[disturbance]\nx = [-1e-3, 1e-3]\nv = [-0.05, 0.05]\n[output]",
    );
    let p = AtlasPlan::from_toml(&given, "p.toml").unwrap();
    let s = p.space.physical_at(0).unwrap().scales();
    let d = p.settings_at(0).disturbance;
    assert!((d.x[1] * s.length - 1e-3).abs() < 1e-15);
    assert!((d.v[0] * s.velocity + 0.05).abs() < 1e-15);
    assert_eq!(p.disturbance_units(), ["m", "m/s"]);
}

/// `info` labelled a measured curve's default box "in units of mu_k g / omega_0^2", but the
/// table law has no mu_k: it is written in the normal force, one length unit N / k and one
/// velocity unit N / sqrt(m k) (crates/core/MODEL.md section 8; scans/brake-curve.toml:
/// 1500 N / sqrt(0.8 * 2e5) = 3.75 m/s). The laws with mu_k keep it in theirs.
#[test]
fn a_measured_curves_default_box_is_labelled_in_its_own_units() {
    let spec = "version = 1\nname = \"t\"\n[model]\nlaw = \"table\"\n[physical]\nm = 0.8\n\
                k = 2.0e5\nc = { from = 10.0, to = 400.0, count = 3, spacing = \"log\" }\n\
                v_belt = 0.3\nnormal_force = 1500.0\n\
                friction_table = [[0.0, 0.6], [0.1, 0.5], [1.0, 0.45]]\n\
                [output]\npath = \"t.h5\"\n";
    let p = AtlasPlan::from_toml(spec, "t.toml").unwrap();
    let [x, v] = p.disturbance_units();
    assert!(x.contains("units of N / k") && !x.contains("mu_k"), "{x}");
    assert!(
        v.contains("units of N / sqrt(m k)") && !v.contains("mu_k"),
        "{v}"
    );
    let s = p.space.physical_at(0).unwrap().scales();
    assert!((s.velocity - 3.75).abs() < 1e-12, "{}", s.velocity);
    let [x, v] = AtlasPlan::from_toml(PHYS, "p.toml")
        .unwrap()
        .disturbance_units();
    assert!(x.contains("units of mu_k N / k") && v.contains("mu_k N / sqrt(m k)"));
}

#[test]
fn bad_specs_name_the_key() {
    let cases: Vec<(String, &str)> = vec![
        (
            GOOD.replace("lambda = [2.0, 3.0]", "lambda = []"),
            "model.lambda",
        ),
        (GOOD.replace("count = 3", "count = 0"), "model.nu.count"),
        (
            GOOD.replace("lambda = [2.0, 3.0]", "lambda = [2.0, 3.0]\nfoo = 1"),
            "foo",
        ),
        (
            GOOD.replace("lambda = [2.0, 3.0]", "lambda = [2.0, -3.0]"),
            "model.lambda",
        ),
        (
            GOOD.replace("lambda = [2.0, 3.0]", "lambda = [3.0, 2.0, 3.0]"),
            "model.lambda",
        ),
        (PHYS.replace("m = 1.0", "m = -1.0"), "physical.m"),
        (PHYS.replace("k = 1.0e4", "k = -1.0e4"), "physical.k"),
        (PHYS.replace("mu_s = 0.4", "mu_s = 0.3"), "physical.mu_s"),
        (
            PHYS.replace("[physical]", "nu = 0.01\n[physical]"),
            "model.nu",
        ),
        (PHYS.replace("tau = 3e-3", "tau = 3e-3\nmass = 2"), "mass"),
        (
            GOOD.replace("[output]", "[cycle]\nrtol = 0.0\n[output]"),
            "cycle.rtol",
        ),
        // One coarse step cannot see a second change of regime.
        (
            GOOD.replace("[output]", "[boundaries]\ncoarse = 1\n[output]"),
            "boundaries.coarse",
        ),
        // Lifetimes: a count, above the crisis of the hysteretic law's fold in nu.
        (
            GOOD.replace("[output]", "[boundaries]\nlifetime_starts = -1\n[output]"),
            "boundaries.lifetime_starts",
        ),
        (
            GOOD.replace("[output]", "[boundaries]\nlifetime_starts = 5000\n[output]"),
            "boundaries.lifetime_starts",
        ),
        (
            GOOD.replace(
                "[output]",
                "[boundaries]\nlifetime_starts = 8\nfold = false\n[output]",
            ),
            "boundaries.lifetime_starts",
        ),
        (
            GOOD.replace(
                "[output]",
                "[boundaries]\nlifetime_starts = 8\nin = \"lambda\"\n[output]",
            ),
            "boundaries.lifetime_starts",
        ),
        (
            STRIBECK.replace("[output]", "[boundaries]\nlifetime_starts = 8\n[output]"),
            "boundaries.lifetime_starts",
        ),
        (
            GOOD.replace(
                "[output]",
                "[disturbance]\nx = [1.0, 0.0]\nv = [0.0, 1.0]\n[output]",
            ),
            "disturbance.x",
        ),
    ];
    for (text, key) in cases {
        let e = err(&text);
        assert!(e.contains(key), "expected `{key}` in: {e}");
    }
}

const STRIBECK: &str = r#"
version = 1
[model]
law = "stribeck"
xi = [0.02, 0.05]
v_d = { from = 1.0, to = 2.2, count = 4 }
[output]
path = "s.h5"
"#;

#[test]
fn a_stribeck_spec_has_its_own_axes_and_defaults() {
    let p = AtlasPlan::from_toml(STRIBECK, "s.toml").unwrap();
    let keys: Vec<&str> = p.space.params.iter().map(|a| a.key).collect();
    assert_eq!(keys, FrictionLaw::Stribeck.keys());
    assert_eq!(p.space.shape(), vec![2, 4]);
    // Point 5 = (xi index 1, v_d index 1); the fixed keys at bSTAB's case.
    let q = p.space.params_at(5);
    assert_eq!((q.nu, q.lambda), (0.05, 1.4));
    assert_eq!(q.law.stribeck(), Some(squeal_core::Stribeck::default()));
    assert_eq!(p.damping_axis(), ("xi", Some(0)));
    // Boundaries in xi by default (xi is swept), over v_d; in v_d on request.
    assert_eq!(p.boundary_axis(), ("xi", Some(0)));
    assert_eq!(
        p.boundary_dataset("fold_nu_lo", "x").0,
        "fold_xi_lo".to_string()
    );
    // A long name citing other datasets cites them by their names in this file (the
    // long name of fold_xi_err said "fold_nu -+ fold_nu_err").
    let err = crate::atlas::columns::BOUNDARY_COLUMNS
        .iter()
        .find(|c| c.name == "fold_nu_err")
        .unwrap();
    let (name, long) = p.boundary_dataset(err.name, err.long_name);
    assert_eq!(name, "fold_xi_err");
    assert!(
        long.contains("fold_xi -+ fold_xi_err") && !long.contains("_nu"),
        "{long}"
    );
    let v = AtlasPlan::from_toml(
        &STRIBECK.replace("[output]", "[boundaries]\nin = \"v_d\"\n[output]"),
        "s.toml",
    )
    .unwrap();
    assert_eq!(v.boundary_axis(), ("v_d", Some(1)));
    let (name, long) = v.boundary_dataset(
        "critical_nu",
        "critical damping ratio: the operating point stops squealing above it",
    );
    assert_eq!(name, "critical_v_d");
    assert!(long.starts_with("critical belt speed v_d"), "{long}");
    assert_eq!(v.boundary_words(), "belt speed v_d");
    // Unset keys take the scan spec's defaults (the law's own: crates/core/src/law/).
    let d = AtlasPlan::from_toml(&STRIBECK.replace("xi = [0.02, 0.05]\n", ""), "s.toml")
        .unwrap()
        .space
        .params_at(0);
    assert_eq!(d.nu, squeal_core::Stribeck::XI);
}

#[test]
fn bad_stribeck_specs_name_the_key() {
    let with = |k: &str| STRIBECK.replace("[output]", &format!("{k}\n[output]"));
    let model = |k: &str| STRIBECK.replace("xi = [0.02, 0.05]", &format!("xi = [0.02, 0.05]\n{k}"));
    let cases: Vec<(String, &str)> = vec![
        (model("nu = 0.01"), "model.nu"),
        (model("lambda = 3.0"), "model.lambda"),
        (model("tau = 0.3"), "model.tau"),
        (model("phi = 1.0"), "model.phi"),
        (
            GOOD.replace("lambda = [2.0, 3.0]", "lambda = [2.0, 3.0]\nxi = 0.1"),
            "model.xi",
        ),
        (
            GOOD.replace("lambda = [2.0, 3.0]", "lambda = [2.0, 3.0]\nmu_sd = 2.0"),
            "model.mu_sd",
        ),
        (model("mu_sd = 0.5"), "model.mu_sd"),
        (model("v_0 = 0.0"), "model.v_0"),
        (model("v_0 = -1.0"), "model.v_0"),
        (
            STRIBECK.replace("xi = [0.02, 0.05]", "xi = [-0.1, 0.05]"),
            "model.xi",
        ),
        (
            STRIBECK.replace("count = 4", "count = 0"),
            "model.v_d.count",
        ),
        (model("mu_d = 0.0"), "model.mu_d"),
        (model("mu_v = -1.0"), "model.mu_v"),
        (
            with(
                "[physical]\nm = 1.0\nk = 1.0\nc = 1.0\nv_belt = 1.0\nmu_k = 0.3\nmu_s = 0.4\ntau = 1.0",
            ),
            "physical",
        ),
        (with("[boundaries]\nin = \"nu\""), "boundaries.in"),
        (with("[boundaries]\nnu_lo = 0.01"), "boundaries.nu_lo"),
        (
            with("[boundaries]\nxi_lo = 0.5\nxi_hi = 0.1"),
            "boundaries.xi_lo",
        ),
        (
            GOOD.replace("[output]", "[boundaries]\nv_d_hi = 3.0\n[output]"),
            "boundaries.v_d_hi",
        ),
        (
            GOOD.replace("[output]", "[boundaries]\nin = \"xi\"\n[output]"),
            "boundaries.in",
        ),
    ];
    for (text, key) in cases {
        let e = err(&text);
        assert!(e.contains(key), "expected `{key}` in: {e}");
    }
}

const GRID: &str = "[grid]\nx0 = { min = -2.0, max = 4.0, count = 8 }\nv0 = { min = -3.0, max = 3.0, count = 6 }\n[output]";

#[test]
fn a_grid_makes_maps_with_the_scan_rules() {
    let p = AtlasPlan::from_toml(&GOOD.replace("[output]", GRID), "t.toml").unwrap();
    let m = p.maps.unwrap();
    assert_eq!(
        (m.grid.x0.count, m.grid.v0.count, m.grid.block_rows),
        (8, 6, 8)
    );
    // The box the cells tile is the disturbance box: half a spacing (6/7 in x, 6/5 in
    // v) beyond the first and last grid values.
    assert_eq!(p.point.disturbance.x, [-2.0 - 3.0 / 7.0, 4.0 + 3.0 / 7.0]);
    assert_eq!(p.point.disturbance.v, [-3.0 - 0.6, 3.0 + 0.6]);
    let mp = p.map_plan().unwrap();
    assert_eq!(mp.maps.len(), p.space.n_points());
    assert_eq!(mp.maps[3], p.space.params_at(3));
    assert_eq!(mp.map.early_stop, EarlyStop::Cycle);
    assert!(
        AtlasPlan::from_toml(GOOD, "t.toml")
            .unwrap()
            .map_plan()
            .is_none()
    );
    // The scheme is read and kept.
    let z = AtlasPlan::from_toml(
        &GOOD.replace("[output]", "[integration]\nscheme = \"zoh\"\n[output]"),
        "t.toml",
    )
    .unwrap();
    assert_eq!(z.solver.scheme, squeal_core::Scheme::Zoh);
    assert_eq!(
        AtlasPlan::from_toml(GOOD, "t.toml").unwrap().solver.scheme,
        squeal_core::Scheme::default()
    );
}

#[test]
fn bad_grids_name_the_key() {
    let g = GOOD.replace("[output]", GRID);
    let cases: Vec<(String, &str)> = vec![
        (g.replace("count = 8 }", "count = 0 }"), "grid.x0.count"),
        (
            g.replace("min = -3.0, max = 3.0", "min = 3.0, max = -3.0"),
            "grid.v0",
        ),
        (g.replace("v0 = {", "w0 = {"), "w0"),
        (
            g.replace("[output]", "block_rows = 0\n[output]"),
            "grid.block_rows",
        ),
        (
            g.replace("[output]", "[classifier]\ntrap_margin = 0.9\n[output]"),
            "classifier.trap_margin",
        ),
        (
            GOOD.replace("[output]", "[classifier]\nt_max = 100.0\n[output]"),
            "classifier",
        ),
        (
            g.replace(
                "[grid]",
                "[disturbance]\nx = [-1.0, 1.0]\nv = [-1.0, 1.0]\n[grid]",
            ),
            "disturbance",
        ),
        // A physical grid is in m and m/s; with a swept mass the maps' units would differ.
        (
            PHYS.replace(
                "[output]",
                &format!("[boundaries]\nfold = false\ncritical = false\n{GRID}"),
            )
            .replace("m = 1.0", "m = [1.0, 2.0]"),
            "physical.m",
        ),
        (
            GOOD.replace("[output]", "[integration]\nscheme = \"rk4\"\n[output]"),
            "scheme",
        ),
    ];
    for (text, key) in cases {
        let e = err(&text);
        assert!(e.contains(key), "expected `{key}` in: {e}");
    }
}

#[test]
fn every_shipped_atlas_spec_validates() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scans");
    let mut n = 0;
    for e in std::fs::read_dir(&dir).unwrap() {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().into_owned();
        if !name.ends_with(".toml") {
            continue;
        }
        // atlas-*.toml, or a spec without [grid] and [sample] (a scan needs one of them).
        let t: toml::Table = toml::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap();
        if name.starts_with("atlas-") || !t.contains_key("grid") && !t.contains_key("sample") {
            let plan = AtlasPlan::from_file(&p).unwrap_or_else(|e| panic!("{name}: {e}"));
            // Read back from a file, the spec is the same plan (the stored reading is the
            // checked one with today's bounds left out).
            let stored = AtlasPlan::from_stored_toml(&plan.spec_text, &plan.spec_path).unwrap();
            assert_eq!(stored.differs_from(&plan), None, "{name}");
            n += 1;
        }
    }
    assert!(n >= 2, "expected the shipped atlas specs in scans/");
}

/// An atlas file's stored spec describes what was run: values a squeal of today refuses
/// (each outside a bound of parse.rs, classifier.rs or tables.rs) read back as stored,
/// where before the file was refused with the bound's error; given to run, the same spec
/// is refused naming the key.
#[test]
fn a_stored_atlas_spec_outside_todays_bounds_reads_as_stored() {
    let with = |table: &str| GOOD.replace("[output]", &format!("{table}\n[output]"));
    let g = GOOD.replace("[output]", GRID);
    let cases = [
        // coarse below 2, rtol at or above 0.5, lifetime_starts above 4096.
        (with("[boundaries]\ncoarse = 1"), "boundaries.coarse"),
        (with("[boundaries]\nrtol = 0.7"), "boundaries.rtol"),
        (
            with("[boundaries]\nlifetime_starts = 5000"),
            "boundaries.lifetime_starts",
        ),
        // Below 4 revolutions; beyond the escape radius 1e6; cycle rtol outside (0, 0.1).
        (with("[attractor]\ntransient = 2"), "attractor.transient"),
        (with("[operating_point]\nx = 2e6"), "operating_point.x"),
        (with("[cycle]\nrtol = 0.5"), "cycle.rtol"),
        // A map's classifier: trap_margin above 0.5, t_max / dt = 1e12 / 0.005 above 1e10.
        (
            g.replace("[output]", "[classifier]\ntrap_margin = 0.9\n[output]"),
            "classifier.trap_margin",
        ),
        (
            g.replace("[output]", "[classifier]\nt_max = 1e12\n[output]"),
            "classifier.t_max",
        ),
        // Phi above pi/2 at one point of the sweep.
        (
            GOOD.replace(
                "lambda = [2.0, 3.0]",
                "lambda = [2.0, 3.0]\nphi = [1.0, 2.0]",
            ),
            "model.phi",
        ),
    ];
    for (text, key) in &cases {
        assert!(err(text).contains(key), "{key}: {}", err(text));
        AtlasPlan::from_stored_toml(text, "a.toml").unwrap_or_else(|e| panic!("{key}: {e}"));
    }
    let stored = |i: usize| AtlasPlan::from_stored_toml(&cases[i].0, "a.toml").unwrap();
    assert_eq!(stored(0).boundary_coarse, 1);
    assert_eq!(stored(1).boundary_rtol, 0.7);
    assert_eq!(stored(2).lifetime_starts, 5000);
    assert_eq!(stored(3).point.transient, 2);
    assert_eq!(stored(4).point.operating.x, 2e6);
    assert_eq!(stored(5).point.cycle.rtol, 0.5);
    assert_eq!(stored(6).maps.unwrap().trap_margin, 0.9);
    assert_eq!(stored(7).maps.unwrap().classifier.t_max, 1e12);
    let phi = stored(8)
        .space
        .params
        .iter()
        .find(|a| a.key == "phi")
        .unwrap()
        .values
        .clone();
    assert_eq!(phi, [1.0, 2.0]);
    // What the plan cannot be built without is still refused, as the file's: a range of
    // no values, a map grid of one column (its cells tile no box).
    for (text, key) in [
        (GOOD.replace("count = 3", "count = 0"), "model.nu.count"),
        (g.replace("count = 8 }", "count = 1 }"), "grid.x0.count"),
    ] {
        let e = AtlasPlan::from_stored_toml(&text, "a.toml")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("a.toml: this file's stored spec") && e.contains(key),
            "{e}"
        );
    }
}

/// One parameter space: a scan spec and an atlas spec with the same `[physical]` (or
/// `[model]`) table read the same points, in the same order, with the same models (the
/// scan's maps are the atlas's points); before, each kind of spec had its own reader and a
/// scan converted its physical keys by its own scaling.
#[test]
fn a_scan_and_an_atlas_read_one_parameter_space() {
    let grid = "[grid]\nx0 = { min = -1e-4, max = 1e-4, count = 2 }\n\
                v0 = { min = -0.01, max = 0.01, count = 2 }\n[output]";
    let physical = PHYS.replace("v_belt = 0.1", "v_belt = [0.1, 0.2, 0.3]");
    for text in [
        GOOD.replace("[output]", GRID),
        physical.replace("[output]", grid),
    ] {
        let atlas = AtlasPlan::from_toml(&text, "a.toml").unwrap();
        let scan = crate::Plan::from_toml(&text, "s.toml").unwrap();
        assert_eq!(scan.maps.len(), atlas.space.n_points());
        for (i, p) in scan.maps.iter().enumerate() {
            // One conversion, bit for bit (before, the scan divided by the scales and the
            // atlas took another order of the same factors: the last bit differed).
            assert_eq!(*p, atlas.space.params_at(i), "point {i}");
        }
        assert_eq!(scan.physical(), atlas.space.physical_at(0));
        // The scan indexes its maps by the swept keys in the model's units.
        let sweep = scan.sweep.unwrap();
        let names: Vec<&str> = sweep.axes.iter().map(|a| a.name).collect();
        let swept: Vec<&str> = atlas.space.axes().iter().map(|a| a.key).collect();
        match atlas.space.units {
            Units::Nondimensional => assert_eq!(names, swept),
            Units::Physical => {
                assert_eq!((names, swept), (vec!["nu", "lambda"], vec!["c", "v_belt"]))
            }
        }
        for (m, p) in scan.maps.iter().enumerate() {
            assert_eq!(sweep.values_at(m), [p.nu, p.lambda], "map {m}");
        }
    }
}

/// A changed parameter is a changed plan: `differs_from` names the space's keys (it
/// compares the plans as TOML, where the space is flattened into the plan's table).
#[test]
fn a_changed_parameter_is_a_different_atlas() {
    let a = AtlasPlan::from_toml(GOOD, "a.toml").unwrap();
    let b = AtlasPlan::from_toml(&GOOD.replace("[2.0, 3.0]", "[2.0, 3.5]"), "a.toml").unwrap();
    assert_eq!(a.differs_from(&a.clone()), None);
    assert_eq!(a.differs_from(&b).as_deref(), Some("params"));
}
