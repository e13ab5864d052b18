//! Exact point-in-polygon for gear outlines that are not star-shaped about their centre
//! (teeth that lean under a large pressure-angle deviation overhang the root): the even–odd
//! crossing rule on a horizontal ray, with the edges indexed by horizontal bands.

use crate::math::Point;
/// Edges of a closed polyline bucketed by horizontal bands of height `band_mm`.
#[derive(Debug, Clone)]
pub(crate) struct Bands {
    pts: Vec<Point>,
    y0: f64,
    h: f64,
    /// Band `k`'s edges are `edges[first[k]..first[k + 1]]`, in outline order.
    first: Vec<u32>,
    edges: Vec<u32>,
}

impl Bands {
    /// Indexes the edges of the closed polyline `points_mm` (no duplicated end vertex).
    pub(crate) fn new(points_mm: &[Point], band_mm: f64) -> Self {
        let n = points_mm.len();
        let (lo, hi) = points_mm
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
                (l.min(p.y), h.max(p.y))
            });
        let h = band_mm.max((hi - lo) / 1.0e5).max(f64::MIN_POSITIVE);
        let count = (((hi - lo) / h).floor() as usize + 1).max(1);
        let index = |y: f64| (((y - lo) / h).floor().max(0.0) as usize).min(count - 1);
        let span = |i: usize| {
            let (a, b) = (points_mm[i], points_mm[(i + 1) % n]);
            index(a.y.min(b.y))..=index(a.y.max(b.y))
        };
        // Counted, then filled: one flat array of edge indices instead of a vector per band.
        let mut first = vec![0u32; count + 1];
        for i in 0..n {
            for k in span(i) {
                first[k + 1] += 1;
            }
        }
        for k in 0..count {
            first[k + 1] += first[k];
        }
        let mut fill = first.clone();
        let mut edges = vec![0u32; first[count] as usize];
        for i in 0..n {
            for k in span(i) {
                edges[fill[k] as usize] = i as u32;
                fill[k] += 1;
            }
        }
        Self {
            pts: points_mm.to_vec(),
            y0: lo,
            h,
            first,
            edges,
        }
    }

    /// Whether `x` lies inside the polygon (even–odd rule; boundary points either way).
    pub(crate) fn contains(&self, x: Point) -> bool {
        let k = (x.y - self.y0) / self.h;
        let count = self.first.len() - 1;
        if !(k >= 0.0) || k as usize >= count {
            return false;
        }
        let k = k as usize;
        let n = self.pts.len();
        let mut inside = false;
        for &i in &self.edges[self.first[k] as usize..self.first[k + 1] as usize] {
            let (a, b) = (self.pts[i as usize], self.pts[(i as usize + 1) % n]);
            if (a.y > x.y) != (b.y > x.y) {
                let xc = a.x + (x.y - a.y) * (b.x - a.x) / (b.y - a.y);
                if xc > x.x {
                    inside = !inside;
                }
            }
        }
        inside
    }
}

#[cfg(test)]
mod tests {
    use super::Bands;
    use crate::math::Point;

    /// A star-shaped test would call the pocket under the overhang "inside"; the crossing rule
    /// does not.
    #[test]
    fn overhanging_tooth_pocket_is_outside() {
        // A square with a hook: the notch between x = 1..3, y = 1..2 is outside.
        let poly = [
            Point::new(0.0, 0.0),
            Point::new(4.0, 0.0),
            Point::new(4.0, 3.0),
            Point::new(1.0, 3.0),
            Point::new(1.0, 2.0),
            Point::new(3.0, 2.0),
            Point::new(3.0, 1.0),
            Point::new(0.0, 1.0),
        ];
        let b = Bands::new(&poly, 0.3);
        assert!(b.contains(Point::new(0.5, 0.5)));
        assert!(b.contains(Point::new(3.5, 2.5)));
        assert!(b.contains(Point::new(2.0, 2.5)));
        assert!(!b.contains(Point::new(2.0, 1.5)), "the pocket");
        assert!(!b.contains(Point::new(0.5, 1.5)));
        assert!(!b.contains(Point::new(5.0, 0.5)));
        assert!(!b.contains(Point::new(2.0, -1.0)));
    }
}
