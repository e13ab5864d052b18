//! `ncgear loads` and `ncgear design --module auto --loads` end to end: the report, the nominal
//! Hertz stress at every instant, the module sized by strength on the bundled targets, and every
//! bad scene refused at once (exit 2) naming its key.
use super::cli::{message, ncgear};
use std::path::{Path, PathBuf};

fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn asset(rel: &str) -> String {
    format!("{}/{rel}", env!("CARGO_MANIFEST_DIR"))
}

/// The bundled scene with its design named by absolute path, `extra` appended and `replace`
/// applied to the text.
fn g1_scene(dir: &Path, name: &str, edit: impl Fn(String) -> String) -> PathBuf {
    let text = std::fs::read_to_string(asset("assets/loads/g1_rotor.toml")).unwrap();
    let text = text.replace(
        "design = \"g1_m2_design.json\"",
        &format!("design = \"{}\"", asset("assets/loads/g1_m2_design.json")),
    );
    let p = dir.join(name);
    std::fs::write(&p, edit(text)).unwrap();
    p
}

/// Runs `scene`, asserts exit 0 and returns its `--json` report.
fn report(scene: &Path, out: &Path) -> serde_json::Value {
    let o = run(scene, out);
    assert_eq!(o.status.code(), Some(0), "{}", message(&o));
    serde_json::from_slice(&o.stdout).unwrap()
}

fn run(scene: &Path, out: &Path) -> std::process::Output {
    ncgear()
        .arg("loads")
        .arg(scene)
        .arg("--out")
        .arg(out)
        .arg("--json")
        .output()
        .unwrap()
}

