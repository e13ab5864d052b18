//! The least-squares extraction (docs/math/companion.md §A.8, default method): regressors `[1, t, sin ω_k t, cos ω_k t …]`
//! for the planet line(s) and every nuisance line, solved by a blocked (TSQR) Householder QR, with
//! the condition-number refusal and the covariance `σ̂² (MᵀM)⁻¹`; and its de-rotated variant.
//!
//! The `N × p` regression matrix is augmented with the x and y columns; the record is cut into a
//! fixed number of blocks (independent of the thread count, so results are bit-identical for any
//! number of threads), each block is reduced to its `R` factor in chunks, and the block factors are
//! stacked and reduced once more.

use super::extract::{Extractor, Measurement, Uncertainty};
use super::frame::{detrend, rotate};
use super::record::Record;
use crate::analysis::orbit::{C64, Orbit, OrbitError};
use nalgebra::DMatrix;
use rayon::prelude::*;
use std::f64::consts::TAU;

/// Number of independent blocks of the TSQR (fixed: results do not depend on the thread count).
const BLOCKS: usize = 64;
/// Rows per chunk inside a block.
const CHUNK: usize = 512;

impl Extractor {
    /// Least-squares fit; fills `m` and returns the fitted periodic part (all sinusoid columns,
    /// without mean and drift) as `(ω_k, x sine/cosine coefficients, y coefficients)`.
    pub(super) fn least_squares(
        &self,
        t: &[f64],
        x: &[f64],
        y: &[f64],
        m: &mut Measurement,
    ) -> Result<PeriodicFit, OrbitError> {
        // Distinct real frequencies (columns): the planet lines first, merged with each other only.
        let (wp, wm) = self.target_omegas();
        let tiny = 1e-12 * (wp.abs().max(wm.abs()));
        let mut freqs: Vec<(f64, String)> = vec![(wp.abs(), "planet Z+".into())];
        if (wm.abs() - wp.abs()).abs() > tiny {
            freqs.push((wm.abs(), "planet Z-".into()));
        }
        let n_target = freqs.len();
        for l in &self.opts.nuisance {
            let w = l.omega_rad_s.abs();
            if w <= tiny {
                continue; // DC is the mean column
            }
            let dup = freqs[n_target..].iter().any(|(f, _)| (f - w).abs() <= tiny);
            if !dup {
                freqs.push((w, l.label.clone()));
            }
        }
        let n0 = if self.opts.drift { 2 } else { 1 };
        let p = n0 + 2 * freqs.len();
        let k = p + 2;
        let n = t.len();
        if n <= p + 1 {
            return Err(OrbitError::Record(format!(
                "{n} samples cannot fit {p} regressors"
            )));
        }
        let (t0, t1) = (t[0], t[n - 1]);
        let (tm, th) = (0.5 * (t0 + t1), 0.5 * (t1 - t0));
        let omegas: Vec<f64> = freqs.iter().map(|f| f.0).collect();
        let fill = |row: &mut [f64], i: usize| {
            row[0] = 1.0;
            if n0 == 2 {
                row[1] = (t[i] - tm) / th;
            }
            for (j, w) in omegas.iter().enumerate() {
                let (s, c) = (w * t[i]).sin_cos();
                row[n0 + 2 * j] = s;
                row[n0 + 2 * j + 1] = c;
            }
            row[p] = x[i];
            row[p + 1] = y[i];
        };
        let blocks = BLOCKS.min(n.div_ceil(CHUNK));
        let bounds: Vec<(usize, usize)> = (0..blocks)
            .map(|b| (b * n / blocks, (b + 1) * n / blocks))
            .collect();
        let rs: Vec<DMatrix<f64>> = bounds
            .par_iter()
            .map(|&(a, b)| block_r(a, b, k, &fill))
            .collect();
        let mut stack = DMatrix::zeros(k * rs.len(), k);
        for (b, r) in rs.iter().enumerate() {
            stack.view_mut((b * k, 0), (r.nrows(), k)).copy_from(r);
        }
        let r = qr_r(stack, k);
        let rp = r.view((0, 0), (p, p)).into_owned();
        // Condition number of the column-scaled matrix (singular values of R D⁻¹).
        let norms: Vec<f64> = (0..p).map(|j| rp.column(j).norm()).collect();
        let scaled = DMatrix::from_fn(p, p, |i, j| {
            if norms[j] > 0.0 {
                rp[(i, j)] / norms[j]
            } else {
                0.0
            }
        });
        let sv = scaled.singular_values();
        let (smax, smin) = (sv.max(), sv.min());
        let cond = if smin > 0.0 {
            smax / smin
        } else {
            f64::INFINITY
        };
        m.condition_number = Some(cond);
        if cond.is_nan() || cond > self.opts.max_condition {
            let detail = closest_pair(&freqs, TAU / m.record_length_s);
            return Err(OrbitError::Collision {
                condition: cond,
                limit: self.opts.max_condition,
                detail,
            });
        }
        let rinv = rp
            .clone()
            .try_inverse()
            .ok_or_else(|| OrbitError::Collision {
                condition: f64::INFINITY,
                limit: self.opts.max_condition,
                detail: closest_pair(&freqs, TAU / m.record_length_s),
            })?;
        let qx = r.view((0, p), (p, 1)).into_owned();
        let qy = r.view((0, p + 1), (p, 1)).into_owned();
        let bx = &rinv * qx;
        let by = &rinv * qy;
        let rss_x = r[(p, p)].powi(2);
        let rss_y = r[(p, p + 1)].powi(2) + r[(p + 1, p + 1)].powi(2);
        let dof = (n - p) as f64;
        let (s2x, s2y) = (rss_x / dof, rss_y / dof);
        m.residual_rms_um = Some(((rss_x / n as f64).sqrt(), (rss_y / n as f64).sqrt()));
        let cov0 = &rinv * rinv.transpose(); // (RᵀR)⁻¹
        // Map coefficients → orbit (linear): x-coefficient at signed ω from the |ω| sine phasor.
        let to_orbit = |bx: &[f64], by: &[f64]| -> Orbit {
            let coef = |b: &[f64], w: f64| -> C64 {
                let idx = if (w.abs() - freqs[0].0).abs() <= tiny {
                    0
                } else {
                    1
                };
                let ph = C64::new(b[n0 + 2 * idx], b[n0 + 2 * idx + 1]) / C64::new(0.0, 2.0);
                if w > 0.0 { ph } else { ph.conj() }
            };
            let i = C64::i();
            Orbit {
                omega_p_rad_s: self.omega_p_rad_s,
                z_plus_um: coef(bx, wp) + i * coef(by, wp),
                z_minus_um: coef(bx, wm) + i * coef(by, wm),
            }
        };
        let (bxs, bys): (Vec<f64>, Vec<f64>) =
            (bx.iter().copied().collect(), by.iter().copied().collect());
        let orbit = to_orbit(&bxs, &bys);
        m.orbit = orbit;
        // Linear error propagation: outputs Re/Im of P_x, P_y, Z₊, Z₋.
        let outputs = |o: &Orbit| -> [f64; 8] {
            let (px, py) = o.sin_phasors();
            [
                px.re,
                px.im,
                py.re,
                py.im,
                o.z_plus_um.re,
                o.z_plus_um.im,
                o.z_minus_um.re,
                o.z_minus_um.im,
            ]
        };
        let zero = vec![0.0; p];
        let mut cov = [[0.0f64; 8]; 8];
        for (chan, s2) in [(0usize, s2x), (1, s2y)] {
            let mut jac = vec![[0.0f64; 8]; p];
            for (c, col) in jac.iter_mut().enumerate() {
                let mut e = zero.clone();
                e[c] = 1.0;
                let o = if chan == 0 {
                    to_orbit(&e, &zero)
                } else {
                    to_orbit(&zero, &e)
                };
                *col = outputs(&o);
            }
            for a in 0..8 {
                for b in 0..8 {
                    let mut s = 0.0;
                    for c in 0..p {
                        if jac[c][a] == 0.0 {
                            continue;
                        }
                        for d in 0..p {
                            s += jac[c][a] * cov0[(c, d)] * jac[d][b];
                        }
                    }
                    cov[a][b] += s2 * s;
                }
            }
        }
        let polar_sigma = |re: f64, im: f64, o: usize| -> (f64, f64) {
            let a = re.hypot(im);
            let (c00, c01, c11) = (cov[o][o], cov[o][o + 1], cov[o + 1][o + 1]);
            if a == 0.0 {
                // Zero amplitude: the phase is undefined.
                return (c00.max(c11).max(0.0).sqrt(), f64::INFINITY);
            }
            let va = (re * re * c00 + 2.0 * re * im * c01 + im * im * c11) / (a * a);
            let vp = (im * im * c00 - 2.0 * re * im * c01 + re * re * c11) / (a * a * a * a);
            (va.max(0.0).sqrt(), vp.max(0.0).sqrt())
        };
        let out = outputs(&orbit);
        let (sax, spx) = polar_sigma(out[0], out[1], 0);
        let (say, spy) = polar_sigma(out[2], out[3], 2);
        let (szp, _) = polar_sigma(out[4], out[5], 4);
        let (szm, _) = polar_sigma(out[6], out[7], 6);
        m.uncertainty = Some(Uncertainty {
            a_x_um: sax,
            phi_x_rad: spx,
            a_y_um: say,
            phi_y_rad: spy,
            z_plus_um: szp,
            z_minus_um: szm,
        });
        Ok(PeriodicFit {
            omegas,
            x: bxs[n0..].to_vec(),
            y: bys[n0..].to_vec(),
        })
    }

