//! Step 1: static trajectory → arm lengths `l1`, `l3`, the carrier angle of every trajectory point
//! and the needle's relative rotation `ψ3(t)` (docs/math/chain.md §3).
//!
//! Closed-form two-circle inversion (docs/math/chain.md §3.3): with `ρ(s) = |P(s)|`, `θ(s) = atan2 P(s)`,
//!
//! ```text
//! q(s)  = (l1² + ρ² − l3²) / (2 l1 ρ),    δ(s) = arccos q(s) ∈ [0, π]
//! φH(s) = unwrap( θ(s) + σ(s)·δ(s) ),     σ = +1 from s_max to s_min (travel order), −1 after
//! β(s)  = atan2( P(s) − l1·e(φH(s)) ),     ψ3(t) = t − (β − β0),   t = φH − φH0
//! ```
//!
//! `l1 = (ρmax − ρmin)/2`, `l3 = (ρmax + ρmin)/2` (winding number 0, docs/math/chain.md §3.2). The reference instant
//! `t = 0` is the ρmax instant, where the needle is collinear with OA (`β0 = φH0`).
//! `ψ3` is resampled on a uniform grid of `N` carrier angles by solving `φH(s) = φH0 + t_n` on the
//! interpolant itself (no second interpolation), so its error is the spline's, O(h⁴) (docs/math/chain.md §3.5).

pub mod compat;
pub mod needle_law;

use crate::math::Point;
mod frame;

use crate::design::inverse::needle_law::NeedleLaw;
use crate::design::trajectory::{ClosedSpline, Trajectory};
use frame::{Solved, coarse_rejects, dense_count, solve_frame, winding_number};

/// Accuracy knobs of the inversion (docs/math/chain.md §13).
#[derive(
    Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct InverseOptions {
    /// Dense samples of the interpolant used to locate extremes and check monotonicity (`n_s`). Default 20 000.
    pub dense_samples: usize,
    /// Uniform carrier-angle grid size `N` for ψ3 (FFT size). Default 1024.
    pub grid: usize,
    /// Tolerance on the spline parameter when solving for extremes and carrier angles, in units
    /// of the trajectory length. Default 1e-14.
    pub tol_relative: f64,
    /// Low-pass the needle law `ψ3 − t` to this many harmonics (for measured, noisy data: the
    /// inversion amplifies noise near the extremes, docs/math/chain.md §3.5); `None` (default) keeps it as computed.
    pub law_harmonics: Option<usize>,
    /// Carrier sense to design for: `Some(1)` CCW, `Some(-1)` CW; `None` (default) tries both and
    /// keeps the law the train realises best when both trace the path.
    pub sense: Option<i8>,
}

crate::builder::with_fields!(InverseOptions {
    with_dense_samples => dense_samples: usize,
    with_grid => grid: usize,
    with_tol_relative => tol_relative: f64,
    with_law_harmonics => law_harmonics: Option<usize>,
    with_sense => sense: Option<i8>,
});

impl Default for InverseOptions {
    fn default() -> Self {
        Self {
            dense_samples: 20_000,
            grid: 1024,
            tol_relative: 1e-14,
            law_harmonics: None,
            sense: None,
        }
    }
}

