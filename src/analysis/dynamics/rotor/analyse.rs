//! The settled turn made into the [`RotorReport`]: dynamic beside rigid forces on the loads'
//! samples, the contact flanks, the deviations, the tip's dynamic path and its distance from the
//! static path, the carrier torque, and the summary (dynamic factor, ISO K_v, contact losses,
//! impacts, natural frequencies).

use super::RotorError;
use super::law::ToothData;
use super::model::RotorModel;
use super::report::{
    Contact, DriveReport, Impact, MeshSeries, MeshSummary, ROTOR_SCHEMA_VERSION, RotorMeshes,
    RotorReport, RotorSummary, SteadyReport, distance_to_path,
};
use super::scene::Settings;
use super::steady::{Steady, Transition, settle};
use crate::loads::LoadCase;
use crate::loads::analysis::{over_arms, train_turn};
use crate::loads::kinetostatics::{MeshForce, TrainTurn};
use crate::loads::rating::equivalent::EquivalentPair;
use crate::loads::rating::factors::{FactorMode, Factors};
use crate::loads::rating::pitch_line_speeds_m_s;
use crate::math::Point;
use crate::progress::Progress;
use std::f64::consts::TAU;

/// A rotor run: the report and what a warm start needs.
#[derive(Debug, Clone)]
pub struct RotorRun {
    /// The report.
    pub report: RotorReport,
    /// The state at the end of the last turn, `[Δθ2, Δθ3, Δθ̇2, Δθ̇3]` (rad, rad/s).
    pub end_state: Vec<f64>,
    /// The state at the start of the settled turn.
    pub start_state: Vec<f64>,
    /// The start time of the settled turn, s.
    pub start_time_s: f64,
    /// The settled turn's states at the loads' samples, `[Δθ2, Δθ3, Δθ̇2, Δθ̇3]` (rad, rad/s) of
    /// train 1; with a drive, every arm's and then the shaft's twist (rad) and the carrier's
    /// speed (rad/s).
    pub sample_states: Vec<Vec<f64>>,
}

impl RotorRun {
    /// The dynamic mesh forces of the settled turn at the loads' samples, as the loads' rating
    /// takes them (train 1, SI, the CCW frame of the rebuilt train): each mesh's force on its
    /// driven gear along the flank in contact (zero out of contact), its flank, and the
    /// effective pressure angle of the rigid loads at the same sample (`rigid`).
    #[must_use]
    pub fn mesh_forces(&self, model: &RotorModel, rigid: &TrainTurn) -> Vec<[MeshForce; 2]> {
        let tp = model.period_s();
        let n = self.sample_states.len();
        self.sample_states
            .iter()
            .zip(&rigid.forces)
            .enumerate()
            .map(|(k, (y, r))| {
                let i = model.instant(self.start_time_s + tp * k as f64 / n as f64, y);
                let rigid = [r.sun_mesh, r.planet_mesh];
                [0, 1].map(|j| MeshForce {
                    force_n: i.mesh[j].force,
                    normal_force_n: i.mesh[j].force_n,
                    flank: i.mesh[j].flank,
                    effective_pressure_angle_rad: rigid[j].effective_pressure_angle_rad,
                })
            })
            .collect()
    }
}

/// Runs `model` (built on `case`) to its steady state with `settings`, from `warm` (a state at
/// φ = 0, e.g. the previous speed's) or the quasi-static state; `teeth` for the ISO K_v.
///
/// # Errors
/// [`RotorError`]: the integrator's, a diverging response, a mesh that locks.
pub fn run_model(
    model: &RotorModel,
    case: &LoadCase,
    settings: &Settings,
    teeth: Option<ToothData>,
    warm: Option<&[f64]>,
    progress: &Progress,
) -> Result<RotorRun, RotorError> {
    let rigid = train_turn(&model.rebuilt, case, &model.bodies, model.alpha)?;
    let y0 = warm.map_or_else(|| initial_state(model, &rigid), <[f64]>::to_vec);
    let freqs = model.natural_frequencies_hz();
    let window_s = 2.0 / freqs[0].max(1e-9);
    let steady = settle(model, &y0, case.samples, settings, window_s, progress)?;
    let report = analyse(model, case, &rigid, &steady, settings, teeth, freqs);
    Ok(RotorRun {
        start_state: steady.turn.states[0].to_vec(),
        start_time_s: steady.turn.t0,
        end_state: steady.end_state.clone(),
        sample_states: steady.turn.states.clone(),
        report,
    })
}

