//! The target loop of an SVG drawing: a closed subpath of a `<path>`, `<polyline>`, `<polygon>` (or
//! any shape: `usvg` turns them all into paths), chosen by `id` when there are several.
//!
//! - **Parsing**: `usvg` reads the file, applies every `transform` (element and ancestors) and
//!   converts all lengths to CSS pixels (96 per inch). Elements `usvg` drops as invisible
//!   (neither fill nor stroke, `display="none"`) are not seen.
//! - **Units**: coordinates are the file's user units (the numbers in the elements, after
//!   their transforms; the viewBox only frames them: its origin does not move the loop). When
//!   the root `<svg>`'s `width` (or else `height`) has an absolute unit (`mm`, `cm`, `in`, `pt`,
//!   `pc`, `px`, `Q`), one user unit is `s·25.4/96 mm`, `s` the viewBox scale (px per user
//!   unit, `min(width/vb_w, height/vb_h)`: `preserveAspectRatio` is taken as its default,
//!   xMidYMid meet). Otherwise (no size, a bare number, a percentage) the units are unknown
//!   and the file is refused unless [`DrawingOptions::units`] says what one user unit (a
//!   coordinate before the viewBox scaling) is; the caller's units override the file's the
//!   same way.
//! - **Axes**: SVG's y axis points down; the reader flips it, `y_mm = −y`, so that up in the
//!   drawing is +y as in the CSV files (the loop keeps its drawn shape; its sense of travel
//!   reads the opposite way round in numbers, as drawn on screen).
//! - **Curves**: quadratic and cubic Béziers are flattened in mm to
//!   [`super::drawing::FLATNESS_MM`]; a subpath is closed by `Z` or when its ends meet within
//!   `1e-6` of its size.
//! - **Choice**: a path is named by its own `id`, else by the `id` of its nearest group that has
//!   one; [`DrawingOptions::id`] picks it, or names a group (a vector editor's layer) and picks
//!   the paths inside it. Without an id the drawing must hold one closed
//!   subpath.

use super::drawing::{
    DrawingOptions, FLATNESS_MM, Loop, choose, close_tolerance, open_loop, trajectory,
};
use super::flatten::flatten;
use super::{Trajectory, TrajectoryError};
use crate::math::Point;
use usvg::roxmltree;
use usvg::tiny_skia_path::{PathSegment, Transform};

/// Reads the loop (module docs).
pub(super) fn read(
    text: &str,
    opts: &DrawingOptions,
    file: &str,
) -> Result<Trajectory, TrajectoryError> {
    let not_svg = |message: String| TrajectoryError::NotADrawing {
        file: file.to_string(),
        format: "SVG".into(),
        message,
    };
    let tree = usvg::Tree::from_str(text, &usvg::Options::default())
        .map_err(|e| not_svg(e.to_string()))?;
    let doc = roxmltree::Document::parse(text).map_err(|e| not_svg(e.to_string()))?;
    let frame = frame(&doc, &tree, opts, file)?;
    let mut subpaths = Vec::new();
    collect(tree.root(), "", &[], frame, &mut subpaths);
    if subpaths.is_empty() {
        return Err(TrajectoryError::NoGeometry {
            file: file.to_string(),
            message: "no visible <path>, <polyline>, <polygon> or shape".into(),
        });
    }
    let wanted = opts.id.as_deref();
    // An id that names a group (an editor's layer) picks every subpath inside it.
    if let Some(w) = wanted
        && !subpaths.iter().any(|s| s.shape.group == w)
    {
        for s in subpaths
            .iter_mut()
            .filter(|s| s.groups.iter().any(|g| g == w))
        {
            s.shape.group = w.to_string();
        }
    }
    let named = |id: &str| wanted.is_none_or(|w| w == id);
    let mut loops = Vec::new();
    let mut open = None;
    for s in subpaths {
        if s.closed {
            loops.push(s.shape);
        } else if open.is_none() && named(&s.shape.group) {
            open = Some(s.shape);
        }
    }
    if !loops.iter().any(|l| named(&l.group))
        && let Some(o) = open
    {
        let (start, end) = (o.points[0], o.points[o.points.len() - 1]);
        return Err(open_loop(file, o.what, end, start));
    }
    trajectory(choose(loops, wanted, "id", file)?, file)
}

/// The map from `usvg` pixels back to the drawing's user units and on to mm.
#[derive(Debug, Clone, Copy)]
struct Frame {
    /// The root's viewBox mapping `px = s·user + t` (xMidYMid meet, the default).
    s: f64,
    tx: f64,
    ty: f64,
    /// Millimetres per user unit.
    mm_per_user: f64,
}

impl Frame {
    /// `(x, y)` px to mm, y flipped.
    fn mm(self, x: f64, y: f64) -> Point {
        let k = self.mm_per_user / self.s;
        Point::new(k * (x - self.tx), -k * (y - self.ty))
    }
}

