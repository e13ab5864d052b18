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

/// Distance (mm) from each point of `p` to the closed polyline `q`, with the segments of `q` bucketed on a uniform grid so each
/// query only visits nearby cells (exact: rings are searched until no closer segment can exist).
#[must_use]
pub fn distances_to_polyline(p: &[[f64; 2]], q: &[[f64; 2]]) -> Vec<f64> {
    let n = q.len();
    if n == 0 || p.is_empty() {
        return vec![0.0; p.len()];
    }
    let (mut x0, mut y0, mut x1, mut y1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
    for v in q.iter().chain(p) {
        x0 = x0.min(v[0]);
        y0 = y0.min(v[1]);
        x1 = x1.max(v[0]);
        y1 = y1.max(v[1]);
    }
    let cells = ((n as f64).sqrt().ceil() as usize).clamp(1, 256);
    let h = ((x1 - x0).max(y1 - y0) / cells as f64).max(1e-12);
    let (nx, ny) = (((x1 - x0) / h) as usize + 1, ((y1 - y0) / h) as usize + 1);
    let cell = |v: f64, o: f64, m: usize| (((v - o) / h) as usize).min(m - 1);
    let mut grid: Vec<Vec<usize>> = vec![Vec::new(); nx * ny];
    for k in 0..n {
        let (a, b) = (q[k], q[(k + 1) % n]);
        let (cx0, cx1) = (cell(a[0].min(b[0]), x0, nx), cell(a[0].max(b[0]), x0, nx));
        let (cy0, cy1) = (cell(a[1].min(b[1]), y0, ny), cell(a[1].max(b[1]), y0, ny));
        for cx in cx0..=cx1 {
            for cy in cy0..=cy1 {
                grid[cy * nx + cx].push(k);
            }
        }
    }
    p.iter()
        .map(|x| {
            let (cx, cy) = (cell(x[0], x0, nx) as i64, cell(x[1], y0, ny) as i64);
            let mut best = f64::INFINITY;
            for ring in 0..(nx.max(ny) as i64 + 1) {
                // Any segment in ring r or beyond is at least (r − 1)·h away.
                if best <= (ring as f64 - 1.0) * h {
                    break;
                }
                for gx in (cx - ring)..=(cx + ring) {
                    for gy in (cy - ring)..=(cy + ring) {
                        let on_ring = (gx - cx).abs() == ring || (gy - cy).abs() == ring;
                        if !on_ring || gx < 0 || gy < 0 || gx >= nx as i64 || gy >= ny as i64 {
                            continue;
                        }
                        for &k in &grid[gy as usize * nx + gx as usize] {
                            best = best.min(seg_dist(*x, q[k], q[(k + 1) % n]));
                        }
                    }
                }
            }
            best
        })
        .collect()
}

/// Distance from `x` to the segment `ab`, mm.
#[must_use]
pub fn seg_dist(x: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (((x[0] - a[0]) * dx + (x[1] - a[1]) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (x[0] - a[0] - t * dx).hypot(x[1] - a[1] - t * dy)
}

/// Simplifies a closed polyline so that no removed vertex deviates more than `tol_mm` from the
/// kept chords (Douglas–Peucker on the two halves split at the farthest vertex from vertex 0).
#[must_use]
pub fn simplify_closed(points_mm: &[[f64; 2]], tol_mm: f64) -> Vec<[f64; 2]> {
    let n = points_mm.len();
    if n < 4 {
        return points_mm.to_vec();
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
    let mut stack = vec![(0usize, far), (far, n)];
    while let Some((a, b)) = stack.pop() {
        if b <= a + 1 {
            continue;
        }
        let pa = points_mm[a];
        let pb = points_mm[b % n];
        let (dx, dy) = (pb[0] - pa[0], pb[1] - pa[1]);
        let l = dx.hypot(dy).max(1e-300);
        let mut worst = (0.0, a);
        for (i, p) in points_mm.iter().enumerate().take(b).skip(a + 1) {
            let d = ((p[0] - pa[0]) * dy - (p[1] - pa[1]) * dx).abs() / l;
            if d > worst.0 {
                worst = (d, i);
            }
        }
        if worst.0 > tol_mm {
            keep[worst.1] = true;
            stack.push((a, worst.1));
            stack.push((worst.1, b));
        }
    }
    points_mm
        .iter()
        .zip(keep)
        .filter(|(_, k)| *k)
        .map(|(p, _)| *p)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

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
}
