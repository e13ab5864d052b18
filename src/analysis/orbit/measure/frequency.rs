//! Estimate of the planet frequency from the record when it is only approximately known
//! (docs/math/companion.md §A.8 step 3): interpolated Hann spectrum, then least-squares refinement.

use super::extract::{Extractor, Method};
use super::frame::Frame;
use super::record::Record;
use super::spectrum::hann_fft;
use crate::analysis::orbit::{OrbitError, invalid};
use crate::progress::Progress;
use std::f64::consts::TAU;

/// Estimate of the planet frequency when it is only approximately known (docs/math/companion.md §A.8 step 3).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, schemars::JsonSchema)]
pub struct FrequencyEstimate {
    /// Coarse estimate from the Hann-windowed complex spectrum with 3-point (Grandke)
    /// interpolation, signed rad/s.
    pub interpolated_rad_s: f64,
    /// Refined estimate minimising the least-squares residual over ω, signed rad/s.
    pub refined_rad_s: f64,
    /// Golden-section iterations of the refinement.
    pub iterations: u32,
}

impl Extractor {
    /// Estimates ω_p from the record when the configured ω_p is only approximate:
    /// (1) Hann-windowed FFT of the analysis-frame `z = x + iy`, strongest bin at ±|ω_p| within
    /// `±search_rel·|ω_p|`, Grandke interpolation `δ = ±(2a−1)/(a+1)`, `a` = larger-neighbour
    /// ratio; (2) golden-section minimisation of the residual sum of squares of this extractor's
    /// fit over `ω ∈ [ω̂ − 1 bin, ω̂ + 1 bin]` down to `tol_rad_s`. The sign of the configured ω_p is
    /// kept (the spectrum of the orbit alone cannot tell it). Carrier frame or de-rotation only;
    /// needs uniform sampling. `progress` receives the number of refinement iterations done (at most
    /// [`Extractor::frequency_iterations`]); each costs one least-squares fit.
    ///
    /// # Errors
    /// [`OrbitError::Invalid`] for bad `search_rel`/`tol_rad_s` or the full-spectrum frame,
    /// [`OrbitError::Record`] for non-uniform sampling or when the band holds no bin.
    pub fn estimate_frequency(
        &self,
        rec: &Record,
        search_rel: f64,
        tol_rad_s: f64,
        progress: &Progress,
    ) -> Result<FrequencyEstimate, OrbitError> {
        self.check_estimable(rec, search_rel, tol_rad_s)?;
        let (coarse, bin) = self.interpolated_peak(rec, search_rel)?;
        let rss = |om: f64| self.residual_at(rec, om);
        let (a, b, it) = golden_section(rss, coarse - bin, coarse + bin, tol_rad_s, progress);
        let sign = self.omega_p_rad_s.signum();
        Ok(FrequencyEstimate {
            interpolated_rad_s: sign * coarse,
            refined_rad_s: sign * 0.5 * (a + b),
            iterations: it,
        })
    }

    /// Refuses bad `search_rel`/`tol_rad_s`, the full-spectrum frame and non-uniform sampling.
    fn check_estimable(
        &self,
        rec: &Record,
        search_rel: f64,
        tol_rad_s: f64,
    ) -> Result<(), OrbitError> {
        if !(search_rel > 0.0 && search_rel < 1.0) {
            return Err(invalid("search_rel", "must lie in (0, 1)"));
        }
        if !(tol_rad_s > 0.0 && tol_rad_s.is_finite()) {
            return Err(invalid("tol_rad_s", "must be positive and finite"));
        }
        if matches!(self.opts.frame, Frame::HousingFullSpectrum { .. }) {
            return Err(invalid(
                "frame",
                "frequency estimation needs the carrier frame or de-rotation",
            ));
        }
        if !rec.is_uniform(1e-6) {
            return Err(OrbitError::Record(
                "frequency estimation needs uniformly sampled data".into(),
            ));
        }
        Ok(())
    }

