//! Re-designing from an earlier design: the edit loop of an interactive designer (the entry
//! beside [`design`](crate::design::design); its warm start is [`crate::design::strategy::warm`]).

use crate::design::report::DesignReport;
use crate::design::{Design, DesignError, DesignOptions, trajectory::Trajectory};

/// The design of `traj` started from `start` (an earlier `design.json` of a nearby target, e.g.
/// before an edit), with `opts` as [`design`](crate::design::design) takes them: the edit loop of
/// an interactive designer.
///
/// A trajectory edited by hand is no longer exactly traceable, and the full search of the fit
/// stage (restarts, continuation, minimax finish; [`crate::design::fit::fit_with_restarts`]) takes up to a
/// second on such a target. An edit moves the target by a little, so the design before the edit
/// is a start inside the right basin: [`redesign`] runs the chain as [`design`](crate::design::design)
/// does — step 1, the patent route, the same gear limits, checks and round trip — but replaces
/// the fit stage by one Levenberg–Marquardt fit from that design's train, at its Fourier order
/// (and, designing for a module, at its tooth count: the perimeter `zπm` held), finished by
/// [`crate::design::strategy::warm::WARM_MINIMAX_PASSES`] reweighting passes towards the minimax fit on clean points (the full
/// search runs 12). The result is a local optimum near the start, so its largest deviation may
/// exceed the full design's (on 60 cumulative edits of the G1 target by bumps of up to 1 mm:
/// 0.96 mm against the full search's 0.74 mm at the end); running [`design`](crate::design::design) on
/// the same points gives that one.
///
/// The start is used only when it fits the new target: same carrier sense, an order the fit
/// accepts; otherwise (and when the patent route alone is within the tolerance, as on an exact
/// target) the result is exactly [`design`](crate::design::design)'s.
///
/// ```
/// use ncgear::{DesignOptions, Trajectory, design};
/// use ncgear::design::redesign;
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
/// Errors: those of [`design`](crate::design::design).
pub fn redesign(
    traj: &Trajectory,
    opts: &DesignOptions,
    start: &DesignReport,
) -> Result<Design, DesignError> {
    crate::design::chain::design_from(traj, opts, Some(start))
}
