//! `ncgear dynamics`.
use super::{CliResult, runtime_error};

/// Arguments of `ncgear dynamics`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `ncgear dynamics`.
pub fn run(_args: Args) -> CliResult {
    Err(runtime_error(miette::miette!("`ncgear dynamics` is not built yet")))
}
