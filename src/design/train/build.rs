//! Putting teeth on the train: integer tooth count, mating phases, rack-generated outlines,
//! the verification of both meshes and the round trip of the scaled mechanism.
use super::amplitude::{refit_needle_and_phase, rescale_ratio_amplitude};
use super::layout::{Layout, planet_law, sun_law};
use super::pending::PendingTrainMesh;
use super::{ToothedTrain, TrainError, TrainPolicy, TrainRoundTrip, TrainTeethOptions};
use crate::design::Design;
use crate::design::trajectory::roundtrip::deviations_as_designed;
use crate::geometry::assembly::{Assembly, Rebuilt};
use crate::math::Point;
use crate::math::polyline::{distances_to_polyline, hausdorff_mm};
use crate::teeth::ToothPolicy;
use std::f64::consts::PI;

fn max_tip_distance(traced: &[Point], target: &[Point]) -> f64 {
    distances_to_polyline(traced, target)
        .into_iter()
        .fold(0.0, f64::max)
}

/// What [`tooth_train`] puts teeth on.
#[derive(Debug, Clone, Copy)]
pub enum TrainSource<'a> {
    /// A fresh design: every policy of docs/math/teeth.md §12.1, including
    /// [`TrainPolicy::Designed`] (the design's own tooth count) and
    /// [`TrainPolicy::RatioAmplitude`] (which rebuilds the mechanism with `i_λ = 1 + λ(i21 − 1)`,
    /// the same `a`, `l3` and γ, and [`TrainTeethOptions::accuracy_mm`] on the perimeter equation
    /// `L(λ) = zπm`). `From<&Design>` makes `tooth_train(&design, &opts)`.
    Design(&'a Design),
    /// An assembled train (world frame, as read from `design.json`) and the target it was
    /// designed for (mm, world frame): the scaling policies.
    Assembly {
        /// The train.
        assembly: &'a Assembly,
        /// The trajectory, world frame, mm.
        target_mm: &'a [Point],
    },
}

impl<'a> From<&'a Design> for TrainSource<'a> {
    fn from(design: &'a Design) -> Self {
        Self::Design(design)
    }
}

/// Puts teeth on a train: integer tooth count by the policy, rack-generated outlines with mating
/// phases, undercut reports, the mesh verification of both meshes and the round trip of the
/// toothed mechanism against the target. Record the result in its design with
/// [`ToothedTrain::record`]. To watch the verification (`2·verify_steps` positions), run the two
/// stages: [`tooth_train_staged`], then [`PendingTrainMesh::run`] with a [`Progress`](crate::progress::Progress).
///
/// # Errors
/// [`TrainError::Teeth`] naming the gear (undercut with the largest module that works, concave
/// arc), [`TrainError::InvalidOption`], [`TrainError::NotDesignedForModule`], a mesh check that
/// cannot run.
pub fn tooth_train<'a>(
    on: impl Into<TrainSource<'a>>,
    opts: &TrainTeethOptions,
) -> Result<ToothedTrain, TrainError> {
    let (mut train, pending) = tooth_train_staged(on, opts)?;
    if let Some(p) = pending {
        train.report.mesh = Some(p.run(&crate::progress::Progress::none())?);
    }
    Ok(train)
}

/// [`tooth_train`] in its two stages, for a caller that runs the mesh verification beside other
/// work (the CAD exports do not read it): the train, its `report.mesh` `None`, and the check
/// ready to run ([`PendingTrainMesh::run`]; `None` when `verify_steps` is 0).
///
/// # Errors
/// As [`tooth_train`], except the check's own.
pub fn tooth_train_staged<'a>(
    on: impl Into<TrainSource<'a>>,
    opts: &TrainTeethOptions,
) -> Result<(ToothedTrain, Option<PendingTrainMesh>), TrainError> {
    check_options(opts)?;
    match on.into() {
        TrainSource::Design(design) => design_staged(design, opts),
        TrainSource::Assembly {
            assembly,
            target_mm,
        } => train_from(assembly, None, (target_mm, None), opts),
    }
}

