//! What a new user meets first: the words of `squeal compare` on maps nothing decided.

use std::path::Path;
use std::process::{Command, Output};

fn squeal(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the squeal binary runs")
}

/// A 12 x 12 scan whose runs stop at t = 1, long before any decision (no cycle located,
/// no early stopping): every one of its 144 cells is undecided.
const UNDECIDED: &str = r#"version = 1
name = "undecided"
[model]
law = "mcmillan"
nu = 1e-3
lambda = 3.0
tau = 0.31622776601683794
phi = 1.0
[grid]
x0 = { min = -3.0, max = 5.0, count = 12 }
v0 = { min = -4.0, max = 4.0, count = 12 }
[classifier]
t_max = 1.0
early_stop = "none"
[cycle]
locate = false
[output]
path = "u.h5"
"#;

/// Two identical fully undecided maps said "0 of 144 cells agree (0.0000%)" (and JSON
/// `share` 0): agreement is now counted over the cells decided in either file, and the
/// cells undecided in both are counted apart.
#[test]
fn compare_of_maps_nothing_decided_says_so() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("u.toml"), UNDECIDED).unwrap();
    let o = squeal(d.path(), &["scan", "u.toml", "--quiet"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = squeal(d.path(), &["compare", "u.h5", "u.h5"]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains(": no cell decided in either file; 144 undecided in both; 0 not computed"),
        "{out}"
    );
    assert!(!out.contains("cells agree"), "{out}");
    let o = squeal(d.path(), &["compare", "u.h5", "u.h5", "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("one JSON object");
    let m = &v["maps"][0];
    assert_eq!(m["decided"], 0, "{v}");
    assert_eq!(m["undecided_both"], 144, "{v}");
    assert!(m["share"].is_null(), "no share of nothing: {v}");
    // A share the maps cannot have is not reached.
    let o = squeal(
        d.path(),
        &["compare", "u.h5", "u.h5", "--min-agreement", "0.5"],
    );
    assert_eq!(
        o.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
}

/// The first-build notice about HDF5 appeared about six minutes into the build: the root
/// build script printed it, and cargo runs a package's build script only once the build
/// scripts of its dependencies have run, HDF5's own (the C library's compilation) among
/// them. The script that prints it must belong to a package with no dependencies, which
/// does not wait for HDF5, and squeal-core, which every crate builds on, must depend on it.
/// (On a terminal the CMake shim also says it as HDF5's compile starts:
/// scripts/tools/cmake-shim.sh.)
#[test]
fn the_hdf5_notice_comes_from_a_build_script_that_runs_first() {
    let out = Command::new(env!("CARGO"))
        .args([
            "metadata",
            "--format-version",
            "1",
            "--no-deps",
            "--offline",
        ])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("cargo metadata");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let meta: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let packages = meta["packages"].as_array().unwrap();
    let mut noticing = Vec::new();
    for p in packages {
        for t in p["targets"].as_array().unwrap() {
            let build = t["kind"]
                .as_array()
                .unwrap()
                .iter()
                .any(|k| k == "custom-build");
            let src = std::fs::read_to_string(t["src_path"].as_str().unwrap()).unwrap_or_default();
            if build && src.contains("HDF5 is being compiled from source") {
                noticing.push(p);
            }
        }
    }
    assert_eq!(noticing.len(), 1, "one build script prints the notice");
    let notice = noticing[0];
    let name = notice["name"].as_str().unwrap();
    let deps: Vec<&str> = notice["dependencies"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| d["name"].as_str().unwrap())
        .collect();
    assert!(
        deps.is_empty(),
        "{name} depends on {deps:?}: its build script waits for theirs"
    );
    // squeal-store links HDF5; squeal-core is what every crate of the workspace builds on,
    // and cargo starts first the units that most others wait for: as a dependency of the
    // store alone the notice came 127 s into an idle fresh release build of 306 s, as one of
    // the core 28 s in (HDF5's own compile starts 14 s in).
    for user in ["squeal-store", "squeal-core"] {
        let package = packages.iter().find(|p| p["name"] == user).unwrap();
        assert!(
            package["dependencies"]
                .as_array()
                .unwrap()
                .iter()
                .any(|d| d["name"] == name),
            "{user} does not depend on {name}: cargo would schedule the notice late"
        );
    }
}
