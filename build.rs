//! Records the git revision for the provenance attributes of every output file, and says on
//! the first build of a profile that HDF5 is being compiled from source.
use std::path::Path;

fn main() {
    let rev = std::process::Command::new("git")
        .args(["describe", "--always", "--dirty", "--abbrev=12"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_else(|| "unknown".to_string());
    println!("cargo:rustc-env=SQUEAL_GIT_REV={rev}");
    println!("cargo:rerun-if-changed=.git/HEAD");
    println!("cargo:rerun-if-changed=.git/index");
    hdf5_notice();
}

/// With the default `static-hdf5` feature, warns when this profile's target folder holds no
/// HDF5 library yet: cargo otherwise shows only `Building ... hdf5-metno-src` for the several
/// minutes the C library takes to compile (README, "Two commands").
fn hdf5_notice() {
    if std::env::var_os("CARGO_FEATURE_STATIC_HDF5").is_none() {
        return;
    }
    let Some(out) = std::env::var_os("OUT_DIR") else {
        return;
    };
    // OUT_DIR is <target>/<profile>/build/squeal-<hash>/out.
    let Some(build) = Path::new(&out).ancestors().nth(2) else {
        return;
    };
    let built = std::fs::read_dir(build).is_ok_and(|entries| {
        entries.flatten().any(|e| {
            e.file_name()
                .to_string_lossy()
                .starts_with("hdf5-metno-src-")
                && e.path().join("out").join("lib").is_dir()
        })
    });
    if !built {
        println!(
            "cargo:warning=first build of this profile: HDF5 is being compiled from source and \
             linked statically (several minutes more; cargo shows `Building ... hdf5-metno-src` \
             meanwhile). Later builds reuse it. See README.md, \"Two commands\"."
        );
    }
}
