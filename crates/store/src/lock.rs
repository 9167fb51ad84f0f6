//! The output lock `<out>.lock`: one scan (or merge) writes an output at a time.
//!
//! The lock file holds `pid host start` of its owner (`start`: the process start time from
//! `/proc/PID/stat`, so a recycled PID is not mistaken for the owner). A lock whose owner
//! is on this host and no longer alive is stale and taken over; a lock from another host
//! cannot be checked and is refused with the command to remove it.

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::StoreError;
use crate::error::io;

/// Held while a scan writes its output; removed on drop.
#[derive(Debug)]
pub struct OutputLock {
    path: PathBuf,
}

/// Who holds a lock.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LockOwner {
    /// Process id.
    pub pid: u32,
    /// Host name.
    pub host: String,
    /// Process start time (clock ticks after boot), if known.
    pub start: Option<u64>,
}

/// This machine's host name.
pub fn hostname() -> String {
    ["/proc/sys/kernel/hostname", "/etc/hostname"]
        .iter()
        .find_map(|p| std::fs::read_to_string(p).ok())
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .or_else(|| std::env::var("HOSTNAME").ok())
        .unwrap_or_else(|| "unknown-host".into())
}

/// Start time of process `pid` (field 22 of `/proc/PID/stat`), if it runs.
fn start_time(pid: u32) -> Option<u64> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // The command name (field 2) is in parentheses and may hold spaces: split after it.
    let rest = &stat[stat.rfind(')')? + 1..];
    rest.split_whitespace().nth(19)?.parse().ok()
}

fn me() -> LockOwner {
    let pid = std::process::id();
    LockOwner {
        pid,
        host: hostname(),
        start: start_time(pid),
    }
}

fn parse(text: &str) -> Option<LockOwner> {
    let mut it = text.split_whitespace();
    let pid = it.next()?.parse().ok()?;
    let host = it.next()?.to_string();
    let start = it.next().and_then(|s| s.parse().ok());
    Some(LockOwner { pid, host, start })
}

impl LockOwner {
    /// Whether this owner is certainly gone: same host, and no process with its PID and
    /// start time.
    pub fn is_stale(&self) -> bool {
        if self.host != hostname() || !Path::new("/proc/self").exists() {
            return false;
        }
        match (start_time(self.pid), self.start) {
            (None, _) => true,
            (Some(now), Some(then)) => now != then,
            (Some(_), None) => false,
        }
    }
}

/// `<out>.lock`.
pub fn lock_path(out: &Path) -> PathBuf {
    let mut s = out.as_os_str().to_owned();
    s.push(".lock");
    PathBuf::from(s)
}

impl OutputLock {
    /// Refuses at once, before any work, when a live process holds the lock of `out`: the
    /// answer [`OutputLock::acquire`] gives, without taking the lock (a run's estimate
    /// comes before its writer takes the lock, and a second run should not wait for it).
    pub fn check_free(out: &Path) -> Result<(), StoreError> {
        let path = lock_path(out);
        let Ok(text) = std::fs::read_to_string(&path) else {
            return Ok(());
        };
        match parse(&text) {
            Some(owner) if !owner.is_stale() => Err(StoreError::Locked {
                path: out.to_path_buf(),
                lock: path,
                pid: owner.pid,
                host: owner.host,
            }),
            _ => Ok(()),
        }
    }

