//! Stage B of the synthesis: the carrier sense, the carrier angle of each pose, and the smoothest
//! sun ratio whose train turns the needle into every pose's direction.
//!
//! With the dyad fixed, pose k is reached at carrier angle `φ_k = arg(A_k − O)`. The poses are
//! in travel order, so the carrier sense is the one in which the `φ_k` advance by exactly one turn
//! around the cycle (checked first: poses out of order are refused). In the solved frame (relative
//! to O, CCW; a CW carrier is mirrored in y, angles negated) the train's needle direction is
//! `β(φ) = φ + π − S(φ − u0) + γ` ([`Mechanism::needle_direction`], `S` the half-turn map of the
//! sun ratio `i21 = 1 + Σ a_j cos ju + b_j sin ju`), so the pose equations are
//!
//! ```text
//! β(φ_k) = θ_k  (mod 2π),   k = 1…K,
//! ```
//!
//! in the unknowns `a_j, b_j` (j ≤ N), the sun phase `u0` and the needle angle `γ`: fewer
//! equations than unknowns for the usual orders, so the ratio is chosen smoothest — the pose
//! residuals divided by their tolerance (exact poses: [`POSE_TOL_RAD`]) and the smoothness rows
//! `λ·j²·(a_j, b_j)` minimised together by Levenberg–Marquardt (numerical Jacobian), from four
//! sun phases, the pose rows tightened in steps (a continuation: the smoothness rows steer while
//! the poses are loose); the best is kept. Every candidate is a sun ratio, so every candidate is a train
//! (docs/math/chain.md §6: the planet law follows from the sun), i21 > 0 by construction.

use super::dyad::{Dyad, Pose};
use crate::geometry::fourier::SunRatio;
use crate::geometry::limits::{GearLimits, constraint_values};
use crate::geometry::mechanism::Mechanism;
use crate::math::least_squares::{LmOptions, Residuals, levenberg_marquardt};
use nalgebra::DVector;
use std::f64::consts::{PI, TAU};

/// Needle-direction tolerance standing for an exact pose, rad (1e-6°).
pub const POSE_TOL_RAD: f64 = 1e-6 * PI / 180.0;

/// Relative margin kept inside the gear limits by the timing (the design chain's projection keeps
/// a smaller one, so a timing within this margin is taken as it is).
pub const LIMIT_MARGIN: f64 = 0.02;

/// Weight λ of the smoothness rows `λ·j²·(a_j, b_j)`.
const SMOOTHNESS: f64 = 1e-2;

/// Floors of the pose tolerance, rad, one Levenberg–Marquardt run each: from 0.6° down to the
/// exact poses' [`POSE_TOL_RAD`].
const CONTINUATION_RAD: [f64; 5] = [1e-2, 1e-3, 1e-4, 1e-6, POSE_TOL_RAD];

/// The timing of a train through the poses.
#[derive(Debug, Clone)]
pub struct Timing {
    /// +1 CCW, −1 CW.
    pub direction: i8,
    /// Carrier angle of each pose in the solved frame (CCW from the first pose's), rad.
    pub carrier_angles_rad: Vec<f64>,
    /// The train, solved frame (relative to O, CCW).
    pub mechanism: Mechanism,
    /// Each pose's needle-direction residual of the fit, rad.
    pub residuals_rad: Vec<f64>,
}

/// Why no timing could be found.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum TimingError {
    /// The poses are not in travel order for any carrier sense.
    #[error(
        "the poses are not in travel order: their carrier angles (deg, in the order given) {angles_deg:?} go round the axis {turns} times counter-clockwise; reorder the poses along the path"
    )]
    TravelOrder {
        /// Carrier angles of the poses, degrees.
        angles_deg: Vec<f64>,
        /// Turns made in the CCW reading.
        turns: i64,
    },
    /// The needle directions ask for a planet turning backwards, or for more or less than one
    /// relative turn per carrier turn, between two poses (i31 ≤ 0 somewhere).
    #[error(
        "the needle directions of the poses make the needle turn {turns_deg:.1}° relative to the carrier over one carrier turn; a planet that never turns back (i31 > 0) turns exactly 360°: check the needle directions of poses {poses:?} (the pairs whose relative turn is largest)"
    )]
    PlanetTurns {
        /// The relative turn the poses ask for over the cycle, degrees (a multiple of 360).
        turns_deg: f64,
        /// The pose pairs `(k, k + 1)` with the largest relative turns.
        poses: Vec<(usize, usize)>,
    },
    /// Between two poses the mean planet ratio is outside what the sun ratio bounds allow.
    #[error(
        "poses {from} → {to}: the needle turns {psi_deg:.2}° relative to the carrier while the carrier turns {phi_deg:.2}°, a mean planet ratio i31 = {ratio:.4} outside [{min:.4}, {max:.4}] (the sun ratio bounds i21 ∈ [{i_min}, {i_max}], i31 = i21(t)/i21(S(t))): move the poses or their needle directions"
    )]
    PlanetRatio {
        /// First pose of the pair.
        from: usize,
        /// Second pose of the pair.
        to: usize,
        /// Relative needle turn asked for, degrees.
        psi_deg: f64,
        /// Carrier turn between the poses, degrees.
        phi_deg: f64,
        /// Their ratio.
        ratio: f64,
        /// Smallest reachable mean i31, `i_min/i_max`.
        min: f64,
        /// Largest reachable mean i31, `i_max/i_min`.
        max: f64,
        /// Sun ratio lower bound.
        i_min: f64,
        /// Sun ratio upper bound.
        i_max: f64,
    },
    /// The sense asked for is not the poses' travel sense.
    #[error("the poses run {found} round the carrier axis, but the carrier was set to {asked}")]
    Sense {
        /// The sense of the poses.
        found: &'static str,
        /// The sense asked for.
        asked: &'static str,
    },
}

