//! The closed chord-length spline through the points (docs/math/chain.md §3.1).

use super::dist;
use crate::math::Point;
use crate::math::periodic::PeriodicSpline;

/// A periodic C² chord-length cubic spline `P(s) = (x(s), y(s))`, `s ∈ [0, L)` in mm of chord length.
#[derive(Debug, Clone)]
pub struct ClosedSpline {
    x: PeriodicSpline,
    y: PeriodicSpline,
}

impl ClosedSpline {
    /// Interpolates closed points (no repeated end point, distinct consecutive points).
    #[must_use]
    pub fn through(points: &[Point]) -> Self {
        let n = points.len();
        let mut s = Vec::with_capacity(n);
        let mut acc = 0.0;
        for k in 0..n {
            s.push(acc);
            acc += dist(points[k], points[(k + 1) % n]);
        }
        let xs = points.iter().map(|p| p.x).collect();
        let ys = points.iter().map(|p| p.y).collect();
        // Knots are strictly increasing (distinct consecutive points) and n ≥ 3.
        let x = PeriodicSpline::new(s.clone(), xs, acc).expect("validated trajectory");
        let y = PeriodicSpline::new(s, ys, acc).expect("validated trajectory");
        Self { x, y }
    }

    /// Parameter period `L` (mm).
    #[must_use]
    pub fn period(&self) -> f64 {
        self.x.period()
    }

    /// `(P, P′, P″)` at `s`.
    #[must_use]
    pub fn eval(&self, s: f64) -> [Point; 3] {
        // Both coordinates share their knots: one search for the piece.
        let p = self.x.locate(s);
        let (x, y) = (self.x.eval3_on(p), self.y.eval3_on(p));
        [
            Point::new(x[0], y[0]),
            Point::new(x[1], y[1]),
            Point::new(x[2], y[2]),
        ]
    }

    /// `P(s)` in mm.
    #[must_use]
    pub fn point(&self, s: f64) -> Point {
        let p = self.x.locate(s);
        Point::new(self.x.value_on(p), self.y.value_on(p))
    }
}
