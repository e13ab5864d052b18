//! The target loop of a DXF drawing: a closed LWPOLYLINE, POLYLINE, SPLINE or CIRCLE, or LINEs and
//! ARCs (and open polylines or splines) that close end to end, in model space.
//!
//! - **Units**: `$INSUNITS` millimetres, centimetres, metres or inches; unitless or other units
//!   are refused unless [`DrawingOptions::units`] gives them (which then replaces `$INSUNITS`).
//! - **Polylines**: a vertex's bulge `b` makes its segment a circular arc of included angle
//!   `θ = 4·atan b` (counter-clockwise when b > 0), radius `r = c/(2·|sin(θ/2)|)` for the chord
//!   c, centre at the chord midpoint plus `c·(1 − b²)/(4b)` along the chord's left normal.
//!   The closing segment of a closed polyline carries the last vertex's bulge.
//! - **Splines**: the B-spline the entity stores, degree, knots and (rational) weights as
//!   written, evaluated by [`super::nurbs`] over its whole knot domain. A SPLINE with fit
//!   points only (no control points) is refused: the curve AutoCAD draws through them depends
//!   on its own end-tangent rules, which a reader can only approximate; convert it to control
//!   points in the CAD program (or export a polyline).
//! - **Chains**: open pieces on one layer are joined end to end (either way round) in file
//!   order, starting with the first as drawn; ends meet within `1e-6` of the drawing size
//!   ([`super::drawing::CLOSE_RELATIVE`]). A chain that does not close is an open loop; more
//!   than two ends at one point are refused ([`super::dxf_chain`]). A polyline or spline is
//!   taken in the order drawn, crossing itself or not.
//! - **Choice**: one loop in the whole drawing, or the one loop on [`DrawingOptions::layer`].
//!   Entities in paper space and inside blocks (INSERT) are not read; an extrusion direction
//!   of −Z mirrors x (the arbitrary-axis rule for the OCS of ARC, CIRCLE and LWPOLYLINE).

use super::drawing::{DrawingOptions, DrawingUnits, FLATNESS_MM, choose, open_loop, trajectory};
use super::dxf_chain::{Piece, chains};
use super::flatten::flatten;
use super::nurbs::Nurbs;
use super::{Trajectory, TrajectoryError};
use crate::math::Point;
use dxf::entities::{Entity, EntityType};
use dxf::enums::Units;
use std::f64::consts::TAU;

/// Reads the loop (module docs).
pub(super) fn read(
    bytes: &[u8],
    opts: &DrawingOptions,
    file: &str,
) -> Result<Trajectory, TrajectoryError> {
    let drawing = dxf::Drawing::load(&mut std::io::Cursor::new(bytes)).map_err(|e| {
        TrajectoryError::NotADrawing {
            file: file.to_string(),
            format: "DXF".into(),
            message: e.to_string(),
        }
    })?;
    let mm = match opts.units {
        Some(u) => u.mm(),
        None => file_units(drawing.header.default_drawing_units, file)?.mm(),
    };
    let wanted = opts.layer.as_deref();
    let mut pieces = Vec::new();
    for e in drawing.entities().filter(|e| !e.common.is_in_paper_space) {
        match piece(e, mm) {
            Ok(Some(p)) => pieces.push(p),
            Ok(None) => {}
            Err(message) if wanted.is_none_or(|w| w == e.common.layer) => {
                return Err(TrajectoryError::BadSpline {
                    file: file.to_string(),
                    what: describe(e),
                    message,
                });
            }
            Err(_) => {}
        }
    }
    if pieces.is_empty() {
        return Err(TrajectoryError::NoGeometry {
            file: file.to_string(),
            message: "no LWPOLYLINE, POLYLINE, SPLINE, CIRCLE, LINE or ARC in model space".into(),
        });
    }
    let (loops, open, junctions) = chains(pieces);
    let named = |layer: &str| wanted.is_none_or(|w| w == layer);
    if let Some(j) = junctions.into_iter().find(|j| named(&j.layer)) {
        return Err(j.error(file));
    }
    if !loops.iter().any(|l| named(&l.group))
        && let Some((what, end, start, _)) = open.into_iter().find(|o| named(&o.3))
    {
        return Err(open_loop(file, what, end, start));
    }
    trajectory(choose(loops, wanted, "layer", file)?, file)
}

