//! The rotor's loads over a turn: closed forms of a circular train, the balances of power,
//! momentum and angular momentum on designed trains (positions differentiated numerically, not
//! the library's rates), the speed law, the arms, the mirror image, the nominal Hertz stress.
use ncgear::geometry::assembly::{Assembly, Rebuilt};
use ncgear::geometry::fourier::SunRatio;
use ncgear::geometry::golden::g1_mechanism;
use ncgear::geometry::mechanism::Mechanism;
use ncgear::loads::report::GearMass;
use ncgear::loads::{LoadsReport, Rotor, RotorSource, Scene, analyse};
use ncgear::math::Point;
use std::f64::consts::{PI, TAU};

const G: f64 = 9.80665;

fn scene(text: &str) -> ncgear::loads::LoadCase {
    let s: Scene = toml::from_str(text).unwrap();
    s.validate("scene.toml").unwrap()
}

fn loads(asm: &Assembly, text: &str) -> LoadsReport {
    analyse(&Rotor::pitch(asm), &scene(text), "scene.toml").unwrap()
}

/// An arm of 0.5 kg at (30, −80) mm in the planet frame, 1500 kg·mm²; gears 12 mm wide of steel
/// with a 10 mm bore.
const BODIES: &str = "[arm]\nmass_kg = 0.5\ncom_mm = [30.0, -80.0]\ninertia_kg_mm2 = 1500.0\n\
                      [gears]\nface_width_mm = 12.0\ndensity_kg_m3 = 7850.0\nbore_mm = 10.0\n";

