//! The indexed outline of the mesh check and the overlap area: a closed polyline with a segment
//! grid for exact signed distances near it ([`Shape`]) and a polar table ([`StarShape`]).
use super::cells::{CellTable, FarMap, Side};
use crate::math::Point;
use std::f64::consts::TAU;

/// Errors of mesh verification.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MeshError {
    /// An outline is not star-shaped about its centre (polar angle not increasing).
    #[error("outline `{which}` is not star-shaped about its centre (vertex {index})")]
    NotStarShaped {
        /// Which outline.
        which: &'static str,
        /// First vertex where the polar angle decreases.
        index: usize,
    },
    /// Bad parameter.
    #[error("invalid mesh parameter `{name}` = {value}: {expected}")]
    InvalidParameter {
        /// Name.
        name: &'static str,
        /// Value.
        value: f64,
        /// Expectation.
        expected: &'static str,
    },
}

/// A star-shaped closed outline in polar form, for fast point-inside tests.
#[derive(Debug, Clone)]
pub struct StarShape {
    theta: Vec<f64>,
    /// Radius of each entry, mm.
    pub(super) r: Vec<f64>,
    /// Index of each entry in the original polyline.
    pub(super) orig: Vec<u32>,
    /// Each entry's vertex (the original point, mm).
    xy: Vec<Point>,
}

impl StarShape {
    /// From a CCW closed polyline (mm) about the origin. Vertices are sorted by polar angle; a
    /// polyline whose polar angle folds back slightly (flank bottoms of non-circular gears) is
    /// accepted — the radial test is then only a coarse inside/outside sign far from the fold.
    pub fn new(points_mm: &[Point], which: &'static str) -> Result<Self, MeshError> {
        if points_mm.len() < 3 {
            return Err(MeshError::NotStarShaped {
                which,
                index: points_mm.len(),
            });
        }
        let mut tr: Vec<(f64, f64, u32)> = points_mm
            .iter()
            .enumerate()
            .map(|(i, p)| (p.atan2(), p.hypot(), i as u32))
            .collect();
        // A generated outline is usually one increasing run of polar angles from its start
        // vertex, wrapping once: then a rotation sorts it (the same order as the stable sort).
        let mut descents = (1..tr.len()).filter(|&i| tr[i].0 <= tr[i - 1].0);
        match (descents.next(), descents.next()) {
            (None, _) => {}
            (Some(k), None) if tr[tr.len() - 1].0 < tr[0].0 => tr.rotate_left(k),
            _ => {
                tr.sort_by(|a, b| a.0.total_cmp(&b.0));
                tr.dedup_by(|a, b| a.0 <= b.0);
            }
        }
        Ok(Self {
            theta: tr.iter().map(|v| v.0).collect(),
            r: tr.iter().map(|v| v.1).collect(),
            orig: tr.iter().map(|v| v.2).collect(),
            xy: tr.iter().map(|v| points_mm[v.2 as usize]).collect(),
        })
    }

    /// Boundary radius at polar angle `t` (rad), mm.
    #[must_use]
    pub fn radius_at(&self, t: f64) -> f64 {
        let t0 = self.theta[0];
        let x = t0 + (t - t0).rem_euclid(TAU);
        let n = self.theta.len();
        let j = self.theta.partition_point(|&v| v <= x);
        let (ta, ra, tb, rb) = if j == 0 || j == n {
            (
                self.theta[n - 1] - if j == 0 { TAU } else { 0.0 },
                self.r[n - 1],
                self.theta[0] + if j == n { TAU } else { 0.0 },
                self.r[0],
            )
        } else {
            (self.theta[j - 1], self.r[j - 1], self.theta[j], self.r[j])
        };
        ra + (rb - ra) * (x - ta) / (tb - ta)
    }

    /// Indices of the vertices with polar angle within `half_width` of `t`.
    pub(super) fn window(&self, t: f64, half_width: f64) -> Vec<usize> {
        let t0 = self.theta[0];
        let n = self.theta.len();
        let lo = t0 + (t - half_width - t0).rem_euclid(TAU);
        let hi = lo + 2.0 * half_width;
        let mut out = Vec::new();
        let a = self.theta.partition_point(|&v| v < lo);
        let mut j = a;
        while j < n && self.theta[j] <= hi {
            out.push(j);
            j += 1;
        }
        if hi > t0 + TAU {
            let hi2 = hi - TAU;
            let mut j = 0;
            while j < a && self.theta[j] <= hi2 {
                out.push(j);
                j += 1;
            }
        }
        out
    }