    /// Least squares on de-rotated data with the sensor offset and drift removed in the housing
    /// frame (where they live): alternate (i) fit in the carrier frame, (ii) rotate the fitted
    /// periodic part back to the housing frame and fit the mean/drift of the remainder there.
    /// The coupling is weak (≈ 1/number of carrier revolutions), so three passes suffice.
    pub(super) fn least_squares_derotated(
        &self,
        rec: &Record,
        m: &mut Measurement,
    ) -> Result<(), OrbitError> {
        let c = rec.carrier_angle_rad().ok_or_else(|| {
            OrbitError::Record("de-rotation needs a carrier angle column (carrier_deg)".into())
        })?;
        let t = rec.t_s();
        let n = rec.len();
        let (mut xr, mut yr) = (rec.x_um().to_vec(), rec.y_um().to_vec());
        for pass in 0..DEROTATION_PASSES {
            let (xc, yc) = rotate(&xr, &yr, c, -1.0);
            let fit = self.least_squares(t, &xc, &yc, m)?;
            if pass + 1 == DEROTATION_PASSES {
                break;
            }
            let (mut px, mut py) = (vec![0.0; n], vec![0.0; n]);
            for i in 0..n {
                (px[i], py[i]) = fit.eval(t[i]);
            }
            let (hx, hy) = rotate(&px, &py, c, 1.0);
            let rx: Vec<f64> = (0..n).map(|i| rec.x_um()[i] - hx[i]).collect();
            let ry: Vec<f64> = (0..n).map(|i| rec.y_um()[i] - hy[i]).collect();
            let (dx, dy) = detrend(t, &rx, &ry, self.opts.drift);
            // raw − trend, where trend = remainder − detrended remainder
            for i in 0..n {
                xr[i] = rec.x_um()[i] - (rx[i] - dx[i]);
                yr[i] = rec.y_um()[i] - (ry[i] - dy[i]);
            }
        }
        Ok(())
    }
}

