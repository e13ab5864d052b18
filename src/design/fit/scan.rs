//! The nearest local minima of the distance from a point to the samples of a closed curve: where
//! a point's projection on the traced curve starts ([`super::curve::initial_projections_on`]).
//!
//! Every point of a fit is scanned against every sample (360 points × 4096 samples, several
//! times per fit: the hot loop of a warm re-design). The scan takes the samples in blocks of
//! [`BLOCK`]: a block's distances are computed into a buffer in one pass with no branch (the
//! compiler vectorizes it), then one more branch-free pass tells whether the block holds a
//! sample that is a local minimum and closer than the worst kept so far; only such a block is
//! walked sample by sample, in order, as the plain scan walks it. The result is exactly the plain
//! scan's: the same distances, computed by the same operations, and the same samples taken in
//! the same order (a block with no such sample would change nothing).

use crate::math::Point;

/// Samples per block.
const BLOCK: usize = 64;

/// The samples of a closed curve (the last joins the first), their abscissae and ordinates apart
/// (mm) so that a block's distances are one vector loop.
pub(super) struct Samples {
    xs: Vec<f64>,
    ys: Vec<f64>,
}

impl Samples {
    /// The samples `tips` in curve order (at least one).
    pub(super) fn new(tips: &[Point]) -> Self {
        Self {
            xs: tips.iter().map(|q| q.x).collect(),
            ys: tips.iter().map(|q| q.y).collect(),
        }
    }

    /// The `N` smallest local minima of the squared distance (mm²) from `p` to the samples
    /// (sample `k` is one when it is not farther than either neighbour), in increasing distance
    /// (ties in sample order), as `(squared distance, sample index)`; unused slots are
    /// `(∞, usize::MAX)`.
    pub(super) fn nearest_minima<const N: usize>(&self, p: Point) -> [(f64, usize); N] {
        let (xs, ys) = (&self.xs, &self.ys);
        let n = xs.len();
        let d = |k: usize| (xs[k] - p.x).powi(2) + (ys[k] - p.y).powi(2);
        let mut minima = [(f64::INFINITY, usize::MAX); N];
        // buf[0] is the sample before the block, buf[1..=len] the block, buf[len + 1] the one after.
        let mut buf = [0.0; BLOCK + 2];
        for k0 in (0..n).step_by(BLOCK) {
            let len = BLOCK.min(n - k0);
            buf[0] = d((k0 + n - 1) % n);
            for ((b, x), y) in buf[1..=len]
                .iter_mut()
                .zip(&xs[k0..k0 + len])
                .zip(&ys[k0..k0 + len])
            {
                *b = (x - p.x).powi(2) + (y - p.y).powi(2);
            }
            buf[len + 1] = d((k0 + len) % n);
            if !has_candidate(&buf[..len + 2], minima[N - 1].0) {
                continue;
            }
            for j in 1..=len {
                let (prev, cur, next) = (buf[j - 1], buf[j], buf[j + 1]);
                if cur <= prev && cur <= next && cur < minima[N - 1].0 {
                    let at = minima.iter().position(|m| cur < m.0).unwrap_or(N - 1);
                    minima.copy_within(at..N - 1, at + 1);
                    minima[at] = (cur, k0 + j - 1);
                }
            }
        }
        minima
    }
}

/// Whether an inner value of `buf` is not above either neighbour and below `worst` (branch-free,
/// so that it vectorizes).
#[inline]
fn has_candidate(buf: &[f64], worst: f64) -> bool {
    let inner = &buf[1..buf.len() - 1];
    let before = &buf[..buf.len() - 2];
    let after = &buf[2..];
    let mut any = 0u8;
    for ((c, b), n) in inner.iter().zip(before).zip(after) {
        any |= u8::from(*c <= *b) & u8::from(*c <= *n) & u8::from(*c < worst);
    }
    any != 0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The plain scan over every sample, the reference.
    fn plain<const N: usize>(tips: &[Point], p: Point) -> [(f64, usize); N] {
        let n = tips.len();
        let d = |k: usize| (tips[k % n].x - p.x).powi(2) + (tips[k % n].y - p.y).powi(2);
        let mut minima = [(f64::INFINITY, usize::MAX); N];
        let (mut prev, mut cur) = (d(n - 1), d(0));
        for k in 0..n {
            let next = d(k + 1);
            if cur <= prev && cur <= next && cur < minima[N - 1].0 {
                let at = minima.iter().position(|m| cur < m.0).unwrap_or(N - 1);
                minima.copy_within(at..N - 1, at + 1);
                minima[at] = (cur, k);
            }
            (prev, cur) = (cur, next);
        }
        minima
    }

    #[test]
    fn equals_the_plain_scan_bit_for_bit() {
        // A looped, lobed curve (several local minima per point) at sizes that are and are not
        // whole blocks, and points inside, outside and on it.
        for n in [1, 5, 64, 100, 4096, 4097] {
            let tips: Vec<Point> = (0..n)
                .map(|k| {
                    let t = std::f64::consts::TAU * k as f64 / n as f64;
                    let r = 100.0 + 30.0 * (3.0 * t).sin();
                    Point::new(r * t.cos() + 20.0 * (2.0 * t).cos(), r * t.sin())
                })
                .collect();
            let s = Samples::new(&tips);
            for j in 0..200 {
                let a = 0.37 * j as f64;
                let p = Point::new(160.0 * (a * 0.61).cos(), 150.0 * a.sin());
                let got = s.nearest_minima::<3>(p);
                let want = plain::<3>(&tips, p);
                for (g, w) in got.iter().zip(&want) {
                    assert_eq!(
                        (g.0.to_bits(), g.1),
                        (w.0.to_bits(), w.1),
                        "n = {n}, p = {p:?}"
                    );
                }
            }
            // A point on a sample: that sample, at distance 0, first.
            let on = s.nearest_minima::<3>(tips[n / 2]);
            assert_eq!(on[0], (0.0, n / 2));
        }
    }
}
