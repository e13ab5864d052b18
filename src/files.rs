//! Output files written whole: every file goes to a hidden temporary name beside its place
//! (`.partial-NAME`) and is renamed onto its name once written, so a run interrupted (Ctrl-C,
//! a kill, a full disk) leaves no file under a real name that looks complete and is not. A
//! rename within one directory is atomic on POSIX file systems and replaces on Windows.
//!
//! ```
//! let dir = std::env::temp_dir().join(format!("ncgear-files-doc-{}", std::process::id()));
//! std::fs::create_dir_all(&dir).unwrap();
//! let path = dir.join("report.json");
//! ncgear::files::write_whole(&path, "{}").unwrap();
//! assert_eq!(std::fs::read_to_string(&path).unwrap(), "{}");
//! assert!(!ncgear::files::partial_path(&path).exists());
//! # std::fs::remove_dir_all(&dir).unwrap();
//! ```

use std::path::{Path, PathBuf};

/// The temporary name a file is written under before it takes `path`: `.partial-NAME` in the
/// same directory (the same file system, so the final rename is atomic; the extension kept, for
/// writers that choose the format by it).
#[must_use]
pub fn partial_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
    path.with_file_name(format!(".partial-{name}"))
}

/// Writes `contents` to `path` whole (module documentation).
pub fn write_whole(path: &Path, contents: impl AsRef<[u8]>) -> std::io::Result<()> {
    write_whole_with(path, |tmp| std::fs::write(tmp, contents), |e| e)
}

/// Lets `write` create the file at a temporary path (for writers that take a path: plotters,
/// the DXF crate), then renames it onto `path`. On an error the temporary file is removed and
/// the error returned; `io` turns a failed rename into the caller's error type.
pub fn write_whole_with<T, E>(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<T, E>,
    io: impl FnOnce(std::io::Error) -> E,
) -> Result<T, E> {
    let tmp = partial_path(path);
    match write(&tmp) {
        Ok(v) => match std::fs::rename(&tmp, path) {
            Ok(()) => Ok(v),
            Err(e) => {
                let _ = std::fs::remove_file(&tmp);
                Err(io(e))
            }
        },
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            Err(e)
        }
    }
}

/// Removes a report left by an earlier run at `path` before the files of a new run are written,
/// so that files of two runs never sit beside a report that vouches for them (the report is
/// written last). A missing file is not an error.
pub fn remove_stale(path: &Path) -> std::io::Result<()> {
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(e),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_writer_leaves_neither_the_file_nor_its_temporary() {
        let dir = std::env::temp_dir().join(format!("ncgear-files-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("a.svg");
        std::fs::write(&path, "old").unwrap();
        let r: Result<(), String> = write_whole_with(
            &path,
            |tmp| {
                std::fs::write(tmp, "half").unwrap();
                Err("interrupted".into())
            },
            |e| e.to_string(),
        );
        assert_eq!(r.unwrap_err(), "interrupted");
        assert!(!partial_path(&path).exists());
        // The earlier file is untouched: a failed write never replaces it with a torn one.
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
        write_whole(&path, "new").unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
        remove_stale(&path).unwrap();
        remove_stale(&path).unwrap();
        assert!(!path.exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn the_temporary_name_is_hidden_beside_the_file() {
        assert_eq!(
            partial_path(Path::new("out/teeth/sun.step")),
            Path::new("out/teeth/.partial-sun.step")
        );
    }
}