fn peak(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// The circular train (i21 ≡ 1: three equal circles of radius a/2): the intermediate turns at
/// twice the carrier speed, the planet does not turn, its arm only translates with A. Without
/// gravity the kinetic energy is constant, so the carrier needs no torque; the planet needs the
/// moment of its first moment's centripetal load, `M = S × a_A = −ω²·(R(θ3)·m·c) × A`, and both
/// meshes carry it at the pitch radius a/2 and the pressure angle: `F_n = |M|/((a/2)·cos α)`.
/// With gravity and one arm, the drive lifts the moving masses: `T = −Σ m·g·dG/dφ`; the frame
/// holds `Σ m·a_G − (Σ m)·g`.
#[test]
fn a_circular_train_has_its_closed_forms() {
    let m = Mechanism {
        a_mm: 45.0,
        l3_mm: 170.0,
        ratio: SunRatio::new(vec![0.0], vec![0.0]).unwrap(),
        sun_phase_rad: 0.3,
        needle_angle_rad: -1.2,
        idler_offset_rad: 0.15,
    };
    let asm = Assembly::from_mechanism(&m, Point::ZERO, 1, 720).unwrap();
    let r = asm.rebuild();
    let op = "[operation]\ncarrier_rpm = 300.0\n";
    let l = loads(&asm, &format!("{op}{BODIES}"));
    let w = 300.0 * TAU / 60.0;
    let theta3 = r.pose(0.0).planet_angle_rad;
    let s = Point::new(30.0, -80.0).rotate(theta3) * (0.5 * 1e-3); // kg·m
    let alpha = 20f64.to_radians();
    for (k, travel) in l.travel_deg.iter().enumerate() {
        let phi = travel.to_radians();
        assert!((r.pose(phi).planet_angle_rad - theta3).abs() < 1e-9);
        let a = Point::from_polar(m.l1_mm() * 1e-3, phi);
        let moment = -w * w * s.cross(a);
        assert!((l.planet_mesh_torque_nm[k] - moment).abs() < 1e-9, "{k}");
        let f = moment.abs() / (0.5 * m.a_mm * 1e-3 * alpha.cos());
        for mesh in [&l.meshes.sun_intermediate, &l.meshes.intermediate_planet] {
            assert!(
                (mesh.normal_force_n[k] - f).abs() < 1e-9 * f.max(1.0),
                "{k}"
            );
        }
        assert!(
            l.carrier_torque_nm[k].abs() < 1e-9,
            "{}",
            l.carrier_torque_nm[k]
        );
    }
    // Gravity along −y, one arm: T = −Σ m g·dG/dφ and the frame force, closed form.
    let l = loads(&asm, &format!("{op}gravity = [0.0, -1.0]\n{BODIES}"));
    let masses = [&l.gears.intermediate, &l.gears.planet].map(|g| g.mass_kg);
    let planet = masses[1] + 0.5;
    let (mi, ms) = (masses[0], l.gears.sun.mass_kg);
    let eps = m.idler_offset_rad;
    for (k, travel) in l.travel_deg.iter().enumerate() {
        let phi = travel.to_radians();
        let g = Point::new(0.0, -G);
        let d_a = Point::from_polar(m.l1_mm() * 1e-3, phi).perp();
        let d_d = Point::from_polar(m.a_mm * 1e-3, phi + eps).perp();
        let t = -(planet * g.dot(d_a) + mi * g.dot(d_d));
        assert!((l.carrier_torque_nm[k] - t).abs() < 1e-9, "{k}");
        let acc = -(Point::from_polar(m.l1_mm(), phi) * planet
            + Point::from_polar(m.a_mm, phi + eps) * mi)
            * (w * w * 1e-3);
        let frame = acc - g * (planet + mi + ms);
        assert!(l.frame_force_n[k].distance(frame) < 1e-9, "{k}");
    }
}

/// The centre of mass (m, world) of a body at `center_mm` turned by `angle` with `com_mm` in its
/// frame.
fn com(center_mm: Point, angle: f64, com_mm: Point) -> Point {
    (center_mm + com_mm.rotate(angle)) * 1e-3
}

/// The moving bodies of train 1 at world carrier angle φ: (mass kg, centre of mass m, angle rad,
/// inertia about the centre of mass kg·m²) of the intermediate and of the planet with its arm,
/// and the tip (m).
fn bodies(
    r: &Rebuilt,
    l: &LoadsReport,
    arm: GearMass,
    phi: f64,
) -> ([(f64, Point, f64, f64); 2], Point) {
    let p = r.pose(phi);
    let about_com = |g: &GearMass| g.inertia_kg_mm2 - g.mass_kg * g.com_mm.norm_squared();
    let gi = &l.gears.intermediate;
    let gp = &l.gears.planet;
    let planet_mass = gp.mass_kg + arm.mass_kg;
    let planet_com = (gp.com_mm * gp.mass_kg + arm.com_mm * arm.mass_kg) / planet_mass;
    let planet_j = about_com(gp)
        + gp.mass_kg * (gp.com_mm - planet_com).norm_squared()
        + arm.inertia_kg_mm2
        + arm.mass_kg * (arm.com_mm - planet_com).norm_squared();
    (
        [
            (
                gi.mass_kg,
                com(
                    p.intermediate_center_mm,
                    p.intermediate_angle_rad,
                    gi.com_mm,
                ),
                p.intermediate_angle_rad,
                about_com(gi) * 1e-6,
            ),
            (
                planet_mass,
                com(p.planet_center_mm, p.planet_angle_rad, planet_com),
                p.planet_angle_rad,
                planet_j * 1e-6,
            ),
        ],
        p.tip_mm * 1e-3,
    )
}

/// On the bundled G1 train at module 2 (its design file, the intermediate axis 13.5° off the
/// carrier line), two arms, gravity, a needle table: at every sample, with the bodies' positions
/// differentiated numerically in time (not the library's rates),
/// - power: `T·ω = dE_kin/dt − Σ m·g·v_G − Σ F_needle·v_B` over both arms;
/// - momentum: the frame force is `Σ m·a_G − (Σ m)·g − Σ F_needle` (the sun's weight too);
/// - angular momentum about O: the sun torque is `dH_O/dt − T − Σ G × m·g − Σ B × F_needle`.
#[test]
fn a_designed_train_balances_power_momentum_and_angular_momentum() {
    let source = RotorSource::read(
        std::path::Path::new("assets/loads/g1_m2_design.json"),
        false,
    )
    .unwrap();
    let r = source.assembly.rebuild();
    assert!(source.assembly.idler_offset_rad.abs() > 0.2);
    let text = format!(
        "[operation]\ncarrier_rpm = 240.0\narms = 2\ngravity = [0.6, -0.8]\n{BODIES}\
         [needle]\nforce_N = [[0, 0, 0], [160, 4, 25], [190, 0, 0]]\n"
    );
    let l = loads(&source.assembly, &text);
    let arm = l.gears.arm.unwrap();
    let w = 240.0 * TAU / 60.0;
    let g = Point::new(0.6, -0.8) * G;
    let n = l.travel_deg.len();
    let h = 1e-4; // rad of travel
    let sun = &l.gears.sun;
    for k in (0..n).step_by(7) {
        let phi = l.travel_deg[k].to_radians();
        let (mut power, mut mom, mut h_dot, mut ext_moment) = (0.0, Point::ZERO, 0.0, 0.0);
        for arm_k in 0..2 {
            let phi_k = phi + PI * f64::from(arm_k);
            let at = |x: f64| bodies(&r, &l, arm, x);
            // Velocity and acceleration by central differences in time (dt = h/ω).
            let vel = |x: f64, i: usize| (at(x + h).0[i].1 - at(x - h).0[i].1) * (w / (2.0 * h));
            let spin = |x: f64, i: usize| (at(x + h).0[i].2 - at(x - h).0[i].2) * (w / (2.0 * h));
            let kinetic = |x: f64| {
                (0..2)
                    .map(|i| {
                        let (m, _, _, j) = at(x).0[i];
                        0.5 * m * vel(x, i).norm_squared() + 0.5 * j * spin(x, i).powi(2)
                    })
                    .sum::<f64>()
            };
            let ang = |x: f64| {
                (0..2)
                    .map(|i| {
                        let (m, c, _, j) = at(x).0[i];
                        m * c.cross(vel(x, i)) + j * spin(x, i)
                    })
                    .sum::<f64>()
            };
            let hh = 1e-3;
            let dk = (kinetic(phi_k + hh) - kinetic(phi_k - hh)) * (w / (2.0 * hh));
            h_dot += (ang(phi_k + hh) - ang(phi_k - hh)) * (w / (2.0 * hh));
            let (b0, tip) = at(phi_k);
            let needle = l.needle_force_n[(k + n / 2 * arm_k as usize) % n];
            let v_tip = (at(phi_k + h).1 - at(phi_k - h).1) * (w / (2.0 * h));
            power += dk
                - (0..2).map(|i| b0[i].0 * g.dot(vel(phi_k, i))).sum::<f64>()
                - needle.dot(v_tip);
            for (i, (mass, c, _, _)) in b0.iter().enumerate() {
                let a = (at(phi_k + hh).0[i].1 - *c * 2.0 + at(phi_k - hh).0[i].1)
                    * (w * w / (hh * hh));
                mom += a * *mass - g * *mass;
                ext_moment += c.cross(g * *mass);
            }
            mom -= needle;
            ext_moment += tip.cross(needle);
        }
        mom -= g * sun.mass_kg;
        ext_moment += (sun.com_mm * (sun.mass_kg * 1e-3)).cross(g);
        let t = l.carrier_torque_nm[k];
        let scale = peak(&l.carrier_torque_nm);
        assert!(
            (t * w - power).abs() < 1e-4 * scale * w,
            "{k}: {t} vs {}",
            power / w
        );
        let f = l.frame_force_n[k];
        let fscale = l
            .frame_force_n
            .iter()
            .fold(0.0, |m: f64, p| m.max(p.norm()));
        assert!(f.distance(mom) < 1e-4 * fscale, "{k}: {f:?} vs {mom:?}");
        let sun_t = h_dot - t - ext_moment;
        assert!(
            (l.sun_torque_nm[k] - sun_t).abs() < 1e-4 * peak(&l.sun_torque_nm),
            "{k}: {} vs {sun_t}",
            l.sun_torque_nm[k]
        );
    }
}

/// Without gravity and needle load every force is an inertia force, ∝ ω²: doubling the speed
/// multiplies the torques and forces by 4, and the drive does no net work over a turn.
#[test]
fn doubling_the_speed_quadruples_the_inertia_loads() {
    let asm = Assembly::from_mechanism(&g1_mechanism(), Point::new(3.0, -2.0), 1, 1440).unwrap();
    let slow = loads(&asm, &format!("[operation]\ncarrier_rpm = 150.0\n{BODIES}"));
    let fast = loads(&asm, &format!("[operation]\ncarrier_rpm = 300.0\n{BODIES}"));
    for k in 0..slow.travel_deg.len() {
        for (a, b) in [
            (slow.carrier_torque_nm[k], fast.carrier_torque_nm[k]),
            (slow.planet_mesh_torque_nm[k], fast.planet_mesh_torque_nm[k]),
            (slow.sun_torque_nm[k], fast.sun_torque_nm[k]),
        ] {
            assert!(
                (4.0 * a - b).abs() <= 1e-12 * b.abs().max(1e-9),
                "{k}: {a} {b}"
            );
        }
        assert!(slow.frame_force_n[k].distance(fast.frame_force_n[k] / 4.0) < 1e-12);
    }
    assert!(slow.summary.mean_power_w.abs() < 1e-9 * slow.summary.carrier_torque_peak_nm);
    assert_eq!(slow.summary.reversals_deg, fast.summary.reversals_deg);
}

/// Train k at travel φ is train 1 at φ + 360°·k/arms: with two arms the carrier torque is the
/// one-arm torque at φ and φ + 180° summed, and the first arm's planet mesh is unchanged.
#[test]
fn two_arms_are_one_arm_twice_half_a_turn_apart() {
    let asm = Assembly::from_mechanism(&g1_mechanism(), Point::ZERO, 1, 1440).unwrap();
    let effects = format!(
        "gravity = [0.0, -1.0]\n{BODIES}[needle]\nforce_N = [[0, 0, 0], [165, 4, 25], [185, 0, 0]]\n"
    );
    let one = loads(
        &asm,
        &format!("[operation]\ncarrier_rpm = 300.0\narms = 1\n{effects}"),
    );
    let two = loads(
        &asm,
        &format!("[operation]\ncarrier_rpm = 300.0\narms = 2\n{effects}"),
    );
    let n = one.travel_deg.len();
    for k in 0..n {
        let sum = one.carrier_torque_nm[k] + one.carrier_torque_nm[(k + n / 2) % n];
        assert!((two.carrier_torque_nm[k] - sum).abs() < 1e-12 * peak(&two.carrier_torque_nm));
        assert_eq!(two.planet_mesh_torque_nm[k], one.planet_mesh_torque_nm[k]);
    }
}

/// A clockwise design is the mirror image of a counter-clockwise one: with gravity, the arm's
/// centre of mass and the needle forces mirrored too, the torques (positive in the sense of
/// travel) are the same at every travel angle, the forces mirrored, the reversals the same.
#[test]
fn a_clockwise_train_is_the_mirror_image() {
    let m = g1_mechanism();
    let ccw = Assembly::from_mechanism(&m, Point::new(5.0, 1.0), 1, 1440).unwrap();
    let cw = Assembly::from_mechanism(&m, Point::new(5.0, 1.0), -1, 1440).unwrap();
    let effects = |s: f64| {
        format!(
            "[operation]\ncarrier_rpm = 280.0\narms = 2\ngravity = [0.6, {}]\n\
             [arm]\nmass_kg = 0.5\ncom_mm = [30.0, {}]\ninertia_kg_mm2 = 1500.0\n\
             [gears]\nface_width_mm = 12.0\n\
             [needle]\nforce_N = [[0, 0, 0], [165, 4, {}], [185, 0, 0]]\n",
            -0.8 * s,
            -80.0 * s,
            25.0 * s
        )
    };
    let a = loads(&ccw, &effects(1.0));
    let b = loads(&cw, &effects(-1.0));
    let mirror = |p: Point| Point::new(p.x, -p.y);
    for k in 0..a.travel_deg.len() {
        assert!((a.carrier_torque_nm[k] - b.carrier_torque_nm[k]).abs() < 1e-9);
        assert!((a.planet_mesh_torque_nm[k] - b.planet_mesh_torque_nm[k]).abs() < 1e-9);
        assert!((a.sun_torque_nm[k] - b.sun_torque_nm[k]).abs() < 1e-9);
        assert!(a.frame_force_n[k].distance(mirror(b.frame_force_n[k])) < 1e-9);
        assert!(a.bearings.a_n[k].distance(mirror(b.bearings.a_n[k])) < 1e-9);
    }
    assert_eq!(a.summary.reversals_deg.len(), b.summary.reversals_deg.len());
    for (x, y) in a.summary.reversals_deg.iter().zip(&b.summary.reversals_deg) {
        assert!((x - y).abs() < 1e-9);
    }
    assert!((a.gears.planet.com_mm.y + b.gears.planet.com_mm.y).abs() < 1e-12);
}

/// A train with concave pitch arcs (the exact concave-sun target designed without the gear
/// limits at module 1: shaper-cut gears, undercut flanks, tip relief) is rated tooth by tooth:
/// the concave contacts as internal pairs (reported), every loaded sample with a finite positive
/// stress, each gear's Y_F·Y_S in the range of real teeth, the contact ratio of the equivalent
/// pairs above 1.
#[test]
fn concave_shaper_cut_gears_are_rated_as_internal_pairs() {
    use ncgear::design::train::{TrainPolicy, TrainTeethOptions, tooth_train};
    use ncgear::design::{DesignOptions, design};
    let t =
        ncgear::Trajectory::from_path(std::path::Path::new("assets/cases/exact_concave_sun.csv"))
            .unwrap();
    let d = design(
        &t,
        &DesignOptions::default()
            .with_limits(false)
            .with_module_mm(Some(1.0)),
    )
    .unwrap();
    let mut opts = TrainTeethOptions::new(1.0).with_policy(TrainPolicy::Designed);
    opts.toothing.verify_steps = 0;
    let train = tooth_train(&d, &opts).unwrap();
    let case = scene(&format!(
        "[operation]\ncarrier_rpm = 300.0\narms = 2\ngravity = [0.0, -1.0]\n{BODIES}\
         [material]\npreset = \"steel\"\n"
    ));
    let l = analyse(&Rotor::toothed(&train), &case, "scene.toml").unwrap();
    let rating = l.rating.as_ref().unwrap();
    assert!(
        rating.notes.iter().any(|n| n.contains("concave flank")),
        "{:?}",
        rating.notes
    );
    for mesh in [&l.meshes.sun_intermediate, &l.meshes.intermediate_planet] {
        let radii = mesh.pitch_radius_of_curvature_mm.iter();
        assert!(radii.clone().any(|r| r[0] < 0.0 || r[1] < 0.0));
        let contact = mesh.contact_stress_mpa.as_ref().unwrap();
        for (k, f) in mesh.normal_force_n.iter().enumerate() {
            if *f > 1.0 {
                assert!(contact[k].is_finite() && contact[k] > 0.0, "{k}");
                for v in mesh.root_stress_mpa.as_ref().unwrap().values() {
                    assert!(v[k].is_finite() && v[k] > 0.0, "{k}");
                }
            }
        }
        assert!(
            mesh.contact_ratio
                .as_ref()
                .unwrap()
                .iter()
                .all(|e| *e > 1.0)
        );
    }
    for (name, g) in &rating.gears {
        let [lo, hi] = g.y_f_y_s_range;
        assert!(lo > 2.0 && hi < 8.0, "{name}: {lo}…{hi}");
    }
}