    /// The vertex of entry `i` (mm).
    #[inline]
    pub(super) fn point(&self, i: usize) -> Point {
        self.xy[i]
    }
}

/// `⌊v⌋` as a cell index: the same value as `v.floor() as i64` for every finite `v` (saturating
/// like the cast beyond ±2⁶³), without the library call `floor` is on targets without SSE4.1 —
/// the clearance query takes two per call.
#[inline]
fn cell_of(v: f64) -> i64 {
    let t = v as i64;
    if (t as f64) > v { t - 1 } else { t }
}

/// One segment `a → a + d` of the outline in a grid cell: `d2 = |d|²` (computed as the distance
/// query computes it), `i` its index.
#[derive(Debug, Clone, Copy)]
struct SegEntry {
    a: Point,
    d: Point,
    d2: f64,
    i: u32,
}

/// A closed CCW polyline with a uniform-grid segment index for signed distances near the
/// boundary, and a polar table for the coarse inside/outside sign away from it.
#[derive(Debug, Clone)]
pub struct Shape {
    pub(super) pts: Vec<Point>,
    pub(super) polar: StarShape,
    bands: super::inside::Bands,
    cell: f64,
    /// Occupied cell → its run `(start, len)` in `entries`.
    grid: CellTable,
    /// Coarse blocks farther than one cell from the outline, with their side.
    far: FarMap,
    /// The segments of every occupied cell, cell by cell, with their geometry inline (one
    /// contiguous read per cell instead of an index list and two vertex look-ups per segment).
    entries: Vec<SegEntry>,
    /// Longest edge, mm.
    pub(super) max_edge: f64,
}

impl Shape {
    /// Indexes `points_mm` with grid cell `cap_mm` (the largest distance reported exactly).
    pub fn new(points_mm: &[Point], cap_mm: f64, which: &'static str) -> Result<Self, MeshError> {
        let polar = StarShape::new(points_mm, which)?;
        let n = points_mm.len();
        // Runs of consecutive segments in one cell, `(cell, first, end)`, sorted by cell then
        // first segment: each cell's segments in outline order. The outline passes through a
        // cell in one or two runs, so this sorts about a tenth as many items as (cell, segment)
        // pairs would.
        let mut runs: Vec<((i64, i64), u32, u32)> = Vec::with_capacity(n / 4 + 16);
        for i in 0..n {
            let (a, b) = (points_mm[i], points_mm[(i + 1) % n]);
            let (x0, x1) = (
                cell_of(a.x.min(b.x) / cap_mm),
                cell_of(a.x.max(b.x) / cap_mm),
            );
            let (y0, y1) = (
                cell_of(a.y.min(b.y) / cap_mm),
                cell_of(a.y.max(b.y) / cap_mm),
            );
            let i = i as u32;
            for cx in x0..=x1 {
                for cy in y0..=y1 {
                    match runs.last_mut() {
                        Some(r) if r.0 == (cx, cy) && r.2 == i => r.2 = i + 1,
                        _ => runs.push(((cx, cy), i, i + 1)),
                    }
                }
            }
        }
        runs.sort_unstable_by_key(|r| (r.0, r.1));
        let cells = runs.chunk_by(|p, q| p.0 == q.0).count();
        let mut grid = CellTable::with_cells(cells);
        let mut occupied = Vec::with_capacity(cells);
        let mut entries: Vec<SegEntry> =
            Vec::with_capacity(runs.iter().map(|r| (r.2 - r.1) as usize).sum());
        for cell_runs in runs.chunk_by(|p, q| p.0 == q.0) {
            let start = entries.len() as u32;
            for &(_, first, end) in cell_runs {
                entries.extend((first..end).map(|i| {
                    let (a, b) = (points_mm[i as usize], points_mm[(i as usize + 1) % n]);
                    let d = b - a;
                    SegEntry {
                        a,
                        d,
                        d2: d.norm_squared(),
                        i,
                    }
                }));
            }
            grid.insert(cell_runs[0].0, (start, entries.len() as u32 - start));
            occupied.push(cell_runs[0].0);
        }
        // Edge lengths (no overflow or underflow at gear sizes: a square root, not `hypot`).
        let (sum_edge, max_edge) = (0..n).fold((0.0, 0.0f64), |(sum, max), i| {
            let (a, b) = (points_mm[i], points_mm[(i + 1) % n]);
            let l = ((b.x - a.x).powi(2) + (b.y - a.y).powi(2)).sqrt();
            (sum + l, max.max(l))
        });
        // Bands about one mean edge tall: a band then lists one or two edges per crossing of
        // the outline, where bands as tall as a grid cell list a dozen on the fine outlines.
        let mean_edge = sum_edge / n as f64;
        let bands = super::inside::Bands::new(points_mm, mean_edge.clamp(cap_mm / 64.0, cap_mm));
        let far = FarMap::new(&occupied, cap_mm, |x| bands.contains(x));
        Ok(Self {
            pts: points_mm.to_vec(),
            polar,
            bands,
            cell: cap_mm,
            grid,
            far,
            entries,
            max_edge,
        })
    }

