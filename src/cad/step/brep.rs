//! The B-rep of one extruded gear: a closed shell of two planar caps (the bore, if any, as an
//! inner loop of two exact half circles), one planar side face per outline segment and two
//! half-cylinder bore faces, written as ISO 10303-21 entities.
//!
//! Orientation: the outline is CCW about +z; every face's surface normal points out of the
//! material (the bore faces use `same_sense = .F.` on a cylinder whose normal points away from
//! the axis), and every loop is CCW about its face's outward normal. Each edge is used by exactly
//! two faces, once in each direction.
use super::{Ents, Prism, real};

/// A `CARTESIAN_POINT` (mm) or a `DIRECTION` of three coordinates.
fn triple(e: &mut Ents, kind: &str, p: [f64; 3]) -> usize {
    let [x, y, z] = p.map(real);
    e.add(format_args!("{kind}('',({x},{y},{z}))"))
}

/// A cartesian point `(x, y, z)`, mm.
fn point(e: &mut Ents, p: [f64; 3]) -> usize {
    triple(e, "CARTESIAN_POINT", p)
}

/// A direction.
fn direction(e: &mut Ents, d: [f64; 3]) -> usize {
    triple(e, "DIRECTION", d)
}

/// An `AXIS2_PLACEMENT_3D` at `at` with axis `z` and reference direction `x` (entity ids).
pub(super) fn placement(e: &mut Ents, at: [f64; 3], z: [f64; 3], x: [f64; 3]) -> usize {
    let (p, dz, dx) = (point(e, at), direction(e, z), direction(e, x));
    e.add(format_args!("AXIS2_PLACEMENT_3D('',#{p},#{dz},#{dx})"))
}

/// A straight edge from vertex `v0` (at `p0`) to vertex `v1` along the unit `dir`, length `len`.
fn line_edge(e: &mut Ents, (v0, p0): (usize, usize), v1: usize, dir: [f64; 3], len: f64) -> usize {
    let d = direction(e, dir);
    let vec = e.add(format_args!("VECTOR('',#{d},{})", real(len)));
    let line = e.add(format_args!("LINE('',#{p0},#{vec})"));
    e.add(format_args!("EDGE_CURVE('',#{v0},#{v1},#{line},.T.)"))
}

/// A loop of `(edge, forward)`.
type Loop = Vec<(usize, bool)>;

/// A face on `surface` bounded by loops of `(edge, forward)` (the first loop is the outer one).
fn face(e: &mut Ents, surface: usize, same_sense: bool, loops: &[Loop]) -> usize {
    let mut bounds = Vec::with_capacity(loops.len());
    for (k, l) in loops.iter().enumerate() {
        let oriented: Vec<String> = l
            .iter()
            .map(|&(edge, fwd)| {
                let f = if fwd { ".T." } else { ".F." };
                format!(
                    "#{}",
                    e.add(format_args!("ORIENTED_EDGE('',*,*,#{edge},{f})"))
                )
            })
            .collect();
        let lp = e.add(format_args!("EDGE_LOOP('',({}))", oriented.join(",")));
        let kind = if k == 0 {
            "FACE_OUTER_BOUND"
        } else {
            "FACE_BOUND"
        };
        bounds.push(format!("#{}", e.add(format_args!("{kind}('',#{lp},.T.)"))));
    }
    let s = if same_sense { ".T." } else { ".F." };
    e.add(format_args!(
        "ADVANCED_FACE('',({}),#{surface},{s})",
        bounds.join(",")
    ))
}

/// A vertex at `p`: `(vertex, point)` entity ids.
fn vertex(e: &mut Ents, p: [f64; 3]) -> (usize, usize) {
    let pt = point(e, p);
    (e.add(format_args!("VERTEX_POINT('',#{pt})")), pt)
}