/// Why no mechanism with constant `l1`, `l3` can trace a trajectory. Angles are carrier angles in
/// degrees in the file's frame.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum InverseError {
    /// The carrier axis is too far from the trajectory.
    #[error(
        "the carrier axis O is {distance_mm:.4e} mm from the farthest trajectory point, more than {limit_mm:.1} mm (20 × the trajectory's size): check the carrier axis position (`center_mm`, in mm like the points)"
    )]
    AxisTooFar {
        /// Largest distance of a point from O, mm.
        distance_mm: f64,
        /// The limit, mm.
        limit_mm: f64,
    },
    /// The carrier axis is inside the loop.
    #[error(
        "the carrier axis O lies inside the loop (winding number {winding}); a transplanter needs O outside the loop (l3 > l1): check the carrier axis position (`center_mm`)"
    )]
    AxisInsideLoop {
        /// Winding number of the loop about O.
        winding: i64,
    },
    /// The largest distance from O is reached at several separate places.
    #[error(
        "the largest distance from O ({rho_max_mm:.4} mm) is reached at {count} separate places (points near {at:?} mm); the needle tip of a constant-length arm reaches its farthest point exactly once per turn"
    )]
    SeveralMaxima {
        /// ρmax, mm.
        rho_max_mm: f64,
        /// Number of separate maxima.
        count: usize,
        /// Their positions, mm (file frame).
        at: Vec<Point>,
    },
    /// Some point is too close to the carrier axis.
    #[error(
        "the trajectory comes within {rho_min_mm:.3} mm of the carrier axis, below 5 % of l3 ({limit_mm:.3} mm); the inversion is ill-conditioned there (docs/math/chain.md §14): move the carrier axis (`center_mm`) or the trajectory"
    )]
    TooCloseToAxis {
        /// ρmin, mm.
        rho_min_mm: f64,
        /// Limit, mm.
        limit_mm: f64,
    },
    /// The carrier sense asked for cannot trace the path.
    #[error(
        "a carrier turning {} cannot trace this path (in that sense the carrier angle does not advance steadily by one turn along the points), the other sense can: leave the sense to be chosen (`--sense auto`) or give the other one",
        if *sense > 0 { "CCW" } else { "CW" }
    )]
    SenseNotTraceable {
        /// The sense asked for: +1 CCW, −1 CW.
        sense: i8,
    },
    /// The carrier angle is not monotone along the trajectory.
    #[error("no arm with constant l1 = {l1_mm:.3} mm and l3 = {l3_mm:.3} mm can trace this path: the carrier angle would have to run backwards on {} stretch(es), carrier angles (deg) {stretches_deg:?} (monotonicity criterion, docs/math/chain.md §3.3); redraw those parts (the points as read and smoothed copies of them were tried)", stretches_deg.len())]
    NotMonotone {
        /// l1, mm.
        l1_mm: f64,
        /// l3, mm.
        l3_mm: f64,
        /// Offending stretches `[from, to]`, carrier degrees.
        stretches_deg: Vec<[f64; 2]>,
    },
    /// The needle would have to turn against the gears.
    #[error(
        "the needle would have to turn faster than the carrier (i31 ≤ 0) on carrier angles (deg) {stretches_deg:?}; gear ratios are positive, so no gear train can do this: flatten the needle swing there"
    )]
    NeedleReverses {
        /// Offending stretches `[from, to]`, carrier degrees.
        stretches_deg: Vec<[f64; 2]>,
    },
}

/// Result of step 1, in the solved frame: relative to the carrier axis, mirrored when the carrier
/// turns clockwise (docs/math/chain.md §1: solve CCW, mirror back).
#[derive(Debug, Clone)]
pub struct Inversion {
    /// Carrier arm length `l1 = |OA|`, mm.
    pub l1_mm: f64,
    /// Needle length `l3 = |AB|`, mm.
    pub l3_mm: f64,
    /// Largest distance of the tip from O, mm.
    pub rho_max_mm: f64,
    /// Smallest distance of the tip from O, mm.
    pub rho_min_mm: f64,
    /// +1 when the carrier turns CCW in the file frame, −1 when CW (solved mirrored).
    pub direction: i8,
    /// Carrier angle at the ρmax instant (reference instant `t = 0`), rad, solved frame.
    pub phi_h0_rad: f64,
    /// Needle rotation relative to the carrier.
    pub law: NeedleLaw,
    /// The trajectory points relative to O in the solved frame, mm.
    pub points: Vec<Point>,
    /// Whether the other carrier sense (with the arm's elbow flipped) also traces the path.
    pub other_sense_traceable: bool,
}

impl Inversion {
    /// Target needle direction `β(φH) = φH0 − p(φH − φH0)` (rad, solved frame).
    #[must_use]
    pub fn beta(&self, phi_h: f64) -> f64 {
        let t = phi_h - self.phi_h0_rad;
        self.phi_h0_rad + t - self.law.psi3(t)
    }

