//! `ncgear tolerance`.
use super::{CliResult, runtime_error};

/// Arguments of `ncgear tolerance`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `ncgear tolerance`.
pub fn run(_args: Args) -> CliResult {
    Err(runtime_error(miette::miette!("`ncgear tolerance` is not built yet")))
}
