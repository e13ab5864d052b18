//! Closed polylines (mm): distances from points, the Hausdorff distance, simplification.

use crate::math::Point;
/// Hausdorff distance (mm) between two closed polylines.
#[must_use]
pub fn hausdorff_mm(p: &[Point], q: &[Point]) -> f64 {
    directed(p, q).max(directed(q, p))
}

/// `max_{x∈p} dist(x, polyline q)`, exactly as the largest of [`distances_to_polyline`].
///
/// Early break (Taha & Hanbury, IEEE TPAMI 37(11), 2015): a point that lies within the running
/// maximum of one of the segments next to its predecessor's nearest one cannot raise the
/// maximum, so it is not searched. Consecutive points of a loop have neighbouring nearest
/// segments, so nearly every point is settled by a few segment tests (as many either side of the
/// hint as `q` has vertices per vertex of `p`, and one); the others are searched in full on the
/// grid. The result is the same number: a skipped point's distance is at most the
/// (identically computed) distance to one of the tested segments.
fn directed(p: &[Point], q: &[Point]) -> f64 {
    let n = q.len();
    if n == 0 {
        return 0.0;
    }
    let grid = SegmentGrid::new(q);
    // Segments either side of the hint: as many as `q` has vertices per vertex of `p`, and one.
    let reach = n.div_ceil(p.len().max(1)) + 1;
    let (mut max_d2, mut hint) = (0.0f64, None::<usize>);
    for &x in p {
        if let Some(k) = hint {
            let (mut d2, mut best) = (f64::INFINITY, k);
            let mut j = (k + n - reach % n) % n;
            for _ in 0..=2 * reach {
                let next = if j + 1 == n { 0 } else { j + 1 };
                let e = seg_nearest_sq(x, q[j], q[next]).1;
                if e < d2 {
                    (d2, best) = (e, j);
                }
                j = next;
            }
            let j = best;
            if d2 <= max_d2 {
                hint = Some(j);
                continue;
            }
        }
        let (segment, _, d2) = grid.search(x);
        max_d2 = max_d2.max(d2);
        hint = Some(segment);
    }
    max_d2.sqrt()
}

/// Distance (mm) from each point of `p` to the closed polyline `q` (see [`SegmentGrid`]).
#[must_use]
pub fn distances_to_polyline(p: &[Point], q: &[Point]) -> Vec<f64> {
    if q.is_empty() {
        return vec![0.0; p.len()];
    }
    let grid = SegmentGrid::new(q);
    p.iter().map(|x| grid.nearest(*x).distance_mm).collect()
}

/// The segments of a closed polyline bucketed on a uniform grid (about 2√n cells a side), so a
/// nearest-segment query visits only nearby cells. Exact: rings of cells are searched outwards
/// until no closer segment can exist (a segment in ring r is at least (r − 1)·h away).
///
/// A query far from the loop (more than [`NEAR_RINGS`] cells) would have its rings sweep a
/// square holding most of the loop; it is finished on runs of [`RUN`] consecutive segments
/// instead, each skipped when its bounding box lies beyond the nearest distance found so far.
/// Every segment that could be nearer is still measured, so the distance is the same number.
#[derive(Debug, Clone)]
pub struct SegmentGrid<'a> {
    q: &'a [Point],
    origin: Point,
    /// Cell size, mm.
    h: f64,
    nx: usize,
    ny: usize,
    /// Segment indices of cell c: `items[starts[c]..starts[c + 1]]` (u32: half the memory to
    /// fill and read).
    starts: Vec<usize>,
    items: Vec<u32>,
    /// Bounding box `[xmin, ymin, xmax, ymax]` (mm) of segments `RUN·j .. RUN·(j + 1)`.
    runs: Vec<[f64; 4]>,
}

/// Rings of cells searched around a query before the search goes over to runs of segments.
pub const NEAR_RINGS: i64 = 3;

/// Consecutive segments per bounding box of the far search.
pub const RUN: usize = 16;

/// The point of a polyline nearest to a query.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Nearest {
    /// Segment index k (from vertex k to vertex k + 1, cyclically).
    pub segment: usize,
    /// The nearest point, mm.
    pub point: Point,
    /// Its distance from the query, mm.
    pub distance_mm: f64,
}

