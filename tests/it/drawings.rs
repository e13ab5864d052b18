//! Target loops read from DXF and SVG drawings made by other tools (assets/drawings/, made by
//! scripts/make_drawings.py with ezdxf and svgwrite) design the same gears as the CSV points.
use crate::cli::{message, ncgear};
use ncgear::design::trajectory::{DrawingOptions, DrawingUnits, Trajectory, TrajectoryError};
use ncgear::design::{Design, DesignOptions, design};
use std::path::{Path, PathBuf};

fn asset(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(name)
}

fn drawing(name: &str) -> PathBuf {
    asset(&format!("assets/drawings/{name}"))
}

fn designed(t: &Trajectory) -> Design {
    design(t, &DesignOptions::default()).expect("the G1 loop designs")
}

/// Largest difference of l1, l3 and the sun's pitch radii (mm) between two designs.
fn difference_mm(a: &Design, b: &Design) -> (f64, f64, f64) {
    let (ra, rb) = (&a.report, &b.report);
    let radii = ra
        .gears
        .sun
        .pitch
        .iter()
        .zip(&rb.gears.sun.pitch)
        .map(|(p, q)| (p[1] - q[1]).abs())
        .fold(0.0, f64::max);
    assert_eq!(ra.gears.sun.pitch.len(), rb.gears.sun.pitch.len());
    (
        (ra.l1_mm - rb.l1_mm).abs(),
        (ra.l3_mm - rb.l3_mm).abs(),
        radii,
    )
}

#[test]
fn g1_drawn_as_spline_bulges_lines_and_beziers_designs_as_the_csv() {
    let csv =
        designed(&Trajectory::from_path(&asset("assets/trajectories/g1_ellipse.csv")).unwrap());
    for name in [
        "g1_spline.dxf",
        "g1_bulge.dxf",
        "g1_lines.dxf",
        "g1_bezier.svg",
        "g1_px.svg",
    ] {
        let t = Trajectory::from_path(&drawing(name)).unwrap_or_else(|e| panic!("{e}"));
        // Straight lines keep their vertices (the CSV points); curves are resampled.
        let n = if name == "g1_lines.dxf" {
            360
        } else {
            ncgear::design::trajectory::DRAWING_SAMPLES
        };
        assert_eq!(t.len(), n, "{name}");
        let (dl1, dl3, dr) = difference_mm(&csv, &designed(&t));
        eprintln!("{name}: |Δl1| = {dl1:.2e} mm, |Δl3| = {dl3:.2e} mm, max |Δr_sun| = {dr:.2e} mm");
        assert!(
            dl1 < 0.01 && dl3 < 0.01 && dr < 0.01,
            "{name}: {dl1} {dl3} {dr}"
        );
    }
}