    /// The coarse estimate `(|ω̂|, bin width)`, rad/s: the strongest Hann-spectrum bin of the
    /// analysis-frame `z` at ±|ω_p| within `±search_rel·|ω_p|`, Grandke-interpolated
    /// (`δ = ±(2a−1)/(a+1)`, `a` = larger-neighbour ratio).
    fn interpolated_peak(&self, rec: &Record, search_rel: f64) -> Result<(f64, f64), OrbitError> {
        let (x, y) = self.analysis_signal(rec)?;
        let n = x.len();
        let (buf, _) = hann_fft(&x, &y);
        let bin = TAU / (n as f64 * rec.mean_step_s());
        let wp = self.omega_p_rad_s.abs();
        let kmin = (((1.0 - search_rel) * wp / bin).floor() as usize).max(1);
        let kmax = (((1.0 + search_rel) * wp / bin).ceil() as usize).min(n / 2 - 1);
        if kmin > kmax {
            return Err(OrbitError::Record(
                "no spectral bin in the search band".into(),
            ));
        }
        // Magnitude of bin k on the positive (+) or negative (−) side.
        let mag = |k: usize, neg: bool| {
            if neg {
                buf[(n - k) % n].norm()
            } else {
                buf[k].norm()
            }
        };
        let mut best = (0.0, kmin, false);
        for k in kmin..=kmax {
            for neg in [false, true] {
                if mag(k, neg) > best.0 {
                    best = (mag(k, neg), k, neg);
                }
            }
        }
        let (_, k, neg) = best;
        let (l, r, c) = (mag(k - 1, neg), mag(k + 1, neg), mag(k, neg));
        let delta = if r >= l {
            let a = r / c;
            (2.0 * a - 1.0) / (a + 1.0)
        } else {
            let a = l / c;
            -(2.0 * a - 1.0) / (a + 1.0)
        };
        Ok(((k as f64 + delta) * bin, bin))
    }

    /// Residual sum of squares (µm²) of this extractor's least-squares fit at `|ω| = om` rad/s
    /// (sign of the configured ω_p), ∞ when the fit fails.
    fn residual_at(&self, rec: &Record, om: f64) -> f64 {
        let mut e = self.clone();
        e.omega_p_rad_s = om.copysign(self.omega_p_rad_s);
        e.opts.method = Method::LeastSquares;
        match e.extract(rec) {
            Ok(m) => m
                .residual_rms_um
                .map_or(f64::INFINITY, |(a, b)| a * a + b * b),
            Err(_) => f64::INFINITY,
        }
    }

    /// Upper bound of the golden-section iterations of [`Extractor::estimate_frequency`] for a
    /// record of length `record_s` (bracket 2 bins = `4π/T_rec`) and tolerance `tol_rad_s`.
    #[must_use]
    pub fn frequency_iterations(record_s: f64, tol_rad_s: f64) -> u64 {
        let bracket = 2.0 * TAU / record_s;
        let g = 0.5 * (5f64.sqrt() - 1.0);
        ((bracket / tol_rad_s).ln() / (1.0 / g).ln())
            .ceil()
            .clamp(0.0, 200.0) as u64
    }
}

/// Golden-section minimisation of `f` on `[a, b]` down to a bracket of `tol` (at most 200
/// iterations, each reported to `progress`): the final bracket and the iterations.
fn golden_section(
    f: impl Fn(f64) -> f64,
    a: f64,
    b: f64,
    tol: f64,
    progress: &Progress,
) -> (f64, f64, u32) {
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut a, mut b) = (a, b);
    let (mut c1, mut c2) = (b - g * (b - a), a + g * (b - a));
    let (mut f1, mut f2) = (f(c1), f(c2));
    let mut it = 0;
    while b - a > tol && it < 200 {
        if f1 <= f2 {
            b = c2;
            c2 = c1;
            f2 = f1;
            c1 = b - g * (b - a);
            f1 = f(c1);
        } else {
            a = c1;
            c1 = c2;
            f1 = f2;
            c2 = a + g * (b - a);
            f2 = f(c2);
        }
        it += 1;
        progress.advance(1);
    }
    (a, b, it)
}