/// `$INSUNITS` as drawing units, or why not.
fn file_units(u: Units, file: &str) -> Result<DrawingUnits, TrajectoryError> {
    match u {
        Units::Millimeters => Ok(DrawingUnits::Mm),
        Units::Centimeters => Ok(DrawingUnits::Cm),
        Units::Meters => Ok(DrawingUnits::M),
        Units::Inches => Ok(DrawingUnits::In),
        other => Err(TrajectoryError::UnitsUnknown {
            file: file.to_string(),
            found: format!("$INSUNITS is {other:?}"),
        }),
    }
}

/// `LWPOLYLINE 2F on layer "0"`.
fn describe(e: &Entity) -> String {
    let kind = match &e.specific {
        EntityType::LwPolyline(_) => "LWPOLYLINE",
        EntityType::Polyline(_) => "POLYLINE",
        EntityType::Spline(_) => "SPLINE",
        EntityType::Circle(_) => "CIRCLE",
        EntityType::Line(_) => "LINE",
        EntityType::Arc(_) => "ARC",
        _ => "entity",
    };
    format!(
        "{kind} {:X} on layer \"{}\"",
        e.common.handle.0, e.common.layer
    )
}

/// The entity flattened in mm (`None`: not a curve of the loop), or what is wrong with it.
fn piece(e: &Entity, mm: f64) -> Result<Option<Piece>, String> {
    let scale = |x: f64, y: f64| Point::new(mm * x, mm * y);
    let mut pts = Vec::new();
    let mut straight = false;
    match &e.specific {
        EntityType::Line(l) => {
            pts = vec![scale(l.p1.x, l.p1.y), scale(l.p2.x, l.p2.y)];
            straight = true;
        }
        EntityType::Arc(a) => {
            let sx = if a.normal.z < 0.0 { -1.0 } else { 1.0 };
            let (t0, mut t1) = (a.start_angle.to_radians(), a.end_angle.to_radians());
            while t1 <= t0 {
                t1 += TAU;
            }
            let (c, r) = (&a.center, a.radius);
            let f = |t: f64| scale(sx * (c.x + r * t.cos()), c.y + r * t.sin());
            pts.push(f(t0));
            flatten(&f, t0, t1, FLATNESS_MM, &mut pts);
        }
        EntityType::Circle(a) => {
            let sx = if a.normal.z < 0.0 { -1.0 } else { 1.0 };
            let (c, r) = (&a.center, a.radius);
            let f = |t: f64| scale(sx * (c.x + r * t.cos()), c.y + r * t.sin());
            pts.push(f(0.0));
            flatten(&f, 0.0, TAU, FLATNESS_MM, &mut pts);
        }
        EntityType::LwPolyline(p) => {
            let sx = if p.extrusion_direction.z < 0.0 {
                -1.0
            } else {
                1.0
            };
            let v: Vec<(Point, f64)> = p
                .vertices
                .iter()
                .map(|v| (scale(sx * v.x, v.y), sx * v.bulge))
                .collect();
            straight = v.iter().all(|(_, b)| *b == 0.0);
            pts = bulged(&v, p.is_closed());
        }
        EntityType::Polyline(p) => {
            if p.flags & (16 | 64) != 0 {
                return Ok(None); // polygon and polyface meshes
            }
            let v: Vec<(Point, f64)> = p
                .vertices()
                .filter(|v| v.flags & 16 == 0) // spline frame control points
                .map(|v| (scale(v.location.x, v.location.y), v.bulge))
                .collect();
            straight = v.iter().all(|(_, b)| *b == 0.0);
            pts = bulged(&v, p.is_closed());
        }
        EntityType::Spline(s) => pts = spline(s, mm)?,
        _ => return Ok(None),
    }
    if pts.len() < 2 {
        return Ok(None);
    }
    Ok(Some(Piece {
        layer: e.common.layer.clone(),
        what: describe(e),
        points: pts,
        straight,
    }))
}

