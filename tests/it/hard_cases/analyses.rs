//! Hard cases of the companion analyses: stiff dynamics scenes (Hertz bearings
//! a thousand times stiffer, micrometre clearances and backlash), degenerate error lists (empty,
//! zero amplitude, zero frequency, duplicates, huge counts), colliding and duplicated frequencies
//! in orbit records, and NaN/∞ anywhere in the inputs. Each asserts an exact or bounded result or
//! a typed error.
use ncgear::analysis::dynamics::{
    DynamicsError, Method, RunOptions, Scene, simulate, static_state,
};
use ncgear::analysis::orbit::OrbitError;
use ncgear::analysis::orbit::measure::{ExtractOptions, Extractor, Record};
use ncgear::analysis::orbit::model::{Hand, Line, LineKind, Planet, PlanetSet};
use ncgear::analysis::peak::PeakOptions;
use ncgear::analysis::tolerance::{Analysis, ErrorFile, ToleranceError};
use ncgear::config::Format;
use ncgear::math::monte_carlo::{McError, McOptions};
use ncgear::progress::Progress;
use std::f64::consts::TAU;

const HERTZ: &str = include_str!("../../../assets/dynamics/full16_hertz.toml");
const BACKLASH: &str = include_str!("../../../assets/dynamics/backlash_oscillator.toml");

/// Runs `mesh_periods` mesh periods from the static state with DOPRI5 (breakpoints and events):
/// the largest |DTE| (m) of a finite run, or a typed error.
fn run_stiff(text: &str, label: &str, mesh_periods: u32) -> Result<f64, DynamicsError> {
    let s = Scene::parse(text, label, Format::Toml)?;
    let (m, _) = s.build(label)?;
    let y0 = static_state(&m, 1e-6);
    assert!(y0.iter().all(|v| v.is_finite()), "{label}: static state");
    let o = RunOptions::window(
        Method::Dopri5 {
            rtol: 1e-6,
            atol: 1e-12,
            breakpoints: true,
            events: true,
        },
        mesh_periods,
        16,
    );
    let run = simulate(&m, &y0, &o, &Progress::none())?;
    let worst = run.dte_m.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    assert!(
        run.dte_m
            .iter()
            .chain(&run.mesh_force_n)
            .all(|v| v.is_finite()),
        "{label}: non-finite samples in an Ok run"
    );
    Ok(worst)
}

#[test]
fn stiff_dynamics_scenes_stay_finite_or_fail_typed() {
    let stiff = [
        (
            "Hertz bearings ×1000 stiffer, 0.01 µm clearance",
            HERTZ
                .replace("Kc = 7.055e9", "Kc = 7.055e12")
                .replace("clearance_um = 5.0", "clearance_um = 0.01"),
        ),
        (
            "Hertz bearings, backlash 0.01 µm",
            HERTZ.replace("half_gap_um = 50.0", "half_gap_um = 0.01"),
        ),
        (
            "Hertz ×1000, zero clearance, backlash 0.01 µm, mesh ×100 stiffer",
            HERTZ
                .replace("Kc = 7.055e9", "Kc = 7.055e12")
                .replace("clearance_um = 5.0", "clearance_um = 0.0")
                .replace("half_gap_um = 50.0", "half_gap_um = 0.01")
                .replace("kmax = 4.5e8, kmin = 2.5e8", "kmax = 4.5e10, kmin = 2.5e10"),
        ),
        (
            "backlash oscillator, backlash 1e-6 µm",
            BACKLASH.replace("half_gap_um = 50.0", "half_gap_um = 1e-6"),
        ),
    ];
    let mut finished = 0;
    for (label, text) in &stiff {
        assert_ne!(text, HERTZ, "{label}: the replacement did not apply");
        match run_stiff(text, label, 20) {
            Ok(worst) => {
                finished += 1;
                eprintln!("{label}: max |DTE| = {:.3} µm", worst * 1e6);
                // Excitations of these scenes: backlash ≤ 50 µm + static deflection F0/k ≈ 4 µm
                // + STE 10 µm (+ eccentricity 20 µm) ≈ 84 µm; 200 µm leaves room for dynamic
                // amplification but catches a blow-up.
                assert!(worst < 200e-6, "{label}: |DTE| = {worst} m");
            }
            Err(DynamicsError::Ode(e)) => eprintln!("{label}: typed integrator error: {e}"),
            Err(DynamicsError::Diverged(t)) => eprintln!("{label}: diverged at {t} s"),
            Err(e) => panic!("{label}: unexpected error {e}"),
        }
    }
    assert!(
        finished >= 3,
        "only {finished} of the stiff scenes finished"
    );
}

