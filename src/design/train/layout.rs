//! The train the teeth go on: the integer tooth count by the policy, the assembly scaled to it,
//! its kinematics, the gears' arc frames and mating phases, and what the gears are cut and
//! checked on (the meshes over a carrier turn, the pending mesh check, the teeth report).
use super::cut::{Cutting, teeth_err};
use super::pending::PendingTrainMesh;
use super::swept::TrainMeshes;
use super::{
    TrainError, TrainPolicy, TrainProcess, TrainRoundTrip, TrainTeethOptions, TrainTeethReport,
    TrainUndercut,
};
use crate::geometry::assembly::{Assembly, Rebuilt};
use crate::geometry::pitch::{PitchCurve, PitchError};
use crate::math::Point;
use crate::teeth::mate_motion::{MeshMotion, POSITIONS_PER_PITCH};
use crate::teeth::mesh::MeshCheck;
use crate::teeth::process::GearProcess;
use crate::teeth::{ArcFrame, Outline, ToothCount, ToothPolicy, scale_curve, tooth_count};
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

/// The rounding rule of the tooth count, and whether the module is adjusted instead of the
/// centre distance scaled; refuses the policies that need the designed mechanism.
fn rounding(policy: TrainPolicy) -> Result<(ToothPolicy, bool), TrainError> {
    match policy {
        TrainPolicy::ScaleCenterDistance(p) => Ok((p, false)),
        TrainPolicy::AdjustModule => Ok((ToothPolicy::Nearest, true)),
        TrainPolicy::RatioAmplitude | TrainPolicy::Designed => Err(TrainError::InvalidOption {
            name: "policy",
            value: f64::NAN,
            expected: "scale-centre-distance or adjust-module here; a policy that needs \
                       the designed mechanism (ratio-amplitude, designed) takes the design (TrainSource::Design)",
        }),
    }
}

/// The arc frames of the sun, intermediate and planet pitch curves, built side by side.
fn arc_frames(fin: &Assembly) -> [ArcFrame; 3] {
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
}

/// Mating phases at φH = 0 (the train module's doc): the arc positions (mm) of tooth 0 of the sun, the
/// intermediate gear and the planet, at `z` teeth on the sun's frame. At φH = 0 the intermediate
/// gear faces the sun along D→O (world angle π + ε) and the planet along D→A (−ε).
fn mating_phases(fin: &Assembly, rebuilt: &Rebuilt, sun_frame: &ArcFrame, z: u32) -> [f64; 3] {
    let acc = 1e-12 * fin.a_mm;
    let eps = fin.idler_offset_rad;
    let pose0 = rebuilt.pose(0.0);
    let (th2_0, th3_0) = (pose0.intermediate_angle_rad, pose0.planet_angle_rad);
    let p = sun_frame.length_mm() / f64::from(z);
    let phase_sun = 0.0;
    // The sun (tooth 0 at its arc 0) touches at its body angle ε: its tooth nearest the contact
    // is `s_sun` behind it, and the intermediate gear's tooth space as far ahead on its side.
    let s_sun = arc_at(&fin.sun, eps, acc);
    let s_mid_sun = arc_at(&fin.intermediate, PI + eps - th2_0, acc);
    let phase_mid = s_mid_sun + s_sun + 0.5 * p;
    let s_mid_planet = arc_at(&fin.intermediate, -eps - th2_0, acc);
    let delta = (s_mid_planet - phase_mid).rem_euclid(p);
    let s_planet = arc_at(&fin.planet, PI - eps - th3_0, acc);
    let phase_planet = s_planet + delta + 0.5 * p;
    [phase_sun, phase_mid, phase_planet]
}

/// The sun → intermediate mesh at carrier cycle fraction `u` (φH = 2πu): (driver angle φ, law
/// angle ψ), rad, seen from its line of centres OD at world angle `λ = φH + ε`: `φ = −λ` (the
/// fixed sun), `ψ = λ − θ2`.
pub(super) fn sun_law(rebuilt: &Rebuilt, u: f64) -> (f64, f64) {
    let phi_h = TAU * u;
    let line = phi_h + rebuilt.assembly().idler_offset_rad;
    (-line, line - rebuilt.pose(phi_h).intermediate_angle_rad)
}

/// The intermediate → planet mesh at carrier cycle fraction `u` (φH = 2πu): (driver angle φ, law
/// angle ψ), rad, seen from its line of centres DA at world angle `λ = φH − ε`: `φ = θ2 − λ`,
/// `ψ = λ − θ3`.
pub(super) fn planet_law(rebuilt: &Rebuilt, u: f64) -> (f64, f64) {
    let pose = rebuilt.pose(TAU * u);
    let line = TAU * u - rebuilt.assembly().idler_offset_rad;
    (
        pose.intermediate_angle_rad - line,
        line - pose.planet_angle_rad,
    )
}

