use super::*;

pub(crate) const GOOD: &str = r#"
version = 1
[model]
law = "mcmillan"
nu = 1e-3
[grid]
x0 = { min = -3.0, max = 5.0, count = 4 }
v0 = { min = -4.0, max = 4.0, count = 3 }
[output]
path = "x.h5"
"#;

fn err(text: &str) -> String {
    Plan::from_toml(text, "t.toml").unwrap_err().to_string()
}

#[test]
fn good_spec_gives_defaults() {
    let p = Plan::from_toml(GOOD, "scans/t.toml").unwrap();
    assert_eq!(p.maps.len(), 1);
    assert_eq!(p.maps[0].lambda, 3.0);
    assert_eq!(p.name, "t");
    assert_eq!(p.map.grid.cells(), 12);
    assert!(p.sweep.is_none());
    assert_eq!(p.map.early_stop, EarlyStop::Cycle);
    // 12 cells: one start per 32 cells, at least 64.
    assert_eq!(p.map.sensitivity_samples, 64);
}

#[test]
fn bad_specs_name_the_problem() {
    let cases: Vec<(String, &str)> = vec![
        (GOOD.replace("version = 1", "version = 2"), "version"),
        (
            GOOD.replace("nu = 1e-3", "nu = 1e-3\nmu = 2"),
            "unknown field `mu`",
        ),
        (GOOD.replace("nu = 1e-3\n", ""), "`model.nu` = missing"),
        (
            GOOD.replace("min = -3.0, max = 5.0", "min = 5.0, max = -3.0"),
            "inverted",
        ),
        (
            GOOD.replace("min = -3.0, max = 5.0", "min = 1.0, max = 1.0"),
            "empty range",
        ),
        (GOOD.replace("count = 4", "count = 0"), "grid.x0.count"),
        (
            GOOD.replace("count = 4", "count = 100000000"),
            "grid.x0.count",
        ),
        (GOOD.replace("nu = 1e-3", "nu = -1.0"), "model.nu"),
        (GOOD.replace("nu = 1e-3", "nu = []"), "non-empty"),
        (
            GOOD.replace("nu = 1e-3", "nu = [1e-3, 3e-3, 2e-3]"),
            "monotone",
        ),
        (GOOD.replace("nu = 1e-3", "nu = nan"), "model.nu"),
        (
            format!("{GOOD}\n[classifier]\nsensitivity_samples = 5\n"),
            "classifier.sensitivity_samples",
        ),
        (
            format!("{GOOD}\n[classifier]\nsensitivity_samples = -1\n"),
            "classifier.sensitivity_samples",
        ),
        (
            GOOD.replace("law = \"mcmillan\"", "law = \"stribeck\""),
            "stribeck",
        ),
        (
            GOOD.replace("[output]", "[integration]\ndt = 0.0\n[output]"),
            "integration.dt",
        ),
        (
            GOOD.replace("nu = 1e-3", "nu = [1e-3, 2e-3]\nlambda = [1.0, 1.0]"),
            "model.lambda",
        ),
        (GOOD.replace("[model]", "[model\n"), "line"),
        (
            GOOD.replace("version = 1", "version = 1\nname = \"a\\u0000b\""),
            "`name`",
        ),
        (
            GOOD.replace("nu = 1e-3", "nu = \"small\""),
            // The TOML error quotes the line (naming the key) and says what is accepted.
            "nu = \"small\"\n  |      ^^^^^^^\na number, a list of numbers",
        ),
    ];
    for (text, want) in cases {
        let e = err(&text);
        assert!(e.contains(want), "expected '{want}' in: {e}");
    }
}

pub(crate) const SAMPLED: &str = r#"
version = 1
[model]
law = "mcmillan"
nu = 1e-3
[sample]
kind = "random"
n = 50
seed = 3
region = { x0 = [-2.0, 2.0], v0 = [0.0, 2.0] }
[output]
path = "x.h5"
"#;

#[test]
fn a_random_sample_is_a_list_of_points_in_the_region() {
    let p = Plan::from_toml(SAMPLED, "t.toml").unwrap();
    let g = p.map.grid;
    assert_eq!((g.cells(), g.x0.count, g.v0.count), (50, 1, 50));
    assert_eq!(g.block_rows, DEFAULT_SAMPLE_BLOCK as usize);
    assert_eq!(g.blocks(), 1);
    for i in 0..50 {
        let (x, v) = g.state(i, 0);
        assert!(
            (-2.0..2.0).contains(&x) && (0.0..2.0).contains(&v),
            "{x} {v}"
        );
    }
    // Another seed is another plan (a resume refuses it).
    let q = Plan::from_toml(&SAMPLED.replace("seed = 3", "seed = 4"), "t.toml").unwrap();
    assert_eq!(p.differs_from(&q).as_deref(), Some("grid"));
}

