//! Pairs with unequal tooth counts: a law advancing the driven gear by
//! Δ = ψ(φ + 2π) − ψ(φ) ≠ 2π per driver turn gives z : z·2π/Δ teeth; closure, phase and the mesh
//! verification over the q driver turns after which the pair is back at its start.
use ncgear::cad::dxf::{DxfVersion, write_dxf};
use ncgear::cad::points::write_points;
use ncgear::math::Point;
use ncgear::pair::{Expr, Law, Motion, PairOptions, design_pair};
use ncgear::teeth::mesh::MeshSpan;
use ncgear::teeth::overlap::first_self_intersection;
use std::f64::consts::{PI, TAU};

fn motion(e: &str) -> Law {
    Law::Motion(Expr::parse(e).unwrap())
}

/// Designs, then checks what every closed pair must satisfy: simple outlines, both perimeters
/// `z·π·m` (the driven one is an independent measure of the driven gear's closure), no
/// interference over the whole cycle and a transmission error far below a tooth's play.
fn check(law: &Law, z: u32, z_driven: u32, m: f64) -> ncgear::pair::PairDesign {
    use std::sync::Arc;
    use std::sync::atomic::{AtomicU64, Ordering};
    let done = Arc::new(AtomicU64::new(0));
    let seen = Arc::clone(&done);
    let opts = PairOptions::new(Some(z), m);
    let progress = ncgear::progress::Progress::new(move |n| {
        seen.fetch_add(n, Ordering::Relaxed);
    });
    let (mut d, pending) = ncgear::pair::design_pair_staged(law, &opts).unwrap();
    d.mesh = Some(pending.expect("verified").run(&progress).unwrap());
    // The whole entry gives the same design.
    assert_eq!(design_pair(law, &opts).unwrap().mesh, d.mesh);
    // The progress sink hears of every verified driver position.
    let steps = d.mesh.as_ref().expect("verified").steps;
    assert_eq!(done.load(Ordering::Relaxed), steps as u64);
    assert_eq!((d.z, d.z_driven), (z, z_driven));
    for o in [&d.driver, &d.driven] {
        assert_eq!(first_self_intersection(&o.points_mm).unwrap(), None);
    }
    let per = |n: u32| f64::from(n) * PI * m;
    assert!(
        (d.perimeter_mm - per(z)).abs() < 1e-9 * per(z),
        "{}",
        d.perimeter_mm
    );
    assert!(
        (d.driven_perimeter_mm - per(z_driven)).abs() < 1e-8 * per(z_driven),
        "driven perimeter {} vs {}",
        d.driven_perimeter_mm,
        per(z_driven)
    );
    let mesh = d.mesh.clone().unwrap();
    assert_eq!(mesh.interference_steps, 0, "{mesh:?}");
    assert!(mesh.max_overlap_area_mm2 <= 1e-9, "{mesh:?}");
    assert!(mesh.min_backlash_mm > 0.0, "{mesh:?}");
    assert!(mesh.max_transmission_error_deg <= 1e-5, "{mesh:?}");
    d
}

/// Closed form: a constant ratio 1/2 is a pair of circles r1 = a/3, r2 = 2a/3; at 24 teeth of
/// module 1 they are 12 and 24 mm, so a = 36 mm, and the check rolls 2 driver turns.
#[test]
fn constant_half_ratio_is_two_circles_at_the_closed_form_distance() {
    let d = check(&motion("0.5*phi"), 24, 48, 1.0);
    assert!(
        (d.center_distance_mm - 36.0).abs() < 1e-9,
        "{}",
        d.center_distance_mm
    );
    assert!((d.advance_rad - PI).abs() < 1e-12);
    let mesh = d.mesh.unwrap();
    assert_eq!(mesh.steps, 180, "90 positions per driver turn over 2 turns");
    let r = |p: &[Point]| p.iter().map(|q| q.hypot()).fold(0.0, f64::max);
    assert!((r(&d.driver_pitch_mm) - 12.0).abs() < 1e-9);
    assert!((r(&d.driven_pitch_mm) - 24.0).abs() < 1e-9);
}

