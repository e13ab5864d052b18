//! A needle-tip path that crosses itself (assets/trajectories/g1_looped.csv: the G1 train with
//! l3 = 260 mm, needle angle 110°, traced by `ncgear simulate`, a small loop) drawn as a DXF
//! SPLINE, a LWPOLYLINE with bulges, a chain of LINEs and an SVG path in px under a transform
//! (scripts/make_drawings.py) designs as its CSV does; the truly ambiguous drawings (three ends
//! at a point, a spike out and back) are refused, saying where.
use crate::cli::{message, ncgear, succeed_json};
use ncgear::design::trajectory::{DrawingOptions, Trajectory, TrajectoryError};
use ncgear::design::{DesignOptions, design};
use ncgear::math::Point;
use ncgear::math::polyline::seg_crossing;
use std::path::{Path, PathBuf};

fn asset(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(name)
}

const CSV: &str = "assets/trajectories/g1_looped.csv";
const DRAWINGS: [&str; 4] = [
    "g1_looped_spline.dxf",
    "g1_looped_bulge.dxf",
    "g1_looped_lines.dxf",
    "g1_looped_px.svg",
];

fn drawing(name: &str) -> PathBuf {
    asset(&format!("assets/drawings/{name}"))
}

/// `(l1, l3)` of the default design of `t`, mm.
fn lengths(t: &Trajectory) -> (f64, f64) {
    let d = design(t, &DesignOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    (d.report.l1_mm, d.report.l3_mm)
}

/// Crossings of the closed polyline `p`: pairs of non-adjacent edges that meet.
fn crossings(p: &[Point]) -> usize {
    let n = p.len();
    let mut count = 0;
    for i in 0..n {
        for j in i + 2..n {
            if !(i == 0 && j == n - 1)
                && seg_crossing(p[i], p[(i + 1) % n], p[j], p[(j + 1) % n]).is_some()
            {
                count += 1;
            }
        }
    }
    count
}

#[test]
fn a_looped_path_drawn_four_ways_designs_as_its_csv() {
    let csv = Trajectory::from_path(&asset(CSV)).unwrap();
    assert_eq!(crossings(csv.points()), 1, "the target has its one loop");
    let (l1, l3) = lengths(&csv);
    for name in DRAWINGS {
        let t = Trajectory::from_path(&drawing(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(crossings(t.points()), 1, "{name} is read with its loop");
        let (dl1, dl3) = lengths(&t);
        eprintln!(
            "{name}: |Δl1| = {:.1e} mm, |Δl3| = {:.1e} mm",
            (dl1 - l1).abs(),
            (dl3 - l3).abs()
        );
        if name == "g1_looped_lines.dxf" {
            // Straight lines keep their vertices: the CSV's points, in its order.
            assert_eq!(t.points(), csv.points());
        }
        assert!(
            (dl1 - l1).abs() < 1e-3 && (dl3 - l3).abs() < 1e-3,
            "{name}: l1 {dl1} vs {l1}, l3 {dl3} vs {l3}"
        );
    }
}

#[test]
fn the_cli_designs_the_looped_drawings_as_the_csv() {
    let run = |path: &Path| {
        let name = path.file_name().unwrap().to_string_lossy();
        let out = std::env::temp_dir().join(format!("ncgear_looped_{}_{name}", std::process::id()));
        let v = succeed_json(
            ncgear()
                .arg("design")
                .arg(path)
                .arg("--out")
                .arg(&out)
                .arg("--json"),
        );
        std::fs::remove_dir_all(&out).ok();
        (v["l1_mm"].as_f64().unwrap(), v["l3_mm"].as_f64().unwrap())
    };
    let (l1, l3) = run(&asset(CSV));
    // The train it was traced from: l1 = 90 mm, l3 = 260 mm.
    assert!(
        (l1 - 90.0).abs() < 1e-3 && (l3 - 260.0).abs() < 1e-3,
        "{l1} {l3}"
    );
    for name in DRAWINGS {
        let (a, b) = run(&drawing(name));
        assert!(
            (a - l1).abs() < 1e-3 && (b - l3).abs() < 1e-3,
            "{name}: {a} {b}"
        );
    }
}

#[test]
fn a_junction_and_a_spike_are_refused_with_their_place() {
    let csv = Trajectory::from_path(&asset(CSV)).unwrap();
    let p = csv.points();
    // Three ends meet at vertex 200, where the extra LINE starts.
    match Trajectory::from_path(&drawing("g1_looped_junction.dxf")).unwrap_err() {
        e @ TrajectoryError::Junction { ends, x, y, .. } => {
            assert_eq!(ends, 3, "{e}");
            assert!(Point::new(x, y).distance(p[200]) < 1e-6, "{e}");
            let m = e.to_string();
            assert!(
                m.contains("one polyline or spline") && m.contains("layer \"0\""),
                "{m}"
            );
        }
        other => panic!("{other:?}"),
    }
    // The spike runs 20 mm out of vertex 100 along the normal and back: its middle is 10 mm out.
    let normal = (p[101] - p[100]).perp() * (-1.0 / p[101].distance(p[100]));
    let middle = p[100] + normal * 10.0;
    match Trajectory::from_path(&drawing("g1_looped_spike.dxf")).unwrap_err() {
        e @ TrajectoryError::Retraced { x, y, .. } => {
            assert!(
                Point::new(x, y).distance(middle) < 1e-6,
                "{e} vs {middle:?}"
            );
            assert!(e.to_string().contains("drawn once"), "{e}");
        }
        other => panic!("{other:?}"),
    }
    for name in ["g1_looped_junction.dxf", "g1_looped_spike.dxf"] {
        let out = ncgear()
            .arg("design")
            .arg(drawing(name))
            .args(["--out", "/nonexistent/never-written"])
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{name}");
        let m = message(&out);
        assert!(m.contains(name) && m.contains(" mm"), "{m}");
    }
    // A figure eight drawn as one polyline is read in its order; the design's own checks
    // refuse it (its farthest point from the carrier axis is reached twice), as for a CSV.
    let eight =
        Trajectory::from_path_with(&drawing("g1_figure8.dxf"), &DrawingOptions::default()).unwrap();
    assert_eq!(eight.len(), 200);
    assert!(crossings(eight.points()) >= 1);
    let e = design(&eight, &DesignOptions::default()).unwrap_err();
    assert!(e.to_string().contains("farthest point"), "{e}");
}
