//! Every numeric value of every shipped spec in `scans/`, set in turn to 0, -1, NaN, inf,
//! 1e308 and -1e308: the spec is refused with a message naming the key, or accepted with a
//! plan whose derived numbers (grid coordinates, boxes, parameters, work estimate) are all
//! finite. Never a panic. The counts are printed (`--nocapture`).

use std::panic::{AssertUnwindSafe, catch_unwind};

use proptest::strategy::Strategy;
use squeal_mutate::{Shipped, Step, at, shipped};
use squeal_scan::Plan;
use squeal_scan::atlas::AtlasPlan;
use toml::Value;

/// Whether a refusal names the value at `path`: its dotted key (`grid.x0.min`, also where a
/// bound on another key depends on it: `t_max / integration.dt`), the key
/// above it (an axis or range checked as a whole: `grid.x0`, `model.nu`), or the TOML line
/// (`count = 1e308`, quoted by a type error). A physical parameter may also be named as
/// a word of the message about a physical quantity it sets (the formula of lambda, nu or
/// Phi, or the keys that scale the disturbance box).
fn names_it(path: &[Step], msg: &str) -> bool {
    let keys: Vec<&str> = path
        .iter()
        .filter_map(|s| match s {
            Step::Key(k) => Some(k.as_str()),
            Step::Index(_) => None,
        })
        .collect();
    let leaf = keys[keys.len() - 1];
    let dotted = keys.join(".");
    let parent = keys[..keys.len() - 1].join(".");
    let word = msg
        .split(|c: char| !(c.is_alphanumeric() || c == '_'))
        .any(|w| w == leaf || keys.len() > 2 && w == keys[keys.len() - 2]);
    msg.contains(&dotted)
        || (keys.len() > 2 && msg.contains(&format!("`{parent}")))
        || msg.contains(&format!("{leaf} = "))
        // The nondimensional value a physical key sets, named with its formula
        // (`physical.v_belt (lambda = v_belt sqrt(k/m) / (mu_k g))`), or the box it scales.
        || (keys[0] == "physical" && msg.contains("physical") && word)
        // Too many parameter points: the swept keys are listed with their value counts.
        || (keys.len() > 1 && msg.contains("parameter points") && msg.contains(&format!("{}: ", keys[1])))
}

/// Why an accepted scan plan is wrong, if it is.
fn scan_wrong(p: &Plan) -> Option<String> {
    let g = &p.map.grid;
    for a in [&g.x0, &g.v0] {
        if ![a.min, a.max, a.spacing()].iter().all(|v| v.is_finite()) {
            return Some(format!("axis {a:?}"));
        }
    }
    let corners = [(0, 0), (g.v0.count - 1, g.x0.count - 1)];
    if !g.is_sample()
        && corners
            .iter()
            .any(|&(r, c)| !(g.state(r, c).0.is_finite() && g.state(r, c).1.is_finite()))
    {
        return Some("a grid corner is not finite".into());
    }
    let e = p.estimate_seconds(p.total_cells(), 2);
    if !e.is_finite() || e < 0.0 {
        return Some(format!("estimate {e}"));
    }
    // Every kind of work at the documented rates (the cycle searches included).
    let all = squeal_scan::Pending::of(p, None, &squeal_scan::MemorySink::default());
    let e = squeal_scan::estimate::documented_seconds(p, &all, 2);
    if !e.is_finite() || e < 0.0 {
        return Some(format!("documented estimate {e}"));
    }
    if p.maps
        .iter()
        .any(|m| m.named().iter().any(|n| !n.value.is_finite()))
    {
        return Some("a parameter is not finite".into());
    }
    None
}

/// Why an accepted atlas plan is wrong, if it is.
fn atlas_wrong(p: &AtlasPlan) -> Option<String> {
    if p.space
        .params
        .iter()
        .any(|a| a.values.iter().any(|v| !v.is_finite()))
    {
        return Some("a parameter is not finite".into());
    }
    let s = p.settings_at(0);
    let d = s.disturbance;
    let area = (d.x[1] - d.x[0]) * (d.v[1] - d.v[0]);
    if !(area.is_finite() && area > 0.0) {
        return Some(format!("disturbance box {d:?}"));
    }
    if !(s.operating.x.is_finite() && s.operating.v.is_finite()) {
        return Some("operating point".into());
    }
    let e = squeal_scan::estimate::atlas_documented_seconds(p, 2);
    if !e.is_finite() || e < 0.0 {
        return Some(format!("documented estimate {e}"));
    }
    let c = s.cycle;
    if !(c.r_max.is_finite() && c.r_max <= squeal_scan::bounds::MAX_STATE * 10.0) {
        return Some(format!("cycle r_max {}", c.r_max));
    }
    p.maps.and_then(|m| {
        let g = m.grid;
        let ok = [
            g.x0.min,
            g.x0.max,
            g.x0.spacing(),
            g.v0.min,
            g.v0.max,
            g.v0.spacing(),
        ]
        .iter()
        .all(|v| v.is_finite());
        (!ok).then(|| "map grid".to_string())
    })
}