#[test]
fn bad_samples_name_the_problem() {
    let cases: Vec<(String, &str)> = vec![
            (SAMPLED.replace("n = 50", "n = 0"), "sample.n"),
            (SAMPLED.replace("n = 50", "n = -5"), "sample.n"),
            (
                SAMPLED.replace("x0 = [-2.0, 2.0]", "x0 = [2.0, -2.0]"),
                "`sample.region.x0` = [2.0, -2.0]: min <= max (the range is inverted)",
            ),
            (
                SAMPLED.replace("v0 = [0.0, 2.0]", "v0 = [nan, 2.0]"),
                "sample.region.v0",
            ),
            // A NaN (or any float) seed: the TOML error quotes the `seed` line.
            (SAMPLED.replace("seed = 3", "seed = nan"), "seed = nan"),
            (SAMPLED.replace("seed = 3", "seed = -1"), "seed = -1"),
            (SAMPLED.replace("kind = \"random\"", "kind = \"sobol\""), "sobol"),
            (
                SAMPLED.replace("[output]", "block = 0\n[output]"),
                "sample.block",
            ),
            (
                SAMPLED.replace("[output]", "[grid]\nx0 = { min = 0.0, max = 1.0, count = 2 }\nv0 = { min = 0.0, max = 1.0, count = 2 }\n[output]"),
                "one of [grid]",
            ),
            (
                SAMPLED.replace("[sample]", "[unused]").replace("kind = \"random\"\n", ""),
                "unknown field `unused`",
            ),
            (
                GOOD.replace("[grid]", "[other]"),
                "unknown field `other`",
            ),
        ];
    for (text, want) in cases {
        let e = err(&text);
        assert!(e.contains(want), "expected '{want}' in: {e}");
    }
    let neither = GOOD
        .replace("[grid]\n", "")
        .replace("x0 = { min = -3.0, max = 5.0, count = 4 }\n", "")
        .replace("v0 = { min = -4.0, max = 4.0, count = 3 }\n", "");
    let e = err(&neither);
    assert!(e.contains("`grid`") && e.contains("neither"), "{e}");
}

#[test]
fn comment_edits_do_not_change_the_plan() {
    let a = Plan::from_toml(GOOD, "t.toml").unwrap();
    let b = Plan::from_toml(&format!("# a note\n{GOOD}"), "t.toml").unwrap();
    assert_ne!(a.spec_text, b.spec_text);
    assert_eq!(a.differs_from(&b), None);
    let c = Plan::from_toml(&GOOD.replace("nu = 1e-3", "nu = 2e-3"), "t.toml").unwrap();
    assert_eq!(a.differs_from(&c).as_deref(), Some("maps"));
}

#[test]
fn sweeps_expand() {
    let p = Plan::from_toml(
        &GOOD.replace(
            "nu = 1e-3",
            "nu = { from = 1e-3, to = 1e-1, count = 3, spacing = \"log\" }",
        ),
        "t.toml",
    )
    .unwrap();
    let s = p.sweep.unwrap();
    assert_eq!(s.names(), ["nu"]);
    assert!((s.axes[0].values[1] - 1e-2).abs() < 1e-15);
    assert_eq!(p.maps.len(), 3);
}

