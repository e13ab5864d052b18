//! `dynamics.json` of a rotor scene: the settled turn on the loads' samples of travel and its
//! summary (docs/dynamics.md, "The rotor"). World frame (the trajectory's), mm, degrees, N, N·m.

use crate::analysis::dynamics::ode::OdeStats;
use crate::math::Point;
use serde::Serialize;

/// The flank of a mesh in contact.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Contact {
    /// The flank the rigid loads use for most of the turn (the mesh's working flank).
    Drive,
    /// The other flank.
    Coast,
    /// No contact (inside the backlash).
    None,
}

/// One mesh over the settled turn.
#[derive(Debug, Clone, Default, Serialize, schemars::JsonSchema)]
pub struct MeshSeries {
    /// Dynamic normal force along the contact flank's line of action, N (≥ 0 when the damping
    /// does not pull).
    pub dynamic_force_n: Vec<f64>,
    /// The rigid (kinetostatic) normal force of `ncgear loads` for the same scene, N.
    pub rigid_force_n: Vec<f64>,
    /// The flank in contact.
    pub contact: Vec<Contact>,
    /// Approach of the drive flank `δ`, µm (negative: towards the coast flank).
    pub deflection_um: Vec<f64>,
}

/// One impact: a re-contact after a contact loss.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Impact {
    /// Travel angle, degrees.
    pub travel_deg: f64,
    /// The flank struck.
    pub flank: Contact,
    /// Approach speed along the line of action at re-contact, m/s.
    pub speed_m_s: f64,
    /// The largest mesh force from the impact over the impact window, N.
    pub peak_force_n: f64,
}

/// One mesh's summary.
#[derive(Debug, Clone, Default, Serialize, schemars::JsonSchema)]
pub struct MeshSummary {
    /// Largest dynamic force, N.
    pub peak_dynamic_n: f64,
    /// Largest rigid force, N.
    pub peak_rigid_n: f64,
    /// Dynamic factor: largest dynamic over largest rigid force.
    pub dynamic_factor: f64,
    /// Largest `|F_dyn − F_rigid|` over the turn, relative to the largest rigid force.
    pub largest_deviation_of_peak: f64,
    /// ISO 6336-1 method C's K_v (the loads' formula) at the sample of the largest rigid force
    /// (absent without teeth).
    #[serde(rename = "iso_K_v", skip_serializing_if = "Option::is_none")]
    pub iso_k_v: Option<f64>,
    /// Contact-loss intervals `[from, to]`, travel degrees (`to < from`: across φ = 0).
    pub contact_loss_deg: Vec<[f64; 2]>,
    /// The impacts of the turn.
    pub impacts: Vec<Impact>,
    /// Impacts per turn.
    pub impacts_per_turn: usize,
}

/// The meshes of a rotor report.
#[derive(Debug, Clone, Default, Serialize, schemars::JsonSchema)]
pub struct RotorMeshes<T> {
    /// Sun–intermediate.
    pub sun_intermediate: T,
    /// Intermediate–planet.
    pub intermediate_planet: T,
}

/// The steady state reached.
#[derive(Debug, Clone, Copy, Serialize, schemars::JsonSchema)]
pub struct SteadyReport {
    /// Turns integrated.
    pub turns: u32,
    /// Periodic residual of the last turn (relative).
    pub residual: f64,
    /// The scene's tolerance.
    pub poincare_tol: f64,
    /// Whether the residual fell below it.
    pub settled: bool,
}

/// The summary of the settled turn.
#[derive(Debug, Clone, Default, Serialize, schemars::JsonSchema)]
pub struct RotorSummary {
    /// Each mesh.
    pub meshes: RotorMeshes<MeshSummary>,
    /// Largest distance of the dynamic tip from the static path, mm.
    pub max_tip_deviation_mm: f64,
    /// Its travel angle, degrees.
    pub max_tip_deviation_at_deg: f64,
    /// Linearised train's natural frequencies at the mean stiffness, Hz.
    pub natural_frequencies_hz: [f64; 2],
    /// Largest impact speed of either mesh, m/s (0: none).
    pub max_impact_speed_m_s: f64,
    /// Impacts per turn of both meshes of one train.
    pub impacts_per_turn: usize,
}