    /// Takes the lock of `out`, or says who holds it. A stale lock is taken over.
    pub fn acquire(out: &Path) -> Result<OutputLock, StoreError> {
        let path = lock_path(out);
        for _ in 0..3 {
            match std::fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&path)
            {
                Ok(mut f) => {
                    let m = me();
                    let line = format!("{} {} {}\n", m.pid, m.host, m.start.unwrap_or(0));
                    if let Err(e) = f.write_all(line.as_bytes()).and_then(|_| f.sync_all()) {
                        // A full disk: leave no empty lock behind.
                        let _ = std::fs::remove_file(&path);
                        return Err(io(&path, "cannot write the lock")(e));
                    }
                    return Ok(OutputLock { path });
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                    // Only a regular file is a lock; anything else would never parse and
                    // was reported as held by "process 0 on host ?".
                    match std::fs::symlink_metadata(&path) {
                        Ok(md) if !md.is_file() => {
                            return Err(StoreError::NotALock {
                                path: out.to_path_buf(),
                                lock: path,
                                what: if md.is_dir() {
                                    "a directory".into()
                                } else {
                                    format!("{:?}", md.file_type())
                                },
                            });
                        }
                        _ => {}
                    }
                    let text = std::fs::read_to_string(&path).unwrap_or_default();
                    match parse(&text) {
                        Some(owner) if owner.is_stale() => {
                            // The owner was killed: take the lock over.
                            let _ = std::fs::remove_file(&path);
                        }
                        Some(owner) => {
                            return Err(StoreError::Locked {
                                path: out.to_path_buf(),
                                lock: path,
                                pid: owner.pid,
                                host: owner.host,
                            });
                        }
                        // Being written this instant, or garbage: wait once, then judge.
                        None => {
                            std::thread::sleep(std::time::Duration::from_millis(50));
                            if parse(&std::fs::read_to_string(&path).unwrap_or_default()).is_none()
                            {
                                let _ = std::fs::remove_file(&path);
                            }
                        }
                    }
                }
                Err(e) => return Err(io(&path, "cannot create the lock")(e)),
            }
        }
        Err(StoreError::Locked {
            path: out.to_path_buf(),
            lock: path,
            pid: 0,
            host: "?".into(),
        })
    }
}

impl Drop for OutputLock {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.path);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A PID no process has now: counting down from the kernel's largest.
    fn not_running() -> u32 {
        let max: u32 = std::fs::read_to_string("/proc/sys/kernel/pid_max")
            .ok()
            .and_then(|s| s.trim().parse().ok())
            .unwrap_or(32768);
        (2..max)
            .rev()
            .find(|p| !Path::new(&format!("/proc/{p}")).exists())
            .expect("a free PID")
    }

    #[test]
    fn a_live_lock_is_refused_and_a_dead_one_taken_over() {
        let d = tempfile::tempdir().unwrap();
        let out = d.path().join("x.h5");
        let held = OutputLock::acquire(&out).unwrap();
        let e = OutputLock::acquire(&out).unwrap_err().to_string();
        assert!(e.contains(&std::process::id().to_string()), "{e}");
        assert!(e.contains(&hostname()), "{e}");
        drop(held);
        assert!(!lock_path(&out).exists());
        // A lock left by a process that no longer runs: a PID with no /proc entry. (Not a
        // spawned child that has exited: a child inherits the HDF5 files other tests of
        // this binary hold open at that moment, with their flock, since HDF5 opens them
        // without close-on-exec; while it lived, reopening such a file failed with
        // "unable to lock file, errno = 11", in about 1 run of 15 of this binary:
        // `atlas::record::tests::note_kinds_survive_the_journal_and_the_file`.)
        let pid = not_running();
        std::fs::write(lock_path(&out), format!("{pid} {} 1\n", hostname())).unwrap();
        let _l = OutputLock::acquire(&out).unwrap();
        // From another host: cannot be checked, refused.
        drop(_l);
        std::fs::write(lock_path(&out), "1 some-other-host 1\n").unwrap();
        assert!(OutputLock::acquire(&out).is_err());
    }

    #[test]
    fn a_directory_in_the_locks_place_is_named() {
        let d = tempfile::tempdir().unwrap();
        let out = d.path().join("x.h5");
        std::fs::create_dir(lock_path(&out)).unwrap();
        let e = OutputLock::acquire(&out).unwrap_err().to_string();
        // Before: "... is being written by process 0 on host ?".
        assert!(e.contains("not a lock file (a directory)"), "{e}");
        assert!(!e.contains("process 0"), "{e}");
    }

    #[test]
    fn an_empty_lock_left_by_a_full_disk_is_taken_over() {
        let d = tempfile::tempdir().unwrap();
        let out = d.path().join("x.h5");
        std::fs::write(lock_path(&out), "").unwrap();
        let _l = OutputLock::acquire(&out).unwrap();
    }
}
