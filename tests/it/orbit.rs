//! Integration tests: orbit (docs/math/companion.md §A, §A.10).
use ncgear::analysis::orbit::identify::identify;
use ncgear::analysis::orbit::model::{
    GearSpeeds, Hand, LineKind, PlanetSet, patent_abcd, patent_position_um,
};
use ncgear::analysis::orbit::{C64, Orbit, Whirl, ellipse_group8};
use ncgear::progress::Progress;
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

// docs/math/companion.md §A.10 values are printed with 6 decimals: they are checked to their printed precision
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
    // Group-8 closed form (docs/math/companion.md §A.6 eq. A-7) agrees with the full-spectrum form (docs/math/companion.md §A.6 eq. A-8).
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
    // The sampled orbit lies on the implicit ellipse (docs/math/companion.md §A.6 eq. A-6), and its max/min radius are R_L/R_S.
    let (mut rmax, mut rmin) = (0.0f64, f64::INFINITY);
    for k in 0..20000 {
        let t = TAU * k as f64 / 20000.0;
        let (x, y) = s.orbit.position_um(t);
        assert!(s.orbit.implicit_residual(x, y).unwrap().abs() < 1e-12);
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

// ---------------------------------------------------------------------------------------------
// Measurement (docs/math/companion.md §A.7–§A.8) on synthetic records.

use ncgear::analysis::orbit::OrbitError;
use ncgear::analysis::orbit::measure::{
    Comparison, ExtractOptions, Extractor, Frame, Method, Record, full_spectrum,
};
use ncgear::analysis::orbit::model::Line;
use rand::SeedableRng;
use rand::rngs::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

/// A synthetic record description (carrier frame unless `carrier_rad_s` ≠ 0).
struct Synth {
    orbit: Orbit,
    periods: f64,
    samples: usize,
    sigma_um: f64,
    /// Extra circular lines `Z e^{iωt}` in the analysis frame: (signed ω rad/s, Z µm).
    lines: Vec<(f64, C64)>,
    dc_um: (f64, f64),
    drift_um_s: (f64, f64),
    carrier_rad_s: f64,
    jitter: f64,
    t0_s: f64,
    seed: u64,
}

impl Synth {
    fn base(seed: u64) -> Self {
        let o = set([10.0, 6.0, 8.0], [0.0, 0.7, 2.1]).solve().orbit;
        let orbit = Orbit {
            omega_p_rad_s: TAU * 3.37,
            ..o
        };
        Self {
            orbit,
            periods: 26.185,
            samples: 15540,
            sigma_um: 2.0,
            lines: vec![
                (TAU * 4.91, C64::new(3.0, 4.0)),         // sun runout (5 µm)
                (TAU * 3.37 * 12.0, C64::new(2.0, 0.0)),  // mesh line
                (-TAU * 3.37 * 12.0, C64::new(0.0, 1.5)), // mesh line, backward
            ],
            dc_um: (30.0, -12.0),
            drift_um_s: (4.0, -2.5),
            carrier_rad_s: 0.0,
            jitter: 0.0,
            t0_s: 0.0,
            seed,
        }
    }

    fn duration(&self) -> f64 {
        self.periods * TAU / self.orbit.omega_p_rad_s.abs()
    }

    fn nuisance(&self) -> Vec<Line> {
        self.lines
            .iter()
            .map(|(w, _)| Line::new(format!("{w:.3}"), *w, LineKind::Nuisance))
            .collect()
    }

    fn record(&self) -> Record {
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        let noise = Normal::new(0.0, self.sigma_um).unwrap();
        let dt = self.duration() / self.samples as f64;
        let (mut t, mut x, mut y, mut c) = (vec![], vec![], vec![], vec![]);
        for k in 0..self.samples {
            let u: f64 = Normal::new(0.0, 1.0).unwrap().sample(&mut rng);
            let tk = self.t0_s + dt * (k as f64 + self.jitter * u.clamp(-0.45, 0.45));
            let (ox, oy) = self.orbit.position_um(tk);
            let mut z = C64::new(ox, oy);
            for (w, a) in &self.lines {
                z += a * C64::from_polar(1.0, w * tk);
            }
            let th = self.carrier_rad_s * tk;
            z *= C64::from_polar(1.0, th); // housing frame when ω_c ≠ 0
            t.push(tk);
            x.push(z.re + self.dc_um.0 + self.drift_um_s.0 * tk + noise.sample(&mut rng));
            y.push(z.im + self.dc_um.1 + self.drift_um_s.1 * tk + noise.sample(&mut rng));
            c.push(th);
        }
        let carrier = (self.carrier_rad_s != 0.0).then_some(c);
        Record::new(t, x, y, carrier).unwrap()
    }

    /// CRLB (docs/math/companion.md §A.8 step 5): std(A) ≈ σ√(2/N), std(φ) ≈ σ√(2/N)/A.
    fn crlb_amp(&self) -> f64 {
        self.sigma_um * (2.0 / self.samples as f64).sqrt()
    }
}

/// Errors of A_x, φ_x, A_y, φ_y.
fn errors(got: &Orbit, want: &Orbit) -> [f64; 4] {
    let (g, w) = (got.sin_pair(), want.sin_pair());
    [
        g.a_x_um - w.a_x_um,
        ncgear_wrap(g.phi_x_rad - w.phi_x_rad),
        g.a_y_um - w.a_y_um,
        ncgear_wrap(g.phi_y_rad - w.phi_y_rad),
    ]
}

fn ncgear_wrap(a: f64) -> f64 {
    let w = a.rem_euclid(TAU);
    if w > PI { w - TAU } else { w }
}

fn assert_within_crlb(s: &Synth, got: &Orbit, factor: f64) {
    let w = s.orbit.sin_pair();
    let e = errors(got, &s.orbit);
    let ca = s.crlb_amp();
    let lim = [
        factor * ca,
        factor * ca / w.a_x_um,
        factor * ca,
        factor * ca / w.a_y_um,
    ];
    for k in 0..4 {
        assert!(
            e[k].abs() <= lim[k],
            "error[{k}] = {:.3e} > {:.3e} ({factor}×CRLB); all errors {e:?}",
            e[k],
            lim[k]
        );
    }
}

#[test]
fn ls_extraction_within_4x_crlb_non_integer_drift_noise_nuisance() {
    for seed in [1u64, 2, 3] {
        let s = Synth::base(seed);
        let rec = s.record();
        let ex = Extractor::new(
            s.orbit.omega_p_rad_s,
            ExtractOptions::default().with_nuisance(s.nuisance()),
        )
        .unwrap();
        let m = ex.extract(&rec).unwrap();
        assert_within_crlb(&s, &m.orbit, 4.0);
        let e = errors(&m.orbit, &s.orbit);
        let w = s.orbit.sin_pair();
        eprintln!(
            "seed {seed}: errors / CRLB: A_x {:+.2}, φ_x {:+.2}, A_y {:+.2}, φ_y {:+.2} (CRLB A = {:.4} µm)",
            e[0] / s.crlb_amp(),
            e[1] / (s.crlb_amp() / w.a_x_um),
            e[2] / s.crlb_amp(),
            e[3] / (s.crlb_amp() / w.a_y_um),
            s.crlb_amp()
        );
        assert!(m.warnings.is_empty(), "{:?}", m.warnings);
        // The reported 1-σ matches the CRLB (white noise).
        let u = m.uncertainty.unwrap();
        let r = u.a_x_um / s.crlb_amp();
        assert!((0.8..1.25).contains(&r), "σ(A_x)/CRLB = {r}");
        let r = u.phi_y_rad / (s.crlb_amp() / s.orbit.sin_pair().a_y_um);
        assert!((0.8..1.25).contains(&r), "σ(φ_y)/CRLB = {r}");
        // Residual RMS ≈ noise σ.
        let (rx, ry) = m.residual_rms_um.unwrap();
        assert!(
            (rx / 2.0 - 1.0).abs() < 0.05 && (ry / 2.0 - 1.0).abs() < 0.05,
            "{rx} {ry}"
        );
        // Comparison with the model: ellipse within a few CRLB.
        let c = Comparison::new(&m.orbit, &s.orbit);
        assert!(
            c.d_r_long_um.abs() < 6.0 * s.crlb_amp() && c.d_r_short_um.abs() < 6.0 * s.crlb_amp(),
            "{c:?}"
        );
    }
}

#[test]
fn ls_handles_nearby_nuisance_line_and_jittered_time() {
    // A strong nuisance line 4 bins from the planet line, non-uniform sampling, record not
    // starting at t = 0.
    let mut s = Synth::base(7);
    let bin = TAU / s.duration();
    s.lines
        .push((s.orbit.omega_p_rad_s + 2.5 * bin, C64::new(-6.0, 6.0)));
    s.lines
        .push((-(s.orbit.omega_p_rad_s - 5.0 * bin), C64::new(4.0, 1.0)));
    s.jitter = 0.3;
    s.t0_s = 0.8;
    let rec = s.record();
    assert!(!rec.is_uniform(1e-6));
    let m = Extractor::new(
        s.orbit.omega_p_rad_s,
        ExtractOptions::default().with_nuisance(s.nuisance()),
    )
    .unwrap()
    .extract(&rec)
    .unwrap();
    assert_within_crlb(&s, &m.orbit, 4.0);
    assert_eq!(m.warnings.len(), 1, "{:?}", m.warnings); // 2.5 bins < 3 bins
    // Without the nuisance lines in the model the estimate is biased far beyond the CRLB.
    let naive = Extractor::new(s.orbit.omega_p_rad_s, ExtractOptions::default())
        .unwrap()
        .extract(&rec)
        .unwrap();
    let e = errors(&naive.orbit, &s.orbit);
    assert!(e[0].abs().max(e[2].abs()) > 10.0 * s.crlb_amp(), "{e:?}");
}

#[test]
fn plain_fft_phase_error_contrast() {
    let s = Synth::base(11);
    let rec = s.record();
    let run = |m: Method| {
        Extractor::new(
            s.orbit.omega_p_rad_s,
            ExtractOptions::default()
                .with_method(m)
                .with_nuisance(s.nuisance()),
        )
        .unwrap()
        .extract(&rec)
        .unwrap()
    };
    let fft = errors(&run(Method::PlainFft).orbit, &s.orbit);
    let hann = errors(&run(Method::HannDtft).orbit, &s.orbit);
    let sync = errors(&run(Method::Synchronous).orbit, &s.orbit);
    let ls = errors(&run(Method::LeastSquares).orbit, &s.orbit);
    // Plain FFT bin on 26.185 periods: phase off by ≈ π·0.185 = 0.58 rad (docs/math/companion.md §A.8 table).
    assert!(
        fft[1].abs() > 0.5 && fft[3].abs() > 0.5,
        "plain FFT phase errors {fft:?}"
    );
    assert!((fft[1].abs() - 0.185 * PI).abs() < 0.05, "{fft:?}");
    // Hann-DTFT at the exact frequency and synchronous resampling are much better …
    for e in [hann, sync] {
        assert!(e[1].abs() < 0.05 && e[3].abs() < 0.05, "{e:?}");
    }
    // … and least squares is within 4× CRLB.
    assert!(
        ls[1].abs() < 4.0 * s.crlb_amp() / s.orbit.sin_pair().a_x_um,
        "{ls:?}"
    );
    eprintln!(
        "phase errors x/y [rad]: plain FFT {:.4}/{:.4}, Hann-DTFT {:.4}/{:.4}, synchronous {:.4}/{:.4}, LS {:.5}/{:.5}",
        fft[1], fft[3], hann[1], hann[3], sync[1], sync[3], ls[1], ls[3]
    );
}

#[test]
fn colliding_lines_are_refused() {
    let s = Synth::base(5);
    let rec = s.record();
    let bin = TAU / s.duration();
    // A nuisance line 1e-7 bin from the planet line: condition number > 1e6, refused.
    let mut lines = s.nuisance();
    lines.push(Line::new(
        "runout (zs = zp)",
        -(s.orbit.omega_p_rad_s + 1e-7 * bin),
        LineKind::Nuisance,
    ));
    let err = Extractor::new(
        s.orbit.omega_p_rad_s,
        ExtractOptions::default().with_nuisance(lines),
    )
    .unwrap()
    .extract(&rec)
    .unwrap_err();
    match &err {
        OrbitError::Collision {
            condition,
            limit,
            detail,
        } => {
            assert!(*condition > *limit && *limit == 1e6, "{err}");
            assert!(
                detail.contains("runout (zs = zp)") && detail.contains("planet Z+"),
                "{detail}"
            );
        }
        other => panic!("expected a collision, got {other}"),
    }
    // Exactly on the line (zs = zp): refused as well.
    let mut lines = s.nuisance();
    lines.push(Line::new(
        "runout",
        -s.orbit.omega_p_rad_s,
        LineKind::Nuisance,
    ));
    assert!(matches!(
        Extractor::new(
            s.orbit.omega_p_rad_s,
            ExtractOptions::default().with_nuisance(lines)
        )
        .unwrap()
        .extract(&rec),
        Err(OrbitError::Collision { .. })
    ));
    // 0.001 bin away: condition ≈ 1e3 < 1e6, so analysed — but warned, and the reported
    // uncertainty is inflated by orders of magnitude over the CRLB (the estimate is useless).
    let mut lines = s.nuisance();
    lines.push(Line::new(
        "near",
        -(s.orbit.omega_p_rad_s + 0.001 * bin),
        LineKind::Nuisance,
    ));
    let m = Extractor::new(
        s.orbit.omega_p_rad_s,
        ExtractOptions::default().with_nuisance(lines),
    )
    .unwrap()
    .extract(&rec)
    .unwrap();
    assert!(
        m.warnings
            .iter()
            .any(|w| w.contains("near") && w.contains("0.001 bins")),
        "{:?}",
        m.warnings
    );
    assert!(m.uncertainty.unwrap().a_x_um > 100.0 * s.crlb_amp());
    // 2 bins away: analysed, but warned (< 3 bins).
    let mut lines = s.nuisance();
    lines.push(Line::new(
        "close",
        s.orbit.omega_p_rad_s + 2.0 * bin,
        LineKind::Nuisance,
    ));
    let m = Extractor::new(
        s.orbit.omega_p_rad_s,
        ExtractOptions::default().with_nuisance(lines),
    )
    .unwrap()
    .extract(&rec)
    .unwrap();
    assert!(
        m.warnings
            .iter()
            .any(|w| w.contains("close") && w.contains("2.000 bins")),
        "{:?}",
        m.warnings
    );
    assert!(m.condition_number.unwrap() < 1e6);
}

#[test]
fn housing_frame_derotation_and_full_spectrum() {
    let mut s = Synth::base(21);
    s.carrier_rad_s = TAU * 1.13;
    s.lines.truncate(1); // runout line, given in the carrier frame
    let rec = s.record();
    // (a) de-rotate with the recorded carrier angle.
    let m = Extractor::new(
        s.orbit.omega_p_rad_s,
        ExtractOptions::default()
            .with_frame(Frame::HousingDerotate)
            .with_nuisance(s.nuisance()),
    )
    .unwrap()
    .extract(&rec)
    .unwrap();
    assert_within_crlb(&s, &m.orbit, 4.0);
    // (b) full spectrum at the signed frequencies ω_c ± ω_p; nuisance shifted to the housing frame.
    let wc = s.carrier_rad_s;
    let housing: Vec<Line> = s
        .lines
        .iter()
        .map(|(w, _)| Line::new("runout", w + wc, LineKind::Nuisance))
        .collect();
    let m = Extractor::new(
        s.orbit.omega_p_rad_s,
        ExtractOptions::default()
            .with_frame(Frame::HousingFullSpectrum { carrier_rad_s: wc })
            .with_nuisance(housing),
    )
    .unwrap()
    .extract(&rec)
    .unwrap();
    assert_within_crlb(&s, &m.orbit, 4.0);
    // Reading the housing record as if it were the carrier frame is wrong by far.
    let wrong = Extractor::new(s.orbit.omega_p_rad_s, ExtractOptions::default())
        .unwrap()
        .extract(&rec)
        .unwrap();
    assert!((wrong.orbit.z_plus_um - s.orbit.z_plus_um).norm() > 3.0);
}

#[test]
fn least_squares_is_thread_count_independent() {
    let s = Synth::base(3);
    let rec = s.record();
    let ex = Extractor::new(
        s.orbit.omega_p_rad_s,
        ExtractOptions::default().with_nuisance(s.nuisance()),
    )
    .unwrap();
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| ex.extract(&rec).unwrap());
    let many = rayon::ThreadPoolBuilder::new()
        .num_threads(3)
        .build()
        .unwrap()
        .install(|| ex.extract(&rec).unwrap());
    assert_eq!(one.orbit, many.orbit);
}

