//! Integration tests: orbit (spec companion-methods.md part A, table A.10).
use ncgear::analysis::orbit::identify::identify;
use ncgear::analysis::orbit::model::{
    GearSpeeds, Hand, LineKind, PlanetSet, patent_abcd, patent_position_um,
};
use ncgear::analysis::orbit::{C64, Orbit, Whirl, ellipse_group8};
use std::f64::consts::{FRAC_PI_3, PI, TAU};

const ALPHA: f64 = 20.0 * PI / 180.0;

fn set(e: [f64; 3], th: [f64; 3]) -> PlanetSet {
    PlanetSet::equally_spaced(ALPHA, Hand::Ccw, 0.0, 1.0, &e, &th).unwrap()
}

/// Relative closeness.
fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

/// Angles equal modulo `m`.
fn ang(a: f64, b: f64, m: f64) -> f64 {
    let d = (a - b).rem_euclid(m);
    d.min(m - d)
}

// Table A.10 values are printed with 6 decimals: they are checked to their printed precision
// (half a unit of the last digit); closed forms are checked to 1e-9 relative (or better).

#[test]
fn a10_general_case_amplitudes_phases() {
    let s = set([10.0, 6.0, 8.0], [0.0, 0.7, 2.1]).solve();
    let p = s.orbit.sin_pair();
    assert!((p.a_x_um - 4.697099).abs() < 5e-7, "{}", p.a_x_um);
    assert!((p.phi_x_rad - 2.972121).abs() < 5e-7, "{}", p.phi_x_rad);
    assert!((p.a_y_um - 16.445517).abs() < 5e-7, "{}", p.a_y_um);
    assert!((p.phi_y_rad - -0.471436).abs() < 5e-7, "{}", p.phi_y_rad);
}

#[test]
fn a10_general_case_ellipse_and_whirl() {
    let s = set([10.0, 6.0, 8.0], [0.0, 0.7, 2.1]).solve();
    let el = s.orbit.ellipse();
    assert!((el.r_long_um - 17.049996).abs() < 5e-7, "{}", el.r_long_um);
    assert!((el.r_short_um - 1.347374).abs() < 5e-7, "{}", el.r_short_um);
    let al = el.alpha_long_rad.unwrap();
    assert!((al - -1.302862).abs() < 5e-7, "{al}");
    assert!(ang(al.to_degrees(), 105.3515, 180.0) < 5e-5);
    assert!((s.orbit.z_plus_um.norm() - 7.851311).abs() < 5e-7);
    assert!((s.orbit.z_minus_um.norm() - 9.198685).abs() < 5e-7);
    assert_eq!(el.whirl, Whirl::Backward);
    assert_eq!(el.counter_clockwise, Some(false)); // ω_p > 0, backward ⇒ CW
    // Group-8 closed form agrees with the full-spectrum form.
    let (rl, rs, a8) = ellipse_group8(&s.orbit.sin_pair());
    assert!(rel(rl, el.r_long_um) < 1e-12 && rel(rs, el.r_short_um) < 1e-10);
    assert!(ang(a8, al, PI) < 1e-12);
    // Area identity R_L R_S = A_x A_y |sin Δ|.
    let p = s.orbit.sin_pair();
    assert!(
        rel(
            el.r_long_um * el.r_short_um,
            p.a_x_um * p.a_y_um * (p.phi_y_rad - p.phi_x_rad).sin().abs()
        ) < 1e-12
    );
    // The sampled orbit lies on the implicit ellipse, and its max/min radius are R_L/R_S.
    let (mut rmax, mut rmin) = (0.0f64, f64::INFINITY);
    for k in 0..20000 {
        let t = TAU * k as f64 / 20000.0;
        let (x, y) = s.orbit.position_um(t);
        assert!(s.orbit.implicit_residual(x, y).abs() < 1e-12);
        rmax = rmax.max(x.hypot(y));
        rmin = rmin.min(x.hypot(y));
    }
    assert!(rel(rmax, el.r_long_um) < 1e-7 && rel(rmin, el.r_short_um) < 1e-5);
}

#[test]
fn model_matches_closed_form_a3_and_patent_a4() {
    let ps = set([10.0, 6.0, 8.0], [0.0, 0.7, 2.1]);
    let s = ps.solve();
    for k in 0..50 {
        let t = 0.37 * k as f64;
        let (x, y) = s.orbit.position_um(t);
        let (xc, yc) = ps.closed_form_position_um(t);
        let (xp, yp) = patent_position_um(&ps, t).unwrap();
        for (a, b) in [(x, xc), (y, yc), (x, xp), (y, yp)] {
            assert!((a - b).abs() < 1e-12 * 20.0, "{a} vs {b}");
        }
    }
    // Clockwise sun: the closed form holds for h = −1 too.
    let cw = PlanetSet::equally_spaced(
        ALPHA,
        Hand::Cw,
        0.3,
        -2.0,
        &[3.0, 7.0, 5.0],
        &[1.0, -0.4, 2.2],
    )
    .unwrap();
    let so = cw.solve().orbit;
    for k in 0..20 {
        let t = 0.21 * k as f64;
        let (x, y) = so.position_um(t);
        let (xc, yc) = cw.closed_form_position_um(t);
        let (xp, yp) = patent_position_um(&cw, t).unwrap();
        assert!((x - xc).abs() < 1e-12 * 20.0 && (y - yc).abs() < 1e-12 * 20.0);
        assert!((x - xp).abs() < 1e-12 * 20.0 && (y - yp).abs() < 1e-12 * 20.0);
    }
}

