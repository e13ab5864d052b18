//! Final stage: the whole train fitted to the trajectory points themselves (orthogonal-distance
//! least squares).
//!
//! The chain's earlier stages (l1, l3 from the extreme distances, the inversion, the patent route)
//! only give a *start*: a coarsely sampled nose, noisy points or a target the train cannot trace
//! exactly spoil them. This stage fits every design parameter to the points:
//!
//! ```text
//! p = (a, l3, γ, φ_ref, a_1..a_K, b_1..b_K)           a, l3 in mm; γ, φ_ref in rad
//! B(φ; p) = 2a·e(φ) + l3·e(β),   β = φ + π − S(φ − φ_ref) + γ,   S = Φ⁻¹(Φ + π)   (docs/math/chain.md §2, §6.2)
//! min_p Σ_j dist(P_j, B(·; p))²   subject to   i21(θ) ∈ [i_min, i_max] for all θ
//! ```
//!
//! Each point carries its own carrier angle φ_j (the instant the tip passes it), found by projecting
//! the point on the traced curve (Newton on `(B − P)·B′ = 0`, from the nearest local minima of the
//! distance to dense curve samples). The residual is the signed distance `d_j = n_j·(P_j − B(φ_j))`
//! with `n_j = ±(P_j − B(φ_j))/|P_j − B(φ_j)|` (the sign tells the side of the curve); since
//! `P_j − B(φ_j) ⟂ B′(φ_j)` at the projection, its gradient is `−n_j·∂B/∂p` (no term from φ_j).
//! The derivatives are analytic:
//!
//! ```text
//! ∂S/∂t = i21(t)/i21(S),       ∂S/∂c = (∂Φ/∂c(t) − ∂Φ/∂c(S)) / i21(S),
//! ∂Φ/∂a_k(θ) = sin kθ / k,      ∂Φ/∂b_k(θ) = (1 − cos kθ) / k
//! ```
//!
//! Solved by Levenberg–Marquardt with Marquardt scaling (written here rather than with the
//! `levenberg-marquardt` crate because every trial step must re-project the points and be made
//! admissible before it is judged). The gear limits ([`FitOptions::limits`]: ratio bounds, and in
//! the design chain the pressure angle and the concave radius) are constraints: penalty rows per
//! sampled angle give the solver their gradients, and every iterate is made admissible by
//! shrinking `i21 − 1` ([`crate::geometry::limits`]; the closure `Φ(2π) = 2π` is kept) — so every
//! start and every iterate is a realisable train. With [`FitOptions::perimeter_mm`] the centre
//! distance follows from the ratio (a tooth count at a module, [`crate::geometry::perimeter`]).
//!
//! The Fourier order rises (6, 8, 12, 16, 24, 32, 40) while the fit is above its tolerance, above
//! the noise level and still improving.
//!
//! ```
//! use ncgear::design::fit::{fit_points, FitOptions};
//! use ncgear::geometry::{fourier::SunRatio, mechanism::Mechanism};
//! let truth = Mechanism { a_mm: 45.0, l3_mm: 170.0,
//!     ratio: SunRatio::new(vec![0.3, 0.045], vec![0.0, 0.0]).unwrap(),
//!     sun_phase_rad: 0.2, needle_angle_rad: -1.2, idler_offset_rad: 0.0 };
//! let pts: Vec<ncgear::math::Point> = (0..300).map(|k| truth.tip(0.021 * k as f64)).collect();
//! let mut start = truth.clone();
//! start.a_mm += 0.3; start.l3_mm -= 0.5; start.needle_angle_rad += 0.01;
//! let fit = fit_points(&pts, &start, &FitOptions::default()).unwrap();
//! assert!(fit.max_mm < 1e-4);
//! assert!((fit.mechanism.a_mm - 45.0).abs() < 1e-5);
//! ```

pub mod noise;

use crate::math::Point;
mod curve;
mod lawson;
mod restarts;
mod scan;
mod solver;
mod summary;

/// Noise σ (mm) above which points count as measured: the start is then taken from a smoothed copy.
pub const MEASURED_NOISE_MM: f64 = 0.002;
pub use restarts::fit_with_restarts;
pub use summary::FitSummary;
pub(in crate::design) use summary::fit_summary;

use crate::geometry::limits::GearLimits;
use crate::geometry::mechanism::Mechanism;
use crate::math::polyline::SegmentGrid;
use curve::{
    INITIAL_SAMPLES, contact_guess, curve_evals, initial_angles, initial_projections_on,
    project_near,
};
pub(crate) use lawson::{Lawson, LawsonStart, lawson, race};
use rayon::prelude::*;
use solver::{Lm, to_params, with_order};

