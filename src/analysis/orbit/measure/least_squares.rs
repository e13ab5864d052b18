//! The least-squares extraction (docs/math/companion.md §A.8, default method): regressors `[1, t, sin ω_k t, cos ω_k t …]`
//! for the planet line(s) and every nuisance line, solved by the blocked (TSQR) Householder QR of
//! `tsqr`, with the condition-number refusal and the covariance `σ̂² (MᵀM)⁻¹`;
//! and its de-rotated variant.

use super::extract::{Extractor, Measurement, Uncertainty};
use super::frame::{detrend, rotate};
use super::record::Record;
use super::tsqr::r_factor;
use crate::analysis::orbit::{C64, Orbit, OrbitError};
use nalgebra::DMatrix;
use std::f64::consts::TAU;

/// The regression columns: the real frequencies fitted as sine/cosine pairs, after the mean (and
/// drift) column(s).
struct Columns {
    /// `(|ω| rad/s, label)`: the planet line(s) first (Z₋ only when its |ω| differs from Z₊'s,
    /// merged with each other only), then every distinct nuisance line except DC.
    freqs: Vec<(f64, String)>,
    /// Signed frequencies of Z₊ and Z₋, rad/s.
    wp: f64,
    wm: f64,
    /// Frequencies closer than this are one column, rad/s.
    tiny: f64,
    /// Columns before the sinusoids: 1 (mean) or 2 (mean, drift).
    n0: usize,
}

impl Columns {
    /// Number of regressors `p`.
    fn count(&self) -> usize {
        self.n0 + 2 * self.freqs.len()
    }

    /// The fitted `|ω_k|`, rad/s.
    fn omegas(&self) -> Vec<f64> {
        self.freqs.iter().map(|f| f.0).collect()
    }

    /// Coefficients → orbit (linear): the x (y) phasor at signed ω from the |ω| sine phasor of
    /// the x (y) coefficients `bx` (`by`), µm.
    fn orbit(&self, omega_p_rad_s: f64, bx: &[f64], by: &[f64]) -> Orbit {
        let n0 = self.n0;
        let coef = |b: &[f64], w: f64| -> C64 {
            let idx = if (w.abs() - self.freqs[0].0).abs() <= self.tiny {
                0
            } else {
                1
            };
            let ph = C64::new(b[n0 + 2 * idx], b[n0 + 2 * idx + 1]) / C64::new(0.0, 2.0);
            if w > 0.0 { ph } else { ph.conj() }
        };
        let i = C64::i();
        Orbit {
            omega_p_rad_s,
            z_plus_um: coef(bx, self.wp) + i * coef(by, self.wp),
            z_minus_um: coef(bx, self.wm) + i * coef(by, self.wm),
        }
    }
}

/// The solved regression: coefficients, residual variances and the unscaled covariance.
struct Solution {
    /// Coefficients of the x and y channels (µm per regressor).
    bx: Vec<f64>,
    by: Vec<f64>,
    /// Residual variances `σ̂²` of x and y, µm² (RSS over `N − p` degrees of freedom).
    s2x: f64,
    s2y: f64,
    /// Residual RMS of x and y over all `N` samples, µm.
    rms: (f64, f64),
    /// `(RᵀR)⁻¹ = (MᵀM)⁻¹` of the regressors.
    cov0: DMatrix<f64>,
}

