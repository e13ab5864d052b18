//! Targets only: a train whose agronomic indices lie in their bands, within the gear limits — the
//! synthesis when the spec gives target bands and no poses.
//!
//! The unknowns are those of the pose synthesis without the poses: the carrier arm `l1`, the
//! needle `l3`, the needle angle γ, the sun phase `u0` and the sun ratio
//! `i21 = 1 + Σ_{j≤N} a_j cos ju + b_j sin ju` (order [`TARGETS_ORDER`]); the carrier axis O and sense
//! are the machine's (the indices do not depend on where O is). Every candidate is a sun ratio, so
//! every candidate is a train (docs/math/chain.md §6). The problem is
//!
//! ```text
//! minimise  Σ_i (h_i / s_i)²  +  W·g²  +  Σ_j j²(a_j² + b_j²)  +  μ·(l1 + l3)
//! h_i = distance of index i outside its band shrunk by m_i = min(0.1·width, s_i)
//! g   = (α_eff − 0.98·α_max)⁺ [deg] + (1.02·R_min − ρ_concave)⁺ [mm]
//!       + 100·(ratio outside its bounds narrowed by 2 %)
//!       + (l1 − 0.9·l3)⁺ + (a − (l3 − l1))⁺ [mm]
//! ```
//!
//! with `s_i` one unit of the index (1° or 1 mm). The last two terms keep the tip's closest
//! approach to the carrier axis, `l3 − l1`, well above the design chain's refusal
//! ([`MIN_AXIS_DISTANCE_L3`]) and outside the circle of radius `a = l1/2` about O that holds the
//! sun gear (its pitch radius `a·i/(1 + i)` is below `a`): the needle clears the gearbox.
//! The gear limits are those of the design chain
//! ([`crate::geometry::limits`]) and `μ` = [`SIZE_WEIGHT`] per mm (the compact arm breaks ties:
//! the smaller gearbox and planting arm). The indices are those of [`crate::simulate::features`]
//! (one implementation), evaluated on the train's two arms at [`SEARCH_SAMPLES`] instants while
//! screening and [`REFINE_SAMPLES`] in the long runs.
//!
//! `l1` and `l3` are kept in their search box (the machine's `l1_mm`, `l3_mm`, else
//! [`DEFAULT_L1_MM`], [`DEFAULT_L3_MM`]): a parameter outside is brought to the box's edge and
//! charged `W·d²` for its distance `d` (mm) outside.
//!
//! The search is deterministic: a grid of starts (arm sizes over the search box, needle angles
//! every 45°, four sun phases, three ratio amplitudes) is screened by its cost; the best
//! [`SCREENED_STARTS`] get a short Nelder–Mead run (argmin) and the best [`REFINED_STARTS`] of
//! those a long one, restarted once from its best point; runs go side by side.

use crate::design::inverse::MIN_AXIS_DISTANCE_L3;
use crate::geometry::assembly::Pose as ArmPose;
use crate::geometry::fourier::SunRatio;
use crate::geometry::limits::GearLimits;
use crate::geometry::mechanism::Mechanism;
use crate::math::Point;
use crate::math::optimize::nelder_mead_starts;
use crate::simulate::{FeatureOptions, Features, TwoArms, features_of_turn};
use argmin::core::CostFunction;
use nalgebra::DVector;
use std::f64::consts::{FRAC_PI_4, PI, TAU};

/// Fourier order of the sun ratio searched.
pub const TARGETS_ORDER: usize = 3;

/// Instants per carrier turn at which the indices are evaluated during the search.
pub const SEARCH_SAMPLES: usize = 180;

/// Instants per carrier turn of the long runs (and of the returned costs).
pub const REFINE_SAMPLES: usize = 720;

/// Starts of the grid (lowest cost first) given a short Nelder–Mead run.
pub const SCREENED_STARTS: usize = 24;

/// Best short runs continued by long Nelder–Mead runs.
pub const REFINED_STARTS: usize = 4;

/// Weight μ of the arm size `l1 + l3` in the cost, per mm.
pub const SIZE_WEIGHT: f64 = 1e-3;

/// Relative margin kept inside the ratio bounds, the pressure-angle and the concave-radius limits, so that the design
/// chain takes the train as it is (its own projection keeps a margin too).
pub const LIMIT_MARGIN: f64 = 0.02;

/// Weight W of the gear-limit and search-box hinge.
const GEAR_WEIGHT: f64 = 100.0;

