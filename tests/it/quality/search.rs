//! Tools of the reference optimum: point-to-polyline distances and an adaptive Nelder–Mead.

use ncgear::math::Point;
/// Distance (mm) from `p` to the segment `a b`.
pub fn seg_dist(p: Point, a: Point, b: Point) -> f64 {
    seg_dist2(p, a, b).sqrt()
}

/// Squared distance (mm²) from `p` to the segment `a b`.
fn seg_dist2(p: Point, a: Point, b: Point) -> f64 {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (((p.x - a.x) * dx + (p.y - a.y) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let (ex, ey) = (p.x - a.x - t * dx, p.y - a.y - t * dy);
    ex * ex + ey * ey
}

/// A closed polyline with its segments bucketed in a uniform grid, for exact point distances:
/// a query searches ring by ring until no unseen cell can hold a closer segment.
pub struct ClosedPolyline<'a> {
    poly: &'a [Point],
    lo: [f64; 2],
    cell: f64,
    nx: i64,
    ny: i64,
    /// Segments of cell `c` are `segs[start[c]..start[c + 1]]`.
    start: Vec<u32>,
    segs: Vec<u32>,
}

impl<'a> ClosedPolyline<'a> {
    /// The index of the closed polyline `poly` (mm).
    pub fn new(poly: &'a [Point]) -> Self {
        let n = poly.len();
        let (mut lo, mut hi, mut len) = ([f64::MAX; 2], [f64::MIN; 2], 0.0);
        for k in 0..n {
            let (p, q) = (poly[k], poly[(k + 1) % n]);
            for d in 0..2 {
                lo[d] = lo[d].min(p.to_array()[d]);
                hi[d] = hi[d].max(p.to_array()[d]);
            }
            len += q.distance(p);
        }
        let span = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1e-9);
        let cell = (4.0 * len / n as f64).max(span / 64.0);
        let nx = ((hi[0] - lo[0]) / cell) as i64 + 1;
        let ny = ((hi[1] - lo[1]) / cell) as i64 + 1;
        let cx = |x: f64| (((x - lo[0]) / cell).floor() as i64).clamp(0, nx - 1);
        let cy = |y: f64| (((y - lo[1]) / cell).floor() as i64).clamp(0, ny - 1);
        // Cells of each segment's bounding box, in compressed rows: start[c]..start[c + 1].
        let boxes: Vec<[i64; 4]> = (0..n)
            .map(|k| {
                let (p, q) = (poly[k], poly[(k + 1) % n]);
                [
                    cx(p.x.min(q.x)),
                    cx(p.x.max(q.x)),
                    cy(p.y.min(q.y)),
                    cy(p.y.max(q.y)),
                ]
            })
            .collect();
        let mut start = vec![0u32; (nx * ny + 1) as usize];
        for b in &boxes {
            for ix in b[0]..=b[1] {
                for iy in b[2]..=b[3] {
                    start[(iy * nx + ix) as usize + 1] += 1;
                }
            }
        }
        for c in 1..start.len() {
            start[c] += start[c - 1];
        }
        let mut fill = start.clone();
        let mut segs = vec![0u32; start[start.len() - 1] as usize];
        for (k, b) in boxes.iter().enumerate() {
            for ix in b[0]..=b[1] {
                for iy in b[2]..=b[3] {
                    let c = (iy * nx + ix) as usize;
                    segs[fill[c] as usize] = k as u32;
                    fill[c] += 1;
                }
            }
        }
        Self {
            poly,
            lo,
            cell,
            nx,
            ny,
            start,
            segs,
        }
    }

    /// Exact distance (mm) of `p` to the polyline.
    pub fn distance(&self, p: Point) -> f64 {
        let (poly, n, cell, nx, ny) = (self.poly, self.poly.len(), self.cell, self.nx, self.ny);
        let ix = ((p.x - self.lo[0]) / cell).floor() as i64;
        let iy = ((p.y - self.lo[1]) / cell).floor() as i64;
        // Rings around the (possibly outside) cell of p, up to the whole grid.
        let rmax = nx.max(ny) + ix.abs().max(iy.abs()) + 2;
        let mut best = f64::INFINITY;
        for r in 0..=rmax {
            for jx in (ix - r).max(0)..=(ix + r).min(nx - 1) {
                for jy in (iy - r).max(0)..=(iy + r).min(ny - 1) {
                    if (jx - ix).abs() != r && (jy - iy).abs() != r {
                        continue;
                    }
                    let c = (jy * nx + jx) as usize;
                    for &s in &self.segs[self.start[c] as usize..self.start[c + 1] as usize] {
                        let s = s as usize;
                        best = best.min(seg_dist2(p, poly[s], poly[(s + 1) % n]));
                    }
                }
            }
            // Every unseen segment lies in a cell of ring ≥ r + 1: at least r·cell away.
            if best <= (r as f64 * cell).powi(2) {
                break;
            }
        }
        best.sqrt()
    }

    /// [`Self::distance`] of each point.
    pub fn distances(&self, points: &[Point]) -> Vec<f64> {
        points.iter().map(|&p| self.distance(p)).collect()
    }
}

/// Exact distance (mm) of each point to the closed polyline `poly`.
pub fn distances_to_closed(points: &[Point], poly: &[Point]) -> Vec<f64> {
    ClosedPolyline::new(poly).distances(points)
}