impl Solution {
    /// Back-substitution from the augmented `R` (`(p+2)²`, the x and y columns last) and the
    /// inverse of its leading `p × p` block, for `n` samples.
    fn from_r(r: &DMatrix<f64>, rinv: &DMatrix<f64>, p: usize, n: usize) -> Self {
        let qx = r.view((0, p), (p, 1)).into_owned();
        let qy = r.view((0, p + 1), (p, 1)).into_owned();
        let bx = rinv * qx;
        let by = rinv * qy;
        let rss_x = r[(p, p)].powi(2);
        let rss_y = r[(p, p + 1)].powi(2) + r[(p + 1, p + 1)].powi(2);
        let dof = (n - p) as f64;
        Solution {
            bx: bx.iter().copied().collect(),
            by: by.iter().copied().collect(),
            s2x: rss_x / dof,
            s2y: rss_y / dof,
            rms: ((rss_x / n as f64).sqrt(), (rss_y / n as f64).sqrt()),
            cov0: rinv * rinv.transpose(),
        }
    }
}

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
        let cols = self.columns();
        let p = cols.count();
        let n = t.len();
        if n <= p + 1 {
            return Err(OrbitError::Record(format!(
                "{n} samples cannot fit {p} regressors"
            )));
        }
        let omegas = cols.omegas();
        let r = augmented_r(t, x, y, cols.n0, &omegas);
        let rp = r.view((0, 0), (p, p)).into_owned();
        let cond = scaled_condition(&rp);
        m.condition_number = Some(cond);
        let collision = |condition: f64| OrbitError::Collision {
            condition,
            limit: self.opts.max_condition,
            detail: closest_pair(&cols.freqs, TAU / m.record_length_s),
        };
        if cond.is_nan() || cond > self.opts.max_condition {
            return Err(collision(cond));
        }
        let rinv = rp
            .clone()
            .try_inverse()
            .ok_or_else(|| collision(f64::INFINITY))?;
        let sol = Solution::from_r(&r, &rinv, p, n);
        m.residual_rms_um = Some(sol.rms);
        let orbit = cols.orbit(self.omega_p_rad_s, &sol.bx, &sol.by);
        m.orbit = orbit;
        let cov = output_covariance(&cols, self.omega_p_rad_s, &sol);
        m.uncertainty = Some(uncertainty(&cov, &orbit));
        Ok(PeriodicFit {
            omegas,
            x: sol.bx[cols.n0..].to_vec(),
            y: sol.by[cols.n0..].to_vec(),
        })
    }

    /// The regression columns of this extractor (see [`Columns`]).
    fn columns(&self) -> Columns {
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
        Columns {
            freqs,
            wp,
            wm,
            tiny,
            n0: if self.opts.drift { 2 } else { 1 },
        }
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

/// The `(p+2) × (p+2)` `R` factor of the regressors `[1, (t − t_m)/t_h (with drift), sin ω_k t,
/// cos ω_k t …]` augmented with the x and y columns; `t_m`, `t_h` are the centre and half-length
/// of the record, s (the drift column is scaled to [−1, 1]).
fn augmented_r(t: &[f64], x: &[f64], y: &[f64], n0: usize, omegas: &[f64]) -> DMatrix<f64> {
    let p = n0 + 2 * omegas.len();
    let n = t.len();
    let (t0, t1) = (t[0], t[n - 1]);
    let (tm, th) = (0.5 * (t0 + t1), 0.5 * (t1 - t0));
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
    r_factor(n, p + 2, &fill)
}

/// Condition number of the column-scaled regressors: the singular values of `R D⁻¹`, `D` the
/// column norms of `R` (∞ when a singular value is zero).
fn scaled_condition(rp: &DMatrix<f64>) -> f64 {
    let p = rp.ncols();
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
    if smin > 0.0 {
        smax / smin
    } else {
        f64::INFINITY
    }
}

/// The outputs whose covariance is propagated: Re/Im of `P_x`, `P_y`, `Z₊`, `Z₋`, µm.
fn orbit_outputs(o: &Orbit) -> [f64; 8] {
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
}

/// Linear error propagation of the coefficient covariance `σ̂² (MᵀM)⁻¹` of each channel to the
/// [`orbit_outputs`] (µm²): `J C Jᵀ` with the (exact, linear) Jacobian of [`Columns::orbit`].
fn output_covariance(cols: &Columns, omega_p_rad_s: f64, sol: &Solution) -> [[f64; 8]; 8] {
    let p = cols.count();
    let zero = vec![0.0; p];
    let mut cov = [[0.0f64; 8]; 8];
    for (chan, s2) in [(0usize, sol.s2x), (1, sol.s2y)] {
        let mut jac = vec![[0.0f64; 8]; p];
        for (c, col) in jac.iter_mut().enumerate() {
            let mut e = zero.clone();
            e[c] = 1.0;
            let o = if chan == 0 {
                cols.orbit(omega_p_rad_s, &e, &zero)
            } else {
                cols.orbit(omega_p_rad_s, &zero, &e)
            };
            *col = orbit_outputs(&o);
        }
        for a in 0..8 {
            for b in 0..8 {
                let mut s = 0.0;
                for c in 0..p {
                    if jac[c][a] == 0.0 {
                        continue;
                    }
                    for d in 0..p {
                        s += jac[c][a] * sol.cov0[(c, d)] * jac[d][b];
                    }
                }
                cov[a][b] += s2 * s;
            }
        }
    }
    cov
}

/// Standard deviations of amplitude (µm) and phase (rad) of the output pair `(re, im)` at index
/// `o` of `cov`; the phase is undefined (∞) at zero amplitude.
fn polar_sigma(cov: &[[f64; 8]; 8], re: f64, im: f64, o: usize) -> (f64, f64) {
    let a = re.hypot(im);
    let (c00, c01, c11) = (cov[o][o], cov[o][o + 1], cov[o + 1][o + 1]);
    if a == 0.0 {
        return (c00.max(c11).max(0.0).sqrt(), f64::INFINITY);
    }
    let va = (re * re * c00 + 2.0 * re * im * c01 + im * im * c11) / (a * a);
    let vp = (im * im * c00 - 2.0 * re * im * c01 + re * re * c11) / (a * a * a * a);
    (va.max(0.0).sqrt(), vp.max(0.0).sqrt())
}

/// The [`Uncertainty`] of `orbit` from the output covariance `cov`.
fn uncertainty(cov: &[[f64; 8]; 8], orbit: &Orbit) -> Uncertainty {
    let out = orbit_outputs(orbit);
    let (sax, spx) = polar_sigma(cov, out[0], out[1], 0);
    let (say, spy) = polar_sigma(cov, out[2], out[3], 2);
    let (szp, _) = polar_sigma(cov, out[4], out[5], 4);
    let (szm, _) = polar_sigma(cov, out[6], out[7], 6);
    Uncertainty {
        a_x_um: sax,
        phi_x_rad: spx,
        a_y_um: say,
        phi_y_rad: spy,
        z_plus_um: szp,
        z_minus_um: szm,
    }
}
