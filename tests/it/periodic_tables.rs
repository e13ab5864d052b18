//! Periodic tables written with both ends: a last row at the first's abscissa + 360° that is the
//! first row again (the needle force of a loads scene: the same force; a pair's law table: ψ one
//! turn on) is the same point and is dropped, so the table reads as without it; one that is not
//! the first row is refused naming both rows.
use ncgear::geometry::assembly::Assembly;
use ncgear::geometry::golden::g1_mechanism;
use ncgear::loads::{LoadsError, Rotor, Scene, analyse};
use ncgear::math::Point;
use ncgear::pair::{Law, PairError};

const OP: &str = "[operation]\ncarrier_rpm = 300.0\narms = 2\n[arm]\nmass_kg = 0.5\n\
                  com_mm = [30.0, -80.0]\ninertia_kg_mm2 = 1500.0\n";

fn scene(force: &str) -> Result<ncgear::loads::LoadCase, LoadsError> {
    let s: Scene = toml::from_str(&format!("{OP}[needle]\nforce_N = {force}\n")).unwrap();
    s.validate("scene.toml")
}

#[test]
fn a_needle_force_table_with_its_360_degree_row_reads_as_without_it() {
    let asm = Assembly::from_mechanism(&g1_mechanism(), Point::ZERO, 1, 720).unwrap();
    let open = "[[0, 4.5, -2], [165, 4, 25], [185, 0, 0]]";
    let both = "[[0, 4.5, -2], [165, 4, 25], [185, 0, 0], [360, 4.5, -2]]";
    let (a, b) = (scene(open).unwrap(), scene(both).unwrap());
    let ra = analyse(&Rotor::pitch(&asm), &a, "scene.toml").unwrap();
    let rb = analyse(&Rotor::pitch(&asm), &b, "scene.toml").unwrap();
    // The same table: the same loads, to the bit.
    assert_eq!(ra.carrier_torque_nm, rb.carrier_torque_nm);
    assert_eq!(ra.planet_mesh_torque_nm, rb.planet_mesh_torque_nm);
    assert!(ra.carrier_torque_nm.iter().any(|t| t.abs() > 1e-6));
    // A 360° row with another force is a contradiction: both rows named, with their values.
    let e = scene("[[0, 4.5, -2], [165, 4, 25], [185, 0, 0], [360, 4.5, -2.5]]").unwrap_err();
    let m = e.to_string();
    assert!(
        m.contains("scene.toml") && m.contains("needle.force_N[3]"),
        "{m}"
    );
    assert!(
        m.contains("[360, 4.5, -2.5]")
            && m.contains("needle.force_N[0] = [0, 4.5, -2]")
            && m.contains("make it [360, 4.5, -2]"),
        "{m}"
    );
    // Past the turn is still refused as a span, not taken as a closing row.
    let e = scene("[[0, 4.5, -2], [365, 4.5, -2]]").unwrap_err();
    assert!(e.to_string().contains("span 365.000°"), "{e}");
}

#[test]
fn a_law_table_with_its_closing_row_reads_as_without_it() {
    // ψ = φ + 10·sin φ (degrees), every 30°, with and without φ = 360°.
    let row = |phi: f64| format!("{phi},{}\n", phi + 10.0 * phi.to_radians().sin());
    let rows: String = (0..12).map(|k| row(30.0 * f64::from(k))).collect();
    let open = format!("phi_deg,psi_deg\n{rows}");
    let both = format!("{open}\n{}", row(360.0));
    let (Law::Table(a), Law::Table(b)) = (
        Law::parse_csv(&open, "law.csv").unwrap(),
        Law::parse_csv(&both, "law.csv").unwrap(),
    ) else {
        panic!("tables")
    };
    assert_eq!(a.len(), 12);
    assert_eq!(a, b);
    // ψ at 360° not one turn on from ψ at 0°: named by both lines (the blank line counts).
    let bad = format!("{open}\n360,361\n");
    match Law::parse_csv(&bad, "law.csv").unwrap_err() {
        e @ PairError::Csv { line, .. } => {
            assert_eq!(line, 15, "{e}");
            let m = e.to_string();
            assert!(
                m.contains("law.csv")
                    && m.contains("[360, 361]")
                    && m.contains("line 2's [0, 0]")
                    && m.contains("make it [360, 360]"),
                "{m}"
            );
        }
        other => panic!("{other:?}"),
    }
}
