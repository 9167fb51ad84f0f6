//! `squeal merge SHARD.h5... -o OUT.h5`: join shard files (of a scan or an atlas) into one
//! file.

use std::path::PathBuf;
use std::process::ExitCode;

use super::common;
use super::pictures;

/// Flags of `squeal merge`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The shard files (all N shards of one spec).
    #[arg(required = true)]
    pub shards: Vec<PathBuf>,
    /// The joined file.
    #[arg(short = 'o', long)]
    pub out: PathBuf,
    /// Overwrite an existing output.
    #[arg(long)]
    pub force: bool,
    /// Do not draw the picture.
    #[arg(long)]
    pub no_render: bool,
}

/// Joins the shards.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let png = common::sibling(&args.out, "", "png");
    if !args.no_render {
        common::check_new(&png, args.force, "picture")?;
    }
    // Atlas shards (schema squeal-atlas/1) are joined by the atlas store. Both merges
    // refuse an input as their output (squeal_store::refuse_input_as_output).
    let atlas = squeal_store::file_kind(&args.shards[0])? == squeal_store::FileKind::Atlas;
    // Random samples are a list of points, not a map: nothing to draw (the merge used to
    // end with an error after the file was written).
    let samples = if atlas {
        crate::merge_atlas(&args.shards, &args.out, args.force, &common::provenance())?;
        false
    } else {
        let plan = crate::merge_scan(&args.shards, &args.out, args.force)?;
        plan.map.grid.is_sample()
    };
    println!("{}", args.out.display());
    if !args.no_render && !samples {
        let drawn = if atlas {
            super::atlas::render_atlas(&args.out, &png, true)?
        } else {
            pictures::render_file(&args.out, &png, true)?
        };
        for p in drawn {
            println!("{}", p.display());
        }
    }
    Ok(ExitCode::SUCCESS)
}
