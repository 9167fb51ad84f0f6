//! Odd files and other users at the paths squeal reads and writes: another
//! user's lock is refused naming its owner and never removed; an input of a merge is never
//! removed or renamed; a FIFO is refused instead of blocking for ever; pictures are not
//! overwritten; the output's folder and lock come before the pilot, and a signal during the
//! pilot says what happened.
//!
//! The cases of two users need root to make a file another user owns and a way to run the
//! binary as an unprivileged user (`setpriv`): without them they are skipped, saying why.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// The user owning the foreign lock ("nobody") and the user running squeal: two ordinary
/// users, as in a shared folder.
const OWNER: u32 = 65534;
const OTHER: u32 = 65533;

fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_squeal")
}

/// Runs squeal in `dir` with `args`, killed after `limit` (a run blocked on a FIFO never
/// ends): its output, or `None` if it had to be killed.
pub(crate) fn squeal_within(cmd: &mut Command, limit: Duration) -> Option<Output> {
    let mut child = cmd
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the squeal binary runs");
    let t0 = Instant::now();
    while t0.elapsed() < limit {
        if child.try_wait().unwrap().is_some() {
            return Some(child.wait_with_output().unwrap());
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let _ = child.kill();
    let _ = child.wait();
    None
}

fn squeal(dir: &Path, args: &[&str]) -> Output {
    let mut c = Command::new(bin());
    c.args(args).current_dir(dir);
    squeal_within(&mut c, Duration::from_secs(120)).expect("squeal ends within 120 s")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn refused(o: &Output, needle: &str) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "should fail with code 2: {err}");
    assert!(!err.contains("panicked"), "panic: {err}");
    assert!(
        err.contains(needle),
        "message should contain {needle:?}: {err}"
    );
}

/// A 3 x 3 scan of a fraction of a second, written to `name.h5`.
fn tiny_spec(dir: &Path, name: &str) {
    let spec = format!(
        "version = 1\n[model]\nlaw = \"mcmillan\"\nnu = 1e-2\n[grid]\n\
         x0 = {{ min = 0.0, max = 2.0, count = 3 }}\nv0 = {{ min = -1.0, max = 1.0, count = 3 }}\n\
         [classifier]\nt_max = 500.0\n[output]\npath = \"{name}.h5\"\n"
    );
    std::fs::write(dir.join(format!("{name}.toml")), spec).unwrap();
}

fn mkfifo(p: &Path) -> bool {
    Command::new("mkfifo")
        .arg(p)
        .status()
        .map(|s| s.success())
        .unwrap_or(false)
}

/// Whether this test can act as two users: root (to give a file to another user) and
/// `setpriv` (to run squeal as another user). The reason when not.
fn two_users() -> Result<(), String> {
    let uid = std::fs::metadata("/proc/self").map(|m| {
        use std::os::unix::fs::MetadataExt;
        m.uid()
    });
    if uid.ok() != Some(0) {
        return Err("not root: cannot make a file owned by another user".into());
    }
    let ok = Command::new("setpriv")
        .args(["--reuid=65533", "--regid=65533", "--clear-groups", "true"])
        .status()
        .map(|s| s.success())
        .unwrap_or(false);
    if !ok {
        return Err("setpriv cannot run a command as another user here".into());
    }
    Ok(())
}

/// squeal run as user `OTHER` (uid and gid) in `dir`.
fn as_other(dir: &Path, args: &[&str]) -> Output {
    let mut c = Command::new("setpriv");
    c.args([
        format!("--reuid={OTHER}"),
        format!("--regid={OTHER}"),
        "--clear-groups".into(),
        bin().into(),
    ])
    .args(args)
    .current_dir(dir);
    squeal_within(&mut c, Duration::from_secs(120)).expect("squeal ends within 120 s")
}

/// A folder every user may write in (`mode`: 0o777, or 0o1777 sticky as /tmp), with the
/// tiny spec `s.toml` (output `s.h5`) readable by all.
fn shared_folder(mode: u32) -> (tempfile::TempDir, PathBuf) {
    use std::os::unix::fs::PermissionsExt;
    let t = tempfile::tempdir().unwrap();
    let d = t.path().join("shared");
    std::fs::create_dir(&d).unwrap();
    std::fs::set_permissions(t.path(), std::fs::Permissions::from_mode(0o755)).unwrap();
    std::fs::set_permissions(&d, std::fs::Permissions::from_mode(mode)).unwrap();
    tiny_spec(&d, "s");
    (t, d)
}

/// A file of user `OWNER` with mode 0600 (its owner's umask 077), holding `text`.
fn owned_by_other(p: &Path, text: &str) {
    use std::os::unix::fs::PermissionsExt;
    std::fs::write(p, text).unwrap();
    std::os::unix::fs::chown(p, Some(OWNER), Some(OWNER)).unwrap();
    std::fs::set_permissions(p, std::fs::Permissions::from_mode(0o600)).unwrap();
}

/// User A (umask 077) runs a scan in a shared folder; user B runs the
/// same. B could not read A's lock, took it for garbage and removed it; with `--force` it
/// removed A's journal too, and both wrote `out.h5`. In a sticky folder the removal failed
/// and B was told the output was written by "process 0 on host ?". Now B is refused,
/// naming A's uid and the lock, and A's lock and journal stay.
#[test]
fn another_users_unreadable_lock_is_refused_naming_its_owner_and_kept() {
    if let Err(why) = two_users() {
        eprintln!("skipping: {why}");
        return;
    }
    // A's run: a live process (this test's), as the lock records it.
    let live = format!("{} {} 0\n", std::process::id(), "some-host");
    for mode in [0o777, 0o1777] {
        let (_t, d) = shared_folder(mode);
        let lock = d.join("s.h5.lock");
        let journal = d.join("s.h5.journal");
        owned_by_other(&lock, &live);
        owned_by_other(&journal, "A's journal");
        for force in [false, true] {
            let mut args = vec!["scan", "s.toml", "--quiet"];
            if force {
                args.push("--force");
            }
            let o = as_other(&d, &args);
            refused(&o, &format!("locked by user uid {OWNER}"));
            refused(&o, "(lock s.h5.lock: this user cannot read it");
            assert!(
                !stderr(&o).contains("process 0 on host ?"),
                "{}",
                stderr(&o)
            );
            assert!(
                lock.exists(),
                "A's lock removed (mode {mode:o}, force {force})"
            );
            assert_eq!(std::fs::read_to_string(&journal).unwrap(), "A's journal");
            assert!(!d.join("s.h5").exists());
        }
    }
}

/// With an output folder this user cannot write, an atlas ran its pilot
/// (74 s) before "cannot create the lock ... Permission denied". The lock comes first now:
/// refused before any estimate is printed.
#[test]
fn an_unwritable_output_folder_is_refused_before_the_pilot() {
    if let Err(why) = two_users() {
        eprintln!("skipping: {why}");
        return;
    }
    use std::os::unix::fs::PermissionsExt;
    let (_t, d) = shared_folder(0o777);
    let locked = d.join("ro");
    std::fs::create_dir(&locked).unwrap();
    std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o755)).unwrap();
    let spec = "version = 1\n[model]\nlaw = \"mcmillan\"\nnu = [1e-3, 2e-3]\n\
                [boundaries]\nfold = false\ncritical = false\n[output]\npath = \"ro/a.h5\"\n";
    std::fs::write(d.join("a.toml"), spec).unwrap();
    for cmd in ["atlas", "scan"] {
        let args: Vec<&str> = if cmd == "scan" {
            vec!["scan", "s.toml", "-o", "ro/s.h5"]
        } else {
            vec!["atlas", "a.toml", "--no-render"]
        };
        let o = as_other(&d, &args);
        refused(&o, "cannot create the lock");
        let err = stderr(&o);
        assert!(!err.contains("roughly"), "the estimate ran first: {err}");
    }
}

