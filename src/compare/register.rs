//! Robust registration of a track to the design path: a similarity and the timing, fitted by
//! Levenberg–Marquardt with iteratively reweighted (Huber) least squares and trimming.
//!
//! Model (mm, rad, s): frame `i` at time `t_i`, track point `u_i` (mirrored when asked, y flipped
//! from image coordinates, relative to the track's centroid or to the carrier axis as filmed)
//! lands at `q_i = s·R(θ)·u_i + t` and should be the design tip at its carrier angle,
//! `φ_i = φ₀ + ω·(t_i − t_m) + Σ_{k=2}^{D} c_k·τ_i^k`, `τ_i = (t_i − t_m)/t_h` (`t_m`, `t_h`:
//! the record's mid time and half span): residual `r_i = q_i − B(φ_i)`. The unknowns are θ,
//! `t` (fixed to the carrier axis O with a datum), `ln s` (with `--fit-scale`), φ₀, ω and the drift
//! `c_2…c_D`. Jacobian: `∂r/∂θ = (q_i − t)^⊥`, `∂r/∂t = I`, `∂r/∂ln s = q_i − t`,
//! `∂r/∂φ₀ = −B′(φ_i)`, `∂r/∂ω = −B′·(t_i − t_m)`, `∂r/∂c_k = −B′·τ_i^k`.
//!
//! With an encoder column the timing is measured: `φ_i = φ₀ + e_i` (`e_i` the encoder's carrier
//! angle from the mid frame's, in the design's sense), and φ₀ the only timing unknown.
//!
//! Robustness: each iteration fits the smooth deviation `d(φ)` (a Fourier series of order K,
//! [`super::smooth`]) to the residuals and scores each frame by `e_i = |r_i − d(φ_i)|`, its
//! departure from its neighbours in carrier angle. With `σ = median(e)/√(2 ln 2)` (the
//! median of a Rayleigh distance of per-axis deviation σ), frames with `e_i > k_out·σ` are
//! outliers (weight 0) and the others get Huber's weight `min(1, k_H·σ/e_i)`. Standard errors:
//! `√diag((JᵀWJ)⁻¹)·σ̂`, `σ̂² = Σ w_i|r_i|² / (2·n_w − P)`.

use super::design_path::DesignPath;
use super::initial::Start;
use super::smooth::Fourier;
use crate::math::Point;
use nalgebra::{DMatrix, DVector};

/// Options of the fit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitOptions {
    /// Fit the scale.
    pub fit_scale: bool,
    /// The carrier axis pins the translation (the track is relative to it).
    pub datum: bool,
    /// The rotation is given (a level line in the image), not fitted.
    pub fixed_rotation: bool,
    /// Highest power D of the timing drift (1: constant speed).
    pub drift_order: usize,
    /// Order K of the smooth deviation that scores the frames.
    pub smooth_order: usize,
    /// Huber threshold k_H, in σ.
    pub huber_k: f64,
    /// Outlier threshold k_out, in σ.
    pub outlier_k: f64,
}

/// The fitted registration.
#[derive(Debug, Clone, PartialEq)]
pub struct Fit {
    /// Parameter names, in the order of `values` and `standard_errors`.
    pub names: Vec<&'static str>,
    /// Parameter values (rad, mm, ln of mm per unit, rad, rad/s, rad).
    pub values: Vec<f64>,
    /// Their standard errors.
    pub standard_errors: Vec<f64>,
    /// Carrier angle of each frame, rad.
    pub phi_rad: Vec<f64>,
    /// Registered track points q_i, mm.
    pub q_mm: Vec<Point>,
    /// Residuals r_i = q_i − B(φ_i), mm.
    pub residual_mm: Vec<Point>,
    /// Outlier flags.
    pub outlier: Vec<bool>,
    /// Per-axis noise σ of the frames about the smooth deviation, mm.
    pub sigma_mm: f64,
    /// Iterations taken.
    pub iterations: usize,
    /// Whether the step fell below 1e-10 (relative) before the iteration limit.
    pub converged: bool,
}

struct Model<'a> {
    path: &'a DesignPath,
    u: &'a [Point],
    dt: &'a [f64],
    encoder: Option<&'a [f64]>,
    half: f64,
    opts: FitOptions,
    scale0: f64,
}

