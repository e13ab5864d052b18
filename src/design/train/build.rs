//! Putting teeth on the train: integer tooth count, mating phases, rack-generated outlines,
//! the verification of both meshes and the round trip of the scaled mechanism.
use super::amplitude::{refit_needle_and_phase, rescale_ratio_amplitude};
use super::pending::PendingTrainMesh;
use super::relief::relieve_gear;
use super::swept::{TrainMeshes, neighbours, sweep_gear, sweepable};
use super::{
    ToothedTrain, TrainError, TrainPolicy, TrainProcess, TrainRoundTrip, TrainTeethOptions,
    TrainTeethReport, TrainUndercut,
};
use crate::design::Design;
use crate::geometry::assembly::Assembly;
use crate::geometry::pitch::{PitchCurve, PitchError};
use crate::math::polyline::{distances_to_polyline, hausdorff_mm};
use crate::teeth::TeethError;
use crate::teeth::mate_motion::{MeshMotion, POSITIONS_PER_PITCH};
use crate::teeth::mesh::MeshCheck;
use crate::teeth::process::{
    CutterChoice, GearProcess, Process, generate_as, generate_by_process, swept_process,
};
use crate::teeth::{ArcFrame, Outline, OutlineOptions, ToothPolicy, scale_curve, tooth_count};
use rayon::prelude::*;
use std::f64::consts::{PI, TAU};

fn scaled(asm: &Assembly, s: f64) -> Result<Assembly, PitchError> {
    Ok(Assembly {
        a_mm: asm.a_mm * s,
        sun: scale_curve(&asm.sun, s)?,
        intermediate: scale_curve(&asm.intermediate, s)?,
        planet: scale_curve(&asm.planet, s)?,
        ..asm.clone()
    })
}

/// Arc length (mm) from body angle 0 to `theta` (CCW, wrapped to `[0, 2π)`).
fn arc_at(curve: &PitchCurve, theta: f64, accuracy_mm: f64) -> f64 {
    curve.arc_length_between_mm(0.0, theta.rem_euclid(TAU), accuracy_mm)
}

fn max_tip_distance(traced: &[[f64; 2]], target: &[[f64; 2]]) -> f64 {
    distances_to_polyline(traced, target)
        .into_iter()
        .fold(0.0, f64::max)
}

