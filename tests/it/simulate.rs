//! `ncgear simulate`: forward kinematics from tables, both arms, features, animation, errors.
use ncgear::geometry::assembly::Assembly;
use ncgear::geometry::fourier::SunRatio;
use ncgear::geometry::mechanism::Mechanism;
use ncgear::math::Point;
use ncgear::simulate::{DesignFile, FeatureOptions, SimulateError, Simulation, features};
use std::f64::consts::{PI, TAU};

const G1_CSV: &str = include_str!("../data/G1_trajectory_360.csv");

fn g1_points() -> Vec<Point> {
    G1_CSV
        .lines()
        .filter_map(|l| {
            let v: Vec<f64> = l.split(',').filter_map(|x| x.trim().parse().ok()).collect();
            (v.len() == 2).then(|| Point::new(v[0], v[1]))
        })
        .collect()
}

/// The exact G1 mechanism (docs/math/chain.md §11.1) assembled into design-file tables of 720 samples.
fn g1_sim() -> Simulation {
    let e: f64 = 0.15;
    let m = Mechanism {
        a_mm: 45.0,
        l3_mm: 170.0,
        ratio: SunRatio::new((1..=30).map(|k| 2.0 * e.powi(k)).collect(), vec![0.0; 30]).unwrap(),
        sun_phase_rad: 0.0,
        needle_angle_rad: (-70f64).to_radians(),
        idler_offset_rad: 0.0,
    };
    Simulation::new(Assembly::from_mechanism(&m, Point::new(0.0, 0.0), 1, 720).unwrap())
}

#[test]
fn g1_tables_trace_the_golden_trajectory_and_arm_2_follows_half_a_turn_later() {
    let sim = g1_sim();
    let pts = g1_points();
    assert_eq!(pts.len(), 360);
    let mut worst: f64 = 0.0;
    for (k, p) in pts.iter().enumerate() {
        let phi = (k as f64).to_radians();
        let t = sim.pose(phi);
        worst = worst.max(t.arm1.tip_mm.distance(*p));
        // Arm 2 at φ is at the golden point of φ + 180°.
        let q = pts[(k + 180) % 360];
        worst = worst.max(t.arm2.tip_mm.distance(q));
        // Mesh conditions hold on the tables.
        assert!(t.arm1.sun_mesh_error_mm.abs() < 1e-9 && t.arm1.planet_mesh_error_mm.abs() < 1e-9);
        // Arm 2's centres are opposite arm 1's.
        assert!((t.arm2.planet_center_mm.x + t.arm1.planet_center_mm.x).abs() < 1e-9);
    }
    assert!(
        worst < 1e-6,
        "max deviation from G1_trajectory_360.csv: {worst:e} mm"
    );
}

#[test]
fn g1_features_against_independent_values() {
    let sim = g1_sim();
    let opts = FeatureOptions::default()
        .with_samples(36_000)
        .with_rpm(300.0)
        .with_forward_mm_s(1000.0);
    let f = features(&sim, &opts).unwrap();
    // Extreme tip distances are l1 + l3 = 260 and l3 − l1 = 80 (docs/math/chain.md §11.1).
    assert!(
        (f.rho_range_mm[0] - 260.0).abs() < 1e-4 && (f.rho_range_mm[1] - 80.0).abs() < 1e-4,
        "{:?}",
        f.rho_range_mm
    );
    // Height and bounding box from the golden file's own points (1° resolution) and the bbox of docs/math/chain.md §11.1.
    let pts = g1_points();
    let (ymin, ymax) = pts
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.y), b.max(p.y)));
    assert!(
        f.height_mm >= ymax - ymin - 1e-9 && f.height_mm - (ymax - ymin) < 0.05,
        "{} vs {}",
        f.height_mm,
        ymax - ymin
    );
    assert!((f.bbox_mm[0] + 62.2).abs() < 0.05 && (f.bbox_mm[1] - 194.1).abs() < 0.05);
    assert!((f.bbox_mm[2] + 198.3).abs() < 0.05 && (f.bbox_mm[3] + 75.7).abs() < 0.05);
    // Needle angle at the lowest point, from the file: direction from A = l1·e(k°) to the point.
    let (k_low, p_low) = pts
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.y.total_cmp(&b.1.y))
        .unwrap();
    let phi = (k_low as f64).to_radians();
    let needle = (p_low.y - 90.0 * phi.sin())
        .atan2(p_low.x - 90.0 * phi.cos())
        .to_degrees();
    assert!(
        (f.needle_angle_plant_deg - needle).abs() < 1.0,
        "{} vs {needle}",
        f.needle_angle_plant_deg
    );
    assert!((f.plant_carrier_deg - k_low as f64).abs() < 1.0);
    // Max tip speed by central differences on the file at 300 rpm (ω = 10π rad/s).
    let n = pts.len();
    let vmax = (0..n)
        .map(|k| {
            let (a, b) = (pts[(k + n - 1) % n], pts[(k + 1) % n]);
            b.distance(a) / (2.0 * TAU / n as f64) * 10.0 * PI
        })
        .fold(0.0, f64::max);
    assert!(
        (f.max_tip_speed_mm_s / vmax - 1.0).abs() < 0.005,
        "{} vs {vmax}",
        f.max_tip_speed_mm_s
    );
    // Needles come closest when arm 1's tip is at ρmin on the line towards A2: 2·l1 − l3 = 10 mm.
    assert!(
        (f.min_arm_clearance_mm - 10.0).abs() < 1e-3,
        "{}",
        f.min_arm_clearance_mm
    );
    // Two plants per turn: spacing = v·T/2 = 1000 mm/s · 0.2 s / 2.
    assert!((f.plant_spacing_mm - 100.0).abs() < 1e-9);
    assert!((FeatureOptions::forward_for_spacing(100.0, 300.0) - 1000.0).abs() < 1e-9);
    // Hole width: the dynamic stroke is narrower than the static loop at the same depth when the
    // machine moves forward (the loop is swept backwards under the soil).
    assert!(f.hole_width_mm > 0.0 && f.hole_width_mm < f.static_width_at_depth_mm);
    let still = features(&sim, &opts.with_forward_mm_s(0.0)).unwrap();
    assert!((still.hole_width_mm - still.static_width_at_depth_mm).abs() < 1e-6);
    // Levels outside the path are refused.
    assert!(matches!(
        features(&sim, &opts.with_plant_level_mm(Some(10.0))),
        Err(SimulateError::BadOption { .. })
    ));
}

