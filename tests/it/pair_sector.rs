//! Open (incomplete) sector pairs: teeth over a driver interval only, clean
//! sector ends, the verification over the interval.
use ncgear::cad::dxf::{DxfVersion, write_dxf};
use ncgear::cad::points::write_points;
use ncgear::pair::{Expr, Law, PairDesign, PairOptions, design_pair};
use ncgear::teeth::overlap::first_self_intersection;
use std::f64::consts::PI;

fn open(law: &str, z: u32, m: f64, deg: [f64; 2]) -> Result<PairDesign, ncgear::pair::PairError> {
    let o = PairOptions::new(Some(z), m)
        .with_open_sector_rad(Some([deg[0].to_radians(), deg[1].to_radians()]));
    design_pair(&Law::Motion(Expr::parse(law).unwrap()), &o)
}

/// What every sector pair must satisfy: simple outlines, no interference over the active
/// interval, transmission error far below a tooth's play, backlash present, and every outline
/// vertex either on a kept tooth (above the hub) or on the hub circle / its two radial cuts.
fn check(d: &PairDesign) {
    let s = d.sector.clone().unwrap();
    for (o, hub) in [
        (&d.driver, s.hub_radius_mm[0]),
        (&d.driven, s.hub_radius_mm[1]),
    ] {
        assert_eq!(first_self_intersection(&o.points_mm).unwrap(), None);
        let on_hub = o
            .points_mm
            .iter()
            .filter(|p| (p.hypot() - hub).abs() < 1e-9)
            .count();
        assert!(on_hub > 10, "hub circle present");
        assert!(
            o.points_mm.iter().all(|p| p.hypot() >= hub - 1e-9),
            "nothing inside the hub"
        );
    }
    let mesh = d.mesh.clone().unwrap();
    assert_eq!(mesh.interference_steps, 0, "{mesh:?}");
    assert!(mesh.max_overlap_area_mm2 <= 1e-9, "{mesh:?}");
    assert!(mesh.min_backlash_mm > 0.0, "{mesh:?}");
    assert!(mesh.max_transmission_error_deg <= 1e-5, "{mesh:?}");
}

/// Closed form: `φ − 0.08 sin 2φ` repeats every 180°, so its half-turn sector with 12 teeth
/// has exactly half the perimeter of the closed 24-tooth pair: the same centre distance, and
/// 12 pitches on the active arc.
#[test]
fn half_turn_sector_of_a_period_pi_law_matches_the_closed_pair() {
    let law = "phi - 0.08*sin(2*phi)";
    let d = open(law, 12, 1.5, [0.0, 180.0]).unwrap();
    check(&d);
    let closed = design_pair(
        &Law::Motion(Expr::parse(law).unwrap()),
        &PairOptions::new(Some(24), 1.5),
    )
    .unwrap();
    assert!(
        (d.center_distance_mm - closed.center_distance_mm).abs() < 1e-9 * closed.center_distance_mm,
        "{} vs {}",
        d.center_distance_mm,
        closed.center_distance_mm
    );
    let s = d.sector.unwrap();
    assert!((s.active_teeth - 12.0).abs() < 1e-6, "{}", s.active_teeth);
    assert!((s.driven_advance_deg - 180.0).abs() < 1e-9);
    // 12 active teeth and 2 padding teeth beyond each end (± the tooth cut at a space).
    assert!((15..=17).contains(&s.kept_teeth[0]), "{:?}", s.kept_teeth);
    assert!((15..=17).contains(&s.kept_teeth[1]), "{:?}", s.kept_teeth);
}

/// An asymmetric sector of an unequal-ratio law: 0 interference over its interval. Its DXF
/// (R2010 and R12) and point lists go to `target/test-dxf` for the ezdxf read-back in `.ci/run`
/// (outlines closed, pitch arcs open).
#[test]
fn asymmetric_sector_meshes_over_its_interval() {
    let d = open("0.6*phi + 0.05*sin(phi)", 10, 1.0, [30.0, 200.0]).unwrap();
    check(&d);
    let dir = crate::teeth::out_dir("test-dxf");
    let sheet = d.assembly_sheet();
    for (name, v) in [
        ("pair_sector_r2010.dxf", DxfVersion::R2010),
        ("pair_sector_r12.dxf", DxfVersion::R12),
    ] {
        write_dxf(&sheet, &dir.join(name), v, 1e-3).unwrap();
    }
    write_points(&sheet, &dir.join("pair_sector_points"), "pair_sector").unwrap();
    let s = d.sector.unwrap();
    assert!((s.active_teeth - 10.0).abs() < 0.5, "{}", s.active_teeth);
    let want =
        0.6 * 170.0 + (0.05 * (200f64.to_radians().sin() - 30f64.to_radians().sin())).to_degrees();
    assert!((s.driven_advance_deg - want).abs() < 1e-9);
    // The mesh check covers the active interval: positions every ≤ 4° and both ends.
    assert!(d.mesh.unwrap().steps > (170.0 / 4.0) as usize);
}

/// Sectors that cannot be made are typed errors naming the cause.
#[test]
fn impossible_sectors_are_refused_with_the_reason() {
    let e = open("phi", 20, 1.0, [0.0, 350.0]).unwrap_err().to_string();
    assert!(e.contains("spans") && e.contains("315"), "{e}");
    let e = open("phi", 20, 1.0, [10.0, 10.0]).unwrap_err().to_string();
    assert!(e.contains("end > start"), "{e}");
    let o = PairOptions::new(Some(12), 1.0).with_open_sector_rad(Some([0.0, PI]));
    let e = design_pair(&Law::Centrode(Expr::parse("1").unwrap()), &o)
        .unwrap_err()
        .to_string();
    assert!(e.contains("motion law"), "{e}");
}