#[test]
fn a10_single_planet_is_a_line_along_beta1() {
    let s = set([10.0, 0.0, 0.0], [0.0, 0.0, 0.0]).solve();
    let el = s.orbit.ellipse();
    let expect = 4.0 / 3.0 * 10.0 * ALPHA.cos();
    assert!(rel(el.r_long_um, expect) < 1e-12, "{}", el.r_long_um);
    assert!((el.r_long_um - 12.529235).abs() < 5e-7);
    assert!(el.r_short_um < 1e-12 * expect);
    assert_eq!(el.whirl, Whirl::Line);
    assert!(ang(el.alpha_long_rad.unwrap(), 70f64.to_radians(), PI) < 1e-12);
}

#[test]
fn a10_forward_and_backward_circles() {
    let r = 2.0 * 10.0 * ALPHA.cos();
    assert!((r - 18.793852).abs() < 5e-7);
    let phi = [0.0, 2.0 * FRAC_PI_3, 4.0 * FRAC_PI_3];
    let fwd = set([10.0; 3], [-phi[0], -phi[1], -phi[2]])
        .solve()
        .orbit
        .ellipse();
    assert!(
        rel(fwd.r_long_um, r) < 1e-12 && rel(fwd.r_short_um, r) < 1e-12,
        "{fwd:?}"
    );
    assert_eq!(fwd.whirl, Whirl::Forward);
    assert_eq!(fwd.alpha_long_rad, None);
    let bwd = set([10.0; 3], phi).solve().orbit.ellipse();
    assert!(
        rel(bwd.r_long_um, r) < 1e-12 && rel(bwd.r_short_um, r) < 1e-12,
        "{bwd:?}"
    );
    assert_eq!(bwd.whirl, Whirl::Backward);
    assert_eq!(bwd.alpha_long_rad, None);
}

#[test]
fn a10_common_mode_moves_no_sun() {
    let s = set([10.0; 3], [0.0; 3]).solve();
    let el = s.orbit.ellipse();
    assert!(el.r_long_um < 1e-12 && el.r_short_um < 1e-12, "{el:?}");
    // c(t) = 2·10·cos20°·sin(ω_p t): sine phasor 2e cos α at phase 0.
    let c = s.common_mode_um;
    assert!(
        (c - C64::new(2.0 * 10.0 * ALPHA.cos(), 0.0)).norm() < 1e-12 * 20.0,
        "{c}"
    );
    assert!(s.load_independent);
}

#[test]
fn a10_patent_abcd() {
    let [a, b, c, d] = patent_abcd(&set([1.0; 3], [0.0; 3])).unwrap();
    for (v, e) in [
        (a, -1.326828),
        (b, -1.113341),
        (c, 0.300767),
        (d, -1.705737),
    ] {
        assert!((v - e).abs() < 5e-7, "{v} vs {e}");
    }
    let det = a * d - b * c;
    assert!(rel(det, 3.0 * 3f64.sqrt() / 2.0) < 1e-12, "{det}");
    assert!((det - 2.598076).abs() < 5e-7);
}

#[test]
fn a10_identifiability_pinv_is_e_minus_mean() {
    // Deterministic "random" phasors.
    let e = [C64::new(3.1, -2.0), C64::new(-1.4, 5.5), C64::new(0.7, 0.9)];
    let ps = PlanetSet::equally_spaced(
        ALPHA,
        Hand::Ccw,
        0.0,
        1.0,
        &e.iter().map(|z| z.norm()).collect::<Vec<_>>(),
        &e.iter().map(|z| z.arg()).collect::<Vec<_>>(),
    )
    .unwrap();
    let sol = ps.solve();
    let id = identify(&ps.kinematic_map(), &sol.orbit, None).unwrap();
    let mean: C64 = e.iter().sum::<C64>() / 3.0;
    for (got, want) in id.phasors_um.iter().zip(e.iter()) {
        assert!(
            (got - (want - mean)).norm() < 1e-12 * 10.0,
            "{got} vs {}",
            want - mean
        );
    }
    assert_eq!(id.null_space.len(), 1);
    for v in &id.null_space[0] {
        assert!((v.abs() - 1.0 / 3f64.sqrt()).abs() < 1e-12);
    }
    assert!(id.statement.contains("common-mode component unobservable"));
    // With the transmission-error channel everything is identified.
    let full = identify(&ps.kinematic_map(), &sol.orbit, Some(sol.common_mode_um)).unwrap();
    assert!(full.null_space.is_empty());
    for (got, want) in full.phasors_um.iter().zip(e.iter()) {
        assert!((got - want).norm() < 1e-12 * 10.0);
    }
}