/// The 1:2 law that ncgears 0.3.1 makes 24:48 with centre distance 35.5186 mm. Its
/// DXF and point lists go to `target/test-dxf` for the ezdxf read-back in `.ci/run`.
#[test]
fn one_to_two_law_makes_24_48() {
    let d = check(&motion("0.5*phi + 0.05*sin(2*phi)"), 24, 48, 1.0);
    let dir = crate::teeth::out_dir("test-dxf");
    let sheet = d.assembly_sheet();
    write_dxf(
        &sheet,
        &dir.join("pair_1to2_r2010.dxf"),
        DxfVersion::R2010,
        1e-3,
    )
    .unwrap();
    write_points(&sheet, &dir.join("pair_1to2_points"), "pair_1to2").unwrap();
    assert!(
        (d.center_distance_mm - 35.5186).abs() < 5e-5,
        "{}",
        d.center_distance_mm
    );
    // Ratio range of i = 0.5 + 0.1 cos 2φ.
    assert!((d.ratio_range[0] - 0.4).abs() < 1e-9 && (d.ratio_range[1] - 0.6).abs() < 1e-9);
}

/// 2:3 — a two-lobe driver (i of period π) against a three-lobe driven gear: 24:36, checked over
/// the 3 driver turns of one full cycle.
#[test]
fn two_to_three_law_closes_after_three_driver_turns() {
    let d = check(&motion("2/3*phi + 0.04*sin(2*phi)"), 24, 36, 1.0);
    assert_eq!(d.mesh.unwrap().steps, 270);
}

/// Centrode with a given cycle advance: mean r/(a − r) = Δ/2π. A circle r = 1 at Δ = π closes at
/// a = 3 exactly; a two-lobe centrode at Δ = π meshes 24:48.
#[test]
fn centrode_with_a_cycle_advance_solves_its_centre_distance() {
    let circle = Law::Centrode(Expr::parse("1").unwrap());
    let m = Motion::from_law_advancing(&circle, 256, PI).unwrap();
    assert!(
        (m.unit_center_distance - 3.0).abs() < 1e-12,
        "{}",
        m.unit_center_distance
    );
    assert!((m.psi(1.0) - m.psi(0.0) - 0.5).abs() < 1e-12);
    let law = Law::Centrode(Expr::parse("1 + 0.08*cos(2*phi)").unwrap());
    let opts = PairOptions::new(Some(24), 1.0).with_centrode_advance_rad(PI);
    let d = design_pair(&law, &opts).unwrap();
    assert_eq!((d.z, d.z_driven), (24, 48));
    assert_eq!(d.mesh.unwrap().interference_steps, 0);
}

/// A law that cannot make a closed pair is a typed error naming the cause.
#[test]
fn laws_without_a_closed_pair_are_refused_with_the_reason() {
    let err = |law: &str, z: u32| {
        design_pair(&motion(law), &PairOptions::new(Some(z), 1.0))
            .unwrap_err()
            .to_string()
    };
    // 2:3 with a one-lobe variation: the driven gear would not close.
    let e = err("2/3*phi + 0.04*sin(phi)", 24);
    assert!(
        e.contains("does not close") && e.contains("180.0000°"),
        "{e}"
    );
    // 2:3 needs an even driver count.
    let e = err("2/3*phi + 0.04*sin(2*phi)", 25);
    assert!(e.contains("multiple of 2"), "{e}");
    // An irrational turn ratio.
    let e = err("0.7071067811865476*phi", 24);
    assert!(e.contains("not a fraction"), "{e}");
    // A ratio that does not repeat every driver turn.
    let e = err("phi + 0.01*phi^2", 24);
    assert!(e.contains("must repeat"), "{e}");
    // A law that does not advance.
    let e = err("0.1*sin(phi)", 24);
    assert!(e.contains("must advance"), "{e}");
}

/// The positions of a span: whole turns exclude the end (it is the start again); an interval
/// includes both ends.
#[test]
fn mesh_span_positions() {
    let t = MeshSpan::Turns(2);
    assert!((t.position_rad(90, 180) - TAU).abs() < 1e-15);
    assert!((t.position_rad(179, 180) - 2.0 * TAU * 179.0 / 180.0).abs() < 1e-15);
    let i = MeshSpan::Interval {
        start_rad: 0.5,
        end_rad: 2.5,
    };
    assert_eq!(i.position_rad(0, 5), 0.5);
    assert_eq!(i.position_rad(4, 5), 2.5);
    assert_eq!(i.position_rad(2, 5), 1.5);
}
