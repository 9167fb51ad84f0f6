//! docs/spec.md against the spec parser: the keys it documents are exactly the keys the
//! parser accepts, each documented example parses, and each documented default is the value
//! the parser uses when the key is left out.
//!
//! The accepted keys come from the parser itself: a valid spec with an unknown key added to a
//! table fails with serde's "unknown field `x`, expected one of `a`, `b`, ..." message, which
//! lists the table's fields. A key added to the parser without a row in docs/spec.md (or a
//! row left behind after a key is removed) fails here.
//!
//! A new key: add a row to its table in docs/spec.md (key, default, range, example, meaning).
//! A new table: add a `### \`[name]\`` section with its rows, and its place in a spec to
//! [`location`] below.

use std::collections::{BTreeMap, BTreeSet};

use squeal_core::FrictionLaw;
use squeal_scan::Plan;
use toml::{Table, Value};

const DOC: &str = include_str!("../../../../docs/spec.md");

/// A valid spec to which keys are added (the one in docs/spec.md, smaller).
const GOOD: &str = r#"
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

/// A row of a key table in docs/spec.md.
#[derive(Debug)]
struct Row {
    key: String,
    default: String,
    range: String,
    example: String,
}

/// The documented tables: section name (`""` for the top level, `[model]`, `grid.x0`,
/// `range`, ...) to rows.
fn documented() -> BTreeMap<String, Vec<Row>> {
    let mut out: BTreeMap<String, Vec<Row>> = BTreeMap::new();
    let mut section: Option<String> = None;
    for line in DOC.lines() {
        if let Some(h) = line.strip_prefix("### ") {
            section = Some(if h.starts_with("Top level") {
                String::new()
            } else {
                first_code(h).expect("a section heading names its table in backticks")
            });
            continue;
        }
        let Some(sec) = &section else { continue };
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        // "| `key` | default | range | example | meaning |" splits into 7 cells.
        if cells.len() == 7 && cells[1].starts_with('`') {
            out.entry(sec.clone()).or_default().push(Row {
                key: first_code(cells[1]).unwrap(),
                default: cells[2].to_string(),
                range: cells[3].to_string(),
                example: cells[4].to_string(),
            });
        }
    }
    out
}

fn first_code(s: &str) -> Option<String> {
    let a = s.find('`')?;
    let b = s[a + 1..].find('`')?;
    Some(s[a + 1..a + 1 + b].to_string())
}

/// A cell holding exactly one backticked TOML value, parsed.
fn toml_value(cell: &str) -> Option<Value> {
    let inner = cell.strip_prefix('`')?.strip_suffix('`')?;
    if inner.contains('`') {
        return None;
    }
    let t: Table = toml::from_str(&format!("v = {inner}")).ok()?;
    t.get("v").cloned()
}

/// Where each documented section lives in a spec, and the spec to edit.
fn location(section: &str) -> (Vec<&'static str>, Table) {
    let mut base: Table = toml::from_str(GOOD).unwrap();
    let path = match section {
        "" => vec![],
        "[model]" => vec!["model"],
        "[grid]" => vec!["grid"],
        "grid.x0" => vec!["grid", "x0"],
        "range" => {
            let range: Table = toml::from_str("from = 1e-3\nto = 2e-3\ncount = 2").unwrap();
            base["model"]
                .as_table_mut()
                .unwrap()
                .insert("nu".into(), Value::Table(range));
            vec!["model", "nu"]
        }
        "[sample]" | "sample.region" => {
            base.remove("grid");
            let sample: Table = toml::from_str(
                "kind = \"random\"\nn = 4\nseed = 1\nregion = { x0 = [-1.0, 1.0], v0 = [0.0, 1.0] }",
            )
            .unwrap();
            base.insert("sample".into(), Value::Table(sample));
            if section == "[sample]" {
                vec!["sample"]
            } else {
                vec!["sample", "region"]
            }
        }
        "[physical]" => {
            base["model"].as_table_mut().unwrap().remove("nu");
            let physical: Table = toml::from_str(
                "m = 2.0\nk = 5.0e4\nc = 10.0\nv_belt = 0.05\nmu_k = 0.35\nmu_s = 0.45\ntau = 1e-3",
            )
            .unwrap();
            base.insert("physical".into(), Value::Table(physical));
            vec!["physical"]
        }
        "[integration]" => vec!["integration"],
        "[classifier]" => vec!["classifier"],
        "[cycle]" => vec!["cycle"],
        "[output]" => vec!["output"],
        other => panic!("docs/spec.md has a section `{other}` this test does not know"),
    };
    (path, base)
}