/// `dynamics.json` of a rotor scene.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct RotorReport {
    /// Report format version.
    pub schema_version: u32,
    /// Scene name.
    pub scene: String,
    /// `rotor`.
    pub model: String,
    /// The design file, as the scene names it.
    pub design: String,
    /// Carrier speed, r/min.
    pub carrier_rpm: f64,
    /// Trains on the carrier.
    pub arms: u32,
    /// Degrees of freedom (per train).
    pub dofs: Vec<String>,
    /// One line per effect built, with its parameters.
    pub effects: Vec<String>,
    /// The steady state.
    pub steady: SteadyReport,
    /// Integrator counters over all turns.
    pub stats: OdeStats,
    /// Samples of travel, degrees (the loads').
    pub travel_deg: Vec<f64>,
    /// The meshes of train 1.
    pub meshes: RotorMeshes<MeshSeries>,
    /// The intermediate's rotation away from the kinematic law, µrad (CCW frame: positive in
    /// the carrier's sense of travel).
    pub intermediate_deviation_urad: Vec<f64>,
    /// The planet's rotation away from the kinematic law, µrad.
    pub planet_deviation_urad: Vec<f64>,
    /// The needle tip's dynamic path, mm, world frame.
    pub tip_mm: Vec<Point>,
    /// Its distance from the static path, mm.
    pub tip_deviation_mm: Vec<f64>,
    /// The rotor's carrier torque (every arm), dynamic, N·m, positive in the sense of travel.
    pub carrier_torque_nm: Vec<f64>,
    /// The same of the rigid loads, N·m.
    pub rigid_carrier_torque_nm: Vec<f64>,
    /// The compliant drive over the settled turn (only with `[effects] drive`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub drive: Option<DriveReport>,
    /// Summary.
    pub summary: RotorSummary,
}

/// The compliant drive over the settled turn, on the samples of travel (docs/dynamics.md,
/// "The drive").
#[derive(Debug, Clone, Default, Serialize, schemars::JsonSchema)]
pub struct DriveReport {
    /// The shaft's torque `T_s = k_s·ψ + c_s·(Ω − w)`, N·m, positive in the sense of travel.
    pub shaft_torque_nm: Vec<f64>,
    /// The carrier's speed w, r/min.
    pub carrier_speed_rpm: Vec<f64>,
    /// The shaft's twist `ψ = Ω·t − φ` (the motor ahead of the carrier), degrees.
    pub twist_deg: Vec<f64>,
    /// The shaft's torsional frequency with the carrier and the arms' mean inertia on it, Hz.
    pub shaft_frequency_hz: f64,
    /// Largest `|T_s|`, N·m.
    pub peak_shaft_torque_nm: f64,
    /// The carrier's speed fluctuation `(max w − min w)/Ω` (dimensionless).
    pub speed_fluctuation: f64,
}

/// The version of the rotor report's format.
pub const ROTOR_SCHEMA_VERSION: u32 = 1;

/// Distance from `p` to the closed polyline `path` searched within `±w` vertices of `k`, mm.
pub(crate) fn distance_to_path(path: &[Point], k: usize, w: usize, p: Point) -> f64 {
    let n = path.len();
    let mut best = f64::INFINITY;
    for o in 0..=2 * w {
        let i = (k + n + o - w) % n;
        let (a, b) = (path[i], path[(i + 1) % n]);
        let ab = b - a;
        let t = ((p - a).dot(ab) / ab.dot(ab).max(1e-300)).clamp(0.0, 1.0);
        best = best.min(p.distance(a + ab * t));
    }
    best
}