impl<'a> SegmentGrid<'a> {
    /// Buckets the segments of the closed polyline `q` (mm; at least one vertex, fewer than 2³²).
    #[must_use]
    pub fn new(q: &'a [Point]) -> Self {
        let n = q.len();
        let [x0, y0, x1, y1] = bbox(q);
        // About 2√n cells a side (4n cells): a closed loop crosses few of them, so a query's
        // first two rings hold a handful of segments each.
        let cells = ((4.0 * n as f64).sqrt().ceil() as usize).clamp(1, 512);
        let h = ((x1 - x0).max(y1 - y0) / cells as f64).max(1e-12);
        let nx = ((x1 - x0) / h) as usize + 1;
        let ny = ((y1 - y0) / h) as usize + 1;
        let mut grid = Self {
            q,
            origin: Point::new(x0, y0),
            h,
            nx,
            ny,
            starts: Vec::new(),
            items: Vec::new(),
            // Run j spans vertices RUN·j ..= RUN·(j + 1), the last one closing on vertex 0.
            runs: (0..n.div_ceil(RUN))
                .map(|j| {
                    let close = (RUN * (j + 1) >= n).then_some(&q[0]);
                    bbox(q[j * RUN..].iter().take(RUN + 1).chain(close))
                })
                .collect(),
        };
        let cells_of = |k: usize| {
            let (a, b) = (q[k], q[if k + 1 == n { 0 } else { k + 1 }]);
            let [x0, y0] = grid.cell(Point::new(a.x.min(b.x), a.y.min(b.y)));
            let [x1, y1] = grid.cell(Point::new(a.x.max(b.x), a.y.max(b.y)));
            (y0..=y1).flat_map(move |cy| (x0..=x1).map(move |cx| cy * nx + cx))
        };
        // Counting sort: counts, running ends, then each segment placed just below its cell's
        // end (segments taken in decreasing order, so each cell lists them increasing).
        let mut starts = vec![0usize; nx * ny + 1];
        for k in 0..n {
            for c in cells_of(k) {
                starts[c] += 1;
            }
        }
        let mut total = 0usize;
        for v in &mut starts[..nx * ny] {
            total += *v;
            *v = total;
        }
        starts[nx * ny] = total;
        let mut items = vec![0u32; total];
        for k in (0..n).rev() {
            for c in cells_of(k) {
                starts[c] -= 1;
                items[starts[c]] = k as u32;
            }
        }
        grid.starts = starts;
        grid.items = items;
        grid
    }

    /// Length of segment `k`, mm.
    #[must_use]
    pub fn segment_length_mm(&self, k: usize) -> f64 {
        let (a, b) = (self.q[k], self.q[(k + 1) % self.q.len()]);
        b.distance(a)
    }

    /// Cell of `v`, clamped into the grid.
    fn cell(&self, v: Point) -> [usize; 2] {
        let f = |x: f64, o: f64, m: usize| (((x - o) / self.h).max(0.0) as usize).min(m - 1);
        [
            f(v.x, self.origin.x, self.nx),
            f(v.y, self.origin.y, self.ny),
        ]
    }

    /// The point of the polyline nearest to `x` (mm). Among equally near segments (the two
    /// sides of a vertex) the first the search meets: near the loop, rings of cells outwards,
    /// each row by row and left to right, segments in order within a cell.
    #[must_use]
    pub fn nearest(&self, x: Point) -> Nearest {
        let (segment, point, d2) = self.search(x);
        Nearest {
            segment,
            point,
            distance_mm: d2.sqrt(),
        }
    }

    /// The nearest segment, its nearest point and the squared distance (mm²).
    fn search(&self, x: Point) -> (usize, Point, f64) {
        let mut best = (0, self.q[0], f64::INFINITY);
        let [cx, cy] = self.cell(x).map(|c| c as i64);
        for ring in 0..(self.nx.max(self.ny) as i64 + 1) {
            let reach = (ring as f64 - 1.0) * self.h;
            if reach > 0.0 && best.2 <= reach * reach {
                break;
            }
            if ring > NEAR_RINGS {
                self.search_runs(x, &mut best);
                break;
            }
            // The ring's cells within the grid, row by row and left to right (the order decides
            // between segments at the same distance): its first and last rows whole, its two
            // side cells on the rows between.
            let (nx, ny) = (self.nx as i64, self.ny as i64);
            let (x0, x1) = ((cx - ring).max(0), (cx + ring).min(nx - 1));
            let mut visit = |gx: i64, gy: i64| {
                let c = gy as usize * self.nx + gx as usize;
                for &k in &self.items[self.starts[c]..self.starts[c + 1]] {
                    self.measure(x, k as usize, &mut best);
                }
            };
            for gy in (cy - ring).max(0)..=(cy + ring).min(ny - 1) {
                if gy == cy - ring || gy == cy + ring {
                    (x0..=x1).for_each(|gx| visit(gx, gy));
                } else {
                    for gx in [cx - ring, cx + ring] {
                        if (0..nx).contains(&gx) {
                            visit(gx, gy);
                        }
                    }
                }
            }
        }
        best
    }

