//! Re-designing from an earlier design (`ncgear::design::redesign`): the edit loop of `ncgear serve`.
use ncgear::design::redesign;
use ncgear::geometry::golden::g1_mechanism;
use ncgear::math::Point;
use ncgear::{DesignOptions, Trajectory, design};

fn g1_points() -> Vec<Point> {
    let g1 = g1_mechanism();
    (0..360)
        .map(|k| g1.tip(f64::from(k).to_radians()))
        .collect()
}

/// `points` with a Gaussian bump of `amp` mm around point `at` (about 10 points wide).
fn bumped(points: &[Point], at: f64, amp: f64) -> Vec<Point> {
    points
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let w = amp * (-((k as f64 - at) / 10.0).powi(2)).exp();
            Point::new(p.x + 0.8 * w, p.y + 0.6 * w)
        })
        .collect()
}

/// An exact target needs no fit: the warm start changes nothing, the design is the cold one.
#[test]
fn an_exact_target_redesigns_exactly_as_the_cold_chain() {
    let t = Trajectory::from_points(g1_points()).unwrap();
    let opts = DesignOptions::default();
    let cold = design(&t, &opts).unwrap();
    let warm = redesign(&t, &opts, &cold.report).unwrap();
    assert_eq!(warm.report.l1_mm, cold.report.l1_mm);
    assert_eq!(
        warm.report.roundtrip.max_deviation_mm,
        cold.report.roundtrip.max_deviation_mm
    );
    assert!(warm.report.roundtrip.max_deviation_mm < 0.01);
}

/// Edits of 0.2 to 2 mm: the warm design stays within the gear limits, traces the edited target
/// no worse than 10 % + 0.05 mm beyond the full search's design, and its fit starts from the
/// design before the edit (the warm path ran: one order, no restarts).
#[test]
fn an_edit_redesigns_from_the_design_before_it_close_to_the_full_search() {
    let opts = DesignOptions::default();
    let before = design(&Trajectory::from_points(g1_points()).unwrap(), &opts).unwrap();
    for (at, amp) in [(90.0, 0.2), (200.0, -0.7), (300.0, 2.0)] {
        let t = Trajectory::from_points(bumped(&g1_points(), at, amp)).unwrap();
        let warm = redesign(&t, &opts, &before.report).unwrap();
        let cold = design(&t, &opts).unwrap();
        let (w, c) = (
            warm.report.roundtrip.max_deviation_mm,
            cold.report.roundtrip.max_deviation_mm,
        );
        assert!(
            w <= 1.1 * c + 0.05,
            "bump {amp} mm at {at}: warm {w} mm, full search {c} mm"
        );
        let l = &warm.report.limits;
        assert!(
            l.pressure_angle_deg <= l.max_pressure_angle_deg + 1e-9,
            "{l:?}"
        );
        let fit = warm
            .report
            .fit
            .as_ref()
            .expect("the edited target is fitted");
        assert_eq!(fit.order_scan.len(), 1, "one order: {:?}", fit.order_scan);
        assert_eq!(fit.order, before.report.fourier.order);
    }
}

/// A start of the other carrier sense is not used: the result is the cold design's.
#[test]
fn a_start_of_the_other_sense_is_ignored() {
    let opts = DesignOptions::default();
    let t = Trajectory::from_points(bumped(&g1_points(), 90.0, 1.0)).unwrap();
    let mut start = design(&t, &opts).unwrap().report;
    start.carrier.direction = -start.carrier.direction;
    let warm = redesign(&t, &opts, &start).unwrap();
    let cold = design(&t, &opts).unwrap();
    assert_eq!(warm.report.l1_mm, cold.report.l1_mm);
    assert_eq!(warm.report.l3_mm, cold.report.l3_mm);
}

/// Designing for a module from a start made for the same module: the tooth count is kept and
/// the perimeter is exactly zπm.
#[test]
fn a_start_for_the_same_module_keeps_its_tooth_count() {
    let opts = DesignOptions::default().with_module_mm(Some(2.0));
    let before = design(&Trajectory::from_points(g1_points()).unwrap(), &opts).unwrap();
    let z = before.report.module.as_ref().unwrap().teeth;
    let t = Trajectory::from_points(bumped(&g1_points(), 120.0, 1.5)).unwrap();
    let warm = redesign(&t, &opts, &before.report).unwrap();
    let m = warm.report.module.as_ref().unwrap();
    assert_eq!(m.teeth, z);
    assert_eq!(m.candidates.len(), 1);
    let perimeter = warm.assembly.sun.perimeter_mm(1e-9);
    assert!(
        (perimeter - f64::from(z) * std::f64::consts::PI * 2.0).abs() < 1e-3,
        "perimeter {perimeter} mm for z = {z}"
    );
}