/// `merge a.h5 all.h5.lock -o all.h5` removed the input as a garbage
/// lock; an input `all2.h5.tmp` (`-o all2.h5`) was consumed. Both are refused, and the
/// inputs stay as they were.
#[test]
fn a_merge_never_removes_or_renames_an_input() {
    let d = tempfile::tempdir().unwrap();
    tiny_spec(d.path(), "m");
    for (k, out) in [("1/2", "s1.h5"), ("2/2", "s2.h5")] {
        let o = squeal(
            d.path(),
            &["scan", "m.toml", "--shard", k, "-o", out, "--quiet"],
        );
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let s2 = std::fs::read(d.path().join("s2.h5")).unwrap();
    for (input, out, what) in [
        ("all.h5.lock", "all.h5", "lock"),
        ("all2.h5.tmp", "all2.h5", "temporary file"),
        ("all3.h5.journal", "all3.h5", "journal"),
    ] {
        let p = d.path().join(input);
        std::fs::write(&p, &s2).unwrap();
        for force in [false, true] {
            let mut args = vec!["merge", "s1.h5", input, "-o", out, "--no-render"];
            if force {
                args.push("--force");
            }
            let o = squeal(d.path(), &args);
            refused(&o, &format!("is the {what} of the output"));
            assert_eq!(std::fs::read(&p).unwrap(), s2, "{input} changed");
            assert!(!d.path().join(out).exists());
        }
    }
}

/// `merge -o dir.h5 --force` (a folder at the output) left `dir.h5.tmp`
/// behind; a merge to a name not ending in `.h5` was accepted.
#[test]
fn a_merge_refuses_a_folder_or_a_name_without_h5_and_leaves_nothing() {
    let d = tempfile::tempdir().unwrap();
    tiny_spec(d.path(), "m");
    for (k, out) in [("1/2", "s1.h5"), ("2/2", "s2.h5")] {
        let o = squeal(
            d.path(),
            &["scan", "m.toml", "--shard", k, "-o", out, "--quiet"],
        );
        assert!(o.status.success(), "{}", stderr(&o));
    }
    std::fs::create_dir(d.path().join("dir.h5")).unwrap();
    let o = squeal(
        d.path(),
        &["merge", "s1.h5", "s2.h5", "-o", "dir.h5", "--force"],
    );
    refused(&o, "dir.h5 is a directory, not a regular file");
    assert!(!d.path().join("dir.h5.tmp").exists());
    assert!(!d.path().join("dir.h5.lock").exists());
    let o = squeal(
        d.path(),
        &["merge", "s1.h5", "s2.h5", "-o", "all.txt", "--no-render"],
    );
    refused(&o, "output all.txt: expected a file name ending in .h5");
    assert!(!d.path().join("all.txt").exists());
}

/// A FIFO at the spec's path, at `OUT.h5`, at `OUT.h5.lock`, or at the
/// journal under `--resume` blocked for ever with no message. Each is refused naming what
/// is there, within seconds (the limit here is 60 s).
#[test]
fn a_fifo_anywhere_is_refused_instead_of_blocking() {
    let d = tempfile::tempdir().unwrap();
    if !mkfifo(&d.path().join("probe")) {
        eprintln!("skipping: mkfifo did not run");
        return;
    }
    tiny_spec(d.path(), "f");
    let cases: [(&str, &[&str], &str); 4] = [
        ("pipe.toml", &["scan", "pipe.toml"], "it is a FIFO"),
        ("f.h5", &["scan", "f.toml", "--quiet"], "f.h5 is a FIFO"),
        (
            "f.h5.lock",
            &["scan", "f.toml", "--quiet"],
            "f.h5.lock is not a lock file (a FIFO (named pipe))",
        ),
        (
            "f.h5.journal",
            &["scan", "f.toml", "--quiet", "--resume"],
            "f.h5.journal is a FIFO",
        ),
    ];
    for (fifo, args, needle) in cases {
        let p = d.path().join(fifo);
        assert!(mkfifo(&p));
        let mut c = Command::new(bin());
        c.args(args).current_dir(d.path());
        let o = squeal_within(&mut c, Duration::from_secs(60))
            .unwrap_or_else(|| panic!("blocked on the FIFO {fifo}: {args:?}"));
        refused(&o, needle);
        std::fs::remove_file(&p).unwrap();
    }
    // A FIFO given to a command that reads a file.
    let p = d.path().join("in.h5");
    assert!(mkfifo(&p));
    for args in [&["info", "in.h5"][..], &["render", "in.h5"]] {
        let mut c = Command::new(bin());
        c.args(args).current_dir(d.path());
        let o = squeal_within(&mut c, Duration::from_secs(60))
            .unwrap_or_else(|| panic!("blocked on the FIFO: {args:?}"));
        refused(&o, "in.h5 is a FIFO");
    }
}

/// A fresh scan overwrote an existing `NAME-t_squeal.png` without
/// `--force` (the other pictures were refused). It is refused as they are.
#[test]
fn a_fresh_scan_does_not_overwrite_the_transient_picture() {
    let d = tempfile::tempdir().unwrap();
    tiny_spec(d.path(), "t");
    let png = d.path().join("t-t_squeal.png");
    std::fs::write(&png, b"someone's picture").unwrap();
    let o = squeal(d.path(), &["scan", "t.toml", "--quiet"]);
    refused(&o, "refusing to overwrite");
    refused(&o, "t-t_squeal.png");
    assert_eq!(std::fs::read(&png).unwrap(), b"someone's picture");
    assert!(!d.path().join("t.h5").exists());
    let o = squeal(d.path(), &["scan", "t.toml", "--quiet", "--force"]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// `--threads 4096` turned a 0.4 s scan into 63 s. The threads are
/// capped at 8 per core, and the run says so.
#[test]
fn too_many_threads_are_capped_saying_so() {
    let d = tempfile::tempdir().unwrap();
    tiny_spec(d.path(), "c");
    let o = squeal(
        d.path(),
        &["scan", "c.toml", "--quiet", "--threads", "4096"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
    let cap = 8 * cores;
    if 4096 > cap {
        let err = stderr(&o);
        assert!(
            err.contains(&format!(
                "--threads 4096 is more than 8 per core ({cores} core(s)): running {cap} threads"
            )),
            "{err}"
        );
    }
}

/// A signal during the atlas's pilot ended it with code 143 and no word
/// (the handler was installed after the pilot). It now says that nothing was computed or
/// written and exits with code 130.
#[test]
fn a_signal_during_the_pilot_says_what_happened() {
    let d = tempfile::tempdir().unwrap();
    // Each point measures 400 + 400 revolutions of its attractor: a pilot bounded by 29 s at
    // the documented rate, so it runs (a pilot over 30 s is skipped) and is announced (over
    // 5 s); it takes about 0.9 s of a core. The signal follows the announcement at once,
    // while the pilot runs.
    let spec = "version = 1\n[model]\nlaw = \"mcmillan\"\nnu = [1e-3, 2e-3]\n\
                [attractor]\ntransient = 400\nwindow = 400\n\
                [boundaries]\nfold = false\ncritical = false\n[output]\npath = \"p.h5\"\n";
    std::fs::write(d.path().join("p.toml"), spec).unwrap();
    let mut child = Command::new(bin())
        .args(["atlas", "p.toml", "--no-render"])
        .current_dir(d.path())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut announced = String::new();
    let mut lines = std::io::BufReader::new(child.stderr.take().unwrap());
    std::io::BufRead::read_line(&mut lines, &mut announced).unwrap();
    assert!(announced.contains("timing a pilot"), "{announced}");
    let killed = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let status = child.wait().unwrap();
    let mut err = String::new();
    std::io::Read::read_to_string(&mut lines, &mut err).unwrap();
    assert_eq!(status.code(), Some(130), "{err}");
    assert!(
        err.contains("interrupted while estimating the work"),
        "{err}"
    );
    assert!(!d.path().join("p.h5").exists() && !d.path().join("p.h5.lock").exists());
}