#[test]
fn non_finite_and_extreme_scene_values_are_typed_errors() {
    // TOML has nan and inf literals: every numeric key that reaches the model is checked.
    for (from, to) in [
        ("Kc = 7.055e9", "Kc = nan"),
        ("Kc = 7.055e9", "Kc = inf"),
        ("clearance_um = 5.0", "clearance_um = nan"),
        ("half_gap_um = 50.0", "half_gap_um = -inf"),
        ("kmax = 4.5e8", "kmax = inf"),
        ("n1_rpm = 6000.0", "n1_rpm = nan"),
        ("input_torque_Nm = 50.0", "input_torque_Nm = 1e308"),
        ("face_width_mm = 20.0", "face_width_mm = 1e300"),
        ("module_mm = 3.0", "module_mm = 1e-300"),
        ("mu = 0.05", "mu = nan"),
        ("rho_um = 20.0", "rho_um = inf"),
        ("g = [0.0, -9.81]", "g = [nan, -9.81]"),
        ("rtol = 1e-6", "rtol = nan"),
        (
            "record_mesh_periods = 50",
            "record_mesh_periods = 4000000000",
        ),
        ("max_periods = 2", "max_periods = 4000000000"),
        ("samples_per_mesh = 64", "samples_per_mesh = 0"),
    ] {
        let text = HERTZ.replace(from, to);
        assert_ne!(text, HERTZ, "{from}");
        let outcome = Scene::parse(&text, "h.toml", Format::Toml)
            .map_err(DynamicsError::from)
            .and_then(|s| {
                let (model, _) = s.build("h.toml")?;
                RunOptions::from_scene(&s, &model).map(|_| s)
            });
        match outcome {
            Err(e) => {
                let msg = e.to_string();
                assert!(!msg.is_empty(), "{to}");
            }
            Ok(s) => {
                // Accepted only if everything derived stays finite.
                let d = s.derived("h.toml").unwrap();
                panic!("{to}: accepted (m_e = {}, F0 = {})", d.m_e_kg, d.f0_n);
            }
        }
    }
}

fn errors(terms: &str) -> Result<ErrorFile, ToleranceError> {
    ErrorFile::parse(
        &format!("base_radius_mm = 47.0\n{terms}"),
        "e.toml",
        Format::Toml,
    )
}

/// A TOML number (TOML spells the non-finite values `nan`, `inf`, `-inf`).
fn num(v: f64) -> String {
    match v {
        v if v.is_nan() => "nan".into(),
        f64::INFINITY => "inf".into(),
        f64::NEG_INFINITY => "-inf".into(),
        v => format!("{v:?}"),
    }
}

fn term(a: f64, w: f64, phase: f64) -> String {
    format!(
        "[[terms]]\namplitude_um = {}\nomega_rad_s = {}\nphase_deg = {}\n",
        num(a),
        num(w),
        num(phase)
    )
}

fn peak_of(f: &ErrorFile) -> f64 {
    let a = Analysis::new(f, PeakOptions::default());
    a.peak(&vec![0.0; a.free_count()], None).value
}

