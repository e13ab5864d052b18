//! Integration tests: teeth (rack-envelope outlines, undercut, mesh), `pair`, exports.
use ncgear::cad::dxf::{DxfVersion, write_dxf};
use ncgear::cad::points::write_points;
use ncgear::cad::svg::write_svg;
use ncgear::geometry::pitch::PitchCurve;
use ncgear::math::Point;
use ncgear::pair::{Expr, Law, Motion, PairOptions, design_pair};
use ncgear::teeth::overlap::first_self_intersection;
use ncgear::teeth::{
    ArcFrame, GearBlank, Generation, Outline, OutlineOptions, RackParams, TeethError, ToothPolicy,
    generate, scale_curve, tooth_count,
};
use std::path::PathBuf;

/// The rack-generated outline of `curve` (mm) with `z` teeth of module `m` (mm): the
/// [`Generation::Rack`] of its blank.
pub(crate) fn rack_cut(
    curve: &PitchCurve,
    rack: &RackParams,
    z: u32,
    m: f64,
    opts: &OutlineOptions,
) -> Result<Outline, TeethError> {
    let frame = ArcFrame::new(curve);
    generate(
        &GearBlank::new(&frame, *rack, z, m, *opts),
        Generation::Rack,
    )
    .map(|g| g.outline)
}

fn focus_ellipse(a: f64, e: f64) -> impl Fn(f64) -> f64 {
    move |t: f64| a * (1.0 - e * e) / (1.0 - e * t.cos())
}

