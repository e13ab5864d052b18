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
use ncgear::analysis::dynamics::rotor::rating::forces_of_scene;
use ncgear::loads::report::Bearings;
use ncgear::loads::scene::FaceWidth;
use ncgear::loads::{LoadsError, LoadsReport, RotorSource, Scene, analyse_with};
use ncgear::simulate::DesignFile;
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
    let mut source = RotorSource::from_design_file(file, assembly);
    if case.rating.is_some() {
        source.make_teeth().map_err(|e| loads_error(&e))?;
    }
    let dynamics = if case.rating.is_some() {
        forces_of_scene(&scene, SCENE).map_err(|e| loads_error(&e))?
    } else {
        None
    };
    let report = analyse_with(&source.rotor(), &case, SCENE, dynamics.as_deref())
        .map_err(|e| loads_error(&e))?;
    Ok(Loads { report, left_out })
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
    r.needle_table_n = Vec::new();
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

#[cfg(test)]
mod tests {
    use super::super::dispatch::route;
    use ncgear::loads::{LoadsReport, Rotor, Scene, analyse, run_scene};
    use serde_json::{Value, json};
    use std::path::Path;

    fn asset(path: &str) -> String {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join(path)
            .display()
            .to_string()
    }

    /// `(status, answer)` of a request.
    fn post(path: &str, body: &Value) -> (u16, Value) {
        let r = route("POST", path, &body.to_string(), &|| false);
        (r.status, serde_json::from_slice(&r.body).unwrap())
    }

    /// The page's default scene, as `GET /api/loads/scene` answers it.
    fn default_scene() -> Value {
        let r = route("GET", "/api/loads/scene", "", &|| false);
        assert_eq!(r.status, 200);
        let v: Value = serde_json::from_slice(&r.body).unwrap();
        assert_eq!(v["scene"]["operation"]["carrier_rpm"], json!(300.0));
        assert_eq!(v["scene"]["material"]["preset"], json!("cast_iron"));
        v["scene"].clone()
    }

    fn close(a: &[f64], b: &[f64], tol: f64) -> f64 {
        assert_eq!(a.len(), b.len());
        let worst = a
            .iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        assert!(worst <= tol, "largest difference {worst:e} > {tol:e}");
        worst
    }

    /// The endpoint on a design file's object is `ncgear loads` on that file: the bundled G1
    /// train at module 2 under assets/loads/g1_rotor.toml (the same report, value for value).
    #[test]
    fn the_loads_of_a_design_are_ncgear_loads_of_its_file() {
        let cli = run_scene(Path::new(&asset("assets/loads/g1_rotor.toml"))).unwrap();
        let mut scene = Scene::from_path(Path::new(&asset("assets/loads/g1_rotor.toml"))).unwrap();
        scene.design = None;
        let text = std::fs::read_to_string(asset("assets/loads/g1_m2_design.json")).unwrap();
        let design: Value = serde_json::from_str(&text).unwrap();
        let (status, v) = post(
            "/api/loads",
            &json!({"design": design, "scene": scene, "full": true}),
        );
        assert_eq!(status, 200, "{v}");
        assert!(v.get("left_out").is_none());
        let got: LoadsReport = serde_json::from_value(v).unwrap();
        close(&got.carrier_torque_nm, &cli.carrier_torque_nm, 1e-9);
        close(&got.planet_mesh_torque_nm, &cli.planet_mesh_torque_nm, 1e-9);
        let (g, c) = (got.rating.unwrap(), cli.rating.unwrap());
        assert!((g.min_s_h.value - c.min_s_h.value).abs() < 1e-9);
        assert!((g.min_s_f.value - c.min_s_f.value).abs() < 1e-9);
        assert!((g.life_h - c.life_h).abs() <= 1e-9 * c.life_h);
        assert_eq!(got.summary.reversals_deg, cli.summary.reversals_deg);
    }