/// The carrier sense of `poses` reached by `dyad` in travel order (`sense` asked for, or either),
/// and the carrier angles in the solved frame, unwrapped from the first pose.
pub fn carrier_angles(
    poses: &[Pose],
    dyad: &Dyad,
    sense: Option<i8>,
) -> Result<(i8, Vec<f64>), TimingError> {
    let phi = dyad.carrier_angles_rad(poses);
    let k = phi.len();
    let step = |i: usize, s: f64| (s * (phi[(i + 1) % k] - phi[i])).rem_euclid(TAU);
    let turns = |s: f64| ((0..k).map(|i| step(i, s)).sum::<f64>() / TAU).round() as i64;
    let name = |d: i8| if d > 0 { "CCW" } else { "CW" };
    let found = match (turns(1.0), turns(-1.0)) {
        (1, _) => 1,
        (_, 1) => -1,
        (t, _) => {
            return Err(TimingError::TravelOrder {
                angles_deg: phi.iter().map(|p| p.to_degrees()).collect(),
                turns: t,
            });
        }
    };
    let direction = match sense {
        Some(s) if s != found && k != 2 => {
            return Err(TimingError::Sense {
                found: name(found),
                asked: name(s),
            });
        }
        Some(s) => s,
        None => found,
    };
    let s = f64::from(direction);
    let mut out = vec![0.0];
    for i in 0..k - 1 {
        out.push(out[i] + step(i, s));
    }
    // Solved frame: the first pose's angle, mirrored for CW.
    let phi0 = s * phi[0];
    Ok((direction, out.iter().map(|d| phi0 + d).collect()))
}

/// The necessary conditions of a timing through the poses (checked before any fit): with the
/// planet's relative rotation `ψ3 = φ − β + const` strictly increasing by exactly one turn per
/// carrier turn (i31 > 0), the relative turn between poses k and k + 1 is
/// `Δψ_k = (Δφ_k − Δθ_k) mod 2π` (solved frame), the turns must add up to 360°, and each mean
/// ratio `Δψ_k/Δφ_k` must lie in `[i_min/i_max, i_max/i_min]` (`i31 = i21(t)/i21(S(t))` with
/// `i21 ∈ ratio_bounds`). `angles` are the carrier angles of [`carrier_angles`] for `direction`.
pub fn check_planet_turns(
    poses: &[Pose],
    direction: i8,
    angles: &[f64],
    ratio_bounds: [f64; 2],
) -> Result<(), TimingError> {
    let k = poses.len();
    if k < 2 {
        return Ok(());
    }
    let s = f64::from(direction);
    let theta = |i: usize| s * poses[i].needle_rad;
    let steps: Vec<(f64, f64)> = (0..k)
        .map(|i| {
            let j = (i + 1) % k;
            let dphi = if j == 0 {
                angles[0] + TAU - angles[i]
            } else {
                angles[j] - angles[i]
            };
            (dphi, (dphi - (theta(j) - theta(i))).rem_euclid(TAU))
        })
        .collect();
    let total: f64 = steps.iter().map(|s| s.1).sum();
    // The wrapped turns sum to a multiple of 2π; 1e-6 rad only absorbs rounding.
    if (total - TAU).abs() > 1e-6 {
        let mut by_turn: Vec<usize> = (0..k).collect();
        by_turn.sort_by(|a, b| steps[*b].1.total_cmp(&steps[*a].1));
        let extra = ((total / TAU).round() as usize).saturating_sub(1).max(1);
        return Err(TimingError::PlanetTurns {
            turns_deg: total.to_degrees(),
            poses: by_turn
                .into_iter()
                .take(extra)
                .map(|i| (i, (i + 1) % k))
                .collect(),
        });
    }
    let [lo, hi] = ratio_bounds;
    let (min, max) = (lo / hi, hi / lo);
    for (i, (dphi, dpsi)) in steps.iter().enumerate() {
        let ratio = dpsi / dphi;
        if !(ratio > min && ratio < max) {
            return Err(TimingError::PlanetRatio {
                from: i,
                to: (i + 1) % k,
                psi_deg: dpsi.to_degrees(),
                phi_deg: dphi.to_degrees(),
                ratio,
                min,
                max,
                i_min: lo,
                i_max: hi,
            });
        }
    }
    Ok(())
}

