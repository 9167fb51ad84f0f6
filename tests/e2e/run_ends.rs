//! The end of a scan or an atlas: signals while the data file is written (GNU `timeout`
//! sends two SIGTERMs, one to the run and one to its group), and a `--resume` of a run
//! whose every block or unit is journalled (stopped while its file was written).
//!
//! A small run's file is written in milliseconds, too short to aim a signal at: the run
//! waits `SQUEAL_TEST_PAUSE_BEFORE_WRITE_MS` before writing it, saying so on stderr.

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc::{Receiver, channel};
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_squeal");
const PAUSE_VAR: &str = "SQUEAL_TEST_PAUSE_BEFORE_WRITE_MS";

/// A 3 x 3 scan of a fraction of a second, written to `name.h5` (no picture is drawn for
/// a shard; this one is whole, so it has its picture).
fn tiny_scan(dir: &Path, name: &str) {
    let spec = format!(
        "version = 1\n[model]\nlaw = \"mcmillan\"\nnu = 1e-2\n[grid]\n\
         x0 = {{ min = 0.0, max = 2.0, count = 3 }}\nv0 = {{ min = -1.0, max = 1.0, count = 3 }}\n\
         [classifier]\nt_max = 500.0\n[output]\npath = \"{name}.h5\"\n"
    );
    std::fs::write(dir.join(format!("{name}.toml")), spec).unwrap();
}

/// An atlas of two points without boundary searches (a pilot runs: it is not `--quiet`).
fn tiny_atlas(dir: &Path, name: &str) {
    let spec = format!(
        "version = 1\n[model]\nlaw = \"mcmillan\"\nnu = [1e-3, 1e-2]\n[boundaries]\n\
         fold = false\ncritical = false\n[output]\npath = \"{name}.h5\"\n"
    );
    std::fs::write(dir.join(format!("{name}.toml")), spec).unwrap();
}

/// `squeal args` started in `dir` with the pause before the write, and its stderr a line
/// at a time.
fn start_paused(dir: &Path, args: &[&str], pause_ms: u64) -> (Child, Receiver<String>) {
    let mut child = Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .env(PAUSE_VAR, pause_ms.to_string())
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the squeal binary runs");
    let err = child.stderr.take().unwrap();
    let (tx, rx) = channel();
    std::thread::spawn(move || {
        for line in BufReader::new(err).lines().map_while(Result::ok) {
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    (child, rx)
}

/// Lines of `rx` up to and including the first holding `needle` (within `limit`); panics
/// with what was said if none does.
fn wait_for(rx: &Receiver<String>, needle: &str, limit: Duration) -> Vec<String> {
    let (t0, mut seen) = (Instant::now(), Vec::new());
    while let Some(left) = limit.checked_sub(t0.elapsed()) {
        match rx.recv_timeout(left) {
            Ok(line) => {
                let found = line.contains(needle);
                seen.push(line);
                if found {
                    return seen;
                }
            }
            Err(_) => break,
        }
    }
    panic!("no line with {needle:?} within {limit:?}: {seen:#?}");
}

/// The exit code of `child` within `limit` (killed and panicking otherwise).
fn exit_within(child: &mut Child, limit: Duration) -> Option<i32> {
    let t0 = Instant::now();
    while t0.elapsed() < limit {
        if let Some(s) = child.try_wait().unwrap() {
            return s.code();
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let _ = child.kill();
    panic!("did not end within {limit:?}");
}

fn signal(child: &Child, sig: &str) {
    let ok = Command::new("kill")
        .args([sig, &child.id().to_string()])
        .status()
        .unwrap()
        .success();
    assert!(ok, "kill {sig}");
}

/// The files a run leaves beside its output `out` in `dir` when it is not finished.
fn leftovers(dir: &Path, out: &str) -> Vec<String> {
    [".tmp", ".lock", ".journal"]
        .iter()
        .map(|s| format!("{out}{s}"))
        .filter(|f| dir.join(f).exists())
        .collect()
}

/// Two SIGTERMs while the data file is written (as GNU `timeout` sends them): the second
/// quit at once, without the file, leaving its `.tmp`, the lock and the journal. Now the
/// file is written, named, and nothing is left beside it; the pictures are not drawn and
/// the run ends with code 130, naming the command that draws them. A scan and an atlas.
#[test]
fn two_sigterms_while_the_data_file_is_written_let_it_be_written() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    tiny_scan(dir, "s");
    tiny_atlas(dir, "a");
    for (cmd, name) in [("scan", "s"), ("atlas", "a")] {
        let spec = format!("{name}.toml");
        let (mut child, rx) = start_paused(dir, &[cmd, &spec], 3000);
        wait_for(&rx, PAUSE_VAR, Duration::from_secs(120));
        signal(&child, "-TERM");
        signal(&child, "-TERM");
        let code = exit_within(&mut child, Duration::from_secs(60));
        let said: Vec<String> = rx.try_iter().collect();
        let said = said.join("\n");
        let out = format!("{name}.h5");
        assert_eq!(code, Some(130), "{cmd}: {said}");
        assert!(
            said.contains(&format!("still writing the data file {out}")),
            "{cmd}: {said}"
        );
        assert!(
            said.contains(&format!("the data file {out} is complete")),
            "{cmd}: {said}"
        );
        assert_eq!(leftovers(dir, &out), Vec::<String>::new(), "{cmd}: {said}");
        let info = Command::new(BIN)
            .args(["info", &out])
            .current_dir(dir)
            .output()
            .unwrap();
        assert!(
            info.status.success(),
            "{cmd}: {}",
            String::from_utf8_lossy(&info.stderr)
        );
    }
}

/// A run killed while its file was to be written (every block or unit journalled): its
/// `--resume` ran the pilot again (54 s for an atlas, announced as "up to 12 s") to time
/// work that was not to be done. It now writes the file from the journal with no pilot.
#[test]
fn a_resume_with_nothing_left_runs_no_pilot() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    tiny_scan(dir, "s");
    tiny_atlas(dir, "a");
    for (cmd, name, what) in [("scan", "s", "every block"), ("atlas", "a", "every unit")] {
        let spec = format!("{name}.toml");
        let out = format!("{name}.h5");
        let (mut child, rx) = start_paused(dir, &[cmd, &spec], 60_000);
        let before = wait_for(&rx, PAUSE_VAR, Duration::from_secs(120)).join("\n");
        // The first run piloted (the test means something only if a pilot runs here).
        assert!(before.contains("pilot of"), "{cmd}: {before}");
        child.kill().unwrap();
        child.wait().unwrap();
        assert!(!dir.join(&out).exists() && dir.join(format!("{out}.journal")).exists());
        let o = Command::new(BIN)
            .args([cmd, &spec, "--resume"])
            .current_dir(dir)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{cmd}: {err}");
        assert!(!err.contains("pilot of"), "{cmd} ran a pilot: {err}");
        assert!(
            err.contains(what) && err.contains("(no pilot)"),
            "{cmd}: {err}"
        );
        assert!(dir.join(&out).is_file() && leftovers(dir, &out).is_empty());
    }
}
