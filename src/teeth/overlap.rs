//! Overlap (interference) area of two closed outlines, exact for polygons.
//!
//! The boundary of `A ∩ B` is made of the pieces of `∂A` inside `B` and the pieces of `∂B`
//! inside `A`, each traversed in its own CCW sense, so by the shoelace formula
//!
//! ```text
//! area(A ∩ B) = ½ Σ_{pieces of ∂A in B} (x dy − y dx) + ½ Σ_{pieces of ∂B in A} (x dy − y dx)
//! ```
//!
//! with all pieces in one (world) frame. Each edge is split at its crossings with the other
//! polyline (found through the other outline's segment grid) and a piece counts when its midpoint
//! lies inside the other outline. Restricted to chains of edges (the teeth near the contact), the
//! sum is exact as long as the overlap lies within those chains.
use super::shape::{MeshError, Shape};
use crate::math::Point;
use nalgebra::{Isometry2, Point2};

/// `iso(p)` on plain `[x, y]` points (mm).
fn apply(iso: &Isometry2<f64>, p: Point) -> Point {
    let q = iso * Point2::new(p.x, p.y);
    Point::new(q.x, q.y)
}

/// `½ Σ (x dy − y dx)` (mm², world frame) over the pieces of the edges `i → i+1` (`edges` hold
/// the start indices) of `a` that lie inside `b`. `a_to_b` maps `a`'s body frame into `b`'s,
/// `a_to_world` into the common frame of the sum.
pub(crate) fn inside_term(
    a: &Shape,
    edges: &[usize],
    a_to_b: &Isometry2<f64>,
    a_to_world: &Isometry2<f64>,
    b: &Shape,
) -> f64 {
    let pa = a.points();
    let n = pa.len();
    let mut sum = 0.0;
    let mut hits: Vec<u32> = Vec::new();
    let mut ts: Vec<f64> = Vec::new();
    for &i in edges {
        let (p0, p1) = (pa[i], pa[(i + 1) % n]);
        let (p, q) = (apply(a_to_b, p0), apply(a_to_b, p1));
        b.segments_near(p, q, &mut hits);
        ts.clear();
        ts.push(0.0);
        let d = q - p;
        let pb = b.points();
        let nb = pb.len();
        for &j in &hits {
            let (s0, s1) = (pb[j as usize], pb[(j as usize + 1) % nb]);
            let e = s1 - s0;
            let den = d.cross(e);
            if den == 0.0 {
                continue;
            }
            let w = s0 - p;
            let (t, u) = (w.cross(e) / den, w.cross(d) / den);
            if (0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&u) {
                ts.push(t);
            }
        }
        ts.push(1.0);
        ts.sort_by(f64::total_cmp);
        let at = |t: f64| p0.lerp(p1, t);
        for k in 0..ts.len() - 1 {
            let (t0, t1) = (ts[k], ts[k + 1]);
            if t1 <= t0 {
                continue;
            }
            let tm = 0.5 * (t0 + t1);
            if b.clearance(p + d * tm) < 0.0 {
                sum += 0.5 * apply(a_to_world, at(t0)).cross(apply(a_to_world, at(t1)));
            }
        }
    }
    sum
}

