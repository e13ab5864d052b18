//! Agronomic features of the perturbed train (exact model) and their deviation distributions
//! over random assemblies.

use super::common::{TransplanterOptions, mc_error, rng_for};
use super::report::FeatureDeviations;
use super::{
    ErrorVector, ExactModel, Inventory, LinearModel, N_COORDS, TrainState, TransplanterError,
};
use crate::geometry::assembly::{Assembly, Pose};
use crate::math::monte_carlo;
use crate::simulate::{FeatureOptions, Features, TwoArms, features_of_turn};
use rayon::prelude::*;

fn to_pose(s: &TrainState) -> Pose {
    Pose {
        phi_h_rad: s.phi_h_rad,
        intermediate_center_mm: s.intermediate_center_mm,
        planet_center_mm: s.planet_center_mm,
        intermediate_angle_rad: s.intermediate_angle_rad,
        planet_angle_rad: s.planet_angle_rad,
        tip_mm: s.tip_mm,
        sun_mesh_error_mm: 0.0,
        planet_mesh_error_mm: 0.0,
    }
}

/// Features of the perturbed train (both arms carry the same errors; arm 2 = arm 1 at φH + π).
pub(super) fn perturbed_features(
    model: &ExactModel,
    asm: &Assembly,
    phis: &[f64],
    x: &ErrorVector,
    opts: &FeatureOptions,
) -> Result<Features, TransplanterError> {
    let turn: Result<Vec<TwoArms>, TransplanterError> = phis
        .iter()
        .map(|&p| {
            Ok(TwoArms {
                arm1: to_pose(&model.state(p, x)?),
                arm2: to_pose(&model.state(p + model.half_turn(), x)?),
            })
        })
        .collect();
    features_of_turn(&turn?, asm.center_mm, asm.direction, opts)
        .map_err(|e| TransplanterError::Numerical(format!("features: {e}")))
}

/// Deviations (perturbed − nominal) of the features over `opts.feature_samples` random
/// assemblies (exact model); `None` when no samples are asked for.
pub(super) fn feature_deviations(
    model: &ExactModel,
    asm: &Assembly,
    lin: &LinearModel,
    inv: &Inventory,
    opts: &TransplanterOptions,
) -> Result<Option<FeatureDeviations>, TransplanterError> {
    if opts.feature_samples == 0 {
        return Ok(None);
    }
    let phis = &lin.phis_rad;
    let nominal = perturbed_features(model, asm, phis, &[0.0; N_COORDS], &opts.features)?;
    let feats: Result<Vec<Features>, TransplanterError> = (0..opts.feature_samples)
        .into_par_iter()
        .map(|i| {
            let mut rng = rng_for(opts.mc.seed, 2, i);
            let x = inv.draw(&mut rng);
            perturbed_features(model, asm, phis, &x, &opts.features)
        })
        .collect();
    let feats = feats?;
    let stats = |f: &dyn Fn(&Features) -> f64| {
        let v: Vec<f64> = feats.iter().map(|x| f(x) - f(&nominal)).collect();
        monte_carlo::summarize(&v, opts.mc.bins).map_err(mc_error("feature"))
    };
    let wrap = |a: f64| (a + 180.0).rem_euclid(360.0) - 180.0;
    Ok(Some(FeatureDeviations {
        samples: feats.len(),
        height_mm: stats(&|f| f.height_mm)?,
        hole_width_mm: stats(&|f| f.hole_width_mm)?,
        static_width_at_depth_mm: stats(&|f| f.static_width_at_depth_mm)?,
        needle_angle_take_deg: stats(&|f| {
            wrap(f.needle_angle_take_deg - nominal.needle_angle_take_deg)
        })?,
        needle_angle_plant_deg: stats(&|f| {
            wrap(f.needle_angle_plant_deg - nominal.needle_angle_plant_deg)
        })?,
        lowest_point_mm: stats(&|f| f.bbox_mm[2])?,
        nominal,
    }))
}
