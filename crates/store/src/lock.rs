//! The output lock `<out>.lock`: one scan (or merge) writes an output at a time.
//!
//! The lock file holds `pid host start` of its owner (`start`: the process start time from
//! `/proc/PID/stat`, so a recycled PID is not mistaken for the owner). A lock whose owner
//! is on this host and no longer alive is stale and taken over; a lock from another host
//! cannot be checked and is refused with the command to remove it.
//!
//! Across users (a shared folder): the lock file's owner is the user whose run holds it.
//! A lock this user cannot read, or another user's that does not read as a lock, is refused
//! naming that owner's uid and the lock's path, and never removed; another user's stale
//! lock is taken over only where that user's processes are visible (not under `hidepid`).
//! Only a regular file is a lock: anything else at its path is refused in words.

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

/// The largest lock file taken over as one left half-written (a full disk, a kill during
/// the write): a lock is one line `pid host start`, a host name at most 64 bytes. A larger
/// file at the lock's path is something else under that name, never removed.
const MAX_LOCK_BYTES: u64 = 256;

/// The user id this process runs as (the owner of the files it creates), on Linux.
fn my_uid() -> Option<u32> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        std::fs::metadata("/proc/self").ok().map(|m| m.uid())
    }
    #[cfg(not(unix))]
    None
}

/// The user id owning a file.
fn uid_of(md: &std::fs::Metadata) -> u32 {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        md.uid()
    }
    #[cfg(not(unix))]
    {
        let _ = md;
        0
    }
}

/// Whether this process sees other users' processes (not so under `/proc` mounted with
/// `hidepid`, where another user's live process looks gone).
fn sees_others() -> bool {
    Path::new("/proc/1/stat").exists()
}

/// What a lock that is there says, judged once.
enum Seen {
    /// Gone meanwhile: try to create it again.
    Gone,
    /// Its owner is certainly gone (or it was left half-written by this user): take it over.
    Stale,
}

/// Judges the lock `lock` of `out` that is there: a live owner's, another user's that
/// cannot be judged, or something that is not a lock are refused; never removed here.
fn judge(out: &Path, lock: &Path) -> Result<Seen, StoreError> {
    let md = match std::fs::symlink_metadata(lock) {
        Ok(md) => md,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Seen::Gone),
        Err(e) => return Err(io(lock, "cannot look at the lock")(e)),
    };
    // Only a regular file is a lock: anything else would never parse, and was reported as
    // held by "process 0 on host ?", or named by a Rust debug dump of its file type.
    if !md.is_file() {
        return Err(StoreError::NotALock {
            path: out.to_path_buf(),
            lock: lock.to_path_buf(),
            what: squeal_scan::files::what_is(md.file_type()).into(),
        });
    }
    let uid = uid_of(&md);
    let mine = my_uid() == Some(uid);
    let foreign = |why: String| StoreError::ForeignLock {
        path: out.to_path_buf(),
        lock: lock.to_path_buf(),
        uid,
        why,
    };
    // A lock this user cannot read is another user's (umask 077): taken for garbage and
    // removed, it would let two users write one output.
    let text = match std::fs::read_to_string(lock) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Seen::Gone),
        Err(e) if !mine => return Err(foreign(format!("this user cannot read it: {e}"))),
        Err(e) => return Err(io(lock, "cannot read the lock")(e)),
    };
    match parse(&text) {
        // Another user's stale lock is taken over only where their processes are seen.
        Some(owner) if owner.is_stale() && (mine || sees_others()) => Ok(Seen::Stale),
        Some(owner) => Err(StoreError::Locked {
            path: out.to_path_buf(),
            lock: lock.to_path_buf(),
            pid: owner.pid,
            host: owner.host,
            uid,
        }),
        None if md.len() > MAX_LOCK_BYTES => Err(StoreError::NotALock {
            path: out.to_path_buf(),
            lock: lock.to_path_buf(),
            what: format!("a file of {} bytes that is not a squeal lock", md.len()),
        }),
        None if !mine => Err(foreign("it does not read as a squeal lock".into())),
        // Being written this instant, or left half-written: wait once, then judge.
        None => {
            std::thread::sleep(std::time::Duration::from_millis(50));
            match std::fs::read_to_string(lock) {
                Ok(t) if parse(&t).is_some() => judge(out, lock),
                Ok(_) => Ok(Seen::Stale),
                Err(_) => Ok(Seen::Gone),
            }
        }
    }
}