use crate::cli::{ncgear, succeed_json};

#[test]
fn simulate_cli_writes_animation_and_refuses_bad_design_files() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("sim_cli");
    let _ = std::fs::remove_dir_all(&dir);
    let traj = format!(
        "{}/assets/trajectories/g1_ellipse.csv",
        env!("CARGO_MANIFEST_DIR")
    );
    let st = ncgear()
        .args(["design", &traj, "--out"])
        .arg(dir.join("d"))
        .output()
        .unwrap();
    assert!(st.status.success());
    let v = succeed_json(
        ncgear()
            .arg("simulate")
            .arg(dir.join("d/design.json"))
            .arg("--out")
            .arg(dir.join("s"))
            .arg("--json"),
    );
    assert!(v["deviation_max_mm"].as_f64().unwrap() < 0.05);
    assert!(v["arm2_vs_arm1_mm"].as_f64().unwrap() < 1e-6);
    let svg = std::fs::read_to_string(dir.join("s/animation.svg")).unwrap();
    assert!(
        svg.matches("<animateTransform").count() >= 9,
        "carrier + 2 × (2 translate + 2 rotate)"
    );
    assert!(svg.contains("repeatCount=\"indefinite\"") && !svg.contains("<script"));
    for f in [
        "traced.csv",
        "dynamic.csv",
        "frames.svg",
        "ratios.png",
        "pitch.svg",
        "curvature.png",
        "pressure_angle.svg",
        "deviation.png",
        "dynamic.png",
        "features.png",
        "features.svg",
        "simulate.json",
    ] {
        assert!(
            std::fs::metadata(dir.join("s").join(f)).unwrap().len() > 500,
            "{f}"
        );
    }
    // A corrupted design file: radius beyond the centre distance, and a missing field.
    let text = std::fs::read_to_string(dir.join("d/design.json")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["gears"]["sun"]["pitch"][5][1] = serde_json::json!(99.0);
    std::fs::write(dir.join("bad1.json"), v.to_string()).unwrap();
    let out = ncgear()
        .arg("simulate")
        .arg(dir.join("bad1.json"))
        .arg("--out")
        .arg(dir.join("x"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("gears.sun.pitch[5]") && err.contains("bad1.json"),
        "{err}"
    );
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v.as_object_mut().unwrap().remove("needle_angle_deg");
    let err = DesignFile::parse(&v.to_string(), "bad2.json").unwrap_err();
    assert!(err.to_string().contains("needle_angle_deg"), "{err}");
}

/// A design file of layout version 1 (`l1`, `l3`, `center_distance`, `carrier.center_mm`: the
/// bundled transplanter example) reads to the same train as its version-2 spelling, and the
/// design report reads it too (version 1 when the file names none).
#[test]
fn a_version_1_design_file_reads_as_its_version_2_spelling() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/transplanter/g1_design.json"
    );
    let v1 = std::fs::read_to_string(path).unwrap();
    let mut doc: serde_json::Value = serde_json::from_str(&v1).unwrap();
    assert!(doc.get("schema_version").is_none() && doc.get("l3").is_some());
    let o = doc.as_object_mut().unwrap();
    for (old, new) in [
        ("l1", "l1_mm"),
        ("l3", "l3_mm"),
        ("center_distance", "center_distance_mm"),
    ] {
        let v = o.remove(old).unwrap();
        o.insert(new.into(), v);
    }
    o.insert("schema_version".into(), 2.into());
    let carrier = o["carrier"].as_object_mut().unwrap();
    let c = carrier.remove("center").unwrap();
    carrier.insert("center_mm".into(), c);
    let v2 = doc.to_string();
    let (_, a1) = DesignFile::parse(&v1, "v1").unwrap();
    let (_, a2) = DesignFile::parse(&v2, "v2").unwrap();
    assert_eq!(format!("{a1:?}"), format!("{a2:?}"));
    assert!((a1.a_mm - 45.0).abs() < 1e-5, "{}", a1.a_mm);
    let r1: ncgear::design::DesignReport = serde_json::from_str(&v1).unwrap();
    let r2: ncgear::design::DesignReport = serde_json::from_str(&v2).unwrap();
    assert_eq!((r1.schema_version, r2.schema_version), (1, 2));
    assert_eq!(r1.l3_mm, r2.l3_mm);
    assert_eq!(r1.carrier.center_mm, r2.carrier.center_mm);
}