/// Parameters of a train fitted to the points with a sun ratio of Fourier order `order`:
/// `4 + 2K` (a, l3, γ, the sun phase and the ratio's coefficients).
#[must_use]
pub fn fitted_parameters(order: usize) -> usize {
    4 + 2 * order
}

/// Orders the fit climbs through.
pub const FIT_ORDERS: [usize; 7] = [6, 8, 12, 16, 24, 32, 40];

/// Options of the orthogonal-distance fit. (De)serialisable without `limits` and
/// `perimeter_mm`, which the design chain sets from its own options (they keep their defaults
/// when read).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct FitOptions {
    /// Fixed Fourier order K of the sun ratio; `None` (default) = climb [`FIT_ORDERS`] from the
    /// start's order.
    pub order: Option<usize>,
    /// Highest order tried when climbing (default 40).
    pub max_order: usize,
    /// The gear limits every iterate satisfies (default: the sun ratio within `[0.3, 3.3]`
    /// alone, [`GearLimits::ratio_only`]; the design chain adds the pressure-angle and
    /// concave-radius limits).
    #[serde(skip)]
    pub limits: GearLimits,
    /// The pitch perimeter the train must have, mm (default `None`): `z·π·m` for `z` teeth of
    /// module `m`. The centre distance is then not a free parameter but `a = L/L̂(i)`
    /// ([`crate::geometry::perimeter`]).
    #[serde(skip)]
    pub perimeter_mm: Option<f64>,
    /// Fit the idler offset ε too (default false: ε stays the start's): a train whose
    /// intermediate axis leaves the carrier line ([`crate::geometry::mechanism`]). Set by the
    /// design chain from [`crate::design::DesignOptions::idler_offset`].
    #[serde(skip)]
    pub free_idler_offset: bool,
    /// The least gap the sun's and the planet's pitch curves keep across the carrier, mm
    /// (default 0): every iterate's idler offset is held within
    /// [`Mechanism::max_idler_offset_rad`] of it. Set by the design chain: the teeth's depth
    /// at a module.
    #[serde(skip)]
    pub sun_planet_gap_mm: f64,
    /// The order stops rising once the largest point distance is below this, mm (default 0.0125).
    pub tol_mm: f64,
    /// Noise level σ of the points, per coordinate, mm (default 0): the order stops rising once
    /// the RMS distance is down to the noise a fit of p = 4 + 2K parameters keeps, `σ·√(1 − p/N)`.
    pub noise_sigma_mm: f64,
    /// Levenberg–Marquardt iterations per order (default 40).
    pub max_iterations: usize,
    /// At most this many points (evenly taken) drive the iterations; all points are measured at
    /// the end (default 360: a drawn target's chord is then still a few mm, far below its
    /// curvature radii; on designer targets the fit from 360 points is as close as from 900, and
    /// a toothed design of a long target faster: docs/performance.md, "The fit's point budget").
    pub max_points: usize,
    /// Smoothness weight √λ relative to l3 on `k²·(a_k, b_k)` (default 0: the order choice
    /// regularises).
    pub smoothness: f64,
}

crate::builder::with_fields!(FitOptions {
    with_order => order: Option<usize>,
    with_max_order => max_order: usize,
    with_limits => limits: GearLimits,
    with_perimeter_mm => perimeter_mm: Option<f64>,
    with_free_idler_offset => free_idler_offset: bool,
    with_sun_planet_gap_mm => sun_planet_gap_mm: f64,
    with_tol_mm => tol_mm: f64,
    with_noise_sigma_mm => noise_sigma_mm: f64,
    with_max_iterations => max_iterations: usize,
    with_max_points => max_points: usize,
    with_smoothness => smoothness: f64,
});

impl Default for FitOptions {
    fn default() -> Self {
        Self {
            order: None,
            max_order: 40,
            limits: GearLimits::ratio_only([0.3, 3.3]).expect("valid bounds"),
            perimeter_mm: None,
            free_idler_offset: false,
            sun_planet_gap_mm: 0.0,
            tol_mm: 0.0125,
            noise_sigma_mm: 0.0,
            max_iterations: 40,
            max_points: 360,
            smoothness: 1e-6,
        }
    }
}

/// Why a fit could not start.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum FitError {
    /// Too few points.
    #[error("the fit needs at least 8 points, got {0}")]
    TooFewPoints(usize),
    /// A non-finite point or start parameter.
    #[error("the fit got a non-finite {0}")]
    NotFinite(&'static str),
}

