//! Spectral estimators of the planet-frequency components: DTFT with or without a Hann window,
//! synchronous averaging (nominal speed or tach pulses) and the full (complex) spectrum of
//! `z = x + i y`.

use super::record::Record;
use crate::analysis::orbit::{C64, OrbitError};
use std::f64::consts::TAU;

/// `Σ w_n z_n e^{−iωt_n} / Σ w_n` (rectangular window when `w` is `None`).
pub(super) fn dtft(t: &[f64], z: &[C64], omega: f64, w: Option<&[f64]>) -> C64 {
    let mut acc = C64::new(0.0, 0.0);
    let mut ws = 0.0;
    for (k, (tk, zk)) in t.iter().zip(z).enumerate() {
        let wk = w.map_or(1.0, |w| w[k]);
        acc += zk * C64::from_polar(wk, -omega * tk);
        ws += wk;
    }
    acc / ws
}

/// Symmetric Hann window `w_k = ½ − ½ cos(2πk/(n−1))`, `n ≥ 2`.
fn hann(n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| 0.5 - 0.5 * (TAU * k as f64 / (n - 1) as f64).cos())
        .collect()
}

/// Unnormalised FFT of the Hann-windowed `x + iy`, and the window sum `Σ w_k`.
pub(super) fn hann_fft(x: &[f64], y: &[f64]) -> (Vec<rustfft::num_complex::Complex<f64>>, f64) {
    let n = x.len().min(y.len());
    let w = hann(n);
    let mut buf: Vec<rustfft::num_complex::Complex<f64>> = (0..n)
        .map(|k| rustfft::num_complex::Complex::new(x[k] * w[k], y[k] * w[k]))
        .collect();
    rustfft::FftPlanner::new()
        .plan_fft_forward(n)
        .process(&mut buf);
    (buf, w.iter().sum())
}

/// Hann-window DTFT at ω (coefficient estimate of `e^{iωt}`).
pub(super) fn hann_dtft(t: &[f64], z: &[C64], omega: f64) -> C64 {
    dtft(t, z, omega, Some(&hann(t.len())))
}

/// Synchronous average: cubic (4-point Lagrange) resampling of z at M points per planet revolution
/// over the largest whole number K of revolutions, then the DFT bin at ±ω_p.
pub(super) fn synchronous(rec: &Record, z: &[C64], omega_p: f64) -> Result<(C64, C64), OrbitError> {
    let t = rec.t_s();
    let n = t.len();
    let period = TAU / omega_p.abs();
    let span = t[n - 1] - t[0];
    let revs = (span / period).floor() as usize;
    if revs == 0 {
        return Err(OrbitError::Record(
            "synchronous resampling needs at least one whole planet revolution".into(),
        ));
    }
    let dt = rec.mean_step_s();
    let per_rev = ((period / dt).floor() as usize).max(8);
    let total = revs * per_rev;
    let h = period / per_rev as f64;
    let interp = |tt: f64| cubic_at(t[0], dt, z, tt);
    let (mut zp, mut zm) = (C64::new(0.0, 0.0), C64::new(0.0, 0.0));
    for j in 0..total {
        let tt = t[0] + h * j as f64;
        let v = interp(tt);
        let e = C64::from_polar(1.0, -omega_p * tt);
        zp += v * e;
        zm += v * e.conj();
    }
    Ok((zp / total as f64, zm / total as f64))
}

/// 4-point Lagrange (cubic) interpolation of uniformly sampled `z` (first sample at `t0`, step `dt`).
fn cubic_at(t0: f64, dt: f64, z: &[C64], tt: f64) -> C64 {
    let n = z.len();
    let u = (tt - t0) / dt;
    let i = (u.floor() as isize).clamp(1, n as isize - 3) as usize;
    let f = u - i as f64;
    let (a, b, c, d) = (z[i - 1], z[i], z[i + 1], z[i + 2]);
    a * (-f * (f - 1.0) * (f - 2.0) / 6.0)
        + b * ((f + 1.0) * (f - 1.0) * (f - 2.0) / 2.0)
        + c * (-(f + 1.0) * f * (f - 2.0) / 2.0)
        + d * ((f + 1.0) * f * (f - 1.0) / 6.0)
}

/// Tach-driven synchronous average (docs/math/companion.md §A.8 step 4): the planet angle is `sign·2π·(r + s)` between
/// pulses r and r+1 (linear in time within a revolution); z is resampled (cubic) at M points per
/// revolution over all whole revolutions and the DFT bin at ±1 order taken. The result refers to
/// the first pulse; it is moved to the time origin with the mean speed
/// `ω̄ = sign·2π·revs/(t_last − t_first)`: `Z₊ = Z₊,angle e^{−iω̄ t_first}`, `Z₋ = Z₋,angle e^{iω̄ t_first}`.
pub(super) fn synchronous_tach(
    rec: &Record,
    z: &[C64],
    pulses: &[f64],
    sign: f64,
) -> Result<(C64, C64), OrbitError> {
    let t = rec.t_s();
    let dt = rec.mean_step_s();
    let revs = pulses.len() - 1;
    let span = pulses[revs] - pulses[0];
    let per_rev = ((span / revs as f64 / dt).floor() as usize).max(8);
    let (mut zp, mut zm) = (C64::new(0.0, 0.0), C64::new(0.0, 0.0));
    for r in 0..revs {
        let (a, b) = (pulses[r], pulses[r + 1]);
        for j in 0..per_rev {
            let s = j as f64 / per_rev as f64;
            let v = cubic_at(t[0], dt, z, a + (b - a) * s);
            let e = C64::from_polar(1.0, -sign * TAU * s);
            zp += v * e;
            zm += v * e.conj();
        }
    }
    let total = (revs * per_rev) as f64;
    let w_mean = sign * TAU * revs as f64 / span;
    let shift = C64::from_polar(1.0, -w_mean * pulses[0]);
    Ok((zp / total * shift, zm / total * shift.conj()))
}

/// Full (complex) spectrum of `z = x + i y` with a Hann window: `(signed frequency Hz, amplitude µm)`
/// sorted by frequency; amplitude-corrected so a line `Z e^{iωt}` on a bin shows `|Z|`. For
/// uniformly sampled data with step `dt_s`; pass detrended data (e.g. [`Extractor::analysis_signal`](super::Extractor::analysis_signal)).
#[must_use]
pub fn full_spectrum(dt_s: f64, x_um: &[f64], y_um: &[f64]) -> Vec<(f64, f64)> {
    let n = x_um.len().min(y_um.len());
    if n < 2 {
        return Vec::new();
    }
    let (buf, ws) = hann_fft(&x_um[..n], &y_um[..n]);
    let df = 1.0 / (n as f64 * dt_s);
    let mut out: Vec<(f64, f64)> = buf
        .iter()
        .enumerate()
        .map(|(k, c)| {
            let kk = if k <= n / 2 {
                k as f64
            } else {
                k as f64 - n as f64
            };
            (kk * df, c.norm() / ws)
        })
        .collect();
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    out
}
