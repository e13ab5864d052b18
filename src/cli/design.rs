//! `ncgear design`.
use super::{CliResult, runtime_error};

/// Arguments of `ncgear design`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `ncgear design`.
pub fn run(_args: Args) -> CliResult {
    Err(runtime_error(miette::miette!("`ncgear design` is not built yet")))
}