/// Several swept keys make one map per point of their product, in the law's key order with
/// the last key fastest; a key neither the damping nor the belt speed may be swept too.
#[test]
fn sweeps_of_several_keys_are_their_product() {
    let text = GOOD.replace("nu = 1e-3", "nu = [1e-3, 2e-3]\nphi = [0.5, 0.7, 0.9]");
    let p = Plan::from_toml(&text, "t.toml").unwrap();
    let s = p.sweep.as_ref().unwrap();
    assert_eq!(s.names(), ["nu", "phi"]);
    assert_eq!(s.shape(), [2, 3]);
    assert_eq!(p.maps.len(), 6);
    let phi = |m: usize| p.maps[m].law.surface().unwrap().phi;
    assert_eq!((p.maps[2].nu, phi(2)), (1e-3, 0.9));
    assert_eq!((p.maps[3].nu, phi(3)), (2e-3, 0.5));
    assert_eq!(s.values_at(4), [2e-3, 0.7]);
    assert_eq!(s.per_map("phi").unwrap(), [0.5, 0.7, 0.9, 0.5, 0.7, 0.9]);
    // A value of one swept key out of range is named by its key, as for a single value.
    let bad = text.replace("phi = [0.5, 0.7, 0.9]", "phi = [0.5, 2.0]");
    let e = Plan::from_toml(&bad, "t.toml").unwrap_err().to_string();
    assert!(e.contains("model.phi"), "{e}");
    // The product is bounded as a single key's values are.
    let big = GOOD.replace(
        "nu = 1e-3",
        "nu = { from = 1e-3, to = 1e-2, count = 200 }\nlambda = { from = 1, to = 3, count = 60 }",
    );
    let e = Plan::from_toml(&big, "t.toml").unwrap_err().to_string();
    assert!(e.contains("at most 10000 maps"), "{e}");
}

/// Every key of a spec, valid as a whole: (table, key, value). The grid axes are written
/// as sub-tables so that each of their keys is a line of its own.
const FULL: &[(&str, &str, &str)] = &[
    ("", "version", "1"),
    ("", "name", "\"fuzz\""),
    ("model", "law", "\"mcmillan\""),
    ("model", "nu", "1e-3"),
    ("model", "lambda", "3.0"),
    ("model", "tau", "0.31622776601683794"),
    ("model", "phi", "1.0"),
    ("grid", "block_rows", "8"),
    ("grid.x0", "min", "-3.0"),
    ("grid.x0", "max", "5.0"),
    ("grid.x0", "count", "4"),
    ("grid.v0", "min", "-4.0"),
    ("grid.v0", "max", "4.0"),
    ("grid.v0", "count", "3"),
    ("integration", "dt", "0.01"),
    ("integration", "solver", "\"robust\""),
    ("integration", "max_iter", "100"),
    ("classifier", "t_max", "5000.0"),
    ("classifier", "fp_radius", "1e-3"),
    ("classifier", "settle_cycles", "20"),
    ("classifier", "settle_rtol", "0.05"),
    ("classifier", "early_stop", "\"cycle\""),
    ("classifier", "trap_margin", "1e-5"),
    ("classifier", "sensitivity_samples", "64"),
    ("cycle", "locate", "true"),
    ("output", "path", "\"x.h5\""),
];

/// What to do to one key of [`FULL`].
#[derive(Clone, Debug)]
enum Mutation {
    /// Give it this TOML value (any type).
    Set(String),
    /// Remove the line.
    Delete,
    /// Write the line twice.
    Duplicate,
}

/// The spec of [`FULL`] with `mutation` applied to key number `at`.
fn mutated(at: usize, mutation: &Mutation) -> String {
    let mut text = String::new();
    let mut table = "";
    for (i, &(t, key, value)) in FULL.iter().enumerate() {
        if t != table {
            text += &format!("[{t}]\n");
            table = t;
        }
        let line = format!("{key} = {value}\n");
        match (i == at, mutation) {
            (false, _) => text += &line,
            (true, Mutation::Set(v)) => text += &format!("{key} = {v}\n"),
            (true, Mutation::Delete) => {}
            (true, Mutation::Duplicate) => {
                text += &line;
                text += &line;
            }
        }
    }
    text
}

/// TOML literals of every type, in and out of range.
fn toml_value() -> impl proptest::strategy::Strategy<Value = String> {
    use proptest::prelude::*;
    let float = proptest::num::f64::ANY.prop_map(|f| {
        if f.is_nan() {
            "nan".to_string()
        } else if f.is_infinite() {
            if f > 0.0 { "inf" } else { "-inf" }.to_string()
        } else {
            format!("{f:?}")
        }
    });
    let small = (-10.0f64..10.0).prop_map(|f| format!("{f:?}"));
    let string =
        "\\PC{0,12}".prop_map(|s| format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\"")));
    let word = proptest::sample::select(vec![
        "\"mcmillan\"",
        "\"coulomb\"",
        "\"none\"",
        "\"paper\"",
        "\"log\"",
        "\"\"",
    ])
    .prop_map(str::to_string);
    // Weighted towards numbers of the right type, which get past the parser.
    prop_oneof![
        2 => float,
        4 => small,
        1 => any::<i64>().prop_map(|n| n.to_string()),
        3 => (-5i64..300).prop_map(|n| n.to_string()),
        1 => any::<bool>().prop_map(|b| b.to_string()),
        1 => string,
        2 => word,
        1 => proptest::collection::vec(-1.0f64..1.0, 0..4)
            .prop_map(|v| format!("{v:?}")),
        1 => Just("{ from = 1e-3, to = 1e-2, count = 3, spacing = \"log\" }".to_string()),
        1 => Just("{ min = -1.0, max = 1.0, count = 2 }".to_string()),
        1 => Just("{}".to_string()),
    ]
}