/// The band rows of a train (solved frame): each index's distance outside its band, degrees or mm.
pub type BandRows<'a> = dyn Fn(&Mechanism) -> Vec<f64> + Sync + 'a;

/// What a timing keeps to besides the poses ([`fit_timing`]).
#[derive(Clone, Copy, Default)]
pub struct TimingGoals<'a> {
    /// The gear limits (the design chain's).
    pub limits: Option<&'a GearLimits>,
    /// Rows of the target bands: each index's distance outside its band (degrees or mm, 0
    /// inside) for a train in the solved frame.
    pub bands: Option<&'a BandRows<'a>>,
}

/// The smoothest train of Fourier order `order` through the poses (module documentation);
/// `tolerances_rad[k]` is pose k's direction tolerance ([`POSE_TOL_RAD`] for an exact pose).
/// With `goals.limits`, the train's gears are kept within them (the design chain's, with a
/// [`LIMIT_MARGIN`] margin), and with `goals.bands` its indices in their bands: when the best
/// timing of the poses and smoothness alone breaks a limit or misses a band, the fit is run again
/// from every start with one more row per limit, `√(mean (c⁻)²)` over a grid of the ratio,
/// weighted like a pose row (a timing the chain would have to bend, and so miss the poses, is
/// avoided where the poses allow), and one per band, weighted 1 per degree or mm: the bands steer
/// while the poses are loose and yield to exact poses as they tighten.
#[must_use]
pub fn fit_timing(
    poses: &[Pose],
    dyad: &Dyad,
    direction: i8,
    angles: &[f64],
    order: usize,
    tolerances_rad: &[f64],
    goals: &TimingGoals<'_>,
) -> Timing {
    let fit = TimingFit {
        dyad,
        angles,
        // Needle directions in the solved frame (a CW carrier mirrored in y: θ → −θ).
        theta: poses
            .iter()
            .map(|p| f64::from(direction) * p.needle_rad)
            .collect(),
        order,
        tolerances_rad,
        goals,
    };
    // The poses and smoothness alone first (the usual case: their train is within the limits);
    // when the best breaks a limit, every start again with the limit rows.
    let best = fit.best_of_starts(false);
    // (The extra rows are zero when kept to: equal costs up to rounding.)
    let best = if fit.cost(&best, true) > fit.cost(&best, false) * (1.0 + 1e-9) {
        fit.best_of_starts(true)
    } else {
        best
    };
    let m = fit.build(&best).expect("the fit keeps an admissible ratio");
    let residuals_rad = angles
        .iter()
        .zip(&fit.theta)
        .map(|(phi, th)| (m.needle_direction(*phi) - th + PI).rem_euclid(TAU) - PI)
        .collect();
    Timing {
        direction,
        carrier_angles_rad: angles.to_vec(),
        mechanism: m,
        residuals_rad,
    }
}

/// The least-squares problem of [`fit_timing`] over `x = [sun phase u₀, needle angle γ, a₁…a_N,
/// b₁…b_N]` (rad; the Fourier coefficients of the sun ratio).
struct TimingFit<'a> {
    dyad: &'a Dyad,
    /// Carrier angle of each pose, rad.
    angles: &'a [f64],
    /// Needle direction of each pose in the solved frame, rad.
    theta: Vec<f64>,
    /// Fourier order `N` of the sun ratio.
    order: usize,
    /// Direction tolerance of each pose, rad.
    tolerances_rad: &'a [f64],
    goals: &'a TimingGoals<'a>,
}

