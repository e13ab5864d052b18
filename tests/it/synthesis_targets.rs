//! Synthesis from target bands alone (`ncgear::synthesis::targets`): the train whose agronomic
//! indices lie in their bands, with gears a shop can make.
use ncgear::design::DesignOptions;
use ncgear::math::Point;
use ncgear::simulate::{FeatureOptions, Simulation, features};
use ncgear::synthesis::spec::{Machine, Targets};
use ncgear::synthesis::{Spec, Synthesis, synthesize};

fn bands(targets: Targets, machine: Machine) -> Spec {
    Spec {
        machine,
        targets,
        ..Spec::default()
    }
}

/// Every band met on the designed gears, with the gears within the limits and their checks
/// passed; the values reported are those `ncgear simulate` measures on the design (one
/// implementation).
fn assert_met_on_buildable_gears(s: &Synthesis, fopts: &FeatureOptions) {
    let r = &s.report;
    assert_eq!(r.dyad_kind, "targets");
    assert!(r.poses.is_empty());
    for t in &r.targets {
        assert!(t.margin >= 0.0, "{t:?} (binding {:?})", r.binding);
    }
    let d = &s.design.report;
    assert!(d.verdict.passed, "{:?}", d.verdict);
    assert!(d.limits.pressure_angle_deg <= 45.0, "{:?}", d.limits);
    if let Some(rc) = d.limits.tightest_concave_radius_mm {
        assert!(rc >= 10.0, "concave radius {rc} mm");
    }
    assert!(d.roundtrip.max_deviation_mm < 0.05, "{:?}", d.roundtrip);
    let f = features(&Simulation::new(s.design.assembly.clone()), fopts).unwrap();
    for t in &r.targets {
        let v = ncgear::synthesis::targets::index_value(&t.index, &f);
        assert!(
            (v - t.value).abs() < 1e-9,
            "{}: {v} vs {}",
            t.index,
            t.value
        );
    }
    // The tip keeps clear of the sun gear's circle (radius a = l1/2) about the carrier axis.
    let arm = r.candidates[r.chosen].dyad;
    assert!(arm.l3_mm - arm.l1_mm >= 0.5 * arm.l1_mm - 1e-6, "{arm:?}");
}

/// The published rice figures (taking 5.18°, pushing 71.56°, height 289.76 mm, hole width
/// ≤ 22.43 mm; examples, not standards), ±1° and ±5 mm: met, with convex-or-cuttable gears.
#[test]
fn published_rice_figures_are_met_with_buildable_gears() {
    let machine = Machine {
        rpm: Some(300.0),
        spacing_mm: Some(140.0),
        ..Machine::default()
    };
    let spec = bands(
        Targets {
            take_angle_deg: Some([4.18, 6.18]),
            push_angle_deg: Some([70.56, 72.56]),
            height_mm: Some([284.76, 294.76]),
            hole_width_mm: Some([0.0, 22.43]),
            ..Targets::default()
        },
        machine,
    );
    let s = synthesize(&spec, &DesignOptions::default()).unwrap();
    let fopts = FeatureOptions::default()
        .with_forward_mm_s(FeatureOptions::forward_for_spacing(140.0, 300.0));
    assert_met_on_buildable_gears(&s, &fopts);
    assert_eq!(s.report.targets.len(), 4);
}

/// Bands about G1's own indices (taking 76.82°, pushing 43.65° below the horizontal, height
/// 122.67 mm: docs/math/chain.md §11.1), a clockwise carrier about another axis: met, and the
/// design turns the way and about the axis asked for.
#[test]
fn bands_of_a_known_train_are_met_clockwise_about_another_axis() {
    let machine = Machine {
        center_mm: Some(Point::new(120.0, 350.0)),
        carrier: Some("cw".into()),
        ..Machine::default()
    };
    let spec = bands(
        Targets {
            take_angle_deg: Some([75.8, 77.8]),
            push_angle_deg: Some([42.6, 44.6]),
            height_mm: Some([120.0, 125.0]),
            arm_clearance_mm: Some([5.0, 1e9]),
            ..Targets::default()
        },
        machine,
    );
    let s = synthesize(&spec, &DesignOptions::default()).unwrap();
    assert_met_on_buildable_gears(&s, &FeatureOptions::default());
    assert_eq!(s.report.carrier, "cw");
    assert_eq!(s.design.assembly.direction, -1);
    assert_eq!(s.design.assembly.center_mm, Point::new(120.0, 350.0));
}

