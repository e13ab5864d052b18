//! The report of the transplanter tolerance analysis (the keys of `transplanter.json`) and the
//! geometry of its plots.

use crate::math::Point;
use crate::math::monte_carlo::McStats;
use crate::simulate::Features;
use serde::Serialize;

/// Linear vs exact model on samples at the 3σ tolerances.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Validation {
    /// Number of samples.
    pub samples: usize,
    /// Largest relative error `max_φ|ΔB_lin − ΔB_exact| / max_φ|ΔB_exact|` over the samples.
    pub max_relative_error: f64,
    /// Mean relative error.
    pub mean_relative_error: f64,
    /// Largest absolute error, µm.
    pub max_absolute_error_um: f64,
    /// Model used by the Monte Carlo: "linear" or "exact" (fallback).
    pub model_used: String,
}

/// The tip-deviation envelope at one carrier angle.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct EnvelopePoint {
    /// Carrier angle φH, degrees (world).
    pub carrier_deg: f64,
    /// Nominal tip, mm.
    pub nominal_tip_mm: Point,
    /// Mean tip deviation over random assembly, µm.
    pub mean_deviation_um: Point,
    /// `3·sqrt(λ_max)` of the deviation covariance, µm.
    pub three_sigma_um: f64,
    /// Envelope `|mean| + 3σ`, µm.
    pub envelope_um: f64,
    /// Deviation with the nominal (as-given) errors, linear model, µm.
    pub nominal_errors_um: f64,
    /// Unit normal of the nominal path (left of the travel direction), for drawing the band.
    pub normal: Point,
}

/// Distributions of the agronomic-feature deviations (perturbed − nominal), exact model.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct FeatureDeviations {
    /// Samples (random assemblies).
    pub samples: usize,
    /// Features of the error-free train (same sampling).
    pub nominal: Features,
    /// Trajectory height, mm.
    pub height_mm: McStats,
    /// Hole width at the planting depth, mm.
    pub hole_width_mm: McStats,
    /// Static loop width at the planting depth, mm.
    pub static_width_at_depth_mm: McStats,
    /// Needle angle at taking, degrees.
    pub needle_angle_take_deg: McStats,
    /// Needle angle at planting, degrees.
    pub needle_angle_plant_deg: McStats,
    /// Lowest point (planting depth reference) `min y`, mm.
    pub lowest_point_mm: McStats,
}

/// Contribution of one error to `max_φ |ΔB|` at its 3σ value.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Contribution {
    /// Error name.
    pub error: String,
    /// Unit of the tolerance: "µm" or "deg".
    pub unit: String,
    /// `|nominal| + 3σ` (or + the half width; eccentricity `e + 3σ`).
    pub three_sigma: f64,
    /// `max_φ |S(φ)|` (µm of tip deviation per unit; worst direction for an eccentricity).
    pub sensitivity_um_per_unit: f64,
    /// Tip deviation at the 3σ value, µm.
    pub max_deviation_um: f64,
    /// Share of the sum of all contributions, %.
    pub share_percent: f64,
}

/// One step of the greedy assembly.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct GreedyChoice {
    /// Gear whose runout direction is chosen.
    pub gear: String,
    /// Chosen direction, degrees (body frame).
    pub direction_deg: f64,
    /// `max_φ |ΔB|` with the gears placed so far, µm.
    pub max_deviation_um: f64,
}

/// Best assembly of the free runout orientations.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct AssemblyOptimum {
    /// Gears with a free direction.
    pub free: Vec<String>,
    /// Keyed positions of each (0 = continuous).
    pub keyed_positions: Vec<usize>,
    /// `max_φ |ΔB|` with the directions as given in the file, µm.
    pub as_given_um: f64,
    /// Greedy sequential choice (docs/math/companion.md §C.3).
    pub greedy: Vec<GreedyChoice>,
    /// Greedy result, µm.
    pub greedy_um: f64,
    /// Joint optimum directions, degrees.
    pub joint_directions_deg: Vec<f64>,
    /// Joint optimum, µm (linear model).
    pub joint_um: f64,
    /// The joint optimum re-evaluated with the exact model, µm.
    pub joint_exact_um: f64,
    /// "exhaustive" (keyed positions) or "nelder-mead" (multistart).
    pub joint_method: String,
    /// `max_φ |ΔB|` over random directions (uniform / uniform over the keys), µm.
    pub random: McStats,
    /// Probability that a random assembly is at least as good as the joint optimum.
    pub p_random_beats_joint: f64,
    /// `1 − joint/mean(random)`, %.
    pub gain_vs_random_mean_percent: f64,
    /// `|ΔB(φH)|` of the joint optimum on the grid (linear model), µm.
    pub joint_deviation_um: Vec<f64>,
}

/// The report of `ncgear tolerance DESIGN.json --errors ERRORS`.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct TransplanterReport {
    /// Pressure angle, degrees.
    pub pressure_angle_deg: f64,
    /// Loaded flank of the sun–intermediate mesh.
    pub load_side: i8,
    /// Carrier angles per turn.
    pub samples_per_turn: usize,
    /// `max_φ |ΔB|` with the nominal (as-given) errors, exact model, µm.
    pub nominal_errors_exact_um: f64,
    /// The same with the linear model, µm.
    pub nominal_errors_linear_um: f64,
    /// Linear-model validation.
    pub validation: Validation,
    /// Monte Carlo seed.
    pub seed: u64,
    /// `max_φ |ΔB|` over random assemblies, µm.
    pub max_deviation_um: McStats,
    /// `max_φ |Δθ3|` of the planet (the transmission error of docs/math/companion.md §C) over the same random
    /// assemblies, arc seconds.
    pub planet_angle_error_arcsec: McStats,
    /// Deviation envelope along the trajectory.
    pub envelope: Vec<EnvelopePoint>,
    /// Largest envelope value, µm.
    pub envelope_max_um: f64,
    /// Agronomic-feature deviations.
    pub features: Option<FeatureDeviations>,
    /// Errors sorted by contribution (largest first).
    pub ranking: Vec<Contribution>,
    /// Best assembly of the free runout orientations, when any is free.
    pub assembly: Option<AssemblyOptimum>,
}

impl TransplanterReport {
    /// Magnification of the 3σ band drawn around the nominal trajectory: the power of ten (≥ 1)
    /// that makes the largest envelope value about 2 % of the trajectory's x extent.
    #[must_use]
    pub fn band_magnification(&self) -> f64 {
        let (mut lo, mut hi) = (f64::MAX, f64::MIN);
        for p in &self.envelope {
            lo = lo.min(p.nominal_tip_mm.x);
            hi = hi.max(p.nominal_tip_mm.x);
        }
        let env_max = self.envelope_max_um.max(1e-9) * 1e-3;
        let raw = 0.02 * (hi - lo) / env_max;
        10f64.powf(raw.log10().floor()).max(1.0)
    }

    /// The closed polyline `B₀ + side·magnification·envelope·n` (mm) along the trajectory, n the
    /// path normal: `side` = 0 the nominal path, ±1 the outer and inner band.
    #[must_use]
    pub fn band(&self, side: f64, magnification: f64) -> Vec<(f64, f64)> {
        let mut v: Vec<(f64, f64)> = self
            .envelope
            .iter()
            .map(|p| {
                let d = side * magnification * p.envelope_um * 1e-3;
                (
                    p.nominal_tip_mm.x + d * p.normal.x,
                    p.nominal_tip_mm.y + d * p.normal.y,
                )
            })
            .collect();
        if let Some(f) = v.first().copied() {
            v.push(f);
        }
        v
    }
}
