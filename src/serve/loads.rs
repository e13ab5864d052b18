//! The loads of the design on screen (`POST /api/loads`, [`ncgear::loads`], docs/loads.md): the
//! rotor read back from the design's `design.json` object as `ncgear loads` reads a design file
//! (its teeth made again from its `teeth` block when they are rated), under a scene sent as the
//! tables of a scene file in JSON and checked by the library (its messages name the key:
//! `arm.mass_kg`, …). The answer is `ncgear loads`'s report of that design file.
//!
//! A design without teeth (no module) is not rated: the scene's `[material]` and `[rating]` are
//! left out, and a face width `"auto"` (the rating chooses it) leaves the gears massless; the
//! answer lists what was left out, and why, in `left_out`.

use super::api::ApiError;
use ncgear::design::train::{TrainPolicy, TrainTeethOptions};
use ncgear::geometry::assembly::Assembly;
use ncgear::loads::report::Bearings;
use ncgear::loads::scene::FaceWidth;
use ncgear::loads::{LoadsError, LoadsReport, RotorSource, Scene, analyse};
use ncgear::simulate::DesignFile;
use ncgear::teeth::ToothPolicy;
use serde::Deserialize;
use serde_json::Value;

/// What the scene is called in the library's messages (`scene: `arm.mass_kg`: …`) and the
/// request field its keys are under.
const SCENE: &str = "scene";

/// The tables a scene may have, in the order of a scene file.
const TABLES: [&str; 6] = ["operation", "arm", "gears", "needle", "material", "rating"];

/// Said when the scene rates the teeth of a design that has none.
pub const NO_TEETH: &str = "the design has no teeth: set a module to rate the teeth (the \
                            scene's [material] and [rating] are left out: these are the loads \
                            alone)";

/// Said when an `"auto"` face width has no rating to choose it.
pub const NO_FACE_WIDTH: &str = "the face width \"auto\" is chosen by the tooth rating, and the \
                                 teeth are not rated: the gears are taken massless (give the \
                                 face width in mm to count their mass)";

/// The loads of a design, and what of the scene was left out.
pub struct Loads {
    /// The library's report.
    pub report: LoadsReport,
    /// What the scene asked for that these loads leave out, and why (see the module docs).
    pub left_out: Vec<String>,
}

/// The loads of `design` (a `design.json` object) under `scene` (a scene's tables).
pub fn loads(design: &Value, scene: &Value) -> Result<Loads, ApiError> {
    let scene = parse_scene(scene)?;
    let mut case = scene.validate(SCENE).map_err(|e| loads_error(&e))?;
    let file = DesignFile::deserialize(design)
        .map_err(|e| ApiError::bad("design", format!("not a design.json object: {e}")))?;
    let assembly = file
        .assembly("design")
        .map_err(|e| ApiError::bad("design", e.to_string()))?;
    let mut left_out = Vec::new();
    if case.rating.is_some() && file.teeth.is_none() {
        case.rating = None;
        left_out.push(NO_TEETH.to_string());
    }
    if case.rating.is_none() && case.bodies.is_some_and(|b| b.face_width == FaceWidth::Auto) {
        case.bodies = None;
        left_out.push(NO_FACE_WIDTH.to_string());
    }
    let mut source = rotor_source(file, assembly);
    if case.rating.is_some() {
        source.make_teeth().map_err(|e| loads_error(&e))?;
    }
    let report = analyse(&source.rotor(), &case, SCENE).map_err(|e| loads_error(&e))?;
    Ok(Loads { report, left_out })
}

/// The rotor of a design file, as [`RotorSource::read`] makes it from the file's text: the
/// `teeth` block's own tooth count at its module, rack, backlash and cutters (teeth not made yet).
fn rotor_source(file: DesignFile, assembly: Assembly) -> RotorSource {
    let teeth_options = file.teeth.as_ref().map(|t| {
        t.options
            .clone()
            .unwrap_or_else(|| TrainTeethOptions::new(t.module_mm))
            .with_policy(TrainPolicy::ScaleCenterDistance(ToothPolicy::Exact(t.z)))
    });
    RotorSource {
        pressure_angle_rad: teeth_options.as_ref().map(|o| o.toothing.rack.alpha_rad()),
        assembly,
        teeth: None,
        teeth_options,
        target_mm: file.target_points,
    }
}

/// The scene of a request: a scene file's tables, without `design` (no file is read here).
fn parse_scene(v: &Value) -> Result<Scene, ApiError> {
    let Some(obj) = v.as_object() else {
        return Err(ApiError::bad(
            SCENE,
            "expected an object of the scene's tables: {\"operation\": {\"carrier_rpm\": …}, \
             \"arm\": {…}, …} (docs/loads.md)",
        ));
    };
    if obj.get("design").is_some_and(|d| !d.is_null()) {
        return Err(ApiError::bad(
            "scene.design",
            "the loads are those of the request's design: remove `design` from the scene",
        ));
    }
    Scene::deserialize(v).map_err(|e| {
        // The table at fault: the first that does not parse on its own (or a missing operation).
        let field = TABLES
            .into_iter()
            .find(|t| match obj.get(*t) {
                Some(table) => !table_parses(t, table),
                None => *t == "operation",
            })
            .map_or_else(|| SCENE.to_string(), |t| format!("{SCENE}.{t}"));
        ApiError::bad(&field, format!("{SCENE}: not a loads scene: {e}"))
    })
}

/// Whether the table `name` parses in a scene of its own.
fn table_parses(name: &str, table: &Value) -> bool {
    let mut probe = serde_json::json!({"operation": {"carrier_rpm": 300.0}});
    probe[name] = table.clone();
    Scene::deserialize(&probe).is_ok()
}

/// A library error as the API answers it: 400 naming the scene's key, or the design.
fn loads_error(e: &LoadsError) -> ApiError {
    let field = match e {
        LoadsError::Field { key, .. } => format!("{SCENE}.{key}"),
        LoadsError::Scene(_) => SCENE.to_string(),
        // The design's own: not a design, teeth that cannot be made again, a mesh that locks.
        _ => "design".to_string(),
    };
    ApiError::bad(&field, e.to_string())
}

/// Leaves the per-sample arrays the page draws (travel, carrier torque, planet mesh torque) and
/// empties the others (sun torque, frame, needle and bearing forces, the meshes' samples); the
/// summary, the rating and every reversal stay.
pub fn slim(r: &mut LoadsReport) {
    r.sun_torque_nm = Vec::new();
    r.frame_force_n = Vec::new();
    r.needle_force_n = Vec::new();
    r.bearings = Bearings::default();
    for m in [
        &mut r.meshes.sun_intermediate,
        &mut r.meshes.intermediate_planet,
    ] {
        m.normal_force_n = Vec::new();
        m.flank = Vec::new();
        m.pitch_point_mm = Vec::new();
        m.effective_pressure_angle_deg = Vec::new();
        m.pitch_radius_of_curvature_mm = Vec::new();
        m.flank_radius_mm = None;
        m.contact_ratio = None;
        m.contact_stress_mpa = None;
        m.root_stress_mpa = None;
    }
}