    /// Points and a module: designed as `ncgear design --module 2` designs them, then loaded as
    /// the page's design is; the carrier torque is the library's on the design made in memory.
    #[test]
    fn points_with_a_module_give_the_librarys_loads_of_their_design() {
        let r = route("GET", "/api/examples/g1_ellipse", "", &|| false);
        let points = serde_json::from_slice::<Value>(&r.body).unwrap()["points"].clone();
        let scene = default_scene();
        let (status, v) = post(
            "/api/loads",
            &json!({"points": points, "options": {"module": 2.0}, "scene": scene}),
        );
        assert_eq!(status, 200, "{v}");
        let got: LoadsReport = serde_json::from_value(v).unwrap();
        // The same design in memory: designed for the module, its teeth as the designer makes them.
        let traj = ncgear::design::trajectory::Trajectory::from_points(
            serde_json::from_value(points).unwrap(),
        )
        .unwrap();
        let opts = ncgear::design::DesignOptions::default().with_module_mm(Some(2.0));
        let d = ncgear::design::design(&traj, &opts).unwrap();
        let t = ncgear::design::train::TrainTeethOptions::new(2.0)
            .with_policy(ncgear::design::train::TrainPolicy::Designed);
        let train = ncgear::design::train::tooth_train(&d, &t).unwrap();
        let case = serde_json::from_value::<Scene>(scene)
            .unwrap()
            .validate("scene")
            .unwrap();
        let lib = analyse(&Rotor::toothed(&train), &case, "scene").unwrap();
        let worst = close(&got.carrier_torque_nm, &lib.carrier_torque_nm, 1e-9);
        eprintln!("carrier torque: largest difference from the library's {worst:e} N·m");
        assert!(
            (got.summary.carrier_torque_peak_nm - lib.summary.carrier_torque_peak_nm).abs() < 1e-9
        );
        assert!(got.rating.is_some() && got.summary.min_s_h.is_some());
        // Slimmed: the arrays the page draws, not the others.
        assert_eq!(got.travel_deg.len(), got.planet_mesh_torque_nm.len());
        assert!(got.bearings.o_n.is_empty() && got.meshes.sun_intermediate.flank.is_empty());
    }

    /// A negative arm mass is refused naming its key; a scene naming a file is refused.
    #[test]
    fn a_bad_scene_names_its_key() {
        let text = std::fs::read_to_string(asset("assets/loads/g1_m2_design.json")).unwrap();
        let design: Value = serde_json::from_str(&text).unwrap();
        let mut scene = default_scene();
        scene["arm"]["mass_kg"] = json!(-0.5);
        let (status, v) = post("/api/loads", &json!({"design": design, "scene": scene}));
        assert_eq!(
            (status, &v["field"]),
            (400, &json!("scene.arm.mass_kg")),
            "{v}"
        );
        assert!(v["error"].as_str().unwrap().contains("arm.mass_kg"));
        let mut scene = default_scene();
        scene["design"] = json!("/etc/passwd");
        let (status, v) = post("/api/loads", &json!({"design": design, "scene": scene}));
        assert_eq!((status, &v["field"]), (400, &json!("scene.design")), "{v}");
        let mut scene = default_scene();
        scene["operation"]["arms"] = json!(1.5);
        let (status, v) = post("/api/loads", &json!({"design": design, "scene": scene}));
        assert_eq!(
            (status, &v["field"]),
            (400, &json!("scene.operation")),
            "{v}"
        );
    }

    /// Without teeth: the loads alone, the rating and the "auto" face width left out, and said.
    #[test]
    fn a_design_without_teeth_is_not_rated() {
        let text = std::fs::read_to_string(asset("assets/loads/g1_m2_design.json")).unwrap();
        let mut design: Value = serde_json::from_str(&text).unwrap();
        design.as_object_mut().unwrap().remove("teeth");
        let (status, v) = post(
            "/api/loads",
            &json!({"design": design, "scene": default_scene()}),
        );
        assert_eq!(status, 200, "{v}");
        assert_eq!(
            v["left_out"],
            json!([super::NO_TEETH, super::NO_FACE_WIDTH])
        );
        let got: LoadsReport = serde_json::from_value(v).unwrap();
        assert!(got.rating.is_none() && got.gears.face_width_mm.is_none());
        assert!(got.summary.carrier_torque_peak_nm > 0.0);
    }
}