    /// The far search (type docs): the run whose box is nearest first, then every run whose box
    /// is not beyond the best distance so far, segments in order.
    fn search_runs(&self, x: Point, best: &mut (usize, Point, f64)) {
        let bound = |b: &[f64; 4]| {
            let dx = (b[0] - x.x).max(x.x - b[2]).max(0.0);
            let dy = (b[1] - x.y).max(x.y - b[3]).max(0.0);
            dx * dx + dy * dy
        };
        let n = self.q.len();
        let scan = |j: usize, best: &mut (usize, Point, f64)| {
            for k in RUN * j..(RUN * (j + 1)).min(n) {
                self.measure(x, k, best);
            }
        };
        let first = (self.runs.iter().map(bound).enumerate())
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map_or(0, |(j, _)| j);
        scan(first, best);
        for (j, b) in self.runs.iter().enumerate() {
            // A relative hair over the bound: a measured distance may round below the box's.
            if j != first && bound(b) <= best.2 * (1.0 + 1e-9) {
                scan(j, best);
            }
        }
    }

    /// Segment `k` measured from `x`, kept in `best` when strictly nearer: among equally near
    /// segments the first met wins (a vertex's two segments give the same point).
    fn measure(&self, x: Point, k: usize, best: &mut (usize, Point, f64)) {
        let (q, n) = (self.q, self.q.len());
        let (point, d2) = seg_nearest_sq(x, q[k], q[if k + 1 == n { 0 } else { k + 1 }]);
        if d2 < best.2 {
            *best = (k, point, d2);
        }
    }
}

/// Bounding box `[xmin, ymin, xmax, ymax]` of `pts`, mm (infinite, inverted, when empty).
pub fn bbox<'a>(pts: impl IntoIterator<Item = &'a Point>) -> [f64; 4] {
    pts.into_iter().fold(
        [
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ],
        |b, p| [b[0].min(p.x), b[1].min(p.y), b[2].max(p.x), b[3].max(p.y)],
    )
}

/// The point of the segment `ab` nearest to `x` and its distance, mm.
#[must_use]
pub fn seg_nearest(x: Point, a: Point, b: Point) -> (Point, f64) {
    let (c, d2) = seg_nearest_sq(x, a, b);
    (c, d2.sqrt())
}

