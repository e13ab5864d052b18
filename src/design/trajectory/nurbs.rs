//! The B-spline (NURBS) of a DXF SPLINE entity, evaluated by de Boor's algorithm.
//!
//! Written here rather than taken from a crate: it is thirty lines, it must take the degree,
//! knots and weights exactly as the DXF stores them (clamped or periodic knot vectors, any
//! degree), and it must refuse bad data with a message instead of panicking; the geometry
//! crates at hand either approximate splines by Béziers of fixed degree or assume clamped
//! uniform knots.
//!
//! With control points `P_i`, weights `w_i` (1 when the spline is not rational), degree `p`
//! and knots `u_0 ≤ … ≤ u_{n+p}` (n control points):
//!
//! ```text
//! C(t) = Σ N_{i,p}(t)·w_i·P_i / Σ N_{i,p}(t)·w_i,   t ∈ [u_p, u_n]
//! ```
//!
//! evaluated in homogeneous coordinates `(w·x, w·y, w)`: on the span `u_k ≤ t < u_{k+1}`,
//! `d_j = Q_{k−p+j}` (j = 0…p), then for r = 1…p and j = p…r,
//! `α = (t − u_{k−p+j}) / (u_{k+1+j−r} − u_{k−p+j})`, `d_j = (1 − α)·d_{j−1} + α·d_j`;
//! `C(t) = d_p` divided by its weight.

use crate::math::Point;

/// A validated non-uniform rational B-spline in the plane.
#[derive(Debug, Clone)]
pub(super) struct Nurbs {
    degree: usize,
    knots: Vec<f64>,
    /// `(w·x, w·y, w)` per control point.
    homogeneous: Vec<[f64; 3]>,
}

impl Nurbs {
    /// Checks and builds; the error says what is wrong with the data.
    pub fn new(
        degree: i32,
        control: &[Point],
        weights: &[f64],
        knots: Vec<f64>,
    ) -> Result<Self, String> {
        let n = control.len();
        let p = usize::try_from(degree)
            .ok()
            .filter(|&p| p >= 1)
            .ok_or_else(|| format!("degree {degree}: a spline needs degree 1 or more"))?;
        if n < p + 1 {
            return Err(format!(
                "{n} control points, a degree-{p} spline needs at least {}",
                p + 1
            ));
        }
        if knots.len() != n + p + 1 {
            return Err(format!(
                "{} knots, {n} control points of degree {p} need {} (n + p + 1)",
                knots.len(),
                n + p + 1
            ));
        }
        if knots.iter().any(|u| !u.is_finite()) || knots.windows(2).any(|w| w[1] < w[0]) {
            return Err("the knots are not finite and non-decreasing".into());
        }
        if knots[p] >= knots[n] {
            return Err(format!("the knot domain [u_{p}, u_{n}] is empty"));
        }
        if !weights.is_empty()
            && (weights.len() != n || weights.iter().any(|w| !(w.is_finite() && *w > 0.0)))
        {
            return Err(format!(
                "{} weights for {n} control points; weights must be positive, one per control point",
                weights.len()
            ));
        }
        if control
            .iter()
            .any(|c| !(c.x.is_finite() && c.y.is_finite()))
        {
            return Err("a control point is not finite".into());
        }
        let homogeneous = control
            .iter()
            .enumerate()
            .map(|(i, c)| {
                let w = weights.get(i).copied().unwrap_or(1.0);
                [w * c.x, w * c.y, w]
            })
            .collect();
        Ok(Self {
            degree: p,
            knots,
            homogeneous,
        })
    }

    /// The parameter spans `[u_k, u_{k+1}]` of non-zero length inside the domain.
    pub fn spans(&self) -> Vec<(f64, f64)> {
        let (p, n) = (self.degree, self.homogeneous.len());
        (p..n)
            .map(|k| (self.knots[k], self.knots[k + 1]))
            .filter(|(a, b)| b > a)
            .collect()
    }

