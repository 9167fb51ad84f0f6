//! A file's stored spec describes what was run: a value outside a bound of today (one
//! added or tightened after the file was written) still reads, wherever the spec is read
//! back (`info`, `render`, `merge`, the make-like rerun rule). Before, readers checked the
//! stored spec against today's bounds, so each new bound made old files unreadable.

use std::path::Path;

use crate::physical_outputs::{run, store_spec};

/// A small scan (McMillan, nu = 0.01, 3 x 2 cells, one row per block so that two shards
/// each hold a block), fast: runs stop at t_max = 200 and nothing is audited.
const SCAN: &str = r#"
version = 1
name = "s"
[model]
law = "mcmillan"
nu = 0.01
[grid]
x0 = { min = -1.0, max = 2.0, count = 3 }
v0 = { min = -1.0, max = 1.0, count = 2 }
block_rows = 1
[classifier]
t_max = 200.0
audit_every = 0
[output]
path = "s.h5"
"#;

/// A two-point atlas (nu = 0.01 and 0.02) without boundaries.
const ATLAS: &str = r#"
version = 1
name = "two"
[model]
law = "mcmillan"
nu = [0.01, 0.02]
[boundaries]
fold = false
critical = false
[output]
path = "a.h5"
"#;

/// `squeal info --json FILE` in `dir`, parsed.
fn info_json(dir: &Path, file: &str) -> serde_json::Value {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(["info", "--json", file])
        .current_dir(dir)
        .output()
        .expect("the squeal binary runs");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "info {file}: {err}");
    serde_json::from_slice(&o.stdout).unwrap_or_else(|e| panic!("info --json {file}: {e}"))
}

/// A scan's shards whose stored spec has `fp_radius = 1e-12`, below today's lower bound
/// (`bounds::MIN_FP_RADIUS` = 1e-10, which came after files were written with smaller
/// radii): `info` and `render` read a shard (they read its attributes, and did before),
/// `merge` reads the stored spec and joins them (before: "`classifier.fp_radius` = 1e-12:
/// a radius in [1e-10, 0.01]", refused), and the merged file records the stored radius.
/// A rerun of today's spec onto the merged file is judged by what differs, the classifier
/// (before: the stored spec did not read, and the refusal named only `spec`).
#[test]
fn a_scan_whose_stored_spec_breaks_a_bound_of_today_still_reads() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("s.toml"), SCAN).unwrap();
    let old = SCAN.replace("t_max = 200.0", "t_max = 200.0\nfp_radius = 1e-12");
    std::fs::write(d.join("old.toml"), &old).unwrap();
    let (ok, err) = run(d, &["scan", "old.toml", "--quiet", "-o", "y.h5"]);
    assert!(!ok && err.contains("classifier.fp_radius"), "{err}");
    for k in ["1/2", "2/2"] {
        let name = format!("s{}.h5", &k[..1]);
        let (ok, err) = run(d, &["scan", "s.toml", "-o", &name, "--shard", k, "--quiet"]);
        assert!(ok, "{err}");
        store_spec(&d.join(&name), &old);
    }
    let (ok, err) = run(d, &["info", "s1.h5"]);
    assert!(ok, "{err}");
    let (ok, err) = run(d, &["render", "s1.h5", "-o", "s1.png"]);
    assert!(ok, "{err}");
    let (ok, err) = run(d, &["merge", "s1.h5", "s2.h5", "-o", "m.h5", "--no-render"]);
    assert!(ok, "{err}");
    let info = info_json(d, "m.h5");
    assert_eq!(info["attributes"]["fp_radius"], "1e-12", "{info}");
    let (ok, err) = run(d, &["render", "m.h5", "-o", "m.png"]);
    assert!(ok, "{err}");
    let (ok, err) = run(d, &["scan", "s.toml", "-o", "m.h5", "--quiet"]);
    assert!(!ok && err.contains("`classifier` differs"), "{err}");
}

/// An atlas whose stored spec has `phi = 2e-6`, below today's lower bound
/// (`squeal_core::law::MIN_PHI` = 1e-5, which came after files were written with smaller
/// angles): `info` reads it and reports the stored value (before: "`model.phi` = 2e-6:
/// an angle in [1e-5, pi/2]", refused), `render` draws it, and its shards merge.
#[test]
fn an_atlas_whose_stored_spec_breaks_a_bound_of_today_still_reads() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("a.toml"), ATLAS).unwrap();
    let old = ATLAS.replace("nu = [0.01, 0.02]", "nu = [0.01, 0.02]\nphi = 2e-6");
    std::fs::write(d.join("old.toml"), &old).unwrap();
    let (ok, err) = run(d, &["atlas", "old.toml", "--quiet", "--no-render"]);
    assert!(!ok && err.contains("model.phi"), "{err}");
    for k in ["1/2", "2/2"] {
        let name = format!("a{}.h5", &k[..1]);
        let args = [
            "atlas",
            "a.toml",
            "-o",
            &name,
            "--shard",
            k,
            "--quiet",
            "--no-render",
        ];
        let (ok, err) = run(d, &args);
        assert!(ok, "{err}");
        store_spec(&d.join(&name), &old);
    }
    let info = info_json(d, "a1.h5");
    assert_eq!(info["fixed"]["phi"]["value"], 2e-6, "{info}");
    let (ok, err) = run(d, &["merge", "a1.h5", "a2.h5", "-o", "m.h5", "--no-render"]);
    assert!(ok, "{err}");
    let info = info_json(d, "m.h5");
    assert_eq!(info["fixed"]["phi"]["value"], 2e-6, "{info}");
    let (ok, err) = run(d, &["render", "m.h5", "-o", "m.png"]);
    assert!(ok, "{err}");
    let (ok, err) = run(d, &["info", "m.h5"]);
    assert!(ok, "{err}");
}

/// What a plan cannot be built without is still refused, and the error says it is the
/// file's stored spec and names the key: a grid count that is no count.
#[test]
fn a_stored_spec_that_cannot_be_a_plan_is_refused_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("a.toml"), ATLAS).unwrap();
    let (ok, err) = run(d, &["atlas", "a.toml", "--quiet", "--no-render"]);
    assert!(ok, "{err}");
    let bad = ATLAS.replace(
        "nu = [0.01, 0.02]",
        "nu = { from = 0.01, to = 0.02, count = -2 }",
    );
    store_spec(&d.join("a.h5"), &bad);
    let (ok, err) = run(d, &["info", "a.h5"]);
    assert!(
        !ok && err.contains("this file's stored spec") && err.contains("`model.nu.count`"),
        "{err}"
    );
}
