//! Pieces shared by the subcommands: provenance, output checks, signals, the run flags,
//! basin shares in words and JSON, durations. Progress is in [`super::progress`], pictures of
//! files in [`super::pictures`].

use std::path::{Path, PathBuf};

use anyhow::{Context, bail};

/// Version and git revision recorded in every output.
pub fn provenance() -> squeal_store::Provenance {
    squeal_store::Provenance {
        version: env!("CARGO_PKG_VERSION").to_string(),
        git_revision: env!("SQUEAL_GIT_REV").to_string(),
    }
}

/// Refuses to overwrite `path` unless `force`, and anything but a regular file there even
/// with `force` (a FIFO at a picture's or the labels' path blocked the run for ever).
pub fn check_new(path: &Path, force: bool, what: &str) -> anyhow::Result<()> {
    squeal_scan::files::refuse_non_regular(path)
        .map_err(|e| anyhow::anyhow!("cannot write the {what} there: {e}"))?;
    if path.exists() && !force {
        bail!(
            "refusing to overwrite {} ({what}): use --force",
            path.display()
        );
    }
    Ok(())
}

/// Whether `path` holds a whole picture: a file that starts with the PNG signature and
/// ends with the PNG's closing `IEND` chunk (its name and fixed CRC). A full disk left a
/// 0-byte or cut PNG that a rerun reported "up to date"; such a file is drawn again. Only
/// a regular file is read (a FIFO blocked the read for ever).
pub fn is_drawn(path: &Path) -> bool {
    const SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', b'\r', b'\n', 0x1a, b'\n'];
    const END: [u8; 8] = [b'I', b'E', b'N', b'D', 0xAE, 0x42, 0x60, 0x82];
    if !std::fs::metadata(path).is_ok_and(|m| m.is_file()) {
        return false;
    }
    std::fs::read(path)
        .is_ok_and(|b| b.len() > 16 && b.starts_with(&SIGNATURE) && b.ends_with(&END))
}

/// Writes `text` to standard output; a reader that has stopped reading (`squeal info f.h5 |
/// head`) ends the output quietly, as for other Unix tools, instead of a panic on the
/// closed pipe.
pub fn print_to_reader(text: &str) -> anyhow::Result<()> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        r => r.context("writing to standard output"),
    }
}

/// Makes the output's folder and takes and releases its lock, before any estimate or
/// computing (scans and atlases alike): a live run's lock, another user's, or a folder this
/// user cannot write is refused here, not after the pilot.
pub fn prepare_output(out: &Path) -> anyhow::Result<()> {
    squeal_store::create_parent(out)?;
    squeal_store::OutputLock::check_free(out)?;
    Ok(())
}

/// Exit code of a run stopped by SIGINT or SIGTERM: resumable with `--resume`
/// ([`super::signals`]).
pub const EXIT_INTERRUPTED: u8 = 130;

/// Like make, for scans and atlases alike, by the library's rule
/// ([`squeal_store::OutputState::up_to_date`]): a finished file of the same parsed spec (and
/// shard) is up to date, for a rerun and for `--resume` (a requeued job that had finished):
/// any of `pictures` missing is drawn again with `draw`, it says so and returns `true`
/// (nothing to compute). A file of another spec, or not a finished file of this kind, is
/// refused naming `--force`. Anything else returns `false`: the writer takes over.
pub fn up_to_date(
    out: &Path,
    state: squeal_store::OutputState,
    run: &RunArgs,
    pictures: &[PathBuf],
    draw: impl FnOnce() -> anyhow::Result<Vec<PathBuf>>,
) -> anyhow::Result<bool> {
    if !state.up_to_date(out, run.force)? {
        return Ok(false);
    }
    let drew = pictures.iter().any(|p| !is_drawn(p));
    if drew {
        draw()?;
    }
    eprintln!(
        "squeal: {} is up to date (made from the same spec){}",
        out.display(),
        if drew {
            "; drew the missing picture"
        } else {
            ""
        }
    );
    Ok(true)
}

/// The error of a drawing, with the picture it left removed (a full disk left a 0-byte or
/// cut PNG).
pub fn discard(png: &Path, e: impl Into<anyhow::Error>) -> anyhow::Error {
    let _ = std::fs::remove_file(png);
    e.into().context(format!("drawing {}", png.display()))
}

