//! `squeal render OUT.h5 [-o PNG]`: redraw the picture(s) of a scan file.

use std::path::PathBuf;
use std::process::ExitCode;

use super::common;

/// Flags of `squeal render`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// A scan file written by `squeal scan` or `squeal merge`.
    pub file: PathBuf,
    /// The picture (.png); default: beside the file.
    #[arg(short = 'o', long)]
    pub out: Option<PathBuf>,
    /// Overwrite existing pictures.
    #[arg(long)]
    pub force: bool,
}

/// Draws the pictures.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let png = args
        .out
        .unwrap_or_else(|| common::sibling(&args.file, "", "png"));
    if png.extension().and_then(|e| e.to_str()) != Some("png") {
        anyhow::bail!("-o {}: expected a file name ending in .png", png.display());
    }
    for p in common::render_file(&args.file, &png, args.force)? {
        println!("{}", p.display());
    }
    Ok(ExitCode::SUCCESS)
}
