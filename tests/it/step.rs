//! STEP solids: the same model gives the same bytes, every shell is closed (each edge
//! bounds exactly two faces, once each way), the counts follow the outline, bad options are typed
//! errors naming the option.
use ncgear::cad::ExportError;
use ncgear::cad::step::{Instance, Prism, StepModel, step_text};
use ncgear::math::Point;
use std::collections::HashMap;
use std::process::Command;

/// A 12-tooth star (24 vertices, CCW), radii 8 and 10 mm.
fn star(name: &str) -> Prism {
    let pts = (0..24)
        .map(|k| {
            let t = std::f64::consts::TAU * k as f64 / 24.0;
            let r = if k % 2 == 0 { 10.0 } else { 8.0 };
            Point::new(r * t.cos(), r * t.sin())
        })
        .collect();
    Prism {
        name: name.into(),
        outline_mm: pts,
        face_width_mm: 5.0,
        bore_mm: 0.0,
    }
}

fn assembly(bore_mm: f64) -> StepModel {
    let mut a = star("driver");
    a.bore_mm = bore_mm;
    let mut b = star("driven");
    b.outline_mm.reverse(); // CW on input: written CCW
    StepModel {
        name: "pair".into(),
        parts: vec![a, b],
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
                center_mm: Point::new(18.5, 0.0),
                angle_rad: 0.1,
            },
        ],
    }
}

/// `#id → entity text` of the DATA section.
fn entities(text: &str) -> HashMap<usize, String> {
    text.lines()
        .filter_map(|l| l.strip_prefix('#'))
        .filter_map(|l| l.split_once('='))
        .map(|(id, e)| (id.parse().unwrap(), e.trim_end_matches(';').to_string()))
        .collect()
}

#[test]
fn same_model_same_bytes_and_every_edge_bounds_two_faces_once_each_way() {
    let (text, stats) = step_text(&assembly(6.0)).unwrap();
    assert_eq!(text, step_text(&assembly(6.0)).unwrap().0, "deterministic");
    assert!(text.starts_with("ISO-10303-21;") && text.ends_with("END-ISO-10303-21;\n"));
    assert!(text.contains("AUTOMOTIVE_DESIGN") && text.contains("SI_UNIT(.MILLI.,.METRE.)"));
    let e = entities(&text);
    let count = |kind: &str| e.values().filter(|v| v.starts_with(kind)).count();
    assert_eq!(count("MANIFOLD_SOLID_BREP("), 2);
    assert_eq!(count("CLOSED_SHELL("), 2);
    // 24 sides + 2 caps each, + 2 half-cylinder bore faces on the driver.
    assert_eq!(count("ADVANCED_FACE("), 2 * 26 + 2);
    assert_eq!(stats.faces, 54);
    assert_eq!(count("CYLINDRICAL_SURFACE("), 1);
    assert_eq!(count("NEXT_ASSEMBLY_USAGE_OCCURRENCE("), 2);
    assert_eq!(count("ITEM_DEFINED_TRANSFORMATION("), 2);
    // Edges: 3 per outline vertex, + 4 arcs and 2 seams of the bore.
    assert_eq!(count("EDGE_CURVE("), 2 * 72 + 6);
    let mut uses: HashMap<String, (u32, u32)> = HashMap::new();
    for v in e.values().filter(|v| v.starts_with("ORIENTED_EDGE(")) {
        let args: Vec<&str> = v.trim_end_matches(')').split(',').collect();
        let u = uses.entry(args[3].to_string()).or_default();
        if args[4] == ".T." { u.0 += 1 } else { u.1 += 1 }
    }
    assert_eq!(uses.len(), 2 * 72 + 6, "every edge is used");
    assert!(
        uses.values().all(|&u| u == (1, 1)),
        "closed, consistently oriented shells"
    );
    assert!(!text.contains("NaN") && !text.contains("inf"));
}

#[test]
fn bad_bore_and_face_width_are_typed_errors_naming_the_option() {
    let err = |m: &StepModel| step_text(m).unwrap_err();
    // The star's outline comes no closer than 8 mm to its centre: a 16 mm bore does not fit.
    match err(&assembly(16.0)) {
        ExportError::InvalidOption { name, value, .. } => assert_eq!((name, value), ("bore", 16.0)),
        e => panic!("{e}"),
    }
    assert!(
        step_text(&assembly(14.0)).is_ok(),
        "a 14 mm bore fits inside 8 mm"
    );
    let mut m = assembly(0.0);
    m.parts[1].face_width_mm = 0.0;
    assert!(err(&m).to_string().contains("`face_width`"), "{}", err(&m));
    let mut m = assembly(-1.0);
    m.instances.clear();
    assert!(matches!(
        err(&m),
        ExportError::InvalidOption { name: "bore", .. }
    ));
}

#[test]
fn cli_pair_writes_a_step_assembly_and_refuses_a_bore_larger_than_the_gear() {
    let out = std::env::temp_dir().join(format!("ncgear-step-{}", std::process::id()));
    let run = |extra: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_ncgear"))
            .args([
                "pair",
                "phi - 0.08*sin(2*phi)",
                "--teeth",
                "24",
                "--module",
                "1.5",
            ])
            .args(["--verify-steps", "0", "--out"])
            .arg(&out)
            .args(extra)
            .output()
            .unwrap()
    };
    let ok = run(&["--face-width", "12", "--bore", "8"]);
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    let text = std::fs::read_to_string(out.join("pair.step")).unwrap();
    let e = entities(&text);
    assert_eq!(
        e.values()
            .filter(|v| v.starts_with("MANIFOLD_SOLID_BREP("))
            .count(),
        2
    );
    assert!(
        text.contains("VECTOR('',") && text.contains(",12.)"),
        "face width 12 mm"
    );
    let bad = run(&["--bore", "100"]);
    assert_eq!(bad.status.code(), Some(2));
    let msg = String::from_utf8_lossy(&bad.stderr);
    assert!(msg.contains("`bore` = 100"), "{msg}");
    let _ = std::fs::remove_dir_all(&out);
}
