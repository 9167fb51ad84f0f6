//! `squeal render OUT.h5 [-o PNG]`: redraw the picture(s) of a scan file.

use std::path::PathBuf;
use std::process::ExitCode;

use super::common;
use super::pictures;

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
    // A FIFO at the picture blocked the drawing for ever (with --force).
    super::out_files::regular("-o", &png)?;
    // An atlas file (schema squeal-atlas/1) gets its chart; a scan file its basin maps.
    let drawn = if squeal_store::atlas::is_atlas_file(&args.file) {
        super::atlas::render_atlas(&args.file, &png, args.force)?
    } else {
        pictures::render_file(&args.file, &png, args.force)?
    };
    for p in drawn {
        println!("{}", p.display());
    }
    Ok(ExitCode::SUCCESS)
}