/// The G1 loop as FreeCAD 0.20 and Inkscape 1.2 write it (scripts/make_exporter_drawings.sh):
/// each one's conventions (SPLINEs of 6 significant digits, LINEs of 3 decimals, Inkscape
/// layers under transforms with the carrier axis at the page centre, relative path data of 8
/// digits, a px document without units, 360 open SPLINE pieces on a layer) designs the CSV's
/// train within 0.01 mm once the drawing's own choices (layer, id, units, where the axis is) are
/// named; without them it is refused, saying which.
#[test]
fn drawings_from_freecad_and_inkscape_design_as_the_csv() {
    let csv =
        designed(&Trajectory::from_path(&asset("assets/trajectories/g1_ellipse.csv")).unwrap());
    let none = DrawingOptions::default();
    let id = |s: &str| DrawingOptions::default().with_id(Some(s.into()));
    let page_svg = ncgear::math::Point::new(210.0, -148.5);
    let page_dxf = ncgear::math::Point::new(210.0, 148.5);
    let origin = ncgear::math::Point::new(0.0, 0.0);
    let cases = [
        ("g1_freecad_spline.dxf", none.clone(), origin),
        ("g1_freecad_lines.dxf", none.clone(), origin),
        (
            "g1_inkscape.dxf",
            DrawingOptions::default().with_layer(Some("TARGET".into())),
            page_dxf,
        ),
        ("g1_inkscape.svg", id("target"), page_svg),
        // The Inkscape layer's id picks the paths inside it.
        ("g1_inkscape.svg", id("layer1"), page_svg),
        (
            "g1_inkscape_px.svg",
            id("target").with_units(Some(DrawingUnits::Px)),
            page_svg,
        ),
    ];
    for (name, opts, center) in cases {
        let t = Trajectory::from_path_with(&drawing(name), &opts).unwrap_or_else(|e| panic!("{e}"));
        let o = DesignOptions::default().with_center_mm(center);
        let d = design(&t, &o).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(d.report.verdict.passed, "{name}: {:?}", d.report.verdict);
        let (dl1, dl3, dr) = difference_mm(&csv, &d);
        eprintln!("{name}: |Δl1| = {dl1:.2e} mm, |Δl3| = {dl3:.2e} mm, max |Δr_sun| = {dr:.2e} mm");
        assert!(
            dl1 < 0.01 && dl3 < 0.01 && dr < 0.01,
            "{name}: {dl1} {dl3} {dr}"
        );
    }
    // Refused, with the reason, when the drawing's own choice is not named.
    let refused = [
        (
            "g1_inkscape.dxf",
            none.clone(),
            "layer \"SKETCH\": 27 loops",
        ),
        (
            "g1_inkscape.svg",
            none.clone(),
            "id \"carrier_circle\": 1 loop",
        ),
        (
            "g1_inkscape_px.svg",
            id("target"),
            "1587.4016 wide, a length without a unit",
        ),
    ];
    for (name, opts, says) in refused {
        let e = Trajectory::from_path_with(&drawing(name), &opts).unwrap_err();
        assert!(e.to_string().contains(says), "{name}: {e}");
    }
}

#[test]
fn several_loops_need_a_layer() {
    let path = drawing("g1_layers.dxf");
    match Trajectory::from_path(&path) {
        Err(e @ TrajectoryError::SeveralLoops { .. }) => {
            let m = e.to_string();
            assert!(
                m.contains("layer \"TARGET\": 1 loop") && m.contains("layer \"SKETCH\": 2 loops"),
                "{m}"
            );
            assert!(m.contains("--layer"), "{m}");
        }
        other => panic!("{other:?}"),
    }
    let opts = DrawingOptions::default().with_layer(Some("TARGET".into()));
    let t = Trajectory::from_path_with(&path, &opts).unwrap();
    let csv = Trajectory::from_path(&asset("assets/trajectories/g1_ellipse.csv")).unwrap();
    // The polyline's vertices are the CSV points: the resampled loop starts at the first.
    assert!(t.points()[0].distance(csv.points()[0]) < 1e-9);
    let missing = DrawingOptions::default().with_layer(Some("NOPE".into()));
    let e = Trajectory::from_path_with(&path, &missing).unwrap_err();
    assert!(matches!(e, TrajectoryError::NoLoopNamed { .. }), "{e}");
    assert!(e.to_string().contains("TARGET"), "{e}");
}