/// Carrier angles at which a fitted train's traced curve is measured against the points' polyline
/// (the curve side of the Hausdorff distance that picks between fits): fine enough that a sharp
/// nose of the traced curve is not stepped over.
const MEASURE_COVERAGE_SAMPLES: usize = 1024;

/// Result of [`fit_points`].
#[derive(Debug, Clone)]
pub struct Fitted {
    /// The fitted train (solved frame: CCW, relative to O), admissible ratio.
    pub mechanism: Mechanism,
    /// Carrier angle at which the tip passes each point, rad.
    pub carrier_angles_rad: Vec<f64>,
    /// Distance of each point from the traced curve, mm.
    pub distances_mm: Vec<f64>,
    /// RMS point distance, mm.
    pub rms_mm: f64,
    /// Largest point distance, mm.
    pub max_mm: f64,
    /// Largest distance of the traced curve (1024 carrier angles) from the target polyline, mm:
    /// with `max_mm`, the Hausdorff distance to the points' polyline.
    pub coverage_mm: f64,
    /// Largest distance of the traced curve from the target polyline beyond what its chords can
    /// explain (0.6 of the nearest chord, as in the fit's coverage rows), mm: where the points
    /// do not sample a sharp nose, the true curve itself lies that far off the chords (0.57 mm
    /// round the 0.27 mm nose of a 360-point exact target), and only the excess is the curve's.
    pub coverage_excess_mm: f64,
    /// Levenberg–Marquardt iterations over all orders.
    pub iterations: usize,
    /// `[K, rms_mm, max_mm]` for each order tried.
    pub order_scan: Vec<[f64; 3]>,
}

/// Fits the train to `points` (mm, relative to the carrier axis, solved frame: CCW) from `start`.
///
/// Every iterate is admissible (within `opts.limits`); the start is made admissible
/// first. See the module documentation for the model and the solver.
pub fn fit_points(
    points: &[Point],
    start: &Mechanism,
    opts: &FitOptions,
) -> Result<Fitted, FitError> {
    if points.len() < 8 {
        return Err(FitError::TooFewPoints(points.len()));
    }
    if points.iter().any(|p| !p.is_finite()) {
        return Err(FitError::NotFinite("point"));
    }
    if !to_params(start, true).iter().all(|v| v.is_finite()) {
        return Err(FitError::NotFinite("start parameter"));
    }
    let (stride, sub) = subsample(points, opts);
    let grid = SegmentGrid::new(&sub);
    let orders: Vec<usize> = match opts.order {
        Some(k) => vec![k.max(1)],
        None => {
            // From the start's order, at least the first of FIT_ORDERS, at most max_order.
            let k0 = start
                .ratio
                .order()
                .max(FIT_ORDERS[0])
                .min(opts.max_order.max(1));
            let mut v = vec![k0];
            v.extend(
                FIT_ORDERS
                    .iter()
                    .copied()
                    .filter(|&k| k > k0 && k <= opts.max_order),
            );
            v
        }
    };
    let mut m = with_order(start, orders[0]);
    solver::admit(&mut m, opts);
    let mut phis_all = initial_angles(&m, points);
    let mut scan = Vec::new();
    let mut iterations = 0;
    let mut best: Option<(Mechanism, Measured)> = None;
    for (idx, &k) in orders.iter().enumerate() {
        let lm = Lm {
            pts: &sub,
            k,
            opts,
            weights: None,
            grid: &grid,
            coverage_weights: None,
        };
        let mut phis: Vec<f64> = phis_all.iter().step_by(stride).copied().collect();
        let (fitted, it) = lm.run(with_order(&m, k), &mut phis);
        iterations += it;
        // Measure on every point.
        let measured = measure_from(&fitted, points, Some(&phis_all));
        let (rms, max) = (measured.rms_mm, measured.max_mm);
        scan.push([k as f64, rms, max]);
        let prev_rms = best.as_ref().map(|b| b.1.rms_mm);
        let new_phis = measured.carrier_angles_rad.clone();
        if prev_rms.is_none_or(|p| rms < p) {
            best = Some((fitted.clone(), measured));
        }
        let done = max <= opts.tol_mm
            || rms <= noise_floor_mm(opts.noise_sigma_mm, k, points.len())
            || prev_rms.is_some_and(|p| rms > 0.9 * p)
            || idx + 1 == orders.len();
        if done {
            break;
        }
        m = fitted;
        phis_all = new_phis;
    }
    let (mechanism, measured) = best.expect("at least one order is tried");
    Ok(Fitted::new(mechanism, measured, iterations, scan))
}

