//! Closed polylines (mm): distances from points, the Hausdorff distance, simplification.

/// Hausdorff distance (mm) between two closed polylines.
#[must_use]
pub fn hausdorff_mm(p: &[[f64; 2]], q: &[[f64; 2]]) -> f64 {
    directed(p, q).max(directed(q, p))
}

/// `max_{x∈p} dist(x, polyline q)`.
fn directed(p: &[[f64; 2]], q: &[[f64; 2]]) -> f64 {
    distances_to_polyline(p, q).into_iter().fold(0.0, f64::max)
}

/// Distance (mm) from each point of `p` to the closed polyline `q` (see [`SegmentGrid`]).
#[must_use]
pub fn distances_to_polyline(p: &[[f64; 2]], q: &[[f64; 2]]) -> Vec<f64> {
    if q.is_empty() {
        return vec![0.0; p.len()];
    }
    let grid = SegmentGrid::new(q);
    p.iter().map(|x| grid.nearest(*x).distance_mm).collect()
}

/// The segments of a closed polyline bucketed on a uniform grid (about 2√n cells a side), so a
/// nearest-segment query visits only nearby cells. Exact: rings of cells are searched outwards
/// until no closer segment can exist (a segment in ring r is at least (r − 1)·h away).
#[derive(Debug, Clone)]
pub struct SegmentGrid<'a> {
    q: &'a [[f64; 2]],
    origin: [f64; 2],
    /// Cell size, mm.
    h: f64,
    nx: usize,
    ny: usize,
    /// Segment indices of cell c: `items[starts[c]..starts[c + 1]]`.
    starts: Vec<usize>,
    items: Vec<usize>,
}

/// The point of a polyline nearest to a query.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Nearest {
    /// Segment index k (from vertex k to vertex k + 1, cyclically).
    pub segment: usize,
    /// The nearest point, mm.
    pub point: [f64; 2],
    /// Its distance from the query, mm.
    pub distance_mm: f64,
}

impl<'a> SegmentGrid<'a> {
    /// Buckets the segments of the closed polyline `q` (mm; at least one vertex).
    #[must_use]
    pub fn new(q: &'a [[f64; 2]]) -> Self {
        let n = q.len();
        let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
        for v in q {
            for c in 0..2 {
                lo[c] = lo[c].min(v[c]);
                hi[c] = hi[c].max(v[c]);
            }
        }
        // About 2√n cells a side (4n cells): a closed loop crosses few of them, so a query's
        // first two rings hold a handful of segments each.
        let cells = ((4.0 * n as f64).sqrt().ceil() as usize).clamp(1, 512);
        let h = ((hi[0] - lo[0]).max(hi[1] - lo[1]) / cells as f64).max(1e-12);
        let nx = ((hi[0] - lo[0]) / h) as usize + 1;
        let ny = ((hi[1] - lo[1]) / h) as usize + 1;
        let mut grid = Self {
            q,
            origin: lo,
            h,
            nx,
            ny,
            starts: vec![0; nx * ny + 1],
            items: Vec::new(),
        };
        let boxes: Vec<[usize; 4]> = (0..n)
            .map(|k| {
                let (a, b) = (q[k], q[(k + 1) % n]);
                let [x0, y0] = grid.cell([a[0].min(b[0]), a[1].min(b[1])]);
                let [x1, y1] = grid.cell([a[0].max(b[0]), a[1].max(b[1])]);
                [x0, x1, y0, y1]
            })
            .collect();
        for &[x0, x1, y0, y1] in &boxes {
            for cy in y0..=y1 {
                for cx in x0..=x1 {
                    grid.starts[cy * nx + cx + 1] += 1;
                }
            }
        }
        for c in 0..nx * ny {
            grid.starts[c + 1] += grid.starts[c];
        }
        let mut fill = grid.starts.clone();
        grid.items = vec![0; grid.starts[nx * ny]];
        for (k, &[x0, x1, y0, y1]) in boxes.iter().enumerate() {
            for cy in y0..=y1 {
                for cx in x0..=x1 {
                    grid.items[fill[cy * nx + cx]] = k;
                    fill[cy * nx + cx] += 1;
                }
            }
        }
        grid
    }

    /// Length of segment `k`, mm.
    #[must_use]
    pub fn segment_length_mm(&self, k: usize) -> f64 {
        let (a, b) = (self.q[k], self.q[(k + 1) % self.q.len()]);
        (b[0] - a[0]).hypot(b[1] - a[1])
    }

    /// Cell of `v`, clamped into the grid.
    fn cell(&self, v: [f64; 2]) -> [usize; 2] {
        let f = |x: f64, o: f64, m: usize| (((x - o) / self.h).max(0.0) as usize).min(m - 1);
        [
            f(v[0], self.origin[0], self.nx),
            f(v[1], self.origin[1], self.ny),
        ]
    }

    /// The point of the polyline nearest to `x` (mm).
    #[must_use]
    pub fn nearest(&self, x: [f64; 2]) -> Nearest {
        let (q, n) = (self.q, self.q.len());
        let [cx, cy] = self.cell(x).map(|c| c as i64);
        let mut best = Nearest {
            segment: 0,
            point: q[0],
            distance_mm: f64::INFINITY,
        };
        let mut best_d2 = f64::INFINITY;
        for ring in 0..(self.nx.max(self.ny) as i64 + 1) {
            let reach = (ring as f64 - 1.0) * self.h;
            if reach > 0.0 && best_d2 <= reach * reach {
                break;
            }
            for gy in (cy - ring)..=(cy + ring) {
                for gx in (cx - ring)..=(cx + ring) {
                    let on_ring = (gx - cx).abs() == ring || (gy - cy).abs() == ring;
                    if !on_ring || gx < 0 || gy < 0 || gx >= self.nx as i64 || gy >= self.ny as i64
                    {
                        continue;
                    }
                    let c = gy as usize * self.nx + gx as usize;
                    for &k in &self.items[self.starts[c]..self.starts[c + 1]] {
                        let (point, d2) = seg_nearest_sq(x, q[k], q[(k + 1) % n]);
                        if d2 < best_d2 {
                            best_d2 = d2;
                            best.segment = k;
                            best.point = point;
                        }
                    }
                }
            }
        }
        best.distance_mm = best_d2.sqrt();
        best
    }
}

