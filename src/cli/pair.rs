//! `ncgear pair`.
use super::{CliResult, runtime_error};

/// Arguments of `ncgear pair`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `ncgear pair`.
pub fn run(_args: Args) -> CliResult {
    Err(runtime_error(miette::miette!(
        "`ncgear pair` is not built yet"
    )))
}