/// The quasi-static start at φ = 0 from the rigid loads `rigid`: train 1's, or with a drive
/// every arm's at its own travel, the shaft twisted by the rigid carrier torque, the carrier at Ω.
fn initial_state(model: &RotorModel, rigid: &TrainTurn) -> Vec<f64> {
    let at = |sample: usize, phi: f64| {
        let f = &rigid.forces[sample];
        model.quasi_static(
            phi,
            [f.sun_mesh.normal_force_n, f.planet_mesh.normal_force_n],
            [f.sun_mesh.flank, f.planet_mesh.flank],
        )
    };
    let Some(d) = model.drive else {
        return at(0, 0.0);
    };
    let n = rigid.forces.len();
    let mut y = Vec::with_capacity(d.dim());
    let mut torque = 0.0;
    for k in 0..d.arms {
        let sample = k * n / d.arms;
        y.extend(at(sample, d.arm_phi(0.0, k)));
        torque += rigid.forces[sample].carrier_torque_nm;
    }
    y.push(torque / d.drive.stiffness_nm_per_rad);
    y.push(model.omega);
    y
}

/// The degrees of freedom integrated.
fn dofs(model: &RotorModel) -> Vec<String> {
    let mut d = vec!["intermediate Δθ2".to_string(), "planet Δθ3".to_string()];
    if model.drive.is_some() {
        d.push("carrier φ (the shaft's twist ψ, the carrier's speed)".into());
    }
    d
}

/// The drive's part of the report ([`DriveReport`]), on the turn's samples.
fn drive_report(model: &RotorModel, turn: &super::steady::Turn) -> Option<DriveReport> {
    let d = model.drive?;
    let i = d.twist_index();
    let dt = model.period_s() / turn.states.len() as f64;
    let shaft_torque_nm: Vec<f64> = turn
        .states
        .iter()
        .enumerate()
        .map(|(k, y)| d.carrier(model, turn.t0 + dt * k as f64, y).shaft_torque_nm)
        .collect();
    let w: Vec<f64> = turn.states.iter().map(|y| y[i + 1]).collect();
    let (lo, hi) = w
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    Some(DriveReport {
        peak_shaft_torque_nm: shaft_torque_nm.iter().fold(0.0, |a, t| a.max(t.abs())),
        shaft_torque_nm,
        carrier_speed_rpm: w.iter().map(|w| w * 60.0 / TAU).collect(),
        twist_deg: turn.states.iter().map(|y| y[i].to_degrees()).collect(),
        shaft_frequency_hz: d.frequency_hz(model, 360),
        speed_fluctuation: (hi - lo) / model.omega,
    })
}

/// The working flank of a mesh: the one the rigid loads use on most samples.
fn working_flank(flanks: &[i8]) -> i8 {
    let pos = flanks.iter().filter(|&&f| f > 0).count();
    if 2 * pos >= flanks.len() { 1 } else { -1 }
}

fn contact_of(flank: i8, drive: i8) -> Contact {
    match flank {
        0 => Contact::None,
        f if f == drive => Contact::Drive,
        _ => Contact::Coast,
    }
}

