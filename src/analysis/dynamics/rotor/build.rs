//! From a validated scene and a designed train to the [`RotorModel`]: the rigid train of the
//! loads (bodies, pressure angle, needle table), each named effect built, and the run log's
//! line for each.

use super::RotorError;
use super::drive::DriveModel;
use super::law::{MeshLaw, ToothData};
use super::lever_rate::LeverRates;
use super::model::RotorModel;
use super::scene::{Backlash, Effects, StiffnessLaw};
use crate::loads::analysis::{needle_table, rigid_train, train_turn};
use crate::loads::motion::TrainMotion;
use crate::loads::scene::FaceWidth;
use crate::loads::{LoadCase, Rotor};
use std::f64::consts::TAU;

/// A built model and the run log's lines (one per effect, with its parameters).
#[derive(Debug, Clone)]
pub struct Built {
    /// The model of train 1.
    pub model: RotorModel,
    /// One line per effect built.
    pub effects_log: Vec<String>,
}

/// Builds the model of `rotor` under `case` with `effects`; `teeth` the design's teeth (for the
/// ISO stiffness and `backlash = "teeth"`); `file` names the scene in errors.
///
/// # Errors
/// [`RotorError::Field`]: no face width, ISO stiffness or `"teeth"` backlash without teeth; the
/// loads' errors.
pub fn build(
    rotor: &Rotor<'_>,
    case: &LoadCase,
    effects: &Effects,
    teeth: Option<ToothData>,
    file: &str,
) -> Result<Built, RotorError> {
    let field = |key: &str, message: &str| RotorError::Field {
        file: file.into(),
        key: key.into(),
        message: message.into(),
    };
    let face_mm = match case.bodies.map(|b| b.face_width) {
        Some(FaceWidth::Mm(b)) => b,
        _ => {
            return Err(field(
                "gears.face_width_mm",
                "the dynamics need the gear bodies' face width in mm (for the stiffness and \
                 the inertias)",
            ));
        }
    };
    let rigid = rigid_train(rotor, case, face_mm, file)?;
    let r = rigid.rebuilt;
    let n = case.samples;
    let motion: Vec<TrainMotion> = (0..n)
        .map(|k| TrainMotion::at(&r, TAU * k as f64 / n as f64))
        .collect();
    let needle = needle_table(&r, case, &motion);
    let mut log = Vec::new();
    let need_teeth = |what: &str| {
        teeth.ok_or_else(|| {
            field(
                if what == "backlash" {
                    "effects.backlash"
                } else {
                    "effects.mesh_stiffness"
                },
                &format!(
                    "the {what} reads the design's teeth, and the design has none: design with \
                     a module (teeth), or give a value ({})",
                    if what == "backlash" {
                        "backlash = 0.08, mm on the line of action"
                    } else {
                        "kind = \"constant\""
                    }
                ),
            )
        })
    };
    let sign = r.sign();
    let laws = match effects.stiffness {
        StiffnessLaw::Constant(k) => {
            log.push(format!(
                "mesh_stiffness: constant, k = {:.4e}, {:.4e} N/m (sun–intermediate, \
                 intermediate–planet)",
                k[0], k[1]
            ));
            k.map(MeshLaw::Constant)
        }
        StiffnessLaw::Iso { scale, pairs } => {
            let t = need_teeth("ISO stiffness")?;
            let [sun, mid, _] = r.ccw_curves();
            // The rigid loads' signed mesh forces at the samples: their flank between samples
            // is the sign of the force linear between them (law's module docs).
            let signed: [Vec<f64>; 2] = if pairs == super::spec::PairsMode::Alternating {
                let turn = train_turn(&r, case, &rigid.bodies, rigid.alpha_rad)?;
                [0, 1].map(|j| {
                    turn.forces
                        .iter()
                        .map(|f| {
                            let m = if j == 0 { f.sun_mesh } else { f.planet_mesh };
                            f64::from(m.flank) * m.normal_force_n
                        })
                        .collect()
                })
            } else {
                [Vec::new(), Vec::new()]
            };
            let make = |j: usize| {
                let driver = if j == 0 { sun } else { mid };
                let phase = r.sign() * t.phase_mm[j];
                let f = &signed[j];
                let flank = |phi: f64| -> i8 {
                    if f.is_empty() {
                        return 1;
                    }
                    let x = phi.rem_euclid(TAU) / TAU * n as f64;
                    let k = (x.floor() as usize).min(n - 1);
                    let u = x - k as f64;
                    let v = (1.0 - u) * f[k] + u * f[(k + 1) % n];
                    if v < 0.0 { -1 } else { 1 }
                };
                MeshLaw::iso(
                    scale,
                    pairs,
                    t,
                    face_mm,
                    driver,
                    phase,
                    &flank,
                    &|phi, f| {
                        let m = TrainMotion::at(&r, phi);
                        let [s, mi, p] = r.ccw_curves();
                        let (pitch, curves) = if j == 0 {
                            (&m.sun_mesh, [s, mi])
                        } else {
                            (&m.planet_mesh, [mi, p])
                        };
                        f(&super::law::Contact { pitch, curves });
                    },
                )
            };
            let laws = [make(0), make(1)];
            log.push(format!(
                "mesh_stiffness: ISO 6336-1 c′, c_γα on the local equivalent pair × {scale}, \
                 pairs {pairs:?}, b = {face_mm} mm, m = {} mm, z = {}; {} + {} pair switches a turn",
                t.module_mm,
                t.z,
                laws[0].switches().len(),
                laws[1].switches().len()
            ));
            laws
        }
    };
    let half_gap_m = match effects.backlash {
        None => [0.0; 2],
        Some(Backlash::Normal(b)) => b.map(|b| 0.5 * b),
        Some(Backlash::Teeth) => {
            let t = need_teeth("backlash")?;
            [0.5 * t.backlash_mm * 1e-3 * t.alpha_rad.cos(); 2]
        }
    };
    if effects.backlash.is_some() {
        log.push(format!(
            "backlash: dead zone ±{:.2}, ±{:.2} µm on the line of action, contact loss and \
             re-contact located as events",
            half_gap_m[0] * 1e6,
            half_gap_m[1] * 1e6
        ));
    }
    let mut model = RotorModel {
        omega: case.omega_rad_s,
        bodies: rigid.bodies,
        alpha: rigid.alpha_rad,
        gravity: {
            let g = case.gravity_m_s2;
            crate::math::Point::new(g.x, sign * g.y)
        },
        needle,
        laws,
        damping: [0.0; 2],
        half_gap_m,
        vibration_damping: [0.0; 2],
        lever_rates: None,
        drive: None,
        id: super::model::new_model_id(),
        turn_periodic: RotorModel::repeats_each_turn(&r),
        rebuilt: r,
    };
    if effects.zeta.iter().any(|&z| z > 0.0) {
        let (lev, k) = model.means(360);
        let [j2, j3] = model.inertias_kg_m2();
        let m_e = [
            j2 / lev[0][1].powi(2),
            j2 * j3 / (j2 * lev[1][1].powi(2) + j3 * lev[1][0].powi(2)),
        ];
        model.damping = [0, 1].map(|j| 2.0 * effects.zeta[j] * (k[j] * m_e[j]).sqrt());
        let rates = LeverRates::new(model.turn_periodic, &|p| {
            model.geometry(&TrainMotion::at(&model.rebuilt, p))
        });
        model.lever_rates = Some(rates);
        log.push(format!(
            "mesh_damping: ζ = {}, {} → c = {:.4e}, {:.4e} N·s/m (2ζ√(k̄·m_e), m_e = {:.4e}, \
             {:.4e} kg)",
            effects.zeta[0], effects.zeta[1], model.damping[0], model.damping[1], m_e[0], m_e[1]
        ));
    }
    if effects.vibration_zeta > 0.0 {
        let w1 = TAU * model.natural_frequencies_hz()[0];
        let j = model.inertias_kg_m2();
        model.vibration_damping = j.map(|j| 2.0 * effects.vibration_zeta * j * w1);
        log.push(format!(
            "vibration_damping: ζ = {} on the lowest mode ({:.1} Hz) → c = {:.4e}, {:.4e} \
             N·m·s/rad on the intermediate's and the planet's Δθ̇ (2ζ·J·ω₁)",
            effects.vibration_zeta,
            w1 / TAU,
            model.vibration_damping[0],
            model.vibration_damping[1]
        ));
    }
    if let Some(drive) = effects.drive {
        let d = DriveModel {
            drive,
            arms: case.arms as usize,
        };
        model.drive = Some(d);
        log.push(format!(
            "drive: a shaft of {} N·m/rad and {} N·m·s/rad from a motor at {:.3} r/min, the \
             carrier ({} kg·mm²) a degree of freedom, the {} arms integrated together; the \
             shaft's frequency ≈ {:.1} Hz",
            drive.stiffness_nm_per_rad,
            drive.damping_nms_per_rad,
            case.omega_rad_s * 60.0 / TAU,
            drive.carrier_inertia_kg_m2 * 1e6,
            d.arms,
            d.frequency_hz(&model, 360)
        ));
    }
    if model.needle.is_some() {
        log.push("needle: the loads scene's needle force on the tip".into());
    }
    if case.gravity_m_s2.norm() > 0.0 {
        log.push(format!(
            "gravity: {:.5} m/s² along [{:.3}, {:.3}]",
            case.gravity_m_s2.norm(),
            case.gravity_m_s2.x / case.gravity_m_s2.norm(),
            case.gravity_m_s2.y / case.gravity_m_s2.norm()
        ));
    }
    Ok(Built {
        model,
        effects_log: log,
    })
}
