//! The rotor scene checked (`[scene] model = "rotor"`): every number of the file
//! ([`super::spec`]) checked before any work ([`RotorScene::validate`]), each effect built only
//! when named.
//!
//! The validated [`RotorCase`] works in SI (m, rad, s, N).

use super::RotorError;
use super::spec::{
    BacklashSpec, PairsMode, RotorMethod, RotorScene, RotorSolverSpec, SteadySpec, StiffnessSpec,
};
use crate::loads::LoadCase;
use std::path::{Path, PathBuf};

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

    /// With a compliant drive (the carrier a degree of freedom).
    #[must_use]
    pub fn with_drive(mut self, d: Option<Drive>) -> Self {
        self.drive = d;
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
        let st = SteadySpec::default();
        Self {
            method: s.method,
            rtol: s.rtol,
            atol: s.atol,
            breakpoints: true,
            events: true,
            rk4_steps_per_turn: s.rk4_steps_per_turn,
            poincare_tol: st.poincare_tol,
            max_turns: st.max_turns,
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
    ///
    /// # Errors
    /// [`RotorError::Field`] on `scene.design` when the scene names none.
    pub fn design_path(&self, scene_file: &Path) -> Result<PathBuf, RotorError> {
        let d = self
            .scene
            .design
            .as_ref()
            .ok_or_else(|| RotorError::Field {
                file: scene_file.display().to_string(),
                key: "scene.design".into(),
                message: "the scene names no design: add design = \"…/design.json\" (relative to \
                      the scene file)"
                    .into(),
            })?;
        Ok(if d.is_absolute() {
            d.clone()
        } else {
            scene_file.parent().unwrap_or(Path::new("")).join(d)
        })
    }

    /// The loads scene of the same tables.
    #[must_use]
    pub fn loads_scene(&self) -> crate::loads::Scene {
        crate::loads::Scene {
            design: self.scene.design.clone(),
            operation: self.operation.clone(),
            arm: self.arm.clone(),
            gears: Some(self.gears.clone()),
            needle: self.needle.clone(),
            material: None,
            rating: None,
            effects: None,
            solver: None,
            steady: None,
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