/// The train the teeth go on: the options, the integer tooth count, the scale and module, the
/// scaled assembly and its kinematics, the gears' arc frames and mating phases.
pub(super) struct Layout<'o> {
    pub(super) opts: &'o TrainTeethOptions,
    pub(super) count: ToothCount,
    pub(super) scale: f64,
    pub(super) module_mm: f64,
    pub(super) fin: Assembly,
    pub(super) rebuilt: Rebuilt,
    pub(super) frames: [ArcFrame; 3],
    pub(super) phases: [f64; 3],
}

impl<'o> Layout<'o> {
    /// The tooth count by the policy's rounding on the sun, and `asm` scaled to it (or the module
    /// adjusted to it, the scale 1).
    pub(super) fn new(asm: &Assembly, opts: &'o TrainTeethOptions) -> Result<Self, TrainError> {
        let m = opts.toothing.module_mm;
        let (rounding, adjust) = rounding(opts.policy)?;
        let count =
            tooth_count(&asm.sun, m, rounding, 1e-10 * asm.a_mm).map_err(teeth_err("sun"))?;
        crate::bounds::check_teeth("teeth", count.z).map_err(|e| teeth_err("sun")(e.into()))?;
        let (s, m) = if adjust {
            (1.0, count.perimeter_mm / (f64::from(count.z) * PI))
        } else {
            (count.scale, m)
        };
        let fin = scaled(asm, s)?;
        let rebuilt = fin.rebuild();
        let frames = arc_frames(&fin);
        let phases = mating_phases(&fin, &rebuilt, &frames[0], count.z);
        Ok(Self {
            opts,
            count,
            scale: s,
            module_mm: m,
            fin,
            rebuilt,
            frames,
            phases,
        })
    }

    /// The train's two meshes on the carrier `laws` ([`sun_law`], [`planet_law`]), with the whole-outline
    /// mate positions per turn.
    pub(super) fn meshes<'a>(
        &'a self,
        laws: [&'a (dyn Fn(f64) -> (f64, f64) + Sync); 2],
    ) -> TrainMeshes<'a> {
        let (a, m) = (self.fin.a_mm, self.module_mm);
        let backlash_mm = self.opts.toothing.backlash_mm;
        TrainMeshes {
            motions: [
                MeshMotion {
                    at: laws[0],
                    a_mm: a,
                    backlash_mm,
                    driver_pitch: &self.fin.sun,
                    module_mm: m,
                },
                MeshMotion {
                    at: laws[1],
                    a_mm: a,
                    backlash_mm,
                    driver_pitch: &self.fin.intermediate,
                    module_mm: m,
                },
            ],
            positions: self.count.z as usize * POSITIONS_PER_PITCH,
        }
    }

    /// What the gears are cut on, sweeping through `meshes`.
    pub(super) fn cutting<'a>(&'a self, meshes: &'a TrainMeshes<'a>) -> Cutting<'a> {
        Cutting {
            toothing: &self.opts.toothing,
            wire_edm: self.opts.wire_edm,
            frames: &self.frames,
            pitches: [&self.fin.sun, &self.fin.intermediate, &self.fin.planet],
            meshes,
            phases: self.phases,
            z: self.count.z,
            module_mm: self.module_mm,
        }
    }

    /// The mesh check of both meshes on the `fine` outlines, when the options verify.
    pub(super) fn pending(&self, fine: Option<[Vec<Point>; 3]>) -> Option<PendingTrainMesh> {
        let toothing = &self.opts.toothing;
        fine.filter(|_| toothing.verify_steps > 0)
            .map(|outlines| PendingTrainMesh {
                outlines,
                rebuilt: self.rebuilt.clone(),
                check: MeshCheck {
                    steps: toothing.verify_steps,
                    backlash_mm: toothing.backlash_mm,
                    ..MeshCheck::new(self.fin.a_mm, self.module_mm)
                },
            })
    }

    /// The train's teeth report (no mesh check, files or warnings yet) from the unscaled centre
    /// distance `unscaled_a_mm`, the round trip and the cut `gears` and `processes`.
    pub(super) fn report(
        &self,
        unscaled_a_mm: f64,
        roundtrip: TrainRoundTrip,
        gears: &[Outline; 3],
        processes: [GearProcess; 3],
    ) -> TrainTeethReport {
        let (s, a) = (self.scale, self.fin.a_mm);
        let [sun, intermediate, planet] = gears;
        let [sun_process, intermediate_process, planet_process] = processes;
        TrainTeethReport {
            options: self.opts.clone(),
            z: self.count.z,
            module_mm: self.module_mm,
            ratio_amplitude: 1.0,
            z_raw: self.count.z_raw,
            scale: s,
            perimeter_mm: self.frames[0].length_mm(),
            center_distance_mm: a,
            l1_mm: self.rebuilt.l1_mm(),
            radial_shift_mm: (s - 1.0) * 2.0 * unscaled_a_mm * self.fin.idler_offset_rad.cos(),
            roundtrip,
            phase_mm: self.phases,
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
        }
    }
}
