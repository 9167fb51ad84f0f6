//! With the `static-hdf5` feature, warns when this profile's target folder holds no HDF5
//! library yet: cargo otherwise shows only `Building ... hdf5-metno-src` for the several
//! minutes the C library takes to compile. This crate has no dependencies, so the script
//! does not wait for HDF5 (a script of a crate that depends on HDF5 runs after it), and
//! squeal-core depends on it, so cargo schedules it among the first units (about 30 s into
//! a fresh build). On a terminal the CMake shim, scripts/tools/cmake-shim.sh, also says it
//! as HDF5's compile starts.
use std::path::Path;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    if std::env::var_os("CARGO_FEATURE_STATIC_HDF5").is_none() {
        return;
    }
    let Some(out) = std::env::var_os("OUT_DIR") else {
        return;
    };
    // OUT_DIR is <target>/<profile>/build/squeal-hdf5-notice-<hash>/out.
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
        // A path that never exists: this script runs again on every build until HDF5 is
        // built (cargo would otherwise repeat this warning on every later build).
        println!(
            "cargo:rerun-if-changed={}",
            Path::new(&out).join("until-hdf5-is-built").display()
        );
        println!(
            "cargo:warning=first build of this profile: HDF5 is being compiled from source and \
             linked statically (several minutes more; cargo shows `Building ... hdf5-metno-src` \
             meanwhile). Later builds reuse it. See docs/building.md."
        );
    }
}