    /// The outline's vertices (body frame, mm), in order.
    pub(crate) fn points(&self) -> &[Point] {
        &self.pts
    }

    fn cell_entries(&self, (start, len): (u32, u32)) -> &[SegEntry] {
        &self.entries[start as usize..(start + len) as usize]
    }

    /// Indices of the segments listed in the grid cells that the box of `p`–`q` touches
    /// (sorted, without repeats) into `out`.
    pub(crate) fn segments_near(&self, p: Point, q: Point, out: &mut Vec<u32>) {
        out.clear();
        let cell = |v: f64| cell_of(v / self.cell);
        let (x0, x1) = (cell(p.x.min(q.x)), cell(p.x.max(q.x)));
        let (y0, y1) = (cell(p.y.min(q.y)), cell(p.y.max(q.y)));
        let boxed = (x1 - x0 + 1).saturating_mul(y1 - y0 + 1);
        if boxed > self.grid.len() as i64 {
            // A long edge over a fine grid: scan the occupied cells instead of the box.
            for ((gx, gy), run) in self.grid.iter() {
                if (x0..=x1).contains(&gx) && (y0..=y1).contains(&gy) {
                    out.extend(self.cell_entries(run).iter().map(|e| e.i));
                }
            }
        } else {
            for gx in x0..=x1 {
                for gy in y0..=y1 {
                    if let Some(run) = self.grid.get((gx, gy)) {
                        out.extend(self.cell_entries(run).iter().map(|e| e.i));
                    }
                }
            }
        }
        out.sort_unstable();
        out.dedup();
    }