/// The shipped specs' folder.
fn scans() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scans")
}

#[derive(Debug, Default)]
struct Counts {
    specs: usize,
    numbers: usize,
    cases: usize,
    refused_naming_the_key: usize,
    refused_unclear: usize,
    accepted: usize,
    wrong: usize,
    panics: usize,
}

/// Sets the number at `path` of spec `sh` to `m`, checks the spec, counts the outcome in
/// `n` and returns the problem, if any. On a float key an integer is written as a float
/// (an integer there is a type error, which says nothing about the bounds).
fn judge(sh: &Shipped, path: &[Step], m: &Value, n: &mut Counts) -> Option<String> {
    let was_float = matches!(at(&mut sh.spec.clone(), path), Value::Float(_));
    let m = match (m, was_float) {
        (Value::Integer(i), true) => Value::Float(*i as f64),
        (m, _) => m.clone(),
    };
    let mut s = sh.spec.clone();
    *at(&mut s, path) = m.clone();
    let text = toml::to_string(&s).unwrap();
    n.cases += 1;
    // Read as from its folder: a spec's `friction_csv` is relative to it.
    let at_path = scans().join(&sh.name);
    let at_path = at_path.to_str().expect("a UTF-8 path");
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        if sh.atlas {
            AtlasPlan::from_toml(&text, at_path).map(|p| atlas_wrong(&p))
        } else {
            Plan::from_toml(&text, at_path).map(|p| scan_wrong(&p))
        }
    }));
    let case = format!("{} {path:?} = {m}", sh.name);
    match outcome {
        Err(_) => {
            n.panics += 1;
            Some(format!("panic: {case}"))
        }
        Ok(Err(e)) if names_it(path, &e.to_string()) => {
            n.refused_naming_the_key += 1;
            None
        }
        Ok(Err(e)) => {
            n.refused_unclear += 1;
            Some(format!("unclear: {case}: {e}"))
        }
        Ok(Ok(None)) => {
            n.accepted += 1;
            None
        }
        Ok(Ok(Some(why))) => {
            n.wrong += 1;
            Some(format!("wrong: {case}: {why}"))
        }
    }
}

#[test]
fn every_number_of_every_shipped_spec_mutated() {
    let mutations = [
        Value::Integer(0),
        Value::Integer(-1),
        Value::Float(f64::NAN),
        Value::Float(f64::INFINITY),
        Value::Float(1e308),
        Value::Float(-1e308),
    ];
    let mut n = Counts::default();
    let mut problems = Vec::new();
    for sh in &shipped(&scans()) {
        n.specs += 1;
        n.numbers += sh.paths.len();
        for path in &sh.paths {
            problems.extend(mutations.iter().filter_map(|m| judge(sh, path, m, &mut n)));
        }
    }
    eprintln!("shipped spec mutations: {n:?}");
    for p in &problems {
        eprintln!("{p}");
    }
    assert!(n.specs >= 10 && n.cases > 500, "{n:?}");
    assert!(
        problems.is_empty(),
        "{} problems, first: {}",
        problems.len(),
        problems[0]
    );
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig {
        // Reproduce from the printed input: no regression file next to the test.
        failure_persistence: None,
        ..proptest::prelude::ProptestConfig::with_cases(2000)
    })]
    /// Any float or integer at any number of any shipped spec: refused naming the key, or
    /// accepted with finite derived numbers; never a panic.
    #[test]
    fn any_value_at_any_number_of_a_shipped_spec(
        spec in 0usize..1000,
        key in 0usize..1000,
        value in proptest::prop_oneof![
            proptest::num::f64::ANY.prop_map(Value::Float),
            proptest::num::i64::ANY.prop_map(Value::Integer),
            (-1e7f64..1e7).prop_map(Value::Float),
            (-100i64..100_000).prop_map(Value::Integer),
        ],
    ) {
        use proptest::prop_assert;
        let all = shipped(&scans());
        let sh = &all[spec % all.len()];
        let path = &sh.paths[key % sh.paths.len()];
        let problem = judge(sh, path, &value, &mut Counts::default());
        prop_assert!(problem.is_none(), "{}", problem.unwrap_or_default());
    }
}
