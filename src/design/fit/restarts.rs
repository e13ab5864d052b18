//! Restarts of the fit to the points for targets the first fit does not reproduce.

use super::{FitError, FitOptions, Fitted, MEASURED_NOISE_MM, fit_points, minimax};
use crate::geometry::mechanism::Mechanism;

/// The fit to the points from the chain's result. A target it does not reproduce (and noise does
/// not explain) may sit in another basin: restarts from `restarts` (the patent route at order 2)
/// and from the first fit with its ratio cut to order 2 are screened on a few points with a
/// short budget; the best is refitted on every point and kept if it beats the first fit —
/// by RMS on measured points, by `max(max, coverage)` (the Hausdorff distance to the points'
/// polyline) on clean ones, which then get the minimax finish.
pub fn fit_with_restarts(
    points: &[[f64; 2]],
    start: &Mechanism,
    restarts: Vec<Mechanism>,
    fit_opts: &FitOptions,
    tol_tip_mm: f64,
) -> Result<Fitted, FitError> {
    let mut f = fit_points(points, start, fit_opts)?;
    let noise = fit_opts.noise_sigma_mm;
    if f.max_mm <= tol_tip_mm || f.rms_mm <= 2.0 * noise {
        return Ok(f);
    }
    let measured = noise > MEASURED_NOISE_MM;
    let score = |g: &Fitted| {
        if measured {
            g.rms_mm
        } else {
            g.max_mm.max(g.coverage_mm)
        }
    };
    let screen = FitOptions {
        max_points: SCREEN_POINTS,
        max_iterations: SCREEN_ITERATIONS,
        max_order: f.mechanism.ratio.order(),
        ..fit_opts.clone()
    };
    let cut = |k: usize| Mechanism {
        ratio: f.mechanism.ratio.with_order(k),
        ..f.mechanism.clone()
    };
    let starts: Vec<Mechanism> = restarts.into_iter().chain([cut(2)]).collect();
    let screened = starts
        .iter()
        .filter_map(|s| fit_points(points, s, &screen).ok())
        .min_by(|a, b| score(a).total_cmp(&score(b)));
    if let Some(g) = screened.filter(|g| score(g) < score(&f)) {
        // On every point, at the screened order, with the screening's iteration budget.
        let refit = FitOptions {
            order: Some(g.mechanism.ratio.order()),
            max_iterations: SCREEN_ITERATIONS,
            ..fit_opts.clone()
        };
        let g = fit_points(points, &g.mechanism, &refit).unwrap_or(g);
        if score(&g) < score(&f) {
            f = g;
        }
    }
    // Not traceable (and clean): trade RMS for the largest deviation, which is what the user
    // sees. Never on measured points, where the largest distance is the noise's.
    if !measured {
        f = minimax(points, f, fit_opts);
    }
    Ok(f)
}

/// Points and Levenberg–Marquardt iterations of a screening fit of a restart.
const SCREEN_POINTS: usize = 240;

const SCREEN_ITERATIONS: usize = 15;
