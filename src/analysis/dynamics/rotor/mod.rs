//! The planting rotor in motion (docs/dynamics.md, "The rotor"): the designed non-circular
//! train's own dynamics — elastic teeth, tooth-pair alternation, damping, backlash with contact
//! loss and impacts — run from a scene (`[scene] model = "rotor"`) on the loads' tables, on the
//! same DOPRI5 integrator (breakpoints at the tooth-pair switches, state events at the
//! backlash) as the spur model.
//!
//! A newcomer's map: [`scene`] reads and checks the file; [`build()`] makes the [`RotorModel`]
//! (one effect per named entry); [`model`] holds the equations of motion, [`mesh`] the force law
//! of one mesh, [`law`] and [`stiffness`] the stiffness (constant or ISO 6336-1); [`steady`]
//! integrates turns until periodic; [`mod@analyse`] turns the settled turn into the [`RotorReport`];
//! [`energy`] audits the settled turn's energy; [`sweep`] runs a carrier-speed sweep; [`rating`]
//! gives the loads' rating the dynamic forces (`rating.K_v = "dynamic"`).
//!
//! Units: scene files speak mm, degrees, r/min; the library works in SI (m, rad, s, N).

pub mod analyse;
pub mod build;
mod drive;
pub mod energy;
mod instant;
pub mod law;
mod lever_rate;
pub mod mesh;
pub mod model;
pub mod rating;
pub mod report;
pub mod scene;
pub mod spec;
pub mod steady;
pub mod stiffness;
pub mod sweep;

pub use analyse::{RotorRun, run_model};
pub use build::{Built, build};
pub use law::ToothData;
pub use model::RotorModel;
pub use report::RotorReport;
pub use scene::{Drive, Effects, RotorCase, Settings};
pub use spec::RotorScene;
pub use sweep::{SweepRow, sweep_rpm};

use crate::loads::{LoadsError, RotorSource};
use crate::progress::Progress;
use std::path::Path;

/// Why a rotor scene cannot run.
#[derive(Debug, Clone, thiserror::Error)]
#[non_exhaustive]
pub enum RotorError {
    /// The scene file cannot be read or parsed (names file, line, key).
    #[error("{0}")]
    Scene(String),
    /// A value outside its range.
    #[error("{file}: `{key}`: {message}")]
    Field {
        /// The scene file.
        file: String,
        /// The key.
        key: String,
        /// What is wrong and what is expected.
        message: String,
    },
    /// The loads tables or the design.
    #[error(transparent)]
    Loads(#[from] LoadsError),
    /// The integrator.
    #[error(transparent)]
    Ode(#[from] crate::analysis::dynamics::ode::OdeError),
    /// The response diverged.
    #[error("the response diverged (non-finite state) at t = {0} s")]
    Diverged(f64),
}

impl RotorError {
    /// Whether the error is the input's (exit 2).
    #[must_use]
    pub fn is_input(&self) -> bool {
        matches!(
            self,
            Self::Scene(_)
                | Self::Field { .. }
                | Self::Loads(
                    LoadsError::Scene(_)
                        | LoadsError::Field { .. }
                        | LoadsError::Design(_)
                        | LoadsError::NoTeeth
                )
        )
    }
}

/// The teeth of a design source, as the dynamics reads them (none for a pitch-only design):
/// the made teeth's own count and module when the source holds them (a train in memory), else
/// the design file's `teeth` block (its exact tooth count and its teeth's `phase_mm`).
#[must_use]
pub fn tooth_data(source: &RotorSource) -> Option<ToothData> {
    if let Some(t) = &source.teeth {
        return Some(ToothData::of(
            &t.report.options,
            t.report.module_mm,
            t.report.z,
            t.report.phase_mm,
        ));
    }
    let o = source.teeth_options.as_ref()?;
    let z = match o.policy {
        crate::design::train::TrainPolicy::ScaleCenterDistance(
            crate::teeth::ToothPolicy::Exact(z),
        ) => z,
        _ => return None,
    };
    Some(ToothData::of(
        o,
        o.toothing.module_mm,
        z,
        source.teeth_phase_mm.unwrap_or([0.0; 3]),
    ))
}

/// A rotor scene prepared to run: the case, the design and the built model.
#[derive(Debug, Clone)]
pub struct Prepared {
    /// The validated case.
    pub case: RotorCase,
    /// The design file as the scene names it.
    pub design: String,
    /// The design.
    pub source: RotorSource,
    /// The model and the run log's effect lines.
    pub built: Built,
    /// The design's teeth, if any.
    pub teeth: Option<ToothData>,
}

impl Prepared {
    /// Reads, checks and builds the scene at `path`.
    ///
    /// # Errors
    /// [`RotorError`]: the scene's (file, key, range), the design's, an effect the design cannot
    /// give.
    pub fn from_path(path: &Path) -> Result<Self, RotorError> {
        let file = path.display().to_string();
        let scene = RotorScene::from_path(path)?;
        let case = scene.validate(&file)?;
        let source = RotorSource::read(&scene.design_path(path)?, false)?;
        Self::new(&scene, case, source, &file)
    }

    /// The scene `scene` (validated as `case`) on the design `source` (a design file read, or a
    /// train in memory: the scene's `design` key, if any, is then only echoed in the report, empty
    /// without one); `file`
    /// names the scene in errors.
    ///
    /// # Errors
    /// [`RotorError`]: an effect the design cannot give (`"teeth"` backlash or ISO stiffness
    /// without teeth), the loads'.
    pub fn new(
        scene: &RotorScene,
        case: RotorCase,
        source: RotorSource,
        file: &str,
    ) -> Result<Self, RotorError> {
        let teeth = tooth_data(&source);
        let built = build(&source.rotor(), &case.loads, &case.effects, teeth, file)?;
        Ok(Self {
            case,
            design: scene
                .scene
                .design
                .as_ref()
                .map_or_else(String::new, |d| d.display().to_string()),
            source,
            built,
            teeth,
        })
    }

    /// Runs the steady state and makes the report; `progress` hears every turn.
    ///
    /// # Errors
    /// [`RotorError`]: the integrator's, a diverging response.
    pub fn run(&self, progress: &Progress) -> Result<RotorRun, RotorError> {
        let mut run = run_model(
            &self.built.model,
            &self.case.loads,
            &self.case.settings,
            self.teeth,
            None,
            progress,
        )?;
        self.label(&mut run);
        Ok(run)
    }

    /// [`Self::run`] at carrier speed `rpm` (r/min) instead of the scene's, from `warm` (a state
    /// of the same train, e.g. a nearby speed's `end_state`) when given: a sweep's step, or the
    /// dynamic path of a filmed track at its recorded speed.
    ///
    /// # Errors
    /// As [`Self::run`].
    pub fn run_at_rpm(
        &self,
        rpm: f64,
        warm: Option<&[f64]>,
        progress: &Progress,
    ) -> Result<RotorRun, RotorError> {
        let mut model = self.built.model.clone();
        model.omega = rpm * std::f64::consts::TAU / 60.0;
        let mut case = self.case.loads.clone();
        case.omega_rad_s = model.omega;
        let mut run = run_model(
            &model,
            &case,
            &self.case.settings,
            self.teeth,
            warm,
            progress,
        )?;
        self.label(&mut run);
        Ok(run)
    }

    /// The scene's name, design and effects on a run's report.
    fn label(&self, run: &mut RotorRun) {
        let r = &mut run.report;
        r.scene = self.case.name.clone();
        r.design = self.design.clone();
        r.effects = self.built.effects_log.clone();
    }
}