#[test]
fn degenerate_error_lists_give_typed_errors_or_exact_peaks() {
    // Empty list and too many terms: typed errors naming `terms`.
    for text in ["terms = []\n".to_string(), term(1.0, 10.0, 0.0).repeat(65)] {
        match errors(&text) {
            Err(ToleranceError::BadValue { key, .. }) => assert_eq!(key, "terms"),
            other => panic!("expected BadValue(terms), got {other:?}"),
        }
    }
    // All amplitudes zero: peak exactly 0.
    let f = errors(&(term(0.0, 75.0, 0.0) + &term(0.0, 525.0, 20.0))).unwrap();
    assert_eq!(peak_of(&f), 0.0);
    // A zero frequency is a constant: 3 sin 30° = 1.5 alone, 1.5 + 2 on top of a sinusoid.
    let f = errors(&term(3.0, 0.0, 30.0)).unwrap();
    assert!((peak_of(&f) - 1.5).abs() < 1e-12, "{}", peak_of(&f));
    let f = errors(&(term(3.0, 0.0, 30.0) + &term(2.0, 10.0, 0.0))).unwrap();
    assert!((peak_of(&f) - 3.5).abs() < 1e-9, "{}", peak_of(&f));
    // All frequencies zero: |Σ A sin φ|.
    let f = errors(&(term(3.0, 0.0, 90.0) + &term(-1.0, 0.0, 90.0))).unwrap();
    assert!((peak_of(&f) - 2.0).abs() < 1e-12);
    // Duplicated terms add as phasors: equal → 2A; opposite → exactly cancelled.
    let f = errors(&term(5.0, 100.0, 10.0).repeat(2)).unwrap();
    assert!((peak_of(&f) - 10.0).abs() < 1e-9, "{}", peak_of(&f));
    let f = errors(&(term(5.0, 100.0, 10.0) + &term(5.0, 100.0, 190.0))).unwrap();
    assert!(peak_of(&f).abs() < 1e-9, "{}", peak_of(&f));
    // 64 identical terms (the maximum): 64 A.
    let f = errors(&term(0.5, 42.0, 0.0).repeat(64)).unwrap();
    assert!((peak_of(&f) - 32.0).abs() < 1e-9, "{}", peak_of(&f));
    // Incommensurate and wildly spread frequencies: a finite certified peak ≤ Σ|A|.
    let f = errors(&(term(1.0, 1e-9, 0.0) + &term(1.0, 1e6, 0.0) + &term(1.0, 2f64.sqrt(), 0.0)))
        .unwrap();
    let p = peak_of(&f);
    assert!(p.is_finite() && p <= 3.0 + 1e-9, "{p}");
    // Scan counts outside 1..=100000: typed errors.
    for steps in ["scan_steps = 0\n", "scan_steps = 100001\n"] {
        assert!(matches!(
            errors(&format!("{steps}{}", term(1.0, 1.0, 0.0))),
            Err(ToleranceError::BadValue { .. })
        ));
    }
    // Monte Carlo counts: zero or absurd sample/bin counts are typed errors.
    let f = errors(&term(1.0, 1.0, 0.0)).unwrap();
    let a = Analysis::new(&f, PeakOptions::default());
    for (samples, bins) in [(0, 10), (usize::MAX, 10), (100, 0), (100, usize::MAX)] {
        let o = McOptions::default()
            .with_samples(samples)
            .with_seed(1)
            .with_bins(bins);
        assert!(matches!(
            a.monte_carlo(&o, &Progress::none()),
            Err(McError::BadOption { .. })
        ));
    }
}

#[test]
fn non_finite_error_file_values_are_typed_errors() {
    let ok = term(1.0, 10.0, 0.0);
    for text in [
        term(f64::NAN, 10.0, 0.0),
        term(1.0, f64::INFINITY, 0.0),
        term(1.0, -10.0, 0.0),
        term(1.0, 10.0, f64::NAN),
        ok.clone() + "sign = nan\n",
        ok.clone() + "sign = 0.5\n",
        ok.clone() + "amplitude_dist = { uniform_um = [nan, 1.0] }\n",
        ok.clone() + "amplitude_dist = { uniform_um = [2.0, 1.0] }\n",
        ok.clone() + "amplitude_dist = { rayleigh_sigma_um = inf }\n",
        ok.clone() + "amplitude_dist = { rayleigh_sigma_um = 0.0 }\n",
    ] {
        assert!(
            matches!(errors(&text), Err(ToleranceError::BadValue { .. })),
            "accepted: {text}"
        );
    }
    for base in [
        "base_radius_mm = nan",
        "base_radius_mm = inf",
        "base_radius_mm = 0.0",
        "[base_circle]\nmodule_mm = nan\nteeth = 50\npressure_angle_deg = 20.0",
        "[base_circle]\nmodule_mm = 1e300\nteeth = 1e300\npressure_angle_deg = 20.0",
        "[base_circle]\nmodule_mm = 2.0\nteeth = inf\npressure_angle_deg = 20.0",
        "[base_circle]\nmodule_mm = 2.0\nteeth = 50\npressure_angle_deg = nan",
    ] {
        let text = format!("{ok}\n{base}\n");
        // TOML: the [[terms]] table must come last; put the base first.
        let text = format!("{base}\n{}", text.replace(base, ""));
        assert!(
            matches!(
                ErrorFile::parse(&text, "e.toml", Format::Toml),
                Err(ToleranceError::BadValue { .. })
            ),
            "accepted: {base}"
        );
    }
}

/// A synthetic carrier-frame record of a known orbit: `x = Ax sin(ωp t + φx)`, `y = Ay sin(…)`.
fn orbit_record(n: usize, dt: f64, wp: f64) -> Record {
    let t: Vec<f64> = (0..n).map(|k| k as f64 * dt).collect();
    let x = t.iter().map(|t| 7.0 * (wp * t + 0.4).sin()).collect();
    let y = t.iter().map(|t| 3.0 * (wp * t - 1.1).sin()).collect();
    Record::new(t, x, y, None).unwrap()
}

