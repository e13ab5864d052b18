//! The scene file schema (docs/math/companion.md §B.10): the serde types of every table and effect. Units are those
//! of the file (mm, µm, degrees, rpm); effects with several forms are tagged enums keyed by their
//! `kind` / `law` / `direction` string.

use super::settings::{OutputSpec, SolverSpec, yes};
use serde::{Deserialize, Serialize};

/// `[scene]`.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SceneMeta {
    /// Scene name.
    pub name: String,
    /// Model kind: only `spur_pair`.
    pub model: ModelKind,
    /// `auto` (prune DOFs, docs/math/companion.md §B.10) or `full` (keep every lateral DOF, e.g. for eigen-analysis);
    /// default `auto`.
    #[serde(default)]
    pub dofs: DofSet,
}

/// `scene.model`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ModelKind {
    /// One spur pair (planetary sets are not implemented).
    SpurPair,
}

/// `scene.dofs`.
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum DofSet {
    /// Keep only the DOFs the named effects need (16 / 6 / 4 / 2 / 1).
    #[default]
    Auto,
    /// Keep every lateral DOF the shafts and bearings allow.
    Full,
}

/// `[gears]`: standard involute spur pair; masses default to solid steel discs.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GearsSpec {
    /// Pinion teeth.
    pub z1: u32,
    /// Gear teeth.
    pub z2: u32,
    /// Module, mm.
    pub module_mm: f64,
    /// Pressure angle, degrees.
    pub pressure_angle_deg: f64,
    /// Face width, mm.
    pub face_width_mm: f64,
    /// Addendum coefficient h_a* (default 1).
    #[serde(default = "one")]
    pub addendum_coeff: f64,
    /// Density for the disc masses, kg/m³ (default 7850).
    #[serde(default = "steel")]
    pub density_kg_m3: f64,
    /// Override of the gear masses [m1, m2], kg.
    pub mass_kg: Option<[f64; 2]>,
    /// Override of the gear inertias [J1, J2], kg·m².
    pub inertia_kgm2: Option<[f64; 2]>,
}

fn one() -> f64 {
    1.0
}
fn steel() -> f64 {
    7850.0
}

/// `[operating]`.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct Operating {
    /// Pinion speed, rpm.
    pub n1_rpm: f64,
    /// Input torque on the pinion side, N·m.
    pub input_torque_Nm: f64,
}

/// `effects.mesh_stiffness` (required), keyed by `kind`. Every kind has the mesh damping ratio
/// ζ_m: c_m = 2ζ_m sqrt(k_mean m_e).
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum MeshSpec {
    /// `constant`: time-invariant stiffness `k`.
    Constant {
        /// Stiffness, N/m.
        k: f64,
        /// Mesh damping ratio ζ_m.
        zeta: f64,
    },
    /// `fourier`: the rectangular wave's Fourier series with `n` harmonics.
    Fourier {
        /// Double-contact stiffness, N/m.
        kmax: f64,
        /// Single-contact stiffness, N/m.
        kmin: f64,
        /// Harmonics (default 9).
        n: Option<u32>,
        /// Mesh damping ratio ζ_m.
        zeta: f64,
    },
    /// `rectangular`: kmax in double contact, kmin in single contact.
    Rectangular {
        /// Double-contact stiffness, N/m.
        kmax: f64,
        /// Single-contact stiffness, N/m.
        kmin: f64,
        /// Mesh damping ratio ζ_m.
        zeta: f64,
    },
    /// `pairs`: the rectangular wave split over the two tooth pairs.
    Pairs {
        /// Double-contact stiffness, N/m.
        kmax: f64,
        /// Single-contact stiffness, N/m.
        kmin: f64,
        /// Mesh damping ratio ζ_m.
        zeta: f64,
    },
}

impl MeshSpec {
    /// The `kind` string of the file.
    #[must_use]
    pub fn kind(&self) -> &'static str {
        match self {
            Self::Constant { .. } => "constant",
            Self::Fourier { .. } => "fourier",
            Self::Rectangular { .. } => "rectangular",
            Self::Pairs { .. } => "pairs",
        }
    }

    /// Mesh damping ratio ζ_m.
    #[must_use]
    pub fn zeta(&self) -> f64 {
        match *self {
            Self::Constant { zeta, .. }
            | Self::Fourier { zeta, .. }
            | Self::Rectangular { zeta, .. }
            | Self::Pairs { zeta, .. } => zeta,
        }
    }
}

/// `effects.static_te`.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SteSpec {
    /// Mean e0, µm.
    #[serde(default)]
    pub e0_um: f64,
    /// Amplitude er, µm.
    pub er_um: f64,
    /// Phase, degrees.
    #[serde(default)]
    pub phase_deg: f64,
}

/// `effects.backlash`.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BacklashSpec {
    /// HALF of the backlash b, µm.
    pub half_gap_um: f64,
    /// Mesh damping also inside the gap (default true, Kahraman–Singh).
    #[serde(default = "yes")]
    pub damping_in_gap: bool,
    /// Clamp pulling forces (default false).
    #[serde(default)]
    pub no_tension: bool,
}

/// `effects.tip_relief`.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ReliefSpec {
    /// Δmax, µm.
    pub delta_max_um: f64,
    /// Relief length along the line of action, mm.
    pub length_mm: f64,
    /// Relief shape (default `linear`).
    #[serde(default)]
    pub kind: ReliefKind,
}

/// `effects.tip_relief.kind`.
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum ReliefKind {
    /// Linear relief from Δmax at the tip to 0 at the relief length.
    #[default]
    Linear,
}

