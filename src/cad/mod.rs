//! CAD exports of closed polylines in mm: SVG (mm-exact), DXF (R2010 LWPOLYLINE or R12 POLYLINE),
//! point lists (CSV with header, header-less `x y 0` TXT) and STEP AP214 solids of the extruded
//! gears. Conventions: docs/math/cad.md §6, §8.
use crate::math::Point;
pub mod dxf;
pub mod points;
pub mod step;
pub mod svg;

use serde::Serialize;

/// One named polyline on a layer, in mm.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Contour {
    /// Name (e.g. `driver_outline`); used for point-list file names.
    pub name: String,
    /// Layer (e.g. `DRIVER_OUTLINE`, `DRIVER_PITCH`).
    pub layer: String,
    /// Vertices, mm. For closed contours, no duplicated end vertex.
    pub points_mm: Vec<Point>,
    /// Closed contour.
    pub closed: bool,
}

/// A named point (e.g. a gear centre), mm.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Marker {
    /// Label.
    pub name: String,
    /// Layer (e.g. `CENTRES`).
    pub layer: String,
    /// Position, mm.
    pub at_mm: Point,
}

/// A sheet: contours and markers, all in mm.
#[derive(Debug, Clone, PartialEq, Default, Serialize, schemars::JsonSchema)]
pub struct Sheet {
    /// Contours.
    pub contours: Vec<Contour>,
    /// Markers.
    pub markers: Vec<Marker>,
}

/// Errors of the exporters.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ExportError {
    /// Cannot write the file.
    #[error("cannot write {path}: {source}")]
    Io {
        /// File path.
        path: String,
        /// Cause.
        source: std::io::Error,
    },
    /// The DXF crate failed.
    #[error("DXF writer failed for {path}: {message}")]
    Dxf {
        /// File path.
        path: String,
        /// Message.
        message: String,
    },
    /// A contour has fewer than 3 vertices or a non-finite coordinate.
    #[error("contour `{name}` is invalid: {what}")]
    BadContour {
        /// Contour name.
        name: String,
        /// What is wrong.
        what: &'static str,
    },
    /// Bad option.
    #[error("invalid export option `{name}` = {value}: {expected}")]
    InvalidOption {
        /// Name.
        name: &'static str,
        /// Value.
        value: f64,
        /// Expectation.
        expected: &'static str,
    },
}

impl Sheet {
    /// Bounding box `[xmin, ymin, xmax, ymax]` of all contours and markers, mm.
    #[must_use]
    pub fn bbox_mm(&self) -> [f64; 4] {
        crate::math::polyline::bbox(
            self.contours
                .iter()
                .flat_map(|c| c.points_mm.iter())
                .chain(self.markers.iter().map(|m| &m.at_mm)),
        )
    }

    pub(crate) fn validate(&self) -> Result<(), ExportError> {
        for c in &self.contours {
            if c.points_mm.len() < 3 {
                return Err(ExportError::BadContour {
                    name: c.name.clone(),
                    what: "fewer than 3 vertices",
                });
            }
            if c.points_mm
                .iter()
                .any(|p| !(p.x.is_finite() && p.y.is_finite()))
            {
                return Err(ExportError::BadContour {
                    name: c.name.clone(),
                    what: "non-finite coordinate",
                });
            }
        }
        Ok(())
    }

    /// Sorted unique layer names.
    #[must_use]
    pub fn layers(&self) -> Vec<String> {
        let mut l: Vec<String> = self
            .contours
            .iter()
            .map(|c| c.layer.clone())
            .chain(self.markers.iter().map(|m| m.layer.clone()))
            .collect();
        l.sort();
        l.dedup();
        l
    }
}

pub(crate) fn io_err(path: &std::path::Path, source: std::io::Error) -> ExportError {
    ExportError::Io {
        path: path.display().to_string(),
        source,
    }
}