#[test]
fn a9_identify_five_planets() {
    // N = 5 equally spaced: still the common mode is the only unobservable direction (+ the LS model).
    let ps = PlanetSet::equally_spaced(
        ALPHA,
        Hand::Ccw,
        0.0,
        1.0,
        &[4.0, 1.0, 2.0, 6.0, 3.0],
        &[0.1, 0.2, 3.0, -1.0, 2.0],
    )
    .unwrap();
    let s = ps.solve();
    assert!(s.load_independent);
    let id = identify(&ps.kinematic_map(), &s.orbit, Some(s.common_mode_um)).unwrap();
    assert_eq!(id.null_space.len(), 2); // 5 unknowns, 3 equations
    // The identified phasors reproduce the orbit exactly.
    let back = ps.kinematic_map().apply(&id.phasors_um);
    let (px, py) = s.orbit.sin_phasors();
    assert!((back[0] - px).norm() < 1e-10 && (back[1] - py).norm() < 1e-10);
    // Unequal spacing is flagged as load dependent.
    let planets = [0.0f64, 100.0, 250.0]
        .iter()
        .map(|d| ncgear::analysis::orbit::model::Planet {
            position_rad: d.to_radians(),
            eccentricity_um: 5.0,
            phase_rad: 0.3,
        })
        .collect();
    let un = PlanetSet::new(ALPHA, Hand::Ccw, 0.0, 1.0, planets).unwrap();
    assert!(!un.solve().load_independent);
}

#[test]
fn a7_frequencies_example() {
    let g = GearSpeeds::fixed_ring(20, 25, 70, 1.0).unwrap();
    assert!(rel(g.carrier_rad_s, 2.0 / 9.0) < 1e-12);
    assert!(rel(g.planet_rad_s, -0.622222222222222) < 1e-12);
    assert!(rel(g.sun_relative_rad_s, 7.0 / 9.0) < 1e-12);
    assert!(rel(g.sun_relative_rad_s, -(25.0 / 20.0) * g.planet_rad_s) < 1e-12);
    let lines = g.expected_lines(true, 1);
    let zp = lines.iter().find(|l| l.label == "planet Z+").unwrap();
    let zm = lines.iter().find(|l| l.label == "planet Z-").unwrap();
    assert!(rel(zp.omega_rad_s, -0.4) < 1e-12 && zp.kind == LineKind::Planet);
    assert!(rel(zm.omega_rad_s, 0.844444444444444) < 1e-12);
    // zs = zp: the sun runout lands exactly on the Z− line (carrier frame).
    let eq = GearSpeeds::fixed_ring(25, 25, 75, 1.0).unwrap();
    let l = eq.expected_lines(false, 0);
    let zm = l
        .iter()
        .find(|l| l.label == "planet Z-")
        .unwrap()
        .omega_rad_s;
    let ro = l
        .iter()
        .find(|l| l.label == "sun runout")
        .unwrap()
        .omega_rad_s;
    assert!((zm - ro).abs() < 1e-12);
}

#[test]
fn orbit_phasor_round_trip() {
    let o = Orbit {
        omega_p_rad_s: -1.3,
        z_plus_um: C64::new(1.0, 2.0),
        z_minus_um: C64::new(-0.5, 0.25),
    };
    let back = Orbit::from_sin_pair(o.omega_p_rad_s, &o.sin_pair());
    assert!(
        (back.z_plus_um - o.z_plus_um).norm() < 1e-14
            && (back.z_minus_um - o.z_minus_um).norm() < 1e-14
    );
    // ω_p < 0 and forward ⇒ physically clockwise.
    let el = o.ellipse();
    assert_eq!(el.whirl, Whirl::Forward);
    assert_eq!(el.counter_clockwise, Some(false));
    // x(t) from the sine pair equals Re z(t).
    let p = o.sin_pair();
    for k in 0..10 {
        let t = 0.3 * k as f64;
        let (x, y) = o.position_um(t);
        assert!((x - p.a_x_um * (o.omega_p_rad_s * t + p.phi_x_rad).sin()).abs() < 1e-13);
        assert!((y - p.a_y_um * (o.omega_p_rad_s * t + p.phi_y_rad).sin()).abs() < 1e-13);
    }
}

#[test]
fn model_rejects_bad_parameters() {
    let e = PlanetSet::equally_spaced(ALPHA, Hand::Ccw, 0.0, 1.0, &[1.0, -2.0, 1.0], &[0.0; 3])
        .unwrap_err();
    assert!(e.to_string().contains("planet[1].eccentricity_um"), "{e}");
    let e =
        PlanetSet::equally_spaced(ALPHA, Hand::Ccw, 0.0, 1.0, &[1.0, 2.0], &[0.0; 2]).unwrap_err();
    assert!(e.to_string().contains("at least 3"), "{e}");
    let e = PlanetSet::equally_spaced(1.7, Hand::Ccw, 0.0, 1.0, &[1.0; 3], &[0.0; 3]).unwrap_err();
    assert!(e.to_string().contains("pressure_angle"), "{e}");
}