/// The flattened SPLINE, mm.
fn spline(s: &dxf::entities::Spline, mm: f64) -> Result<Vec<Point>, String> {
    if s.control_points.is_empty() {
        return Err(format!(
            "{} fit points and no control points: convert the spline to control points in the CAD program (or export it as a polyline)",
            s.fit_points.len()
        ));
    }
    let control: Vec<Point> = s
        .control_points
        .iter()
        .map(|c| Point::new(mm * c.x, mm * c.y))
        .collect();
    let weights: &[f64] = if s.weight_values.iter().all(|&w| w == 1.0) {
        &[]
    } else {
        &s.weight_values
    };
    let n = Nurbs::new(s.degree_of_curve, &control, weights, s.knot_values.clone())?;
    let spans = n.spans();
    let f = |t: f64| n.point(t);
    let mut pts = vec![f(spans[0].0)];
    for (a, b) in spans {
        flatten(&f, a, b, FLATNESS_MM, &mut pts);
    }
    Ok(pts)
}

/// Polyline vertices `(point, bulge)` as a flattened curve (mm); closed: back to the first.
fn bulged(v: &[(Point, f64)], closed: bool) -> Vec<Point> {
    let Some(&(first, _)) = v.first() else {
        return Vec::new();
    };
    let mut pts = vec![first];
    let segments = if closed { v.len() } else { v.len() - 1 };
    for k in 0..segments {
        let ((a, b), (c, _)) = (v[k], v[(k + 1) % v.len()]);
        if b == 0.0 || a == c {
            pts.push(c);
        } else {
            let f = |t: f64| bulge_point(a, c, b, t);
            flatten(&f, 0.0, 1.0, FLATNESS_MM, &mut pts);
        }
    }
    pts
}

/// The point at fraction `t` of the bulge arc from `a` to `c` (module docs).
pub(super) fn bulge_point(a: Point, c: Point, bulge: f64, t: f64) -> Point {
    let chord = c - a;
    let len = chord.norm();
    let left = Point::new(-chord.y, chord.x) * (1.0 / len);
    let center = a.lerp(c, 0.5) + left * (len * (1.0 - bulge * bulge) / (4.0 * bulge));
    let theta = 4.0 * bulge.atan();
    let r = a.distance(center);
    let a0 = (a.y - center.y).atan2(a.x - center.x);
    center + Point::from_polar(r, a0 + theta * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bulge_arc_has_its_radius_sagitta_and_sense() {
        let (a, c) = (Point::new(10.0, 0.0), Point::new(0.0, 10.0));
        // A quarter circle about the origin, counter-clockwise: θ = π/2, b = tan(π/8).
        let b = (std::f64::consts::PI / 8.0).tan();
        for k in 0..=20 {
            let p = bulge_point(a, c, b, k as f64 / 20.0);
            assert!((p.norm() - 10.0).abs() < 1e-12, "{p:?}");
        }
        let mid = bulge_point(a, c, b, 0.5);
        assert!(mid.distance(Point::from_polar(10.0, std::f64::consts::FRAC_PI_4)) < 1e-12);
        // Sagitta = b·chord/2.
        let sagitta = mid.distance(a.lerp(c, 0.5));
        assert!((sagitta - b * a.distance(c) / 2.0).abs() < 1e-12);
        // A negative bulge runs clockwise, on the other side of the chord.
        let m2 = bulge_point(a, c, -b, 0.5);
        assert!((m2 - a.lerp(c, 0.5)).dot(mid - a.lerp(c, 0.5)) < 0.0);
        // b = 1: the counter-clockwise semicircle from (0, 10) to (10, 0) about (5, 5) passes
        // through the origin.
        assert!(bulge_point(c, a, 1.0, 0.5).distance(Point::new(0.0, 0.0)) < 1e-12);
    }
}
