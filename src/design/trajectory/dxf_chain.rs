//! A DXF drawing's open pieces (LINEs, ARCs, open polylines and splines) joined end to end into
//! loops, per layer.
//!
//! Two ends join when they lie within [`close_tolerance`] of the layer's geometry (`1e-6` of its
//! size). Each piece is followed by the first piece in file order with an end there, either way
//! round, from the first piece as drawn; a chain closes when its end meets its start. Only ends
//! join pieces: two pieces that cross are not joined where they cross, so a looped path drawn as
//! LINEs is followed through its crossing along its own pieces. Where more than two ends meet
//! the chain could go on along any of them: such a junction is reported (and refused by the
//! reader when it lies on the layer read), never resolved by file order.

use super::TrajectoryError;
use super::drawing::{Loop, close_tolerance};
use crate::math::Point;

/// One curve of the drawing, flattened, mm.
pub(super) struct Piece {
    pub layer: String,
    pub what: String,
    pub points: Vec<Point>,
    /// Straight segments only.
    pub straight: bool,
}

/// An open chain that did not close: `(what, end, start, layer)`.
pub(super) type OpenChain = (String, Point, Point, String);

/// More than two piece ends at one point of a layer.
pub(super) struct Junction {
    pub layer: String,
    /// Where, mm.
    pub at: Point,
    /// How many ends meet there.
    pub ends: usize,
    /// The pieces whose ends they are (first few).
    pub pieces: Vec<String>,
}

impl Junction {
    /// The refusal naming the place and the pieces.
    pub fn error(self, file: &str) -> TrajectoryError {
        TrajectoryError::Junction {
            file: file.to_string(),
            layer: self.layer,
            ends: self.ends,
            pieces: self.pieces.join(", "),
            x: self.at.x,
            y: self.at.y,
        }
    }
}

/// The closed loops the pieces make, per layer, the chains that stay open, and the junctions
/// (first one per layer).
pub(super) fn chains(pieces: Vec<Piece>) -> (Vec<Loop>, Vec<OpenChain>, Vec<Junction>) {
    let mut layers: Vec<(String, Vec<Piece>)> = Vec::new();
    for p in pieces {
        match layers.iter_mut().find(|(l, _)| *l == p.layer) {
            Some((_, v)) => v.push(p),
            None => layers.push((p.layer.clone(), vec![p])),
        }
    }
    let (mut loops, mut open, mut junctions) = (Vec::new(), Vec::new(), Vec::new());
    for (layer, mut rest) in layers {
        let tol = close_tolerance(rest.iter().flat_map(|p| p.points.iter()));
        if let Some(j) = junction(&rest, &layer, tol) {
            junctions.push(j);
        }
        while !rest.is_empty() {
            let first = rest.remove(0);
            let (mut pts, mut count, mut straight) = (first.points, 1usize, first.straight);
            let name = |count: usize| match count {
                1 => first.what.clone(),
                _ => format!("the chain of {count} entities from {}", first.what),
            };
            loop {
                let end = pts[pts.len() - 1];
                if pts.len() > 2 && end.distance(pts[0]) <= tol {
                    pts.pop();
                    let (what, group) = (name(count), layer.clone());
                    loops.push(Loop {
                        what,
                        group,
                        points: pts,
                        straight,
                    });
                    break;
                }
                let Some((k, reversed)) = next_piece(&rest, end, tol) else {
                    open.push((name(count), end, pts[0], layer.clone()));
                    break;
                };
                let next_piece = rest.remove(k);
                straight &= next_piece.straight;
                let mut next = next_piece.points;
                if reversed {
                    next.reverse();
                }
                pts.extend_from_slice(&next[1..]);
                count += 1;
            }
        }
    }
    (loops, open, junctions)
}

/// The first piece in `rest` with an end at `at` (within `tol`), and whether it runs backwards.
fn next_piece(rest: &[Piece], at: Point, tol: f64) -> Option<(usize, bool)> {
    rest.iter().enumerate().find_map(|(k, p)| {
        if p.points[0].distance(at) <= tol {
            Some((k, false))
        } else if p.points[p.points.len() - 1].distance(at) <= tol {
            Some((k, true))
        } else {
            None
        }
    })
}

/// The first point (in order of x) where more than two ends of the open pieces meet within
/// `tol`, mm. A piece closed on itself (its ends meet; or of zero length) has no free ends. Sorted by x, each end
/// is compared with the ends within `tol` of it in x: `O(m log m)` for `m` pieces when ends
/// are apart.
fn junction(pieces: &[Piece], layer: &str, tol: f64) -> Option<Junction> {
    let mut ends: Vec<(Point, usize)> = Vec::new();
    for (k, p) in pieces.iter().enumerate() {
        let (a, b) = (p.points[0], p.points[p.points.len() - 1]);
        if a.distance(b) <= tol {
            continue;
        }
        ends.push((a, k));
        ends.push((b, k));
    }
    ends.sort_by(|p, q| p.0.x.total_cmp(&q.0.x));
    for (i, &(at, _)) in ends.iter().enumerate() {
        let near: Vec<usize> = ends[i..]
            .iter()
            .take_while(|(q, _)| q.x - at.x <= tol)
            .chain(
                ends[..i]
                    .iter()
                    .rev()
                    .take_while(|(q, _)| at.x - q.x <= tol),
            )
            .filter(|(q, _)| q.distance(at) <= tol)
            .map(|&(_, k)| k)
            .collect();
        if near.len() > 2 {
            let mut ks = near.clone();
            ks.sort_unstable();
            ks.dedup();
            return Some(Junction {
                layer: layer.to_string(),
                at,
                ends: near.len(),
                pieces: ks.iter().take(4).map(|&k| pieces[k].what.clone()).collect(),
            });
        }
    }
    None
}