    /// Target tip position at carrier angle `φH` (rad), mm, solved frame:
    /// `B = l1·e(φH) + l3·e(β(φH))`.
    #[must_use]
    pub fn tip(&self, phi_h: f64) -> Point {
        let b = self.beta(phi_h);
        Point::new(
            self.l1_mm * phi_h.cos() + self.l3_mm * b.cos(),
            self.l1_mm * phi_h.sin() + self.l3_mm * b.sin(),
        )
    }

    /// Converts a solved-frame angle (rad) to file-frame degrees in [0, 360).
    #[must_use]
    pub fn file_angle_deg(&self, angle_rad: f64) -> f64 {
        (f64::from(self.direction) * angle_rad)
            .to_degrees()
            .rem_euclid(360.0)
    }
}

/// Runs step 1 on a trajectory with carrier axis `center` (mm).
pub fn invert(
    traj: &Trajectory,
    center: Point,
    opts: &InverseOptions,
) -> Result<Inversion, InverseError> {
    let pts = traj.relative_to(center, false);
    // An axis far from the loop makes arms of metres for a loop of centimetres (and, farther,
    // numbers past what a spline can hold): refused before any work.
    let [x0, y0, x1, y1] = crate::math::polyline::bbox(&pts);
    let size = (x1 - x0).hypot(y1 - y0);
    let far = pts.iter().map(|p| p.hypot()).fold(0.0, f64::max);
    if !(far <= MAX_AXIS_DISTANCE_SIZES * size) {
        return Err(InverseError::AxisTooFar {
            distance_mm: far,
            limit_mm: MAX_AXIS_DISTANCE_SIZES * size,
        });
    }
    let winding = winding_number(&pts);
    if winding != 0 {
        return Err(InverseError::AxisInsideLoop { winding });
    }
    // Both senses are tried: the "elbow-flipped" arm (A reflected across OB) of a CW mechanism can
    // trace the same path CCW. When both are valid, the law that the train can realise best
    // (smaller compatibility residual, docs/math/chain.md §6.4) wins and the other is flagged.
    // The two senses are independent: solved side by side.
    let mirrored = traj.relative_to(center, true);
    // A frame whose coarse pass already shows the carrier running backwards or the wrong way
    // is left at that when the other frame succeeds; it is solved in full otherwise, for its
    // diagnosis.
    let (sa, sb) = rayon::join(
        || ClosedSpline::through(&pts),
        || ClosedSpline::through(&mirrored),
    );
    let ns = dense_count(opts, pts.len());
    let rejects = |s: &ClosedSpline| coarse_rejects(s, ns, opts.tol_relative * s.period());
    type Frame = Result<Solved, InverseError>;
    let solve_a = || solve_frame(&sa, &pts, opts, 1, center);
    let solve_b = || solve_frame(&sb, &mirrored, opts, -1, center);
    // A lone survivor is solved on its own, so that its parallel loops have every core; the
    // rejected frame only when the survivor fails (for its diagnosis).
    let survivor_first = |first: &dyn Fn() -> Frame, other: &dyn Fn() -> Frame| {
        let f = first();
        let o = if matches!(f, Ok(Solved::Done(_))) {
            Ok(Solved::Skipped)
        } else {
            other()
        };
        (f, o)
    };
    // A sense asked for: that frame alone, its own diagnosis when it fails.
    // A sense asked for: that frame; when it fails and the other sense traces the path, the
    // refusal names the sense, else the frame's own diagnosis.
    if let Some(sense) = opts.sense {
        let (mine, other): (&dyn Fn() -> Frame, &dyn Fn() -> Frame) = if sense > 0 {
            (&solve_a, &solve_b)
        } else {
            (&solve_b, &solve_a)
        };
        let not_this_sense = InverseError::SenseNotTraceable { sense };
        return match mine() {
            Ok(Solved::Done(inv)) => Ok(*inv),
            _ if matches!(other(), Ok(Solved::Done(_))) => Err(not_this_sense),
            Ok(Solved::WrongSense(e)) | Err(e) => Err(e),
            Ok(Solved::Skipped) => unreachable!("a frame solved on its own is never skipped"),
        };
    }
    let (ccw, cw) = match rayon::join(|| rejects(&sa), || rejects(&sb)) {
        (false, true) => survivor_first(&solve_a, &solve_b),
        (true, false) => {
            let (b, a) = survivor_first(&solve_b, &solve_a);
            (a, b)
        }
        _ => rayon::join(solve_a, solve_b),
    };
    match (ccw, cw) {
        (Ok(Solved::Done(mut a)), Ok(Solved::Done(mut b))) => {
            let ea = crate::design::inverse::compat::analyse(&a.law, 256, 1e-10).residual_rad;
            let eb = crate::design::inverse::compat::analyse(&b.law, 256, 1e-10).residual_rad;
            a.other_sense_traceable = true;
            b.other_sense_traceable = true;
            Ok(if eb < ea { *b } else { *a })
        }
        (Ok(Solved::Done(a)), _) => Ok(*a),
        (_, Ok(Solved::Done(b))) => Ok(*b),
        (Err(e), _) => Err(e),
        (Ok(Solved::WrongSense(_)), Err(e)) => Err(e),
        (Ok(Solved::WrongSense(e)), Ok(Solved::WrongSense(_))) => Err(e),
        (Ok(Solved::Skipped), _) | (_, Ok(Solved::Skipped)) => {
            unreachable!("a skipped frame is solved in full when the other one fails")
        }
    }
}