/// Hausdorff distance (mm) between the closed polylines through `target` and `traced`: the
/// largest of every target point's distance to `traced` and every traced vertex's distance to
/// `target`: measured at the vertices of both, exact up to the chords of fine polylines.
pub fn hausdorff_closed(target: &[Point], traced: &[Point]) -> f64 {
    let there = distances_to_closed(target, traced)
        .into_iter()
        .fold(0.0, f64::max);
    let back = distances_to_closed(traced, target)
        .into_iter()
        .fold(0.0, f64::max);
    there.max(back)
}

/// Power mean `(Σ d^p / M)^{1/p}` of the distances (mm); `p = ∞` gives the largest.
pub fn power_mean(d: &[f64], p: f64) -> f64 {
    let max = d.iter().copied().fold(0.0, f64::max);
    if p.is_infinite() || max == 0.0 {
        return max;
    }
    let s: f64 = d.iter().map(|&v| (v / max).powf(p)).sum();
    max * (s / d.len() as f64).powf(1.0 / p)
}

/// Nelder–Mead with the dimension-adaptive coefficients of Gao & Han (2012):
/// reflection 1, expansion 1 + 2/n, contraction 0.75 − 1/(2n), shrink 1 − 1/n.
/// Starts from the simplex `x0, x0 + step_k e_k`; stops after `max_evals` evaluations or when the
/// spread of the simplex values is below `ftol` (absolute). Returns `(x_best, f_best, evals)`.
pub fn nelder_mead(
    f: &mut dyn FnMut(&[f64]) -> f64,
    x0: &[f64],
    step: &[f64],
    max_evals: usize,
    ftol: f64,
) -> (Vec<f64>, f64, usize) {
    let n = x0.len();
    let nf = n as f64;
    let (alpha, beta, gamma, delta) = (1.0, 1.0 + 2.0 / nf, 0.75 - 0.5 / nf, 1.0 - 1.0 / nf);
    let mut simplex: Vec<(Vec<f64>, f64)> = Vec::with_capacity(n + 1);
    simplex.push((x0.to_vec(), f(x0)));
    for k in 0..n {
        let mut x = x0.to_vec();
        x[k] += step[k];
        let v = f(&x);
        simplex.push((x, v));
    }
    let mut evals = n + 1;
    let lin = |a: &[f64], b: &[f64], t: f64| -> Vec<f64> {
        a.iter().zip(b).map(|(a, b)| a + t * (b - a)).collect()
    };
    while evals < max_evals {
        simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
        if simplex[n].1 - simplex[0].1 <= ftol {
            break;
        }
        let mut c = vec![0.0; n];
        for (x, _) in &simplex[..n] {
            for (ci, xi) in c.iter_mut().zip(x) {
                *ci += xi / nf;
            }
        }
        let worst = simplex[n].clone();
        let xr = lin(&c, &worst.0, -alpha);
        let fr = f(&xr);
        evals += 1;
        if fr < simplex[0].1 {
            let xe = lin(&c, &worst.0, -alpha * beta);
            let fe = f(&xe);
            evals += 1;
            simplex[n] = if fe < fr { (xe, fe) } else { (xr, fr) };
        } else if fr < simplex[n - 1].1 {
            simplex[n] = (xr, fr);
        } else {
            // Outside contraction when the reflection beat the worst, inside otherwise.
            let (xc, fc) = if fr < worst.1 {
                let xc = lin(&c, &xr, gamma);
                let v = f(&xc);
                (xc, v)
            } else {
                let xc = lin(&c, &worst.0, gamma);
                let v = f(&xc);
                (xc, v)
            };
            evals += 1;
            if fc < fr.min(worst.1) {
                simplex[n] = (xc, fc);
            } else {
                let best = simplex[0].0.clone();
                for s in simplex.iter_mut().skip(1) {
                    s.0 = lin(&best, &s.0, delta);
                    s.1 = f(&s.0);
                }
                evals += n;
            }
        }
    }
    simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
    let (x, v) = simplex.swap_remove(0);
    (x, v, evals)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polyline_distance_matches_brute_force() {
        let poly: Vec<Point> = (0..500)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / 500.0;
                Point::new(100.0 * t.cos() + 30.0 * (2.0 * t).cos(), 60.0 * t.sin())
            })
            .collect();
        let pts: Vec<Point> = (0..300)
            .map(|k| Point::new(-150.0 + k as f64, 40.0 * ((k as f64) * 0.37).sin()))
            .collect();
        let d = distances_to_closed(&pts, &poly);
        for (p, d) in pts.iter().zip(&d) {
            let brute = (0..500)
                .map(|k| seg_dist(*p, poly[k], poly[(k + 1) % 500]))
                .fold(f64::INFINITY, f64::min);
            assert!((d - brute).abs() < 1e-12, "{d} vs {brute}");
        }
    }

    #[test]
    fn nelder_mead_minimises_a_rosenbrock_valley() {
        let mut f = |x: &[f64]| {
            (0..x.len() - 1)
                .map(|k| 100.0 * (x[k + 1] - x[k] * x[k]).powi(2) + (1.0 - x[k]).powi(2))
                .sum::<f64>()
        };
        let (x, v, _) = nelder_mead(&mut f, &[-1.0, 1.5, 0.5], &[0.5; 3], 20_000, 1e-14);
        assert!(v < 1e-8, "f = {v}, x = {x:?}");
    }
}
