//! Helper for `scripts/ci/slurm-ci.sh`: do two scan (or atlas) files hold the same data?
//!
//! `squeal_store::content_digest` hashes every dataset's values and every attribute of every
//! group (not the byte layout), so a merged sharded scan and a single run of the same spec
//! have equal digests exactly when they hold the same data. The cluster script runs
//!
//! ```text
//! SQUEAL_SAME_A=merged.h5 SQUEAL_SAME_B=single.h5 cargo test --test e2e -- --ignored same_content::
//! ```

use std::path::PathBuf;

fn env_path(name: &str) -> PathBuf {
    PathBuf::from(
        std::env::var_os(name).unwrap_or_else(|| panic!("set {name} to the path of a scan file")),
    )
}

#[test]
#[ignore = "run by scripts/ci/slurm-ci.sh with SQUEAL_SAME_A and SQUEAL_SAME_B set"]
fn files_hold_the_same_content() {
    let (a, b) = (env_path("SQUEAL_SAME_A"), env_path("SQUEAL_SAME_B"));
    let da = squeal_store::content_digest(&a).expect("first file readable");
    let db = squeal_store::content_digest(&b).expect("second file readable");
    if !squeal_store::atlas::is_atlas_file(&a) {
        let (ia, ib) = (
            squeal_store::read_info(&a).expect("first file is a scan file"),
            squeal_store::read_info(&b).expect("second file is a scan file"),
        );
        // The label counts first: a readable difference when the digests differ.
        let counts = |i: &squeal_store::FileInfo| -> Vec<[u64; 5]> {
            (0..i.maps)
                .map(|m| squeal_store::map_labels(&i.path, m).expect("labels"))
                .map(|l| squeal_scan::MapSummary::of(&l, i.x0.len(), i.sample).counts)
                .collect()
        };
        assert_eq!(
            counts(&ia),
            counts(&ib),
            "{} vs {}",
            a.display(),
            b.display()
        );
    }
    assert_eq!(
        da,
        db,
        "{} and {} differ in content",
        a.display(),
        b.display()
    );
    println!(
        "same content: {} = {} (digest {da})",
        a.display(),
        b.display()
    );
}

/// The digest is the same for two runs of one spec and differs for another belt speed. (Runs
/// end at t = 300: the labels need not be final for a digest; to t_max's default of 5000
/// the starts near the cycle took 14 s per run on a loaded machine.)
#[test]
fn the_digest_sees_a_changed_parameter() {
    let dir = tempfile::tempdir().unwrap();
    let spec = |lambda: f64| {
        format!(
            "version = 1\nname = \"same\"\n[model]\nlaw = \"mcmillan\"\nnu = 1e-3\nlambda = {lambda:?}\n\
             [grid]\nx0 = {{ min = -3.0, max = 5.0, count = 6 }}\nv0 = {{ min = -4.0, max = 4.0, count = 5 }}\n\
             [cycle]\nlocate = false\n[classifier]\nt_max = 300.0\n[output]\npath = \"x.h5\"\n"
        )
    };
    let mut digests = Vec::new();
    for (name, lambda) in [("a", 3.0), ("b", 3.0), ("c", 2.5)] {
        let toml = dir.path().join(format!("{name}.toml"));
        std::fs::write(&toml, spec(lambda)).unwrap();
        let out = dir.path().join(format!("{name}.h5"));
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_squeal"))
            .args([
                "scan",
                toml.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
                "--quiet",
            ])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        digests.push(squeal_store::content_digest(&out).unwrap());
    }
    assert_eq!(digests[0], digests[1], "two runs of one spec");
    assert_ne!(digests[0], digests[2], "lambda 3 and 2.5");
}
