//! What is at an output path, for scans and atlases alike: the make-like rerun rule
//! ([`output_state`]), the kind of a squeal file ([`file_kind`]), and the merge's refusal of
//! an input as its output ([`refuse_input_as_output`]), and the checks of an output path
//! before anything is opened ([`check_output`]).

use std::path::{Path, PathBuf};

use squeal_scan::atlas::AtlasPlan;
use squeal_scan::{Plan, Shard};

use crate::ATLAS_SCHEMA;
use crate::error::{Advice, H5Ctx};
use crate::{SCHEMA, StoreError, TRAJECTORY_SCHEMA, read};

/// A checked plan whose finished file records its spec text and name: a scan's [`Plan`]
/// or an [`AtlasPlan`]. [`output_state`] judges both by this one rule.
pub trait Recorded: Sized {
    /// The `schema` attribute of the files this plan writes.
    const SCHEMA: &'static str;
    /// The plan of a stored spec text, parsed as if read from `like`'s spec file, and named
    /// `name` if given (a file's `name` attribute); `table`, the friction table a file
    /// stores, stands for the spec's `friction_table` or `friction_csv` (`None`: read them).
    fn stored(
        spec: &str,
        table: Option<&'static squeal_core::FrictionTable>,
        name: Option<String>,
        like: &Self,
    ) -> Option<Self>;
    /// The first setting in which `other` computes something different, if any.
    fn first_difference(&self, other: &Self) -> Option<String>;
    /// The friction table the spec's `friction_table` or `friction_csv` gave (in m/s where
    /// `[physical]` gave it), which [`Recorded::stored`] takes back.
    fn spec_table(&self) -> Option<&'static squeal_core::FrictionTable>;
    /// This plan writing to `other`'s output (a `-o` given at the resume).
    fn writing_to(self, other: &Self) -> Self;
}

/// The plan a journal was started with (its header `started`), judged against the `plan`
/// given at a resume, for scans and atlases alike: a friction table whose rows changed
/// (a CSV edited since: the spec's text names only its file) is refused naming it; the same
/// text is `plan` itself; another text that computes the same (a comment edit) is the
/// journal's own plan, so the file records the spec the run started with; anything else is
/// refused naming the first key that differs.
pub(crate) fn started_plan<P: Recorded + Clone>(
    journal: &Path,
    started: &crate::journal::Header,
    plan: &P,
    plan_text: &str,
) -> Result<P, StoreError> {
    let mismatch = |why: String, advice| StoreError::SpecMismatch {
        path: journal.to_path_buf(),
        why,
        advice,
    };
    let table = crate::journal::table_text(plan.spec_table());
    // A journal of an earlier build did not record its table: its spec decides alone.
    if started.table.as_ref().is_some_and(|t| *t != table) {
        return Err(mismatch(
            "the journal was written for another friction table (friction_csv: the file's \
             rows changed since the run started, or friction_table was edited)"
                .into(),
            Some(Advice::RestoreOrStartOver),
        ));
    }
    let started_text = started.spec.as_str();
    if started_text == plan_text {
        return Ok(plan.clone());
    }
    let started = P::stored(started_text, plan.spec_table(), None, plan)
        .ok_or_else(|| mismatch("the journal's stored spec cannot be read".into(), None))?;
    let started = started.writing_to(plan);
    match started.first_difference(plan) {
        None => Ok(started),
        Some(key) => Err(mismatch(
            format!("the journal was written for another spec ({key} differs)"),
            Some(Advice::StartOver),
        )),
    }
}

impl Recorded for Plan {
    const SCHEMA: &'static str = SCHEMA;
    fn stored(
        spec: &str,
        table: Option<&'static squeal_core::FrictionTable>,
        name: Option<String>,
        like: &Plan,
    ) -> Option<Plan> {
        let p = Plan::from_stored_toml_table(spec, &like.spec_path, table).ok()?;
        Some(Plan {
            name: name.unwrap_or(p.name.clone()),
            ..p
        })
    }
    fn first_difference(&self, other: &Plan) -> Option<String> {
        self.differs_from(other)
    }
    fn spec_table(&self) -> Option<&'static squeal_core::FrictionTable> {
        self.space.table
    }
    fn writing_to(self, other: &Plan) -> Plan {
        Plan {
            output: other.output.clone(),
            ..self
        }
    }
}