impl TimingFit<'_> {
    /// The train of `x`, or `None` when its ratio is inadmissible.
    fn build(&self, x: &[f64]) -> Option<Mechanism> {
        let order = self.order;
        let ratio = SunRatio::new(x[2..2 + order].to_vec(), x[2 + order..].to_vec()).ok()?;
        Some(Mechanism {
            a_mm: 0.5 * self.dyad.l1_mm,
            l3_mm: self.dyad.l3_mm,
            ratio,
            sun_phase_rad: x[0],
            needle_angle_rad: x[1],
            idler_offset_rad: 0.0,
        })
    }

    /// The residual rows at `x`: pose rows divided by max(tolerance, `floor`) (the floor falls
    /// over [`CONTINUATION_RAD`] so that the smoothness rows steer the first steps: the pose
    /// equations alone leave most directions free), the smoothness rows `SMOOTHNESS·j²·(a_j,
    /// b_j)`, and `with_limits` the band rows and [`TimingFit::limit_rows`].
    fn residuals(&self, x: &[f64], floor: f64, with_limits: bool) -> Option<DVector<f64>> {
        let order = self.order;
        let m = self.build(x)?;
        let mut r: Vec<f64> = self
            .angles
            .iter()
            .zip(&self.theta)
            .zip(self.tolerances_rad)
            .map(|((phi, th), tol)| {
                let d = (m.needle_direction(*phi) - th + PI).rem_euclid(TAU) - PI;
                d / tol.max(floor)
            })
            .collect();
        for j in 1..=order {
            let w = SMOOTHNESS * (j * j) as f64;
            r.push(w * x[1 + j]);
            r.push(w * x[1 + order + j]);
        }
        if !with_limits {
            return Some(DVector::from_vec(r));
        }
        if let Some(bands) = self.goals.bands {
            r.extend(bands(&m));
        }
        if let Some(limits) = self.goals.limits {
            r.extend(self.limit_rows(&m, limits, floor));
        }
        Some(DVector::from_vec(r))
    }

    /// One row per gear limit: `√(mean (c⁻)²)` of its constraint value below zero over a grid
    /// of the ratio, over `floor` (weighted like a pose row).
    fn limit_rows(&self, m: &Mechanism, limits: &GearLimits, floor: f64) -> [f64; 7] {
        // 32 samples per period of the highest harmonic (at least 96): coarser than the chain's
        // own limit scans (≥ 1024), which check the design afterwards; this grid only steers.
        let grid = (32 * self.order).max(96);
        let mut excess = [0.0f64; 7];
        for k in 0..grid {
            let v = m.ratio.eval3(TAU * k as f64 / grid as f64);
            let c = constraint_values(limits, v, m.a_mm, LIMIT_MARGIN);
            for (e, c) in excess.iter_mut().zip(c) {
                // An absent limit is infinite (always within); NaN counts as broken.
                let below = if c.is_nan() { -1.0 } else { c.min(0.0) };
                *e += below * below;
            }
        }
        excess.map(|e| (e / grid as f64).sqrt() / floor)
    }

    /// The squared residual norm at the final floor [`POSE_TOL_RAD`] (∞ when inadmissible).
    fn cost(&self, x: &[f64], with_limits: bool) -> f64 {
        self.residuals(x, POSE_TOL_RAD, with_limits)
            .map_or(f64::INFINITY, |r| r.norm_squared())
    }

    /// Levenberg–Marquardt from `x` at each floor of [`CONTINUATION_RAD`] in turn.
    fn continuation(&self, mut x: Vec<f64>, with_limits: bool) -> Vec<f64> {
        for floor in CONTINUATION_RAD {
            let problem = Residuals(|x: &[f64]| self.residuals(x, floor, with_limits));
            x = levenberg_marquardt(&problem, x, &LmOptions::default());
        }
        x
    }

    /// The circular train (i21 ≡ 1) at sun phase `u0` (rad), γ so that it meets the first pose.
    fn start(&self, u0: f64) -> Vec<f64> {
        let mut x = vec![0.0; 2 + 2 * self.order];
        x[0] = u0;
        let m0 = self.build(&x).expect("a circular ratio");
        x[1] = self.theta[0] - (m0.needle_direction(self.angles[0]) - m0.needle_angle_rad);
        x
    }

    /// The cheapest of the continuations from the four sun phases 0, π/2, π, 3π/2.
    fn best_of_starts(&self, with_limits: bool) -> Vec<f64> {
        let phases = [0.0, 0.5 * PI, PI, 1.5 * PI];
        phases
            .into_iter()
            .map(|u0| self.continuation(self.start(u0), with_limits))
            .min_by(|a, b| {
                self.cost(a, with_limits)
                    .total_cmp(&self.cost(b, with_limits))
            })
            .expect("four starts")
    }
}