/// A band out of reach is reported with the index and its shortfall, the search box's edge named
/// as what binds; the same spec with a box that allows the height meets it.
#[test]
fn an_unreachable_band_names_the_index_and_the_box() {
    let target = Targets {
        height_mm: Some([1200.0, 1250.0]),
        ..Targets::default()
    };
    let s = synthesize(
        &bands(target.clone(), Machine::default()),
        &DesignOptions::default(),
    )
    .unwrap();
    let t = &s.report.targets[0];
    assert_eq!(t.index, "height_mm");
    assert!(t.margin < -100.0 && t.value < 1000.0, "{t:?}");
    assert!(
        s.report
            .binding
            .iter()
            .any(|b| b.starts_with("search box") && b.contains("machine.l3_mm")),
        "{:?}",
        s.report.binding
    );
    let wider = Machine {
        l1_mm: Some([100.0, 400.0]),
        l3_mm: Some([200.0, 800.0]),
        ..Machine::default()
    };
    let s = synthesize(&bands(target, wider), &DesignOptions::default()).unwrap();
    assert_met_on_buildable_gears(&s, &FeatureOptions::default());
}

/// Bands that contradict each other, or lie outside what the index can take, are refused by
/// name before any search; a search box given with poses is refused (it would do nothing).
#[test]
fn contradicting_bands_are_refused_by_name() {
    let t0 = std::time::Instant::now();
    let spec = bands(
        Targets {
            take_angle_deg: Some([0.0, 10.0]),
            push_angle_deg: Some([60.0, 70.0]),
            angle_difference_deg: Some([80.0, 90.0]),
            ..Targets::default()
        },
        Machine::default(),
    );
    let e = synthesize(&spec, &DesignOptions::default()).unwrap_err();
    assert!(
        e.to_string().contains("targets.angle_difference_deg")
            && e.to_string().contains("[50, 70]"),
        "{e}"
    );
    for (t, name) in [
        (
            Targets {
                push_angle_deg: Some([95.0, 120.0]),
                ..Targets::default()
            },
            "targets.push_angle_deg",
        ),
        (
            Targets {
                hole_width_mm: Some([-5.0, -1.0]),
                ..Targets::default()
            },
            "targets.hole_width_mm",
        ),
    ] {
        let e = synthesize(&bands(t, Machine::default()), &DesignOptions::default()).unwrap_err();
        assert!(e.to_string().contains(name), "{e}");
    }
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets/synthesis/g1_five_poses.toml");
    let mut spec: Spec = ncgear::config::load(&path).unwrap();
    spec.machine.l1_mm = Some([50.0, 100.0]);
    let e = synthesize(&spec, &DesignOptions::default()).unwrap_err();
    assert!(e.to_string().contains("machine.l1_mm"), "{e}");
    assert!(t0.elapsed().as_secs_f64() < 1.0);
}

/// The taking and pushing angles are the needle's angle to the horizontal: G1's needle points
/// 76.824° below the horizontal at the top of its path (down and to the left, world −103.176°) and
/// 43.647° at the bottom (down and to the right), the spec's static facts; the search's two-arm
/// turn of a train gives G1's height and its arm clearance 2·l1 − l3 = 10 mm.
#[test]
fn g1_taking_and_pushing_angles_are_to_the_horizontal() {
    use ncgear::simulate::features_of_turn;
    use ncgear::synthesis::targets::turn_of;
    let n = 36_000;
    let turn = turn_of(&ncgear::geometry::golden::g1_mechanism(), Point::ZERO, 1, n);
    let f = features_of_turn(&turn, Point::ZERO, 1, &FeatureOptions::default()).unwrap();
    assert!(
        (f.take_angle_deg - 76.824).abs() < 0.01,
        "{}",
        f.take_angle_deg
    );
    assert!(
        (f.push_angle_deg - 43.647).abs() < 0.01,
        "{}",
        f.push_angle_deg
    );
    assert!(
        (f.needle_angle_take_deg + 103.176).abs() < 0.01,
        "{}",
        f.needle_angle_take_deg
    );
    assert!(
        (f.needle_angle_plant_deg + 43.647).abs() < 0.01,
        "{}",
        f.needle_angle_plant_deg
    );
    assert!((f.height_mm - 122.666).abs() < 0.001, "{}", f.height_mm);
    assert!(
        (f.min_arm_clearance_mm - 10.0).abs() < 1e-3,
        "{}",
        f.min_arm_clearance_mm
    );
}
