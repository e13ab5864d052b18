//! `ncgear simulate`.
use super::{CliResult, runtime_error};

/// Arguments of `ncgear simulate`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `ncgear simulate`.
pub fn run(_args: Args) -> CliResult {
    Err(runtime_error(miette::miette!("`ncgear simulate` is not built yet")))
}
