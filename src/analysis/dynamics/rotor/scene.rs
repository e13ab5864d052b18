//! The rotor scene (`[scene] model = "rotor"`): the design it names, the loads scene's tables as
//! they are (`[operation]`, `[arm]`, `[gears]`, `[needle]`), the effects of the motion — each
//! built only when named — the solver and the steady-state criterion. Every unknown key is
//! refused; every number is checked before any work ([`RotorScene::validate`]).
//!
//! Files speak mm, degrees, r/min, N/mm; the validated [`RotorCase`] works in SI (m, rad, s, N).

use super::RotorError;
use crate::loads::LoadCase;
use crate::loads::needle::NeedleSpec;
use crate::loads::scene::{ArmSpec, GearsSpec, Operation};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

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
    /// The design file (`design.json`), relative to the scene file.
    pub design: PathBuf,
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

/// Most turns a scene may ask for.
pub const MAX_TURNS: u32 = 10_000;

/// The validated stiffness law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StiffnessLaw {
    /// N/m per mesh.
    Constant([f64; 2]),
    /// ISO 6336-1 scaled by the factor.
    Iso {
        /// Factor on ISO's stiffness.
        scale: f64,
        /// One/two pairs or the mean.
        pairs: PairsMode,
    },
}

/// The validated backlash.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Backlash {
    /// Total normal backlash per mesh, m.
    Normal([f64; 2]),
    /// The design's teeth's.
    Teeth,
}

/// The validated drive.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drive {
    /// N·m/rad.
    pub stiffness_nm_per_rad: f64,
    /// N·m·s/rad.
    pub damping_nms_per_rad: f64,
    /// kg·m².
    pub carrier_inertia_kg_m2: f64,
}

/// The effects of a validated scene (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct Effects {
    /// Mesh stiffness.
    pub stiffness: StiffnessLaw,
    /// Damping ratio per mesh (0: none).
    pub zeta: [f64; 2],
    /// Backlash, if named.
    pub backlash: Option<Backlash>,
    /// Damping ratio of the lowest mode by mass-proportional vibration damping (0: none).
    pub vibration_zeta: f64,
    /// Drive, if named.
    pub drive: Option<Drive>,
}

impl Effects {
    /// Constant stiffness `k_n_per_m` (N/m per mesh), no damping, backlash or drive.
    #[must_use]
    pub fn constant(k_n_per_m: [f64; 2]) -> Self {
        Self {
            stiffness: StiffnessLaw::Constant(k_n_per_m),
            zeta: [0.0; 2],
            backlash: None,
            vibration_zeta: 0.0,
            drive: None,
        }
    }

    /// ISO stiffness × `scale` with the pair alternation `pairs`.
    #[must_use]
    pub fn iso(scale: f64, pairs: PairsMode) -> Self {
        Self {
            stiffness: StiffnessLaw::Iso { scale, pairs },
            ..Self::constant([0.0; 2])
        }
    }

    /// With the damping ratios `zeta`.
    #[must_use]
    pub fn with_zeta(mut self, zeta: [f64; 2]) -> Self {
        self.zeta = zeta;
        self
    }

    /// With vibration damping of ratio `zeta` on the lowest mode.
    #[must_use]
    pub fn with_vibration_zeta(mut self, zeta: f64) -> Self {
        self.vibration_zeta = zeta;
        self
    }

    /// With backlash.
    #[must_use]
    pub fn with_backlash(mut self, b: Option<Backlash>) -> Self {
        self.backlash = b;
        self
    }
}

/// Integrator settings of a validated scene.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct Settings {
    /// Method.
    pub method: RotorMethod,
    /// DOPRI5 relative tolerance.
    pub rtol: f64,
    /// DOPRI5 absolute tolerance.
    pub atol: f64,
    /// Breakpoints at the tooth-pair switches.
    pub breakpoints: bool,
    /// Contact events.
    pub events: bool,
    /// RK4 steps per turn.
    pub rk4_steps_per_turn: u32,
    /// Poincaré tolerance.
    pub poincare_tol: f64,
    /// Most turns.
    pub max_turns: u32,
}

impl Default for Settings {
    /// DOPRI5, rtol 1e-8, atol 1e-12, breakpoints and events on, Poincaré 1e-6, 40 turns.
    fn default() -> Self {
        let s = RotorSolverSpec::default();
        Self {
            method: s.method,
            rtol: s.rtol,
            atol: s.atol,
            breakpoints: true,
            events: true,
            rk4_steps_per_turn: s.rk4_steps_per_turn,
            poincare_tol: poincare_tol(),
            max_turns: max_turns(),
        }
    }
}

