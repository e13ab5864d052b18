//! docs/math/teeth.md §12.1 option 2: an integer tooth count by rescaling the ratio amplitude of the designed
//! mechanism at a fixed centre distance.
use super::TrainError;
use crate::geometry::fourier::SunRatio;
use crate::geometry::mechanism::Mechanism;
use crate::math::Point;
use crate::math::polyline::seg_dist;
use crate::math::roots::bracketed_root;
use rayon::prelude::*;
use std::f64::consts::{PI, TAU};

/// Result of [`rescale_ratio_amplitude`].
#[derive(Debug, Clone, PartialEq)]
pub struct AmplitudeFit {
    /// The mechanism with the rescaled ratio (same `a`, `l3`, γ, sun phase).
    pub mechanism: Mechanism,
    /// Tooth count.
    pub z: u32,
    /// Amplitude factor λ.
    pub lambda: f64,
    /// Sun perimeter `L(λ)` (= zπm to `accuracy_mm`), mm.
    pub perimeter_mm: f64,
}

pub(super) fn with_amplitude(mech: &Mechanism, lambda: f64) -> Mechanism {
    let k = |v: &[f64]| v.iter().map(|x| x * lambda).collect::<Vec<_>>();
    Mechanism {
        ratio: SunRatio::new_unchecked(
            k(mech.ratio.cos_coefficients()),
            k(mech.ratio.sin_coefficients()),
        ),
        ..mech.clone()
    }
}

/// docs/math/teeth.md §12.1 option 2: the amplitude λ of `i_λ = 1 + λ(i21 − 1)` with `a` held fixed such that
/// the sun perimeter `L(λ) = zπm`, z the achievable integer nearest to `L(1)/(πm)`.
///
/// `L(λ)` is sampled on `λ ∈ [0, λmax]` (`λmax` keeps `i_λ ≥ 0.05` and ≤ 4); the bracket
/// nearest to λ = 1 is refined by bisection to `accuracy_mm` in L. `L(0) = πa` (circle).
/// Errors: no integer z is achievable in that range (module too large for the curve).
pub fn rescale_ratio_amplitude(
    mech: &Mechanism,
    module_mm: f64,
    samples: usize,
    accuracy_mm: f64,
) -> Result<AmplitudeFit, TrainError> {
    let perimeter = |lambda: f64| -> Result<f64, TrainError> {
        Ok(with_amplitude(mech, lambda)
            .sun_curve(samples)?
            .perimeter_mm(0.1 * accuracy_mm))
    };
    let grid = 64;
    let (i_min, _) = mech
        .ratio
        .sampled_extreme(64 * mech.ratio.order() + 256, false);
    let lambda_max = if i_min < 1.0 {
        (0.95 / (1.0 - i_min)).min(4.0)
    } else {
        4.0
    };
    let lambdas: Vec<f64> = (0..=grid)
        .map(|k| lambda_max * k as f64 / f64::from(grid))
        .collect();
    let ls: Vec<f64> = lambdas
        .iter()
        .map(|&l| perimeter(l))
        .collect::<Result<_, _>>()?;
    let pm = PI * module_mm;
    let z_raw = perimeter(1.0)? / pm;
    // Candidate z values, nearest first; take the first with a bracket, nearest to λ = 1.
    let mut candidates: Vec<f64> = (0..40)
        .flat_map(|k| {
            [
                z_raw.round() + f64::from(k),
                z_raw.round() - f64::from(k + 1),
            ]
        })
        .filter(|z| *z >= 3.0)
        .collect();
    candidates.sort_by(|x, y| (x - z_raw).abs().total_cmp(&(y - z_raw).abs()));
    for z in candidates {
        let target = z * pm;
        let best = lambdas
            .windows(2)
            .zip(ls.windows(2))
            .filter(|(_, l)| (l[0] - target) * (l[1] - target) <= 0.0)
            .min_by(|(x, _), (y, _)| {
                (0.5 * (x[0] + x[1]) - 1.0)
                    .abs()
                    .total_cmp(&(0.5 * (y[0] + y[1]) - 1.0).abs())
            });
        if let Some((lam, _)) = best {
            // A failing sample (cannot happen for i_λ ≥ 0.05) reads as NaN and is caught below.
            let lambda = bracketed_root(
                |l| perimeter(l).map_or(f64::NAN, |v| v - target),
                lam[0],
                lam[1],
                1e-14,
            );
            let mechanism = with_amplitude(mech, lambda);
            let perimeter_mm = mechanism
                .sun_curve(samples)?
                .perimeter_mm(0.1 * accuracy_mm);
            return Ok(AmplitudeFit {
                mechanism,
                z: z as u32,
                lambda,
                perimeter_mm,
            });
        }
    }
    Err(TrainError::InvalidOption {
        name: "module_mm",
        value: module_mm,
        expected: "a module for which some integer tooth count is reachable by rescaling the \
                   ratio amplitude (L(λ) ranges between the circle πa and the largest amplitude)",
    })
}

