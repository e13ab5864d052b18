//! The grid pass of the certified peak, its hot loop: the sum of the terms on every grid point,
//! the largest magnitude, and the intervals whose coarse bound reaches it — compiled for the
//! baseline target and for AVX2, bit-identical (no FMA, the same additions in the same order).

use super::grid::{BLOCK, PeakGrid};

impl PeakGrid {
    /// The grid pass: `f` on every grid point (`f_j = Σ_k cs_k sin(ω_k t_j) + sn_k cos(ω_k t_j)`),
    /// its largest magnitude, and the grid intervals (start index, increasing) with an end point
    /// where `|f| + loss` reaches that maximum. Compiled twice: for the baseline target and, where
    /// the CPU has it, for AVX2 (four lanes instead of two). Neither uses FMA and Rust never
    /// contracts `a * b + c`, so both compute the same roundings in the same order: the values are
    /// bit-identical on every machine.
    pub(super) fn grid_pass(
        &self,
        cs: &[f64],
        sn: &[f64],
        loss: f64,
        f: &mut [f64],
    ) -> (f64, Vec<usize>) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2 (checked just above).
            return unsafe { self.grid_pass_avx2(cs, sn, loss, f) };
        }
        self.grid_pass_body(cs, sn, loss, f)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn grid_pass_avx2(
        &self,
        cs: &[f64],
        sn: &[f64],
        loss: f64,
        f: &mut [f64],
    ) -> (f64, Vec<usize>) {
        self.grid_pass_body(cs, sn, loss, f)
    }

    #[inline(always)]
    fn grid_pass_body(
        &self,
        cs: &[f64],
        sn: &[f64],
        loss: f64,
        f: &mut [f64],
    ) -> (f64, Vec<usize>) {
        let n = f.len();
        let (lead, rep) = self.prefix;
        if lead >= 2 && cs.len() >= lead && cs.len() - lead <= 4 {
            // The leading terms' sum over one repeat (plus a block, for contiguous windows).
            let pre = self.leading_sums(cs, sn, rep + BLOCK);
            match cs.len() - lead {
                0 => self.add_terms::<0>(&pre, lead, cs, sn, f),
                1 => self.add_terms::<1>(&pre, lead, cs, sn, f),
                2 => self.add_terms::<2>(&pre, lead, cs, sn, f),
                3 => self.add_terms::<3>(&pre, lead, cs, sn, f),
                _ => self.add_terms::<4>(&pre, lead, cs, sn, f),
            }
        } else {
            self.sum_all(cs, sn, f);
        }
        Self::max_and_candidates(f, loss, n)
    }

    /// The sum of the leading `self.prefix.0` terms on the first `len` grid points, with the
    /// additions of the full sum in the same order (bit-identical values); it repeats every
    /// `self.prefix.1` points.
    #[inline(always)]
    pub(super) fn leading_sums(&self, cs: &[f64], sn: &[f64], len: usize) -> Vec<f64> {
        let mut pre = vec![0.0; len];
        // Term by term (each term's table index wraps at its repeat, no division), the
        // additions per point in term order as in the full sum.
        for k in 0..self.prefix.0 {
            let (ck, sk, p) = (cs[k], sn[k], self.repeat[k]);
            let (s, c) = (&self.sin[k][..p], &self.cos[k][..p]);
            for chunk in pre.chunks_mut(p) {
                for ((v, s), c) in chunk.iter_mut().zip(s).zip(c) {
                    *v += ck * s + sk * c;
                }
            }
        }
        pre
    }

    /// Every term on every grid point, term after term per point.
    #[inline(always)]
    fn sum_all(&self, cs: &[f64], sn: &[f64], f: &mut [f64]) {
        match cs.len() {
            1 => self.sum_terms::<1>(cs, sn, f),
            2 => self.sum_terms::<2>(cs, sn, f),
            3 => self.sum_terms::<3>(cs, sn, f),
            4 => self.sum_terms::<4>(cs, sn, f),
            5 => self.sum_terms::<5>(cs, sn, f),
            6 => self.sum_terms::<6>(cs, sn, f),
            _ => {
                // Term by term over each block (the same additions in the same order as the
                // fixed-count kernels: bit-identical sums).
                for (b, fb) in f.chunks_mut(BLOCK).enumerate() {
                    for k in 0..cs.len() {
                        let o = b * BLOCK % self.repeat[k];
                        let r = o..o + fb.len();
                        let (s, c) = (&self.sin[k][r.clone()], &self.cos[k][r]);
                        let (ck, sk) = (cs[k], sn[k]);
                        for ((fj, s), c) in fb.iter_mut().zip(s).zip(c) {
                            *fj += ck * s + sk * c;
                        }
                    }
                }
            }
        }
    }

    /// The largest |f| over the grid values `f` (`n` of them) and the intervals whose coarse
    /// bound, `|f| + loss` at an end point, reaches it.
    #[inline(always)]
    fn max_and_candidates(f: &[f64], loss: f64, n: usize) -> (f64, Vec<usize>) {
        // The largest |f| of every block of 16 points (four independent lanes, so that the
        // maximum vectorises; the same value as a serial fold, the grid values being finite),
        // then the best grid value.
        const BLK: usize = 16;
        // Plain loops, no closures: a closure would be compiled apart from the AVX2 caller.
        let mut bmax = Vec::with_capacity(n.div_ceil(BLK));
        for fb in f.chunks(BLK) {
            let mut lanes = [0.0_f64; 4];
            let mut quads = fb.chunks_exact(4);
            for q in &mut quads {
                for i in 0..4 {
                    let a = q[i].abs();
                    lanes[i] = if a > lanes[i] { a } else { lanes[i] };
                }
            }
            let mut m = lanes[0].max(lanes[1]).max(lanes[2].max(lanes[3]));
            for v in quads.remainder() {
                m = m.max(v.abs());
            }
            bmax.push(m);
        }
        let gmax = bmax.iter().copied().fold(0.0_f64, f64::max);
        // Intervals whose coarse bound reaches the best grid value: `max(|f_j|, |f_j+1|) + loss
        // ≥ gmax` holds exactly when an end point has `|f| + loss ≥ gmax` (rounded addition is
        // monotone), so find those few points (only in blocks whose largest value qualifies) and
        // take the intervals on both sides, in increasing order.
        let mut cand: Vec<usize> = Vec::new();
        for (b, fb) in f.chunks(BLK).enumerate() {
            if bmax[b] + loss >= gmax {
                for (i, v) in fb.iter().enumerate() {
                    if v.abs() + loss >= gmax {
                        let p = b * BLK + i;
                        cand.extend([if p == 0 { n - 1 } else { p - 1 }, p]);
                    }
                }
            }
        }
        (gmax, cand)
    }

    /// `f_j = pre_j + t_(lead)j + … + t_(lead+R−1)j`, in that order, `pre` holding the sum of the
    /// first `lead` terms over one repeat of it (`self.prefix.1` points) plus a block.
    #[inline(always)]
    fn add_terms<const R: usize>(
        &self,
        pre: &[f64],
        lead: usize,
        cs: &[f64],
        sn: &[f64],
        f: &mut [f64],
    ) {
        let rep = self.prefix.1;
        let ck: [f64; R] = std::array::from_fn(|k| cs[lead + k]);
        let sk: [f64; R] = std::array::from_fn(|k| sn[lead + k]);
        for (b, fb) in f.chunks_mut(BLOCK).enumerate() {
            let len = fb.len();
            let o = b * BLOCK % rep;
            let p = &pre[o..o + len];
            let oo: [usize; R] = std::array::from_fn(|k| b * BLOCK % self.repeat[lead + k]);
            let s: [&[f64]; R] = std::array::from_fn(|k| &self.sin[lead + k][oo[k]..oo[k] + len]);
            let c: [&[f64]; R] = std::array::from_fn(|k| &self.cos[lead + k][oo[k]..oo[k] + len]);
            for (j, fj) in fb.iter_mut().enumerate() {
                let mut acc = p[j];
                for k in 0..R {
                    acc += ck[k] * s[k][j] + sk[k] * c[k][j];
                }
                *fj = acc;
            }
        }
    }

    /// `f_j = (…((0 + t_0j) + t_1j) + …) + t_(K−1)j` with `t_kj = cs_k sin(ω_k t_j) + sn_k cos(ω_k t_j)`,
    /// the terms summed in a register per grid point (one store per point instead of one load
    /// and store per term): the same additions in the same order as the blocked loop.
    #[inline(always)]
    fn sum_terms<const K: usize>(&self, cs: &[f64], sn: &[f64], f: &mut [f64]) {
        let ck: [f64; K] = std::array::from_fn(|k| cs[k]);
        let sk: [f64; K] = std::array::from_fn(|k| sn[k]);
        for (b, fb) in f.chunks_mut(BLOCK).enumerate() {
            let len = fb.len();
            let o: [usize; K] = std::array::from_fn(|k| b * BLOCK % self.repeat[k]);
            let s: [&[f64]; K] = std::array::from_fn(|k| &self.sin[k][o[k]..o[k] + len]);
            let c: [&[f64]; K] = std::array::from_fn(|k| &self.cos[k][o[k]..o[k] + len]);
            for (j, fj) in fb.iter_mut().enumerate() {
                let mut acc = 0.0;
                for k in 0..K {
                    acc += ck[k] * s[k][j] + sk[k] * c[k][j];
                }
                *fj = acc;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::{PeakGrid, PeakOptions};

    /// The paper's four terms: the first three repeat every 168 of the 4 200 grid points, so
    /// their sum is tabulated once; the grid values are the full sums, bit for bit.
    #[test]
    fn tabulated_leading_terms_give_the_full_sums_bit_for_bit() {
        let g = PeakGrid::new(&[75.0, 525.0, 275.0, 63.0], PeakOptions::default());
        assert_eq!((g.len(), g.prefix), (4200, (3, 168)));
        let (cs, sn) = ([-0.7, -12.2, 3.1, -20.5], [0.01, -4.4, -8.7, 14.9]);
        let mut with = vec![0.0; g.len()];
        let (gmax, cand) = g.grid_pass(&cs, &sn, 1e-3, &mut with);
        let mut full = vec![0.0; g.len()];
        g.sum_all(&cs, &sn, &mut full);
        assert!(
            with.iter()
                .zip(&full)
                .all(|(a, b)| a.to_bits() == b.to_bits())
        );
        let want = full.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        assert_eq!(gmax.to_bits(), want.to_bits());
        assert!(!cand.is_empty() && cand.iter().all(|&j| j < g.len()));
        // A term order whose leading terms repeat only over the whole grid: no table.
        let h = PeakGrid::new(&[63.0, 64.0, 525.0], PeakOptions::default());
        assert_eq!(h.prefix, (0, 0));
    }
}
