//! The rotor scene file as written (`[scene] model = "rotor"`): the design it names, the loads
//! scene's tables as they are (`[operation]`, `[arm]`, `[gears]`, `[needle]`), the effects of the
//! motion, the solver and the steady-state criterion, with their documented defaults. Every
//! unknown key is refused; [`super::scene`] checks every number and makes the SI case.
//!
//! Files speak mm, degrees, r/min, N/mm.

use crate::loads::needle::NeedleSpec;
use crate::loads::scene::{ArmSpec, GearsSpec, Operation};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// A rotor scene file.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RotorScene {
    /// `[scene]`.
    pub scene: RotorMeta,
    /// How the carrier turns (the loads scene's `[operation]`).
    pub operation: Operation,
    /// The planting arm on each planet (the loads scene's `[arm]`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub arm: Option<ArmSpec>,
    /// The gear bodies (the loads scene's `[gears]`); required: the face width and the inertias.
    pub gears: GearsSpec,
    /// The needle load (the loads scene's `[needle]`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub needle: Option<NeedleSpec>,
    /// The effects of the motion.
    pub effects: EffectsSpec,
    /// The integrator.
    #[serde(default)]
    pub solver: RotorSolverSpec,
    /// The periodic steady state.
    #[serde(default)]
    pub steady: SteadySpec,
}

/// `[scene]` of a rotor scene.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RotorMeta {
    /// Scene name.
    pub name: String,
    /// `rotor`.
    pub model: RotorWord,
    /// The design file (`design.json`), relative to the scene file; required to run the file
    /// (a train in memory needs none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub design: Option<PathBuf>,
}

/// The word `rotor`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum RotorWord {
    /// The planting rotor.
    Rotor,
}

/// One value for both meshes, or `[sun–intermediate, intermediate–planet]`.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(untagged)]
pub enum PerMesh {
    /// The same for both meshes.
    Both(f64),
    /// Per mesh.
    Each([f64; 2]),
}

impl PerMesh {
    /// `[sun–intermediate, intermediate–planet]`.
    #[must_use]
    pub fn values(self) -> [f64; 2] {
        match self {
            Self::Both(v) => [v, v],
            Self::Each(v) => v,
        }
    }
}

/// `[effects]`: only what is named is built.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct EffectsSpec {
    /// The teeth's elasticity (required).
    pub mesh_stiffness: StiffnessSpec,
    /// Viscous mesh damping; absent: none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mesh_damping: Option<DampingSpec>,
    /// Free play between the flanks; absent: none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub backlash: Option<BacklashSpec>,
    /// Damping of the gears' motion away from the kinematic law (the arm's swing in the
    /// backlash); absent: none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vibration_damping: Option<VibrationDampingSpec>,
    /// A compliant drive shaft (the carrier a degree of freedom); absent: the carrier turns at
    /// exactly the scene's speed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub drive: Option<DriveSpec>,
}

/// `effects.mesh_stiffness`.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum StiffnessSpec {
    /// A constant stiffness per mm of face width, N/mm per mm (`c`; 14 000 ≈ ISO's c′ of steel).
    Constant {
        /// N/mm per mm of face width, > 0.
        c_n_per_mm_mm: PerMesh,
    },
    /// ISO 6336-1 on the local equivalent pair (module [`super::stiffness`]).
    Iso {
        /// Factor on ISO's stiffness (default 1; 100 for the stiff limit), > 0.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        scale: Option<f64>,
        /// `alternating` (default): one and two tooth pairs as the teeth pass; `mean`: c_γα.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pairs: Option<PairsMode>,
    },
}

/// `effects.mesh_stiffness.pairs`.
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum PairsMode {
    /// c′ over single contact, 1.75·c′ over double contact.
    #[default]
    Alternating,
    /// The mean c_γα throughout.
    Mean,
}

/// `effects.mesh_damping`.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DampingSpec {
    /// Damping ratio ζ of each mesh, `c = 2ζ·√(k̄·m_e)`, in [0, 1].
    pub zeta: PerMesh,
}

