//! Target loops read from drawings: the options, units and the steps the DXF and SVG readers share.
//!
//! A drawing gives the needle-tip loop as one closed curve ([`super::dxf`], [`super::svg`]).
//! Every reader does the same four things:
//!
//! 1. **Units**: the file's own (`$INSUNITS` of a DXF; the root `width`/`height` of an SVG),
//!    or [`DrawingOptions::units`] when the file has none (a unitless file is refused rather
//!    than guessed at). The caller's units override the file's.
//! 2. **Flattening**: curves (arcs, B-splines, Béziers) become polylines whose chords stay
//!    within [`FLATNESS_MM`] = 1 µm of the curve (recursive bisection: a piece is split while
//!    its parameter midpoint lies farther than the tolerance from its chord; at least
//!    [`super::flatten::MIN_PIECES`] pieces per span, so that an S-shaped span is not taken for a straight one).
//! 3. **Resampling**: a loop of straight segments only (LINEs, a polyline without bulges, an
//!    SVG polygon) keeps its vertices as drawn, as a CSV file of the same points would (at
//!    least [`MIN_POINTS`], at most [`MAX_KEPT_VERTICES`]; resampling a polygon uniformly would
//!    put its corners between samples and kink the interpolant; a denser polygon is a traced
//!    curve, whose chords are too short for that to matter). Any other loop is resampled at [`DRAWING_SAMPLES`] = 720 points
//!    uniform in arc length, `s_k = k·L/720`, starting at the point where the curve starts in
//!    the drawing and running the way it was drawn. 720 is two points per carrier degree: the
//!    example CSV files have 360, the design interpolates the points by a chord-length
//!    periodic cubic (docs/math/chain.md §3.1), whose error `O(h⁴·|P⁗|)` at a spacing
//!    `h ≈ 0.5 mm` on a 350 mm loop is far below the flattening tolerance.
//! 4. **Checks**: a loop that does not close (gap and ends in mm), a loop that runs back along
//!    itself (a zero-area spike or a stretch drawn twice, [`super::retrace`]: where), several
//!    loops with nothing naming one (listed with their layers or ids). A loop that crosses
//!    itself is taken in the order drawn: a needle-tip path often has a small loop where the
//!    needle picks the seedling, and the chain's own checks decide whether it can be traced,
//!    as for a CSV file.
//!
//! The points then go through [`Trajectory::new`] as the points of a CSV file would: the design
//! treats them exactly as the same loop given in a CSV file, in the same travel order (the
//! carrier sense is detected from the loop, or given by `--sense`, as for a CSV file).

use super::flatten::resample;
use super::retrace::retraced;
use super::{MIN_POINTS, Origin, Trajectory, TrajectoryError};
use crate::math::Point;
use std::str::FromStr;

/// Most vertices of a straight-segment loop kept as drawn (module docs): the retrace check is
/// quadratic in them (≈ 50 ms at 4096).
pub const MAX_KEPT_VERTICES: usize = 4096;

/// Points of a loop read from a drawing: two per carrier degree (module docs).
pub const DRAWING_SAMPLES: usize = 720;
/// Largest distance from a flattened chord to its curve, mm (module docs).
pub const FLATNESS_MM: f64 = 1e-3;
/// Relative tolerance for the ends of a curve to meet: `1e-6` of the drawing size (the
/// diagonal of the bounding box of its geometry).
pub const CLOSE_RELATIVE: f64 = 1e-6;

/// Length unit of a drawing's coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum DrawingUnits {
    /// Millimetres.
    Mm,
    /// Centimetres (10 mm).
    Cm,
    /// Metres (1000 mm).
    M,
    /// Inches (25.4 mm).
    In,
    /// CSS pixels, 96 per inch (25.4/96 mm).
    Px,
}

impl DrawingUnits {
    /// Millimetres per unit.
    #[must_use]
    pub fn mm(self) -> f64 {
        match self {
            Self::Mm => 1.0,
            Self::Cm => 10.0,
            Self::M => 1000.0,
            Self::In => 25.4,
            Self::Px => 25.4 / 96.0,
        }
    }
}

impl FromStr for DrawingUnits {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim().to_ascii_lowercase().as_str() {
            "mm" => Ok(Self::Mm),
            "cm" => Ok(Self::Cm),
            "m" => Ok(Self::M),
            "in" | "inch" => Ok(Self::In),
            "px" => Ok(Self::Px),
            _ => Err(format!("`{s}`: expected mm, cm, m, in or px")),
        }
    }
}

/// How to read the loop from a drawing.
#[derive(Debug, Clone, Default, PartialEq)]
#[non_exhaustive]
pub struct DrawingOptions {
    /// DXF: the layer whose loop is the target (default none: the drawing must hold one loop).
    pub layer: Option<String>,
    /// SVG: the `id` of the element whose path is the target (default none: one path).
    pub id: Option<String>,
    /// Units of the coordinates (default none: the file's own; a file without units is
    /// refused). DXF: replaces `$INSUNITS`. SVG: the size of one user unit (a coordinate
    /// before the root's viewBox scaling).
    pub units: Option<DrawingUnits>,
}

