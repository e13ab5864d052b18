//! Restarts of the fit to the points for targets the first fit does not reproduce.

use super::lawson::RACE_HEAT_PASSES;
use super::{
    FitError, FitOptions, Fitted, Lawson, LawsonStart, MEASURED_NOISE_MM, MINIMAX_PASSES,
    fit_points, minimax, race,
};
use crate::geometry::fourier::SunRatio;
use crate::geometry::mechanism::Mechanism;
use crate::math::Point;
use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};
use rayon::prelude::*;

/// The fit to the points from the chain's result. A target it does not reproduce (and noise does
/// not explain) may sit in another basin: restarts from `restarts` (the patent route at order 2)
/// and from the first fit with its ratio cut to order 2 are screened on a few points with a
/// short budget; the best is refitted on every point and kept if it beats the first fit —
/// by RMS on measured points, by `max(max, coverage)` (the Hausdorff distance to the points'
/// polyline) on clean ones, which then get the minimax finish.
pub fn fit_with_restarts(
    points: &[Point],
    start: &Mechanism,
    restarts: Vec<Mechanism>,
    fit_opts: &FitOptions,
    tol_mm: f64,
) -> Result<Fitted, FitError> {
    let f = fit_points(points, start, fit_opts)?;
    let noise = fit_opts.noise_sigma_mm;
    if f.max_mm <= tol_mm || f.rms_mm <= 2.0 * noise {
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
        max_order: f.mechanism.ratio.order().min(SCREEN_MAX_ORDER),
        ..fit_opts.clone()
    };
    let cut = |k: usize| Mechanism {
        ratio: f.mechanism.ratio.with_order(k),
        ..f.mechanism.clone()
    };
    let starts: Vec<Mechanism> = restarts
        .into_iter()
        .chain([cut(2)])
        .chain(perturbed(&cut(PERTURBED_ORDER), PERTURBED_STARTS))
        .collect();
    let screened = starts
        .par_iter()
        .filter_map(|s| fit_points(points, s, &screen).ok())
        .min_by(|a, b| score(a).total_cmp(&score(b)));
    let Some(g) = screened else {
        return Ok(if measured {
            f
        } else {
            minimax(points, f, fit_opts)
        });
    };
    // On every point, at the screened order, with the screening's iteration budget.
    let refit = FitOptions {
        order: Some(g.mechanism.ratio.order()),
        max_iterations: SCREEN_ITERATIONS,
        ..fit_opts.clone()
    };
    // The refit minimises the RMS, which may raise the score: the better of the two is kept.
    let g = match fit_points(points, &g.mechanism, &refit) {
        Ok(r) if score(&r) < score(&g) => r,
        _ => g,
    };
    if measured {
        return Ok(if score(&g) < score(&f) { g } else { f });
    }
    // Not traceable (and clean): trade RMS for the largest deviation, which is what the user
    // sees (never on measured points, where the largest distance is the noise's). Both the
    // first fit (often a higher order) and the best restart are finished, side by side; the
    // better finish is kept.
    // The three finishes race (`lawson::race`): the first two start their heat while the
    // continuation's start is fitted.
    let heat = |f: Fitted| {
        let mut l = Lawson::new(points, f, fit_opts, LawsonStart::Uniform);
        l.advance(RACE_HEAT_PASSES);
        l
    };
    let ((a, b), c) = rayon::join(
        || rayon::join(|| heat(f), || heat(g)),
        || continuation_start(points, start, fit_opts),
    );
    let c = c.map(|c| Lawson::new(points, c, fit_opts, LawsonStart::Uniform));
    // The same preference as three whole finishes: the restart's over the first fit's, the
    // continuation's over both, each only when closer.
    race([a, b].into_iter().chain(c).collect(), MINIMAX_PASSES)
        .into_iter()
        .reduce(|best, x| if score(&x) < score(&best) { x } else { best })
        .ok_or(FitError::NotFinite("minimax finish"))
}

/// Continuation in the gear limits: the fit under tightened limits
/// ([`crate::geometry::limits::GearLimits::tightened`]: 10° less pressure angle, convex curves), whose landscape has
/// fewer basins, refitted under the real ones from there and finished towards the minimax. A
/// fit under the real limits can settle in a basin that a tighter design already beats (a
/// concave hollow where a convex sun traces closer); this path starts on the other side.
fn continuation_start(points: &[Point], start: &Mechanism, opts: &FitOptions) -> Option<Fitted> {
    let tight = FitOptions {
        limits: opts.limits.tightened()?,
        ..opts.clone()
    };
    let t = fit_points(points, start, &tight).ok()?;
    fit_points(points, &t.mechanism, opts).ok()
}

/// Points and Levenberg–Marquardt iterations of a screening fit of a restart.
const SCREEN_POINTS: usize = 160;

/// Highest Fourier order a screening fit climbs to (from the start's order, at least 6).
const SCREEN_MAX_ORDER: usize = 8;

const SCREEN_ITERATIONS: usize = 12;

/// Fourier order of the perturbed restarts.
const PERTURBED_ORDER: usize = 6;

/// Perturbed restarts screened for a target no train traces.
const PERTURBED_STARTS: usize = 6;

/// `n` starts around `m`: the first three harmonics of the ratio moved by up to ±0.03, the arms
/// by ±0.5 %, the sun phase and the needle angle by ±0.05 rad. A target no train traces has many
/// local optima (the residual has corners where the tip cannot follow); a few nearby starts find
/// better ones. Fixed seed: the same points give the same design.
fn perturbed(m: &Mechanism, n: usize) -> Vec<Mechanism> {
    let mut rng = ChaCha8Rng::seed_from_u64(0x05ee_df17);
    let mut jitter = |r: f64| rng.random_range(-r..r);
    (0..n)
        .filter_map(|_| {
            let mut a = m.ratio.cos_coefficients().to_vec();
            let mut b = m.ratio.sin_coefficients().to_vec();
            for k in 0..a.len().min(3) {
                a[k] += jitter(0.03);
                b[k] += jitter(0.03);
            }
            Some(Mechanism {
                a_mm: m.a_mm * (1.0 + jitter(0.005)),
                l3_mm: m.l3_mm * (1.0 + jitter(0.005)),
                ratio: SunRatio::new(a, b).ok()?,
                sun_phase_rad: m.sun_phase_rad + jitter(0.05),
                needle_angle_rad: m.needle_angle_rad + jitter(0.05),
                idler_offset_rad: 0.0,
            })
        })
        .collect()
}