#[test]
fn bad_drawings_are_refused_with_their_reason() {
    let read = |name: &str| Trajectory::from_path(&drawing(name)).unwrap_err();
    let open = read("g1_open.dxf");
    match &open {
        TrajectoryError::OpenLoop { gap_mm, .. } => assert!(*gap_mm > 20.0, "{open}"),
        other => panic!("{other:?}"),
    }
    assert!(matches!(
        read("g1_open.svg"),
        TrajectoryError::OpenLoop { .. }
    ));
    assert!(matches!(
        read("g1_unitless.dxf"),
        TrajectoryError::UnitsUnknown { .. }
    ));
    assert!(matches!(
        read("g1_unitless.svg"),
        TrajectoryError::UnitsUnknown { .. }
    ));
    let not = Trajectory::from_dxf(b"0\nSECTION\n2\nNOPE", &DrawingOptions::default(), "x.dxf");
    assert!(not.is_err());
    let not = Trajectory::from_svg("<svg", &DrawingOptions::default(), "x.svg");
    assert!(matches!(not, Err(TrajectoryError::NotADrawing { .. })));
    // A vertex of NaN and 1e400 (inf) is named as not finite, not as a loop "NaN mm" open.
    let nan = "0\nSECTION\n2\nENTITIES\n0\nLWPOLYLINE\n8\n0\n90\n3\n70\n1\n10\n0\n20\n0\n\
               10\n5\n20\n0\n10\nnan\n20\n1e400\n0\nENDSEC\n0\nEOF\n";
    let mm = DrawingOptions::default().with_units(Some(DrawingUnits::Mm));
    let e = Trajectory::from_dxf(nan.as_bytes(), &mm, "nan.dxf").unwrap_err();
    assert!(
        matches!(e, TrajectoryError::NonFiniteCoordinate { .. }),
        "{e}"
    );
    // Given units, the unitless files read as the mm ones.
    let mm = DrawingOptions::default().with_units(Some(DrawingUnits::Mm));
    let a = Trajectory::from_path_with(&drawing("g1_unitless.dxf"), &mm).unwrap();
    let b = Trajectory::from_path_with(&drawing("g1_unitless.svg"), &mm).unwrap();
    let c = Trajectory::from_path(&drawing("g1_bezier.svg")).unwrap();
    assert!(a.points()[0].distance(b.points()[0]) < 1e-3);
    assert!(b.points()[0].distance(c.points()[0]) < 1e-3);
}

#[test]
fn the_cli_refuses_a_bad_drawing_with_exit_2_and_reads_a_layer() {
    let out = ncgear()
        .args(["design"])
        .arg(drawing("g1_unitless.dxf"))
        .args(["--out", "/nonexistent/never-written"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let m = message(&out);
    assert!(
        m.contains("g1_unitless.dxf") && m.contains("--units"),
        "{m}"
    );
    let out = ncgear()
        .args(["design"])
        .arg(drawing("g1_layers.dxf"))
        .args(["--out", "/nonexistent/never-written"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(message(&out).contains("--layer"), "{}", message(&out));
}

/// A LWPOLYLINE header in mm (`$INSUNITS` 4) and its vertices `(x, y, bulge)`, closed.
fn lwpolyline(vertices: &[(f64, f64, f64)]) -> String {
    let mut t = String::from(
        "0\nSECTION\n2\nHEADER\n9\n$INSUNITS\n70\n4\n0\nENDSEC\n0\nSECTION\n2\nENTITIES\n\
         0\nLWPOLYLINE\n8\n0\n",
    );
    t += &format!("90\n{}\n70\n1\n", vertices.len());
    for (x, y, b) in vertices {
        t += &format!("10\n{x}\n20\n{y}\n42\n{b}\n");
    }
    t + "0\nENDSEC\n0\nEOF\n"
}

/// A traced polygon of 20 000 vertices is resampled (its retrace check would be quadratic in
/// them), a polygon of 360 keeps its vertices; arcs of absurd size flatten within the bounded
/// depth, not into memory.
#[test]
fn dense_and_absurd_drawings_stay_bounded() {
    let mm = DrawingOptions::default();
    let circle = |n: usize, r: f64, bulge: f64| -> Vec<(f64, f64, f64)> {
        (0..n)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / n as f64;
                (100.0 + r * t.cos(), r * t.sin(), bulge)
            })
            .collect()
    };
    let dense =
        Trajectory::from_dxf(lwpolyline(&circle(20_000, 40.0, 0.0)).as_bytes(), &mm, "d").unwrap();
    assert_eq!(dense.len(), ncgear::design::trajectory::DRAWING_SAMPLES);
    let kept =
        Trajectory::from_dxf(lwpolyline(&circle(360, 40.0, 0.0)).as_bytes(), &mm, "k").unwrap();
    assert_eq!(kept.len(), 360);
    // Half-circle bulges on a loop 2e12 mm across: flattened within the bounded depth and
    // resampled (the design then refuses its carrier axis, as for the same CSV).
    let huge = lwpolyline(&circle(24, 1e12, 1.0));
    let t = Trajectory::from_dxf(huge.as_bytes(), &mm, "h").unwrap();
    assert_eq!(t.len(), ncgear::design::trajectory::DRAWING_SAMPLES);
}