/// `out` with its extension replaced and an optional suffix on the stem.
pub fn sibling(out: &Path, suffix: &str, ext: &str) -> PathBuf {
    let stem = out
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    out.with_file_name(format!("{stem}{suffix}.{ext}"))
}

/// A root attribute of a file, as text.
pub fn attr<'a>(info: &'a squeal_store::FileInfo, key: &str) -> Option<&'a str> {
    info.attrs
        .iter()
        .find(|(k, _)| k == key)
        .map(|(_, v)| v.as_str())
}

/// Output, threads and restart flags shared by `scan` and `atlas` (long jobs that write one
/// journalled file).
#[derive(clap::Args, Debug)]
pub struct RunArgs {
    /// Output file (.h5); default: the spec's output.path.
    #[arg(short = 'o', long)]
    pub out: Option<std::path::PathBuf>,
    /// Worker threads (default: all cores; at most 8 per core).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Finish an interrupted run of the same spec.
    #[arg(long, conflicts_with = "force")]
    pub resume: bool,
    /// Overwrite an existing output (and discard an interrupted run).
    #[arg(long)]
    pub force: bool,
    /// No progress bar (and for `scan` no work estimate).
    #[arg(long)]
    pub quiet: bool,
    /// Run only shard K of N (1-based): its own file, joined later by `squeal merge`.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,
    /// Also write the interactive page of the finished file beside it, OUT.html (what
    /// `squeal report OUT.h5` writes); not for a shard (report the merged file).
    #[arg(long, conflicts_with = "shard")]
    pub report: bool,
}

impl RunArgs {
    /// The command that finishes an interrupted run: `squeal CMD SPEC -o OUT --resume`
    /// (and its `--shard`).
    pub fn resume_command(&self, cmd: &str, spec: &Path, out: &Path) -> String {
        format!(
            "squeal {cmd} {} -o {} --resume{}",
            spec.display(),
            out.display(),
            self.shard
                .as_deref()
                .map(|s| format!(" --shard {s}"))
                .unwrap_or_default()
        )
    }

    /// Checks the flags before any computing and sets the worker threads (at most
    /// [`THREADS_PER_CORE`] per core): the output file (`--out`, else the spec's
    /// `default_out`; [`squeal_store::check_output`]) and the shard, if any.
    pub fn setup(
        &self,
        default_out: &Path,
    ) -> anyhow::Result<(PathBuf, Option<squeal_scan::Shard>)> {
        let out = self
            .out
            .clone()
            .unwrap_or_else(|| default_out.to_path_buf());
        // The name ends in .h5, and nothing but regular files is at the output, its lock,
        // temporary file and journal (the store's check, which Python's door shares).
        squeal_store::check_output(&out)?;
        let shard = self
            .shard
            .as_deref()
            .map(|s| s.parse().with_context(|| format!("--shard {s}")))
            .transpose()?;
        if let Some(n) = self.threads {
            if n == 0 || n > 4096 {
                bail!("--threads {n}: expected 1..=4096");
            }
            let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
            let n = capped_threads(n, cores);
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build_global()
                .context("--threads")?;
        }
        Ok((out, shard))
    }
}

/// Most worker threads per core: more only adds switching (`--threads 4096` on
/// 16 cores turned a 0.4 s scan into 63 s).
pub const THREADS_PER_CORE: usize = 8;

/// The worker threads for `--threads n` on `cores` cores: at most [`THREADS_PER_CORE`] per
/// core, saying so on stderr when `n` is more.
fn capped_threads(n: usize, cores: usize) -> usize {
    let cap = THREADS_PER_CORE * cores;
    if n > cap {
        eprintln!(
            "squeal: --threads {n} is more than {THREADS_PER_CORE} per core ({cores} core(s)): running {cap} threads"
        );
    }
    n.min(cap)
}