#[test]
fn full_spectrum_shows_forward_and_backward_lines() {
    // An integer number of periods so the lines sit on bins.
    let mut s = Synth::base(4);
    s.periods = 40.0;
    s.samples = 4000;
    s.sigma_um = 0.0;
    s.lines.clear();
    s.drift_um_s = (0.0, 0.0);
    s.dc_um = (0.0, 0.0);
    let rec = s.record();
    let spec = full_spectrum(rec.mean_step_s(), rec.x_um(), rec.y_um());
    let at = |f: f64| {
        spec.iter()
            .min_by(|a, b| (a.0 - f).abs().total_cmp(&(b.0 - f).abs()))
            .unwrap()
            .1
    };
    // Hann window on a bin: the amplitude-corrected peak equals |Z±|.
    assert!(
        (at(3.37) - s.orbit.z_plus_um.norm()).abs() < 1e-6,
        "{}",
        at(3.37)
    );
    assert!(
        (at(-3.37) - s.orbit.z_minus_um.norm()).abs() < 1e-6,
        "{}",
        at(-3.37)
    );
}

fn temp_csv(name: &str, text: &str) -> std::path::PathBuf {
    let p = std::env::temp_dir().join(format!("ncgear_orbit_{}_{name}.csv", std::process::id()));
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn csv_errors_name_file_line_and_column() {
    let mut text = String::from("t_s,x_um,y_um\n");
    for k in 0..20 {
        text.push_str(&format!("{},{},{}\n", 0.01 * k as f64, k, -k));
    }
    let ok = temp_csv("ok", &text);
    assert_eq!(Record::from_path(&ok).unwrap().len(), 20);
    let bad = temp_csv("bad", &text.replace("0.05,5,-5", "0.05,5,abc"));
    let e = Record::from_path(&bad).unwrap_err().to_string();
    assert!(
        e.contains(&bad.display().to_string())
            && e.contains(":7:")
            && e.contains("`y_um`")
            && e.contains("\"abc\""),
        "{e}"
    );
    let unk = temp_csv("unk", &text.replace("t_s,x_um,y_um", "t_s,x_um,y_um,z_um"));
    let e = Record::from_path(&unk).unwrap_err().to_string();
    assert!(
        e.contains(":1:") && e.contains("`z_um`") && e.contains("unknown column"),
        "{e}"
    );
    let miss = temp_csv("miss", &text.replace("t_s,x_um,y_um", "t_s,x_um,q"));
    assert!(
        Record::from_path(&miss)
            .unwrap_err()
            .to_string()
            .contains("`q`")
    );
    let order = temp_csv("order", &text.replace("0.05,5,-5", "0.03,5,-5"));
    let e = Record::from_path(&order).unwrap_err().to_string();
    assert!(
        e.contains(":7:") && e.contains("`t_s`") && e.contains("not after"),
        "{e}"
    );
    for p in [ok, bad, unk, miss, order] {
        let _ = std::fs::remove_file(p);
    }
}

// ---------------------------------------------------------------------------------------------
// Files under assets/orbit (the examples of docs/orbit.md).

use ncgear::analysis::orbit::model::ModelParams;

fn asset(name: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets/orbit")
        .join(name)
}

#[test]
fn asset_model_files_load_and_give_table_a10() {
    let p = ModelParams::from_path(&asset("model.toml")).unwrap();
    let set = p.planet_set().unwrap();
    let g = p.gear_speeds().unwrap().unwrap();
    assert!(rel(set.omega_p_rad_s(), g.planet_rad_s) < 1e-15);
    let el = set.solve().orbit.ellipse();
    assert!((el.r_long_um - 17.049996).abs() < 5e-7 && (el.r_short_um - 1.347374).abs() < 5e-7);
    let j = ModelParams::from_path(&asset("model.json"))
        .unwrap()
        .planet_set()
        .unwrap();
    assert_eq!(j.planets().len(), 4);
    assert!(j.solve().load_independent);
}

#[test]
fn model_file_errors_name_the_key() {
    let dir = std::env::temp_dir();
    let p = dir.join(format!("ncgear_orbit_{}_unknown.toml", std::process::id()));
    let text = std::fs::read_to_string(asset("model.toml")).unwrap();
    std::fs::write(
        &p,
        text.replace(
            "eccentricity_um = 6.0",
            "eccentricity_um = 6.0\nrunout_um = 1.0",
        ),
    )
    .unwrap();
    let e = ModelParams::from_path(&p).unwrap_err().to_string();
    assert!(
        e.contains("runout_um") && e.contains(&p.display().to_string()),
        "{e}"
    );
    std::fs::write(
        &p,
        text.replace("eccentricity_um = 6.0", "eccentricity_um = -6.0"),
    )
    .unwrap();
    // Refused when the file is read, naming the file and the key.
    let e = ModelParams::from_path(&p).unwrap_err().to_string();
    assert!(
        e.contains("planet[1].eccentricity_um") && e.contains(&p.display().to_string()),
        "{e}"
    );
    std::fs::write(
        &p,
        text.replace("sun_speed_rpm = 300.0", "sun_speed_rpm = 300.0\n[x]"),
    )
    .unwrap();
    assert!(ModelParams::from_path(&p).is_err());
    let _ = std::fs::remove_file(p);
}

#[test]
fn asset_signals_match_the_model_within_4x_crlb() {
    // signals.csv: housing frame, σ = 1 µm, 4000 samples (make_signals.py).
    let p = ModelParams::from_path(&asset("model.toml")).unwrap();
    let set = p.planet_set().unwrap();
    let g = p.gear_speeds().unwrap().unwrap();
    let rec = Record::from_path(&asset("signals.csv")).unwrap();
    let crlb = (2.0 / rec.len() as f64).sqrt();
    let model = set.solve().orbit;
    for frame in [
        Frame::HousingDerotate,
        Frame::HousingFullSpectrum {
            carrier_rad_s: g.carrier_rad_s,
        },
    ] {
        let housing = matches!(frame, Frame::HousingFullSpectrum { .. });
        let m = Extractor::new(
            set.omega_p_rad_s(),
            ExtractOptions::default()
                .with_frame(frame)
                .with_nuisance(g.expected_lines(housing, 2)),
        )
        .unwrap()
        .extract(&rec)
        .unwrap();
        let e = errors(&m.orbit, &model);
        let s = model.sin_pair();
        let lim = [
            4.0 * crlb,
            4.0 * crlb / s.a_x_um,
            4.0 * crlb,
            4.0 * crlb / s.a_y_um,
        ];
        for k in 0..4 {
            assert!(e[k].abs() <= lim[k], "{frame:?}: {e:?} vs {lim:?}");
        }
    }
}

#[test]
fn planet_frequency_estimated_from_an_approximate_value() {
    let s = Synth::base(13);
    let rec = s.record();
    let wp = s.orbit.omega_p_rad_s;
    // Configured 2 % low (≈ 0.5 bin off).
    let ex = Extractor::new(
        wp * 0.98,
        ExtractOptions::default().with_nuisance(s.nuisance()),
    )
    .unwrap();
    let calls = std::sync::Arc::new(std::sync::atomic::AtomicU64::new(0));
    let heard = std::sync::Arc::clone(&calls);
    let sink = ncgear::progress::Progress::new(move |n| {
        heard.fetch_add(n, std::sync::atomic::Ordering::Relaxed);
    });
    let est = ex.estimate_frequency(&rec, 0.1, 1e-9, &sink).unwrap();
    assert_eq!(
        calls.load(std::sync::atomic::Ordering::Relaxed),
        u64::from(est.iterations)
    );
    assert!(u64::from(est.iterations) <= Extractor::frequency_iterations(rec.duration_s(), 1e-9));
    let bin = TAU / s.duration();
    assert!((est.interpolated_rad_s - wp).abs() < 0.1 * bin, "{est:?}");
    // CRB of a frequency, σ_ω ≈ √12·σ/(A·T·√N) per channel; the refined value is well within.
    let sigma_w = 12f64.sqrt() * s.sigma_um
        / (s.orbit.sin_pair().a_y_um * s.duration() * (s.samples as f64).sqrt());
    assert!(
        (est.refined_rad_s - wp).abs() < 4.0 * sigma_w,
        "{} vs {wp} (σ_ω {sigma_w:.2e})",
        est.refined_rad_s
    );
    // The extraction at the estimated frequency: amplitudes within 4× CRLB; phases (at t = 0, the
    // record start) within 4× the unknown-frequency bound, which is 2× the known-frequency one.
    let m = ex
        .with_omega_p(est.refined_rad_s)
        .unwrap()
        .extract(&rec)
        .unwrap();
    let e = errors(&m.orbit, &s.orbit);
    let w = s.orbit.sin_pair();
    assert!(
        e[0].abs() < 4.0 * s.crlb_amp() && e[2].abs() < 4.0 * s.crlb_amp(),
        "{e:?}"
    );
    assert!(
        e[1].abs() < 8.0 * s.crlb_amp() / w.a_x_um && e[3].abs() < 8.0 * s.crlb_amp() / w.a_y_um,
        "{e:?}"
    );
    // Extracting at the wrong (configured) frequency instead is badly biased.
    let bad = errors(&ex.extract(&rec).unwrap().orbit, &s.orbit);
    assert!(bad[3].abs() > 0.5, "{bad:?}");
}

#[test]
fn ls_is_exact_on_noise_free_non_integer_records() {
    // No noise: least squares with the right nuisance lines and drift recovers Z± to round-off
    // for any non-integer number of periods (no window, no leakage).
    for periods in [3.3, 26.185, 101.77] {
        let mut s = Synth::base(0);
        s.sigma_um = 0.0;
        s.periods = periods;
        s.samples = 6000;
        let m = Extractor::new(
            s.orbit.omega_p_rad_s,
            ExtractOptions::default().with_nuisance(s.nuisance()),
        )
        .unwrap()
        .extract(&s.record())
        .unwrap();
        assert!(
            (m.orbit.z_plus_um - s.orbit.z_plus_um).norm() < 1e-9,
            "{periods}: {:?}",
            m.orbit
        );
        assert!(
            (m.orbit.z_minus_um - s.orbit.z_minus_um).norm() < 1e-9,
            "{periods}: {:?}",
            m.orbit
        );
    }
}

#[test]
fn tach_synchronous_average_corrects_a_wrong_nominal_speed() {
    // The nominal ω_p is 1 % off; once-per-revolution tach pulses give the true angle.
    let mut s = Synth::base(17);
    s.lines.truncate(1);
    let rec = s.record();
    let wp = s.orbit.omega_p_rad_s;
    let period = TAU / wp;
    let t_first = 0.123;
    let pulses: Vec<f64> = (0..)
        .map(|k| t_first + k as f64 * period)
        .take_while(|t| *t < s.duration() - 1e-3)
        .collect();
    let with_tach = rec.clone().with_tach_pulses(pulses).unwrap();
    let ex = Extractor::new(
        wp * 1.01,
        ExtractOptions::default().with_method(Method::Synchronous),
    )
    .unwrap();
    let good = errors(&ex.extract(&with_tach).unwrap().orbit, &s.orbit);
    let bad = errors(&ex.extract(&rec).unwrap().orbit, &s.orbit);
    // Tach: the 5 µm runout line is not synchronous and leaks into the average with about
    // 5/(π·Δbins) µm (rectangular window over 26 revolutions); bound = that leakage + 4× CRLB.
    let dbins = (4.91 - 3.37) * s.duration();
    let lim = 5.0 / (PI * dbins) + 4.0 * s.crlb_amp();
    let w = s.orbit.sin_pair();
    assert!(
        good[0].abs() < lim && good[2].abs() < lim,
        "{good:?} vs {lim}"
    );
    assert!(
        good[1].abs() < lim / w.a_x_um && good[3].abs() < lim / w.a_y_um,
        "{good:?}"
    );
    assert!(bad[1].abs().max(bad[3].abs()) > 0.3, "{bad:?}");
    // Tach column in a CSV: rising edges become pulses; other values are errors.
    let mut text = String::from("t_s,x_um,y_um,tach\n");
    for k in 0..40 {
        text.push_str(&format!(
            "{},{},{},{}\n",
            0.01 * k as f64,
            k,
            -k,
            u8::from(k % 10 == 3 || k % 10 == 4)
        ));
    }
    let p = temp_csv("tach", &text);
    let r = Record::from_path(&p).unwrap();
    assert_eq!(r.tach_pulses_s().unwrap(), &[0.03, 0.13, 0.23, 0.33]);
    let bad_csv = temp_csv("tach_bad", &text.replace("0.05,5,-5,0", "0.05,5,-5,2"));
    let e = Record::from_path(&bad_csv).unwrap_err().to_string();
    assert!(
        e.contains(":7:") && e.contains("`tach`") && e.contains("0 or 1"),
        "{e}"
    );
    for q in [p, bad_csv] {
        let _ = std::fs::remove_file(q);
    }
}

use ncgear::analysis::orbit::evaluate::{Evaluation, MeasureOptions, SensorFrame};
use ncgear::analysis::orbit::report::{IdentifyReport, ModelReport};

#[test]
fn library_reports_are_what_the_cli_prints() {
    let p = ModelParams::from_path(&asset("model.toml")).unwrap();
    let set = p.planet_set().unwrap();
    let model = ModelReport::new(&p).unwrap();
    assert_eq!(model.orbit.orbit(), set.solve().orbit);
    let opts = MeasureOptions::default().with_frame(SensorFrame::Derotate);
    let mut ev = Evaluation::new(Some(&p), &opts).unwrap();
    let rec = Record::from_path(&asset("signals.csv")).unwrap();
    assert!(
        ev.refine_frequency(&rec, &Progress::none())
            .unwrap()
            .is_none()
    );
    let m = ev.extract(&rec).unwrap();
    let report = serde_json::to_value(ev.report(&m)).unwrap();
    for key in [
        "method",
        "frame",
        "orbit",
        "uncertainty_1sigma",
        "condition_number",
        "residual_rms_um",
        "lines",
        "warnings",
        "omega_p_rad_s",
        "frequency_estimated",
        "record_length_s",
        "samples",
        "comparison_with_model",
    ] {
        assert!(!report[key].is_null(), "{key}");
    }
    let id = IdentifyReport::new(&set, &m.orbit, None).unwrap();
    assert_eq!(id.planets.len(), 3);
    assert!(!id.common_mode_observable);
    // Library errors name the field, never a CLI flag.
    let e = Evaluation::new(None, &MeasureOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("planet_speed_rpm") && !e.contains("--"), "{e}");
}