/// `effects.vibration_damping`: a couple `−c·Δθ̇` from the carrier on each gear, with
/// `c = 2ζ·J·ω₁` (J the gear's inertia about its axis, arm included; ω₁ the linearised train's
/// lowest natural frequency, rad/s): mass-proportional (Rayleigh) damping that gives the
/// lowest mode — the planet and its arm swinging on the meshes — the ratio ζ, and a mode of
/// frequency ω the ratio ζ·ω₁/ω.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct VibrationDampingSpec {
    /// Damping ratio ζ of the lowest mode, in [0, 1].
    pub zeta: f64,
}

/// `effects.backlash`: `"teeth"` or the normal backlash, mm, on the line of action.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(untagged)]
pub enum BacklashSpec {
    /// Total normal backlash on the line of action, mm (each flank `j_n/2` from the middle).
    Mm(PerMesh),
    /// `"teeth"`: the design's own nominal backlash (its `backlash_mm` on the pitch curve, times
    /// cos α on the line of action).
    Word(TeethWord),
}

/// The word `teeth`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum TeethWord {
    /// The design's teeth.
    Teeth,
}

/// `effects.drive`: a torsional shaft from a motor at the scene's constant speed.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DriveSpec {
    /// Shaft torsional stiffness, N·m/rad, > 0.
    pub stiffness_nm_per_rad: f64,
    /// Shaft torsional damping, N·m·s/rad, ≥ 0.
    #[serde(default)]
    pub damping_nms_per_rad: f64,
    /// The carrier's inertia about O, kg·mm², > 0 (required with a drive).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub carrier_inertia_kg_mm2: Option<f64>,
}

/// `[solver]`.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RotorSolverSpec {
    /// `dopri5` (default) or `rk4`.
    #[serde(default)]
    pub method: RotorMethod,
    /// Relative tolerance (default 1e-8).
    #[serde(default = "rtol")]
    pub rtol: f64,
    /// Absolute tolerance, rad and rad/s (default 1e-12).
    #[serde(default = "atol")]
    pub atol: f64,
    /// Split the integration at the tooth-pair switches (default true).
    #[serde(default = "yes")]
    pub breakpoints: bool,
    /// Locate contact loss and re-contact (default true).
    #[serde(default = "yes")]
    pub events: bool,
    /// RK4 steps per turn (default 200 000).
    #[serde(default = "rk4_steps")]
    pub rk4_steps_per_turn: u32,
}

impl Default for RotorSolverSpec {
    fn default() -> Self {
        Self {
            method: RotorMethod::Dopri5,
            rtol: rtol(),
            atol: atol(),
            breakpoints: true,
            events: true,
            rk4_steps_per_turn: rk4_steps(),
        }
    }
}

/// `solver.method`.
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum RotorMethod {
    /// Adaptive DOPRI5 with dense output, breakpoints and events.
    #[default]
    Dopri5,
    /// Fixed-step classical RK4 (aligned to the breakpoints when they are on; no events).
    Rk4,
}

/// `[steady]`.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SteadySpec {
    /// Poincaré tolerance: largest change of the state over a turn, relative to the state's
    /// largest value (deviations and rates separately), default 1e-6.
    #[serde(default = "poincare_tol")]
    pub poincare_tol: f64,
    /// Most turns integrated (default 40, at most 10 000).
    #[serde(default = "max_turns")]
    pub max_turns: u32,
}

impl Default for SteadySpec {
    fn default() -> Self {
        Self {
            poincare_tol: poincare_tol(),
            max_turns: max_turns(),
        }
    }
}

fn rtol() -> f64 {
    1e-8
}
fn atol() -> f64 {
    1e-12
}
fn yes() -> bool {
    true
}
fn rk4_steps() -> u32 {
    200_000
}
fn poincare_tol() -> f64 {
    1e-6
}
fn max_turns() -> u32 {
    40
}
