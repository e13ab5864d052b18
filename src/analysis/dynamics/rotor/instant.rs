//! What the rotor's model gives at one instant of one arm: the meshes' states, the gears'
//! accelerations, the tip, the carrier torque and the powers (SI, CCW frame).

use super::mesh::MeshState;
use crate::math::Point;

/// Everything at one instant (SI, CCW frame).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Instant {
    /// `[sun–intermediate, intermediate–planet]`.
    pub mesh: [MeshState; 2],
    /// `[Δθ̈2, Δθ̈3]`, rad/s².
    pub acc: [f64; 2],
    /// Needle tip, dynamic, mm (CCW frame, about O).
    pub tip_mm: Point,
    /// The train's share of the carrier torque, N·m.
    pub carrier_torque_nm: f64,
    /// Power of the needle force on the tip, W.
    pub needle_w: f64,
    /// Kinetic + gravity + mesh energy, J.
    pub energy_j: f64,
    /// Power the vibration dampers take, `Σ c·Δθ̇·(θ̇ − Ω)`, W (their couples' work on the
    /// gears' rotation relative to the carrier).
    pub vibration_damping_w: f64,
}