    /// Signed clearance of `x` (body frame, mm): distance to the outline, negative inside;
    /// clipped to `±cap`.
    #[must_use]
    pub fn clearance(&self, x: Point) -> f64 {
        let n = self.pts.len();
        let (cx, cy) = (cell_of(x.x / self.cell), cell_of(x.y / self.cell));
        // Farther than one cell from the outline: the clip, with the side the scan and the
        // crossing test below would give, from one array read.
        match self.far.side((cx, cy)) {
            Side::Inside => return -self.cell,
            Side::Outside => return self.cell,
            Side::Near => {}
        }
        // Squared distances; one square root at the end. The own cell first, then the
        // neighbours whose nearest point can still beat the best (the 3×3 block covers every
        // segment within one cell of `x`, which is all the exact range needs).
        let mut best = (f64::INFINITY, 0usize, 0.5);
        let scan = |gx: i64, gy: i64, best: &mut (f64, usize, f64)| {
            if let Some(run) = self.grid.get((gx, gy)) {
                for e in self.cell_entries(run) {
                    let (Point { x: ax, y: ay }, Point { x: dx, y: dy }) = (e.a, e.d);
                    let (px, py) = (x.x - ax, x.y - ay);
                    let t = ((px * dx + py * dy) / e.d2).clamp(0.0, 1.0);
                    let (ex, ey) = (px - t * dx, py - t * dy);
                    let d2 = ex * ex + ey * ey;
                    if d2 < best.0 {
                        *best = (d2, e.i as usize, t);
                    }
                }
            }
        };
        scan(cx, cy, &mut best);
        // Distances from `x` to the own cell's lower and upper borders in x and y.
        let (fx, fy) = (x.x - cx as f64 * self.cell, x.y - cy as f64 * self.cell);
        let gap = |o: i64, f: f64| match o {
            -1 => f,
            1 => self.cell - f,
            _ => 0.0,
        };
        for ox in -1..=1i64 {
            for oy in -1..=1i64 {
                if ox == 0 && oy == 0 {
                    continue;
                }
                let (gx, gy) = (gap(ox, fx), gap(oy, fy));
                // Every point of that cell is at least this far (squared) from `x`.
                if gx * gx + gy * gy < best.0 {
                    scan(cx + ox, cy + oy, &mut best);
                }
            }
        }
        let best = (best.0.sqrt(), best.1, best.2);
        if best.0 > self.cell {
            // Far from the boundary: the exact crossing rule (a polar test would misread the
            // pocket under a leaning, overhanging tooth).
            return if self.bands.contains(x) {
                -self.cell
            } else {
                self.cell
            };
        }
        let (d, i, t) = best;
        let left = |j: usize| {
            let (a, b) = (self.pts[j % n], self.pts[(j + 1) % n]);
            (b.x - a.x) * (x.y - a.y) - (b.y - a.y) * (x.x - a.x) > 0.0
        };
        let inside = if t > 0.0 && t < 1.0 {
            left(i)
        } else {
            // Closest point is a vertex v between edges e1 = (u→v) and e2 = (v→w).
            let v = if t >= 1.0 { (i + 1) % n } else { i };
            let prev = (v + n - 1) % n;
            let (u, vv, w) = (self.pts[prev], self.pts[v], self.pts[(v + 1) % n]);
            let convex = (vv.x - u.x) * (w.y - vv.y) - (vv.y - u.y) * (w.x - vv.x) > 0.0;
            if convex {
                left(prev) && left(v)
            } else {
                left(prev) || left(v)
            }
        };
        if inside { -d } else { d }
    }
}

#[cfg(test)]
mod tests {
    use super::Shape;
    use crate::math::Point;
    use std::f64::consts::TAU;

    /// Distance to the polyline and even–odd side, by brute force over every segment.
    fn brute(pts: &[Point], x: Point) -> (f64, bool) {
        let n = pts.len();
        let mut d = f64::INFINITY;
        let mut inside = false;
        for i in 0..n {
            let (a, b) = (pts[i], pts[(i + 1) % n]);
            d = d.min(crate::math::polyline::seg_dist(x, a, b));
            if (a.y > x.y) != (b.y > x.y) && a.x + (x.y - a.y) * (b.x - a.x) / (b.y - a.y) > x.x {
                inside = !inside;
            }
        }
        (d, inside)
    }

    #[test]
    fn clearance_equals_brute_force_near_far_inside_and_outside() {
        // A 24-lobe "gear" whose lobes lean over (not star-shaped about the centre everywhere).
        let pts: Vec<Point> = (0..4800)
            .map(|k| {
                let t = TAU * f64::from(k) / 4800.0;
                let r = 20.0 + 1.5 * (24.0 * t).sin();
                let u = t + 0.02 * (24.0 * t).cos();
                Point::new(r * u.cos(), r * u.sin())
            })
            .collect();
        let cap = 0.05;
        let shape = Shape::new(&pts, cap, "test").expect("shape");
        let mut checked = [0usize; 3];
        for i in 0..120 {
            for j in 0..120 {
                let x = Point::new(
                    -25.0 + 50.0 * f64::from(i) / 119.3,
                    -25.0 + 50.0 * f64::from(j) / 119.7,
                );
                let (d, inside) = brute(&pts, x);
                let got = shape.clearance(x);
                if d <= cap {
                    let want = if inside { -d } else { d };
                    assert!((got - want).abs() <= 1e-12, "{x:?}: {got} vs {want}");
                    checked[0] += 1;
                } else {
                    assert_eq!(got, if inside { -cap } else { cap }, "{x:?}");
                    checked[if inside { 1 } else { 2 }] += 1;
                }
            }
        }
        // Points near, far inside and far outside were all met.
        assert!(checked.iter().all(|&c| c > 50), "{checked:?}");
    }
}
