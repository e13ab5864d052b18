//! Re-designing from an earlier design: the edit loop of an interactive designer.
//!
//! A trajectory edited by hand is no longer exactly traceable, and the full search of the fit
//! stage (restarts, continuation, minimax finish; [`crate::design::fit::fit_with_restarts`]) takes up to a
//! second on such a target. An edit moves the target by a little, so the design before the edit
//! is a start inside the right basin: [`redesign`] runs the chain as [`design`](super::design)
//! does — step 1, the patent route, the same gear limits, checks and round trip — but replaces
//! the fit stage by one Levenberg–Marquardt fit from that design's train, at its Fourier order
//! (and, designing for a module, at its tooth count: the perimeter `zπm` held), finished by
//! [`WARM_MINIMAX_PASSES`] reweighting passes towards the minimax fit on clean points (the full
//! search runs 12). The result is a local optimum near the start, so its largest deviation may
//! exceed the full design's (on 60 cumulative edits of the G1 target by bumps of up to 1 mm:
//! 0.96 mm against the full search's 0.74 mm at the end); running [`design`](super::design) on
//! the same points gives that one.
//!
//! The start is used only when it fits the new target: same carrier sense, an order the fit
//! accepts; otherwise (and when the patent route alone is within the tolerance, as on an exact
//! target) the result is exactly [`design`](super::design)'s.

use super::fit::{FitOptions, Fitted, MEASURED_NOISE_MM, fit_points, minimax_passes};
use super::report::DesignReport;
use super::{Design, DesignError, DesignOptions, trajectory::Trajectory};
use crate::geometry::fourier::SunRatio;
use crate::geometry::mechanism::Mechanism;
use crate::math::Point;
use std::f64::consts::PI;

/// Levenberg–Marquardt iterations of the warm fit (the full search allows 40 per order).
pub const WARM_ITERATIONS: usize = 20;

/// Reweighting passes of the warm fit's minimax finish on clean points (the full search: 12).
pub const WARM_MINIMAX_PASSES: usize = 2;

/// The design of `traj` started from `start` (an earlier `design.json` of a nearby target, e.g.
/// before an edit), with `opts` as [`design`](super::design) takes them (module documentation).
///
/// ```
/// use ncgear::{DesignOptions, Trajectory, design};
/// use ncgear::design::warm::redesign;
/// use ncgear::geometry::golden::g1_mechanism;
/// let g1 = g1_mechanism();
/// let pts: Vec<ncgear::math::Point> = (0..360).map(|k| g1.tip((k as f64).to_radians())).collect();
/// let first = design(&Trajectory::from_points(pts.clone())?, &DesignOptions::default())?;
/// // The target moved by a bump of 0.3 mm around one point: the edit re-designs from `first`.
/// let moved: Vec<ncgear::math::Point> = pts
///     .iter()
///     .enumerate()
///     .map(|(k, p)| {
///         let w = 0.3 * (-((k as f64 - 90.0) / 8.0).powi(2)).exp();
///         *p + ncgear::math::Point::new(w, 0.0)
///     })
///     .collect();
/// let d = redesign(&Trajectory::from_points(moved)?, &DesignOptions::default(), &first.report)?;
/// assert!(d.report.roundtrip.max_deviation_mm < 0.3);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// Errors: those of [`design`](super::design).
pub fn redesign(
    traj: &Trajectory,
    opts: &DesignOptions,
    start: &DesignReport,
) -> Result<Design, DesignError> {
    super::chain::design_from(traj, opts, Some(start))
}

/// The train of `report` in the solved frame of a target whose carrier turns `direction`
/// (+1 CCW, −1 CW); `None` when the report's carrier sense differs or its ratio is not valid.
pub(super) fn start_mechanism(report: &DesignReport, direction: i8) -> Option<Mechanism> {
    if report.carrier.direction != direction {
        return None;
    }
    let f = &report.fourier;
    let ratio = SunRatio::new(f.a.clone(), f.b.clone()).ok()?;
    let sense = f64::from(direction);
    let m = Mechanism {
        a_mm: report.center_distance_mm,
        l3_mm: report.l3_mm,
        ratio,
        // The report's angles are file-frame degrees: the solved angle times the sense.
        sun_phase_rad: sense * f.sun_phase_deg.to_radians(),
        needle_angle_rad: sense * report.needle_angle_deg.to_radians(),
        idler_offset_rad: sense * report.idler_offset_deg.to_radians(),
    };
    (m.a_mm.is_finite() && m.a_mm > 0.0 && m.l3_mm.is_finite() && m.l3_mm > 0.0).then_some(m)
}

/// One fit of `points` (solved frame) from `start` at its order, under `base`'s limits; with
/// `teeth` = `(z, m)` the perimeter is held at `zπm`.
pub(super) fn warm_fit(
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