/// With `factors = "nominal"` the contact stress at every instant is Hertz's for two cylinders
/// of the flanks' radii at the pitch point (`ρ·sin α` of the pitch curves' radii of curvature)
/// under the reported normal force: `σ = √(F_n·E/(2π(1 − ν²)·b)·(1/ρ1 + 1/ρ2))`; the root
/// stress is `F_t/(b·m)·Y_F·Y_S` with `Y_F·Y_S` within the range the rating reports.
#[test]
fn nominal_contact_stress_is_hertz_at_the_pitch_point() {
    let dir = scratch("loads_nominal");
    let scene = g1_scene(&dir, "nominal.toml", |t| {
        t.replace("factors = \"iso\"", "factors = \"nominal\"")
    });
    let out = run(&scene, &dir.join("out"));
    assert!(
        matches!(out.status.code(), Some(0 | 3)),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let (e, nu, b) = (173_000.0, 0.3, 25.0);
    let alpha = 20f64.to_radians();
    let n = v["travel_deg"].as_array().unwrap().len();
    assert!(n >= 720);
    for mesh in ["sun_intermediate", "intermediate_planet"] {
        let m = &v["meshes"][mesh];
        for k in 0..n {
            let f = m["normal_force_N"][k].as_f64().unwrap();
            let rho: Vec<f64> = (0..2)
                .map(|i| m["pitch_radius_of_curvature_mm"][k][i].as_f64().unwrap())
                .collect();
            let flank: Vec<f64> = (0..2)
                .map(|i| m["flank_radius_mm"][k][i].as_f64().unwrap())
                .collect();
            for i in 0..2 {
                assert!((flank[i] - rho[i] * alpha.sin()).abs() < 1e-9 * rho[i].abs());
            }
            let hertz = (f * e / (2.0 * std::f64::consts::PI * (1.0 - nu * nu) * b)
                * (1.0 / flank[0] + 1.0 / flank[1]))
                .sqrt();
            let sigma = m["contact_stress_MPa"][k].as_f64().unwrap();
            assert!(
                (sigma - hertz).abs() <= 1e-9 * hertz.max(1.0),
                "{mesh} {k}: {sigma} {hertz}"
            );
        }
    }
    // The nominal root stress of each gear: F_t/(b·m)·Y_F·Y_S, Y_F·Y_S in the reported range.
    let m_mm = v["rating"]["module_mm"].as_f64().unwrap();
    for (mesh, gear) in [
        ("sun_intermediate", "sun"),
        ("intermediate_planet", "planet"),
    ] {
        let range = &v["rating"]["gears"][gear]["Y_F_Y_S_range"];
        let (lo, hi) = (range[0].as_f64().unwrap(), range[1].as_f64().unwrap());
        assert!(lo > 2.0 && hi < 6.0, "{gear}: {lo}…{hi}");
        let m = &v["meshes"][mesh];
        for k in 0..n {
            let f_t = m["normal_force_N"][k].as_f64().unwrap() * alpha.cos();
            let root = m["root_stress_MPa"][gear][k].as_f64().unwrap();
            if f_t > 1.0 {
                let yfs = root * b * m_mm / f_t;
                assert!(yfs >= lo - 1e-9 && yfs <= hi + 1e-9, "{gear} {k}: {yfs}");
            }
        }
    }
}

/// The bundled scene on the bundled G1 train: the report's shape, its files, the ISO rating with
/// its validity notes, and a verdict that follows the safety factors.
#[test]
fn the_bundled_scene_rates_the_bundled_train() {
    let dir = scratch("loads_bundled");
    let v = report(
        Path::new(&asset("assets/loads/g1_rotor.toml")),
        &dir.join("out"),
    );
    let rating = &v["rating"];
    let (sh, sf) = (
        rating["min_S_H"]["value"].as_f64().unwrap(),
        rating["min_S_F"]["value"].as_f64().unwrap(),
    );
    assert!(
        sh >= 1.0 && sf >= 1.4 && v["verdict"]["passed"] == true,
        "{sh} {sf}"
    );
    assert_eq!(v["summary"]["min_S_H"]["value"], rating["min_S_H"]["value"]);
    assert!(rating["life_h"].as_f64().unwrap() > 100.0);
    // G1 at module 2 reaches an effective pressure angle near 29°: flagged beside the figures.
    let notes = rating["notes"].as_array().unwrap();
    assert!(
        notes
            .iter()
            .any(|n| n.as_str().unwrap().contains("effective pressure angle"))
    );
    // the planet torque's reversals: the slow one at 87–97° (the raised-cosine separation pulse,
    // centred near 90°, takes it through zero three times) and the quick one at 342.5°
    assert_eq!(v["summary"]["reversals_deg"].as_array().unwrap().len(), 4);
    for f in [
        "loads.json",
        "loads.csv",
        "torque.svg",
        "forces.svg",
        "stress.svg",
    ] {
        assert!(dir.join("out").join(f).is_file(), "{f}");
    }
    // A stricter target fails the verdict: exit 3, the files written; --accept-failed exits 0.
    let strict = g1_scene(&dir, "strict.toml", |t| {
        t.replace("S_H_min = 1.0", "S_H_min = 2.0")
    });
    let out = run(&strict, &dir.join("strict"));
    assert_eq!(out.status.code(), Some(3));
    assert!(dir.join("strict/loads.json").is_file());
    let out = ncgear()
        .arg("loads")
        .arg(&strict)
        .arg("--out")
        .arg(dir.join("strict"))
        .arg("--accept-failed")
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
}

/// Bad scenes are refused before any work, exit 2, naming the key and what is expected.
#[test]
fn bad_scenes_are_refused_naming_the_key() {
    let dir = scratch("loads_bad");
    let not_design = dir.join("not_design.json");
    std::fs::write(&not_design, "{\"points\": [1, 2]}").unwrap();
    // (case, text replaced, replacement, the key the message names)
    let cases = [
        ("mass", "mass_kg = 0.55", "mass_kg = -0.55", "arm.mass_kg"),
        (
            "inertia",
            "inertia_kg_mm2 = 2100.0",
            "inertia_kg_mm2 = nan",
            "arm.inertia_kg_mm2",
        ),
        (
            "density",
            "density_kg_m3 = 7100.0",
            "density_kg_m3 = -1.0",
            "gears.density_kg_m3",
        ),
        (
            "speed",
            "carrier_rpm = 300.0",
            "carrier_rpm = 0.0",
            "operation.carrier_rpm",
        ),
        ("arms", "arms = 2", "arms = 0", "operation.arms"),
        (
            "unknown",
            "[arm]",
            "[arm]\nlength_mm = 3.0",
            "unknown field `length_mm`",
        ),
        (
            "needle",
            "profile = \"planting\"",
            "force_N = [[0, 0, 0], [190, 4, 25], [185, 0, 0]]",
            "needle.force_N[2]",
        ),
        (
            "gravity",
            "gravity = [0.0, -1.0]",
            "gravity = [0.0, -9.81]",
            "operation.gravity",
        ),
        ("bore", "bore_mm = 10.0", "bore_mm = 80.0", "gears.bore_mm"),
        (
            "material",
            "preset = \"cast_iron\"",
            "preset = \"bronze\"",
            "material.preset",
        ),
    ];
    for (name, from, to, key) in cases {
        let scene = g1_scene(&dir, &format!("{name}.toml"), |t| t.replace(from, to));
        let out = run(&scene, &dir.join(name));
        let err = message(&out);
        assert_eq!(out.status.code(), Some(2), "{name}: {err}");
        assert!(err.contains(key), "{name}: {err}");
        assert!(!dir.join(name).join("loads.json").exists(), "{name}");
    }
    // A design file that is not one, and stresses asked of a design without teeth.
    let not = g1_scene(&dir, "not.toml", |t| {
        t.replace(
            &asset("assets/loads/g1_m2_design.json"),
            &not_design.display().to_string(),
        )
    });
    let out = run(&not, &dir.join("not"));
    let err = message(&out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("design file"), "{err}");
    let bare = g1_scene(&dir, "bare.toml", |t| {
        t.replace(
            &asset("assets/loads/g1_m2_design.json"),
            &asset("assets/transplanter/g1_design.json"),
        )
    });
    let out = run(&bare, &dir.join("bare"));
    let err = message(&out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("no teeth") && err.contains("--module"),
        "{err}"
    );
    // Without [material] the same design gives its loads (no stresses asked).
    let loads_only = g1_scene(&dir, "loads_only.toml", |t| {
        let t = t.replace(
            &asset("assets/loads/g1_m2_design.json"),
            &asset("assets/transplanter/g1_design.json"),
        );
        t[..t.find("[material]").unwrap()].to_string()
    });
    let v = report(&loads_only, &dir.join("loads_only"));
    assert!(
        v.get("rating").is_none()
            && v["meshes"]["sun_intermediate"]
                .get("contact_stress_MPa")
                .is_none()
    );
}

/// `--module auto` on the bundled targets: the module kept meets S_H ≥ 1 and S_F ≥ 1.4, the
/// next smaller module's row fails and says why, design.json carries the table and its teeth are
/// of the module kept; the teeth rated are the teeth written (a rack flag given: the table's
/// safety factors are those of loads.json).
#[test]
fn module_auto_keeps_the_smallest_module_that_carries_the_load() {
    let dir = scratch("loads_auto");
    for (target, accept, rack) in [
        (
            "assets/trajectories/g1_ellipse.csv",
            false,
            &["--fillet", "0.2"][..],
        ),
        ("assets/trajectories/designer_kidney.csv", true, &[][..]),
    ] {
        let out_dir = dir.join(Path::new(target).file_stem().unwrap());
        let mut cmd = ncgear();
        cmd.args(["design", &asset(target), "--module", "auto", "--loads"])
            .arg(asset("assets/loads/rotor.toml"))
            .arg("--out")
            .arg(&out_dir)
            .args(rack);
        if accept {
            // The kidney is traced by no train of the type at the modules strong enough.
            cmd.arg("--accept-failed");
        }
        let out = cmd.output().unwrap();
        assert_eq!(
            out.status.code(),
            Some(0),
            "{target}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let d: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out_dir.join("design.json")).unwrap())
                .unwrap();
        let s = &d["sizing"];
        let chosen = s["chosen_module_mm"].as_f64().unwrap();
        let rows = s["rows"].as_array().unwrap();
        let kept = rows
            .iter()
            .position(|r| r["module_mm"].as_f64() == Some(chosen))
            .unwrap();
        assert!(kept > 0, "{target}: a smaller module must have failed");
        let row = &rows[kept];
        assert!(
            row["passed"] == true
                && row["S_H"].as_f64().unwrap() >= 1.0
                && row["S_F"].as_f64().unwrap() >= 1.4
        );
        let b = row["face_width_mm"].as_f64().unwrap();
        assert!((6.0 * chosen..=15.0 * chosen).contains(&b), "{b}");
        let smaller = &rows[kept - 1];
        assert!(smaller["passed"] == false && smaller["fails"].as_str().unwrap().contains("< "));
        assert_eq!(d["teeth"]["module_mm"].as_f64(), Some(chosen));
        let l: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(out_dir.join("loads/loads.json")).unwrap(),
        )
        .unwrap();
        for s in ["S_H", "S_F"] {
            let rated = l["rating"][format!("min_{s}")]["value"].as_f64().unwrap();
            assert!(
                (rated - row[s].as_f64().unwrap()).abs() < 1e-9,
                "{target} {s}"
            );
        }
    }
}
