//! The loads' rating on the rotor's own dynamics (`rating.K_v = "dynamic"`, docs/loads.md,
//! "Rated on the dynamics"): a loads scene that also names the dynamics' `[effects]` (and, if it
//! likes, `[solver]` and `[steady]`) has its teeth rated on the settled turn's dynamic mesh
//! forces instead of the rigid ones times ISO 6336-1's K_v:
//!
//! ```text
//! σ_H = Z_B,D·Z_ε·√(K_A·K_Hβ·K_Hα) · Z_E·√(F_n,dyn/b·(1/ρ_f1 + 1/ρ_f2)),   K_v = 1
//! σ_F = F_t,dyn/(b·m)·Y_F·Y_S·Y_B · K_A·K_Fβ·K_Fα,                        F_t,dyn = F_n,dyn·cos α
//! ```
//!
//! at every sample of the turn, on the flank the dynamics find in contact (the coast flank at an
//! impact after a torque reversal). The dynamics run at the face width rated (an `"auto"` face
//! width and the module sizing run them once per width and module tried): the inertias and the
//! stiffness follow the face width. The loads' other figures (torques, bearings) stay rigid.
//!
//! The loads know nothing of the dynamics: they take a [`MeshForceSource`], which this module
//! makes ([`forces_of_scene`]).

use super::RotorError;
use super::analyse::run_model;
use super::build::build;
use super::law::ToothData;
use super::spec::{EffectsSpec, RotorMeta, RotorScene, RotorSolverSpec, RotorWord, SteadySpec};
use crate::loads::analysis::train_turn;
use crate::loads::scene::FaceWidthSpec;
use crate::loads::{
    DynamicMeshForces, LoadCase, LoadsError, LoadsReport, MeshForceSource, Rotor, Scene,
};
use crate::progress::Progress;
use serde::de::DeserializeOwned;
use std::path::Path;

/// The dynamics of a loads scene that rates on them: the loads tables and the dynamics' own,
/// checked.
#[derive(Debug, Clone)]
pub struct DynamicRating {
    scene: RotorScene,
    file: String,
}

/// One of the dynamics' tables kept as written in the loads scene, read as its type (`key`
/// names it in errors).
fn table<T: DeserializeOwned + Default>(
    v: Option<&serde_json::Value>,
    key: &str,
    file: &str,
) -> Result<T, LoadsError> {
    v.map_or_else(
        || Ok(T::default()),
        |v| {
            serde_json::from_value(v.clone()).map_err(|e| LoadsError::Field {
                file: file.into(),
                key: key.into(),
                message: format!("{e} (docs/dynamics.md, \"The rotor\", lists the table's keys)"),
            })
        },
    )
}

/// A rotor error as the loads report it: a field stays a field, the rest is the dynamics'.
fn as_loads(e: RotorError) -> LoadsError {
    match e {
        RotorError::Field { file, key, message } => LoadsError::Field { file, key, message },
        RotorError::Loads(l) => l,
        other => LoadsError::Dynamics(other.to_string()),
    }
}

impl DynamicRating {
    /// The dynamics of `scene` (`file` names it) when it rates on them (`rating.K_v =
    /// "dynamic"`), checked at the scene's face width (or 1 mm for `"auto"`: the checks do not
    /// depend on it); `None` for a scene that does not.
    ///
    /// # Errors
    /// [`LoadsError::Field`] naming the dynamics' key and what is expected.
    pub fn of_scene(scene: &Scene, file: &str) -> Result<Option<Self>, LoadsError> {
        let dynamic = scene
            .rating
            .as_ref()
            .and_then(|r| r.k_v)
            .is_some_and(|k| matches!(k, crate::loads::rating::KvSpec::Word(_)));
        if !dynamic {
            return Ok(None);
        }
        let effects_value = scene.effects.as_ref().ok_or_else(|| LoadsError::Field {
            file: file.into(),
            key: "rating.K_v".into(),
            message: "\"dynamic\" needs the dynamics' [effects] in the scene".into(),
        })?;
        let effects: EffectsSpec =
            serde_json::from_value(effects_value.clone()).map_err(|e| LoadsError::Field {
                file: file.into(),
                key: "effects".into(),
                message: format!("{e} (docs/dynamics.md, \"The rotor\", lists the effects)"),
            })?;
        let solver: RotorSolverSpec = table(scene.solver.as_ref(), "solver", file)?;
        let steady: SteadySpec = table(scene.steady.as_ref(), "steady", file)?;
        let gears = scene.gears.clone().ok_or_else(|| LoadsError::Field {
            file: file.into(),
            key: "gears".into(),
            message: "the dynamics need the gear bodies: add [gears] with face_width_mm".into(),
        })?;
        let rating = Self {
            scene: RotorScene {
                scene: RotorMeta {
                    name: format!("{file} (rating on the dynamics)"),
                    model: RotorWord::Rotor,
                    design: None,
                },
                operation: scene.operation.clone(),
                arm: scene.arm.clone(),
                gears,
                needle: scene.needle.clone(),
                effects,
                solver,
                steady,
            },
            file: file.into(),
        };
        rating.at_face_width(1.0).validate(file).map_err(as_loads)?;
        Ok(Some(rating))
    }