/// The stages on a fresh design (every policy).
fn design_staged(
    design: &Design,
    opts: &TrainTeethOptions,
) -> Result<(ToothedTrain, Option<PendingTrainMesh>), TrainError> {
    let target = &design.report.target_points;
    // Measured as check C12 measures the design, at the carrier angles where its tip passes the
    // points, unless the policy re-times the train (ratio-amplitude refits its phases).
    let as_designed = (target.as_slice(), Some(design.point_angles_rad.as_slice()));
    if opts.policy == TrainPolicy::Designed {
        let m = opts.toothing.module_mm;
        let z = match &design.report.module {
            Some(d) if (d.module_mm - m).abs() <= 1e-12 * m => d.teeth,
            other => {
                return Err(TrainError::NotDesignedForModule {
                    module_mm: m,
                    designed_mm: other.as_ref().map(|d| d.module_mm),
                });
            }
        };
        let exact = TrainTeethOptions {
            policy: TrainPolicy::ScaleCenterDistance(ToothPolicy::Exact(z)),
            ..opts.clone()
        };
        let (mut train, pending) = train_from(&design.assembly, None, as_designed, &exact)?;
        train.report.options.policy = TrainPolicy::Designed;
        return Ok((train, pending));
    }
    if opts.policy != TrainPolicy::RatioAmplitude {
        return train_from(&design.assembly, None, as_designed, opts);
    }
    let n = design.assembly.sun.len();
    let accuracy_mm = opts.accuracy_mm.unwrap_or(1e-9 * design.assembly.a_mm);
    let fit = rescale_ratio_amplitude(&design.mechanism, opts.toothing.module_mm, n, accuracy_mm)?;
    let (center, direction) = (design.assembly.center_mm, design.assembly.direction);
    let sy = f64::from(direction.signum());
    let solved: Vec<Point> = target
        .iter()
        .map(|p| Point::new(p.x - center.x, sy * (p.y - center.y)))
        .collect();
    let (mechanism, _) = refit_needle_and_phase(&fit.mechanism, &solved);
    let asm = Assembly::from_mechanism(&mechanism, center, direction, n)?;
    let exact = TrainTeethOptions {
        policy: TrainPolicy::ScaleCenterDistance(ToothPolicy::Exact(fit.z)),
        ..opts.clone()
    };
    let (mut train, pending) = train_from(&asm, Some(&design.assembly), (target, None), &exact)?;
    let r = &mut train.report;
    r.options.policy = TrainPolicy::RatioAmplitude;
    r.ratio_amplitude = fit.lambda;
    r.needle_angle_deg = Some(sy * mechanism.needle_angle_rad.to_degrees());
    r.sun_phase_deg = Some(
        (sy * mechanism.sun_phase_rad)
            .to_degrees()
            .rem_euclid(360.0),
    );
    r.z_raw = design.report.gears.sun.perimeter_mm / (PI * opts.toothing.module_mm);
    let tol = design_tolerance_mm(design);
    if r.roundtrip.max_deviation_mm > tol {
        r.warnings.push(format!(
            "ratio-amplitude policy: z = {} at m = {} mm needs the ratio amplitude × {:.4} (at a fixed centre distance the perimeter changes only to second order in the amplitude), so the toothed train traces a different path: {:.3} mm from the target after re-fitting the needle angle and sun phase (designed {:.4} mm, tolerance {tol} mm); the default policy (design) fits the train at the tooth count instead, or m = {:.4} mm keeps λ = 1 at z = {}",
            fit.z,
            opts.toothing.module_mm,
            fit.lambda,
            r.roundtrip.max_deviation_mm,
            r.roundtrip.before_max_deviation_mm,
            design.report.gears.sun.perimeter_mm / (PI * f64::from(fit.z)),
            fit.z
        ));
    }
    Ok((train, pending))
}

/// The tip tolerance the design was judged against (check C12's limit), mm; the default
/// `tol_mm` when the report has no C12.
fn design_tolerance_mm(design: &Design) -> f64 {
    design
        .report
        .checks
        .iter()
        .find(|c| c.id == "C12")
        .map_or(crate::design::DesignOptions::default().tol_mm, |c| c.limit)
}

