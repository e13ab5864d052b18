//! The fit's summary in the design report (`fit`): how far the points lie from the fitted
//! train's curve, and from the start's, mm.

use super::Fitted;
use serde::{Deserialize, Serialize};

/// The orthogonal-distance fit ([`crate::design::fit`]): distances of the target points from the curve the
/// fitted train traces (analytic model), mm.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
pub struct FitSummary {
    /// Fourier order K of the fitted sun ratio.
    pub order: usize,
    /// RMS point distance, mm (≈ the noise σ on measured points).
    pub rms_mm: f64,
    /// Largest point distance, mm.
    pub max_mm: f64,
    /// RMS point distance of the start (the chain's result before the fit), mm.
    pub start_rms_mm: f64,
    /// Largest point distance of the start, mm.
    pub start_max_mm: f64,
    /// Noise σ estimated from the points alone (4th differences in the point index), mm.
    pub noise_sigma_mm: f64,
    /// Harmonics of the smoothed copy the start was taken from (measured points), if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start_smoothing_harmonics: Option<usize>,
    /// Levenberg–Marquardt iterations.
    pub iterations: usize,
    /// `[K, rms_mm, max_mm]` per order tried.
    pub order_scan: Vec<[f64; 3]>,
}

/// The report of the fit `f` from a start `start_rms` / `start_max` mm from the points.
pub(in crate::design) fn fit_summary(
    f: &Fitted,
    start_rms: f64,
    start_max: f64,
    noise_sigma: f64,
    start_smoothing: Option<usize>,
) -> FitSummary {
    FitSummary {
        order: f.mechanism.ratio.order(),
        rms_mm: f.rms_mm,
        max_mm: f.max_mm,
        start_rms_mm: start_rms,
        start_max_mm: start_max,
        noise_sigma_mm: noise_sigma,
        start_smoothing_harmonics: start_smoothing,
        iterations: f.iterations,
        order_scan: f.order_scan.clone(),
    }
}
