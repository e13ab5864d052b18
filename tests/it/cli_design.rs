//! `ncgear design` end to end: files, JSON conventions checked by an independent integrator,
//! exit codes and messages on bad input.
use ncgear::math::Point;
use std::f64::consts::{PI, TAU};
use std::path::{Path, PathBuf};

use crate::cli::{ncgear, succeed};

fn out_dir(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn asset(name: &str) -> String {
    format!("{}/assets/trajectories/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// Linear interpolation in a uniform polar table `[[θ_deg, r], ...]` at θ (rad).
fn radius(table: &[[f64; 2]], theta: f64) -> f64 {
    let n = table.len();
    let x = theta.rem_euclid(TAU) / TAU * n as f64;
    let i = (x.floor() as usize) % n;
    let f = x - x.floor();
    table[i][1] * (1.0 - f) + table[(i + 1) % n][1] * f
}

fn pitch(v: &serde_json::Value) -> Vec<[f64; 2]> {
    v["pitch"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| [p[0].as_f64().unwrap(), p[1].as_f64().unwrap()])
        .collect()
}

/// Integrates the train from design.json alone, using only the documented conventions, and
/// returns the tip at `n` carrier angles (world frame, direction-aware).
fn tip_from_json(d: &serde_json::Value, n: usize) -> Vec<Point> {
    let a = d["center_distance_mm"].as_f64().unwrap();
    // The intermediate axis at ε off the carrier line (0 on it): D at φH + ε, A at 2a·cos ε.
    let eps = d["idler_offset_deg"].as_f64().unwrap().to_radians();
    let l1 = 2.0 * a * eps.cos();
    let l3 = d["l3_mm"].as_f64().unwrap();
    let gamma = d["needle_angle_deg"].as_f64().unwrap().to_radians();
    let c = [
        d["carrier"]["center_mm"][0].as_f64().unwrap(),
        d["carrier"]["center_mm"][1].as_f64().unwrap(),
    ];
    let dir = d["carrier"]["direction"].as_f64().unwrap();
    let g = &d["gears"];
    let (sun, mid, planet) = (
        pitch(&g["sun"]),
        pitch(&g["intermediate"]),
        pitch(&g["planet"]),
    );
    let th2_0 = g["intermediate"]["angle_at_zero_deg"]
        .as_f64()
        .unwrap()
        .to_radians();
    let th3_0 = g["planet"]["angle_at_zero_deg"]
        .as_f64()
        .unwrap()
        .to_radians();
    // Relative rotations about the moving centres, rolling without slip at the contacts:
    // dθ2/dφ = 1 + r_sun/ρ2 (sun–intermediate), dθ3/dφ = 1 − (ρ2/r_planet)(dθ2/dφ − 1); the sun
    // meets the intermediate along OD (world angle φ + ε), the planet meets it along DA (φ − ε).
    let rhs = |phi: f64, y: [f64; 2]| {
        let r1 = radius(&sun, phi + eps);
        let r2s = radius(&mid, phi + eps + PI - y[0]);
        let w2 = r1 / r2s;
        let r2p = radius(&mid, phi - eps - y[0]);
        let r3 = radius(&planet, phi + PI - eps - y[1]);
        [1.0 + w2, 1.0 - r2p / r3 * w2]
    };
    let steps = 20 * n;
    let h = dir * TAU / steps as f64;
    let mut y = [th2_0, th3_0];
    let mut phi: f64 = 0.0;
    let mut out = Vec::new();
    for k in 0..steps {
        if k % 20 == 0 {
            let b = y[1] + gamma;
            out.push(Point::new(
                c[0] + l1 * phi.cos() + l3 * b.cos(),
                c[1] + l1 * phi.sin() + l3 * b.sin(),
            ));
        }
        let k1 = rhs(phi, y);
        let k2 = rhs(
            phi + h / 2.0,
            [y[0] + h / 2.0 * k1[0], y[1] + h / 2.0 * k1[1]],
        );
        let k3 = rhs(
            phi + h / 2.0,
            [y[0] + h / 2.0 * k2[0], y[1] + h / 2.0 * k2[1]],
        );
        let k4 = rhs(phi + h, [y[0] + h * k3[0], y[1] + h * k3[1]]);
        for i in 0..2 {
            y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
        phi += h;
    }
    out
}

fn read_points(path: &str) -> Vec<Point> {
    let text = std::fs::read_to_string(path).unwrap();
    if path.ends_with(".json") {
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        return v["points"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| Point::new(p[0].as_f64().unwrap(), p[1].as_f64().unwrap()))
            .collect();
    }
    text.lines()
        .filter_map(|l| {
            let v: Vec<f64> = l.split(',').filter_map(|x| x.trim().parse().ok()).collect();
            (v.len() == 2).then(|| Point::new(v[0], v[1]))
        })
        .collect()
}

fn min_dist(p: Point, pts: &[Point]) -> f64 {
    let n = pts.len();
    (0..n)
        .map(|k| {
            let (a, b) = (pts[k], pts[(k + 1) % n]);
            let (dx, dy) = (b.x - a.x, b.y - a.y);
            let t = (((p.x - a.x) * dx + (p.y - a.y) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
            (p.x - a.x - t * dx).hypot(p.y - a.y - t * dy)
        })
        .fold(f64::INFINITY, f64::min)
}

fn run_design(file: &str, extra: &[&str], dir: &Path) -> serde_json::Value {
    succeed(
        ncgear()
            .arg("design")
            .arg(asset(file))
            .arg("--out")
            .arg(dir)
            .args(extra),
    );
    let text = std::fs::read_to_string(dir.join("design.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

#[test]
fn design_json_conventions_reproduce_the_target_independently() {
    // The third: G1 made for a module of 2 mm, its intermediate axis off the carrier line; the
    // fourth: the CW design off the line at a module (the mirror image, ε included).
    for (file, extra) in [
        ("g1_ellipse.csv", vec!["--png"]),
        ("asymmetric_cw.json", vec!["--center", "250,400"]),
        (
            "g1_ellipse.csv",
            vec!["--module", "2", "--verify-steps", "0"],
        ),
        (
            "asymmetric_cw.json",
            vec![
                "--center",
                "250,400",
                "--module",
                "2",
                "--verify-steps",
                "0",
            ],
        ),
    ] {
        let dir = out_dir(&format!("cli_{file}_{}", extra.len()));
        let d = run_design(file, &extra, &dir);
        if extra.contains(&"--module") {
            let eps = d["idler_offset_deg"].as_f64().unwrap();
            assert!(eps.abs() > 1.0, "{file} {extra:?}: ε = {eps}°");
        }
        for key in ["l1_mm", "l3_mm", "center_distance_mm", "needle_angle_deg"] {
            assert!(d[key].is_f64(), "{key}");
        }
        assert!(pitch(&d["gears"]["sun"]).len() >= 720);
        let claimed = d["roundtrip"]["max_deviation_mm"].as_f64().unwrap();
        let haus = d["roundtrip"]["hausdorff_mm"].as_f64().unwrap();
        assert!(haus <= 0.05 && claimed <= 0.05, "{file}: {claimed} {haus}");
        // Tip from the JSON alone, compared with the target file.
        let target = read_points(&asset(file));
        let traced = tip_from_json(&d, 720);
        let worst = traced
            .iter()
            .map(|p| min_dist(*p, &target))
            .fold(0.0, f64::max);
        assert!(
            worst <= claimed + 0.01,
            "{file}: independent integration deviates {worst} mm (report: {claimed})"
        );
        // Synchronous at φH = 0 for the CCW G1 file (point k at carrier angle k°).
        if file == "g1_ellipse.csv" {
            let p0 = traced[0];
            assert!(p0.distance(target[0]) < 0.05);
        }
        for f in [
            "sun.csv",
            "intermediate.csv",
            "planet.csv",
            "design.svg",
            "ratio.svg",
        ] {
            let meta = std::fs::metadata(dir.join(f)).unwrap();
            assert!(meta.len() > 1000, "{f}");
        }
        // The raster preview only with --png: a PNG signature and the chart's 900 × 800 pixels.
        let png = std::fs::read(dir.join("design.png"));
        if extra.contains(&"--png") {
            let png = png.unwrap();
            assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
            let wh = |o: usize| u32::from_be_bytes(png[o..o + 4].try_into().unwrap());
            assert_eq!((wh(16), wh(20)), (900, 800));
        } else {
            assert!(png.is_err(), "design.png written without --png");
        }
        let csv = std::fs::read_to_string(dir.join("sun.csv")).unwrap();
        assert!(csv.starts_with("theta_deg,r_mm,x_mm,y_mm\n"));
    }
}

#[test]
fn json_flag_prints_the_report() {
    let dir = out_dir("cli_json");
    let out = ncgear()
        .args([
            "design",
            &asset("g1_ellipse.csv"),
            "--json",
            "--order",
            "8",
            "--out",
        ])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["fourier"]["order"].as_u64(), Some(8));
}

fn expect_input_error(args: &[&str], contents: Option<(&str, &str)>, needles: &[&str]) {
    let dir = out_dir("cli_bad");
    std::fs::create_dir_all(&dir).unwrap();
    let mut cmd = ncgear();
    cmd.arg("design");
    if let Some((name, text)) = contents {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        cmd.arg(p);
    }
    let out = cmd
        .args(args)
        .arg("--out")
        .arg(dir.join("o"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    for n in needles {
        assert!(err.contains(n), "missing `{n}` in: {err}");
    }
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn bad_inputs_exit_2_with_a_clear_message() {
    expect_input_error(
        &["/nonexistent/path.csv"],
        None,
        &["/nonexistent/path.csv", "cannot read"],
    );
    expect_input_error(&[], Some(("empty.csv", "")), &["empty.csv", "at least 20"]);
    let g1 = std::fs::read_to_string(asset("g1_ellipse.csv")).unwrap();
    let broken = g1.replacen("\n", "\n1.0;oops\n", 3);
    expect_input_error(
        &[],
        Some(("broken.csv", &broken)),
        &["broken.csv", "line 2", "oops"],
    );
    let nan: String = g1
        .lines()
        .enumerate()
        .map(|(i, l)| {
            if i == 5 {
                "NaN,-159.7\n".to_string()
            } else {
                format!("{l}\n")
            }
        })
        .collect();
    expect_input_error(
        &[],
        Some(("nan.csv", &nan)),
        &["nan.csv", "line 6", "finite"],
    );
    let open: String = g1.lines().take(200).map(|l| format!("{l}\n")).collect();
    expect_input_error(&[], Some(("open.csv", &open)), &["open.csv", "open"]);
    expect_input_error(
        &["--center", "60,-140"],
        Some(("inside.csv", &g1)),
        // The library names the field; the CLI adds the flag as a hint.
        &["inside.csv", "winding", "center_mm", "--center X,Y"],
    );
    expect_input_error(
        &[],
        Some(("bad.json", r#"{"units": "mm", "pts": []}"#)),
        &["bad.json", "pts"],
    );
    expect_input_error(
        &["--order", "0"],
        Some(("g1.csv", &g1)),
        &["option `order`", "set by --order"],
    );
    expect_input_error(
        &["--tol-mm", "0"],
        Some(("g1.csv", &g1)),
        &["option `tol_mm`", "set by --tol-mm"],
    );
}