/// `start` made admissible (within `opts.limits`, at `opts.perimeter_mm` when set) and measured
/// on `points`, unfitted: a fit of zero iterations, the baseline a fit from it must beat.
#[must_use]
pub fn admitted(points: &[Point], start: &Mechanism, opts: &FitOptions) -> Fitted {
    let mut m = start.clone();
    solver::admit(&mut m, opts);
    let measured = measure_from(&m, points, None);
    Fitted::new(m, measured, 0, Vec::new())
}

/// The RMS point distance of a fit that follows the curve under noisy points exactly, mm: the
/// residual keeps the noise the `p = 4 + 2K` parameters cannot follow, `σ·√(1 − p/N)` (σ per
/// coordinate; [`crate::design::fit::noise`]). 0 on exact points (σ = 0).
fn noise_floor_mm(sigma_mm: f64, order: usize, points: usize) -> f64 {
    let p = fitted_parameters(order) as f64;
    sigma_mm * (1.0 - p / points.max(1) as f64).max(0.0).sqrt()
}

/// How far a train's traced curve is from the points.
#[derive(Debug, Clone)]
pub struct Measured {
    /// Carrier angle at which the tip passes closest to each point, rad.
    pub carrier_angles_rad: Vec<f64>,
    /// Distance of each point from the traced curve, mm.
    pub distances_mm: Vec<f64>,
    /// RMS point distance, mm.
    pub rms_mm: f64,
    /// Largest point distance, mm.
    pub max_mm: f64,
    /// Largest distance of the traced curve (1024 carrier angles) from the points' polyline, mm.
    pub coverage_mm: f64,
    /// The same beyond 0.6 of the nearest chord, mm ([`Fitted::coverage_excess_mm`]).
    pub coverage_excess_mm: f64,
}

/// Measures the curve traced by `m` against `points` (mm, relative to the carrier axis, solved
/// frame): each point projected from the nearest of 4096 curve samples.
#[must_use]
pub fn measure(points: &[Point], m: &Mechanism) -> Measured {
    measure_from(m, points, None)
}

/// [`measure`], also projecting from `tracked` angles; the distance is the Euclidean one at the
/// projected angle (never the normal component, which an unconverged projection would understate), (the closer projection wins: near a cusp the
/// nearest sample and the tracked angle can lead to different local minima).
fn measure_from(m: &Mechanism, points: &[Point], tracked: Option<&[f64]>) -> Measured {
    // The scan's samples also give the coverage (every few of them).
    let evals = curve_evals(m, INITIAL_SAMPLES);
    let fresh = initial_projections_on(m, &evals, points);
    let (carrier_angles_rad, distances_mm): (Vec<f64>, Vec<f64>) = points
        .par_iter()
        .zip(fresh)
        .enumerate()
        .map(|(j, (p, (a, ea)))| {
            let da = (ea.b - *p).norm();
            match tracked {
                Some(t) => {
                    let (b, eb) = project_near(m, *p, t[j], contact_guess(&evals, t[j]));
                    let db = (eb.b - *p).norm();
                    if db < da { (b, db) } else { (a, da) }
                }
                None => (a, da),
            }
        })
        .unzip();
    let rms_mm =
        (distances_mm.iter().map(|d| d * d).sum::<f64>() / distances_mm.len() as f64).sqrt();
    let max_mm = distances_mm.iter().copied().fold(0.0, f64::max);
    let grid = SegmentGrid::new(points);
    let (coverage_mm, coverage_excess_mm) = evals
        .par_iter()
        .step_by(INITIAL_SAMPLES / MEASURE_COVERAGE_SAMPLES)
        .map(|e| {
            let c = curve::coverage(&grid, e);
            (c.distance_mm, c.excess_mm())
        })
        .reduce(|| (0.0, 0.0), |a, b| (a.0.max(b.0), a.1.max(b.1)));
    Measured {
        carrier_angles_rad,
        distances_mm,
        rms_mm,
        max_mm,
        coverage_mm,
        coverage_excess_mm,
    }
}

impl Fitted {
    fn new(
        mechanism: Mechanism,
        m: Measured,
        iterations: usize,
        order_scan: Vec<[f64; 3]>,
    ) -> Self {
        Self {
            mechanism,
            carrier_angles_rad: m.carrier_angles_rad,
            distances_mm: m.distances_mm,
            rms_mm: m.rms_mm,
            max_mm: m.max_mm,
            coverage_mm: m.coverage_mm,
            coverage_excess_mm: m.coverage_excess_mm,
            iterations,
            order_scan,
        }
    }
}

