//! What every stage of the transplanter analysis shares: its options, the seeded sample streams,
//! the exact model's peak deviation and the Monte Carlo error mapping.

use super::model::{ExactModel, FdSteps, LinearModel};
use super::{ErrorVector, TransplanterError};
use crate::math::monte_carlo::{McError, McOptions};
use crate::simulate::FeatureOptions;
use rand::SeedableRng;
use rand::rngs::ChaCha8Rng;
use serde::{Deserialize, Serialize};

/// µm per mm.
pub(super) const UM: f64 = 1e3;

/// Options of [`analyse`](super::analyse). (De)serialisable (a missing field takes its default, an unknown one is an error) and
/// built with `with_*`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct TransplanterOptions {
    /// Monte Carlo of random assembly: samples (≥ 2), seed, histogram bins (default
    /// [`McOptions::default`]: 50 000 samples, seed 1, 60 bins).
    pub mc: McOptions,
    /// Samples at 3σ used to validate the linear model against the exact one (docs/math/companion.md §C.6 and default:
    /// 100).
    pub validation_samples: usize,
    /// Largest accepted relative error of the linear model; above it the Monte Carlo uses the
    /// exact model (docs/math/companion.md §C.6 and default: 0.05).
    pub linear_tolerance: f64,
    /// Exact-model samples of the agronomic-feature distributions (0: skip; default 200).
    pub feature_samples: usize,
    /// Random starts of the joint assembly optimizer (Nelder–Mead), besides the greedy directions
    /// (default 16).
    pub starts: usize,
    /// Finite-difference steps of the linear model (default [`FdSteps::default`]: 1 µm, 10 µrad;
    /// written `{"length_mm": …, "angle_rad": …}`).
    pub fd_steps: FdSteps,
    /// Options of the agronomic features (speeds, planting depth; default
    /// [`FeatureOptions::default`]).
    pub features: FeatureOptions,
}

crate::builder::with_fields!(TransplanterOptions {
    with_mc => mc: McOptions,
    with_validation_samples => validation_samples: usize,
    with_linear_tolerance => linear_tolerance: f64,
    with_feature_samples => feature_samples: usize,
    with_starts => starts: usize,
    with_fd_steps => fd_steps: FdSteps,
    with_features => features: FeatureOptions,
});

impl Default for TransplanterOptions {
    fn default() -> Self {
        Self {
            mc: McOptions::default(),
            validation_samples: 100,
            linear_tolerance: 0.05,
            feature_samples: 200,
            starts: 16,
            fd_steps: FdSteps::default(),
            features: FeatureOptions::default(),
        }
    }
}

/// `max_φ |ΔB|` (mm) of the exact model against the linear model's nominal tips.
pub(super) fn exact_max(
    model: &ExactModel,
    lin: &LinearModel,
    x: &ErrorVector,
) -> Result<f64, TransplanterError> {
    let mut m: f64 = 0.0;
    for (p, b0) in lin.phis_rad.iter().zip(&lin.nominal_tips_mm) {
        let b = model.state(*p, x)?.tip_mm;
        m = m.max(b.distance(*b0));
    }
    Ok(m)
}

/// Maps a Monte Carlo failure of the named quantity to a [`TransplanterError`].
pub(super) fn mc_error(what: &'static str) -> impl Fn(McError) -> TransplanterError {
    move |e| match e {
        McError::BadOption {
            name,
            value,
            expected,
        } => TransplanterError::BadOption {
            option: match name {
                "samples" => "mc.samples",
                "bins" => "mc.bins",
                other => other,
            },
            message: format!("{value}: expected {expected}"),
        },
        McError::NonFinite { index } => {
            TransplanterError::Numerical(format!("Monte Carlo sample {index} of the {what}"))
        }
        McError::Memory(b) => TransplanterError::BadOption {
            option: "mc.samples",
            message: b.to_string(),
        },
    }
}

/// Sample `i` of a sub-analysis with its own seed stream family.
pub(super) fn rng_for(seed: u64, family: u64, i: usize) -> ChaCha8Rng {
    let mut r = ChaCha8Rng::seed_from_u64(seed ^ family.wrapping_mul(0x9E37_79B9_7F4A_7C15));
    r.set_stream(i as u64);
    r
}
