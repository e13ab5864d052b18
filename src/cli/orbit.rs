//! `ncgear orbit`.
use super::{CliResult, runtime_error};

/// Arguments of `ncgear orbit`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `ncgear orbit`.
pub fn run(_args: Args) -> CliResult {
    Err(runtime_error(miette::miette!("`ncgear orbit` is not built yet")))
}
