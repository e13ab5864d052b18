//! The grid pass without the grid, when the grid values are two periodic parts: the tabulated
//! leading terms `P` (repeating every `p` points) and one term more `Q` (every `q` points), so
//! that `f_j = P_(j mod p) + Q_(j mod q)`, one rounded addition — the value the full pass
//! computes. The paper's four terms are such a sum (`p` = 168, `q` = 200 of 4 200 points): the
//! best grid value and the candidate intervals come from 368 values instead of 4 200.
//!
//! With `g = gcd(p, q)`, the point `j` pairs `a = j mod p` with `b = j mod q`, `a ≡ b (mod g)`,
//! and every such pair occurs (Chinese remainder theorem), `n/lcm(p, q)` times. Rounding is
//! monotone in each operand, so within a residue class `r` of `g` the largest grid value is the
//! rounded sum of the largest `P` and the largest `Q`, the smallest that of the smallest: the best
//! grid value is exact. A point is a candidate when `|f| + loss` reaches it; `|f| + loss` is
//! the larger of `f + loss` and `−f + loss`, each monotone in `Q`, so a `P_a` whose sums with its
//! class's extreme `Q` miss it has no candidate, and the others are tested pair by pair: the
//! same points as the full pass, their values computed as it does.

use super::gcd;
use super::grid::PeakGrid;

/// The inverse of `x` modulo `m` (`gcd(x, m) = 1`, `m ≥ 1`; 0 for `m = 1`).
fn inverse_mod(x: usize, m: usize) -> usize {
    let (mut r0, mut r1) = (m as i64, (x % m) as i64);
    let (mut t0, mut t1) = (0_i64, 1_i64);
    while r1 != 0 {
        let k = r0 / r1;
        (r0, r1) = (r1, r0 - k * r1);
        (t0, t1) = (t1, t0 - k * t1);
    }
    t0.rem_euclid(m as i64) as usize
}

/// The smallest and largest value of every residue class modulo `g` of `values` (`g` divides
/// its length): `(lo, hi)` with `lo[r] = min_i values[r + i·g]`.
fn class_extremes(values: &[f64], g: usize) -> (Vec<f64>, Vec<f64>) {
    let (mut lo, mut hi) = (values[..g].to_vec(), values[..g].to_vec());
    for chunk in values.chunks_exact(g).skip(1) {
        for ((l, h), &v) in lo.iter_mut().zip(hi.iter_mut()).zip(chunk) {
            *l = if v < *l { v } else { *l };
            *h = if v > *h { v } else { *h };
        }
    }
    (lo, hi)
}

/// `i − 1` and `i + 1` modulo `m`.
fn around(i: usize, m: usize) -> (usize, usize) {
    (
        if i == 0 { m - 1 } else { i - 1 },
        if i + 1 == m { 0 } else { i + 1 },
    )
}

impl PeakGrid {
    /// What [`PeakGrid::grid_pass`] returns — the best grid value and the candidate intervals
    /// (with repeats, in no order) — when the terms are the tabulated leading ones and one more,
    /// writing only the grid values of `f` that the candidates' bounds and refinement read (each
    /// candidate interval's two ends). `None` when the terms are not of that form or a
    /// coefficient is so large that a sum could overflow (the full pass then decides, as before).
    pub(super) fn split_pass(
        &self,
        cs: &[f64],
        sn: &[f64],
        loss: f64,
        f: &mut [f64],
    ) -> Option<(f64, Vec<usize>)> {
        let (lead, p) = self.prefix;
        // Below the cap every sum of the terms (at most 2·terms coefficients times a sine) is
        // finite, so no grid value is infinite or NaN and the extremes are those of the grid.
        let cap = f64::MAX / (4.0 * cs.len() as f64);
        if lead < 2 || cs.len() != lead + 1 || !cs.iter().chain(sn).all(|v| v.abs() <= cap) {
            return None;
        }
        let (n, q) = (f.len(), self.repeat[lead]);
        let pre = self.leading_sums(cs, sn, p);
        let (ck, sk) = (cs[lead], sn[lead]);
        let last: Vec<f64> = self.sin[lead][..q]
            .iter()
            .zip(&self.cos[lead][..q])
            .map(|(s, c)| ck * s + sk * c)
            .collect();
        let g = gcd(p as u128, q as u128) as usize;
        let (plo, phi) = class_extremes(&pre, g);
        let (qlo, qhi) = class_extremes(&last, g);
        // Class r's largest and smallest grid values; the best grid value is the full pass's,
        // which starts from 0.
        let top = |r: usize| phi[r] + qhi[r];
        let bottom = |r: usize| plo[r] + qlo[r];
        let mut gmax = 0.0_f64;
        for r in 0..g {
            let v = top(r).max(-bottom(r));
            if v > gmax {
                gmax = v;
            }
        }
        // j ≡ a (mod p), j ≡ b (mod q): j = a + p·t, t = ((b − a)/g)·(p/g)⁻¹ mod q/g.
        let (pg, qg) = (p / g, q / g);
        let inv = inverse_mod(pg, qg);
        let period = p * qg;
        let mut cand = Vec::new();
        for r in 0..g {
            // A class, then a `P_a`, whose sums with the class's extreme `Q` miss the best
            // value holds no candidate (monotone rounding).
            let reaches = |hi: f64, lo: f64| hi + loss >= gmax || -lo + loss >= gmax;
            if !reaches(top(r), bottom(r)) {
                continue;
            }
            for a in (r..p).step_by(g) {
                let x = pre[a];
                if !reaches(x + qhi[r], x + qlo[r]) {
                    continue;
                }
                for b in (r..q).step_by(g) {
                    let v = x + last[b];
                    if v.abs() + loss < gmax {
                        continue;
                    }
                    let t = (b + q - a % q) % q / g * inv % qg;
                    let ((a0, a1), (b0, b1)) = (around(a, p), around(b, q));
                    for j in (a + p * t..n).step_by(period) {
                        let (before, after) = around(j, n);
                        f[before] = pre[a0] + last[b0];
                        f[j] = v;
                        f[after] = pre[a1] + last[b1];
                        cand.extend([before, j]);
                    }
                }
            }
        }
        Some((gmax, cand))
    }
}

