//! The rotor on a compliant drive (docs/dynamics.md, "The drive"): the carrier a degree of
//! freedom on a torsional shaft from a motor at constant speed, every arm integrated together.
//! Closed form on a circular train, the stiff-shaft limit against the carrier at exactly Ω, the
//! energy balance with the motor's work.

use super::rotor_dynamics::{assert_turn_balances, circle_train, g1_scene, mesh_peak, run};
use ncgear::analysis::dynamics::rotor::{Drive, Effects, build};
use ncgear::loads::{Rotor, Scene};

/// The shaft's torsional frequency on a train of three equal circles (i ≡ 1), constant stiff
/// meshes: the intermediate turns at twice the carrier's speed and the planet (with its arm)
/// does not turn — it translates — so the arms' inertia on the carrier is
/// `n·(m_D·|OD|² + 4·J_D + m_A·|OA|²)` with `|OD| = 2r`, `|OA| = 4r`, and
/// `f = √(k_s/(J_c + that))/2π`, within 1e-6.
#[test]
fn the_circular_train_on_its_shaft_has_the_closed_form_frequency() {
    let r_mm = 25.0;
    let asm = circle_train(r_mm);
    let scene: Scene = toml::from_str(
        "[operation]\ncarrier_rpm = 200.0\narms = 2\n[gears]\nface_width_mm = 20.0\n\
         [arm]\nmass_kg = 0.4\ncom_mm = [30.0, -60.0]\ninertia_kg_mm2 = 3000.0",
    )
    .unwrap();
    let case = scene.validate("circle.toml").unwrap();
    let drive = Drive {
        stiffness_nm_per_rad: 1.0e4,
        damping_nms_per_rad: 0.0,
        carrier_inertia_kg_m2: 0.01,
    };
    let effects = Effects::constant([3.0e8, 2.0e8]).with_drive(Some(drive));
    let rotor = Rotor::pitch(&asm).with_pressure_angle_rad(20f64.to_radians());
    let built = build(&rotor, &case, &effects, None, "circle.toml").unwrap();
    let m = &built.model;
    let [jd, _] = m.inertias_kg_m2();
    let [md, ma] = m.masses_kg();
    let r = r_mm * 1e-3;
    let arms = 2.0 * (md * (2.0 * r).powi(2) + 4.0 * jd + ma * (4.0 * r).powi(2));
    let closed = (1.0e4 / (0.01 + arms)).sqrt() / std::f64::consts::TAU;
    let f = m.drive_frequency_hz().unwrap();
    assert!((f / closed - 1.0).abs() < 1e-6, "{f} Hz vs {closed} Hz");
}

/// The effects of the stiff-shaft comparison, with `drive` (a TOML line or empty), at rtol
/// 1e-10: at 1e-9 the periodic residual of the stiff shaft floors near 2–4e-7, above the
/// scenes' `poincare_tol` of 1e-7, since the planting profile's pulses became 602 rows a turn
/// and arm (2026-12-02; it settles in 2 turns at 1e-10).
fn smooth(drive: &str) -> String {
    format!(
        "mesh_stiffness = {{ kind = \"iso\", pairs = \"mean\" }}\nmesh_damping = {{ zeta = 0.05 }}\n\
         vibration_damping = {{ zeta = 0.05 }}\n{drive}\n[solver]\nrtol = 1e-10\natol = 1e-14"
    )
}

/// Stiff shaft: at 1e8 N·m/rad (≈ 9 kHz on the carrier) the G1 rotor on its shaft moves as with
/// the carrier at exactly Ω: each mesh's dynamic force within 0.2 % of its peak at every sample,
/// the tip within 1 µm, the carrier speed within 1e-5 of Ω, and the shaft carries the carrier
/// torque (within 0.5 % of its peak).
#[test]
fn a_stiff_shaft_is_the_carrier_at_exactly_its_speed() {
    let (_, free) = run(&g1_scene("drive_none", &smooth(""), 8));
    let (_, stiff) = run(&g1_scene(
        "drive_stiff",
        &smooth(
            "drive = { stiffness_nm_per_rad = 1e8, damping_nms_per_rad = 170.0, \
             carrier_inertia_kg_mm2 = 20000.0 }",
        ),
        8,
    ));
    let (a, b) = (&free.report, &stiff.report);
    assert!(
        a.steady.settled && b.steady.settled,
        "{:?} {:?}",
        a.steady,
        b.steady
    );
    assert!(a.drive.is_none());
    for (x, y) in [
        (&a.meshes.sun_intermediate, &b.meshes.sun_intermediate),
        (&a.meshes.intermediate_planet, &b.meshes.intermediate_planet),
    ] {
        let peak = mesh_peak(&x.dynamic_force_n);
        let worst = x
            .dynamic_force_n
            .iter()
            .zip(&y.dynamic_force_n)
            .fold(0.0_f64, |m, (p, q)| m.max((p - q).abs()));
        assert!(worst < 2e-3 * peak, "{worst} N of {peak} N");
    }
    let tip = a
        .tip_mm
        .iter()
        .zip(&b.tip_mm)
        .fold(0.0_f64, |m, (p, q)| m.max(p.distance(*q)));
    assert!(tip < 1e-3, "tip {tip} mm");
    let d = b.drive.as_ref().expect("the drive's report");
    assert!(d.speed_fluctuation < 1e-5, "{}", d.speed_fluctuation);
    let peak = mesh_peak(&b.carrier_torque_nm);
    for (s, t) in d.shaft_torque_nm.iter().zip(&b.carrier_torque_nm) {
        assert!((s - t).abs() < 5e-3 * peak, "shaft {s} vs carrier {t} N·m");
    }
}

/// A soft shaft (5000 N·m/rad, ≈ 60 Hz) under the knock (the teeth's backlash): the carrier's
/// speed fluctuates, and over the settled turn the motor's work equals the dissipation
/// (meshes, impacts, vibration dampers, the shaft's damper) plus the needle's and gravity's work
/// and the energy's change (the carrier's and the shaft's included) within 1e-4 of the motor's
/// largest power × the period.
#[test]
fn a_soft_shaft_balances_its_energy() {
    let path = g1_scene(
        "drive_soft",
        "mesh_stiffness = { kind = \"iso\" }\nmesh_damping = { zeta = 0.05 }\nbacklash = \"teeth\"\n\
         vibration_damping = { zeta = 0.05 }\ndrive = { stiffness_nm_per_rad = 5000.0, \
         damping_nms_per_rad = 2.0, carrier_inertia_kg_mm2 = 20000.0 }\n\
         [solver]\nrtol = 1e-10\natol = 1e-14",
        10,
    );
    let (p, r) = run(&path);
    let rep = &r.report;
    assert!(rep.steady.settled, "{:?}", rep.steady);
    assert!(rep.summary.impacts_per_turn > 0);
    let d = rep.drive.as_ref().unwrap();
    assert!(d.speed_fluctuation > 1e-4, "{}", d.speed_fluctuation);
    assert_turn_balances(&p, &r);
}