impl Model<'_> {
    fn names(&self) -> Vec<&'static str> {
        let mut n = vec![];
        if !self.opts.fixed_rotation {
            n.push("rotation_rad");
        }
        if !self.opts.datum {
            n.extend(["translation_x_mm", "translation_y_mm"]);
        }
        if self.opts.fit_scale {
            n.push("ln_scale");
        }
        n.push("phase_rad");
        if self.encoder.is_some() {
            return n;
        }
        n.push("omega_rad_s");
        const DRIFT: [&str; 5] = [
            "drift_2_rad",
            "drift_3_rad",
            "drift_4_rad",
            "drift_5_rad",
            "drift_6_rad",
        ];
        n.extend(&DRIFT[..self.opts.drift_order.saturating_sub(1).min(5)]);
        n
    }

    /// `(θ, t, s, φ₀, ω, drift)` of a parameter vector.
    fn unpack<'b>(&self, b: &'b [f64], start: &Start) -> (f64, Point, f64, f64, f64, &'b [f64]) {
        let mut k = 0;
        let theta = if self.opts.fixed_rotation {
            start.rotation_rad
        } else {
            k += 1;
            b[0]
        };
        let t = if self.opts.datum {
            start.translation_mm
        } else {
            k += 2;
            Point::new(b[k - 2], b[k - 1])
        };
        let s = if self.opts.fit_scale {
            k += 1;
            self.scale0 * b[k - 1].exp()
        } else {
            self.scale0
        };
        if self.encoder.is_some() {
            return (theta, t, s, b[k], 0.0, &[]);
        }
        (theta, t, s, b[k], b[k + 1], &b[k + 2..])
    }

    fn phi(&self, i: usize, phase: f64, omega: f64, drift: &[f64]) -> f64 {
        if let Some(e) = self.encoder {
            return phase + e[i];
        }
        let tau = self.dt[i] / self.half;
        let mut p = phase + omega * self.dt[i];
        let mut tk = tau;
        for c in drift {
            tk *= tau;
            p += c * tk;
        }
        p
    }

    /// Residuals, and the Jacobian's rows when `jac` is given (2 rows per frame).
    fn eval(
        &self,
        b: &[f64],
        start: &Start,
        mut jac: Option<&mut Vec<[f64; 16]>>,
    ) -> (Vec<Point>, Vec<f64>, Vec<Point>) {
        let (theta, t, s, phase, omega, drift) = self.unpack(b, start);
        let (sn, cs) = theta.sin_cos();
        let n = self.u.len();
        let (mut r, mut phis, mut qs) = (
            Vec::with_capacity(n),
            Vec::with_capacity(n),
            Vec::with_capacity(n),
        );
        if let Some(j) = jac.as_deref_mut() {
            j.clear();
        }
        for i in 0..n {
            let q = self.u[i].rotate_sc(sn, cs) * s + t;
            let phi = self.phi(i, phase, omega, drift);
            let (bp, db) = self.path.tip(phi);
            r.push(q - bp);
            phis.push(phi);
            qs.push(q);
            if let Some(j) = jac.as_deref_mut() {
                let rel = q - t;
                let mut cols: Vec<Point> = Vec::with_capacity(16);
                if !self.opts.fixed_rotation {
                    cols.push(rel.perp());
                }
                if !self.opts.datum {
                    cols.extend([Point::new(1.0, 0.0), Point::new(0.0, 1.0)]);
                }
                if self.opts.fit_scale {
                    cols.push(rel);
                }
                let tau = self.dt[i] / self.half;
                cols.push(-db);
                if self.encoder.is_none() {
                    cols.push(-db * self.dt[i]);
                }
                let mut tk = tau;
                for _ in drift {
                    tk *= tau;
                    cols.push(-db * tk);
                }
                let (mut jx, mut jy) = ([0.0; 16], [0.0; 16]);
                for (k, c) in cols.iter().enumerate() {
                    jx[k] = c.x;
                    jy[k] = c.y;
                }
                j.push(jx);
                j.push(jy);
            }
        }
        (r, phis, qs)
    }
}

/// Robust weights and outlier flags of the residuals `r` at carrier angles `phi`, and σ (mm).
fn weights(
    r: &[Point],
    phi: &[f64],
    prev: &[f64],
    opts: &FitOptions,
) -> (Vec<f64>, Vec<bool>, f64) {
    let comps = vec![
        r.iter().map(|p| p.x).collect(),
        r.iter().map(|p| p.y).collect::<Vec<_>>(),
    ];
    let smooth = Fourier::fit(phi, &comps, prev, opts.smooth_order);
    let e: Vec<f64> = r
        .iter()
        .zip(phi)
        .map(|(p, f)| match &smooth {
            Some(s) => (*p - Point::new(s[0].value(*f), s[1].value(*f))).norm(),
            None => p.norm(),
        })
        .collect();
    let mut sorted: Vec<f64> = e
        .iter()
        .zip(prev)
        .filter(|(_, w)| **w > 0.0)
        .map(|(e, _)| *e)
        .collect();
    if sorted.is_empty() {
        sorted = e.clone();
    }
    sorted.sort_by(f64::total_cmp);
    let sigma = (sorted[sorted.len() / 2] / (2.0 * std::f64::consts::LN_2).sqrt()).max(1e-9);
    let out: Vec<bool> = e.iter().map(|&e| e > opts.outlier_k * sigma).collect();
    let w = e
        .iter()
        .zip(&out)
        .map(|(&e, &o)| {
            if o {
                0.0
            } else {
                (opts.huber_k * sigma / e).min(1.0)
            }
        })
        .collect();
    (w, out, sigma)
}

