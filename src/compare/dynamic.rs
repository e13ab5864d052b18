//! The track against the train's dynamic path (`ncgear compare --dynamics SCENE.toml`,
//! docs/compare.md, "Against the dynamics").
//!
//! The static path assumes rigid teeth without play. A built train leans across its backlash
//! and its teeth bend, so its tip runs off that path by an amount the rotor dynamics compute
//! ([`crate::analysis::dynamics::rotor`]; the bundled G1 rotor, 0.73 mm at 300 r/min). Here the
//! rotor scene runs its settled turn at the track's recorded mean speed, the tip's dynamic path
//! `B_dyn(φ)` replaces the static one as the reference, and the track is registered to it and
//! compared exactly as to the static path ([`super::compare_to_path`]). The share of the static
//! deviation the dynamics explain is `1 − (rms_dyn/rms_static)²` of the smooth deviations'
//! mean squares: the difference the model accounts for, and what is left for the machine.

use super::design_path::{DesignPath, SAMPLES};
use super::report::DynamicsComparison;
use super::{CompareError, CompareOptions, Comparison, Track, compare_to_path};
use crate::analysis::dynamics::rotor::{Prepared, RotorReport};
use crate::geometry::assembly::Rebuilt;
use crate::progress::Progress;
use std::f64::consts::TAU;

/// Largest tip distance (mm) between the scene's design and the compared design over a turn
/// for the two to count as the same train.
pub const SAME_DESIGN_MM: f64 = 1e-6;

/// The track of `static_cmp` (compared with [`super::compare`] to `rebuilt`) against the dynamic
/// path of `prepared` at the track's mean carrier speed: the comparison to that path, and its
/// summary beside the static one. `progress` hears every turn of the rotor's run.
///
/// # Errors
/// [`CompareError::BadOption`] (`dynamics`): the scene's design is not `rebuilt`'s train, or its
/// run failed; otherwise as [`super::compare`].
pub fn against_dynamics(
    track: &Track,
    rebuilt: &Rebuilt,
    static_cmp: &Comparison,
    prepared: &Prepared,
    opts: &CompareOptions,
    progress: &Progress,
) -> Result<(Comparison, DynamicsComparison), CompareError> {
    let bad = |message: String| super::bad("dynamics", message);
    let path = DesignPath::new(rebuilt);
    let scene = DesignPath::new(&prepared.built.model.rebuilt);
    let apart = (0..SAMPLES / 16)
        .map(|k| {
            let phi = TAU * k as f64 / (SAMPLES / 16) as f64;
            path.tip(phi).0.distance(scene.tip(phi).0)
        })
        .fold(0.0, f64::max);
    if apart > SAME_DESIGN_MM || path.direction != scene.direction {
        return Err(bad(format!(
            "the scene `{}` runs another train (its tip is up to {apart:.3} mm from the design's): \
             give it the design file the track was built from",
            prepared.case.name
        )));
    }
    let rpm = static_cmp.report.registration.mean_rpm;
    let run = prepared.run_at_rpm(rpm, None, progress).map_err(|e| {
        bad(format!(
            "the scene `{}` at {rpm:.2} r/min: {e}",
            prepared.case.name
        ))
    })?;
    let moved = path
        .moved_to(&run.report.tip_mm)
        .ok_or_else(|| bad("the scene's run has fewer than 8 samples a turn".into()))?;
    let cmp = compare_to_path(track, &moved, opts)?;
    let (max_dep, rms_dep) = departure(&path, &run.report);
    let d = &cmp.report.deviation;
    let static_rms = static_cmp.report.deviation.rms_mm;
    let summary = DynamicsComparison {
        scene: prepared.case.name.clone(),
        carrier_rpm: rpm,
        turns: run.report.steady.turns,
        settled: run.report.steady.settled,
        max_tip_departure_mm: max_dep,
        rms_tip_departure_mm: rms_dep,
        rms_mm: d.rms_mm,
        max_mm: d.max_mm,
        max_at_carrier_deg: d.max_at_carrier_deg,
        hausdorff_mm: d.hausdorff_mm,
        static_rms_mm: static_rms,
        explained: if static_rms > 0.0 {
            1.0 - (d.rms_mm / static_rms).powi(2)
        } else {
            0.0
        },
        noise_mm: cmp.report.registration.noise_mm,
    };
    Ok((cmp, summary))
}

/// `(largest, RMS)` distance (mm) of the run's dynamic tip from the static tip at the same
/// carrier angle over its samples of travel.
fn departure(path: &DesignPath, report: &RotorReport) -> (f64, f64) {
    let n = report.tip_mm.len().max(1);
    let d: Vec<f64> = report
        .tip_mm
        .iter()
        .enumerate()
        .map(|(k, b)| b.distance(path.tip(path.angle_at(k, n)).0))
        .collect();
    let max = d.iter().copied().fold(0.0, f64::max);
    let rms = (d.iter().map(|x| x * x).sum::<f64>() / n as f64).sqrt();
    (max, rms)
}
