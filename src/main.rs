//! The `squeal` command line. The program is the library crate `squeal-cli`
//! (crates/cli), which the Python package's `squeal` command runs too.

use std::process::ExitCode;

fn main() -> ExitCode {
    squeal_cli::run_from(std::env::args_os())
}
