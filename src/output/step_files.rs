//! STEP solids of a toothed train (`<gear>.step`, `train.step`) and of a pair (`pair.step`): the
//! gear outlines extruded by the face width, with an optional bore, in mm.

use super::error::{OutputError, create_dir};
use crate::cad::step::{Instance, Prism, StepModel, write_step};
use crate::design::train::{Gear, ToothedTrain};
use crate::math::Point;
use crate::math::polyline::simplify_closed;
use crate::pair::PairDesign;
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// Face width and bore of the extruded gears; [`Default`]: face width 10·m, no bore.
/// (De)serialisable (a missing field takes its default, an unknown one is an error) and built
/// with `with_*`.
#[derive(
    Debug,
    Clone,
    Copy,
    PartialEq,
    Default,
    serde::Serialize,
    serde::Deserialize,
    schemars::JsonSchema,
)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct SolidOptions {
    /// Face width, mm (`None`: 10 × the module).
    pub face_width_mm: Option<f64>,
    /// Bore diameter about each gear's rotation centre, mm (0: none).
    pub bore_mm: f64,
}

crate::builder::with_fields!(SolidOptions {
    with_face_width_mm => face_width_mm: Option<f64>,
    with_bore_mm => bore_mm: f64,
});

impl SolidOptions {
    /// The face width at `module_mm`, mm.
    #[must_use]
    pub fn face_width_at(&self, module_mm: f64) -> f64 {
        self.face_width_mm.unwrap_or(10.0 * module_mm)
    }

    /// Checks the sizes before any work ([`crate::cad::step::check_solid_sizes`]; the
    /// default face width, 10 × the module, is always valid). Whether the bore fits a gear is
    /// known only with its outline.
    ///
    /// # Errors
    /// [`crate::cad::ExportError::InvalidOption`] naming `face_width` or `bore`.
    pub fn validate(&self) -> Result<(), crate::cad::ExportError> {
        crate::cad::step::check_solid_sizes(self.face_width_mm.unwrap_or(1.0), self.bore_mm)
    }
}

/// The part `name`: `outline` simplified to `tol_mm` (as the DXF), extruded per `opts`.
fn prism(name: &str, outline: &[Point], tol_mm: f64, module_mm: f64, opts: &SolidOptions) -> Prism {
    Prism {
        name: name.to_string(),
        outline_mm: simplify_closed(outline, tol_mm),
        face_width_mm: opts.face_width_at(module_mm),
        bore_mm: opts.bore_mm,
    }
}

/// One gear of the train as a STEP part, body frame (rotation centre at the origin), z from 0 to
/// the face width; the outline is the DXF's (simplified to the export chord tolerance).
#[must_use]
pub fn gear_prism(train: &ToothedTrain, gear: Gear, opts: &SolidOptions) -> Prism {
    let o = match gear {
        Gear::Sun => &train.sun,
        Gear::Intermediate => &train.intermediate,
        Gear::Planet => &train.planet,
    };
    let r = &train.report;
    prism(
        gear.name(),
        &o.points_mm,
        r.options.toothing.chord_tol_mm,
        r.module_mm,
        opts,
    )
}

/// The whole train at carrier angle 0 as a STEP assembly, world frame of the design (mm): the sun
/// at O, and for each arm (arm 2 is arm 1 half a turn on) the intermediate at D and the planet at
/// A, turned to their orientations. Parts: `sun`, `intermediate`, `planet`; occurrences `sun`,
/// `arm1_intermediate`, `arm1_planet`, `arm2_intermediate`, `arm2_planet`.
#[must_use]
pub fn train_step(train: &ToothedTrain, opts: &SolidOptions) -> StepModel {
    let rebuilt = train.assembly.rebuild();
    let mut instances = vec![Instance {
        name: "sun".into(),
        part: 0,
        center_mm: train.assembly.center_mm,
        angle_rad: 0.0,
    }];
    for (arm, phi) in [(1, 0.0), (2, std::f64::consts::PI)] {
        let p = rebuilt.pose(phi);
        instances.push(Instance {
            name: format!("arm{arm}_intermediate"),
            part: 1,
            center_mm: p.intermediate_center_mm,
            angle_rad: p.intermediate_angle_rad,
        });
        instances.push(Instance {
            name: format!("arm{arm}_planet"),
            part: 2,
            center_mm: p.planet_center_mm,
            angle_rad: p.planet_angle_rad,
        });
    }
    StepModel {
        name: "train".into(),
        parts: Gear::ALL
            .iter()
            .map(|&g| gear_prism(train, g, opts))
            .collect(),
        instances,
    }
}

/// The pair at its start position as a STEP assembly (mm): the driver at the origin, the driven
/// gear at `(a, 0)` turned by `−ψ(0)`, as in `pair.dxf`. Outlines simplified to `chord_tol_mm`.
#[must_use]
pub fn pair_step(pair: &PairDesign, chord_tol_mm: f64, opts: &SolidOptions) -> StepModel {
    let m = pair.module_mm;
    StepModel {
        name: "pair".into(),
        parts: vec![
            prism("driver", &pair.driver.points_mm, chord_tol_mm, m, opts),
            prism("driven", &pair.driven.points_mm, chord_tol_mm, m, opts),
        ],
        instances: vec![
            Instance {
                name: "driver".into(),
                part: 0,
                center_mm: Point::new(0.0, 0.0),
                angle_rad: 0.0,
            },
            Instance {
                name: "driven".into(),
                part: 1,
                center_mm: Point::new(pair.center_distance_mm, 0.0),
                angle_rad: -pair.psi0_rad,
            },
        ],
    }
}

/// The STEP files of a toothed train as `(file name, model)`: `<gear>.step` (each gear about its
/// rotation centre) and `train.step` ([`train_step`]).
#[must_use]
pub fn train_step_models(train: &ToothedTrain, opts: &SolidOptions) -> Vec<(String, StepModel)> {
    let mut models: Vec<(String, StepModel)> = Gear::ALL
        .iter()
        .map(|&g| {
            let model = StepModel {
                name: g.name().into(),
                parts: vec![gear_prism(train, g, opts)],
                instances: Vec::new(),
            };
            (format!("{}.step", g.name()), model)
        })
        .collect();
    models.push(("train.step".into(), train_step(train, opts)));
    models
}

/// Writes [`train_step_models`] into `dir` (created if missing). Returns the written paths.
pub fn write_step_models(
    models: &[(String, StepModel)],
    dir: &Path,
) -> Result<Vec<PathBuf>, OutputError> {
    create_dir(dir)?;
    // Independent files: written side by side, listed in order (the first error in it is
    // returned).
    models
        .par_iter()
        .map(|(file, model)| {
            let path = dir.join(file);
            write_step(model, &path).map(|_| path)
        })
        .collect::<Vec<_>>()
        .into_iter()
        .map(|r| r.map_err(OutputError::from))
        .collect()
}

/// STEP files of a toothed train under `dir/teeth/` ([`train_step_models`]). Returns the written
/// paths.
pub fn write_teeth_step(
    train: &ToothedTrain,
    dir: &Path,
    opts: &SolidOptions,
) -> Result<Vec<PathBuf>, OutputError> {
    write_step_models(&train_step_models(train, opts), &dir.join("teeth"))
}
