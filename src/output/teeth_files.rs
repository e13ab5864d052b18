//! CAD files of a toothed train (`ncgear design --module M`): SVG and DXF sheets of the train and
//! of each gear, and the point lists (mm).

use super::error::{OutputError, create_dir};
use crate::cad::dxf::{DxfVersion, write_dxf};
use crate::cad::points::write_points;
use crate::cad::svg::write_svg;
use crate::design::train::{Gear, ToothedTrain};
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// CAD files of a toothed train (`ncgear design --module M`), under `dir/teeth/`:
/// - `train.svg`, `train.dxf`: the mechanism sheet, the whole train at φH = 0 (world frame);
/// - `<gear>.svg`, `<gear>.dxf`: each gear in its body frame (rotation centre at the origin);
/// - `<gear>_points/`: `points.csv` (`contour,index,x_mm,y_mm`) and a header-less `x y 0` TXT per
///   contour (`<gear>_outline.txt`, `<gear>_pitch.txt`), body frame, unsimplified.
///
/// DXF contours are simplified to `train.report.options.toothing.chord_tol_mm`; SVG and DXF in mm.
/// The written paths are also stored in `train.report.files`.
pub fn write_teeth(
    train: &mut ToothedTrain,
    dir: &Path,
    dxf_version: DxfVersion,
) -> Result<Vec<PathBuf>, OutputError> {
    let dir = dir.join("teeth");
    create_dir(&dir)?;
    let tol = train.report.options.toothing.chord_tol_mm;
    let margin = 2.0 * train.report.module_mm;
    let mut sheets = vec![("train".to_string(), train.sheet(0.0))];
    for g in Gear::ALL {
        sheets.push((g.name().to_string(), train.gear_sheet(g)));
    }
    // The sheets' files are independent: written side by side, listed in sheet order (the first
    // error in that order is returned).
    let per_sheet = sheets
        .par_iter()
        .enumerate()
        .map(|(k, (name, sheet))| -> Result<Vec<PathBuf>, OutputError> {
            let svg = dir.join(format!("{name}.svg"));
            write_svg(sheet, &svg, margin)?;
            let dxf = dir.join(format!("{name}.dxf"));
            write_dxf(sheet, &dxf, dxf_version, tol)?;
            let mut files = vec![svg, dxf];
            if k > 0 {
                files.extend(write_points(
                    sheet,
                    &dir.join(format!("{name}_points")),
                    "points",
                )?);
            }
            Ok(files)
        })
        .collect::<Vec<_>>();
    let mut written = Vec::new();
    for files in per_sheet {
        written.extend(files?);
    }
    train.report.files = written.iter().map(|p| p.display().to_string()).collect();
    Ok(written)
}