impl Settings {
    /// With tolerances.
    #[must_use]
    pub fn with_tolerances(mut self, rtol: f64, atol: f64) -> Self {
        self.rtol = rtol;
        self.atol = atol;
        self
    }
    /// With the steady-state criterion.
    #[must_use]
    pub fn with_steady(mut self, poincare_tol: f64, max_turns: u32) -> Self {
        self.poincare_tol = poincare_tol;
        self.max_turns = max_turns;
        self
    }
    /// With breakpoints and events on or off.
    #[must_use]
    pub fn with_switches(mut self, breakpoints: bool, events: bool) -> Self {
        self.breakpoints = breakpoints;
        self.events = events;
        self
    }
    /// With fixed-step RK4 of `steps_per_turn` steps.
    #[must_use]
    pub fn with_rk4(mut self, steps_per_turn: u32) -> Self {
        self.method = RotorMethod::Rk4;
        self.rk4_steps_per_turn = steps_per_turn;
        self
    }
}

/// A validated rotor scene.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct RotorCase {
    /// Scene name.
    pub name: String,
    /// The loads' case of the same tables.
    pub loads: LoadCase,
    /// The effects.
    pub effects: Effects,
    /// The integrator.
    pub settings: Settings,
}

impl RotorScene {
    /// Whether scene text names `[scene] model = "rotor"` (TOML or JSON).
    #[must_use]
    pub fn names_rotor(text: &str) -> bool {
        let model = |v: &serde_json::Value| {
            v.get("scene")
                .and_then(|s| s.get("model"))
                .and_then(|m| m.as_str())
                .is_some_and(|m| m == "rotor")
        };
        if let Ok(v) = toml::from_str::<toml::Value>(text) {
            return serde_json::to_value(v).is_ok_and(|v| model(&v));
        }
        serde_json::from_str::<serde_json::Value>(text).is_ok_and(|v| model(&v))
    }

    /// Reads a scene file (TOML or JSON).
    ///
    /// # Errors
    /// [`RotorError::Scene`] naming the file, line and key.
    pub fn from_path(path: &Path) -> Result<Self, RotorError> {
        crate::config::load(path).map_err(|e| RotorError::Scene(e.to_string()))
    }

    /// The design file, resolved against the scene file's folder.
    #[must_use]
    pub fn design_path(&self, scene_file: &Path) -> PathBuf {
        let d = &self.scene.design;
        if d.is_absolute() {
            d.clone()
        } else {
            scene_file.parent().unwrap_or(Path::new("")).join(d)
        }
    }

    /// The loads scene of the same tables.
    #[must_use]
    pub fn loads_scene(&self) -> crate::loads::Scene {
        crate::loads::Scene {
            design: Some(self.scene.design.clone()),
            operation: self.operation.clone(),
            arm: self.arm.clone(),
            gears: Some(self.gears.clone()),
            needle: self.needle.clone(),
            material: None,
            rating: None,
        }
    }

