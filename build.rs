//! Records the git revision for the provenance attributes of every output file, and says on
//! the first build of a profile that HDF5 is being compiled from source.
use std::path::Path;
use std::process::Command;

fn git(args: &[&str]) -> Option<String> {
    Command::new("git")
        .args(args)
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
}

fn main() {
    let rev = git(&["describe", "--always", "--dirty", "--abbrev=12"])
        .unwrap_or_else(|| "unknown".to_string());
    println!("cargo:rustc-env=SQUEAL_GIT_REV={rev}");
    // Rebuild when HEAD moves (a commit changes the branch's ref, not HEAD itself, which
    // only names the branch) or the index changes; paths asked of git, so a worktree,
    // whose `.git` is a file, works too.
    let mut watched = vec!["HEAD".to_string(), "index".into(), "packed-refs".into()];
    watched.extend(git(&["symbolic-ref", "-q", "HEAD"]));
    for name in watched {
        if let Some(path) = git(&["rev-parse", "--git-path", &name]) {
            println!("cargo:rerun-if-changed={path}");
        }
    }
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