/// Basin stability of one map as JSON: per regime the share `p` of the computed cells, its
/// binomial `se`, the shares on the nested `2h` and `4h` sub-grids and the change
/// `p_h - p_2h` (the grid error bar); `n` is the number of computed cells.
/// Each map of a scan file read back and summarised by the engine: its cells per label and
/// its basin stability ([`squeal_scan::MapSummary`]; the store only reads the labels).
pub fn map_summaries(
    info: &squeal_store::FileInfo,
) -> Result<Vec<squeal_scan::MapSummary>, squeal_store::StoreError> {
    (0..info.maps)
        .map(|m| {
            let labels = squeal_store::map_labels(&info.path, m)?;
            Ok(squeal_scan::MapSummary::of(
                &labels,
                info.x0.len(),
                info.sample,
            ))
        })
        .collect()
}

pub fn basin_json(b: &squeal_scan::GridShares) -> serde_json::Value {
    let mut o = serde_json::Map::new();
    o.insert(
        "sampling".into(),
        if b.random { "random" } else { "grid" }.into(),
    );
    o.insert("n".into(), b.h.n.into());
    o.insert("n_2h".into(), b.h2.n.into());
    o.insert("n_4h".into(), b.h4.n.into());
    for (i, r) in squeal_scan::basin::REGIMES.iter().enumerate() {
        let s = b.h.shares[i];
        o.insert(
            r.name().into(),
            serde_json::json!({
                "count": s.count,
                "p": s.p,
                "se": s.se,
                "p_2h": b.h2.shares[i].p,
                "p_4h": b.h4.shares[i].p,
                "change": b.change(i),
            }),
        );
    }
    o.into()
}

/// A map's final-state sensitivity as JSON: each stored figure by its file name (null
/// where not measured).
pub fn sensitivity_json(values: &[f64]) -> serde_json::Value {
    squeal_scan::sensitivity::SENSITIVITY_FIELDS
        .iter()
        .zip(values)
        .map(|((name, ..), v)| {
            let v = if v.is_finite() {
                (*v).into()
            } else {
                serde_json::Value::Null
            };
            ((*name).to_string(), v)
        })
        .collect::<serde_json::Map<_, _>>()
        .into()
}

/// Basin stability of one map in words: each decided regime's share, with its change from
/// the `2h` sub-grid.
pub fn basin_words(b: &squeal_scan::GridShares) -> String {
    if b.h.n == 0 {
        // A shard with no rows of this map (`--shard 5/8` of a 4-row grid): no share to
        // give, where "NaN" read as a failed computation.
        return "basin stability: no cell of this map computed here (a shard without its rows)"
            .into();
    }
    let parts: Vec<String> = squeal_scan::basin::REGIMES
        .iter()
        .enumerate()
        .filter(|(i, r)| {
            let quiet = matches!(
                **r,
                squeal_core::Regime::Undecided | squeal_core::Regime::SlipOscillation
            );
            !quiet || b.h.shares[*i].count > 0
        })
        .map(|(i, r)| {
            let s = b.h.shares[i];
            if b.random {
                format!("{} {:.4} +- {:.4}", r.name(), s.p, s.se)
            } else {
                format!(
                    "{} {:.4} (2h {:.4}, change {:+.4})",
                    r.name(),
                    s.p,
                    b.h2.shares[i].p,
                    b.change(i)
                )
            }
        })
        .collect();
    if b.random {
        format!(
            "basin stability of {} random samples (+- one standard error): {}",
            b.h.n,
            parts.join("  ")
        )
    } else {
        format!("basin stability of {} cells: {}", b.h.n, parts.join("  "))
    }
}

/// A pilot that could take longer than this (seconds at the documented rate, at most
/// [`squeal_scan::estimate::PILOT_MAX_SECONDS`]) is announced before it runs: an atlas of
/// overdamped points timed its pilot for 20 s without a word.
pub const PILOT_NOTICE: f64 = 5.0;

/// A duration in the unit that reads best.
pub fn duration(secs: f64) -> String {
    if secs < 120.0 {
        format!("{secs:.0} s")
    } else if secs < 7200.0 {
        format!("{:.0} min", secs / 60.0)
    } else if secs < 2.0 * 86_400.0 {
        format!("{:.1} h", secs / 3600.0)
    } else {
        format!("{:.0} days", secs / 86_400.0)
    }
}
