//! The table law in specs: `friction_table = [[s, mu], ...]` or
//! `friction_csv = "file.csv"` under `[model]` with `law = "table"`, exactly one, for scans
//! and atlases; hostile tables refused naming the key and the row or line. New keys: each
//! test fails on the code before (there `law = "table"` was an unknown variant).

use squeal_core::{FrictionLaw, FrictionTable};
use squeal_scan::atlas::AtlasPlan;
use squeal_scan::spec::Plan;

const GRID: &str = "[grid]\nx0 = { min = -2.0, max = 2.0, count = 8 }\nv0 = { min = 0.0, max = 2.0, count = 8 }\n[output]\npath = \"out/t.h5\"\n";

/// A scan spec of `law = "table"` with `model` lines.
fn scan(model: &str) -> String {
    format!("version = 1\n[model]\nlaw = \"table\"\n{model}\n{GRID}")
}

/// The shipped spec reads its CSV relative to its own folder: bSTAB's Stribeck law sampled
/// at 45 rows, the static coefficient `mu_s = mu_d mu_sd = 1`, the last row `mu_d = 0.5`.
#[test]
fn the_shipped_table_spec_reads_its_csv() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scans/table-stribeck.toml"
    );
    let plan = Plan::from_file(std::path::Path::new(path)).unwrap();
    assert_eq!(plan.law(), FrictionLaw::Table);
    let t = plan.maps[0].law.table().unwrap();
    assert_eq!(t.rows().len(), 45);
    assert_eq!((t.mu_s(), t.rows()[44]), (1.0, (10.0, 0.5)));
    assert_eq!((plan.maps[0].nu, plan.maps[0].lambda), (0.05, 1.5));
}

/// An inline table and a sweep of `v_d`: every map holds the same (interned) table; an
/// atlas over `v_d` reads the same keys.
#[test]
fn an_inline_table_scans_and_atlases() {
    let rows = "friction_table = [[0.0, 0.6], [0.5, 0.45], [2.0, 0.4]]";
    let plan = Plan::from_toml(&scan(&format!("{rows}\nv_d = [1.0, 1.5]")), "s.toml").unwrap();
    let want = FrictionTable::new(&[(0.0, 0.6), (0.5, 0.45), (2.0, 0.4)]).unwrap();
    assert_eq!(plan.maps.len(), 2);
    for p in &plan.maps {
        assert!(std::ptr::eq(p.law.table().unwrap(), want));
    }
    let atlas = format!(
        "version = 1\n[model]\nlaw = \"table\"\n{rows}\nv_d = [1.0, 1.5]\n[output]\npath = \"out/a.h5\"\n"
    );
    let a = AtlasPlan::from_toml(&atlas, "a.toml").unwrap();
    assert_eq!(a.space.n_points(), 2);
    assert!(std::ptr::eq(
        a.space.params_at(1).law.table().unwrap(),
        want
    ));
    assert_eq!(a.space.params_at(1).lambda, 1.5);
}

/// Hostile tables and keys, each refused naming the key (and the row or line).
#[test]
fn hostile_tables_are_refused_by_name() {
    let dir = std::env::temp_dir().join(format!("squeal-table-spec-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("bad.csv"), "s,mu\n0,0.5\n0.5,0.4\n0.4,0.3\n").unwrap();
    let spec_path = dir.join("s.toml");
    let spec_path = spec_path.to_str().unwrap();
    let cases = [
        (
            scan("friction_table = [[0.0, 0.5], [1.0, 0.4], [0.5, 0.3]]"),
            "`model.friction_table` = given: friction table row 3: slip speed 0.5 not above",
        ),
        (
            scan("friction_table = [[0.0, 0.5], [1.0, -0.4]]"),
            "friction table row 2: mu = -0.4",
        ),
        (
            scan("friction_table = [[0.0, 0.5], [nan, 0.4]]"),
            "friction table row 2: slip speed NaN",
        ),
        (scan("friction_table = [[0.0, 0.5]]"), "1 rows given"),
        (
            scan("friction_table = [[0.1, 0.5], [1.0, 0.4]]"),
            "first row must be at slip speed 0",
        ),
        (
            scan("friction_csv = \"bad.csv\""),
            "`model.friction_csv` = \"bad.csv\": ",
        ),
        (
            scan("friction_csv = \"nowhere.csv\""),
            "nowhere.csv: No such file",
        ),
        (
            scan("friction_csv = \"bad.csv\"\nfriction_table = [[0.0, 0.5], [1.0, 0.4]]"),
            "`model.friction_csv` = given with model.friction_table",
        ),
        (
            scan(""),
            "`model.friction_table` = missing: law = \"table\" needs its curve",
        ),
        (
            scan("friction_table = [[0.0, 0.5], [1.0, 0.4]]\nmu_d = 0.5"),
            "`model.mu_d` = given",
        ),
        // With [physical] the curve is the physical system's, in m/s: one in [model] is
        // refused by name (crates/scan/src/spec/physical.rs tests the SI curve).
        (
            scan("friction_table = [[0.0, 0.5], [1.0, 0.4]]").replace(
                "[grid]",
                "[physical]\nm = 1.0\nk = 1.0\nc = 0.1\nv_belt = 1.0\nmu_k = 0.4\n[grid]",
            ),
            "`model.friction_table` = given with [physical]",
        ),
        // The Stribeck law without either key is as before.
        (scan("").replace("\"table\"", "\"stribeck\""), ""),
        (
            format!("version = 1\n[model]\nlaw = \"stribeck\"\nfriction_csv = \"bad.csv\"\n{GRID}"),
            "`model.friction_csv` = given with law = \"stribeck\": no key: only law = \"table\"",
        ),
    ];
    for (text, words) in cases {
        let r = Plan::from_toml(&text, spec_path);
        if words.is_empty() {
            assert!(r.is_ok(), "{r:?}");
            continue;
        }
        let e = r.unwrap_err().to_string();
        assert!(e.contains(words), "{words}\n{e}");
    }
    // The bad CSV's line is named by its number in the file.
    let e = Plan::from_toml(&scan("friction_csv = \"bad.csv\""), spec_path)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("bad.csv: friction table line 4: slip speed 0.4 not above"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