pub(crate) fn out_dir(sub: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("target")
        .join(sub);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Shoelace area (mm²).
fn area(p: &[Point]) -> f64 {
    let n = p.len();
    0.5 * (0..n)
        .map(|i| p[i].x * p[(i + 1) % n].y - p[(i + 1) % n].x * p[i].y)
        .sum::<f64>()
}

#[test]
fn g1_sun_at_module_2_has_23_teeth_and_no_undercut() {
    // docs/math/chain.md §11.1 (G1): A = 22.5, e = 0.15, L = 140.57306651 → z = L/(2π) = 22.373 → 23 after scaling,
    // A = 23.130664; undercut limit ρc ≥ 17.097 mm, min ρc = A(1 − e²).
    let sun = PitchCurve::from_fn(4096, focus_ellipse(22.5, 0.15)).unwrap();
    let tc = tooth_count(&sun, 2.0, ToothPolicy::ScaleUp, 1e-10).unwrap();
    assert_eq!(tc.z, 23);
    assert!((tc.z_raw - 22.373).abs() < 1e-3, "{}", tc.z_raw);
    assert!(
        (22.5 * tc.scale - 23.130_664).abs() < 1e-5,
        "{}",
        22.5 * tc.scale
    );
    let scaled = scale_curve(&sun, tc.scale).unwrap();
    let rack = RackParams::default();
    assert!((rack.undercut_limit_rho_mm(2.0) - 17.097).abs() < 1e-3);
    let o = rack_cut(
        &scaled,
        &rack,
        23,
        2.0,
        &OutlineOptions::new(0.0, 1e-3 * 2.0),
    )
    .unwrap();
    assert_eq!(o.undercut.undercut_count, 0);
    assert_eq!(o.undercut.concave_count, 0);
    assert_eq!(o.undercut.flanks.len(), 46);
    let rho_min = 23.130_664 * (1.0 - 0.15 * 0.15);
    assert!(
        (o.undercut.min_rho_mm - rho_min).abs() < 0.05,
        "{}",
        o.undercut.min_rho_mm
    );
    // One simple closed outline: no two non-adjacent edges touch.
    assert_eq!(first_self_intersection(&o.points_mm).unwrap(), None);
    // Closed CCW outline between root and tip offsets: area between the root and tip curve areas.
    let a = area(&o.points_mm);
    let l = 23.0 * std::f64::consts::PI * 2.0;
    let pitch_area = std::f64::consts::PI * 23.130_664f64.powi(2) * (1.0 - 0.15f64 * 0.15).sqrt();
    // Teeth roughly halve the annulus between root (−2.5) and tip (+2): A ≈ A_pitch − L·(hf−ha)/2 ± 0.5 L.
    assert!(
        a > pitch_area - 2.5 * l && a < pitch_area + 2.0 * l,
        "{a} vs {pitch_area}"
    );
    // Every vertex lies between the root and tip offsets (radially, within 2.5 m and 2 m).
    for p in &o.points_mm {
        let r = p.hypot();
        let t = p.atan2();
        let rp = scaled.radius_mm(t);
        assert!(
            r > rp - 2.5 * 2.0 * 1.02 && r < rp + 2.0 * 1.02,
            "vertex at r={r} vs pitch {rp}"
        );
    }
}

#[test]
fn undercut_caught_at_larger_module_with_rho_sin2_limit() {
    // Unscaled G1 sun (min ρc = 21.99375 mm). Largest module without undercut:
    // m = ρc·sin²α / h_straight* = 2.5729 mm. z = 18 → m = L/(18π) = 2.486 OK; z = 17 → 2.632 undercut.
    let sun = PitchCurve::from_fn(4096, focus_ellipse(22.5, 0.15)).unwrap();
    let l = sun.perimeter_mm(1e-10);
    let rack = RackParams::default();
    let m_max = 21.993_75 * rack.alpha_rad().sin().powi(2) / rack.straight_depth();
    assert!((m_max - 2.5729).abs() < 1e-3);
    let m18 = l / (18.0 * std::f64::consts::PI);
    assert!(rack_cut(&sun, &rack, 18, m18, &OutlineOptions::new(0.0, 1e-3)).is_ok());
    let m17 = l / (17.0 * std::f64::consts::PI);
    // Cut as the rack cuts it by default, with the undercut reported …
    let cut = rack_cut(&sun, &rack, 17, m17, &OutlineOptions::new(0.0, 1e-3)).unwrap();
    assert!(cut.undercut.undercut_count >= 1 && cut.undercut.max_undercut_mm > 0.0);
    // … and refused, naming the largest module that works, with the strict option.
    let mut strict = OutlineOptions::new(0.0, 1e-3);
    strict.refuse_undercut = true;
    match rack_cut(&sun, &rack, 17, m17, &strict) {
        Err(TeethError::Undercut {
            count,
            max_module_mm,
            ..
        }) => {
            assert!(count >= 1);
            assert!(
                (max_module_mm - m_max).abs() < 0.01 * m_max,
                "{max_module_mm} vs {m_max}"
            );
        }
        other => panic!("expected an undercut error, got {other:?}"),
    }
}

#[test]
fn concave_pitch_curve_is_refused() {
    // r = 20(1 + 0.2 cos 3θ) is concave near θ = π/3 (Δ < 0): a rack cannot cut it.
    let c = PitchCurve::from_fn(2048, |t| 20.0 * (1.0 + 0.2 * (3.0 * t).cos())).unwrap();
    assert!(c.curvature_extremes(2048).min_convexity_mm2 < 0.0);
    let tc = tooth_count(&c, 1.0, ToothPolicy::Nearest, 1e-9).unwrap();
    let c = scale_curve(&c, tc.scale).unwrap();
    let err = rack_cut(
        &c,
        &RackParams::default(),
        tc.z,
        1.0,
        &OutlineOptions::new(0.0, 1e-3),
    )
    .unwrap_err();
    assert!(matches!(err, TeethError::Concave { .. }), "{err}");
}

#[test]
fn involute_on_a_circle() {
    // docs/math/chain.md §11.5 (G5): rack generation on a circle gives an exact involute: inv(α_r) − inv(α) = polar angle
    // offset of the flank, constant along the flank. Check the flank points of tooth 0.
    let r0 = 24.0;
    let c = PitchCurve::from_fn(256, |_| r0).unwrap();
    let m = 2.0;
    let o = rack_cut(
        &c,
        &RackParams::default(),
        24,
        m,
        &OutlineOptions::new(0.0, 1e-6),
    )
    .unwrap();
    let alpha = 20f64.to_radians();
    let rb = r0 * alpha.cos();
    let inv = |a: f64| a.tan() - a;
    // Right flank of tooth 0 crosses the pitch circle at polar angle p/4/r0 = π/(2·24).
    let theta_pitch = std::f64::consts::PI / 48.0;
    let mut n = 0;
    for p in &o.points_mm {
        let r = p.hypot();
        let t = p.atan2();
        if t > 0.0 && t < 0.13 && r > rb * 1.01 && r > r0 - 1.0 * m && r < r0 + 0.99 * m {
            let ar = (rb / r).acos();
            // Right flank: polar angle = θ_pitch + inv(α) − inv(α_r).
            let want = theta_pitch + inv(alpha) - inv(ar);
            assert!((t - want).abs() < 1e-9, "r={r}: {t} vs {want}");
            n += 1;
        }
    }
    assert!(n > 50, "{n}");
}

fn check_pair(law: Law, teeth: u32, m: f64, tag: &str) -> ncgear::pair::PairDesign {
    let d = design_pair(&law, &PairOptions::new(Some(teeth), m)).unwrap();
    for o in [&d.driver, &d.driven] {
        assert_eq!(
            first_self_intersection(&o.points_mm).unwrap(),
            None,
            "{tag}"
        );
        assert!(area(&o.points_mm) > 0.0, "{tag}: CCW");
    }
    let mesh = d.mesh.clone().unwrap();
    assert_eq!(mesh.interference_steps, 0, "{tag}: {mesh:?}");
    assert!(mesh.max_penetration_mm <= 0.0);
    assert!(mesh.max_overlap_area_mm2 <= 1e-9, "{tag}: {mesh:?}");
    assert!(mesh.min_backlash_mm > 0.0, "{tag}: {mesh:?}");
    // Backlash = 0.04 m on the pitch curve, measured within 35 % (the lever arm varies).
    assert!(
        mesh.min_backlash_mm > 0.65 * 0.04 * m && mesh.max_backlash_mm < 1.35 * 0.04 * m,
        "{tag}: {mesh:?}"
    );
    assert!(mesh.max_transmission_error_deg <= 1e-5, "{tag}: {mesh:?}");
    assert!((d.perimeter_mm - f64::from(teeth) * std::f64::consts::PI * m).abs() < 1e-6);
    d
}

#[test]
fn pair_motion_law_meshes_without_interference() {
    let d = check_pair(
        Law::Motion(Expr::parse("phi - 0.08*sin(2*phi)").unwrap()),
        24,
        1.5,
        "law",
    );
    assert!((d.ratio_range[0] - 0.84).abs() < 1e-6 && (d.ratio_range[1] - 1.16).abs() < 1e-6);
    let dir = out_dir("test-dxf");
    let sheet = d.assembly_sheet();
    write_dxf(
        &sheet,
        &dir.join("pair_law_r2010.dxf"),
        DxfVersion::R2010,
        1e-3 * 1.5,
    )
    .unwrap();
    write_dxf(
        &sheet,
        &dir.join("pair_law_r12.dxf"),
        DxfVersion::R12,
        1e-3 * 1.5,
    )
    .unwrap();
    write_svg(&sheet, &dir.join("pair_law.svg"), 5.0).unwrap();
    let paths = write_points(&sheet, &dir.join("pair_law_points"), "pair_law").unwrap();
    assert_eq!(paths.len(), 5);
}

#[test]
fn pair_centrode_solves_closure_and_meshes() {
    // Closed form: focus ellipse centrode r = (1 − e²)/(1 − e cos φ) closes at a = 2 (docs/math/chain.md §11.1 (G1)).
    let m = Motion::from_law(
        &Law::Centrode(Expr::parse("(1 - 0.15^2)/(1 - 0.15*cos(phi))").unwrap()),
        2048,
    )
    .unwrap();
    assert!(
        (m.unit_center_distance - 2.0).abs() < 1e-12,
        "{}",
        m.unit_center_distance
    );
    // G1 ψ3 golden: the pair law is 2·atan2(k sin(φ/2), cos(φ/2)), k = (1+e)/(1−e) (docs/math/chain.md §11.1).
    let k = 1.15 / 0.85;
    for deg in [30.0f64, 100.0, 250.0] {
        let f = deg.to_radians();
        let want = 2.0 * (k * (f / 2.0).sin()).atan2((f / 2.0).cos());
        let want = if want < 0.0 {
            want + std::f64::consts::TAU
        } else {
            want
        };
        assert!(
            (m.psi(f) - want).abs() < 1e-9,
            "{deg}: {} vs {want}",
            m.psi(f)
        );
    }
    // ncgears' centrode example uses 20 teeth: its min ρc ≈ 0.83·r̄ makes the equivalent spur gear
    // z ≈ 16.7 < 2/sin²20° = 17.1, so the rack undercuts: cut and reported by default,
    // refused with the largest module under the strict option.
    let law = Law::Centrode(Expr::parse("1 + 0.08*cos(2*phi)").unwrap());
    let cut = design_pair(&law, &PairOptions::new(Some(20), 1.5)).unwrap();
    assert!(cut.driver_undercut.undercut_count > 0);
    assert_eq!(cut.mesh.unwrap().interference_steps, 0);
    let mut strict = PairOptions::new(Some(20), 1.5);
    strict.toothing.refuse_undercut = true;
    let err = design_pair(&law, &strict).unwrap_err();
    assert!(err.to_string().contains("undercut"), "{err}");
    assert!(err.to_string().contains("at least 21 teeth"), "{err}");
    check_pair(law, 24, 1.5, "centrode");
}

#[test]
fn exports_are_closed_mm_polylines() {
    let d = oracle_pair_unverified();
    let dir = out_dir("test-dxf");
    let sheet = d.assembly_sheet();
    let path = dir.join("pair_export_check.dxf");
    let tol = 1e-3 * 1.5;
    write_dxf(&sheet, &path, DxfVersion::R2010, tol).unwrap();
    let dr = dxf::Drawing::load_file(&path).unwrap();
    assert_eq!(
        dr.header.default_drawing_units,
        dxf::enums::Units::Millimeters
    );
    let mut closed = 0;
    for e in dr.entities() {
        if let dxf::entities::EntityType::LwPolyline(p) = &e.specific {
            assert!(p.is_closed());
            let (f, l) = (p.vertices[0], p.vertices[p.vertices.len() - 1]);
            assert!((f.x - l.x).hypot(f.y - l.y) > 1e-9, "duplicated end vertex");
            closed += 1;
            if e.common.layer == "DRIVER_OUTLINE" {
                // Every original vertex within the chord tolerance of the simplified polygon.
                let v: Vec<Point> = p.vertices.iter().map(|v| Point::new(v.x, v.y)).collect();
                let seg = |q: Point| {
                    (0..v.len())
                        .map(|i| {
                            let (a, b) = (v[i], v[(i + 1) % v.len()]);
                            let (dx, dy) = (b.x - a.x, b.y - a.y);
                            let t = (((q.x - a.x) * dx + (q.y - a.y) * dy) / (dx * dx + dy * dy))
                                .clamp(0.0, 1.0);
                            (q.x - a.x - t * dx).hypot(q.y - a.y - t * dy)
                        })
                        .fold(f64::INFINITY, f64::min)
                };
                for q in d.driver.points_mm.iter().step_by(97) {
                    assert!(seg(*q) <= tol * 1.0001, "{}", seg(*q));
                }
                assert!(v.len() < d.driver.points_mm.len());
            }
        }
    }
    assert_eq!(closed, 4);
    let svg = std::fs::read_to_string({
        let p = dir.join("pair_export_check.svg");
        write_svg(&sheet, &p, 5.0).unwrap();
        p
    })
    .unwrap();
    let b = sheet.bbox_mm();
    let w = b[2] - b[0] + 10.0;
    assert!(
        svg.contains(&format!("width=\"{w:.4}mm\"")),
        "{}",
        &svg[..300]
    );
    assert!(svg.contains("id=\"DRIVER_OUTLINE\"") && svg.contains("id=\"TEXT\""));
    assert_eq!(svg.matches("<polygon").count(), 4);
}

#[test]
fn bad_law_inputs_are_typed_errors() {
    assert!(Expr::parse("phi + ").is_err());
    let e = design_pair(
        &Law::Motion(Expr::parse("phi + 0.01*phi^2").unwrap()),
        &PairOptions::new(Some(20), 1.0),
    )
    .unwrap_err();
    assert!(
        e.to_string().contains("must repeat every driver turn"),
        "{e}"
    );
    let e = design_pair(
        &Law::Motion(Expr::parse("phi - 0.8*sin(2*phi)").unwrap()),
        &PairOptions::new(Some(20), 1.0),
    )
    .unwrap_err();
    assert!(e.to_string().contains("> 0"), "{e}");
    assert!(RackParams::new(0.0, 1.0, 0.25, 0.38).is_err());
}

/// Interference as overlap area: zero for the designed pair at the law's position;
/// with the driven gear clocked 0.02 rad off (≈ 6 backlashes) the teeth overlap, and the
/// windowed area found by the mesh check equals the area of the full outlines' intersection
/// computed independently in the world frame.
#[test]
fn overlap_area_is_zero_for_the_pair_and_matches_full_clipping_when_clocked_wrong() {
    use ncgear::progress::Progress;
    use ncgear::teeth::mesh::{MeshCheck, verify_mesh};
    use ncgear::teeth::overlap::polygon_overlap_area;
    let law = Law::Motion(Expr::parse("phi - 0.08*sin(2*phi)").unwrap());
    let d = design_pair(&law, &{
        let mut o = PairOptions::new(Some(24), 1.5);
        o.toothing.verify_steps = 0;
        o
    })
    .unwrap();
    let motion = Motion::from_law(&law, 4096).unwrap();
    let a = d.center_distance_mm;
    let run = |shift: f64| {
        verify_mesh(
            &d.driver.points_mm,
            &d.driven.points_mm,
            &|f| motion.psi(f) + shift,
            &{
                let mut check = MeshCheck::new(a, 1.5);
                check.steps = 24;
                check.backlash_mm = 0.06;
                check
            },
            &Progress::none(),
        )
        .unwrap()
    };
    let good = run(0.0);
    assert_eq!(good.max_overlap_area_mm2, 0.0, "{good:?}");
    assert_eq!(good.interference_steps, 0);
    for shift in [0.02, -0.02] {
        let bad = run(shift);
        assert!(bad.max_overlap_area_mm2 > 0.05, "{shift}: {bad:?}");
        assert_eq!(bad.interference_steps, 24, "{shift}: {bad:?}");
        let phi = bad.max_overlap_at_deg.to_radians();
        let rot = |p: &Point, t: f64, dx: f64| {
            let (s, c) = t.sin_cos();
            Point::new(c * p.x - s * p.y + dx, s * p.x + c * p.y)
        };
        let w1: Vec<Point> = d
            .driver
            .points_mm
            .iter()
            .map(|p| rot(p, phi, 0.0))
            .collect();
        let t2 = -(motion.psi(phi) + shift);
        let w2: Vec<Point> = d.driven.points_mm.iter().map(|p| rot(p, t2, a)).collect();
        let full = polygon_overlap_area(&w1, &w2).unwrap();
        assert!(
            (full - bad.max_overlap_area_mm2).abs() < 1e-9 * full.max(1.0),
            "{shift}: windowed {} vs full {full}",
            bad.max_overlap_area_mm2
        );
    }
}

/// ncgears' own example, `phi - 0.08*sin(2*phi)`, 24 teeth, m = 1.5 mm, without the mesh
/// verification (a fixture for the export and rendering tests).
pub fn oracle_pair_unverified() -> ncgear::pair::PairDesign {
    design_pair(
        &Law::Motion(Expr::parse("phi - 0.08*sin(2*phi)").unwrap()),
        &{
            let mut o = PairOptions::new(Some(24), 1.5);
            o.toothing.verify_steps = 0;
            o
        },
    )
    .unwrap()
}

#[test]
fn pair_and_train_options_build_with_builders_and_round_trip_through_json() {
    use ncgear::design::train::{TrainPolicy, TrainTeethOptions};
    use ncgear::teeth::ToothingOptions;
    let toothing = ToothingOptions::new(2.0)
        .with_backlash_mm(0.1)
        .with_verify_steps(36)
        .with_cutter_teeth(Some(34));
    assert_eq!((toothing.module_mm, toothing.chord_tol_mm), (2.0, 2e-3));
    let pair = PairOptions::new(Some(24), 2.0)
        .with_toothing(toothing)
        .with_open_sector_rad(Some([0.0, 3.0]));
    let json = serde_json::to_string(&pair).unwrap();
    assert!(json.contains("\"backlash_mm\":0.1"), "{json}");
    assert_eq!(serde_json::from_str::<PairOptions>(&json).unwrap(), pair);
    let train = TrainTeethOptions::new(2.0)
        .with_policy(TrainPolicy::Designed)
        .with_toothing(toothing)
        .with_wire_edm(true);
    let json = serde_json::to_string(&train).unwrap();
    assert_eq!(
        serde_json::from_str::<TrainTeethOptions>(&json).unwrap(),
        train
    );
    let outline = OutlineOptions::new(0.5, 1e-3).with_thin_left_mm(0.02);
    let partial: OutlineOptions =
        serde_json::from_str(r#"{"phase_mm": 0.5, "thin_left_mm": 0.02}"#).unwrap();
    assert_eq!(partial, outline);
    assert!(serde_json::from_str::<OutlineOptions>(r#"{"phase": 0.5}"#).is_err());
}