    /// `C(t)` (module docs); `t` is clamped into the domain `[u_p, u_n]`.
    pub fn point(&self, t: f64) -> Point {
        let (p, n) = (self.degree, self.homogeneous.len());
        let u = &self.knots;
        let t = t.clamp(u[p], u[n]);
        // The span k with u_k ≤ t < u_{k+1}, p ≤ k < n (the last span includes u_n).
        let k = (u.partition_point(|&x| x <= t).saturating_sub(1)).clamp(p, n - 1);
        let mut d: Vec<[f64; 3]> = (0..=p).map(|j| self.homogeneous[k - p + j]).collect();
        for r in 1..=p {
            for j in (r..=p).rev() {
                let (lo, hi) = (u[k - p + j], u[k + 1 + j - r]);
                let a = if hi > lo { (t - lo) / (hi - lo) } else { 0.0 };
                let prev = d[j - 1];
                for (c, q) in d[j].iter_mut().zip(prev) {
                    *c = (1.0 - a) * q + a * *c;
                }
            }
        }
        let [x, y, w] = d[p];
        Point::new(x / w, y / w)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rational quadratic circle: 9 control points on the square, weights 1, √½, …,
    /// knots 0,0,0,¼,¼,½,½,¾,¾,1,1,1.
    fn circle(r: f64) -> Nurbs {
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let c = [
            (1.0, 0.0),
            (1.0, 1.0),
            (0.0, 1.0),
            (-1.0, 1.0),
            (-1.0, 0.0),
            (-1.0, -1.0),
            (0.0, -1.0),
            (1.0, -1.0),
            (1.0, 0.0),
        ];
        let pts: Vec<Point> = c.iter().map(|&(x, y)| Point::new(r * x, r * y)).collect();
        let w = [1.0, s, 1.0, s, 1.0, s, 1.0, s, 1.0];
        let knots = vec![
            0.0, 0.0, 0.0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1.0, 1.0, 1.0,
        ];
        Nurbs::new(2, &pts, &w, knots).unwrap()
    }

    #[test]
    fn the_rational_quadratic_circle_is_a_circle() {
        let c = circle(37.5);
        for k in 0..=1000 {
            let p = c.point(k as f64 / 1000.0);
            assert!((p.norm() - 37.5).abs() < 1e-12, "{k}: {}", p.norm());
        }
        assert!(c.point(0.0).distance(Point::new(37.5, 0.0)) < 1e-12);
        assert!(c.point(0.25).distance(Point::new(0.0, 37.5)) < 1e-12);
        assert_eq!(c.spans().len(), 4);
    }

    #[test]
    fn a_clamped_cubic_bezier_matches_bernstein() {
        let pts = [
            Point::new(0.0, 0.0),
            Point::new(1.0, 3.0),
            Point::new(4.0, 3.0),
            Point::new(5.0, 0.0),
        ];
        let b = Nurbs::new(3, &pts, &[], vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0]).unwrap();
        for k in 0..=10 {
            let t = k as f64 / 10.0;
            let s = 1.0 - t;
            let want = pts[0] * (s * s * s)
                + pts[1] * (3.0 * s * s * t)
                + pts[2] * (3.0 * s * t * t)
                + pts[3] * (t * t * t);
            assert!(b.point(t).distance(want) < 1e-13);
        }
    }

    #[test]
    fn bad_splines_are_refused_with_a_reason() {
        let pts = [
            Point::new(0.0, 0.0),
            Point::new(1.0, 0.0),
            Point::new(2.0, 1.0),
        ];
        assert!(
            Nurbs::new(0, &pts, &[], vec![0.0; 4])
                .unwrap_err()
                .contains("degree")
        );
        assert!(
            Nurbs::new(2, &pts, &[], vec![0.0; 5])
                .unwrap_err()
                .contains("knots")
        );
        let dec = vec![0.0, 0.0, 1.0, 0.5, 1.0, 1.0];
        assert!(
            Nurbs::new(2, &pts, &[], dec)
                .unwrap_err()
                .contains("non-decreasing")
        );
        let k = vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0];
        assert!(
            Nurbs::new(2, &pts, &[1.0, -1.0, 1.0], k)
                .unwrap_err()
                .contains("weights")
        );
    }
}
