//! DXF writer: R2010 via the `dxf` crate (one closed LWPOLYLINE per contour, closed flag set, no
//! duplicated end vertex, `$INSUNITS` = 4 mm, `$MEASUREMENT` = metric, a layer per contour kind,
//! POINT entities for markers), or a hand-written minimal R12 (POLYLINE/VERTEX/SEQEND, no
//! group-100 subclass markers) for old programs. No SPLINE entities. Contours are simplified to
//! `chord_tol_mm` (Douglas–Peucker). Spec: peers-and-cad.md §6, §10.
use super::{ExportError, Sheet, io_err};
use crate::math::polyline::simplify_closed;
use ::dxf::LwPolylineVertex;
use ::dxf::entities::{Entity, EntityType, LwPolyline, ModelPoint};
use ::dxf::enums::{AcadVersion, DrawingUnits, Units};
use ::dxf::tables::Layer;
use ::dxf::{Drawing, Point};
use std::fmt::Write as _;
use std::path::Path;

/// DXF flavour.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[non_exhaustive]
pub enum DxfVersion {
    /// AutoCAD 2010, LWPOLYLINE (default).
    R2010,
    /// AutoCAD R12, POLYLINE/VERTEX (hand-written subset).
    R12,
}

/// Writes `sheet` as DXF; each closed contour is simplified to chord tolerance `chord_tol_mm`.
pub fn write_dxf(
    sheet: &Sheet,
    path: &Path,
    version: DxfVersion,
    chord_tol_mm: f64,
) -> Result<(), ExportError> {
    sheet.validate()?;
    if !(chord_tol_mm.is_finite() && chord_tol_mm >= 0.0) {
        return Err(ExportError::InvalidOption {
            name: "chord_tol_mm",
            value: chord_tol_mm,
            expected: "finite and ≥ 0",
        });
    }
    let simplified: Vec<(String, Vec<[f64; 2]>, bool)> = sheet
        .contours
        .iter()
        .map(|c| {
            let pts = if c.closed && chord_tol_mm > 0.0 {
                simplify_closed(&c.points_mm, chord_tol_mm)
            } else {
                c.points_mm.clone()
            };
            (c.layer.clone(), pts, c.closed)
        })
        .collect();
    match version {
        DxfVersion::R2010 => {
            let mut d = Drawing::new();
            d.header.version = AcadVersion::R2010;
            d.header.default_drawing_units = Units::Millimeters;
            d.header.drawing_units = DrawingUnits::Metric;
            for name in sheet.layers() {
                let layer = Layer {
                    name,
                    ..Default::default()
                };
                d.add_layer(layer);
            }
            for (layer, pts, closed) in simplified {
                let mut pl = LwPolyline::default();
                pl.set_is_closed(closed);
                pl.vertices = pts
                    .iter()
                    .map(|p| LwPolylineVertex {
                        x: p[0],
                        y: p[1],
                        ..Default::default()
                    })
                    .collect();
                let mut e = Entity::new(EntityType::LwPolyline(pl));
                e.common.layer = layer;
                d.add_entity(e);
            }
            for m in &sheet.markers {
                let mut e = Entity::new(EntityType::ModelPoint(ModelPoint::new(Point::new(
                    m.at_mm[0], m.at_mm[1], 0.0,
                ))));
                e.common.layer = m.layer.clone();
                d.add_entity(e);
            }
            d.save_file(path).map_err(|e| ExportError::Dxf {
                path: path.display().to_string(),
                message: e.to_string(),
            })
        }
        DxfVersion::R12 => {
            let mut s = String::new();
            let mut pair = |code: i32, v: &str| {
                let _ = writeln!(s, "{code:>3}\n{v}");
            };
            pair(0, "SECTION");
            pair(2, "HEADER");
            pair(9, "$ACADVER");
            pair(1, "AC1009");
            pair(9, "$INSUNITS");
            pair(70, "4");
            pair(0, "ENDSEC");
            pair(0, "SECTION");
            pair(2, "TABLES");
            pair(0, "TABLE");
            pair(2, "LAYER");
            let layers = sheet.layers();
            pair(70, &layers.len().to_string());
            for l in &layers {
                pair(0, "LAYER");
                pair(2, l);
                pair(70, "0");
                pair(62, "7");
                pair(6, "CONTINUOUS");
            }
            pair(0, "ENDTAB");
            pair(0, "ENDSEC");
            pair(0, "SECTION");
            pair(2, "ENTITIES");
            for (layer, pts, closed) in &simplified {
                pair(0, "POLYLINE");
                pair(8, layer);
                pair(66, "1");
                pair(10, "0.0");
                pair(20, "0.0");
                pair(30, "0.0");
                pair(70, if *closed { "1" } else { "0" });
                for p in pts {
                    pair(0, "VERTEX");
                    pair(8, layer);
                    pair(10, &format!("{:.9}", p[0]));
                    pair(20, &format!("{:.9}", p[1]));
                    pair(30, "0.0");
                }
                pair(0, "SEQEND");
                pair(8, layer);
            }
            for m in &sheet.markers {
                pair(0, "POINT");
                pair(8, &m.layer);
                pair(10, &format!("{:.9}", m.at_mm[0]));
                pair(20, &format!("{:.9}", m.at_mm[1]));
                pair(30, "0.0");
            }
            pair(0, "ENDSEC");
            pair(0, "EOF");
            std::fs::write(path, s).map_err(|e| io_err(path, e))
        }
    }
}