/// The point of the segment `ab` nearest to `x` and its distance, mm.
#[must_use]
pub fn seg_nearest(x: [f64; 2], a: [f64; 2], b: [f64; 2]) -> ([f64; 2], f64) {
    let (c, d2) = seg_nearest_sq(x, a, b);
    (c, d2.sqrt())
}

/// [`seg_nearest`] with the squared distance, mm².
fn seg_nearest_sq(x: [f64; 2], a: [f64; 2], b: [f64; 2]) -> ([f64; 2], f64) {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (((x[0] - a[0]) * dx + (x[1] - a[1]) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let c = [a[0] + t * dx, a[1] + t * dy];
    (c, (x[0] - c[0]).powi(2) + (x[1] - c[1]).powi(2))
}

/// Distance from `x` to the segment `ab`, mm.
#[must_use]
pub fn seg_dist(x: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    seg_nearest(x, a, b).1
}

/// Simplifies a closed polyline so that no removed vertex deviates more than `tol_mm` from the
/// kept chords (Douglas–Peucker on the two halves split at the farthest vertex from vertex 0).
#[must_use]
pub fn simplify_closed(points_mm: &[[f64; 2]], tol_mm: f64) -> Vec<[f64; 2]> {
    simplify_closed_dev(points_mm, tol_mm).0
}

/// [`simplify_closed`] with the largest distance of a removed vertex from its chord, mm.
///
/// Distances are to the chord *segments* (not their lines), so the returned deviation `e ≤ tol_mm`
/// bounds the Hausdorff distance of the two polylines both ways: an edge between removed
/// vertices stays within `e` of its chord (distance to a segment is convex), and every chord
/// point is the projection of a point of the path it replaces, which lies within `e` of it.
#[must_use]
pub fn simplify_closed_dev(points_mm: &[[f64; 2]], tol_mm: f64) -> (Vec<[f64; 2]>, f64) {
    let n = points_mm.len();
    if n < 4 {
        return (points_mm.to_vec(), 0.0);
    }
    let p0 = points_mm[0];
    let far = (1..n)
        .max_by(|&a, &b| {
            let da = (points_mm[a][0] - p0[0]).hypot(points_mm[a][1] - p0[1]);
            let db = (points_mm[b][0] - p0[0]).hypot(points_mm[b][1] - p0[1]);
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
        let pts: Vec<[f64; 2]> = (0..2000)
            .map(|k| {
                let t = TAU * f64::from(k / 4 * 4) / 2000.0;
                let r = match k % 4 {
                    1 => 10.0 + 0.05 * f64::from(k % 7),
                    2 => 9.0,
                    _ => 8.0 + 0.2 * (5.0 * t).sin(),
                };
                [r * t.cos(), r * t.sin()]
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
                let tips = |v: &[[f64; 2]]| v.iter().filter(|p| p[0].hypot(p[1]) >= 10.0).count();
                assert_eq!(tips(&pts), tips(&kept), "{tol}");
            }
        }
        // A vertex behind the start of its chord, on the chord's line: 3 mm from the chord
        // segment though 0 from its line.
        let fold = [[0.0, 0.0], [-3.0, 0.0], [5.0, 0.0], [5.0, 1.0], [0.0, 1.0]];
        let (kept, dev) = simplify_closed_dev(&fold, 0.5);
        assert_eq!(kept.len(), 5, "{kept:?}");
        assert_eq!(dev, 0.0);
    }

    #[test]
    fn hausdorff_of_concentric_circles_is_the_radius_gap() {
        let circle = |r: f64, n: usize, shift: f64| -> Vec<[f64; 2]> {
            (0..n)
                .map(|k| {
                    let t = TAU * (k as f64 + shift) / n as f64;
                    [r * t.cos(), r * t.sin()]
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
        let q: Vec<[f64; 2]> = (0..300)
            .map(|k| {
                let t = TAU * (k as f64 / 300.0).powf(1.3);
                let r = 60.0 + 15.0 * (2.0 * t).cos() + 5.0 * (3.0 * t).sin();
                [r * t.cos() + 10.0, 0.6 * r * t.sin() - 4.0]
            })
            .collect();
        let grid = SegmentGrid::new(&q);
        for i in -12..=12 {
            for j in -12..=12 {
                let x = [17.0 * i as f64 + 0.3, 11.0 * j as f64 - 0.7];
                let brute = (0..q.len())
                    .map(|k| seg_dist(x, q[k], q[(k + 1) % q.len()]))
                    .fold(f64::INFINITY, f64::min);
                let near = grid.nearest(x);
                assert!((near.distance_mm - brute).abs() < 1e-9, "{x:?}");
                // The returned point lies on the returned segment, at that distance from x.
                let k = near.segment;
                assert!(seg_dist(near.point, q[k], q[(k + 1) % q.len()]) < 1e-9);
                let d = (x[0] - near.point[0]).hypot(x[1] - near.point[1]);
                assert!((d - near.distance_mm).abs() < 1e-9);
            }
        }
    }
}