#[test]
fn colliding_and_duplicated_lines_in_orbit_records() {
    let wp = TAU * 3.0;
    let rec = orbit_record(4000, 1e-3, wp);
    // Clean record: the least-squares extraction recovers the sinusoids exactly.
    let m = Extractor::new(wp, ExtractOptions::default())
        .unwrap()
        .extract(&rec)
        .unwrap();
    let p = m.orbit.sin_pair();
    assert!(
        (p.a_x_um - 7.0).abs() < 1e-9 && (p.a_y_um - 3.0).abs() < 1e-9,
        "{p:?}"
    );
    assert!((p.phi_x_rad - 0.4).abs() < 1e-9 && (p.phi_y_rad + 1.1).abs() < 1e-9);
    // A nuisance line at ±ωp collides with the planet lines: refused as a collision, never a
    // NaN orbit.
    let nuisance = |w: f64| Line::new("n", w, LineKind::Nuisance);
    for w in [wp, -wp, wp * (1.0 + 1e-13)] {
        match Extractor::new(
            wp,
            ExtractOptions::default().with_nuisance(vec![nuisance(w)]),
        )
        .unwrap()
        .extract(&rec)
        {
            Err(OrbitError::Collision {
                condition, limit, ..
            }) => {
                assert!(condition > limit || condition.is_infinite(), "{w}");
            }
            Ok(m) => panic!("nuisance at {w}: accepted, Z+ = {}", m.orbit.z_plus_um),
            Err(e) => panic!("nuisance at {w}: unexpected {e}"),
        }
    }
    // The same nuisance line twice, and a DC nuisance (the mean column): merged, and the orbit
    // is still recovered exactly.
    for lines in [
        vec![nuisance(2.0 * wp), nuisance(2.0 * wp)],
        vec![nuisance(0.0)],
        vec![nuisance(5.0 * wp), nuisance(-5.0 * wp), nuisance(0.0)],
    ] {
        let m = Extractor::new(wp, ExtractOptions::default().with_nuisance(lines))
            .unwrap()
            .extract(&rec)
            .unwrap();
        let q = m.orbit.sin_pair();
        assert!(
            (q.a_x_um - 7.0).abs() < 1e-9 && (q.a_y_um - 3.0).abs() < 1e-9,
            "{q:?}"
        );
    }
    // NaN or ∞ in every extractor and planet-set input: typed errors.
    for w in [f64::NAN, f64::INFINITY, 0.0] {
        assert!(Extractor::new(w, ExtractOptions::default()).is_err());
    }
    assert!(
        Extractor::new(
            wp,
            ExtractOptions::default().with_nuisance(vec![nuisance(f64::NAN)])
        )
        .is_err()
    );
    assert!(Extractor::new(wp, ExtractOptions::default().with_max_condition(f64::NAN)).is_err());
    assert!(
        Extractor::new(
            wp,
            ExtractOptions::default().with_min_separation_bins(f64::NAN)
        )
        .is_err()
    );
    let planet = |e: f64, pos: f64| Planet {
        position_rad: pos,
        eccentricity_um: e,
        phase_rad: 0.0,
    };
    for bad in [f64::NAN, f64::INFINITY, -1.0, 1e300] {
        let ps = vec![planet(bad, 0.0), planet(1.0, 2.0), planet(1.0, 4.0)];
        assert!(
            PlanetSet::new(0.35, Hand::Ccw, 0.0, wp, ps).is_err(),
            "e = {bad}"
        );
    }
    let ps = vec![planet(1.0, f64::NAN), planet(1.0, 2.0), planet(1.0, 4.0)];
    assert!(PlanetSet::new(0.35, Hand::Ccw, 0.0, wp, ps).is_err());
    // Records: NaN, non-increasing time, too few samples, huge values.
    let t: Vec<f64> = (0..32).map(|k| k as f64).collect();
    let z = vec![0.0; 32];
    let mut tn = t.clone();
    tn[5] = f64::NAN;
    assert!(Record::new(tn, z.clone(), z.clone(), None).is_err());
    let mut tr = t.clone();
    tr[5] = tr[4];
    assert!(Record::new(tr, z.clone(), z.clone(), None).is_err());
    assert!(Record::new(t[..8].to_vec(), z[..8].to_vec(), z[..8].to_vec(), None).is_err());
    let mut xh = z.clone();
    xh[3] = 1e300;
    assert!(Record::new(t.clone(), xh, z.clone(), None).is_err());
}