/// Overlap area (mm²) of two closed CCW polygons given in one frame (mm): `area(P ∩ Q)`,
/// exact up to rounding for simple polygons.
///
/// # Errors
/// [`MeshError::NotStarShaped`] when a polygon has fewer than 3 vertices.
///
/// # Examples
/// ```
/// use ncgear::math::Point;
/// use ncgear::teeth::overlap::polygon_overlap_area;
/// let sq = |x: f64, y: f64| [[x, y], [x + 2.0, y], [x + 2.0, y + 2.0], [x, y + 2.0]].map(Point::from);
/// let a = polygon_overlap_area(&sq(0.0, 0.0), &sq(1.0, 1.5)).unwrap();
/// assert!((a - 0.5).abs() < 1e-12);
/// ```
pub fn polygon_overlap_area(p_mm: &[Point], q_mm: &[Point]) -> Result<f64, MeshError> {
    let cell = |v: &[Point]| {
        let n = v.len().max(1);
        let per: f64 = (0..v.len())
            .map(|i| {
                let (a, b) = (v[i], v[(i + 1) % n]);
                b.distance(a)
            })
            .sum::<f64>()
            / n as f64;
        (2.0 * per).max(1e-9)
    };
    let c = cell(p_mm).max(cell(q_mm));
    let a = Shape::new(p_mm, c, "first polygon")?;
    let b = Shape::new(q_mm, c, "second polygon")?;
    let id = Isometry2::identity();
    let all = |n: usize| (0..n).collect::<Vec<_>>();
    Ok(inside_term(&a, &all(p_mm.len()), &id, &id, &b)
        + inside_term(&b, &all(q_mm.len()), &id, &id, &a))
}

/// First pair of non-adjacent edges `(i, j)`, `i < j` (edge `i` runs from vertex `i` to `i+1`) of
/// the closed polygon `points_mm` that touch or cross, or `None` when the polygon is simple.
/// Grid-indexed: O(n) for outlines with edges of similar length.
///
/// # Errors
/// [`MeshError::NotStarShaped`] when the polygon has fewer than 3 vertices.
///
/// # Examples
/// ```
/// use ncgear::math::Point;
/// use ncgear::teeth::overlap::first_self_intersection;
/// let square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]].map(Point::from);
/// assert_eq!(first_self_intersection(&square).unwrap(), None);
/// let bowtie = [[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]].map(Point::from);
/// assert_eq!(first_self_intersection(&bowtie).unwrap(), Some((0, 2)));
/// ```
pub fn first_self_intersection(points_mm: &[Point]) -> Result<Option<(usize, usize)>, MeshError> {
    let n = points_mm.len();
    let mean = (0..n)
        .map(|i| {
            let (a, b) = (points_mm[i], points_mm[(i + 1) % n.max(1)]);
            b.distance(a)
        })
        .sum::<f64>()
        / n.max(1) as f64;
    let shape = Shape::new(points_mm, (2.0 * mean).max(1e-9), "polygon")?;
    let mut near = Vec::new();
    let mut found: Option<(usize, usize)> = None;
    for i in 0..n {
        let (p, q) = (points_mm[i], points_mm[(i + 1) % n]);
        shape.segments_near(p, q, &mut near);
        for &j in &near {
            let j = j as usize;
            if j <= i || j == i + 1 || (i == 0 && j == n - 1) {
                continue;
            }
            let (a, b) = (points_mm[j], points_mm[(j + 1) % n]);
            let side = |u: Point, v: Point, w: Point| (v - u).cross(w - u);
            let (d1, d2) = (side(p, q, a), side(p, q, b));
            let (d3, d4) = (side(a, b, p), side(a, b, q));
            let crosses = d1 * d2 <= 0.0 && d3 * d4 <= 0.0;
            // Collinear edges: only when their boxes overlap.
            let collinear = d1 == 0.0 && d2 == 0.0;
            let boxes = p.x.min(q.x) <= a.x.max(b.x)
                && a.x.min(b.x) <= p.x.max(q.x)
                && p.y.min(q.y) <= a.y.max(b.y)
                && a.y.min(b.y) <= p.y.max(q.y);
            if crosses && (!collinear || boxes) && found.is_none_or(|f| (i, j) < f) {
                found = Some((i, j));
            }
        }
        if found.is_some_and(|f| f.0 == i) {
            break;
        }
    }
    Ok(found)
}

#[cfg(test)]
mod tests {
    use super::{apply, polygon_overlap_area};
    use crate::math::Point;
    use nalgebra::{Isometry2, Vector2};
    use std::f64::consts::PI;

    fn circle(c: Point, r: f64, n: usize) -> Vec<Point> {
        (0..n)
            .map(|k| {
                let t = 2.0 * PI * k as f64 / n as f64;
                c + Point::from_polar(r, t)
            })
            .collect()
    }

