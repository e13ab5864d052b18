//! DXF writer: R2010 via the `dxf` crate (one closed LWPOLYLINE per contour, closed flag set, no
//! duplicated end vertex, `$INSUNITS` = 4 mm, `$MEASUREMENT` = metric, a layer per contour kind,
//! POINT entities for markers), or a hand-written minimal R12 (POLYLINE/VERTEX/SEQEND, no
//! group-100 subclass markers) for old programs. No SPLINE entities. Contours are simplified to
//! `chord_tol_mm` (Douglas–Peucker). Conventions: docs/math/cad.md §6, §10.
use super::{ExportError, Sheet, io_err};
use crate::math::polyline::simplify_closed;
use ::dxf::Drawing;
use ::dxf::LwPolylineVertex;
use ::dxf::entities::{Entity, EntityType, LwPolyline, ModelPoint};
use ::dxf::enums::{AcadVersion, DrawingUnits, Units};
use ::dxf::tables::Layer;

use crate::math::Point;
use std::fmt::Write as _;
use std::path::Path;

/// DXF flavour.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, schemars::JsonSchema)]
#[non_exhaustive]
pub enum DxfVersion {
    /// AutoCAD 2010, LWPOLYLINE (default).
    R2010,
    /// AutoCAD R12, POLYLINE/VERTEX (hand-written subset).
    R12,
}

/// `$TDCREATE`/`$TDUCREATE`/`$TDUPDATE`/`$TDUUPDATE` (Julian day 2451545.0, 2000-01-01 12:00) and
/// `$FINGERPRINTGUID`/`$VERSIONGUID` (fixed, not random) of every R2010 file: the same sheet gives
/// the same bytes. Read by the `dxf` crate itself, so the values need no date/UUID types here.
const FIXED_HEADER: &str = "  0\nSECTION\n  2\nHEADER\n\
  9\n$TDCREATE\n 40\n2451545.0\n  9\n$TDUCREATE\n 40\n2451545.0\n\
  9\n$TDUPDATE\n 40\n2451545.0\n  9\n$TDUUPDATE\n 40\n2451545.0\n\
  9\n$FINGERPRINTGUID\n  2\n6e636765-6172-4000-8000-000000000001\n\
  9\n$VERSIONGUID\n  2\n6e636765-6172-4000-8000-000000000002\n\
  0\nENDSEC\n  0\nEOF\n";

/// The R2010 drawing of `contours` (`(layer, points mm, closed)`) and the sheet's markers, with the
/// fixed header stamps of [`FIXED_HEADER`].
fn r2010(sheet: &Sheet, contours: Vec<(String, Vec<Point>, bool)>) -> Drawing {
    let mut d = Drawing::new();
    // The template is a constant and valid; on a parse failure the crate's defaults stay.
    if let Ok(fixed) = Drawing::load(&mut FIXED_HEADER.as_bytes()) {
        let (h, f) = (&mut d.header, fixed.header);
        h.creation_date = f.creation_date;
        h.creation_date_universal = f.creation_date_universal;
        h.update_date = f.update_date;
        h.update_date_universal = f.update_date_universal;
        h.fingerprint_guid = f.fingerprint_guid;
        h.version_guid = f.version_guid;
    }
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
    for (layer, pts, closed) in contours {
        let mut pl = LwPolyline::default();
        pl.set_is_closed(closed);
        pl.vertices = pts
            .iter()
            .map(|p| LwPolylineVertex {
                x: p.x,
                y: p.y,
                ..Default::default()
            })
            .collect();
        let mut e = Entity::new(EntityType::LwPolyline(pl));
        e.common.layer = layer;
        d.add_entity(e);
    }
    for m in &sheet.markers {
        let mut e = Entity::new(EntityType::ModelPoint(ModelPoint::new(::dxf::Point::new(
            m.at_mm.x, m.at_mm.y, 0.0,
        ))));
        e.common.layer = m.layer.clone();
        d.add_entity(e);
    }
    d
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
    let simplified: Vec<(String, Vec<Point>, bool)> = sheet
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
            let drawing = r2010(sheet, simplified);
            crate::files::write_whole_with(
                path,
                |tmp| {
                    drawing.save_file(tmp).map_err(|e| ExportError::Dxf {
                        path: path.display().to_string(),
                        message: e.to_string(),
                    })
                },
                |e| io_err(path, e),
            )
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
                    pair(10, &format!("{:.9}", p.x));
                    pair(20, &format!("{:.9}", p.y));
                    pair(30, "0.0");
                }
                pair(0, "SEQEND");
                pair(8, layer);
            }
            for m in &sheet.markers {
                pair(0, "POINT");
                pair(8, &m.layer);
                pair(10, &format!("{:.9}", m.at_mm.x));
                pair(20, &format!("{:.9}", m.at_mm.y));
                pair(30, "0.0");
            }
            pair(0, "ENDSEC");
            pair(0, "EOF");
            crate::files::write_whole(path, s).map_err(|e| io_err(path, e))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cad::{Contour, Marker};

    fn sheet() -> Sheet {
        Sheet {
            contours: vec![Contour {
                name: "square".into(),
                layer: "OUTLINE".into(),
                points_mm: vec![
                    Point::new(0.0, 0.0),
                    Point::new(10.0, 0.0),
                    Point::new(10.0, 10.0),
                    Point::new(0.0, 10.0),
                ],
                closed: true,
            }],
            markers: vec![Marker {
                name: "O".into(),
                layer: "CENTRES".into(),
                at_mm: Point::new(5.0, 5.0),
            }],
        }
    }

    #[test]
    fn same_sheet_gives_the_same_bytes_with_fixed_stamps() {
        let dir = std::env::temp_dir().join(format!("ncgear_dxf_det_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (a, b) = (dir.join("a.dxf"), dir.join("b.dxf"));
        write_dxf(&sheet(), &a, DxfVersion::R2010, 0.0).unwrap();
        std::thread::sleep(std::time::Duration::from_millis(1100));
        write_dxf(&sheet(), &b, DxfVersion::R2010, 0.0).unwrap();
        let (ta, tb) = (std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
        assert_eq!(ta, tb, "two writes of the same sheet differ");
        let text = String::from_utf8(ta).unwrap();
        for stamp in [
            "$TDCREATE\n 40\n2451545.0",
            "$TDUUPDATE\n 40\n2451545.0",
            "$FINGERPRINTGUID\n  2\n6e636765-6172-4000-8000-000000000001",
            "$VERSIONGUID\n  2\n6e636765-6172-4000-8000-000000000002",
        ] {
            let stamp = stamp.replace('\n', "\r\n");
            assert!(
                text.contains(stamp.as_str()) || text.contains(&stamp.replace("\r\n", "\n")),
                "missing {stamp:?}"
            );
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
