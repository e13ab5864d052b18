//! The planting rotor's loads over a turn, the tooth stresses they cause, and the module sized
//! by strength (docs/loads.md): `ncgear loads SCENE.toml`, `ncgear design --module auto --loads`.
//!
//! A stage of its own above the design: a designed train ([`Rotor`]: its assembly, and its teeth
//! when it has them) and a validated scene ([`LoadCase`]) in, a [`LoadsReport`] out.
//! - [`scene`]: the scene file and its ranges → [`LoadCase`];
//! - [`motion`]: the bodies' motion at one carrier angle, from the design's tables;
//! - [`mass`]: the gear bodies' mass properties;
//! - [`needle`]: the needle load by travel angle;
//! - [`kinetostatics`]: Newton–Euler at one instant;
//! - [`analysis`]: the turn, the arms, the rotor's sums ([`analyse`]);
//! - [`rating`]: contact and root stresses by the structure of ISO 6336, safety factors, life;
//! - [`sizing`]: the smallest standard module (and face width) that carries the load;
//! - [`source`]: the rotor from a design file or a design in memory;
//! - [`report`]: the report, `loads.json`.
//!
//! ```
//! use ncgear::geometry::assembly::Assembly;
//! use ncgear::geometry::golden::g1_mechanism;
//! use ncgear::loads::{Rotor, Scene, analyse};
//! use ncgear::math::Point;
//!
//! // The G1 train at 300 r/min, one arm of 0.5 kg 80 mm from the planet axis, no gravity.
//! let asm = Assembly::from_mechanism(&g1_mechanism(), Point::ZERO, 1, 3600)?;
//! let scene: Scene = toml::from_str(
//!     "[operation]\ncarrier_rpm = 300.0\n[arm]\nmass_kg = 0.5\ncom_mm = [0.0, -80.0]\ninertia_kg_mm2 = 1000.0",
//! )?;
//! let loads = analyse(&Rotor::pitch(&asm), &scene.validate("scene.toml")?, "scene.toml")?;
//! // Lossless, rigid, no gravity and no needle load: the drive does no net work over a turn.
//! assert!(loads.summary.mean_power_w.abs() < 1e-9);
//! assert!(loads.summary.carrier_torque_peak_nm > 0.1);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod analysis;
pub mod kinetostatics;
pub mod mass;
pub mod motion;
pub mod needle;
pub mod rating;
pub mod report;
pub mod scene;
pub mod sizing;
pub mod source;

pub use analysis::{DynamicMeshForces, MeshForceSource, analyse, analyse_with};
pub use report::LoadsReport;
pub use scene::{LoadCase, Scene};
pub use sizing::{Kept, Sized, SizingOptions, rating_teeth, size_module};
pub use source::RotorSource;

use crate::design::train::ToothedTrain;
use crate::geometry::assembly::Assembly;
use std::path::Path;

/// A scene file run as `ncgear loads` runs it: the scene read and checked, the design it names
/// read back (its teeth made again when the scene rates them), the loads over the turn. The
/// report names the design file as the scene gives it.
///
/// # Errors
/// [`LoadsError`]: the scene's own (file, key, range), a design file that is not one, stresses
/// asked of a design without teeth, a mesh that locks.
pub fn run_scene(path: &Path) -> Result<LoadsReport, LoadsError> {
    run_scene_with(path, &|_, _| Ok(None))
}

/// Makes the dynamic forces of a scene that rates on them (`rating.K_v = "dynamic"`), from the
/// scene and its file name; `None` for a scene that does not.
pub type DynamicsOfScene =
    dyn Fn(&Scene, &str) -> Result<Option<Box<MeshForceSource<'static>>>, LoadsError>;