/// Sun phases and needle angles of the coarse grid of [`refit_needle_and_phase`] (10° apart).
const GRID: usize = 36;
/// Carrier angles traced, and at most as many target points used, per candidate of the coarse
/// grid.
const COARSE_SAMPLES: usize = 128;
/// The same for the local search.
const FINE_SAMPLES: usize = 512;
/// Smallest step of the local search, rad (0.017 mm of tip motion on a 170 mm needle).
const MIN_STEP_RAD: f64 = 1e-4;

/// Hausdorff distance (mm) between the path `m` traces at `n` uniform carrier angles and the
/// closed polyline `points` (solved frame), every point against every segment: the bucketed
/// [`crate::math::polyline::hausdorff_mm`] slows down on curves tens of mm apart, which most
/// candidates are.
fn path_distance(m: &Mechanism, n: usize, points: &[Point]) -> f64 {
    let theta3 = m.planet_orientations_uniform(n);
    let tips: Vec<Point> = theta3
        .iter()
        .enumerate()
        .map(|(k, t3)| {
            let (phi, beta) = (TAU * k as f64 / n as f64, t3 + m.needle_angle_rad);
            Point::new(
                m.l1_mm() * phi.cos() + m.l3_mm * beta.cos(),
                m.l1_mm() * phi.sin() + m.l3_mm * beta.sin(),
            )
        })
        .collect();
    let directed = |p: &[Point], q: &[Point]| {
        p.iter()
            .map(|x| {
                (0..q.len())
                    .map(|j| seg_dist(*x, q[j], q[(j + 1) % q.len()]))
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max)
    };
    directed(&tips, points).max(directed(points, &tips))
}

/// Every `⌈len/n⌉`-th point: at most `n` of them, in order.
fn thinned(points: &[Point], n: usize) -> Vec<Point> {
    points
        .iter()
        .step_by(points.len().div_ceil(n).max(1))
        .copied()
        .collect()
}

/// The needle angle γ and the sun phase φ_ref of a mechanism whose ratio was rescaled
/// ([`rescale_ratio_amplitude`]), re-fitted to the target points (mm, relative to the carrier
/// axis, solved frame: CCW) with the ratio, `a` and `l3` kept.
///
/// Minimises the Hausdorff distance between the traced path and the points' closed polyline:
/// a 10° grid over (φ_ref, γ) on 128 carrier angles and at most 128 of the points, then a
/// compass search on 512 carrier angles and at most 512 points from the best cell, steps halved
/// from 5° to 1e-4 rad. Returns the mechanism and its distance on those samples, mm (the
/// toothed train's round trip measures the final path).
#[must_use]
pub fn refit_needle_and_phase(rescaled: &Mechanism, points: &[Point]) -> (Mechanism, f64) {
    let with = |phase: f64, gamma: f64| Mechanism {
        sun_phase_rad: phase,
        needle_angle_rad: gamma,
        ..rescaled.clone()
    };
    let angle = |k: usize| TAU * k as f64 / GRID as f64;
    let (coarse, fine) = (
        thinned(points, COARSE_SAMPLES),
        thinned(points, FINE_SAMPLES),
    );
    let cells: Vec<(usize, usize)> = (0..GRID)
        .flat_map(|i| (0..GRID).map(move |j| (i, j)))
        .collect();
    let (_, start) = cells
        .into_par_iter()
        .map(|(i, j)| {
            let m = with(
                rescaled.sun_phase_rad + angle(i),
                rescaled.needle_angle_rad + angle(j),
            );
            (path_distance(&m, COARSE_SAMPLES, &coarse), m)
        })
        .min_by(|x, y| x.0.total_cmp(&y.0))
        .unwrap_or_else(|| (f64::INFINITY, rescaled.clone()));
    let mut best = (start.clone(), path_distance(&start, FINE_SAMPLES, &fine));
    let mut step = 5f64.to_radians();
    while step > MIN_STEP_RAD {
        let (p, g) = (best.0.sun_phase_rad, best.0.needle_angle_rad);
        let improved = [(p + step, g), (p - step, g), (p, g + step), (p, g - step)]
            .into_par_iter()
            .map(|(p, g)| {
                let m = with(p, g);
                let s = path_distance(&m, FINE_SAMPLES, &fine);
                (m, s)
            })
            .filter(|(_, s)| *s < best.1)
            .min_by(|x, y| x.1.total_cmp(&y.1));
        match improved {
            Some(b) => best = b,
            None => step *= 0.5,
        }
    }
    best
}
