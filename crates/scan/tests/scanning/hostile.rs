//! Hostile and careless specs: each case was accepted
//! and silently wrong, or unbounded, before the checks of `squeal_scan::bounds`; each is now
//! refused before any computing with a message naming the key.

use squeal_scan::Plan;
use squeal_scan::atlas::AtlasPlan;

const SCAN: &str = r#"version = 1
[model]
law = "mcmillan"
nu = 1e-3
[grid]
x0 = { min = -3.0, max = 5.0, count = 32 }
v0 = { min = -4.0, max = 4.0, count = 32 }
[output]
path = "x.h5"
"#;

const SAMPLED: &str = r#"version = 1
[model]
law = "mcmillan"
nu = 1e-3
[sample]
kind = "random"
n = 500
seed = 1
region = { x0 = [-2.0, 2.0], v0 = [0.0, 2.0] }
[output]
path = "x.h5"
"#;

const ATLAS: &str = r#"version = 1
[model]
law = "mcmillan"
nu = [1e-3, 2e-3]
[output]
path = "a.h5"
"#;

fn scan_err(text: &str) -> String {
    match Plan::from_toml(text, "t.toml") {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

fn atlas_err(text: &str) -> String {
    match AtlasPlan::from_toml(text, "t.toml") {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

/// `text` with `table` (a `[name]` line and its keys) added before `[output]`.
fn with(text: &str, table: &str) -> String {
    text.replace("[output]", &format!("{table}\n[output]"))
}

fn assert_names(e: &str, key: &str, why: &str) {
    assert!(
        e.contains(&format!("`{key}`")) && e.contains(why),
        "expected `{key}` ({why}) in: {e}"
    );
}

/// `[cycle] r_max = 1e100` was accepted ("> 2 r_min" only): the section search's
/// samples then lie too far apart to see the cycle (see `bounds::MAX_SAMPLE_RATIO`).
#[test]
fn a_cycle_search_beyond_the_escape_radius_or_too_coarse_is_refused() {
    for r_max in ["1e100", "1e300", "2e6"] {
        let e = atlas_err(&with(ATLAS, &format!("[cycle]\nr_max = {r_max}")));
        assert_names(&e, "cycle.r_max", "<= 1e6");
    }
    let e = atlas_err(&with(ATLAS, "[cycle]\nr_max = 1e6\nsamples = 20"));
    assert_names(&e, "cycle.r_max", "at most 1.25");
    AtlasPlan::from_toml(&with(ATLAS, "[cycle]\nr_max = 1e3"), "t.toml").unwrap();
}

/// `fp_radius = 10` labelled every cell of Fig. 9 steady slip.
#[test]
fn a_fixed_point_ball_as_large_as_the_cycle_is_refused() {
    for fp in ["10.0", "0.5", "0.011"] {
        let e = scan_err(&with(
            SCAN,
            &format!("[classifier]\nfp_radius = {fp}\nearly_stop = \"none\""),
        ));
        assert_names(&e, "classifier.fp_radius", "[1e-10, 0.01]");
    }
    Plan::from_toml(&with(SCAN, "[classifier]\nfp_radius = 0.01"), "t.toml").unwrap();
}

/// Huge finite bounds overflowed the grid spacing (x0 = [NaN, inf, ...]) and the
/// box area (basin fraction NaN); a huge sample region gave 500 solver failures.
#[test]
fn bounds_beyond_the_escape_radius_are_refused() {
    let e = scan_err(&SCAN.replace("min = -3.0, max = 5.0", "min = -1e308, max = 1e308"));
    assert_names(&e, "grid.x0.min", "1e6");
    let e = scan_err(&SAMPLED.replace("x0 = [-2.0, 2.0]", "x0 = [-1e308, 1e308]"));
    assert_names(&e, "sample.region.x0", "1e6");
    let grid = "[grid]\nx0 = { min = -1e308, max = 1e308, count = 4 }\nv0 = { min = -1.0, max = 1.0, count = 4 }";
    let e = atlas_err(&with(ATLAS, grid));
    assert_names(&e, "grid.x0.min", "1e6");
    let e = atlas_err(&with(ATLAS, "[disturbance]\nx = [-1e308, 1e308]"));
    assert_names(&e, "disturbance.x", "1e6");
    let e = atlas_err(&with(ATLAS, "[operating_point]\nx = 1e300"));
    assert_names(&e, "operating_point.x", "1e6");
    // At the bound itself every coordinate is finite.
    let p = Plan::from_toml(
        &SCAN.replace("min = -3.0, max = 5.0", "min = -1e6, max = 1e6"),
        "t.toml",
    )
    .unwrap();
    let g = p.map.grid;
    assert!((0..g.x0.count).all(|i| g.state(0, i).0.is_finite()));
}

/// A third list element was dropped (`[0, 1, 2]` used as `[0, 1]`).
#[test]
fn extra_list_elements_are_refused() {
    let e = scan_err(&SAMPLED.replace("x0 = [-2.0, 2.0]", "x0 = [-2.0, 2.0, 3.0]"));
    assert_names(
        &e,
        "sample.region.x0",
        "exactly two numbers [min, max] (got 3)",
    );
    let e = atlas_err(&with(ATLAS, "[disturbance]\nv = [0.0, 1.0, 2.0]"));
    assert_names(
        &e,
        "disturbance.v",
        "exactly two numbers [min, max] (got 3)",
    );
    let e = atlas_err(&with(ATLAS, "[disturbance]\nv = [1.0]"));
    assert_names(&e, "disturbance.v", "(got 1)");
}

/// An atlas `[grid]` with `count = 1` ran (docs: count >= 2), and `count = 1` with
/// `min != max` ignored `max`, in atlases and scans.
#[test]
fn single_point_axes_are_refused_where_they_mean_nothing() {
    let grid = |x0: &str| format!("[grid]\nx0 = {x0}\nv0 = {{ min = -1.0, max = 1.0, count = 4 }}");
    let e = atlas_err(&with(ATLAS, &grid("{ min = 0.5, max = 0.5, count = 1 }")));
    assert_names(&e, "grid.x0.count", "count >= 2");
    let e = atlas_err(&with(ATLAS, &grid("{ min = -1.0, max = 2.0, count = 1 }")));
    assert_names(&e, "grid.x0.count", "min = max for a single value");
    let e = scan_err(&SCAN.replace(
        "min = -3.0, max = 5.0, count = 32",
        "min = -3.0, max = 5.0, count = 1",
    ));
    assert_names(&e, "grid.x0.count", "min = max for a single value");
    // A single value stays a valid scan axis (a line of starts).
    Plan::from_toml(
        &SCAN.replace(
            "min = -3.0, max = 5.0, count = 32",
            "min = 1.0, max = 1.0, count = 1",
        ),
        "t.toml",
    )
    .unwrap();
}

/// With `tau = 1e300` a 4-row block took 20 s where the estimate said "roughly
/// 0 s" (2 / 25000 s per cell). The estimate now grows with tau, up to a run to t_max.
#[test]
fn the_estimate_of_a_slow_model_is_not_zero() {
    let slow = Plan::from_toml(
        &SCAN.replace("nu = 1e-3", "nu = 1e-3\ntau = 1e300"),
        "t.toml",
    )
    .unwrap();
    let paper = Plan::from_toml(SCAN, "t.toml").unwrap();
    let cells = slow.total_cells();
    // Run to t_max: (t_max / dt) steps at 250 ns (docs/history/benchmarks.md, "Time per step").
    let to_t_max = 5000.0 / 0.005 * 250e-9 * cells as f64;
    assert_eq!(slow.estimate_seconds(cells, 1), to_t_max);
    // The paper's tau keeps the measured rate of docs/history/benchmarks.md ("Basin scans").
    assert_eq!(
        paper.estimate_seconds(cells, 1),
        cells as f64 * 2.0 / 25_000.0
    );
}

/// A spec read from /dev/zero grew memory at about 250 MB/s until killed. A device
/// is now refused before it is opened (not a regular file); a regular file longer than the
/// limit is refused by its size.
#[test]
fn an_endless_spec_file_is_refused() {
    for e in [
        Plan::from_file(std::path::Path::new("/dev/zero")).unwrap_err(),
        AtlasPlan::from_file(std::path::Path::new("/dev/zero")).unwrap_err(),
    ] {
        let e = e.to_string();
        assert!(e.contains("it is a character device"), "{e}");
    }
    let long = std::env::temp_dir().join(format!("squeal-long-{}.toml", std::process::id()));
    std::fs::write(&long, vec![b'#'; 1_048_577]).unwrap();
    for e in [
        Plan::from_file(&long).unwrap_err(),
        AtlasPlan::from_file(&long).unwrap_err(),
    ] {
        let e = e.to_string();
        assert!(e.contains("longer than 1048576 bytes"), "{e}");
    }
    std::fs::remove_file(&long).unwrap();
}

/// A bad `boundaries.nu_hi` was reported as `boundaries.nu_lo`.
#[test]
fn a_bad_upper_bisection_end_is_named() {
    let e = atlas_err(&with(ATLAS, "[boundaries]\nnu_hi = 20.0"));
    assert_names(&e, "boundaries.nu_hi", "<= 10");
    let e = atlas_err(&with(ATLAS, "[boundaries]\nlambda_hi = nan"));
    assert_names(&e, "boundaries.lambda_hi", "<= 1000");
    let e = atlas_err(&with(ATLAS, "[boundaries]\nnu_lo = 0.0"));
    assert_names(&e, "boundaries.nu_lo", "0 < nu_lo");
}

/// `[operating_point]` or `[disturbance]` with one key failed with "missing field
/// `v`" though the docs give each key a default.
#[test]
fn one_key_of_a_point_or_box_takes_the_others_default() {
    let p = AtlasPlan::from_toml(&with(ATLAS, "[operating_point]\nx = 0.5"), "t.toml").unwrap();
    assert_eq!((p.point.operating.x, p.point.operating.v), (0.5, 0.0));
    let p = AtlasPlan::from_toml(&with(ATLAS, "[disturbance]\nv = [-1.0, 1.0]"), "t.toml").unwrap();
    let d = squeal_scan::atlas::point::PointSettings::default().disturbance;
    assert_eq!(
        (p.point.disturbance.x, p.point.disturbance.v),
        (d.x, [-1.0, 1.0])
    );
}

/// `fp_radius` against the located cycle: at nu = 5e-5 (Table 1 otherwise) the unstable cycle
/// crosses the section at x' = 0.01845 (`squeal ulc --nu 5e-5`), so a ball of radius 0.01,
/// within the spec's bound, reaches past half of it and is refused before any cell runs.
#[test]
fn a_fixed_point_ball_reaching_the_located_cycle_is_refused() {
    let text = |fp: &str| {
        SCAN.replace("nu = 1e-3", "nu = 5e-5").replace(
            "[output]",
            &format!("[classifier]\nfp_radius = {fp}\n[output]"),
        )
    };
    let wide = Plan::from_toml(&text("0.01"), "t.toml").unwrap();
    let e = match squeal_scan::MapContext::prepare(&wide, 0) {
        Ok(_) => panic!("a ball of 0.01 inside a cycle at 0.018 was accepted"),
        Err(e) => e.to_string(),
    };
    assert_names(
        &e,
        "classifier.fp_radius",
        "at most half its section crossing",
    );
    let small = Plan::from_toml(&text("1e-3"), "t.toml").unwrap();
    assert!(squeal_scan::MapContext::prepare(&small, 0).is_ok());
}

/// A huge value is named as the spec wrote it, in exponent form: `nu = 1e300` was reported
/// as "`model.nu` = 1" followed by 300 zeros (and `integration.dt = 1e300` the same), which
/// no reader can check against the spec.
#[test]
fn a_huge_value_is_named_in_exponent_form() {
    for (text, key) in [
        (SCAN.replace("nu = 1e-3", "nu = 1e300"), "model.nu"),
        (with(SCAN, "[integration]\ndt = 1e300"), "integration.dt"),
        (
            ATLAS.replace("nu = [1e-3, 2e-3]", "nu = [1e-3, 1e300]"),
            "model.nu",
        ),
    ] {
        let e = if text.contains("[grid]") {
            scan_err(&text)
        } else {
            atlas_err(&text)
        };
        assert!(e.contains(&format!("`{key}` = 1e300:")), "{e}");
        assert!(e.len() < 300, "{} characters: {e}", e.len());
    }
}

/// A tiny value inside a refused range is named in exponent form as well: an inverted grid
/// axis `[1e-300, 1e-301]` and an inverted boundary bracket were printed with every one of
/// their 300 zeros (only a lone number was mended, by parsing the message's text back).
#[test]
fn tiny_ends_of_a_refused_range_are_named_in_exponent_form() {
    let e = scan_err(&SCAN.replace(
        "x0 = { min = -3.0, max = 5.0, count = 32 }",
        "x0 = { min = 1e-300, max = 1e-301, count = 32 }",
    ));
    assert_names(&e, "grid.x0", "min <= max");
    assert!(e.contains("`grid.x0` = [1e-300, 1e-301]:"), "{e}");
    let e = atlas_err(&with(
        &ATLAS.replace("nu = [1e-3, 2e-3]", "nu = 1e-3\nlambda = [1.0, 2.0]"),
        "[boundaries]\nnu_lo = 1e-300\nnu_hi = 1e-301",
    ));
    assert!(e.contains("[1e-300, 1e-301]"), "{e}");
    assert!(e.len() < 300, "{} characters: {e}", e.len());
}

/// The damping in a no-cycle note is named in exponent form: a scan of `nu = 1e-300` printed
/// "the return map grows already at r = 0.01 (nu = 0.000...1)" with 300 zeros, and so did
/// `cycle.r_min = 1e-300`.
#[test]
fn a_tiny_damping_in_a_no_cycle_note_is_in_exponent_form() {
    use squeal_scan::NoCycle;
    use squeal_scan::error::Damping;
    let repels = NoCycle::FixedPointRepels {
        r_min: 1e-300,
        damping: Damping::Nu(1e-300),
    };
    assert_eq!(
        repels.to_string(),
        "the steady-slip fixed point repels or attracts no whole neighbourhood (nu = 1e-300): \
         its linearisation says so, or the return map grows already at r = 1e-300"
    );
    // In range, as Rust writes it (what the existing notes read).
    assert_eq!(Damping::Xi(0.05).to_string(), "xi = 0.05");
}

/// A range of one value with two different ends ran one map at `from` and dropped `to`, as a
/// grid axis of `count = 1` with `min != max` did before it was refused; and a huge end of a
/// range was named with 300 digits.
#[test]
fn a_range_of_one_value_between_two_ends_is_refused() {
    let one = |v: &str| SCAN.replace("nu = 1e-3", &format!("nu = {v}"));
    let e = scan_err(&one("{ from = 1e-3, to = 2e-3, count = 1 }"));
    assert_names(&e, "model.nu.count", "count >= 2 for a range, or from = to");
    assert!(e.contains("1 from 0.001 to 0.002"), "{e}");
    let e = atlas_err(&ATLAS.replace(
        "nu = [1e-3, 2e-3]",
        "nu = 1e-3\nlambda = { from = 1.0, to = 2.0, count = 1 }",
    ));
    assert_names(&e, "model.lambda.count", "count >= 2 for a range");
    // One value written as a range is still one map.
    let plan = Plan::from_toml(&one("{ from = 1e-3, to = 1e-3, count = 1 }"), "t.toml").unwrap();
    assert_eq!(plan.maps.len(), 1);
    let e = scan_err(&one(
        "{ from = -1e300, to = 1e-3, count = 3, spacing = \"log\" }",
    ));
    assert!(e.contains("from -1e300 to 0.001"), "{e}");
}

/// A physical spec's grid or sample region is checked in the model's units, as the atlas's
/// box is: with `m = 1e300` a grid 0.4 mm wide became 6e-300 units wide (every cell the same
/// state; that system is now refused first for its belt speed), and x0 in +-3 km (the length unit mu_k g m / k = 69 um for the brake below) put
/// the starts beyond the escape radius; both ran.
#[test]
fn a_physical_grid_is_checked_in_the_models_units() {
    let brake = r#"version = 1
[model]
law = "mcmillan"
[physical]
m = 2.0
k = 5.0e4
c = 5.0
v_belt = 0.05
mu_k = 0.35
mu_s = 0.45
tau = 1e-3
[grid]
x0 = { min = -1e-4, max = 3e-4, count = 6 }
v0 = { min = -0.02, max = 0.02, count = 6 }
[output]
path = "x.h5"
"#;
    assert!(Plan::from_toml(brake, "t.toml").is_ok());
    // A grid 1e-14 m wide is 7.3e-11 length units of 137 um: no box.
    let e = scan_err(&brake.replace("min = -1e-4, max = 3e-4", "min = 0.0, max = 1e-14"));
    assert_names(&e, "grid.x0", "a box with an area");
    assert!(e.contains("in the model's units"), "{e}");
    // m = 1e300 makes the belt speed lambda = 3.3e-150, below the step: refused by its key
    // before the grid it also collapses (Params::check_step).
    let e = scan_err(&brake.replace("m = 2.0", "m = 1e300"));
    assert_names(&e, "physical.m", "dt = 0.005");
    let e = scan_err(&brake.replace("min = -1e-4, max = 3e-4", "min = -3e3, max = 3e3"));
    assert_names(&e, "grid.x0", "<= 1e6");
    // v0 in +-100 km/s: 4.6e6 velocity units of mu_k g / omega_0 = 21.7 mm/s.
    let sampled = brake.replace(
        "[grid]\nx0 = { min = -1e-4, max = 3e-4, count = 6 }\nv0 = { min = -0.02, max = 0.02, count = 6 }",
        "[sample]\nkind = \"random\"\nn = 10\nseed = 1\nregion = { x0 = [-1e-4, 3e-4], v0 = [-1e5, 1e5] }",
    );
    assert_names(&scan_err(&sampled), "sample.region.v0", "<= 1e6");
}

/// A grid axis narrower than the numbers' resolution allows for its count put neighbouring
/// cells at one coordinate: `[1.0, 1.0000000000000002]` (one unit in the last place apart)
/// with 8 cells ran 8 columns from 2 distinct states.
#[test]
fn grid_cells_lie_at_distinct_coordinates() {
    let e = scan_err(&SCAN.replace(
        "x0 = { min = -3.0, max = 5.0, count = 32 }",
        "x0 = { min = 1.0, max = 1.0000000000000002, count = 8 }",
    ));
    assert_names(&e, "grid.x0", "cells at distinct coordinates");
    // Two cells one unit in the last place apart are distinct: accepted.
    let two = SCAN.replace(
        "x0 = { min = -3.0, max = 5.0, count = 32 }",
        "x0 = { min = 1.0, max = 1.0000000000000002, count = 2 }",
    );
    assert!(Plan::from_toml(&two, "t.toml").is_ok());
}

/// `phi = 1e-300` ran, and every start outside the unstable cycle read "diverged": the
/// stick-slip orbit swings to about 1.43 / sin(phi), beyond the escape radius 1e6 below
/// phi = 1.4e-6 (`squeal_core::law::MIN_PHI` gives the measured figures). The physical
/// form's `mu_s = 1e300 mu_k` is the same Phi, refused by the key given.
#[test]
fn a_static_peak_beyond_the_escape_radius_is_refused() {
    for phi in ["1e-300", "1e-6"] {
        let e = scan_err(&SCAN.replace("nu = 1e-3", &format!("nu = 1e-3\nphi = {phi}")));
        assert_names(&e, "model.phi", "[1e-5, pi/2]");
    }
    let e = atlas_err(&ATLAS.replace("nu = [1e-3, 2e-3]", "nu = 1e-3\nphi = [1.0, 1e-300]"));
    assert_names(&e, "model.phi", "[1e-5, pi/2]");
    let physical = |mu_s: &str| {
        format!(
            "version = 1\n[model]\nlaw = \"mcmillan\"\n[physical]\nm = 2.0\nk = 5.0e4\n\
             c = 5.0\nv_belt = 0.05\nmu_k = 0.35\nmu_s = {mu_s}\ntau = 1e-3\n[grid]\n\
             x0 = {{ min = -1e-4, max = 3e-4, count = 6 }}\n\
             v0 = {{ min = -0.02, max = 0.02, count = 6 }}\n[output]\npath = \"x.h5\"\n"
        )
    };
    assert_names(
        &scan_err(&physical("1e300")),
        "physical.mu_s",
        "at most about 1e5 mu_k",
    );
    // At the bound: phi = 1e-5; mu_s = 3e4 = 0.35 * 8.6e4, Phi = arcsin(1 / 8.6e4) = 1.2e-5.
    Plan::from_toml(
        &SCAN.replace("nu = 1e-3", "nu = 1e-3\nphi = 1e-5"),
        "t.toml",
    )
    .unwrap();
    Plan::from_toml(&physical("3e4"), "t.toml").unwrap();
}

/// `fp_radius = 1e-300` and `trap_margin = 1e-300` were accepted. A ball that small is
/// entered by chance or never (at 1e-15 settling runs were labelled stick-slip:
/// `bounds::MIN_FP_RADIUS`), and a band that small is no band in f64 (`r (1 - 1e-300) == r`;
/// `bounds::MIN_TRAP_MARGIN`). Both bounds are 1e-10, in scans and atlases alike.
#[test]
fn a_fixed_point_ball_or_trap_below_the_numbers_resolution_is_refused() {
    for tiny in ["1e-300", "1e-15", "9e-11"] {
        let ball = format!("[classifier]\nfp_radius = {tiny}");
        assert_names(
            &scan_err(&with(SCAN, &ball)),
            "classifier.fp_radius",
            "[1e-10, 0.01]",
        );
        let band = format!("[classifier]\ntrap_margin = {tiny}");
        assert_names(
            &scan_err(&with(SCAN, &band)),
            "classifier.trap_margin",
            "[1e-10, 0.5)",
        );
    }
    let grid = "[grid]\nx0 = { min = 0.5, max = 1.5, count = 4 }\nv0 = { min = -0.5, max = 0.5, count = 4 }";
    let e = atlas_err(&with(
        ATLAS,
        &format!("{grid}\n[classifier]\ntrap_margin = 1e-300"),
    ));
    assert_names(&e, "classifier.trap_margin", "[1e-10, 0.5)");
    assert!(e.contains("= 1e-300"), "{e}");
    let e = atlas_err(&with(
        ATLAS,
        &format!("{grid}\n[classifier]\nfp_radius = 1e-300"),
    ));
    assert_names(&e, "classifier.fp_radius", "[1e-10, 0.01]");
    for key in ["fp_radius", "trap_margin"] {
        let at_bound = with(SCAN, &format!("[classifier]\n{key} = 1e-10"));
        Plan::from_toml(&at_bound, "t.toml").unwrap();
    }
}