#[test]
fn the_full_spec_is_valid_and_mutations_reach_validation() {
    // The base of the mutations is accepted, so an error comes from the mutation.
    Plan::from_toml(&mutated(usize::MAX, &Mutation::Delete), "full.toml").unwrap();
    // Out-of-range values of the right type get past the TOML parser to validation.
    let e = err(&mutated(3, &Mutation::Set("-1.0".into())));
    assert!(e.contains("model.nu"), "{e}");
    assert!(!e.contains("TOML parse error"), "{e}");
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(512))]
    /// A valid spec with one key changed (any value of any type), deleted or duplicated:
    /// never a panic, and a refusal names the key it is about.
    #[test]
    fn mutated_specs_never_panic_and_errors_name_the_key(
        at in 0..FULL.len(),
        mutation in proptest::prop_oneof![
            6 => proptest::strategy::Strategy::prop_map(toml_value(), Mutation::Set),
            1 => proptest::strategy::Just(Mutation::Delete),
            1 => proptest::strategy::Just(Mutation::Duplicate),
        ],
    ) {
        use proptest::prelude::*;
        let text = mutated(at, &mutation);
        let stored = Plan::from_stored_toml(&text, "fuzz.toml");
        let today = Plan::from_toml(&text, "fuzz.toml");
        // A spec that passes today's bounds reads back from a file as the same plan (the
        // stored reading is the checked one with the bounds left out), and what a stored
        // spec is refused for is worded as the file's.
        match (&today, &stored) {
            (Ok(t), s) => prop_assert_eq!(Some(t), s.as_ref().ok(), "{}", text),
            (_, Err(e)) => prop_assert!(e.to_string().contains("this file's stored spec"), "{e}"),
            (Err(_), Ok(_)) => {}
        }
        if let Err(e) = today {
            let (table, key) = (FULL[at].0, FULL[at].1);
            let msg = e.to_string();
            // An axis's min, max and count are checked together (an empty range, too
            // many cells): naming the axis (`grid.v0`) names the key's table.
            let names_axis = table.starts_with("grid.") && msg.contains(table);
            prop_assert!(
                msg.contains(key) || names_axis,
                "{mutation:?} of `{table}.{key}`: {msg}\n{text}"
            );
        }
    }

    #[test]
    fn mutated_numbers_never_panic(a in proptest::num::f64::ANY, n in proptest::num::i64::ANY) {
        let t = GOOD.replace("-3.0", &format!("{a:?}")).replace("count = 4", &format!("count = {n}"));
        let _ = Plan::from_toml(&t, "fuzz.toml");
        let _ = Plan::from_stored_toml(&t, "fuzz.toml");
    }
}

