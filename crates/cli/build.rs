//! Records the git revision for the provenance attributes of every output file. (The notice
//! that HDF5 is being compiled on a first build: crates/hdf5-notice, whose build script does
//! not wait for HDF5, and scripts/tools/cmake-shim.sh.)
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
}