/// Farthest a trajectory point may lie from the carrier axis, in trajectory sizes (the diagonal
/// of its bounding box): a tenth of that is already an arm ten times the loop.
pub const MAX_AXIS_DISTANCE_SIZES: f64 = 20.0;

/// Closest approach of the trajectory to the carrier axis, `ρ_min = l3 − l1`, in units of `l3`:
/// nearer, the inversion is ill-conditioned (docs/math/chain.md §14) and refused.
pub const MIN_AXIS_DISTANCE_L3: f64 = 0.05;

#[cfg(test)]
mod tests {
    use super::frame::{arm_direction, carrier_angle};
    use crate::math::Point;
    use crate::math::periodic::wrap_pi;
    use std::f64::consts::TAU;

    #[test]
    fn algebraic_arm_direction_is_the_two_circle_solution() {
        // The elbow A = l1·e(φH) lies l1 from O and l3 from the tip, on the side σ says, and φH
        // is the closed form atan2 P + σ·arccos q of docs/math/chain.md §3.3.
        let (l1, l3) = (60.0, 200.0);
        for k in 0..2000 {
            let t = TAU * f64::from(k) / 2000.0;
            let rho = 150.0 + 100.0 * (0.5 + 0.5 * (3.0 * t).sin()); // within [l3 − l1, l3 + l1]
            let p = Point::new(rho * t.cos(), rho * t.sin());
            for sigma in [1.0, -1.0] {
                let e = arm_direction(p, l1, l3, sigma);
                let a = e * l1;
                assert!((e.norm() - 1.0).abs() < 1e-14);
                assert!(((p - a).norm() - l3).abs() < 1e-11);
                let q = ((l1 * l1 + rho * rho - l3 * l3) / (2.0 * l1 * rho)).clamp(-1.0, 1.0);
                let closed = p.atan2() + sigma * q.acos();
                assert!(wrap_pi(carrier_angle(p, l1, l3, sigma) - closed).abs() < 1e-12);
            }
        }
        // At the extremes (q = ±1) both sides meet on the ray through the tip.
        let e = arm_direction(Point::new(260.0, 0.0), l1, l3, 1.0);
        assert_eq!(e, arm_direction(Point::new(260.0, 0.0), l1, l3, -1.0));
        assert!((e.x - 1.0).abs() < 1e-15 && e.y.abs() < 1e-15);
    }
}