/// Puts teeth on an assembled train (world frame, as read from `design.json`): integer tooth
/// count by scaling, rack-generated outlines with mating phases, undercut reports, the mesh
/// verification of both meshes (`progress(1)` per verified position, `2·verify_steps` in all) and
/// the round trip of the scaled mechanism against `target_mm` (the trajectory, world frame).
///
/// Errors: [`TrainError::Teeth`] naming the gear (undercut with the largest module that works,
/// concave arc), [`TrainError::InvalidOption`].
pub fn tooth_train(
    asm: &Assembly,
    target_mm: &[[f64; 2]],
    opts: &TrainTeethOptions,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<ToothedTrain, TrainError> {
    verified(train_from(asm, None, target_mm, opts)?, progress)
}

/// [`tooth_train`] on a fresh design, with every policy of docs/math/teeth.md §12.1 including
/// [`TrainPolicy::RatioAmplitude`] (which rebuilds the mechanism with `i_λ = 1 + λ(i21 − 1)`, the
/// same `a`, `l3` and γ, and `accuracy_mm` on the perimeter equation `L(λ) = zπm`).
pub fn tooth_design(
    design: &Design,
    opts: &TrainTeethOptions,
    accuracy_mm: f64,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<ToothedTrain, TrainError> {
    verified(tooth_design_deferred(design, opts, accuracy_mm)?, progress)
}

/// [`tooth_design`] without its mesh verification, which is returned to run later (for example
/// beside the CAD exports, which do not read it): the train's `report.mesh` is `None` until the
/// caller sets it from [`PendingTrainMesh::run`]; no pending check when `verify_steps` is 0.
pub fn tooth_design_deferred(
    design: &Design,
    opts: &TrainTeethOptions,
    accuracy_mm: f64,
) -> Result<(ToothedTrain, Option<PendingTrainMesh>), TrainError> {
    let target = &design.report.target_points;
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
            ..*opts
        };
        let (mut train, pending) = train_from(&design.assembly, None, target, &exact)?;
        train.report.options.policy = TrainPolicy::Designed;
        return Ok((train, pending));
    }
    if opts.policy != TrainPolicy::RatioAmplitude {
        return train_from(&design.assembly, None, target, opts);
    }
    let n = design.assembly.sun.len();
    let fit = rescale_ratio_amplitude(&design.mechanism, opts.toothing.module_mm, n, accuracy_mm)?;
    let (center, direction) = (design.assembly.center_mm, design.assembly.direction);
    let sy = f64::from(direction.signum());
    let solved: Vec<[f64; 2]> = target
        .iter()
        .map(|p| [p[0] - center[0], sy * (p[1] - center[1])])
        .collect();
    let (mechanism, _) = refit_needle_and_phase(&fit.mechanism, &solved);
    let asm = Assembly::from_mechanism(&mechanism, center, direction, n)?;
    let exact = TrainTeethOptions {
        policy: TrainPolicy::ScaleCenterDistance(ToothPolicy::Exact(fit.z)),
        ..*opts
    };
    let (mut train, pending) = train_from(&asm, Some(&design.assembly), target, &exact)?;
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
            "ratio-amplitude policy: z = {} at m = {} mm needs the ratio amplitude × {:.4} (at a fixed centre distance the perimeter changes only to second order in the amplitude), so the toothed train traces a different path: {:.3} mm from the target after re-fitting the needle angle and sun phase (designed {:.4} mm, tolerance {tol} mm); scaling the centre distance (the default policy) keeps the path, or m = {:.4} mm keeps λ = 1 at z = {}",
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
/// `tol_tip_mm` when the report has no C12.
fn design_tolerance_mm(design: &Design) -> f64 {
    design
        .report
        .checks
        .iter()
        .find(|c| c.id == "C12")
        .map_or(crate::design::DesignOptions::default().tol_tip_mm, |c| {
            c.limit
        })
}

/// [`tooth_design`] recorded in the design: on success `design.report.teeth` holds the train's
/// report (the `teeth` block of `design.json`); on error the design is left untouched. Write the
/// CAD files with [`crate::output::write_teeth`], then [`ToothedTrain::record`] again to
/// list them in the report.
pub fn attach_teeth(
    design: &mut Design,
    opts: &TrainTeethOptions,
    accuracy_mm: f64,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<ToothedTrain, TrainError> {
    let train = tooth_design(design, opts, accuracy_mm, progress)?;
    train.record(design);
    Ok(train)
}

/// Runs a pending check (if any) into the train's report.
fn verified(
    (mut train, pending): (ToothedTrain, Option<PendingTrainMesh>),
    progress: &(dyn Fn(u64) + Sync),
) -> Result<ToothedTrain, TrainError> {
    if let Some(p) = pending {
        train.report.mesh = Some(p.run(progress)?);
    }
    Ok(train)
}

fn train_from(
    asm: &Assembly,
    designed: Option<&Assembly>,
    target_mm: &[[f64; 2]],
    opts: &TrainTeethOptions,
) -> Result<(ToothedTrain, Option<PendingTrainMesh>), TrainError> {
    let m = opts.toothing.module_mm;
    for (name, v) in [
        ("module_mm", m),
        ("backlash_mm", opts.toothing.backlash_mm),
        ("chord_tol_mm", opts.toothing.chord_tol_mm),
        ("verify_chord_tol_mm", opts.toothing.verify_chord_tol_mm),
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
    let teeth_err = |gear: &'static str| move |source| TrainError::Teeth { gear, source };
    let (rounding, adjust) = match opts.policy {
        TrainPolicy::ScaleCenterDistance(p) => (p, false),
        TrainPolicy::AdjustModule => (ToothPolicy::Nearest, true),
        TrainPolicy::RatioAmplitude | TrainPolicy::Designed => {
            return Err(TrainError::InvalidOption {
                name: "policy",
                value: f64::NAN,
                expected: "scale-centre-distance or adjust-module here; a policy that needs \
                           the designed mechanism (ratio-amplitude, designed) takes tooth_design",
            });
        }
    };
    let count = tooth_count(&asm.sun, m, rounding, 1e-10 * asm.a_mm).map_err(teeth_err("sun"))?;
    crate::bounds::check_teeth("teeth", count.z).map_err(|e| teeth_err("sun")(e.into()))?;
    let (s, m) = if adjust {
        (1.0, count.perimeter_mm / (f64::from(count.z) * PI))
    } else {
        (count.scale, m)
    };
    let fin = scaled(asm, s)?;
    let a = fin.a_mm;
    let acc = 1e-12 * a;
    let rebuilt = fin.rebuild();
    let pose0 = rebuilt.pose(0.0);
    let (th2_0, th3_0) = (pose0.intermediate_angle_rad, pose0.planet_angle_rad);

    let frames: [ArcFrame; 3] = {
        let (sun, (intermediate, planet)) = rayon::join(
            || ArcFrame::new(&fin.sun),
            || {
                rayon::join(
                    || ArcFrame::new(&fin.intermediate),
                    || ArcFrame::new(&fin.planet),
                )
            },
        );
        [sun, intermediate, planet]
    };
    let p = frames[0].length_mm() / f64::from(count.z);
    // Mating phases at φH = 0 (module doc).
    let phase_sun = 0.0;
    let s_mid_sun = arc_at(&fin.intermediate, PI - th2_0, acc);
    let phase_mid = s_mid_sun + 0.5 * p;
    let s_mid_planet = arc_at(&fin.intermediate, -th2_0, acc);
    let delta = (s_mid_planet - phase_mid).rem_euclid(p);
    let s_planet = arc_at(&fin.planet, PI - th3_0, acc);
    let phase_planet = s_planet + delta + 0.5 * p;
    let phases = [phase_sun, phase_mid, phase_planet];
    let names = ["sun", "intermediate", "planet"];

    let outline_opts = |k: usize, tol: f64| OutlineOptions {
        phase_mm: phases[k],
        thin_left_mm: 0.5 * opts.toothing.backlash_mm,
        thin_right_mm: 0.0,
        chord_tol_mm: tol,
        open_pitch_mm: None,
        refuse_undercut: opts.toothing.refuse_undercut,
    };
    let generate = |k: usize, tol: f64, choice: CutterChoice| {
        generate_by_process(
            &frames[k],
            &opts.toothing.rack,
            count.z,
            m,
            &outline_opts(k, tol),
            choice,
        )
    };
    // The meshes over a carrier turn (φH = 2πu), for sweeping a gear no cutter makes.
    let theta2 = |phi_h: f64| rebuilt.pose(phi_h).intermediate_angle_rad;
    let at1 = |u: f64| {
        let phi_h = TAU * u;
        (-phi_h, phi_h - theta2(phi_h))
    };
    let at2 = |u: f64| {
        let pose = rebuilt.pose(TAU * u);
        (
            pose.intermediate_angle_rad - TAU * u,
            TAU * u - pose.planet_angle_rad,
        )
    };
    let meshes = TrainMeshes {
        motions: [
            MeshMotion {
                at: &at1,
                a_mm: a,
                backlash_mm: opts.toothing.backlash_mm,
                driver_pitch: &fin.sun,
                module_mm: m,
            },
            MeshMotion {
                at: &at2,
                a_mm: a,
                backlash_mm: opts.toothing.backlash_mm,
                driver_pitch: &fin.intermediate,
                module_mm: m,
            },
        ],
        positions: count.z as usize * POSITIONS_PER_PITCH,
    };
    let pitches = [&fin.sun, &fin.intermediate, &fin.planet];
    let choice = opts.toothing.cutter_choice();
    let mut results: Vec<_> = (0..3)
        .into_par_iter()
        .map(|k| generate(k, opts.toothing.chord_tol_mm, choice))
        .collect();
    // A gear no cutter fits is swept by its neighbours when they are cut.
    let cut = [0, 1, 2].map(|k| results[k].is_ok());
    let swept = [0, 1, 2].map(|k| {
        opts.wire_edm && matches!(results[k], Err(TeethError::NoCutter { .. })) && sweepable(k, cut)
    });
    for k in (0..3).filter(|&k| swept[k]) {
        let outlines = [0, 1, 2].map(|j| {
            results[j]
                .as_ref()
                .map_or(&[][..], |g| g.0.points_mm.as_slice())
        });
        let o = outline_opts(k, opts.toothing.chord_tol_mm);
        let rack = &opts.toothing.rack;
        let made = sweep_gear(k, outlines, pitches, &frames, &meshes, rack, count.z, m, &o);
        let placeholder = Err(TeethError::Swept {
            what: String::new(),
        });
        if let Err(no_cutter) = std::mem::replace(&mut results[k], placeholder) {
            results[k] = made.and_then(|(outline, checks)| {
                swept_process(no_cutter, checks).map(|p| (outline, p))
            });
        }
    }
    let mut gears = results
        .into_iter()
        .enumerate()
        .map(|(k, r)| r.map_err(teeth_err(names[k])));
    let (sun, sun_process) = gears.next().expect("three gears")?;
    let (intermediate, intermediate_process) = gears.next().expect("three gears")?;
    let (planet, planet_process) = gears.next().expect("three gears")?;
    let mut gears = [sun, intermediate, planet];
    let mut processes = [sun_process, intermediate_process, planet_process];
    let shaped = |p: &GearProcess| p.process == Process::Shaper;

    // The fine outlines: for the mesh check, and for the tip relief of shaper-cut gears.
    let fine = if opts.toothing.verify_steps > 0 || processes.iter().any(shaped) {
        // Built side by side (collected in gear order); the swept gears then from their
        // neighbours' fine outlines.
        let tol = opts.toothing.verify_chord_tol_mm;
        let mut fine: Vec<Outline> = (0..3)
            .into_par_iter()
            .map(|k| {
                if swept[k] {
                    Ok(Outline {
                        points_mm: Vec::new(),
                        ..gears[k].clone()
                    })
                } else {
                    // The same process and cutter as the export outline.
                    generate_as(
                        &frames[k],
                        &opts.toothing.rack,
                        count.z,
                        m,
                        &outline_opts(k, tol),
                        &processes[k],
                    )
                    .map_err(teeth_err(names[k]))
                }
            })
            .collect::<Result<_, _>>()?;
        for k in (0..3).filter(|&k| swept[k]) {
            let outlines = [0, 1, 2].map(|j| fine[j].points_mm.as_slice());
            let o = outline_opts(k, tol);
            let g = sweep_gear(
                k,
                outlines,
                pitches,
                &frames,
                &meshes,
                &opts.toothing.rack,
                count.z,
                m,
                &o,
            )
            .map_err(teeth_err(names[k]))?;
            fine[k] = g.0;
        }
        let mut fine = <[Outline; 3]>::try_from(fine)
            .unwrap_or_else(|_| unreachable!("three gears"))
            .map(|o| o.points_mm);
        // Tip relief of the cut gears of every mesh with a shaper-cut gear, against their
        // neighbours, all found on the unrelieved outlines (a relief moves only tips, never a
        // fillet); the meshes of two rack-cut (convex) gears keep their outlines.
        let relieve = |k: usize| {
            let mesh_has_shaper = shaped(&processes[k])
                || neighbours(k)
                    .iter()
                    .any(|&(nb, _, _)| shaped(&processes[nb]));
            !swept[k] && mesh_has_shaper
        };
        let relieved = (0..3)
            .into_par_iter()
            .map(|k| {
                if !relieve(k) {
                    return Ok(None);
                }
                relieve_gear(
                    k,
                    &fine,
                    &frames,
                    &meshes,
                    &opts.toothing,
                    count.z,
                    m,
                    &processes[k],
                    &outline_opts(k, opts.toothing.chord_tol_mm),
                )
            })
            .collect::<Result<Vec<_>, _>>()?;
        for (k, r) in relieved.into_iter().enumerate() {
            if let Some(r) = r {
                gears[k] = r.export;
                fine[k] = r.fine_mm;
                processes[k].set_relief(&r.relief_mm, r.min_tip_width_mm);
            }
        }
        Some(fine)
    } else {
        None
    };
    let pending = fine
        .filter(|_| opts.toothing.verify_steps > 0)
        .map(|outlines| PendingTrainMesh {
            outlines,
            rebuilt: rebuilt.clone(),
            check: MeshCheck {
                steps: opts.toothing.verify_steps,
                backlash_mm: opts.toothing.backlash_mm,
                ..MeshCheck::new(a, m)
            },
        });
    let [sun, intermediate, planet] = gears;
    let [sun_process, intermediate_process, planet_process] = processes;

    // Round trip of the final gears (and of the unscaled ones, for the comparison).
    let n = opts.roundtrip_samples;
    let (before, after) = rayon::join(
        || designed.unwrap_or(asm).rebuild().traced(n),
        || rebuilt.traced(n),
    );
    let shift = before
        .iter()
        .zip(&after)
        .map(|(p, q)| (p[0] - q[0]).hypot(p[1] - q[1]))
        .fold(0.0, f64::max);
    let roundtrip = TrainRoundTrip {
        before_max_deviation_mm: max_tip_distance(&before, target_mm),
        max_deviation_mm: max_tip_distance(&after, target_mm),
        hausdorff_mm: hausdorff_mm(&after, target_mm),
        before_hausdorff_mm: hausdorff_mm(&before, target_mm),
        max_tip_shift_mm: shift,
    };
    let report = TrainTeethReport {
        options: *opts,
        z: count.z,
        module_mm: m,
        ratio_amplitude: 1.0,
        z_raw: count.z_raw,
        scale: s,
        perimeter_mm: frames[0].length_mm(),
        center_distance_mm: a,
        l1_mm: 2.0 * a,
        radial_shift_mm: (s - 1.0) * 2.0 * asm.a_mm,
        roundtrip,
        phase_mm: phases,
        undercut: TrainUndercut {
            sun: sun.undercut.clone(),
            intermediate: intermediate.undercut.clone(),
            planet: planet.undercut.clone(),
        },
        mesh: None,
        files: Vec::new(),
        needle_angle_deg: None,
        sun_phase_deg: None,
        warnings: Vec::new(),
        process: Some(TrainProcess {
            sun: sun_process,
            intermediate: intermediate_process,
            planet: planet_process,
        }),
    };
    let train = ToothedTrain {
        report,
        assembly: fin,
        sun,
        intermediate,
        planet,
    };
    Ok((train, pending))
}
