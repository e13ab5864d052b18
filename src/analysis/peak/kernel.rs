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