/// The settled turn's report (module docs).
#[must_use]
pub(crate) fn analyse(
    model: &RotorModel,
    case: &LoadCase,
    rigid: &TrainTurn,
    steady: &Steady,
    settings: &Settings,
    teeth: Option<ToothData>,
    natural_frequencies_hz: [f64; 2],
) -> RotorReport {
    let n = case.samples;
    let tp = model.period_s();
    let turn = &steady.turn;
    let sign = model.rebuilt.sign();
    let o = model.rebuilt.assembly().center_mm;
    let world = |p: Point| o + Point::new(p.x, sign * p.y);
    let travel_deg: Vec<f64> = (0..n).map(|k| 360.0 * k as f64 / n as f64).collect();
    let instants: Vec<_> = turn
        .states
        .iter()
        .enumerate()
        .map(|(k, y)| model.instant(turn.t0 + tp * k as f64 / n as f64, y))
        .collect();
    let rigid_of = |j: usize| -> Vec<f64> {
        rigid
            .forces
            .iter()
            .map(|f| {
                if j == 0 {
                    f.sun_mesh.normal_force_n
                } else {
                    f.planet_mesh.normal_force_n
                }
            })
            .collect()
    };
    let drive = [0, 1].map(|j| {
        let fl: Vec<i8> = rigid
            .forces
            .iter()
            .map(|f| {
                if j == 0 {
                    f.sun_mesh.flank
                } else {
                    f.planet_mesh.flank
                }
            })
            .collect();
        working_flank(&fl)
    });
    let series = |j: usize| MeshSeries {
        dynamic_force_n: instants.iter().map(|i| i.mesh[j].force_n).collect(),
        rigid_force_n: rigid_of(j),
        contact: instants
            .iter()
            .map(|i| contact_of(i.mesh[j].flank, drive[j]))
            .collect(),
        deflection_um: instants
            .iter()
            .map(|i| f64::from(drive[j]) * i.mesh[j].approach_m * 1e6)
            .collect(),
    };
    let meshes = RotorMeshes {
        sun_intermediate: series(0),
        intermediate_planet: series(1),
    };
    let static_tip: Vec<Point> = rigid.motion.iter().map(|m| world(m.tip_mm)).collect();
    let tip_mm: Vec<Point> = instants.iter().map(|i| world(i.tip_mm)).collect();
    let w = (n / 8).max(2);
    let tip_deviation_mm: Vec<f64> = tip_mm
        .iter()
        .enumerate()
        .map(|(k, &p)| distance_to_path(&static_tip, k, w, p))
        .collect();
    let arms = case.arms as usize;
    let torque: Vec<f64> = instants.iter().map(|i| i.carrier_torque_nm).collect();
    let rigid_torque: Vec<f64> = rigid.forces.iter().map(|f| f.carrier_torque_nm).collect();
    let travel_of = |t: f64| ((t - turn.t0) / tp * 360.0).rem_euclid(360.0);
    let summary_of = |j: usize, s: &MeshSeries| {
        let peak = |v: &[f64]| v.iter().fold(0.0_f64, |a, &x| a.max(x));
        let (pd, pr) = (peak(&s.dynamic_force_n), peak(&s.rigid_force_n));
        let dev = s
            .dynamic_force_n
            .iter()
            .zip(&s.rigid_force_n)
            .fold(0.0_f64, |a, (d, r)| a.max((d - r).abs()));
        let trs: Vec<&Transition> = turn.transitions.iter().filter(|t| t.mesh == j).collect();
        let impacts: Vec<Impact> = trs
            .iter()
            .filter(|t| t.from == 0 && t.to != 0)
            .map(|t| Impact {
                travel_deg: travel_of(t.t),
                flank: contact_of(t.to, drive[j]),
                speed_m_s: t.speed_m_s.abs(),
                peak_force_n: t.peak_n,
            })
            .collect();
        let mut losses = Vec::new();
        let mut open: Option<f64> = (instants[0].mesh[j].flank == 0).then_some(0.0);
        for t in &trs {
            if t.to == 0 {
                open = Some(travel_of(t.t));
            } else if let Some(a) = open.take() {
                losses.push([a, travel_of(t.t)]);
            }
        }
        if let Some(a) = open {
            losses.push([a, 360.0]);
        }
        let kmax = s
            .rigid_force_n
            .iter()
            .enumerate()
            .fold((0, 0.0), |b, (k, &f)| if f > b.1 { (k, f) } else { b })
            .0;
        let iso_k_v = teeth.map(|t| {
            let m = &rigid.motion[kmax];
            let [sun, mid, planet] = model.rebuilt.ccw_curves();
            let (pitch, curves) = if j == 0 {
                (&m.sun_mesh, [sun, mid])
            } else {
                (&m.planet_mesh, [mid, planet])
            };
            let pair = EquivalentPair {
                rho_mm: [
                    curves[0]
                        .geometry(pitch.driver_angle_rad)
                        .radius_of_curvature_mm(),
                    curves[1]
                        .geometry(pitch.driven_angle_rad)
                        .radius_of_curvature_mm(),
                ],
                alpha_rad: t.alpha_rad,
                module_mm: t.module_mm,
                addendum_mm: t.addendum_coeff * t.module_mm,
            };
            let b = case.bodies.map_or(1.0, |b| match b.face_width {
                crate::loads::scene::FaceWidth::Mm(b) => b,
                crate::loads::scene::FaceWidth::Auto => 1.0,
            });
            let f = Factors::new(FactorMode::Iso);
            pair.k_v(
                &f,
                pr * t.alpha_rad.cos(),
                b,
                pitch_line_speeds_m_s(m, case.omega_rad_s)[j],
            )
        });
        MeshSummary {
            peak_dynamic_n: pd,
            peak_rigid_n: pr,
            dynamic_factor: pd / pr.max(1e-300),
            largest_deviation_of_peak: dev / pr.max(1e-300),
            iso_k_v,
            contact_loss_deg: losses,
            impacts_per_turn: impacts.len(),
            impacts,
        }
    };
    let sm = RotorMeshes {
        sun_intermediate: summary_of(0, &meshes.sun_intermediate),
        intermediate_planet: summary_of(1, &meshes.intermediate_planet),
    };
    let (kt, tmax) = tip_deviation_mm
        .iter()
        .enumerate()
        .fold((0, 0.0), |b, (k, &d)| if d > b.1 { (k, d) } else { b });
    let all_impacts = sm
        .sun_intermediate
        .impacts
        .iter()
        .chain(&sm.intermediate_planet.impacts);
    let max_impact_speed_m_s = all_impacts.clone().fold(0.0_f64, |a, i| a.max(i.speed_m_s));
    let impacts_per_turn = all_impacts.count();
    RotorReport {
        schema_version: ROTOR_SCHEMA_VERSION,
        scene: String::new(),
        model: "rotor".into(),
        design: String::new(),
        carrier_rpm: case.omega_rad_s * 60.0 / TAU,
        arms: case.arms,
        dofs: dofs(model),
        effects: Vec::new(),
        steady: SteadyReport {
            turns: steady.turns,
            residual: steady.residual,
            poincare_tol: settings.poincare_tol,
            settled: steady.settled,
        },
        stats: steady.stats,
        travel_deg,
        intermediate_deviation_urad: turn.states.iter().map(|y| y[0] * 1e6).collect(),
        planet_deviation_urad: turn.states.iter().map(|y| y[1] * 1e6).collect(),
        meshes,
        tip_mm,
        tip_deviation_mm,
        carrier_torque_nm: over_arms(&torque, arms),
        rigid_carrier_torque_nm: over_arms(&rigid_torque, arms),
        drive: drive_report(model, turn),
        summary: RotorSummary {
            meshes: sm,
            max_tip_deviation_mm: tmax,
            max_tip_deviation_at_deg: 360.0 * kt as f64 / n as f64,
            natural_frequencies_hz,
            max_impact_speed_m_s,
            impacts_per_turn,
        },
    }
}
