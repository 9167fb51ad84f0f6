//! `scripts/tools/plot_basins.py` on a real scan file: its failures are messages, not tracebacks.
//! Needs `python3` on PATH (skipped with a note otherwise); works with or without h5py.

use std::path::Path;
use std::process::{Command, Output};

const TINY: &str = r#"version = 1
[model]
law = "mcmillan"
nu = 1e-3
[grid]
x0 = { min = -3.0, max = 5.0, count = 5 }
v0 = { min = -4.0, max = 4.0, count = 3 }
[classifier]
t_max = 2000.0
[output]
path = "tiny.h5"
"#;

fn python_available() -> bool {
    Command::new("python3")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

fn plot(dir: &Path, pythonpath: Option<&Path>, args: &[&str]) -> Output {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/tools/plot_basins.py");
    let mut c = Command::new("python3");
    c.current_dir(dir).arg(script).args(args);
    if let Some(p) = pythonpath {
        c.env("PYTHONPATH", p);
    }
    c.output().expect("run python3")
}

fn tiny_scan(dir: &Path) {
    std::fs::write(dir.join("tiny.toml"), TINY).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .current_dir(dir)
        .args(["scan", "tiny.toml", "--quiet"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn map_out_of_range_or_missing_h5py_is_a_message() {
    if !python_available() {
        eprintln!("python3 not found: plot_basins.py not checked");
        return;
    }
    let d = tempfile::tempdir().unwrap();
    tiny_scan(d.path());
    // One map: index 9 does not exist. With h5py the script names the valid range; without,
    // it says how to install or run it. Either way no traceback (the old IndexError).
    let o = plot(d.path(), None, &["tiny.h5", "--map", "9", "-o", "p.png"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(!err.contains("Traceback"), "{err}");
    assert!(
        err.contains("--map 9 is out of range; valid: 0 (the file holds one map)")
            || err.contains("python3 -m pip install h5py matplotlib numpy"),
        "{err}"
    );
    assert!(!d.path().join("p.png").exists());
}

#[test]
fn missing_h5py_says_how_to_run_the_script() {
    if !python_available() {
        eprintln!("python3 not found: plot_basins.py not checked");
        return;
    }
    // A PYTHONPATH whose h5py fails to import stands in for a Python without h5py.
    let d = tempfile::tempdir().unwrap();
    std::fs::write(
        d.path().join("h5py.py"),
        "raise ImportError(\"No module named 'h5py'\")\n",
    )
    .unwrap();
    let o = plot(d.path(), Some(d.path()), &["x.h5", "-o", "p.png"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(!err.contains("Traceback"), "{err}");
    assert!(err.contains("uv run scripts/tools/plot_basins.py"), "{err}");
    assert!(
        err.contains("python3 -m pip install h5py matplotlib numpy"),
        "{err}"
    );
}