/// `spec` with `key = value` set in the table at `path` (created if missing).
fn with_key(mut spec: Table, path: &[&str], key: &str, value: Value) -> Table {
    let mut t = &mut spec;
    for p in path {
        t = t
            .entry(p.to_string())
            .or_insert_with(|| Value::Table(Table::new()))
            .as_table_mut()
            .unwrap();
    }
    t.insert(key.to_string(), value);
    spec
}

fn without_key(mut spec: Table, path: &[&str], key: &str) -> Table {
    let mut t = &mut spec;
    for p in path {
        match t.get_mut(*p).and_then(Value::as_table_mut) {
            Some(next) => t = next,
            None => return spec,
        }
    }
    t.remove(key);
    spec
}

fn parse(spec: &Table) -> Result<Plan, String> {
    let text = toml::to_string(spec).unwrap();
    Plan::from_toml(&text, "doc.toml").map_err(|e| format!("{e}\n--- spec ---\n{text}"))
}

/// The fields serde says the table at `path` accepts.
fn accepted(path: &[&str], base: Table) -> BTreeSet<String> {
    let spec = with_key(base, path, "zz_not_a_key", Value::Integer(1));
    let err = parse(&spec).expect_err("an unknown key must be refused");
    let line = err
        .lines()
        .find(|l| l.contains("unknown field `zz_not_a_key`"))
        .unwrap_or_else(|| panic!("no unknown-field message for {path:?}: {err}"));
    let expected = line
        .split_once("expected")
        .unwrap_or_else(|| panic!("no field list in: {line}"))
        .1;
    expected
        .split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect()
}

#[test]
fn documented_keys_are_the_accepted_keys() {
    let doc = documented();
    // Every table of the format is documented (the range's fields are checked below by
    // parsing, since serde reports no field list for the untagged number/list/range value).
    for section in [
        "",
        "[model]",
        "[physical]",
        "[grid]",
        "grid.x0",
        "range",
        "[sample]",
        "sample.region",
        "[integration]",
        "[classifier]",
        "[cycle]",
        "[output]",
    ] {
        assert!(
            doc.contains_key(section),
            "docs/spec.md has no table for `{section}`"
        );
    }
    let mut checked = 0;
    for (section, rows) in &doc {
        if section == "range" {
            continue;
        }
        let (path, base) = location(section);
        let documented: BTreeSet<String> = rows.iter().map(|r| r.key.clone()).collect();
        let parser = accepted(&path, base.clone());
        assert_eq!(
            documented, parser,
            "docs/spec.md `{section}` lists {documented:?}; the parser accepts {parser:?}"
        );
        // grid.v0 is the same type as grid.x0.
        if section == "grid.x0" {
            let v0 = accepted(&["grid", "v0"], base);
            assert_eq!(documented, v0, "grid.v0");
        }
        checked += 1;
    }
    assert_eq!(checked, 11);
}