/// Passes of the housing-trend / carrier-fit alternation of de-rotated least squares.
const DEROTATION_PASSES: usize = 3;

/// Fitted periodic part `Σ_k a_k sin ω_k t + b_k cos ω_k t` of x and y.
pub(super) struct PeriodicFit {
    omegas: Vec<f64>,
    x: Vec<f64>,
    y: Vec<f64>,
}

impl PeriodicFit {
    fn eval(&self, t: f64) -> (f64, f64) {
        let (mut a, mut b) = (0.0, 0.0);
        for (k, w) in self.omegas.iter().enumerate() {
            let (s, c) = (w * t).sin_cos();
            a += self.x[2 * k] * s + self.x[2 * k + 1] * c;
            b += self.y[2 * k] * s + self.y[2 * k + 1] * c;
        }
        (a, b)
    }
}

/// Closest pair of fitted real frequencies, for the collision message.
fn closest_pair(freqs: &[(f64, String)], bin: f64) -> String {
    let mut best: Option<(f64, usize, usize)> = None;
    for i in 0..freqs.len() {
        for j in 0..i {
            let d = (freqs[i].0 - freqs[j].0).abs();
            if best.is_none_or(|b| d < b.0) {
                best = Some((d, i, j));
            }
        }
    }
    match best {
        Some((d, i, j)) => format!(
            "closest lines `{}` and `{}`, {:.4} bins apart, |f| = {:.6} / {:.6} Hz",
            freqs[i].1,
            freqs[j].1,
            d / bin,
            freqs[i].0 / TAU,
            freqs[j].0 / TAU
        ),
        None => "drift and mean columns".into(),
    }
}

/// Upper-triangular `R` (k×k) of rows `a..b` via chunked Householder QR.
fn block_r(
    a: usize,
    b: usize,
    k: usize,
    fill: &(dyn Fn(&mut [f64], usize) + Sync),
) -> DMatrix<f64> {
    let mut r: Option<DMatrix<f64>> = None;
    let mut row = vec![0.0; k];
    let mut start = a;
    while start < b {
        let end = (start + CHUNK).min(b);
        let top = r.as_ref().map_or(0, DMatrix::nrows);
        let mut s = DMatrix::zeros(top + end - start, k);
        if let Some(r) = &r {
            s.view_mut((0, 0), (top, k)).copy_from(r);
        }
        for i in start..end {
            fill(&mut row, i);
            for (j, v) in row.iter().enumerate() {
                s[(top + i - start, j)] = *v;
            }
        }
        r = Some(qr_r(s, k));
        start = end;
    }
    r.unwrap_or_else(|| DMatrix::zeros(0, k))
}

/// `R` factor of an m×k matrix, padded to k×k when m < k.
fn qr_r(s: DMatrix<f64>, k: usize) -> DMatrix<f64> {
    let r = s.qr().r();
    if r.nrows() == k {
        return r;
    }
    let mut full = DMatrix::zeros(k, k);
    full.view_mut((0, 0), (r.nrows(), k)).copy_from(&r);
    full
}
