//! The warm start of a re-design ([`crate::design::redesign`]): an earlier design's train in the
//! solved frame of a new target, and the one fit from it that replaces the fit stage's search —
//! Levenberg–Marquardt at the start's Fourier order (and, designing for a module, at its tooth
//! count: the perimeter `zπm` held), finished by [`WARM_MINIMAX_PASSES`] reweighting passes
//! towards the minimax fit on clean points (the full search runs 12).

use crate::design::fit::{FitOptions, Fitted, MEASURED_NOISE_MM, fit_points, minimax_passes};
use crate::geometry::mechanism::Mechanism;
use crate::math::Point;
use std::f64::consts::PI;

/// Levenberg–Marquardt iterations of the warm fit (the full search allows 40 per order).
pub const WARM_ITERATIONS: usize = 20;

/// Reweighting passes of the warm fit's minimax finish on clean points (the full search: 12).
pub const WARM_MINIMAX_PASSES: usize = 2;

/// One fit of `points` (solved frame) from `start` at its order, under `base`'s limits; with
/// `teeth` = `(z, m)` the perimeter is held at `zπm`.
pub(in crate::design) fn warm_fit(
    points: &[Point],
    start: &Mechanism,
    base: &FitOptions,
    teeth: Option<(u32, f64)>,
) -> Option<Fitted> {
    let opts = FitOptions {
        order: Some(start.ratio.order()),
        max_iterations: WARM_ITERATIONS,
        perimeter_mm: teeth.map(|(z, m)| f64::from(z) * PI * m),
        // A train off the carrier line is refitted with its offset free.
        free_idler_offset: base.free_idler_offset || start.idler_offset_rad != 0.0,
        ..base.clone()
    };
    let f = fit_points(points, start, &opts).ok()?;
    if opts.noise_sigma_mm > MEASURED_NOISE_MM {
        return Some(f);
    }
    Some(minimax_passes(points, f, &opts, WARM_MINIMAX_PASSES))
}
