//! `squeal report FILE.h5 [-o FILE.html]`: one self-contained interactive page of a scan,
//! an atlas or a trajectory file (`squeal_report`).

use std::path::PathBuf;
use std::process::ExitCode;

/// Flags of `squeal report`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// A file written by `squeal scan`, `squeal atlas`, `squeal trajectory --out` or
    /// `squeal merge`.
    pub file: PathBuf,
    /// The page (.html); default: beside the file, FILE.html.
    #[arg(short = 'o', long)]
    pub out: Option<PathBuf>,
    /// Overwrite an existing page.
    #[arg(long)]
    pub force: bool,
}

/// Writes the page and prints its path.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let out = write(&args.file, args.out.as_deref(), args.force)?;
    println!("report: {}", out.display());
    Ok(ExitCode::SUCCESS)
}

/// Writes the report of `file` (what `scan --report` and `atlas --report` call too), with
/// the store's refusals in the words every door uses.
pub fn write(
    file: &std::path::Path,
    out: Option<&std::path::Path>,
    force: bool,
) -> anyhow::Result<PathBuf> {
    squeal_report::write(file, out, force, env!("CARGO_PKG_VERSION")).map_err(|e| match e {
        squeal_report::ReportError::Store(s) => anyhow::Error::from(s),
        other => anyhow::Error::from(other),
    })
}