/// `effects.friction`, keyed by `direction` (the law of the friction force's sign).
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(tag = "direction", rename_all = "snake_case", deny_unknown_fields)]
pub enum FrictionSpec {
    /// `pitch_switch`: the sign flips at the pitch point.
    PitchSwitch {
        /// Coefficient μ.
        mu: f64,
    },
    /// `tanh`: a smooth sign `tanh(v_s / v0)` of the sliding velocity.
    Tanh {
        /// Coefficient μ.
        mu: f64,
        /// Velocity scale, m/s.
        v0: f64,
    },
}

impl FrictionSpec {
    /// Coefficient μ.
    #[must_use]
    pub fn mu(&self) -> f64 {
        match *self {
            Self::PitchSwitch { mu } | Self::Tanh { mu, .. } => mu,
        }
    }
}

/// One gear's eccentricity.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct EccSpec {
    /// Mass-centre offset ρ, µm.
    pub rho_um: f64,
    /// Phase, degrees.
    #[serde(default)]
    pub phase_deg: f64,
    /// Model of the offset (default `unbalance`).
    #[serde(default)]
    pub kind: EccKind,
}

/// `effects.eccentricity.*.kind`.
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum EccKind {
    /// Rotating force `m ρ ω²` (the exact state-dependent mass matrix is not implemented).
    #[default]
    Unbalance,
}

/// `effects.eccentricity`.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct EccentricitySpec {
    /// Pinion.
    pub pinion: Option<EccSpec>,
    /// Gear.
    pub gear: Option<EccSpec>,
}

/// `effects.gravity`.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GravitySpec {
    /// Gravity in the model frame (x ⊥, y ∥ line of action), m/s².
    pub g: [f64; 2],
}

/// `effects.shafts`: torsion, bending, motor/load inertias and bearing masses.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ShaftSpec {
    /// Torsional stiffness [kt1, kt2], N·m/rad.
    pub kt: [f64; 2],
    /// Torsional damping [ct1, ct2], N·m·s/rad (default 0).
    #[serde(default)]
    pub ct: [f64; 2],
    /// Bending stiffness at the gear [ks1, ks2], N/m; absent = shafts rigid in bending (then
    /// only torsion is modelled and the bearings must be rigid).
    pub ks: Option<[f64; 2]>,
    /// Bending damping [cs1, cs2], N·s/m (default 0).
    #[serde(default)]
    pub cs: [f64; 2],
    /// Position coefficients [η1, η2, η3, η4].
    pub eta: [f64; 4],
    /// Motor and load inertias [Jp, Jq], kg·m².
    pub j_kgm2: [f64; 2],
    /// Bearing masses [mb1..mb4], kg (used when the bearings are not rigid).
    pub mb_kg: [f64; 4],
}

/// `effects.bearings`, keyed by `law`.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(tag = "law", rename_all = "snake_case", deny_unknown_fields)]
#[allow(non_snake_case)]
pub enum BearingSpec {
    /// `rigid`: no bearing DOFs.
    Rigid {
        /// Damping, N·s/m (default 0; unused).
        #[serde(default)]
        cb: f64,
    },
    /// `linear`: a spring–damper per axis.
    Linear {
        /// Stiffness, N/m.
        kb: f64,
        /// Damping, N·s/m (default 0).
        #[serde(default)]
        cb: f64,
    },
    /// `hertz`: rolling elements with clearance (docs/math/companion.md §B.5).
    Hertz {
        /// Hertz contact constant, N/m^p.
        Kc: f64,
        /// Rolling elements.
        Nb: u32,
        /// Radial clearance γ0, µm.
        clearance_um: f64,
        /// Load–deflection exponent (1.5 ball, 10/9 roller).
        exponent: f64,
        /// Inner-race radius r′, mm.
        r_in_mm: f64,
        /// Outer-race radius R′, mm.
        R_out_mm: f64,
        /// Damping, N·s/m (default 0).
        #[serde(default)]
        cb: f64,
    },
}

impl BearingSpec {
    /// Damping, N·s/m.
    #[must_use]
    pub fn cb(&self) -> f64 {
        match *self {
            Self::Rigid { cb } | Self::Linear { cb, .. } | Self::Hertz { cb, .. } => cb,
        }
    }
}

/// `[effects]`: a key that is absent = that effect is OFF.
#[derive(Debug, Clone, Default, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Effects {
    /// Mesh stiffness (required).
    pub mesh_stiffness: Option<MeshSpec>,
    /// Static transmission error.
    pub static_te: Option<SteSpec>,
    /// Backlash.
    pub backlash: Option<BacklashSpec>,
    /// Tip relief.
    pub tip_relief: Option<ReliefSpec>,
    /// Sliding friction.
    pub friction: Option<FrictionSpec>,
    /// Eccentricity.
    pub eccentricity: Option<EccentricitySpec>,
    /// Gravity.
    pub gravity: Option<GravitySpec>,
    /// Shafts.
    pub shafts: Option<ShaftSpec>,
    /// Bearings.
    pub bearings: Option<BearingSpec>,
}

/// A whole scene file.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// `[scene]`.
    pub scene: SceneMeta,
    /// `[gears]`.
    pub gears: GearsSpec,
    /// `[operating]`.
    pub operating: Operating,
    /// `[effects]`.
    pub effects: Effects,
    /// `[solver]`.
    #[serde(default)]
    pub solver: SolverSpec,
    /// `[output]`.
    #[serde(default)]
    pub output: OutputSpec,
}
