//! Point lists: a CSV with header and units, and a header-less `x y 0` TXT per closed contour (mm).
use super::{ExportError, Sheet, io_err};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Writes `<dir>/<name>.csv` (`contour,index,x_mm,y_mm`) with every contour, and one
/// `<dir>/<contour name>.txt` per contour with lines `x y 0` (mm, no header). Returns the paths.
pub fn write_points(sheet: &Sheet, dir: &Path, name: &str) -> Result<Vec<PathBuf>, ExportError> {
    sheet.validate()?;
    std::fs::create_dir_all(dir).map_err(|e| io_err(dir, e))?;
    let mut csv = String::from("contour,index,x_mm,y_mm\n");
    let mut paths = Vec::new();
    for c in &sheet.contours {
        let mut txt = String::new();
        for (i, p) in c.points_mm.iter().enumerate() {
            let _ = writeln!(csv, "{},{},{:.9},{:.9}", c.name, i, p.x, p.y);
            let _ = writeln!(txt, "{:.9} {:.9} 0", p.x, p.y);
        }
        let path = dir.join(format!("{}.txt", c.name));
        crate::files::write_whole(&path, txt).map_err(|e| io_err(&path, e))?;
        paths.push(path);
    }
    let path = dir.join(format!("{name}.csv"));
    crate::files::write_whole(&path, csv).map_err(|e| io_err(&path, e))?;
    paths.push(path);
    Ok(paths)
}
