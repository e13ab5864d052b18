//! Files written by `ncgear synthesize`: the synthesized design's files ([`super::write_design_with`])
//! and the synthesis report, `synthesis.json` (an earlier run's removed before the first file).

use super::error::{OutputError, remove_stale, write_json};
use crate::synthesis::Synthesis;
use std::path::{Path, PathBuf};

/// Writes the files of the synthesized design of `s` and then `synthesis.json` into `dir`
/// (created if needed); returns the paths written.
///
/// # Errors
/// [`OutputError`] when a file cannot be written or drawn.
pub fn write_synthesis(s: &Synthesis, dir: &Path) -> Result<Vec<PathBuf>, OutputError> {
    let path = dir.join("synthesis.json");
    remove_stale(&path)?;
    let mut written = super::write_design_with(&s.design, dir, Default::default())?;
    write_json(&path, &s.report)?;
    written.push(path);
    Ok(written)
}
