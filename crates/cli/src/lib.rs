//! # squeal-cli: the `squeal` command line
//!
//! Trajectories, friction curves, basin scans, the unstable limit cycle, sweeps and shards.
//! Numerics live in the other `squeal-*` crates; this crate parses flags, shows progress and
//! prints reports. [`run_from`] runs it: the `squeal` binary (the root package's
//! `src/main.rs`) with the process's arguments, the Python package's `squeal` command with
//! its own. The library API the Python package shares with the command line:
//! [`provenance`], what both record in the files they write, [`run_atlas`], which
//! computes what an atlas file is missing, [`finish_scan`] and [`finish_atlas`], which end
//! a run (what the engine computes from the stored results, handed to the writer); and
//! [`words`], each door's words for what the library's refusals advise.

use std::process::ExitCode;

use clap::{Parser, Subcommand};

mod atlas_json;
mod atlas_run;
mod cmd;
mod finishing;
pub mod words;

pub use atlas_run::{AtlasRunError, run_atlas};
pub use cmd::common::provenance;
pub use finishing::{FinishError, finish_atlas, finish_scan, merge_atlas, merge_scan};

/// Basins of attraction of McMillan's friction oscillator: steady slip or stick-slip squeal.
#[derive(Parser, Debug)]
#[command(name = "squeal", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Integrate one run from (x0, v0) and say where it ends up.
    Trajectory(cmd::trajectory::Args),
    /// The paper's friction curves (Figs 4-7) in physical units, as CSV and PNG.
    Friction(cmd::friction::Args),
    /// Map a grid of initial conditions to labels into an HDF5 file and a PNG.
    Scan(cmd::scan::Args),
    /// Label arbitrary initial conditions from a CSV file.
    Classify(cmd::classify::Args),
    /// Redraw the picture of a scan file.
    Render(cmd::render::Args),
    /// Write a self-contained interactive page (HTML) of a scan, atlas or trajectory file.
    Report(cmd::report::Args),
    /// Print a scan file's parameters and label counts.
    Info(cmd::info::Args),
    /// Locate the unstable limit cycle (the basin boundary) as a periodic orbit.
    Ulc(cmd::ulc::Args),
    /// Find the damping at which the unstable cycle first encloses a given state.
    Critical(cmd::critical::Args),
    /// Figures of merit, regimes, the fold and critical damping over a design space.
    Atlas(cmd::atlas::Args),
    /// Cell-by-cell agreement of two scans of the same grid (e.g. against a reference).
    Compare(cmd::compare::Args),
    /// Join the shard files of a scan into the file a single run would have written.
    Merge(cmd::merge::Args),
}

/// Runs the command line `args` (the program name first) and returns its exit status: the
/// `squeal` binary passes the process's arguments, the Python package's `squeal` command its
/// own.
pub fn run_from<I, T>(args: I) -> ExitCode
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let cli = Cli::parse_from(args);
    let result = match cli.command {
        Command::Trajectory(a) => cmd::trajectory::run(a),
        Command::Friction(a) => cmd::friction::run(a),
        Command::Scan(a) => cmd::scan::run(a),
        Command::Classify(a) => cmd::classify::run(a),
        Command::Render(a) => cmd::render::run(a),
        Command::Report(a) => cmd::report::run(a),
        Command::Info(a) => cmd::info::run(a),
        Command::Ulc(a) => cmd::ulc::run(a),
        Command::Critical(a) => cmd::critical::run(a),
        Command::Merge(a) => cmd::merge::run(a),
        Command::Compare(a) => cmd::compare::run(a),
        Command::Atlas(a) => cmd::atlas::run(a),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {}", words::message(&e, &words::Flags));
            ExitCode::from(2)
        }
    }
}