/// [`run_scene`], the teeth rated on the forces `dynamics` makes for the scene when it rates on
/// them (the rotor dynamics give it: `ncgear::analysis::dynamics::rotor::rating`).
///
/// # Errors
/// As [`run_scene`]; [`LoadsError::Field`] on `rating.K_v` for a scene that rates on dynamic
/// forces that `dynamics` does not make.
pub fn run_scene_with(path: &Path, dynamics: &DynamicsOfScene) -> Result<LoadsReport, LoadsError> {
    let file = path.display().to_string();
    let scene = Scene::from_path(path)?;
    let case = scene.validate(&file)?;
    let design = scene.design_path(path).ok_or_else(|| LoadsError::Field {
        file: file.clone(),
        key: "design".into(),
        message: "the scene names no design: add design = \"path/to/design.json\" (relative \
                  to the scene file), the file `ncgear design` writes"
            .into(),
    })?;
    let source = RotorSource::read(&design, case.rating.is_some())?;
    let forces = dynamics(&scene, &file)?;
    let mut report = analyse_with(&source.rotor(), &case, &file, forces.as_deref())?;
    report.design = scene.design.as_ref().map(|d| d.display().to_string());
    Ok(report)
}

/// The designed train whose loads are computed: its assembly (the design file's tables) and,
/// when it has them, its teeth.
#[derive(Debug, Clone, Copy)]
pub struct Rotor<'a> {
    assembly: &'a Assembly,
    teeth: Option<&'a ToothedTrain>,
    pressure_angle_rad: Option<f64>,
}

impl<'a> Rotor<'a> {
    /// A train of pitch curves (no teeth: no stresses).
    #[must_use]
    pub fn pitch(assembly: &'a Assembly) -> Self {
        Self {
            assembly,
            teeth: None,
            pressure_angle_rad: None,
        }
    }

    /// The same rotor with the mesh forces at the pressure angle `alpha_rad` (rad) instead of
    /// the case's (a design whose teeth are not made).
    #[must_use]
    pub fn with_pressure_angle_rad(self, alpha_rad: f64) -> Self {
        Self {
            pressure_angle_rad: Some(alpha_rad),
            ..self
        }
    }

    /// A toothed train (its own, scaled assembly).
    #[must_use]
    pub fn toothed(train: &'a ToothedTrain) -> Self {
        Self {
            assembly: &train.assembly,
            teeth: Some(train),
            pressure_angle_rad: Some(train.report.options.toothing.rack.alpha_rad()),
        }
    }

    /// The assembly.
    #[must_use]
    pub fn assembly(&self) -> &'a Assembly {
        self.assembly
    }

    /// The teeth, if any.
    #[must_use]
    pub fn teeth(&self) -> Option<&'a ToothedTrain> {
        self.teeth
    }

    /// The pressure angle of the mesh forces, rad: the teeth's rack, else the case's.
    #[must_use]
    pub fn pressure_angle_rad(&self, case: &LoadCase) -> f64 {
        self.pressure_angle_rad.unwrap_or(case.pressure_angle_rad)
    }
}

/// Why loads cannot be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum LoadsError {
    /// The scene file cannot be read or parsed (the message names the file and the key).
    #[error("{0}")]
    Scene(String),
    /// A field of the scene is out of its range.
    #[error("{file}: `{key}`: {message}")]
    Field {
        /// The scene file.
        file: String,
        /// The key, e.g. `arm.mass_kg`.
        key: String,
        /// What is wrong and what is expected.
        message: String,
    },
    /// The design file is not a design.
    #[error("{0}")]
    Design(String),
    /// The scene asks for stresses and the design has no teeth.
    #[error(
        "the scene's [material] asks for tooth stresses, and the design has no teeth: rate a \
         toothed train (a design made for a module), or remove [material] and [rating] for the \
         loads alone"
    )]
    NoTeeth,
    /// A mesh cannot transmit the moment needed (effective pressure angle ≥ 90°).
    #[error(
        "mesh {mesh} locks at travel {travel_deg:.2}°: the line of action passes the driven \
         gear's axis (effective pressure angle ≥ 90°); design within the gear limits"
    )]
    SelfLocking {
        /// `sun-intermediate` or `intermediate-planet`.
        mesh: &'static str,
        /// Travel angle, deg.
        travel_deg: f64,
    },
    /// The teeth of the design file could not be regenerated.
    #[error("{0}")]
    Teeth(String),
    /// No standard module could be designed or rated.
    #[error("{0}")]
    Sizing(String),
    /// The rotor dynamics that a `K_v = "dynamic"` rating runs could not give its forces (the
    /// dynamics' own message: an effect the design cannot give, the integrator's failure).
    #[error("the rotor dynamics of `rating.K_v = \"dynamic\"`: {0}")]
    Dynamics(String),
}
