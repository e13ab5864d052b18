//! Why an output file could not be written, and the helpers that write a text file or create a directory.

use std::path::Path;

/// Why an output file could not be written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OutputError {
    /// File system error.
    #[error("cannot write {path}: {message}")]
    Io {
        /// Path.
        path: String,
        /// OS message.
        message: String,
    },
    /// Plotting failed.
    #[error(transparent)]
    Plot(#[from] super::plot::PlotError),
    /// A CAD export failed.
    #[error(transparent)]
    Export(#[from] crate::cad::ExportError),
    /// A sensor record could not be brought into the frame its plots are drawn in.
    #[error(transparent)]
    Orbit(#[from] crate::analysis::orbit::OrbitError),
}

/// Writes `text` to `path`.
pub(super) fn write(path: &Path, text: &str) -> Result<(), OutputError> {
    crate::files::write_whole(path, text).map_err(|e| OutputError::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    })
}

/// Writes `value` to `path` as the project's JSON ([`super::json::to_string`]).
pub(super) fn write_json(path: &Path, value: &impl serde::Serialize) -> Result<(), OutputError> {
    let text = super::json::to_string(value).map_err(|e| OutputError::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    })?;
    write(path, &text)
}

/// Removes an earlier run's report at `path` ([`crate::files::remove_stale`]).
pub(super) fn remove_stale(path: &Path) -> Result<(), OutputError> {
    crate::files::remove_stale(path).map_err(|e| OutputError::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    })
}

/// Creates `dir` and its parents.
pub(super) fn create_dir(dir: &Path) -> Result<(), OutputError> {
    std::fs::create_dir_all(dir).map_err(|e| OutputError::Io {
        path: dir.display().to_string(),
        message: e.to_string(),
    })
}