impl Recorded for AtlasPlan {
    const SCHEMA: &'static str = ATLAS_SCHEMA;
    fn stored(
        spec: &str,
        table: Option<&'static squeal_core::FrictionTable>,
        name: Option<String>,
        like: &AtlasPlan,
    ) -> Option<AtlasPlan> {
        let p = AtlasPlan::from_stored_toml_table(spec, &like.spec_path, table).ok()?;
        Some(AtlasPlan {
            name: name.unwrap_or(p.name.clone()),
            ..p
        })
    }
    fn first_difference(&self, other: &AtlasPlan) -> Option<String> {
        self.differs_from(other)
    }
    fn spec_table(&self) -> Option<&'static squeal_core::FrictionTable> {
        self.space.table
    }
    fn writing_to(self, other: &AtlasPlan) -> AtlasPlan {
        AtlasPlan {
            out: other.out.clone(),
            ..self
        }
    }
}

/// What is at an output path, judged against the plan that would write it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum OutputState {
    /// Neither the file nor a journal.
    Absent,
    /// A journal of an interrupted run (and no finished file).
    Interrupted,
    /// A finished squeal file made from the same parsed spec.
    Complete,
    /// A finished squeal file of another spec: the first key that differs.
    Different(String),
    /// A file that is not a finished file of this kind (another kind of squeal file, not
    /// HDF5, cut short): what is wrong with it.
    Foreign(String),
}

impl OutputState {
    /// Like make, the one rule of every door (the command line, Python) before anything is
    /// computed: without `force`, a finished file of the same spec is up to date, for a
    /// rerun and for a resume alike (`Ok(true)`: nothing to compute), and a file of another
    /// spec, or not a finished file of this kind, is refused. Anything else (no file, an
    /// interrupted run, or `force`) is `Ok(false)`: the writer takes over.
    pub fn up_to_date(self, out: &Path, force: bool) -> Result<bool, StoreError> {
        if force {
            return Ok(false);
        }
        match self {
            OutputState::Complete => Ok(true),
            OutputState::Different(key) => Err(StoreError::OtherSpec {
                path: out.to_path_buf(),
                key,
            }),
            OutputState::Foreign(why) => Err(StoreError::NotThisKind {
                path: out.to_path_buf(),
                why,
            }),
            OutputState::Absent | OutputState::Interrupted => Ok(false),
        }
    }
}

/// Looks at `out` for `shard` of `plan`, a scan's or an atlas's (without changing
/// anything). Spec texts are compared as parsed plans: a comment edit or `-o` changes
/// nothing.
pub fn output_state<P: Recorded>(
    out: &Path,
    plan: &P,
    shard: Option<Shard>,
) -> Result<OutputState, StoreError> {
    // A file is published (renamed into place) only when complete; a journal beside it is
    // left by a kill between the rename and the journal's removal.
    if out.exists() {
        let f = match read::open_with_schema(out, P::SCHEMA) {
            Ok(f) => f,
            Err(StoreError::NotSquealFile { why, .. }) => return Ok(OutputState::Foreign(why)),
            Err(e) => return Err(e),
        };
        let spec = read::str_attr(&f, "spec").h5(out)?;
        let name = read::str_attr(&f, "name").h5(out)?;
        let stored_shard = read::str_attr(&f, "shard").unwrap_or_default();
        if stored_shard != shard.map(|s| s.to_string()).unwrap_or_default() {
            return Ok(OutputState::Different("shard".into()));
        }
        let table = read::stored_table(&f).h5(out)?;
        let Some(stored) = P::stored(&spec, table, Some(name), plan) else {
            return Ok(OutputState::Different("spec".into()));
        };
        return Ok(match stored.first_difference(plan) {
            None => OutputState::Complete,
            Some(k) => OutputState::Different(k),
        });
    }
    if crate::journal_path(out).exists() {
        return Ok(OutputState::Interrupted);
    }
    Ok(OutputState::Absent)
}

/// The kinds of file squeal writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileKind {
    /// A scan's basin maps (`squeal scan`, schema `squeal-basins/1`).
    Scan,
    /// An atlas (`squeal atlas`, schema `squeal-atlas/1`).
    Atlas,
    /// One run's samples (`squeal trajectory --out`, schema `squeal-trajectory/1`).
    Trajectory,
}

/// Which kind of squeal file `path` is, by its `schema` attribute; other files are
/// refused naming the schema found.
pub fn file_kind(path: &Path) -> Result<FileKind, StoreError> {
    let schema = read::file_schema(path)?;
    match schema.as_str() {
        SCHEMA => Ok(FileKind::Scan),
        ATLAS_SCHEMA => Ok(FileKind::Atlas),
        TRAJECTORY_SCHEMA => Ok(FileKind::Trajectory),
        s => Err(StoreError::NotSquealFile {
            path: path.to_path_buf(),
            why: format!(
                "schema is {s:?}, expected one of {SCHEMA:?}, {ATLAS_SCHEMA:?}, {TRAJECTORY_SCHEMA:?}"
            ),
            advice: None,
        }),
    }
}