/// The spec a documented key `key` of `section` is checked in, from the section's `base`
/// at `path`. The keys of the laws with true stick are checked in a spec of the first such law
/// that has them (a McMillan spec refuses them, and the other way round): xi and
/// v_d (documented at the Stribeck law's defaults) in a Stribeck spec.
/// The table keys (no scalars, so not in `keys()`) in a spec of the table law.
fn base_for_key(section: &str, (path, base): (&[&str], &Table), key: &str) -> Table {
    let table_key = ["friction_table", "friction_csv"].contains(&key);
    let stick_law = [FrictionLaw::Stribeck, FrictionLaw::Cubic]
        .into_iter()
        .find(|l| l.keys().contains(&key))
        .or(table_key.then_some(FrictionLaw::Table));
    match stick_law {
        Some(law) if section == "[model]" => {
            let mut b = without_key(base.clone(), path, "nu");
            b["model"]
                .as_table_mut()
                .unwrap()
                .insert("law".into(), Value::String(law.name().into()));
            b
        }
        // A measured curve in m/s under `[physical]`: a table-law system, which
        // has no mu_k and no surfaces.
        Some(FrictionLaw::Table) if section == "[physical]" => {
            let mut b = ["mu_k", "mu_s", "tau"]
                .into_iter()
                .fold(base.clone(), |b, k| without_key(b, path, k));
            b["model"]
                .as_table_mut()
                .unwrap()
                .insert("law".into(), Value::String("table".into()));
            b
        }
        _ => base.clone(),
    }
}

#[test]
fn documented_examples_parse_and_defaults_hold() {
    let mut examples = 0;
    let mut defaults = 0;
    for (section, rows) in documented() {
        let (path, base) = location(&section);
        parse(&base).expect("the base spec parses");
        for row in rows {
            let base = base_for_key(&section, (&path, &base), &row.key);
            // A key of the shared `[cycle]` table that only an atlas reads: a scan spec
            // refuses it, naming it.
            if row.range.starts_with("atlas only") {
                let v = toml_value(&row.example).expect("an atlas-only key has an example");
                let err = parse(&with_key(base.clone(), &path, &row.key, v))
                    .expect_err("a scan spec refuses an atlas-only key");
                let named = format!("{}.{}", path.join("."), row.key);
                assert!(err.contains(&named), "{err} does not name {named}");
                examples += 1;
                continue;
            }
            if let Some(mut v) = toml_value(&row.example) {
                if row.key == "friction_csv" {
                    // The example is relative to a spec in scans/; this spec is read from
                    // the crate's folder.
                    v = Value::String(format!("../../scans/{}", v.as_str().unwrap()));
                }
                let spec = with_key(base.clone(), &path, &row.key, v);
                if let Err(e) = parse(&spec) {
                    panic!(
                        "docs/spec.md example for `{section}` `{}` does not parse: {e}",
                        row.key
                    );
                }
                examples += 1;
            } else {
                assert_eq!(
                    row.example, "table",
                    "`{section}` `{}`: example is not a TOML value",
                    row.key
                );
            }
            if let Some(v) = toml_value(&row.default) {
                // The plan with the key left out equals the plan with the documented default.
                let omitted = parse(&without_key(base.clone(), &path, &row.key))
                    .unwrap_or_else(|e| panic!("`{section}` `{}` left out: {e}", row.key));
                let given = parse(&with_key(base.clone(), &path, &row.key, v))
                    .unwrap_or_else(|e| panic!("`{section}` `{}` = default: {e}", row.key));
                let strip = |mut p: Plan| {
                    p.spec_text.clear();
                    p
                };
                assert_eq!(
                    strip(omitted),
                    strip(given),
                    "docs/spec.md says `{section}` `{}` defaults to {}: the parser disagrees",
                    row.key,
                    row.default
                );
                defaults += 1;
            }
        }
    }
    // Provenance of the counts: the rows of docs/spec.md with a backticked example (every
    // key but the 6 table-valued top-level ones) and with a backticked default.
    assert!(examples >= 25, "only {examples} examples checked");
    assert!(defaults >= 14, "only {defaults} defaults checked");
}

#[test]
fn range_keys_are_exactly_the_documented_ones() {
    // serde's untagged value gives no field list: check that an undocumented key is refused
    // and that leaving out any required documented key is refused.
    let doc = documented();
    let rows = &doc["range"];
    let (path, base) = location("range");
    let bad = with_key(base.clone(), &path, "zz_not_a_key", Value::Integer(1));
    assert!(parse(&bad).is_err());
    for r in rows.iter().filter(|r| r.default == "required") {
        assert!(
            parse(&without_key(base.clone(), &path, &r.key)).is_err(),
            "`range` `{}` is documented as required",
            r.key
        );
    }
}