impl OutputLock {
    /// Refuses at once, before any work, when the lock of `out` cannot be taken: a live
    /// process holds it, another user's lock is there, or the folder is not writable. The
    /// lock is taken and released again (a run's estimate comes before its writer takes
    /// the lock, and a second run should not wait for it); an unwritable folder was found
    /// only after a 74 s pilot.
    pub fn check_free(out: &Path) -> Result<(), StoreError> {
        OutputLock::acquire(out).map(drop)
    }

    /// Takes the lock of `out`, or says who holds it. A stale lock of this user is taken
    /// over; another user's only where their processes are seen; a lock this user cannot
    /// read, or that is not a regular file, is refused naming its owner, and never removed.
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
                    if let Seen::Stale = judge(out, &path)? {
                        // The owner was killed: take the lock over. Removal refused (a
                        // sticky folder) is an error naming the lock, not a retry.
                        match std::fs::remove_file(&path) {
                            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                                return Err(io(&path, "cannot remove the stale lock")(e));
                            }
                            _ => {}
                        }
                    }
                }
                Err(e) => return Err(io(&path, "cannot create the lock")(e)),
            }
        }
        Err(StoreError::LockBusy {
            path: out.to_path_buf(),
            lock: path,
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

    /// A symbolic link or a socket at the lock's path was named by a Rust debug dump
    /// (`FileType { is_file: false, ... }`); now in words, and left there.
    #[test]
    fn a_link_or_a_socket_in_the_locks_place_is_named_in_words() {
        let d = tempfile::tempdir().unwrap();
        let out = d.path().join("x.h5");
        std::os::unix::fs::symlink("elsewhere", lock_path(&out)).unwrap();
        let e = OutputLock::acquire(&out).unwrap_err().to_string();
        assert!(e.contains("not a lock file (a symbolic link)"), "{e}");
        assert!(!e.contains("FileType"), "{e}");
        assert!(std::fs::symlink_metadata(lock_path(&out)).is_ok());
        let out = d.path().join("y.h5");
        let _socket = std::os::unix::net::UnixListener::bind(lock_path(&out)).unwrap();
        let e = OutputLock::acquire(&out).unwrap_err().to_string();
        assert!(e.contains("not a lock file (a socket)"), "{e}");
        assert!(!e.contains("FileType"), "{e}");
    }

    /// A file at the lock's path that is far larger than a lock (an input of a merge named
    /// `all.h5.lock`) was removed as a garbage lock; it is refused and left.
    #[test]
    fn a_large_file_in_the_locks_place_is_left() {
        let d = tempfile::tempdir().unwrap();
        let out = d.path().join("x.h5");
        let data = vec![7u8; 4096];
        std::fs::write(lock_path(&out), &data).unwrap();
        let e = OutputLock::acquire(&out).unwrap_err().to_string();
        assert!(
            e.contains("a file of 4096 bytes that is not a squeal lock"),
            "{e}"
        );
        assert_eq!(std::fs::read(lock_path(&out)).unwrap(), data);
    }

    /// Another user's lock that does not read as a lock (or, for a user, cannot be read at
    /// all: tests/e2e/cli_files.rs) was removed as garbage; it is refused naming its owner's
    /// uid and the lock, and kept. Needs root to give the file to another user.
    #[test]
    fn another_users_lock_that_does_not_parse_is_refused_and_kept() {
        if my_uid() != Some(0) {
            eprintln!("skipping: not root, cannot make a file owned by another user");
            return;
        }
        let d = tempfile::tempdir().unwrap();
        let out = d.path().join("x.h5");
        let lock = lock_path(&out);
        std::fs::write(&lock, "").unwrap();
        std::os::unix::fs::chown(&lock, Some(65534), Some(65534)).unwrap();
        let e = OutputLock::acquire(&out).unwrap_err().to_string();
        assert!(e.contains("locked by user uid 65534"), "{e}");
        assert!(e.contains(&lock.display().to_string()), "{e}");
        assert!(lock.exists());
        // A live owner is named with its uid too.
        let m = me();
        let line = format!("{} {} {}\n", m.pid, m.host, m.start.unwrap_or(0));
        std::fs::write(&lock, line).unwrap();
        let e = OutputLock::check_free(&out).unwrap_err().to_string();
        assert!(e.contains("of user uid 65534"), "{e}");
        assert!(lock.exists());
    }

    #[test]
    fn an_empty_lock_left_by_a_full_disk_is_taken_over() {
        let d = tempfile::tempdir().unwrap();
        let out = d.path().join("x.h5");
        std::fs::write(lock_path(&out), "").unwrap();
        let _l = OutputLock::acquire(&out).unwrap();
    }
}