/// Teeth on the train `asm` (world frame), its options checked by the caller: the layout scaled
/// to an integer tooth count, the three gears cut (and relieved), the mesh check left pending and
/// the round trip against the target points (mm, world frame; with the design's carrier angles at them
/// when known, [`round_trip`]) compared with `designed` (`asm` when `None`).
fn train_from(
    asm: &Assembly,
    designed: Option<&Assembly>,
    target_mm: (&[Point], Option<&[f64]>),
    opts: &TrainTeethOptions,
) -> Result<(ToothedTrain, Option<PendingTrainMesh>), TrainError> {
    let layout = Layout::new(asm, opts)?;
    // The meshes over a carrier turn (φH = 2πu), for sweeping a gear no cutter makes.
    let rebuilt = &layout.rebuilt;
    let (at1, at2) = (|u| sun_law(rebuilt, u), |u| planet_law(rebuilt, u));
    let meshes = layout.meshes([&at1, &at2]);
    let cutting = layout.cutting(&meshes);
    let mut cut = cutting.cut()?;
    let fine = cutting.fine(&mut cut)?;
    let pending = layout.pending(fine);
    let n = opts.roundtrip_samples;
    let roundtrip = round_trip(designed.unwrap_or(asm), &layout.rebuilt, target_mm, n);
    let report = layout.report(asm.a_mm, roundtrip, &cut.gears, cut.processes);
    let [sun, intermediate, planet] = cut.gears;
    let train = ToothedTrain {
        report,
        assembly: layout.fin,
        sun,
        intermediate,
        planet,
    };
    Ok((train, pending))
}

/// Refuses options out of range: a non-positive module, backlash, chord tolerance or accuracy
/// (a bisection to a tolerance of 0 or NaN would not end), fewer than 16 round-trip samples.
fn check_options(opts: &TrainTeethOptions) -> Result<(), TrainError> {
    let m = opts.toothing.module_mm;
    for (name, v) in [
        ("module_mm", m),
        ("backlash_mm", opts.toothing.backlash_mm),
        ("chord_tol_mm", opts.toothing.chord_tol_mm),
        ("verify_chord_tol_mm", opts.toothing.verify_chord_tol_mm),
        ("accuracy_mm", opts.accuracy_mm.unwrap_or(1.0)),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(TrainError::InvalidOption {
                name,
                value: v,
                expected: "finite and > 0",
            });
        }
    }
    if opts.roundtrip_samples < 16 {
        return Err(TrainError::InvalidOption {
            name: "roundtrip_samples",
            value: opts.roundtrip_samples as f64,
            expected: "≥ 16",
        });
    }
    Ok(())
}

/// Round trip of the final gears (`rebuilt`) and of the unscaled ones (`designed`, for the
/// comparison) over `n` carrier positions, against the target points. With the carrier angles
/// at which the designed tip passes them (`angles`, rad, solved frame), measured as check C12
/// measures the design ([`deviations_as_designed`]: the same numbers for a train made for the
/// module); without, against the points' polyline.
fn round_trip(
    designed: &Assembly,
    rebuilt: &Rebuilt,
    (target_mm, angles): (&[Point], Option<&[f64]>),
    n: usize,
) -> TrainRoundTrip {
    let designed = designed.rebuild();
    let (before, after) = rayon::join(|| designed.traced(n), || rebuilt.traced(n));
    let shift = before
        .iter()
        .zip(&after)
        .map(|(p, q)| p.distance(*q))
        .fold(0.0, f64::max);
    let measure = |r: &Rebuilt, traced: &[Point]| match angles {
        Some(angles) => deviations_as_designed(r, target_mm, angles, n),
        None => (
            max_tip_distance(traced, target_mm),
            hausdorff_mm(traced, target_mm),
        ),
    };
    let ((before_max, before_h), (after_max, after_h)) =
        rayon::join(|| measure(&designed, &before), || measure(rebuilt, &after));
    TrainRoundTrip {
        before_max_deviation_mm: before_max,
        max_deviation_mm: after_max,
        hausdorff_mm: after_h,
        before_hausdorff_mm: before_h,
        max_tip_shift_mm: shift,
    }
}