/// Closest approach of the path to the carrier axis kept by the search, `l3 − l1`, in units of
/// `l3`: twice the design chain's [`MIN_AXIS_DISTANCE_L3`].
pub const AXIS_DISTANCE_L3: f64 = 2.0 * MIN_AXIS_DISTANCE_L3;

/// Parameter scale of the lengths: the search works in `l / LENGTH_UNIT_MM`.
const LENGTH_UNIT_MM: f64 = 100.0;

/// Search box of the carrier arm and the needle when the spec sets none, mm: the proportions of
/// rice transplanter planting arms (G1: l1 = 90, l3 = 170 mm).
pub const DEFAULT_L1_MM: [f64; 2] = [40.0, 160.0];
/// See [`DEFAULT_L1_MM`].
pub const DEFAULT_L3_MM: [f64; 2] = [60.0, 320.0];

/// What the targets search is asked for.
#[derive(Debug, Clone)]
pub struct TargetProblem {
    /// `(index name, [min, max])` of each band (names of [`super::spec::Targets::bands`]).
    pub bands: Vec<(&'static str, [f64; 2])>,
    /// Machine speeds and depth for the indices.
    pub features: FeatureOptions,
    /// The design chain's gear limits.
    pub limits: GearLimits,
    /// Carrier axis O, mm.
    pub center_mm: Point,
    /// Carrier sense, +1 CCW, −1 CW.
    pub direction: i8,
    /// Search box of `l1`, mm.
    pub l1_mm: [f64; 2],
    /// Search box of `l3`, mm.
    pub l3_mm: [f64; 2],
}

/// A train found by the search, in the solved frame (relative to O, CCW; a CW carrier is the
/// mirror image in y), with its cost.
#[derive(Debug, Clone)]
pub struct Found {
    /// The train.
    pub mechanism: Mechanism,
    /// Its cost (module documentation).
    pub cost: f64,
}

/// The value of band `name` among the features (degrees or mm).
#[must_use]
pub fn index_value(name: &str, f: &Features) -> f64 {
    match name {
        "take_angle_deg" => f.take_angle_deg,
        "push_angle_deg" => f.push_angle_deg,
        "angle_difference_deg" => f.push_angle_deg - f.take_angle_deg,
        "height_mm" => f.height_mm,
        "hole_width_mm" => f.hole_width_mm,
        _ => f.min_arm_clearance_mm,
    }
}

/// How far each index lies outside its band shrunk by `min(10 % of its width, 1)` (degrees or
/// mm; 0 inside): the band rows of the searches, which so land inside a band, not on its edge.
#[must_use]
pub fn band_shortfalls(bands: &[(&'static str, [f64; 2])], f: &Features) -> Vec<f64> {
    bands
        .iter()
        .map(|(name, b)| {
            let inset = (0.1 * (b[1] - b[0])).min(1.0);
            let v = index_value(name, f);
            (b[0] + inset - v).max(0.0) + (v - b[1] + inset).max(0.0)
        })
        .collect()
}

/// Both arms of `m` over one turn at `n` instants (time order), world frame: carrier axis at
/// `center_mm`, a CW carrier (`direction < 0`) the mirror image of the solved frame in y.
#[must_use]
pub fn turn_of(m: &Mechanism, center_mm: Point, direction: i8, n: usize) -> Vec<TwoArms> {
    let s = f64::from(direction.signum());
    let world = |p: Point| Point::new(center_mm.x + p.x, center_mm.y + s * p.y);
    let arm = |phi: f64| {
        let (l1, a) = (m.l1_mm(), m.a_mm);
        let theta3 = m.planet_orientation(phi);
        let beta = theta3 + m.needle_angle_rad;
        ArmPose {
            phi_h_rad: s * phi,
            intermediate_center_mm: world(Point::new(a * phi.cos(), a * phi.sin())),
            planet_center_mm: world(Point::new(l1 * phi.cos(), l1 * phi.sin())),
            intermediate_angle_rad: s * m.intermediate_orientation(phi),
            planet_angle_rad: s * theta3,
            tip_mm: world(Point::new(
                l1 * phi.cos() + m.l3_mm * beta.cos(),
                l1 * phi.sin() + m.l3_mm * beta.sin(),
            )),
            sun_mesh_error_mm: 0.0,
            planet_mesh_error_mm: 0.0,
        }
    };
    // Arm 2 is arm 1 half a turn later: with n even, sample k + n/2 of arm 1.
    let n = n.max(2) / 2 * 2;
    let arm1: Vec<ArmPose> = (0..n).map(|k| arm(TAU * k as f64 / n as f64)).collect();
    (0..n)
        .map(|k| TwoArms {
            arm1: arm1[k],
            arm2: arm1[(k + n / 2) % n],
        })
        .collect()
}

impl TargetProblem {
    /// The train of parameters `x = [l1/100, l3/100, γ, u0, a_1…a_N, b_1…b_N]`, its lengths
    /// brought into the search box.
    fn mechanism(&self, x: &[f64]) -> Mechanism {
        let n = (x.len() - 4) / 2;
        let within = |v: f64, r: [f64; 2]| v.clamp(r[0], r[1]);
        Mechanism {
            a_mm: 0.5 * within(LENGTH_UNIT_MM * x[0], self.l1_mm),
            l3_mm: within(LENGTH_UNIT_MM * x[1], self.l3_mm),
            ratio: SunRatio::new_unchecked(x[4..4 + n].to_vec(), x[4 + n..].to_vec()),
            sun_phase_rad: x[3],
            needle_angle_rad: x[2],
            idler_offset_rad: 0.0,
        }
    }

    /// The cost of parameters `x`: that of their train in the box, plus the hinge of the
    /// distance (mm) of `x`'s lengths outside the box, which leads the search back into it.
    fn cost_at(&self, x: &[f64], samples: usize) -> f64 {
        let (l1, l3) = (LENGTH_UNIT_MM * x[0], LENGTH_UNIT_MM * x[1]);
        let outside = (self.l1_mm[0] - l1).max(0.0)
            + (l1 - self.l1_mm[1]).max(0.0)
            + (self.l3_mm[0] - l3).max(0.0)
            + (l3 - self.l3_mm[1]).max(0.0);
        self.cost(&self.mechanism(x), samples) + GEAR_WEIGHT * outside * outside
    }

    /// The cost of a train (module documentation); infinite when it is no train (a ratio ≤ 0, a
    /// length ≤ 0) or its indices cannot be evaluated.
    #[must_use]
    pub fn cost(&self, m: &Mechanism, samples: usize) -> f64 {
        let (l1, l3) = (m.l1_mm(), m.l3_mm);
        if !(l1 > 1.0 && l3 > 1.0) {
            return f64::INFINITY;
        }
        let measure = self.limits.measure(&m.ratio, m.a_mm);
        if !(measure.ratio_range[0] > 0.0) {
            return f64::INFINITY;
        }
        let above = |v: f64, max: f64| (v - max).max(0.0);
        let bounds = self.limits.ratio_bounds();
        let concave = [
            measure.sun_min_concave_radius_mm,
            measure.intermediate_min_concave_radius_mm,
        ]
        .into_iter()
        .flatten()
        .map(|r| {
            above(
                (1.0 + LIMIT_MARGIN) * self.limits.min_concave_radius_mm(),
                r,
            )
        })
        .fold(0.0, f64::max);
        let g = above(
            measure.max_pressure_angle_rad.to_degrees(),
            (1.0 - LIMIT_MARGIN) * self.limits.max_pressure_angle_rad().to_degrees(),
        ) + concave
            + 100.0
                * (above((1.0 + LIMIT_MARGIN) * bounds[0], measure.ratio_range[0])
                    + above(measure.ratio_range[1], (1.0 - LIMIT_MARGIN) * bounds[1]))
            + above(l1, (1.0 - AXIS_DISTANCE_L3) * l3)
            + above(0.5 * l1, l3 - l1);
        let turn = turn_of(m, self.center_mm, self.direction, samples);
        // A transplanter's loop leaves the carrier axis outside (docs/math/chain.md §3.2): a
        // loop around O is no candidate.
        if winding_number(&turn, self.center_mm) != 0 {
            return f64::INFINITY;
        }
        let Ok(f) = features_of_turn(&turn, self.center_mm, self.direction, &self.features) else {
            return f64::INFINITY;
        };
        let bands: f64 = band_shortfalls(&self.bands, &f).iter().map(|h| h * h).sum();
        let smooth: f64 = (1..=m.ratio.order())
            .map(|j| {
                let (a, b) = (
                    m.ratio.cos_coefficients()[j - 1],
                    m.ratio.sin_coefficients()[j - 1],
                );
                (j * j) as f64 * (a * a + b * b)
            })
            .sum();
        bands + GEAR_WEIGHT * g * g + smooth + SIZE_WEIGHT * (l1 + l3)
    }

    /// The deterministic start grid (module documentation), parameter vectors: arm sizes over the
    /// search box, needle angles every 45°, four sun phases, three ratio amplitudes.
    fn starts(&self) -> Vec<Vec<f64>> {
        let lerp = |r: [f64; 2], t: f64| (r[0] + t * (r[1] - r[0])) / LENGTH_UNIT_MM;
        let mut out = Vec::new();
        for t1 in [0.2, 0.5, 0.8] {
            for t3 in [0.3, 0.6, 0.9] {
                for k in 0..8 {
                    for u0 in [0.0, 0.5 * PI, PI, 1.5 * PI] {
                        for a1 in [0.0, 0.2, 0.4] {
                            let mut x = vec![0.0; 4 + 2 * TARGETS_ORDER];
                            x[0] = lerp(self.l1_mm, t1);
                            x[1] = lerp(self.l3_mm, t3);
                            x[2] = f64::from(k) * FRAC_PI_4;
                            x[3] = u0;
                            x[4] = a1;
                            out.push(x);
                        }
                    }
                }
            }
        }
        out
    }

    /// The best trains found, lowest cost first (at most [`REFINED_STARTS`]).
    #[must_use]
    pub fn search(&self) -> Vec<Found> {
        let cost_of = |x: &[f64]| self.cost_at(x, SEARCH_SAMPLES);
        let mut starts: Vec<(f64, Vec<f64>)> = self
            .starts()
            .into_iter()
            .map(|x| (cost_of(&x), x))
            .collect();
        starts.sort_by(|a, b| a.0.total_cmp(&b.0));
        let screened: Vec<Vec<f64>> = starts
            .into_iter()
            .filter(|(c, _)| c.is_finite())
            .take(SCREENED_STARTS)
            .map(|(_, x)| x)
            .collect();
        let make = || Cost {
            problem: self,
            samples: SEARCH_SAMPLES,
        };
        let make_fine = || Cost {
            problem: self,
            samples: REFINE_SAMPLES,
        };
        // A short run from each screened start, then the best few run long (twice: a fresh
        // simplex at the first run's best point).
        let mut short: Vec<(f64, Vec<f64>)> = nelder_mead_starts(make, &screened, 0.1, 1e-9, 300)
            .into_iter()
            .map(|x| (cost_of(&x), x))
            .collect();
        short.sort_by(|a, b| a.0.total_cmp(&b.0));
        let best: Vec<Vec<f64>> = short
            .into_iter()
            .take(REFINED_STARTS)
            .map(|(_, x)| x)
            .collect();
        let once = nelder_mead_starts(make, &best, 0.05, 1e-9, 1500);
        let twice = nelder_mead_starts(make_fine, &once, 0.02, 1e-10, 400);
        let mut found: Vec<Found> = twice
            .iter()
            .map(|x| {
                let mechanism = self.mechanism(x);
                Found {
                    cost: self.cost(&mechanism, REFINE_SAMPLES),
                    mechanism,
                }
            })
            .filter(|f| f.cost.is_finite())
            .collect();
        found.sort_by(|a, b| a.cost.total_cmp(&b.cost));
        found
    }
}

/// Turns of arm 1's tip path about `center_mm`.
fn winding_number(turn: &[TwoArms], center_mm: Point) -> i64 {
    let angle = |p: &TwoArms| (p.arm1.tip_mm - center_mm).atan2();
    let total: f64 = (0..turn.len())
        .map(|k| {
            let d = angle(&turn[(k + 1) % turn.len()]) - angle(&turn[k]);
            (d + PI).rem_euclid(TAU) - PI
        })
        .sum();
    (total / TAU).round() as i64
}

/// The search's cost as an argmin problem.
struct Cost<'a> {
    problem: &'a TargetProblem,
    samples: usize,
}

impl CostFunction for Cost<'_> {
    type Param = DVector<f64>;
    type Output = f64;
    fn cost(&self, p: &DVector<f64>) -> Result<f64, argmin::core::Error> {
        let c = self.problem.cost_at(p.as_slice(), self.samples);
        // Nelder–Mead needs finite values: an inadmissible train costs a large constant.
        Ok(if c.is_finite() { c } else { 1e12 })
    }
}
