//! Verdicts on measured (noisy) points: how far the designed train is from the curve under the
//! noise, which is what check C12 and the chain's warnings judge when the points are measured.
//!
//! The deviation of the traced path from the noisy points is not its deviation from the curve
//! the points measure: on N points with noise σ (per coordinate), the largest point deviation of
//! even the exact train is about `σ·√(2 ln N)` (0.07 mm for σ = 0.02 mm, N = 600). What the
//! points cannot show directly is the part of the noise the fitted parameters absorb (the
//! residual of a least-squares fit is orthogonal to it). Its size follows from the fit itself:
//!
//! ```text
//! p      = 4 + 2K                         parameters fitted (a, l3, γ, φ_ref, a_1..a_K, b_1..b_K)
//! ν      = min(p, N − 1)/N                share of the noise the fit follows
//! b²     = max(0, rms² − σ²(1 − ν))       misfit beyond the noise (rms = RMS synchronous deviation)
//! δ_rms² = σ²·ν + b²                      mean square distance of the path from the curve
//! δ_max  = √(2 ln p)·δ_rms                its largest value along the loop, mm
//! ```
//!
//! The absorbed noise is the projection of N independent normal errors on p directions: its mean
//! square per point is `σ²·p/N`, and it is a smooth random function with about p degrees of
//! freedom, whose largest value is `√(2 ln p)` times its RMS. The residual keeps the rest,
//! `σ²(1 − p/N)`; whatever the RMS deviation has beyond that is misfit (a target the train does
//! not trace), counted in full. Against the measured Hausdorff distance to the clean truth: within
//! 0.004 mm on the shared noisy cases (σ = 0.02/0.03/0.05 mm), up to 0.012 mm above it on
//! generated ones (σ = 0.02–0.05 mm, 300–1200 points).

use crate::design::fit::MEASURED_NOISE_MM;

pub use crate::design::fit::fitted_parameters;

/// Estimated largest distance (mm) of the traced path from the curve under noisy points (module
/// docs: `δ_max = √(2 ln p)·√(σ²ν + max(0, rms² − σ²(1 − ν)))`, `ν = min(p, N − 1)/N`), from the
/// noise σ of the points (mm, per coordinate), the RMS synchronous deviation `rms_mm` of the
/// `points` points and the `params` fitted parameters. `None` for exact points (σ at most
/// [`MEASURED_NOISE_MM`]): their deviation from the points is their deviation from the curve.
#[must_use]
pub fn curve_deviation_mm(sigma_mm: f64, rms_mm: f64, points: usize, params: usize) -> Option<f64> {
    if !(sigma_mm > MEASURED_NOISE_MM) || points < 2 {
        return None;
    }
    let p = params.clamp(2, points - 1) as f64;
    let nu = p / points as f64;
    let s2 = sigma_mm * sigma_mm;
    let misfit2 = (rms_mm * rms_mm - s2 * (1.0 - nu)).max(0.0);
    Some((2.0 * p.ln()).sqrt() * (s2 * nu + misfit2).sqrt())
}

/// Whether a deviation from measured points is explained by their noise: the estimated
/// deviation from the curve under them ([`curve_deviation_mm`]) is within `tol_mm`. Always false
/// on exact points (no estimate).
#[must_use]
pub fn explained_by_noise(curve_deviation_mm: Option<f64>, tol_mm: f64) -> bool {
    curve_deviation_mm.is_some_and(|d| d <= tol_mm)
}

/// Check C12's subject and value: the max synchronous deviation from the points `sync_mm`, or on
/// measured points (`estimate` present) the estimated deviation from the curve under them.
pub(in crate::design) fn c12_measure(
    sync_mm: f64,
    estimate: Option<f64>,
    sigma_mm: f64,
) -> (String, f64) {
    match estimate {
        None => (
            "round trip from the output tables: max synchronous tip deviation, mm".into(),
            sync_mm,
        ),
        Some(e) => (
            format!(
                "round trip from the output tables: estimated max tip deviation from the curve under the measured points (noise σ = {sigma_mm:.4} mm; {sync_mm:.4} mm from the points), mm"
            ),
            e,
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_points_have_no_estimate() {
        assert_eq!(curve_deviation_mm(0.001, 0.02, 600, 52), None);
        assert!(!explained_by_noise(None, 0.05));
    }

    #[test]
    fn pure_noise_gives_the_absorbed_part_and_misfit_adds_in_full() {
        // rms² = σ²(1 − ν): no misfit, δ_rms = σ√ν.
        let (s, n, p) = (0.05_f64, 600, 36);
        let nu: f64 = 36.0 / 600.0;
        let rms = s * (1.0 - nu).sqrt();
        let est = curve_deviation_mm(s, rms, n, p).unwrap();
        let want = (2.0 * 36f64.ln()).sqrt() * s * nu.sqrt();
        assert!((est - want).abs() < 1e-15, "{est} {want}");
        assert!((est - 0.03279).abs() < 1e-5, "{est}");
        // A misfit of 0.1 mm RMS on top.
        let with_misfit = curve_deviation_mm(s, (rms * rms + 0.01).sqrt(), n, p).unwrap();
        let want = (2.0 * 36f64.ln()).sqrt() * (s * s * nu + 0.01).sqrt();
        assert!((with_misfit - want).abs() < 1e-12, "{with_misfit} {want}");
        assert!(
            explained_by_noise(Some(est), 0.05) && !explained_by_noise(Some(with_misfit), 0.05)
        );
    }
}
