//! The transplanter tolerance analysis: linear-model validation at 3σ, Monte Carlo of random
//! assembly, and the assembly of the report from its parts (docs/math/companion.md §C.6 items 3, 4, 6).

use super::best_assembly::optimize_assembly;
use super::common::{TransplanterOptions, UM, exact_max, mc_error, rng_for};
use super::envelope::envelope;
use super::features::feature_deviations;
use super::model::{ExactModel, LinearModel};
use super::ranking::ranking;
use super::report::{TransplanterReport, Validation};
use super::{ErrorVector, Inventory, N_COORDS, TransplanterError};
use crate::analysis::tolerance::ARCSEC_PER_RAD;
use crate::geometry::assembly::Assembly;
use crate::math::monte_carlo::{self};
use crate::math::periodic::wrap_pi;
use crate::progress::Progress;
use rayon::prelude::*;

/// `max_φ |Δθ3|` (rad) of the exact model.
fn exact_max_angle(
    model: &ExactModel,
    lin: &LinearModel,
    x: &ErrorVector,
) -> Result<f64, TransplanterError> {
    let zero = [0.0; N_COORDS];
    let mut m: f64 = 0.0;
    for p in &lin.phis_rad {
        let a = model.state(*p, x)?.planet_angle_rad;
        let b = model.state(*p, &zero)?.planet_angle_rad;
        m = m.max(wrap_pi(a - b).abs());
    }
    Ok(m)
}

/// Relative error of the linear model on one sample: (relative, absolute mm).
fn linear_error(
    model: &ExactModel,
    lin: &LinearModel,
    x: &ErrorVector,
) -> Result<(f64, f64), TransplanterError> {
    let (mut worst, mut peak): (f64, f64) = (0.0, 0.0);
    for (i, (p, b0)) in lin.phis_rad.iter().zip(&lin.nominal_tips_mm).enumerate() {
        let b = model.state(*p, x)?.tip_mm;
        let d = b - *b0;
        let l = lin.deviation_at(i, x);
        worst = worst.max((l - d).hypot());
        peak = peak.max(d.hypot());
    }
    Ok((if peak > 0.0 { worst / peak } else { 0.0 }, worst))
}

/// Most Monte Carlo samples of the transplanter analysis (≈ 27 µs each on one core).
pub const MAX_MC_SAMPLES: usize = 200_000;

/// Runs the transplanter tolerance analysis of one arm of `asm` with the error inventory `inv`.
/// `progress` hears the Monte Carlo samples: `opts.mc.samples` of the tip deviation, then as
/// many of the optimizer's random assemblies when `inv` has a free eccentricity direction.
pub fn analyse(
    asm: &Assembly,
    inv: &Inventory,
    opts: &TransplanterOptions,
    progress: &Progress,
) -> Result<TransplanterReport, TransplanterError> {
    if !(2..=MAX_MC_SAMPLES).contains(&opts.mc.samples) {
        return Err(TransplanterError::BadOption {
            option: "mc.samples",
            message: format!(
                "{}: 2..=200000 Monte Carlo samples (each rebuilds the train's motion: a million \
                 took 27 s)",
                opts.mc.samples
            ),
        });
    }
    if opts.linear_tolerance.is_nan() || opts.linear_tolerance <= 0.0 {
        return Err(TransplanterError::BadOption {
            option: "linear_tolerance",
            message: format!("{}: must be positive", opts.linear_tolerance),
        });
    }
    let model = ExactModel::new(asm, inv.pressure_angle_rad, inv.load_side)?;
    let lin = LinearModel::build(&model, inv.samples_per_turn, opts.fd_steps)?;
    // Validation at 3σ (docs/math/companion.md §C.6 item 3).
    let errs: Result<Vec<(f64, f64)>, TransplanterError> = (0..opts.validation_samples)
        .into_par_iter()
        .map(|i| {
            let mut rng = rng_for(opts.mc.seed, 1, i);
            linear_error(&model, &lin, &inv.draw_three_sigma(&mut rng))
        })
        .collect();
    let errs = errs?;
    let nv = errs.len().max(1) as f64;
    let max_rel = errs.iter().map(|e| e.0).fold(0.0, f64::max);
    let use_linear = max_rel <= opts.linear_tolerance;
    let validation = Validation {
        samples: errs.len(),
        max_relative_error: max_rel,
        mean_relative_error: errs.iter().map(|e| e.0).sum::<f64>() / nv,
        max_absolute_error_um: errs.iter().map(|e| e.1).fold(0.0, f64::max) * UM,
        model_used: if use_linear { "linear" } else { "exact" }.into(),
    };
    let given = inv.nominal_vector();
    // One metric of the random assemblies: the linear model's value, or the exact one's when
    // the validation failed. Both metrics use the same seed, hence the same samples.
    type Exact = fn(&ExactModel, &LinearModel, &ErrorVector) -> Result<f64, TransplanterError>;
    let distribution = |linear: fn(&LinearModel, &ErrorVector) -> f64,
                        exact: Exact,
                        scale: f64,
                        what: &'static str,
                        progress: &Progress| {
        monte_carlo::run(
            &opts.mc,
            |rng, _| {
                let x = inv.draw(rng);
                if use_linear {
                    linear(&lin, &x) * scale
                } else {
                    exact(&model, &lin, &x).map_or(f64::NAN, |v| v * scale)
                }
            },
            progress,
        )
        .map(|(stats, _)| stats)
        .map_err(mc_error(what))
    };
    let stats = distribution(
        LinearModel::max_deviation_mm,
        exact_max,
        UM,
        "tip deviation (the exact model found no contact: errors too large)",
        progress,
    )?;
    let te = distribution(
        LinearModel::max_planet_angle_error_rad,
        exact_max_angle,
        ARCSEC_PER_RAD,
        "planet angle error (the exact model found no contact)",
        &Progress::none(),
    )?;
    let env = envelope(&lin, inv);
    let envelope_max_um = env.iter().map(|p| p.envelope_um).fold(0.0, f64::max);
    Ok(TransplanterReport {
        pressure_angle_deg: inv.pressure_angle_rad.to_degrees(),
        load_side: inv.load_side,
        samples_per_turn: inv.samples_per_turn,
        nominal_errors_exact_um: exact_max(&model, &lin, &given)? * UM,
        nominal_errors_linear_um: lin.max_deviation_mm(&given) * UM,
        validation,
        seed: opts.mc.seed,
        max_deviation_um: stats,
        planet_angle_error_arcsec: te,
        envelope: env,
        envelope_max_um,
        features: feature_deviations(&model, asm, &lin, inv, opts)?,
        ranking: ranking(&lin, inv),
        assembly: optimize_assembly(&model, &lin, inv, opts, progress)?,
    })
}