    /// The rotor scene at face width `b_mm` (mm).
    fn at_face_width(&self, b_mm: f64) -> RotorScene {
        let mut s = self.scene.clone();
        s.gears.face_width_mm = FaceWidthSpec::Mm(b_mm);
        s
    }

    /// The settled turn's dynamic mesh forces of `rotor` at face width `face_width_mm` (mm),
    /// on the samples of `case` (the loads' case of the same scene), and the rating's note.
    ///
    /// # Errors
    /// [`LoadsError::Field`]: an effect the rotor cannot give (ISO stiffness or `"teeth"`
    /// backlash without teeth); [`LoadsError::Dynamics`]: the integrator's failure.
    pub fn forces(
        &self,
        rotor: &Rotor<'_>,
        case: &LoadCase,
        face_width_mm: f64,
    ) -> Result<DynamicMeshForces, LoadsError> {
        let file = &self.file;
        let rc = self
            .at_face_width(face_width_mm)
            .validate(file)
            .map_err(as_loads)?;
        let teeth = rotor.teeth().map(|t| {
            ToothData::of(
                &t.report.options,
                t.report.module_mm,
                t.report.z,
                t.report.phase_mm,
            )
        });
        let built = build(rotor, &rc.loads, &rc.effects, teeth, file).map_err(as_loads)?;
        let model = &built.model;
        let run = run_model(
            model,
            &rc.loads,
            &rc.settings,
            teeth,
            None,
            &Progress::none(),
        )
        .map_err(as_loads)?;
        let rigid = train_turn(&model.rebuilt, &rc.loads, &model.bodies, model.alpha)?;
        if rigid.forces.len() != case.samples {
            return Err(LoadsError::Dynamics(format!(
                "the dynamics sample the turn {} times, the loads {}",
                rigid.forces.len(),
                case.samples
            )));
        }
        let s = &run.report.summary;
        let st = &run.report.steady;
        let note = format!(
            "rated on the rotor dynamics' mesh forces (K_v = 1; {}): dynamic factors {:.2} \
             (sun–intermediate), {:.2} (intermediate–planet), {} impacts a turn, {}",
            built
                .effects_log
                .iter()
                .map(|l| l.split(':').next().unwrap_or(l))
                .collect::<Vec<_>>()
                .join(", "),
            s.meshes.sun_intermediate.dynamic_factor,
            s.meshes.intermediate_planet.dynamic_factor,
            s.impacts_per_turn,
            if st.settled {
                format!("settled in {} turns", st.turns)
            } else {
                format!(
                    "NOT settled after {} turns (residual {:.2e} > {:.1e}): the last turn rated",
                    st.turns, st.residual, st.poincare_tol
                )
            }
        );
        Ok(DynamicMeshForces {
            forces: run.mesh_forces(model, &rigid),
            note,
        })
    }
}

/// The dynamic forces of a loads scene that rates on them, as the loads take them
/// ([`crate::loads::run_scene_with`], [`crate::loads::size_module`]); `None` for a scene that
/// does not.
///
/// # Errors
/// As [`DynamicRating::of_scene`].
pub fn forces_of_scene(
    scene: &Scene,
    file: &str,
) -> Result<Option<Box<MeshForceSource<'static>>>, LoadsError> {
    Ok(DynamicRating::of_scene(scene, file)?.map(|d| {
        Box::new(move |r: &Rotor<'_>, c: &LoadCase, b: f64| d.forces(r, c, b))
            as Box<MeshForceSource<'static>>
    }))
}

/// A loads scene file run as `ncgear loads` runs it ([`crate::loads::run_scene`]), its teeth
/// rated on the dynamics when it asks for it.
///
/// # Errors
/// As [`crate::loads::run_scene_with`].
pub fn run_loads_scene(path: &Path) -> Result<LoadsReport, LoadsError> {
    crate::loads::run_scene_with(path, &forces_of_scene)
}