    /// Checks every value (naming `file` and the key) and converts to SI.
    ///
    /// # Errors
    /// [`RotorError::Field`] naming the key, the value and what is expected; the loads tables'
    /// own errors.
    pub fn validate(&self, file: &str) -> Result<RotorCase, RotorError> {
        let loads = self.loads_scene().validate(file)?;
        let field = |key: &str, message: String| RotorError::Field {
            file: file.into(),
            key: key.into(),
            message,
        };
        let positive = |key: &str, v: f64, what: &str| {
            if v.is_finite() && v > 0.0 {
                Ok(v)
            } else {
                Err(field(key, format!("{v} must be {what}")))
            }
        };
        let e = &self.effects;
        let stiffness = match e.mesh_stiffness {
            StiffnessSpec::Constant { c_n_per_mm_mm } => {
                let c = c_n_per_mm_mm.values();
                for v in c {
                    positive(
                        "effects.mesh_stiffness.c_n_per_mm_mm",
                        v,
                        "a stiffness > 0 in N/mm per mm of face width (ISO's c′ of steel ≈ 14000)",
                    )?;
                }
                let b = match self.gears.face_width_mm {
                    crate::loads::scene::FaceWidthSpec::Mm(b) => b,
                    crate::loads::scene::FaceWidthSpec::Word(_) => {
                        return Err(field(
                            "gears.face_width_mm",
                            "\"auto\" is for the sizing: give the face width in mm".into(),
                        ));
                    }
                };
                StiffnessLaw::Constant(c.map(|c| c * b * 1e3))
            }
            StiffnessSpec::Iso { scale, pairs } => StiffnessLaw::Iso {
                scale: positive(
                    "effects.mesh_stiffness.scale",
                    scale.unwrap_or(1.0),
                    "a factor > 0 on ISO's stiffness",
                )?,
                pairs: pairs.unwrap_or_default(),
            },
        };
        let zeta = match e.mesh_damping {
            None => [0.0; 2],
            Some(d) => {
                let z = d.zeta.values();
                if !z.iter().all(|z| z.is_finite() && (0.0..=1.0).contains(z)) {
                    return Err(field(
                        "effects.mesh_damping.zeta",
                        format!("{z:?} must be damping ratios in [0, 1] (0.03–0.10 typical)"),
                    ));
                }
                z
            }
        };
        let vibration_zeta = match e.vibration_damping {
            None => 0.0,
            Some(d) => {
                if !(d.zeta.is_finite() && (0.0..=1.0).contains(&d.zeta)) {
                    return Err(field(
                        "effects.vibration_damping.zeta",
                        format!(
                            "{} must be a damping ratio in [0, 1] (0.02–0.10 typical)",
                            d.zeta
                        ),
                    ));
                }
                d.zeta
            }
        };
        let backlash = match e.backlash {
            None => None,
            Some(BacklashSpec::Word(_)) => Some(Backlash::Teeth),
            Some(BacklashSpec::Mm(v)) => {
                let v = v.values();
                if !v.iter().all(|b| b.is_finite() && (0.0..=10.0).contains(b)) {
                    return Err(field(
                        "effects.backlash",
                        format!(
                            "{v:?} must be a normal backlash in [0, 10] mm on the line of \
                             action, or \"teeth\" (the design's own)"
                        ),
                    ));
                }
                Some(Backlash::Normal(v.map(|b| b * 1e-3)))
            }
        };
        let drive = e
            .drive
            .map(|d| {
                let k = positive(
                    "effects.drive.stiffness_nm_per_rad",
                    d.stiffness_nm_per_rad,
                    "a torsional stiffness > 0 in N·m/rad",
                )?;
                if !(d.damping_nms_per_rad.is_finite() && d.damping_nms_per_rad >= 0.0) {
                    return Err(field(
                        "effects.drive.damping_nms_per_rad",
                        format!(
                            "{} must be a damping ≥ 0 in N·m·s/rad",
                            d.damping_nms_per_rad
                        ),
                    ));
                }
                let j = d.carrier_inertia_kg_mm2.ok_or_else(|| {
                    field(
                        "effects.drive.carrier_inertia_kg_mm2",
                        "a drive makes the carrier a degree of freedom, and it needs its \
                         inertia: add carrier_inertia_kg_mm2 (kg·mm², about O)"
                            .into(),
                    )
                })?;
                let j = positive(
                    "effects.drive.carrier_inertia_kg_mm2",
                    j,
                    "an inertia > 0 in kg·mm²",
                )?;
                Ok(Drive {
                    stiffness_nm_per_rad: k,
                    damping_nms_per_rad: d.damping_nms_per_rad,
                    carrier_inertia_kg_m2: j * 1e-6,
                })
            })
            .transpose()?;
        let s = &self.solver;
        positive("solver.rtol", s.rtol, "a relative tolerance > 0")?;
        positive("solver.atol", s.atol, "an absolute tolerance > 0")?;
        if s.rk4_steps_per_turn < 100 {
            return Err(field(
                "solver.rk4_steps_per_turn",
                format!("{} must be at least 100 steps", s.rk4_steps_per_turn),
            ));
        }
        positive(
            "steady.poincare_tol",
            self.steady.poincare_tol,
            "a relative tolerance > 0",
        )?;
        if !(1..=MAX_TURNS).contains(&self.steady.max_turns) {
            return Err(field(
                "steady.max_turns",
                format!("{} must be in 1..={MAX_TURNS}", self.steady.max_turns),
            ));
        }
        Ok(RotorCase {
            name: self.scene.name.clone(),
            loads,
            effects: Effects {
                stiffness,
                zeta,
                backlash,
                vibration_zeta,
                drive,
            },
            settings: Settings {
                method: s.method,
                rtol: s.rtol,
                atol: s.atol,
                breakpoints: s.breakpoints,
                events: s.events,
                rk4_steps_per_turn: s.rk4_steps_per_turn,
                poincare_tol: self.steady.poincare_tol,
                max_turns: self.steady.max_turns,
            },
        })
    }
}
