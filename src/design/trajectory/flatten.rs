//! Curves to polylines, and closed polylines to uniform arc-length samples.

use crate::math::Point;
use crate::math::polyline::seg_dist;

/// Fewest flattening pieces per curve span (docs of `drawing`).
pub const MIN_PIECES: usize = 4;

/// Deepest bisection of one flattening piece (2⁻¹² of it: at most 16 384 chords per span, enough
/// for a 1 µm tolerance on an arc of 60 m radius).
const MAX_DEPTH: u32 = 12;

/// Most points a drawing's curves are flattened to (4 M, 64 MB): past it every piece is one
/// chord, so that a drawing of absurd size or span count stays within memory (its loop is then
/// coarser than the tolerance, and a drawing that big is no planting-arm loop anyway).
const MAX_FLATTENED_POINTS: usize = 1 << 22;

/// Appends to `out` the points of the curve `f` on `(t0, t1]` (its start is the caller's last
/// point): [`MIN_PIECES`] equal parameter pieces, each bisected while its parameter midpoint
/// lies farther than `tol` from its chord.
pub(super) fn flatten(f: &dyn Fn(f64) -> Point, t0: f64, t1: f64, tol: f64, out: &mut Vec<Point>) {
    let mut a = f(t0);
    for k in 1..=MIN_PIECES {
        let tb = t0 + (t1 - t0) * k as f64 / MIN_PIECES as f64;
        let ta = t0 + (t1 - t0) * (k - 1) as f64 / MIN_PIECES as f64;
        let b = f(tb);
        bisect(f, (ta, a), (tb, b), tol, 0, out);
        a = b;
    }
}

fn bisect(
    f: &dyn Fn(f64) -> Point,
    (ta, a): (f64, Point),
    (tb, b): (f64, Point),
    tol: f64,
    depth: u32,
    out: &mut Vec<Point>,
) {
    let tm = 0.5 * (ta + tb);
    let m = f(tm);
    // A non-finite point (bad input, refused later) ends the bisection too.
    let d = seg_dist(m, a, b);
    if depth >= MAX_DEPTH || d <= tol || d.is_nan() || out.len() >= MAX_FLATTENED_POINTS {
        out.push(b);
        return;
    }
    bisect(f, (ta, a), (tm, m), tol, depth + 1, out);
    bisect(f, (tm, m), (tb, b), tol, depth + 1, out);
}

/// `n` points uniform in arc length along the closed polyline `pts` (no repeated end point),
/// the first at `pts[0]`: `P(s_k)`, `s_k = k·L/n`, linear between the vertices. `None` when
/// the polyline has zero length.
pub(super) fn resample(pts: &[Point], n: usize) -> Option<Vec<Point>> {
    let m = pts.len();
    let mut cum = Vec::with_capacity(m + 1);
    cum.push(0.0);
    for k in 0..m {
        cum.push(cum[k] + pts[k].distance(pts[(k + 1) % m]));
    }
    let len = cum[m];
    if !(len > 0.0 && len.is_finite()) {
        return None;
    }
    let mut j = 0;
    let out = (0..n)
        .map(|k| {
            let s = len * k as f64 / n as f64;
            while j + 1 < m && cum[j + 1] <= s {
                j += 1;
            }
            let span = cum[j + 1] - cum[j];
            let f = if span > 0.0 { (s - cum[j]) / span } else { 0.0 };
            pts[j].lerp(pts[(j + 1) % m], f.clamp(0.0, 1.0))
        })
        .collect();
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    #[test]
    fn a_flattened_circle_stays_within_the_tolerance_and_resamples_uniformly() {
        let r = 50.0;
        let f = |t: f64| Point::new(r * t.cos(), r * t.sin());
        let mut pts = vec![f(0.0)];
        flatten(&f, 0.0, TAU, 1e-3, &mut pts);
        pts.pop();
        for w in pts.windows(2) {
            let mid = w[0].lerp(w[1], 0.5);
            assert!(r - mid.norm() <= 1e-3 + 1e-12);
        }
        let s = resample(&pts, 720).unwrap();
        assert_eq!(s.len(), 720);
        assert_eq!(s[0], f(0.0));
        let step = s[0].distance(s[1]);
        for k in 0..720 {
            assert!((s[k].distance(s[(k + 1) % 720]) - step).abs() < 1e-4);
        }
    }
}