crate::builder::with_fields!(DrawingOptions {
    with_layer => layer: Option<String>,
    with_id => id: Option<String>,
    with_units => units: Option<DrawingUnits>,
});

/// One closed loop of a drawing, flattened, in mm.
#[derive(Debug, Clone)]
pub(super) struct Loop {
    /// Where it comes from: `LWPOLYLINE 2F on layer "0"`, `path "target"`.
    pub what: String,
    /// Layer (DXF) or id (SVG) it is chosen by.
    pub group: String,
    /// Flattened points, mm, no repeated end point.
    pub points: Vec<Point>,
    /// Straight segments only (no arc, spline or Bézier): the points are the drawn vertices.
    pub straight: bool,
}

/// The loop `wanted` names (`None`: the only one), or why none: `kind` is `layer` or `id`.
pub(super) fn choose(
    loops: Vec<Loop>,
    wanted: Option<&str>,
    kind: &str,
    file: &str,
) -> Result<Loop, TrajectoryError> {
    let listing = listing(&loops, kind);
    let mut picked: Vec<Loop> = match wanted {
        Some(w) => loops.into_iter().filter(|l| l.group == w).collect(),
        None => loops,
    };
    match (picked.len(), wanted) {
        (1, _) => Ok(picked.remove(0)),
        (0, Some(w)) => Err(TrajectoryError::NoLoopNamed {
            file: file.to_string(),
            wanted: format!("with {kind} \"{w}\""),
            found: listing,
        }),
        (0, None) => Err(TrajectoryError::NoGeometry {
            file: file.to_string(),
            message: "no closed curve".into(),
        }),
        _ => Err(TrajectoryError::SeveralLoops {
            file: file.to_string(),
            found: listing,
            flag: format!("--{kind} NAME"),
        }),
    }
}

/// `layer "A": 1 loop; layer "B": 2 loops`, in order of first appearance.
fn listing(loops: &[Loop], kind: &str) -> String {
    let mut groups: Vec<(&str, usize)> = Vec::new();
    for l in loops {
        match groups.iter_mut().find(|(g, _)| *g == l.group) {
            Some((_, n)) => *n += 1,
            None => groups.push((&l.group, 1)),
        }
    }
    if groups.is_empty() {
        return "no closed loop".into();
    }
    groups
        .iter()
        .map(|(g, n)| format!("{kind} \"{g}\": {n} loop{}", if *n == 1 { "" } else { "s" }))
        .collect::<Vec<_>>()
        .join("; ")
}

/// The chosen loop as a trajectory: resampled (module docs), checked for stretches drawn twice
/// (within [`close_tolerance`] of the loop), then validated as any point list is.
pub(super) fn trajectory(chosen: Loop, file: &str) -> Result<Trajectory, TrajectoryError> {
    if (chosen.points.iter()).any(|p| !(p.x.is_finite() && p.y.is_finite())) {
        return Err(TrajectoryError::NonFiniteCoordinate {
            file: file.to_string(),
            what: chosen.what,
        });
    }
    let mut vertices = chosen.points.clone();
    vertices.dedup();
    let points = if chosen.straight && (MIN_POINTS..=MAX_KEPT_VERTICES).contains(&vertices.len()) {
        vertices
    } else {
        resample(&chosen.points, DRAWING_SAMPLES).ok_or_else(|| TrajectoryError::NoGeometry {
            file: file.to_string(),
            message: format!("{} has zero length", chosen.what),
        })?
    };
    if let Some((p, _, _)) = retraced(&points, close_tolerance(&points)) {
        return Err(TrajectoryError::Retraced {
            file: file.to_string(),
            what: chosen.what,
            x: p.x,
            y: p.y,
        });
    }
    let origins: Vec<Origin> = (0..points.len()).map(Origin::Index).collect();
    Trajectory::new(points, &origins, file)
}

/// The open-loop error of a curve from `start` to `end` (mm); a non-finite end is named as
/// such (NaN apart says nothing).
pub(super) fn open_loop(file: &str, what: String, end: Point, start: Point) -> TrajectoryError {
    if !(end.x.is_finite() && end.y.is_finite() && start.x.is_finite() && start.y.is_finite()) {
        return TrajectoryError::NonFiniteCoordinate {
            file: file.to_string(),
            what,
        };
    }
    TrajectoryError::OpenLoop {
        file: file.to_string(),
        what,
        gap_mm: end.distance(start),
        from_x: end.x,
        from_y: end.y,
        to_x: start.x,
        to_y: start.y,
    }
}

/// Tolerance for two ends to meet: [`CLOSE_RELATIVE`] of the bounding-box diagonal of
/// `points` (drawing units), at least `1e-12`.
pub(super) fn close_tolerance<'a>(points: impl IntoIterator<Item = &'a Point>) -> f64 {
    let (mut lo, mut hi) = (
        Point::new(f64::INFINITY, f64::INFINITY),
        Point::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
    );
    for p in points {
        lo = Point::new(lo.x.min(p.x), lo.y.min(p.y));
        hi = Point::new(hi.x.max(p.x), hi.y.max(p.y));
    }
    let d = hi.distance(lo);
    if d.is_finite() {
        (CLOSE_RELATIVE * d).max(1e-12)
    } else {
        1e-12
    }
}
