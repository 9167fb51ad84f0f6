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

/// `scan --report` and `atlas --report`, before anything is computed: a page already beside
/// the output is refused without `--force` (a resume keeps what it finds).
pub fn check_before(run: &super::common::RunArgs, out: &std::path::Path) -> anyhow::Result<()> {
    let page = squeal_report::default_out(out);
    if run.report && !run.resume {
        // `check_new` refuses a FIFO there too, before the existence check.
        super::common::check_new(&page, run.force, "report of the run")?;
    }
    Ok(())
}

/// `scan --report` and `atlas --report`, once the file is finished: writes the page (a
/// page already there is kept unless `--force`) and says where it is, on stdout (stderr
/// beside a JSON summary, which stays one object).
pub fn after_run(
    run: &super::common::RunArgs,
    out: &std::path::Path,
    json: bool,
) -> anyhow::Result<()> {
    if !run.report {
        return Ok(());
    }
    let page = squeal_report::default_out(out);
    let line = if page.exists() && !run.force {
        format!("  report: {} (kept: already there)", page.display())
    } else {
        format!("  report: {}", write(out, Some(&page), true)?.display())
    };
    if json {
        eprintln!("{}", line.trim_start());
    } else {
        println!("{line}");
    }
    Ok(())
}
