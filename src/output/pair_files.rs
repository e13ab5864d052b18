//! The report written by `ncgear pair`: `pair.json`, every object's keys in sorted order (as in
//! `design.json`), written after the pair's CAD files.

use super::error::{OutputError, write_json};
use crate::pair::PairReport;
use std::path::{Path, PathBuf};

/// Writes `report` to `dir/pair.json`, its keys sorted; returns the path written.
///
/// # Errors
/// [`OutputError::Io`] when the report cannot be written.
pub fn write_pair_report(report: &PairReport, dir: &Path) -> Result<PathBuf, OutputError> {
    let path = dir.join("pair.json");
    // Through `serde_json::Value`, whose objects keep their keys sorted.
    let value = serde_json::to_value(report).map_err(|e| OutputError::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    })?;
    write_json(&path, &value)?;
    Ok(path)
}
