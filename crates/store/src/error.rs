//! The store's errors: each names the file and what is wrong with it, and a refusal what
//! the user can ask for instead as data ([`Advice`], made of [`Remedy`]s). The library's
//! own message ([`std::fmt::Display`]) says the remedies in plain words ([`Plain`]); each
//! door into squeal says them in its own ([`StoreError::worded`] with its [`Words`]): the
//! command line as its flags, the Python package as its keyword arguments.

use std::path::{Path, PathBuf};

/// Something a user can ask of a run instead of what was refused; each door names it
/// ([`Words::remedy`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Remedy {
    /// Overwrite the output, or start an interrupted run over (`--force`).
    Force,
    /// Continue the interrupted run (`--resume`).
    Resume,
    /// Write to another output (`-o`).
    OtherOutput,
}

/// What a refusal advises, as data: the sentence is made in a door's [`Words`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Advice {
    /// Overwrite the output.
    Force,
    /// Overwrite the output, or write another.
    ForceOrOtherOutput,
    /// Continue the interrupted run, or start it over.
    ResumeOrForce,
    /// Start the run over (the journal's records are not used).
    StartOver,
    /// Restore the inputs that changed, or start the run over.
    RestoreOrStartOver,
    /// Finish the run with the version of squeal that started it, or start it over.
    OtherVersionOrStartOver,
}

impl Advice {
    /// The advice in the words `w` of a door.
    pub fn worded(self, w: &dyn Words) -> String {
        let force = w.remedy(Remedy::Force);
        match self {
            Advice::Force => format!("use {force}"),
            Advice::ForceOrOtherOutput => format!(
                "use {force} to overwrite it, or {} for another output",
                w.remedy(Remedy::OtherOutput)
            ),
            Advice::ResumeOrForce => {
                format!("use {}, or {force} to start over", w.remedy(Remedy::Resume))
            }
            Advice::StartOver => format!("use {force} to start over"),
            Advice::RestoreOrStartOver => format!("restore them, or use {force} to start over"),
            Advice::OtherVersionOrStartOver => {
                format!("finish it with that version, or use {force} to start over")
            }
        }
    }
}

/// How a door into squeal names what a user can ask for: the command line's flags
/// (`--force`), the Python package's keyword arguments (`force=True`).
pub trait Words {
    /// The name of `remedy` in this door.
    fn remedy(&self, remedy: Remedy) -> &'static str;
    /// How a finished file `path` is looked at in this door, if it has a way to say.
    fn show(&self, _path: &Path) -> Option<String> {
        None
    }
}

/// The library's own words: no door's options.
#[derive(Debug, Clone, Copy, Default)]
pub struct Plain;

impl Words for Plain {
    fn remedy(&self, remedy: Remedy) -> &'static str {
        match remedy {
            Remedy::Force => "the force option",
            Remedy::Resume => "the resume option",
            Remedy::OtherOutput => "another path",
        }
    }
}

/// `: <advice>` in the words `w`, or nothing.
fn advised(advice: &Option<Advice>, w: &dyn Words) -> String {
    advice.map_or_else(String::new, |a| format!(": {}", a.worded(w)))
}

/// What went wrong reading or writing a squeal file, its journal or its shards.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum StoreError {
    /// The output exists and overwriting it was not asked for.
    #[error("{}", self.worded(&Plain))]
    Exists {
        /// The file.
        path: PathBuf,
    },
    /// The output is a finished file of another spec and overwriting it was not asked for.
    #[error("{}", self.worded(&Plain))]
    OtherSpec {
        /// The file.
        path: PathBuf,
        /// The first key that differs.
        key: String,
    },
    /// The output is not a finished file of the plan's kind and overwriting it was not
    /// asked for.
    #[error("{}", self.worded(&Plain))]
    NotThisKind {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        why: String,
    },
    /// A journal of an interrupted scan is next to the output.
    #[error("{}", self.worded(&Plain))]
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
    /// A record of a run's journal no longer reads as the run wrote it: another process
    /// wrote to the journal, or cut it, while the run used it (called "not a squeal file").
    #[error(
        "the journal {} changed on disk while this run used it (its {what} record no longer reads as written): another process wrote to it or cut it short. The file was not written; --resume computes again what no longer reads, --force starts over", path.display()
    )]
    JournalChanged {
        /// The journal.
        path: PathBuf,
        /// The record that changed (block, cycle).
        what: String,
    },
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
    #[error("{}", self.worded(&Plain))]
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
    #[error("{}", self.worded(&Plain))]
    NotSquealFile {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        why: String,
        /// What the user can do about it (a journal that cannot be used: start over).
        advice: Option<Advice>,
    },
    /// The journal or file belongs to another spec or shard.
    #[error("{}", self.worded(&Plain))]
    SpecMismatch {
        /// The file.
        path: PathBuf,
        /// What differs.
        why: String,
        /// What the user can do about it (a journal of another spec: start over).
        advice: Option<Advice>,
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

impl StoreError {
    /// The message in the words `w` of a door into squeal: the same as the error's
    /// [`std::fmt::Display`] (which is in [`Plain`] words) but for the remedies it advises.
    pub fn worded(&self, w: &dyn Words) -> String {
        use StoreError::*;
        match self {
            Exists { path } => {
                let advice = Advice::Force.worded(w);
                format!("refusing to overwrite {}: {advice}", path.display())
            }
            OtherSpec { path, key } => format!(
                "{} exists and was made from a different spec (`{key}` differs): {}",
                path.display(),
                Advice::ForceOrOtherOutput.worded(w)
            ),
            NotThisKind { path, why } => format!(
                "{} exists and is not a finished file of this spec's kind ({why}): {}",
                path.display(),
                Advice::ForceOrOtherOutput.worded(w)
            ),
            Interrupted { path } => format!(
                "an interrupted scan is there ({}): {}",
                path.display(),
                Advice::ResumeOrForce.worded(w)
            ),
            AlreadyComplete { path } => {
                let show = w.show(path).map_or_else(String::new, |s| format!(" ({s})"));
                format!(
                    "{} is already complete: nothing to resume{show}",
                    path.display()
                )
            }
            NotSquealFile { path, why, advice } => format!(
                "{} is not a squeal file: {why}{}",
                path.display(),
                advised(advice, w)
            ),
            SpecMismatch { path, why, advice } => format!(
                "{} belongs to a different scan: {why}{}",
                path.display(),
                advised(advice, w)
            ),
            e => e.to_string(),
        }
    }
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