/// The bore: its two cap loops `(bottom, top)` and its two half-cylinder faces.
fn bore(e: &mut Ents, r: f64, w: f64) -> (Loop, Loop, [usize; 2]) {
    let z = [0.0, 0.0, 1.0];
    let (b0, pb0) = vertex(e, [r, 0.0, 0.0]);
    let (bp, _) = vertex(e, [-r, 0.0, 0.0]);
    let (t0, _) = vertex(e, [r, 0.0, w]);
    let (tp, ptp) = vertex(e, [-r, 0.0, w]);
    let mut arcs = Vec::new();
    for h in [0.0, w] {
        let ax = placement(e, [0.0, 0.0, h], z, [1.0, 0.0, 0.0]);
        let c = e.add(format_args!("CIRCLE('',#{ax},{})", real(r)));
        let (v0, vp) = if h == 0.0 { (b0, bp) } else { (t0, tp) };
        arcs.push(e.add(format_args!("EDGE_CURVE('',#{v0},#{vp},#{c},.T.)")));
        arcs.push(e.add(format_args!("EDGE_CURVE('',#{vp},#{v0},#{c},.T.)")));
    }
    let [cb1, cb2, ct1, ct2] = [arcs[0], arcs[1], arcs[2], arcs[3]];
    let l0 = line_edge(e, (b0, pb0), t0, z, w);
    // The seam at angle π runs down from the top (its line starts at the top point).
    let lp = line_edge(e, (tp, ptp), bp, [0.0, 0.0, -1.0], w);
    let ax = placement(e, [0.0, 0.0, 0.0], z, [1.0, 0.0, 0.0]);
    let cyl = e.add(format_args!("CYLINDRICAL_SURFACE('',#{ax},{})", real(r)));
    let half1 = face(
        e,
        cyl,
        false,
        &[vec![(cb1, false), (l0, true), (ct1, true), (lp, true)]],
    );
    let half2 = face(
        e,
        cyl,
        false,
        &[vec![(cb2, false), (lp, false), (ct2, true), (l0, false)]],
    );
    (
        vec![(cb1, true), (cb2, true)],
        vec![(ct2, false), (ct1, false)],
        [half1, half2],
    )
}

/// Writes the solid of `prism` (outline CCW about +z, validated) in its body frame, z from 0 to
/// the face width: returns the `MANIFOLD_SOLID_BREP` id and the number of faces.
pub(super) fn solid(e: &mut Ents, prism: &Prism) -> (usize, usize) {
    let pts = &prism.outline_mm;
    let n = pts.len();
    let w = prism.face_width_mm;
    let (mut bottom, mut top) = (Vec::with_capacity(n), Vec::with_capacity(n));
    for p in pts {
        bottom.push(vertex(e, [p.x, p.y, 0.0]));
        top.push(vertex(e, [p.x, p.y, w]));
    }
    let z = [0.0, 0.0, 1.0];
    let vertical: Vec<usize> = (0..n)
        .map(|i| line_edge(e, bottom[i], top[i].0, z, w))
        .collect();
    let mut faces = Vec::with_capacity(n + 4);
    let (mut eb, mut et) = (Vec::with_capacity(n), Vec::with_capacity(n));
    for i in 0..n {
        let j = (i + 1) % n;
        let (dx, dy) = (pts[j].x - pts[i].x, pts[j].y - pts[i].y);
        let len = dx.hypot(dy);
        let d = [dx / len, dy / len, 0.0];
        let b = line_edge(e, bottom[i], bottom[j].0, d, len);
        let t = line_edge(e, top[i], top[j].0, d, len);
        // Outward normal of a CCW outline: the segment direction turned clockwise.
        let ax = placement(e, [pts[i].x, pts[i].y, 0.0], [d[1], -d[0], 0.0], d);
        let plane = e.add(format_args!("PLANE('',#{ax})"));
        faces.push(face(
            e,
            plane,
            true,
            &[vec![
                (b, true),
                (vertical[j], true),
                (t, false),
                (vertical[i], false),
            ]],
        ));
        eb.push(b);
        et.push(t);
    }
    let mut bottom_loops = vec![eb.iter().rev().map(|&b| (b, false)).collect::<Vec<_>>()];
    let mut top_loops = vec![et.iter().map(|&t| (t, true)).collect::<Vec<_>>()];
    if prism.bore_mm > 0.0 {
        let (lb, lt, halves) = bore(e, 0.5 * prism.bore_mm, w);
        bottom_loops.push(lb);
        top_loops.push(lt);
        faces.extend(halves);
    }
    let ax = placement(e, [0.0, 0.0, 0.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]);
    let plane = e.add(format_args!("PLANE('',#{ax})"));
    faces.push(face(e, plane, true, &bottom_loops));
    let ax = placement(e, [0.0, 0.0, w], z, [1.0, 0.0, 0.0]);
    let plane = e.add(format_args!("PLANE('',#{ax})"));
    faces.push(face(e, plane, true, &top_loops));
    let list: Vec<String> = faces.iter().map(|f| format!("#{f}")).collect();
    let shell = e.add(format_args!("CLOSED_SHELL('',({}))", list.join(",")));
    let name = super::quote(&prism.name);
    (
        e.add(format_args!("MANIFOLD_SOLID_BREP({name},#{shell})")),
        faces.len(),
    )
}