/// [`seg_nearest`] with the squared distance, mm².
fn seg_nearest_sq(x: Point, a: Point, b: Point) -> (Point, f64) {
    let d = b - a;
    let l2 = d.norm_squared();
    let t = if l2 > 0.0 {
        ((x - a).dot(d) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let c = a + d * t;
    (c, (x.x - c.x).powi(2) + (x.y - c.y).powi(2))
}

/// Where the segments `p + t·(q − p)` and `u + s·(v − u)` cross: `(t, s)`, both in `[0, 1]`,
/// with `t = (u − p)×(v − u) / (q − p)×(v − u)` and `s = (u − p)×(q − p) / (q − p)×(v − u)`;
/// `None` when they do not meet or are parallel (a zero cross product). The crossing point is
/// `p + t·(q − p)`.
#[must_use]
#[inline]
pub fn seg_crossing(p: Point, q: Point, u: Point, v: Point) -> Option<(f64, f64)> {
    let (r, w) = (q - p, v - u);
    let den = r.cross(w);
    if den == 0.0 {
        return None;
    }
    let d = u - p;
    let (t, s) = (d.cross(w) / den, d.cross(r) / den);
    ((0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&s)).then_some((t, s))
}

/// Distance from `x` to the segment `ab`, mm.
#[must_use]
pub fn seg_dist(x: Point, a: Point, b: Point) -> f64 {
    seg_nearest(x, a, b).1
}

/// Simplifies a closed polyline so that no removed vertex deviates more than `tol_mm` from the
/// kept chords (Douglas–Peucker on the two halves split at the farthest vertex from vertex 0).
#[must_use]
pub fn simplify_closed(points_mm: &[Point], tol_mm: f64) -> Vec<Point> {
    simplify_closed_dev(points_mm, tol_mm).0
}

/// [`simplify_closed`] with the largest distance of a removed vertex from its chord, mm.
///
/// Distances are to the chord *segments* (not their lines), so the returned deviation `e ≤ tol_mm`
/// bounds the Hausdorff distance of the two polylines both ways: an edge between removed
/// vertices stays within `e` of its chord (distance to a segment is convex), and every chord
/// point is the projection of a point of the path it replaces, which lies within `e` of it.
#[must_use]
pub fn simplify_closed_dev(points_mm: &[Point], tol_mm: f64) -> (Vec<Point>, f64) {
    let n = points_mm.len();
    if n < 4 {
        return (points_mm.to_vec(), 0.0);
    }
    let p0 = points_mm[0];
    let far = (1..n)
        .max_by(|&a, &b| {
            let da = points_mm[a].distance(p0);
            let db = points_mm[b].distance(p0);
            da.total_cmp(&db)
        })
        .unwrap_or(n / 2);
    let mut keep = vec![false; n];
    keep[0] = true;
    keep[far] = true;
    let mut dev2 = 0.0f64;
    let tol2 = tol_mm * tol_mm;
    let mut stack = vec![(0usize, far), (far, n)];
    while let Some((a, b)) = stack.pop() {
        if b <= a + 1 {
            continue;
        }
        let (pa, pb) = (points_mm[a], points_mm[b % n]);
        let mut worst = (0.0, a);
        for (i, p) in points_mm.iter().enumerate().take(b).skip(a + 1) {
            let d2 = seg_nearest_sq(*p, pa, pb).1;
            if d2 > worst.0 {
                worst = (d2, i);
            }
        }
        if worst.0 > tol2 {
            keep[worst.1] = true;
            stack.push((a, worst.1));
            stack.push((worst.1, b));
        } else {
            dev2 = dev2.max(worst.0);
        }
    }
    let kept = points_mm
        .iter()
        .zip(keep)
        .filter(|(_, k)| *k)
        .map(|(p, _)| *p)
        .collect();
    (kept, dev2.sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    #[test]
    fn simplification_deviation_bounds_the_hausdorff_distance_also_for_folded_spikes() {
        // A star with radial spikes that fold back along their own line: a perpendicular (line)
        // distance would call a spike's tip "on the chord" and drop it.
        let pts: Vec<Point> = (0..2000)
            .map(|k| {
                let t = TAU * f64::from(k / 4 * 4) / 2000.0;
                let r = match k % 4 {
                    1 => 10.0 + 0.05 * f64::from(k % 7),
                    2 => 9.0,
                    _ => 8.0 + 0.2 * (5.0 * t).sin(),
                };
                Point::new(r * t.cos(), r * t.sin())
            })
            .collect();
        for tol in [1e-4, 1e-2, 0.3] {
            let (kept, dev) = simplify_closed_dev(&pts, tol);
            assert!(kept.len() < pts.len() && dev <= tol, "{tol}: {dev}");
            let h = hausdorff_mm(&pts, &kept);
            assert!(
                h <= dev * (1.0 + 1e-12) + 1e-15,
                "{tol}: Hausdorff {h} > deviation {dev}"
            );
            // Every spike tip (radius ≥ 10) stands 1 mm beyond the rest of its spike and 0.126 mm
            // from its neighbours' tips: it is kept at any tolerance below that.
            if tol < 0.1 {
                let tips = |v: &[Point]| v.iter().filter(|p| p.hypot() >= 10.0).count();
                assert_eq!(tips(&pts), tips(&kept), "{tol}");
            }
        }
        // A vertex behind the start of its chord, on the chord's line: 3 mm from the chord
        // segment though 0 from its line.
        let fold = [[0.0, 0.0], [-3.0, 0.0], [5.0, 0.0], [5.0, 1.0], [0.0, 1.0]].map(Point::from);
        let (kept, dev) = simplify_closed_dev(&fold, 0.5);
        assert_eq!(kept.len(), 5, "{kept:?}");
        assert_eq!(dev, 0.0);
    }

    #[test]
    fn hausdorff_of_concentric_circles_is_the_radius_gap() {
        let circle = |r: f64, n: usize, shift: f64| -> Vec<Point> {
            (0..n)
                .map(|k| {
                    let t = TAU * (k as f64 + shift) / n as f64;
                    Point::new(r * t.cos(), r * t.sin())
                })
                .collect()
        };
        let a = circle(50.0, 4000, 0.0);
        let b = circle(50.3, 3000, 0.5);
        let h = hausdorff_mm(&a, &b);
        // Chord sag of the polylines is < 50·(2π/3000)²/8 ≈ 3e-4 mm.
        assert!((h - 0.3).abs() < 5e-4, "{h}");
        // Brute force agrees.
        let brute = a
            .iter()
            .map(|x| {
                (0..b.len())
                    .map(|k| seg_dist(*x, b[k], b[(k + 1) % b.len()]))
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max);
        assert!((directed(&a, &b) - brute).abs() < 1e-12);
    }

    #[test]
    fn grid_nearest_equals_brute_force_inside_and_far_outside() {
        // A kidney-like closed curve with unevenly spaced vertices; queries on a lattice that
        // reaches far beyond its bounding box (the grid clamps them to border cells).
        let q: Vec<Point> = (0..300)
            .map(|k| {
                let t = TAU * (k as f64 / 300.0).powf(1.3);
                let r = 60.0 + 15.0 * (2.0 * t).cos() + 5.0 * (3.0 * t).sin();
                Point::new(r * t.cos() + 10.0, 0.6 * r * t.sin() - 4.0)
            })
            .collect();
        let grid = SegmentGrid::new(&q);
        for i in -12..=12 {
            for j in -12..=12 {
                let x = Point::new(17.0 * i as f64 + 0.3, 11.0 * j as f64 - 0.7);
                let brute = (0..q.len())
                    .map(|k| seg_dist(x, q[k], q[(k + 1) % q.len()]))
                    .fold(f64::INFINITY, f64::min);
                let near = grid.nearest(x);
                assert!((near.distance_mm - brute).abs() < 1e-9, "{x:?}");
                // The returned point lies on the returned segment, at that distance from x.
                let k = near.segment;
                assert!(seg_dist(near.point, q[k], q[(k + 1) % q.len()]) < 1e-9);
                let d = x.distance(near.point);
                assert!((d - near.distance_mm).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn grid_and_early_break_give_the_brute_force_numbers() {
        // Loops of unequal density, one wavy and one with a reversed travel order; the grid's
        // nearest segment and the directed Hausdorff distance must be the brute-force ones,
        // bit for bit (the early break skips only points that cannot raise the maximum).
        let lobed = |n: usize, amp: f64, rev: bool| -> Vec<Point> {
            (0..n)
                .map(|k| {
                    let k = if rev { n - 1 - k } else { k };
                    let t = TAU * k as f64 / n as f64;
                    let r = 60.0 + 25.0 * (2.0 * t).cos() + amp * (37.0 * t).sin();
                    Point::new(r * t.cos() + 5.0, 0.6 * r * t.sin())
                })
                .collect()
        };
        let brute = |x: Point, q: &[Point]| {
            (0..q.len())
                .map(|k| seg_nearest_sq(x, q[k], q[(k + 1) % q.len()]).1)
                .fold(f64::INFINITY, f64::min)
        };
        for (p, q) in [
            (lobed(2048, 0.01, false), lobed(4096, 0.0, false)),
            (lobed(4096, 0.0, false), lobed(2048, 0.01, false)),
            (lobed(700, 0.5, true), lobed(3000, 0.2, false)),
            (lobed(50, 3.0, false), lobed(9, 0.0, true)),
        ] {
            // And the same loop shrunk to 0.3 and grown to 2.5 about a point off its centre:
            // queries tens of millimetres from it, finished on the runs' boxes.
            let far = |s: f64| p.iter().map(move |v| (*v - Point::new(9.0, 2.0)) * s);
            let p: Vec<Point> = p.iter().copied().chain(far(0.3)).chain(far(2.5)).collect();
            let grid = SegmentGrid::new(&q);
            let mut max = 0.0f64;
            for &x in &p {
                let d2 = brute(x, &q);
                assert_eq!(grid.search(x).2, d2);
                max = max.max(d2.sqrt());
            }
            assert_eq!(directed(&p, &q), max);
            let all = distances_to_polyline(&p, &q);
            assert_eq!(all.into_iter().fold(0.0, f64::max), max);
        }
    }
}
