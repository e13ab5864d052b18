//! Where two open polylines cross: the cut between an undercut flank and the fillet trochoid
//! that trims it. Written by hand: a few hundred segments per piece, pruned by the
//! bounding boxes of runs of segments.

use crate::math::Point;
use crate::math::polyline::seg_crossing;
/// A crossing of segment `ia` of polyline `a` with segment `ib` of polyline `b`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Crossing {
    /// Segment of `a` (from vertex `ia` to `ia + 1`).
    pub ia: usize,
    /// Fraction along that segment, in `[0, 1]`.
    pub ta: f64,
    /// Segment of `b`.
    pub ib: usize,
    /// Fraction along that segment, in `[0, 1]`.
    pub tb: f64,
    /// The crossing point, mm.
    pub point: Point,
}

/// Segments per bounding box of the pruning.
const RUN: usize = 16;

/// Bounding boxes `[xmin, ymin, xmax, ymax]` of runs of `RUN` segments of `p`.
fn run_boxes(p: &[Point]) -> Vec<[f64; 4]> {
    (0..p.len().saturating_sub(1))
        .step_by(RUN)
        .map(|s| {
            p[s..(s + RUN + 1).min(p.len())].iter().fold(
                [
                    f64::INFINITY,
                    f64::INFINITY,
                    f64::NEG_INFINITY,
                    f64::NEG_INFINITY,
                ],
                |b, v| [b[0].min(v.x), b[1].min(v.y), b[2].max(v.x), b[3].max(v.y)],
            )
        })
        .collect()
}

/// Every proper crossing of the open polylines `a` and `b` (mm), in no particular order (each
/// segment pair by [`seg_crossing`]).
pub(super) fn crossings(a: &[Point], b: &[Point]) -> Vec<Crossing> {
    let (ba, bb) = (run_boxes(a), run_boxes(b));
    let mut out = Vec::new();
    for (ra, xa) in ba.iter().enumerate() {
        for (rb, xb) in bb.iter().enumerate() {
            if xa[0] > xb[2] || xb[0] > xa[2] || xa[1] > xb[3] || xb[1] > xa[3] {
                continue;
            }
            for ia in ra * RUN..((ra + 1) * RUN).min(a.len() - 1) {
                let (p, q) = (a[ia], a[ia + 1]);
                for ib in rb * RUN..((rb + 1) * RUN).min(b.len() - 1) {
                    if let Some((ta, tb)) = seg_crossing(p, q, b[ib], b[ib + 1]) {
                        out.push(Crossing {
                            ia,
                            ta,
                            ib,
                            tb,
                            point: p + (q - p) * ta,
                        });
                    }
                }
            }
        }
    }
    out
}

/// A jump of [`cut_loops`]: the walk leaves `w` at parameter `from` (segment index + fraction)
/// and re-enters at `to`, both at `point`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Jump {
    /// Parameter where the walk leaves the polyline.
    pub from: f64,
    /// Parameter where it re-enters (> `from`).
    pub to: f64,
    /// The crossing point, mm.
    pub point: Point,
}

/// Walks the open polyline `w` from its start and cuts every loop: where a later, non-adjacent
/// segment crosses the current one ahead of the walk, the walk jumps to the crossing on the
/// latest such segment. Returns the kept polyline and its jumps in order. An undercut flank
/// with its fillet (root → tip) becomes the boundary the rack leaves: the swallowtail of the
/// flank envelope and the stretch the fillet trochoid cuts away are loops of `w`.
pub(super) fn cut_loops(w: &[Point]) -> (Vec<Point>, Vec<Jump>) {
    let mut all: Vec<Crossing> = crossings(w, w)
        .into_iter()
        .filter(|c| c.ib > c.ia + 1)
        .collect();
    all.sort_by_key(|c| c.ia);
    let mut out = vec![w[0]];
    let mut jumps = Vec::new();
    let (mut i, mut at) = (0usize, 0.0f64);
    while i + 1 < w.len() {
        let lo = all.partition_point(|c| c.ia < i);
        let next = all[lo..]
            .iter()
            .take_while(|c| c.ia == i)
            .filter(|c| c.ia as f64 + c.ta > at)
            .max_by(|a, b| (a.ib as f64 + a.tb).total_cmp(&(b.ib as f64 + b.tb)));
        match next {
            Some(c) => {
                out.push(c.point);
                jumps.push(Jump {
                    from: c.ia as f64 + c.ta,
                    to: c.ib as f64 + c.tb,
                    point: c.point,
                });
                (i, at) = (c.ib, c.ib as f64 + c.tb);
            }
            None => {
                out.push(w[i + 1]);
                i += 1;
                at = i as f64;
            }
        }
    }
    (out, jumps)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A zigzag against a line: every crossing found once, at the closed-form points.
    #[test]
    fn zigzag_crosses_a_line_at_every_tooth() {
        let zig: Vec<Point> = (0..=100)
            .map(|k| Point::new(f64::from(k), if k % 2 == 0 { -1.0 } else { 1.0 }))
            .collect();
        let line = [Point::new(-1.0, 0.5), Point::new(101.0, 0.5)];
        let mut c = crossings(&zig, &line);
        c.sort_by_key(|x| x.ia);
        assert_eq!(c.len(), 100);
        for (k, x) in c.iter().enumerate() {
            assert_eq!(x.ia, k);
            // y = ±1 ∓ 2t = 0.5 → t = 0.25 on rising segments (k even), 0.75 on falling ones.
            let want = if k % 2 == 0 { 0.75 } else { 0.25 };
            assert!((x.ta - want).abs() < 1e-12, "{x:?}");
            assert!((x.point.y - 0.5).abs() < 1e-12);
        }
        assert!(crossings(&zig, &[Point::new(0.0, 5.0), Point::new(100.0, 5.0)]).is_empty());
    }

    /// A path with a loop (a swallowtail): the walk cuts it at the self-crossing, closed form.
    #[test]
    fn a_loop_is_cut_at_its_crossing() {
        // Up the line x = 0, a loop to the right and back across it at y = 2, then up again.
        let w = [
            Point::new(0.0, 0.0),
            Point::new(0.0, 3.0),
            Point::new(1.0, 3.0),
            Point::new(1.0, 2.0),
            Point::new(-1.0, 2.0),
            Point::new(-1.0, 4.0),
        ];
        let (kept, jumps) = cut_loops(&w);
        assert_eq!(
            kept,
            vec![
                Point::new(0.0, 0.0),
                Point::new(0.0, 2.0),
                Point::new(-1.0, 2.0),
                Point::new(-1.0, 4.0)
            ]
        );
        assert_eq!(jumps.len(), 1);
        // Segment 0 at 2/3, segment 3 ([1, 2] → [−1, 2]) at 1/2.
        assert!((jumps[0].from - 2.0 / 3.0).abs() < 1e-12 && (jumps[0].to - 3.5).abs() < 1e-12);
        // Without a crossing the path is kept as it is.
        let (kept, jumps) = cut_loops(&w[..3]);
        assert_eq!((kept.len(), jumps.len()), (3, 0));
    }
}
