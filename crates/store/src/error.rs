//! The store's errors: each names the file and what is wrong with it.

use std::path::PathBuf;

/// What went wrong reading or writing a squeal file, its journal or its shards.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum StoreError {
    /// The output exists and `--force` was not given.
    #[error("refusing to overwrite {}: use --force", path.display())]
    Exists {
        /// The file.
        path: PathBuf,
    },
    /// The output is a finished file of another spec and `--force` was not given.
    #[error(
        "{} exists and was made from a different spec (`{key}` differs): use --force to overwrite it, or -o for another output", path.display()
    )]
    OtherSpec {
        /// The file.
        path: PathBuf,
        /// The first key that differs.
        key: String,
    },
    /// The output is not a finished file of the plan's kind and `--force` was not given.
    #[error(
        "{} exists and is not a finished file of this spec's kind ({why}): use --force to overwrite it, or -o for another output", path.display()
    )]
    NotThisKind {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        why: String,
    },
    /// A journal of an interrupted scan is next to the output.
    #[error("an interrupted scan is there ({}): use --resume, or --force to start over", path.display())]
    Interrupted {
        /// The journal.
        path: PathBuf,
    },
    /// Another live process writes this output.
    #[error(
        "{} is being written by process {pid} of user uid {uid} on host {host} (lock {}): wait for it to finish; if that process is gone, remove the lock", path.display(), lock.display()
    )]
    Locked {
        /// The output.
        path: PathBuf,
        /// The lock file.
        lock: PathBuf,
        /// The owner's process id.
        pid: u32,
        /// The owner's host.
        host: String,
        /// The user id owning the lock file.
        uid: u32,
    },
    /// The lock belongs to another user and cannot be judged (this user cannot read it, or
    /// it does not read as a lock): it is someone else's, never removed.
    #[error(
        "{} is locked by user uid {uid} (lock {}: {why}): wait for that user's run to finish, or ask them to remove the lock if none runs", path.display(), lock.display()
    )]
    ForeignLock {
        /// The output.
        path: PathBuf,
        /// The lock file.
        lock: PathBuf,
        /// The user id owning the lock file.
        uid: u32,
        /// Why it cannot be judged.
        why: String,
    },
    /// The lock's path holds something that is not a lock file (a directory, a socket...).
    #[error(
        "{} is not a lock file ({what}): remove it if no squeal run writes {}", lock.display(), path.display()
    )]
    NotALock {
        /// The output.
        path: PathBuf,
        /// The path of the lock.
        lock: PathBuf,
        /// What is there instead.
        what: String,
    },
    /// The lock kept changing hands while this run tried to take it.
    #[error(
        "the lock {} of {} kept changing while this run tried to take it (other runs are starting): try again", lock.display(), path.display()
    )]
    LockBusy {
        /// The output.
        path: PathBuf,
        /// The lock file.
        lock: PathBuf,
    },
    /// Something other than a regular file where squeal reads or writes one (a FIFO
    /// blocked the open for ever).
    #[error(transparent)]
    NotRegular(#[from] squeal_scan::files::NotRegular),
    /// An output whose name does not end in `.h5`.
    #[error("output {}: expected a file name ending in .h5", path.display())]
    NotH5 {
        /// The output.
        path: PathBuf,
    },
    /// An input of a merge is a file the merge writes or removes beside its output (its
    /// lock, temporary file or journal).
    #[error(
        "{} is the {what} of the output {}: an input is never removed or renamed; choose another output", input.display(), path.display()
    )]
    InputBesideOutput {
        /// The input.
        input: PathBuf,
        /// The output.
        path: PathBuf,
        /// Which of the output's files it is.
        what: &'static str,
    },
    /// The output is also one of the inputs.
    #[error("{} is one of the inputs: choose another output", path.display())]
    OutputIsInput {
        /// The file.
        path: PathBuf,
    },
    /// Resume found a complete file and no journal.
    #[error("{} is already complete: nothing to resume (draw its picture with: squeal render {})", path.display(), path.display())]
    AlreadyComplete {
        /// The file.
        path: PathBuf,
    },
    /// Resume found neither journal nor output.
    #[error("nothing to resume: neither {} nor its journal exists", path.display())]
    NothingToResume {
        /// The output.
        path: PathBuf,
    },
    /// The file is not a squeal file (not HDF5, foreign schema, bad journal...).
    #[error("{} is not a squeal file: {why}", path.display())]
    NotSquealFile {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        why: String,
    },
    /// The journal or file belongs to another spec or shard.
    #[error("{} belongs to a different scan: {why}", path.display())]
    SpecMismatch {
        /// The file.
        path: PathBuf,
        /// What differs.
        why: String,
    },
    /// An HDF5 call failed.
    #[error("HDF5 error on {}: {msg}", path.display())]
    Hdf5 {
        /// The file.
        path: PathBuf,
        /// The library's message.
        msg: String,
    },
    /// A file-system call failed.
    // The cause is the error's source: `{:#}` chains print it once.
    #[error("{what} {}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What was being done ("cannot create", ...).
        what: &'static str,
        /// The cause.
        source: std::io::Error,
    },
    /// `finish` was called before every owned block was written, or a shard is incomplete.
    #[error("{} is incomplete: {missing} of {total} blocks missing", path.display())]
    Incomplete {
        /// The file.
        path: PathBuf,
        /// Blocks missing.
        missing: usize,
        /// Blocks expected.
        total: usize,
    },
    /// Shard files that cannot be merged, or a bad `K/N` shard.
    #[error("{0}")]
    Shards(String),
    /// A map index beyond the file's maps.
    #[error("{} holds {count} maps: there is no map {map}", path.display())]
    NoSuchMap {
        /// The file.
        path: PathBuf,
        /// Requested map.
        map: usize,
        /// Maps in the file.
        count: usize,
    },
    /// A per-map statement of the model (the landscape) was not given for every map.
    #[error("{}: cannot state the landscape: {why}", path.display())]
    Landscape {
        /// The output.
        path: PathBuf,
        /// What went wrong.
        why: String,
    },
    /// A block of the wrong shape or index was handed to the writer.
    #[error("bad block for {}: {why}", path.display())]
    BadBlock {
        /// The output.
        path: PathBuf,
        /// What is wrong.
        why: String,
    },
}

pub(crate) trait H5Ctx<T> {
    fn h5(self, path: &std::path::Path) -> Result<T, StoreError>;
}

impl<T> H5Ctx<T> for Result<T, hdf5::Error> {
    fn h5(self, path: &std::path::Path) -> Result<T, StoreError> {
        self.map_err(|e| StoreError::Hdf5 {
            path: path.to_path_buf(),
            msg: e.to_string(),
        })
    }
}

pub(crate) fn io(
    path: &std::path::Path,
    what: &'static str,
) -> impl FnOnce(std::io::Error) -> StoreError {
    let path = path.to_path_buf();
    move |source| StoreError::Io { path, what, source }
}