/// A spec stored in a file describes what was run: a value a squeal of today refuses (a
/// bound added or tightened after the file was written: the lower bounds on phi, fp_radius
/// and trap_margin came after files held values below them) reads back as stored. Before,
/// the stored spec was checked against today's bounds and the file refused with the
/// bound's error, so each new bound made old files unreadable. Given by a user to run, the
/// same spec is refused naming the key, as before.
#[test]
fn a_stored_spec_outside_todays_bounds_reads_as_stored() {
    use crate::Plan;
    use crate::atlas::AtlasPlan;
    let table =
        |table: &str, line: &str| GOOD.replace("[output]", &format!("[{table}]\n{line}\n[output]"));
    // Each value is outside a bound of today (bounds.rs, classifier.rs, tables.rs): phi
    // below MIN_PHI = 1e-5, fp_radius below 1e-10, trap_margin below 1e-10, t_max / dt =
    // 1e12 / 0.005 = 2e14 steps above MAX_STEPS = 1e10, dt above 1, settle_cycles below
    // 4, max_iter above 100000, cycle samples below 3, r_max short of the grid's reach
    // (about 5.7 from (1, 0) to (-3, +-4)).
    let cases = [
        (
            GOOD.replace("nu = 1e-3", "nu = 1e-3\nphi = 2e-6"),
            "model.phi",
        ),
        (
            table("classifier", "fp_radius = 1e-12"),
            "classifier.fp_radius",
        ),
        (
            table("classifier", "trap_margin = 1e-12"),
            "classifier.trap_margin",
        ),
        (table("classifier", "t_max = 1e12"), "classifier.t_max"),
        (table("integration", "dt = 2.0"), "integration.dt"),
        (
            table("classifier", "settle_cycles = 2"),
            "classifier.settle_cycles",
        ),
        (
            table("integration", "max_iter = 200000"),
            "integration.max_iter",
        ),
        (table("cycle", "samples = 2"), "cycle.samples"),
        (table("cycle", "r_max = 3.0"), "cycle.r_max"),
    ];
    for (text, key) in &cases {
        let e = Plan::from_toml(text, "t.toml").unwrap_err().to_string();
        assert!(e.contains(&format!("`{key}`")), "{e}");
        let p = Plan::from_stored_toml(text, "t.toml").unwrap_or_else(|e| panic!("{key}: {e}"));
        assert_eq!(p.map.grid.cells(), 12, "{key}");
    }
    let stored = |i: usize| Plan::from_stored_toml(&cases[i].0, "t.toml").unwrap();
    let phi = stored(0).maps[0].law.surface().unwrap().phi;
    assert_eq!(phi, 2e-6);
    assert_eq!(stored(1).map.classifier.fp_radius, 1e-12);
    assert_eq!(stored(2).map.trap_margin, 1e-12);
    assert_eq!(stored(3).map.classifier.t_max, 1e12);
    assert_eq!(stored(4).dt, 2.0);
    assert_eq!(stored(5).map.classifier.settle_cycles, 2);
    assert_eq!(stored(6).solver.max_iter, 200_000);
    assert_eq!(stored(7).cycle.search.samples, 2);
    assert_eq!(stored(8).cycle.search.r_max, 3.0);
    // mu_s = 2e5 against mu_k = 0.35: Phi = arcsin(0.35 / 2e5) = 1.75e-6, below 1e-5.
    let atlas = "version = 1\n[model]\nlaw = \"mcmillan\"\n[physical]\nm = 2.0\n\
                 k = 5.0e4\nc = 10.0\nv_belt = 0.05\nmu_k = 0.35\nmu_s = 2e5\ntau = 1e-3\n\
                 [boundaries]\nfold = false\ncritical = false\n[output]\npath = \"a.h5\"\n";
    let e = AtlasPlan::from_toml(atlas, "a.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("`physical.mu_s`"), "{e}");
    let a = AtlasPlan::from_stored_toml(atlas, "a.toml").unwrap();
    let phi = a.space.params_at(0).law.surface().unwrap().phi;
    assert!((phi - (0.35f64 / 2e5).asin()).abs() < 1e-20, "{phi}");
}

/// What a plan cannot be built without is refused in a stored spec too, worded as the
/// file's stored spec and naming the key: text that is not TOML, a missing table, a law
/// this squeal does not know, a count that is no count, a range that is no pair.
#[test]
fn a_stored_spec_that_cannot_be_a_plan_is_refused_as_the_files() {
    use crate::Plan;
    let sample = GOOD.replace(
        "[grid]\nx0 = { min = -3.0, max = 5.0, count = 4 }\nv0 = { min = -4.0, max = 4.0, count = 3 }",
        "[sample]\nkind = \"random\"\nn = 8\nseed = 1\nregion = { x0 = [-1.0, 1.0, 2.0], v0 = [0.0, 1.0] }",
    );
    assert!(sample.contains("[sample]"));
    for (text, key) in [
        ("version = 1\n[model".to_string(), "TOML"),
        (GOOD.replace("[output]\npath = \"x.h5\"", ""), "output"),
        (GOOD.replace("\"mcmillan\"", "\"velvet\""), "velvet"),
        (GOOD.replace("count = 4", "count = -4"), "grid.x0.count"),
        (sample, "sample.region.x0"),
        (
            GOOD.replace("[output]", "[integration]\nmax_iter = -1\n[output]"),
            "integration.max_iter",
        ),
    ] {
        let e = Plan::from_stored_toml(&text, "t.toml")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("t.toml: this file's stored spec") && e.contains(key),
            "{key}: {e}"
        );
    }
}