    /// Lens of two circles: 2R²·acos(d/2R) − (d/2)·√(4R² − d²); the inscribed polygons converge
    /// at O(1/n²).
    #[test]
    fn lens_area_matches_the_closed_form() {
        let (r, d) = (10.0f64, 7.0f64);
        let want = 2.0 * r * r * (d / (2.0 * r)).acos() - 0.5 * d * (4.0 * r * r - d * d).sqrt();
        let a = polygon_overlap_area(
            &circle(Point::new(0.0, 0.0), r, 20_000),
            &circle(Point::new(d, 0.0), r, 20_001),
        )
        .unwrap();
        assert!((a - want).abs() < 1e-6 * want, "{a} vs {want}");
        // Disjoint and nested.
        let far = polygon_overlap_area(
            &circle(Point::new(0.0, 0.0), 1.0, 64),
            &circle(Point::new(3.0, 0.0), 1.0, 64),
        );
        assert_eq!(far.unwrap(), 0.0);
        let inner = circle(Point::new(0.2, 0.1), 0.5, 64);
        let nested = polygon_overlap_area(&circle(Point::new(0.0, 0.0), 2.0, 256), &inner).unwrap();
        let shoelace: f64 = (0..64)
            .map(|i| {
                let (p, q) = (inner[i], inner[(i + 1) % 64]);
                0.5 * (p.cross(q))
            })
            .sum();
        assert!((nested - shoelace).abs() < 1e-12, "{nested} vs {shoelace}");
    }

    /// The hand-written rigid motion this module used before nalgebra: composition, inverse and
    /// application of `Isometry2` give the same bits.
    #[test]
    fn nalgebra_isometries_match_the_former_hand_written_motion_bit_for_bit() {
        #[derive(Clone, Copy)]
        struct Rigid {
            cos: f64,
            sin: f64,
            t: Point,
        }
        impl Rigid {
            fn new(angle: f64, t: Point) -> Self {
                let (sin, cos) = angle.sin_cos();
                Self { cos, sin, t }
            }
            fn apply(&self, p: Point) -> Point {
                Point::new(
                    self.cos * p.x - self.sin * p.y + self.t.x,
                    self.sin * p.x + self.cos * p.y + self.t.y,
                )
            }
            fn after(&self, first: &Self) -> Self {
                Self {
                    cos: self.cos * first.cos - self.sin * first.sin,
                    sin: self.sin * first.cos + self.cos * first.sin,
                    t: self.apply(first.t),
                }
            }
            fn inverse(&self) -> Self {
                let t = Point::new(
                    -(self.cos * self.t.x + self.sin * self.t.y),
                    self.sin * self.t.x - self.cos * self.t.y,
                );
                Self {
                    cos: self.cos,
                    sin: -self.sin,
                    t,
                }
            }
        }
        let bits = |p: Point| [p.x.to_bits(), p.y.to_bits()];
        let mut x = 0.123_456_789_f64;
        let mut next = || {
            x = (x * 9301.0 + 0.49297).fract();
            20.0 * x - 10.0
        };
        for _ in 0..2000 {
            let (a1, a2) = (next(), next());
            let (t1, t2) = (Point::new(next(), next()), Point::new(next(), 0.0));
            let p = Point::new(next(), next());
            let (r1, r2) = (Rigid::new(a1, t1), Rigid::new(a2, t2));
            let i1 = Isometry2::new(Vector2::new(t1.x, t1.y), a1);
            let i2 = Isometry2::new(Vector2::new(t2.x, t2.y), a2);
            assert_eq!(bits(r1.apply(p)), bits(apply(&i1, p)));
            let (rc, ic) = (r2.inverse().after(&r1), i2.inverse() * i1);
            assert_eq!(bits(rc.apply(p)), bits(apply(&ic, p)));
            assert_eq!(bits(r1.inverse().apply(p)), bits(apply(&i1.inverse(), p)));
        }
    }
}