/// The files a run writes (and may remove) beside its output `out`: its lock, temporary
/// file and journal, with their names in words.
fn beside(out: &Path) -> [(PathBuf, &'static str); 3] {
    [
        (crate::lock_path(out), "lock"),
        (crate::tmp_path(out), "temporary file"),
        (crate::journal_path(out), "journal"),
    ]
}

/// Refuses an existing `path` unless `force` ([`StoreError::Exists`]): the rule of every
/// door for a file written whole at the end (a trajectory's), checked before the run; and
/// anything but a regular file there, even with `force` (HDF5 opening a FIFO blocked).
pub fn refuse_existing(path: &Path, force: bool) -> Result<(), StoreError> {
    squeal_scan::files::refuse_non_regular(path)?;
    if !force && path.exists() {
        return Err(StoreError::Exists {
            path: path.to_path_buf(),
        });
    }
    Ok(())
}

/// Makes the missing folders above `out`, the same way for every door that writes a file
/// (the command line's `scan -o`, `atlas -o`, `merge -o` and `trajectory --out`, Python's
/// `scan`, `atlas`, `basin_stability` and `trajectory`): some made them and others refused
/// the output ("cannot create the lock").
pub fn create_parent(out: &Path) -> Result<(), StoreError> {
    if let Some(d) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(d).map_err(crate::error::io(d, "cannot create folder"))?;
    }
    Ok(())
}

/// Checks an output path before anything is opened or computed, for every door (the CLI's
/// `scan`, `atlas` and `merge`, Python's `scan` and `atlas`): a name ending in `.h5`, and at
/// the output and at its lock, temporary file and journal, where something is there, a
/// regular file (a FIFO there blocked the run for ever; a directory at the output was
/// found only after the merge wrote its temporary file, which it left behind).
pub fn check_output(out: &Path) -> Result<(), StoreError> {
    if out.extension().and_then(|e| e.to_str()) != Some("h5") {
        return Err(StoreError::NotH5 {
            path: out.to_path_buf(),
        });
    }
    squeal_scan::files::refuse_non_regular(out)?;
    let [(lock, _), tmp, journal] = beside(out);
    // The lock is judged without following a symbolic link: a link is no lock.
    match std::fs::symlink_metadata(&lock) {
        Ok(md) if !md.is_file() => {
            return Err(StoreError::NotALock {
                path: out.to_path_buf(),
                what: squeal_scan::files::what_is(md.file_type()).into(),
                lock,
            });
        }
        _ => {}
    }
    squeal_scan::files::refuse_non_regular(&tmp.0)?;
    squeal_scan::files::refuse_non_regular(&journal.0)?;
    Ok(())
}

/// Refuses an output that is one of the inputs (of a merge): the same path once
/// canonicalised (the output may not exist yet: its folder is canonicalised), or the same
/// file under another name (a hard link: the same device and inode). Refuses as well an
/// input that is the output's lock, temporary file or journal: the merge removes or
/// renames those, and an input is never removed or renamed (`merge a.h5 all.h5.lock -o
/// all.h5` removed the input as a garbage lock; an input `all.h5.tmp` was consumed).
pub fn refuse_input_as_output(inputs: &[PathBuf], out: &Path) -> Result<(), StoreError> {
    let canon = |p: &Path| -> Option<PathBuf> {
        std::fs::canonicalize(p).ok().or_else(|| {
            let dir = p.parent().filter(|d| !d.as_os_str().is_empty());
            let dir = std::fs::canonicalize(dir.unwrap_or(Path::new("."))).ok()?;
            Some(dir.join(p.file_name()?))
        })
    };
    let same = |a: &Path, b: &Path| {
        let (ca, cb) = (canon(a), canon(b));
        let (ia, ib) = (file_id(a), file_id(b));
        (ca.is_some() && ca == cb) || (ia.is_some() && ia == ib)
    };
    for p in inputs {
        if same(p, out) {
            return Err(StoreError::OutputIsInput {
                path: out.to_path_buf(),
            });
        }
        if let Some((_, what)) = beside(out).into_iter().find(|(b, _)| same(p, b)) {
            return Err(StoreError::InputBesideOutput {
                input: p.clone(),
                path: out.to_path_buf(),
                what,
            });
        }
    }
    Ok(())
}

/// The device and inode of an existing file (Unix), to recognise one file by two names.
fn file_id(p: &Path) -> Option<(u64, u64)> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        std::fs::metadata(p).ok().map(|m| (m.dev(), m.ino()))
    }
    #[cfg(not(unix))]
    {
        let _ = p;
        None
    }
}