/// Moves a least-squares fit towards the minimax fit (smallest largest deviation) for targets the
/// train cannot trace exactly: iteratively reweighted least squares with Lawson's weights
/// (`w_j ← w_j·|d_j|/max|d|`, normalised, floored at 1e-6; 12 passes of 10 iterations), at the
/// fit's order. Both sides of the Hausdorff distance are weighted: the points' distances from
/// the traced curve and the curve's 256 coverage samples' distances from the target polyline,
/// under one `max|d|` (with the points alone, a bulge of the curve between points goes unseen,
/// and designer targets end further behind an independent constrained optimum:
/// docs/performance.md, "Both sides of the minimax").
/// Keeps whichever result has the smaller `max(max_mm, coverage_mm)` (the Hausdorff distance to
/// the points' polyline); every iterate stays admissible.
#[must_use]
pub fn minimax(points: &[Point], fitted: Fitted, opts: &FitOptions) -> Fitted {
    minimax_passes(points, fitted, opts, MINIMAX_PASSES)
}

/// [`minimax`] with `passes` reweighting passes instead of 12 (a shorter finish, e.g. for a
/// warm re-design after a small edit).
#[must_use]
pub fn minimax_passes(
    points: &[Point],
    fitted: Fitted,
    opts: &FitOptions,
    passes: usize,
) -> Fitted {
    lawson(points, fitted, opts, passes, LawsonStart::Uniform)
}

/// [`minimax`] with its weights started from `start`'s distances (`LawsonStart::Distances`):
/// a second finish that lands in another basin where the train cannot trace the target (a
/// design for a module); neither finish is the better on every target (docs/performance.md,
/// "The second minimax finish"), so callers keep the better of the two.
#[must_use]
pub fn minimax_from_distances(points: &[Point], fitted: Fitted, opts: &FitOptions) -> Fitted {
    lawson(points, fitted, opts, MINIMAX_PASSES, LawsonStart::Distances)
}

/// Levenberg–Marquardt iterations per reweighting pass of [`minimax`].
pub(crate) const MINIMAX_ITERATIONS: usize = 10;

/// Reweighting passes of [`minimax`].
pub(crate) const MINIMAX_PASSES: usize = 12;

/// Every `stride`-th point, so that at most `opts.max_points` drive the iterations.
fn subsample(points: &[Point], opts: &FitOptions) -> (usize, Vec<Point>) {
    let stride = points.len().div_ceil(opts.max_points.max(16));
    (stride, points.iter().step_by(stride).copied().collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::fourier::SunRatio;
    use std::f64::consts::TAU;

    /// A three-harmonic train, the fixture of the fit's tests (also used by `curve`'s).
    pub(super) fn mech() -> Mechanism {
        Mechanism {
            a_mm: 44.0,
            l3_mm: 172.0,
            ratio: SunRatio::new(vec![0.25, 0.04, -0.02], vec![0.05, -0.03, 0.01]).unwrap(),
            sun_phase_rad: 0.4,
            needle_angle_rad: -1.1,
            idler_offset_rad: 0.0,
        }
    }

    #[test]
    fn fit_recovers_the_train_from_a_perturbed_start() {
        let truth = mech();
        let pts: Vec<Point> = (0..500)
            .map(|k| truth.tip(0.3 + TAU * k as f64 / 500.0))
            .collect();
        let mut start = truth.clone();
        start.a_mm += 0.5;
        start.l3_mm += 1.0;
        start.sun_phase_rad += 0.02;
        start.ratio = SunRatio::new(vec![0.2, 0.0, 0.0], vec![0.0, 0.0, 0.0]).unwrap();
        // At the true order the fit is exact (to the smoothness term); above it the invisible
        // re-timing directions (docs/math/chain.md §6.3) slow the last digits, far below the tolerance.
        let exact = FitOptions {
            order: Some(3),
            tol_mm: 1e-7,
            ..FitOptions::default()
        };
        let f = fit_points(&pts, &start, &exact).unwrap();
        assert!(f.max_mm < 1e-5, "{:?}", f.order_scan);
        // Default stopping: RMS below 1 % of the tolerance, or less than 1e-4 relative gain.
        let f = fit_points(&pts, &start, &FitOptions::default()).unwrap();
        assert!(f.max_mm < 1e-3, "{:?}", f.order_scan);
        assert!((f.mechanism.a_mm - 44.0).abs() < 1e-3 && (f.mechanism.l3_mm - 172.0).abs() < 1e-3);
    }
}
