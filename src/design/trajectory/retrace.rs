//! The one ordering a drawn path cannot give: a stretch it runs along twice.
//!
//! A path whose order the drawing states (a polyline, a spline, an SVG path) may cross itself:
//! at a crossing the two passes meet at one point and the order says which comes first, as the
//! rows of a CSV file do. What no order resolves is a stretch of positive length drawn twice: a
//! zero-area spike (out and back along one line) or a loop retracing part of itself. Along it
//! the two passes are the same curve, so the points of one pass cannot be told from the other's,
//! and the needle would have to stop and reverse (or trace the stretch twice) there.
//!
//! The test, on the closed polyline's edges `e_i = (p_i, p_{i+1})` (adjacent pairs included:
//! two consecutive edges that overlap are a reversal): two edges retrace each other when both
//! ends of one lie within `tol` of the other's line and their projections on it overlap by more
//! than `tol` (mm). `O(n²)` edge pairs with a bounding-box reject, as a crossing test.

use crate::math::Point;

/// The middle of the first stretch the closed polyline `pts` (mm, no repeated end point) runs
/// along twice, with the indices of the two edges, if any (module docs); `tol` in mm.
pub(super) fn retraced(pts: &[Point], tol: f64) -> Option<(Point, usize, usize)> {
    let n = pts.len();
    if n < 2 {
        return None;
    }
    let edge = |k: usize| (pts[k], pts[(k + 1) % n]);
    for i in 0..n {
        let (a, b) = edge(i);
        let len = a.distance(b);
        if !(len > 0.0) {
            continue;
        }
        let u = (b - a) * (1.0 / len);
        for j in i + 1..n {
            let (c, d) = edge(j);
            if a.x.max(b.x) + tol < c.x.min(d.x)
                || c.x.max(d.x) + tol < a.x.min(b.x)
                || a.y.max(b.y) + tol < c.y.min(d.y)
                || c.y.max(d.y) + tol < a.y.min(b.y)
            {
                continue;
            }
            // Distances of c and d from the line of ab, and their positions along it.
            let (hc, hd) = (u.cross(c - a).abs(), u.cross(d - a).abs());
            if hc > tol || hd > tol {
                continue;
            }
            let (sc, sd) = (u.dot(c - a), u.dot(d - a));
            let (lo, hi) = (sc.min(sd).max(0.0), sc.max(sd).min(len));
            if hi - lo > tol {
                return Some((a + u * (0.5 * (lo + hi)), i, j));
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    fn circle(n: usize, turns: f64) -> Vec<Point> {
        (0..n)
            .map(|k| Point::from_polar(40.0, turns * TAU * k as f64 / n as f64))
            .collect()
    }

    #[test]
    fn a_crossing_is_no_retrace_and_a_spike_or_a_doubled_loop_is() {
        // A figure eight crosses itself at the origin: no stretch is drawn twice.
        let eight: Vec<Point> = (0..200)
            .map(|k| {
                let t = TAU * k as f64 / 200.0;
                Point::new(40.0 * (2.0 * t).sin(), 40.0 * t.sin())
            })
            .collect();
        assert_eq!(retraced(&eight, 1e-6), None);
        assert_eq!(retraced(&circle(90, 1.0), 1e-6), None);
        // A spike out from vertex 10 to (100, 0) and back: edges 10 and 11 overlap over the
        // whole spike, whose middle is halfway out.
        let mut s = circle(90, 1.0);
        let base = s[10];
        s.insert(11, Point::new(100.0, 0.0));
        s.insert(12, base);
        let (p, i, j) = retraced(&s, 1e-6).unwrap();
        assert_eq!((i, j), (10, 11));
        assert!(
            p.distance(base.lerp(Point::new(100.0, 0.0), 0.5)) < 1e-12,
            "{p:?}"
        );
        // A loop drawn twice round: its first edge is its 91st.
        let (_, i, j) = retraced(&circle(180, 2.0), 1e-6).unwrap();
        assert_eq!((i, j), (0, 90));
    }
}