/// Fits the registration of track points `u` at times `dt_s = t − t_m` (half span `half_s`)
/// from `start`. With `encoder` (the carrier angle of each frame from the mid frame's, rad, in
/// the design's sense) the timing is `φ_i = φ₀ + encoder_i`: only φ₀ is fitted.
#[must_use]
pub fn fit(
    path: &DesignPath,
    u: &[Point],
    dt_s: &[f64],
    half_s: f64,
    start: &Start,
    opts: FitOptions,
    encoder: Option<&[f64]>,
) -> Fit {
    let m = Model {
        path,
        u,
        dt: dt_s,
        encoder,
        half: half_s,
        opts,
        scale0: start.scale,
    };
    let names = m.names();
    let np = names.len();
    let mut b = vec![0.0; np];
    let mut k = 0;
    if !opts.fixed_rotation {
        b[0] = start.rotation_rad;
        k = 1;
    }
    if !opts.datum {
        b[k] = start.translation_mm.x;
        b[k + 1] = start.translation_mm.y;
        k += 2;
    }
    if opts.fit_scale {
        k += 1;
    }
    b[k] = start.phase_rad;
    if encoder.is_none() {
        b[k + 1] = start.omega_rad_s;
    }
    let n = u.len();
    let mut w = vec![1.0; n];
    let mut jac = Vec::with_capacity(2 * n);
    let mut mu = 1e-3;
    let (mut iterations, mut converged) = (0, false);
    let cost = |r: &[Point], w: &[f64]| {
        r.iter()
            .zip(w)
            .map(|(p, w)| w * p.norm_squared())
            .sum::<f64>()
    };
    for it in 0..200 {
        iterations = it + 1;
        let (r, phi, _) = m.eval(&b, start, Some(&mut jac));
        // Plain least squares for the first steps (the start may be far), then robust.
        if it >= 3 {
            w = weights(&r, &phi, &w, &opts).0;
        }
        let (jtj, jtr) = normal(&jac, &r, &w, np);
        let c0 = cost(&r, &w);
        let mut accepted = false;
        for _ in 0..12 {
            let mut a = jtj.clone();
            for d in 0..np {
                a[(d, d)] += mu * jtj[(d, d)].max(1e-12);
            }
            let Some(step) = a.cholesky().map(|c| c.solve(&(-&jtr))) else {
                mu *= 10.0;
                continue;
            };
            let nb: Vec<f64> = b.iter().zip(step.iter()).map(|(x, d)| x + d).collect();
            let (r1, _, _) = m.eval(&nb, start, None);
            if cost(&r1, &w) <= c0 {
                let rel = step
                    .iter()
                    .zip(&b)
                    .map(|(d, x)| d.abs() / (1.0 + x.abs()))
                    .fold(0.0, f64::max);
                b = nb;
                mu = (mu / 3.0).max(1e-12);
                accepted = true;
                converged = rel < 1e-10;
                break;
            }
            mu *= 4.0;
        }
        if (!accepted || converged) && it >= 6 {
            converged = true;
            break;
        }
    }
    let (r, phi, q) = m.eval(&b, start, Some(&mut jac));
    let (w, outlier, sigma) = weights(&r, &phi, &w, &opts);
    let (jtj, _) = normal(&jac, &r, &w, np);
    let used = w.iter().filter(|w| **w > 0.0).count();
    let dof = (2 * used).saturating_sub(np).max(1) as f64;
    let s2 = cost(&r, &w) / dof;
    let standard_errors = match jtj.try_inverse() {
        Some(c) => (0..np).map(|d| (c[(d, d)] * s2).max(0.0).sqrt()).collect(),
        None => vec![f64::NAN; np],
    };
    Fit {
        names,
        values: b,
        standard_errors,
        phi_rad: phi,
        q_mm: q,
        residual_mm: r,
        outlier,
        sigma_mm: sigma,
        iterations,
        converged,
    }
}

/// `JᵀWJ`, `JᵀWr` of the weighted rows.
fn normal(jac: &[[f64; 16]], r: &[Point], w: &[f64], np: usize) -> (DMatrix<f64>, DVector<f64>) {
    let mut jtj = DMatrix::<f64>::zeros(np, np);
    let mut jtr = DVector::<f64>::zeros(np);
    for (i, (p, &wi)) in r.iter().zip(w).enumerate() {
        if wi <= 0.0 {
            continue;
        }
        for (row, ri) in [(&jac[2 * i], p.x), (&jac[2 * i + 1], p.y)] {
            for a in 0..np {
                let wa = wi * row[a];
                jtr[a] += wa * ri;
                for bb in a..np {
                    jtj[(a, bb)] += wa * row[bb];
                }
            }
        }
    }
    for a in 0..np {
        for bb in 0..a {
            jtj[(a, bb)] = jtj[(bb, a)];
        }
    }
    (jtj, jtr)
}