#[cfg(test)]
mod tests {
    use super::super::{PeakGrid, PeakOptions};
    use super::inverse_mod;

    #[test]
    fn inverse_mod_inverts() {
        for m in 1..40 {
            for x in 1..m {
                if super::gcd(x as u128, m as u128) == 1 {
                    assert_eq!(x * inverse_mod(x, m) % m, 1 % m, "{x} mod {m}");
                }
            }
        }
        assert_eq!(inverse_mod(7, 1), 0);
    }

    /// On the paper's four terms (168- and 200-point parts) and on a grid whose parts share
    /// more (`g` = 8): the best grid value, the candidate intervals and their end values equal
    /// the full pass's, bit for bit, over a spread of amplitudes and phases.
    #[test]
    fn split_pass_is_the_full_pass() {
        for (omegas, parts) in [
            (vec![75.0, 525.0, 275.0, 63.0], (3, 168, 200)),
            (vec![8.0, 12.0, 3.0], (2, 24, 32)),
        ] {
            let g = PeakGrid::new(&omegas, PeakOptions::default());
            assert_eq!((g.prefix.0, g.prefix.1, g.repeat[g.prefix.0]), parts);
            let k = omegas.len();
            for s in 0..200_u32 {
                let x = f64::from(s);
                let cs: Vec<f64> = (0..k).map(|i| (x * 0.37 + i as f64).sin() * 20.0).collect();
                let mut sn: Vec<f64> = (0..k).map(|i| (x * 0.91 - i as f64).cos() * 9.0).collect();
                if s % 50 == 0 {
                    // Exact ties in every residue class.
                    sn.fill(0.0);
                }
                let loss = 0.05 + x * 1e-3;
                let mut full = vec![0.0; g.len()];
                let (gm, mut want) = g.grid_pass(&cs, &sn, loss, &mut full);
                let mut part = vec![f64::NAN; g.len()];
                let (gs, mut got) = g.split_pass(&cs, &sn, loss, &mut part).unwrap();
                assert_eq!(gs.to_bits(), gm.to_bits(), "sample {s}");
                for c in [&mut want, &mut got] {
                    c.sort_unstable();
                    c.dedup();
                }
                assert_eq!(got, want, "sample {s}");
                let next = |j: usize| (j + 1) % g.len();
                for &j in &got {
                    assert_eq!(part[j].to_bits(), full[j].to_bits());
                    assert_eq!(part[next(j)].to_bits(), full[next(j)].to_bits());
                }
            }
        }
    }

    /// Not of the form, or a coefficient that could overflow a sum: the full pass decides.
    #[test]
    fn other_term_sets_take_the_full_pass() {
        let g = PeakGrid::new(&[75.0, 525.0, 275.0, 63.0], PeakOptions::default());
        let mut f = vec![0.0; g.len()];
        assert!(g.split_pass(&[1.0; 3], &[1.0; 3], 0.1, &mut f).is_none());
        for big in [f64::INFINITY, f64::NAN, f64::MAX / 8.0] {
            let cs = [1.0, big, 1.0, 1.0];
            assert!(g.split_pass(&cs, &[0.0; 4], 0.1, &mut f).is_none());
        }
        let h = PeakGrid::new(&[63.0, 64.0, 525.0], PeakOptions::default());
        assert!(h.split_pass(&[1.0; 3], &[1.0; 3], 0.1, &mut f).is_none());
    }
}