/// The frame of the drawing (module docs), or why its units are unknown. A viewBox's origin
/// stays where the drawing put it: coordinates are the user units of the file, scaled.
fn frame(
    doc: &roxmltree::Document<'_>,
    tree: &usvg::Tree,
    opts: &DrawingOptions,
    file: &str,
) -> Result<Frame, TrajectoryError> {
    let root = doc.root_element();
    let size = root.attribute("width").or_else(|| root.attribute("height"));
    let vb: Option<Vec<f64>> = root.attribute("viewBox").and_then(|v| {
        let n: Option<Vec<f64>> = v
            .split([' ', ','])
            .filter(|s| !s.is_empty())
            .map(|s| s.parse().ok())
            .collect();
        n.filter(|n| n.len() == 4 && n[2] > 0.0 && n[3] > 0.0)
    });
    let (w, h) = (
        f64::from(tree.size().width()),
        f64::from(tree.size().height()),
    );
    let (s, tx, ty) = match vb.as_deref() {
        Some(&[x0, y0, vw, vh]) => {
            let s = (w / vw).min(h / vh);
            (
                s,
                -x0 * s + 0.5 * (w - vw * s),
                -y0 * s + 0.5 * (h - vh * s),
            )
        }
        _ => (1.0, 0.0, 0.0),
    };
    let absolute = size.is_some_and(|v| {
        let unit = v
            .trim()
            .trim_start_matches(|c: char| c.is_ascii_digit() || ".+-eE".contains(c));
        ["mm", "cm", "in", "pt", "pc", "px", "q"]
            .contains(&unit.trim().to_ascii_lowercase().as_str())
    });
    let mm_per_user = match (opts.units, absolute) {
        (Some(u), _) => u.mm(),
        (None, true) => s * 25.4 / 96.0,
        (None, false) => {
            return Err(TrajectoryError::UnitsUnknown {
                file: file.to_string(),
                found: match size {
                    Some(v) => format!("the root <svg> is {v} wide, a length without a unit"),
                    None => "the root <svg> has no width or height".into(),
                },
            });
        }
    };
    Ok(Frame {
        s,
        tx,
        ty,
        mm_per_user,
    })
}

/// One subpath, flattened, mm, y up.
struct Subpath {
    shape: Loop,
    closed: bool,
    /// The ids of the named groups holding it (an `--id` of one of them picks it too).
    groups: Vec<String>,
}

/// Every subpath under `g`; `id` is the nearest named ancestor's, `ancestors` the ids of every
/// named group above.
fn collect(g: &usvg::Group, id: &str, ancestors: &[String], frame: Frame, out: &mut Vec<Subpath>) {
    let mut chain = ancestors.to_vec();
    if !g.id().is_empty() {
        chain.push(g.id().to_string());
    }
    let id = if g.id().is_empty() { id } else { g.id() };
    for node in g.children() {
        match node {
            usvg::Node::Group(child) => collect(child, id, &chain, frame, out),
            usvg::Node::Path(p) => {
                let id = if p.id().is_empty() { id } else { p.id() };
                let to_mm = |x: f32, y: f32| mapped(p.abs_transform(), x, y, frame);
                let first = out.len();
                subpaths(p.data(), id, &to_mm, out);
                for s in &mut out[first..] {
                    s.groups.clone_from(&chain);
                }
            }
            _ => {}
        }
    }
}

/// `(x, y)` in the path's space to mm: its transform applied, then [`Frame::mm`].
fn mapped(t: Transform, x: f32, y: f32, frame: Frame) -> Point {
    let (x, y) = (f64::from(x), f64::from(y));
    let xp = f64::from(t.sx) * x + f64::from(t.kx) * y + f64::from(t.tx);
    let yp = f64::from(t.ky) * x + f64::from(t.sy) * y + f64::from(t.ty);
    frame.mm(xp, yp)
}

/// Splits a path into flattened subpaths.
fn subpaths(
    data: &usvg::tiny_skia_path::Path,
    id: &str,
    to_mm: &dyn Fn(f32, f32) -> Point,
    out: &mut Vec<Subpath>,
) {
    let label = if id.is_empty() { "(no id)" } else { id };
    let mut current: Vec<Point> = Vec::new();
    let (mut closed, mut straight) = (false, true);
    let mut finish = |pts: &mut Vec<Point>, closed: bool, straight: bool| {
        if pts.len() < 2 {
            pts.clear();
            return;
        }
        let tol = close_tolerance(pts.iter());
        let meets = pts[0].distance(pts[pts.len() - 1]) <= tol;
        if meets {
            pts.pop();
        }
        out.push(Subpath {
            shape: Loop {
                what: format!("the path \"{label}\""),
                group: label.to_string(),
                points: std::mem::take(pts),
                straight,
            },
            closed: closed || meets,
            groups: Vec::new(),
        });
    };
    for seg in data.segments() {
        let last = current.last().copied();
        match (seg, last) {
            (PathSegment::MoveTo(p), _) => {
                finish(&mut current, closed, straight);
                (closed, straight) = (false, true);
                current.push(to_mm(p.x, p.y));
            }
            (PathSegment::LineTo(p), Some(_)) => current.push(to_mm(p.x, p.y)),
            (PathSegment::QuadTo(c, p), Some(a)) => {
                straight = false;
                let (c, b) = (to_mm(c.x, c.y), to_mm(p.x, p.y));
                let f = |t: f64| a.lerp(c, t).lerp(c.lerp(b, t), t);
                flatten(&f, 0.0, 1.0, FLATNESS_MM, &mut current);
            }
            (PathSegment::CubicTo(c1, c2, p), Some(a)) => {
                straight = false;
                let (c1, c2, b) = (to_mm(c1.x, c1.y), to_mm(c2.x, c2.y), to_mm(p.x, p.y));
                let f = |t: f64| {
                    let (ab, bc, cd) = (a.lerp(c1, t), c1.lerp(c2, t), c2.lerp(b, t));
                    ab.lerp(bc, t).lerp(bc.lerp(cd, t), t)
                };
                flatten(&f, 0.0, 1.0, FLATNESS_MM, &mut current);
            }
            (PathSegment::Close, _) => closed = true,
            _ => {}
        }
    }
    finish(&mut current, closed, straight);
}
