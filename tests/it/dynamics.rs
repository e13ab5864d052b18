//! Integration tests: dynamics (docs/math/companion.md §B, numbers of docs/math/companion.md §B.9).
use ncgear::analysis::dynamics::model::FrictionTerm;
use ncgear::analysis::dynamics::tvms::{PairGeometry, RectangularTvms};
use ncgear::analysis::dynamics::*;
use ncgear::analysis::dynamics::{model, ode};
use ncgear::config::Format;
use ncgear::progress::Progress;

const ASSETS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/dynamics");

fn asset(name: &str) -> Scene {
    Scene::from_path(std::path::Path::new(&format!("{ASSETS}/{name}"))).unwrap()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// The SDOF physical model of docs/math/companion.md §B.9-4 (6000 rpm, rectangular TVMS, b = 50 µm, er = 10 µm, T1 = 50 N·m).
const SDOF_6000: &str = r#"
[scene]
name = "sdof6000"
model = "spur_pair"
[gears]
z1 = 25
z2 = 40
module_mm = 3.0
pressure_angle_deg = 20.0
face_width_mm = 20.0
[operating]
n1_rpm = 6000.0
input_torque_Nm = 50.0
[effects]
mesh_stiffness = { kind = "rectangular", kmax = 4.5e8, kmin = 2.5e8, zeta = 0.05 }
static_te = { er_um = 10.0 }
backlash = { half_gap_um = 50.0 }
"#;

#[test]
fn tvms_mean_harmonics_and_patent_double_count() {
    let g = PairGeometry::new(25, 40, 3.0, 20.0, 1.0).unwrap();
    assert!(
        (g.contact_ratio - 1.6626).abs() < 5e-5,
        "{}",
        g.contact_ratio
    );
    assert!((g.n1a_m * 1e3 - 5.2379).abs() < 1e-4);
    assert!((g.n1p_m * 1e3 - 12.8258).abs() < 1e-4);
    assert!((g.n1e_m * 1e3 - 19.9625).abs() < 1e-4);
    let r = RectangularTvms {
        kmax: 4.5e8,
        kmin: 2.5e8,
        eps: g.contact_ratio,
    };
    assert!(rel(r.mean(), 3.8252e8) < 1e-4, "{}", r.mean());
    // the patent's kd = k0 + A0/2 double-counts: 4.1504e8 ≠ mean
    assert!(rel(r.patent_kd(), 4.1504e8) < 1e-4, "{}", r.patent_kd());
    assert!(rel(r.patent_kd(), r.mean()) > 0.08);
    // the harmonics of docs/math/companion.md §B.9 were computed with ε rounded to 1.6626
    let r = RectangularTvms { eps: 1.6626, ..r };
    let kn = [
        1.1107e8, -5.4302e7, -1.6263e6, 2.8343e7, -2.1195e7, -1.6251e6, 1.6502e7, -1.2899e7,
        -1.6231e6,
    ];
    for (n, &k) in kn.iter().enumerate() {
        let got = r.harmonic(n as u32 + 1);
        assert!(
            (got - k).abs() < 2e-4 * k.abs().max(1e7),
            "k{}: {got} vs {k}",
            n + 1
        );
    }
    // the per-pair split sums to the rectangle exactly; the numeric mean equals the formula
    let m = 10_000;
    let mut mean = 0.0;
    for i in 0..m {
        let s = (i as f64 + 0.5) / m as f64;
        assert_eq!(r.pair(s) + r.pair(s + 1.0), r.at_phase(s));
        mean += r.at_phase(s) / m as f64;
    }
    assert!(rel(mean, r.mean()) < 1e-4);
    // Fourier series with 9 terms: Gibbs overshoot ≈ 8.6 % of (kmax − kmin)
    let over = (0..20_000)
        .map(|i| r.fourier(i as f64 / 20_000.0, 9))
        .fold(f64::MIN, f64::max)
        - r.kmax;
    assert!(
        (over / (r.kmax - r.kmin) - 0.086).abs() < 0.01,
        "{}",
        over / (r.kmax - r.kmin)
    );
}

fn eig_of(text: &str) -> Vec<f64> {
    let s = Scene::parse(text, "inline", Format::Toml).unwrap();
    let (m, _) = s.build("inline").unwrap();
    natural_frequencies_hz(&m).unwrap()
}

fn with_effects(effects: &str, dofs: &str) -> String {
    format!(
        "[scene]\nname = \"e\"\nmodel = \"spur_pair\"\ndofs = \"{dofs}\"\n[gears]\nz1 = 25\nz2 = 40\nmodule_mm = 3.0\npressure_angle_deg = 20.0\nface_width_mm = 20.0\n[operating]\nn1_rpm = 6000.0\ninput_torque_Nm = 50.0\n[effects]\nmesh_stiffness = {{ kind = \"constant\", k = 3.8252e8, zeta = 0.05 }}\n{effects}\n"
    )
}

const TORSION: &str = "shafts = { kt = [3e4, 3e4], eta = [0.5, 0.5, 0.5, 0.5], j_kgm2 = [0.01, 0.05], mb_kg = [0.5, 0.5, 0.5, 0.5] }";
const SHAFTS: &str = "shafts = { kt = [3e4, 3e4], ks = [5e7, 5e7], eta = [0.5, 0.5, 0.5, 0.5], j_kgm2 = [0.01, 0.05], mb_kg = [0.5, 0.5, 0.5, 0.5] }";

#[test]
fn natural_frequencies_16_4_and_pair() {
    let f16 = eig_of(&with_effects(
        &format!("{SHAFTS}\nbearings = {{ law = \"linear\", kb = 2e8 }}"),
        "full",
    ));
    assert_eq!(f16.len(), 16);
    let want16 = [
        0.0, 153.99, 648.73, 793.34, 902.91, 1261.03, 1267.47, 3183.10, 3183.10, 3183.10, 3183.10,
        3385.89, 3388.59, 3400.67, 3410.93, 7420.43,
    ];
    assert!(f16[0] < 1e-3 * want16[1], "{f16:?}");
    for (g, w) in f16.iter().zip(want16).skip(1) {
        assert!(rel(*g, w) < 1e-3, "16-DOF: {g} vs {w}; all {f16:?}");
    }
    let f4 = eig_of(&with_effects(TORSION, "auto"));
    assert_eq!(f4.len(), 4);
    for (g, w) in f4[1..].iter().zip([174.94, 810.36, 5958.84]) {
        assert!(rel(*g, w) < 1e-3, "4-DOF: {g} vs {w}; all {f4:?}");
    }
    let f1 = eig_of(&with_effects("", "auto"));
    assert_eq!(f1.len(), 1);
    assert!(rel(f1[0], 5857.29) < 1e-3, "{f1:?}");
}

fn opts(rtol: f64, max_periods: u32, record: u32, spm: u32) -> RunOptions {
    RunOptions::default()
        .with_method(Method::Dopri5 {
            rtol,
            atol: rtol * 1e-6,
            breakpoints: true,
            events: true,
        })
        .with_poincare_tol(1e-9)
        .with_max_periods(max_periods)
        .with_record_mesh_periods(record)
        .with_samples_per_mesh(spm)
}

#[test]
fn dte_harmonics_at_6000_rpm() {
    let s = Scene::parse(SDOF_6000, "sdof", Format::Toml).unwrap();
    let (m, d) = s.build("sdof").unwrap();
    assert_eq!(m.dof_names(), ["u"]);
    assert!((d.omega_e_rad_s / d.omega_n_rad_s - 0.4268).abs() < 1e-4);
    let y0 = static_state(&m, 1e-9);
    // quasi-static at t = 0 (v = 0, double contact): k(δ − b) = F0 + c_m ė(0), ė(0) = er ωe
    let dte0 = m.mesh.dte(0.0, &y0[..1]);
    let want = 50e-6 + (d.f0_n + d.c_m_n_s_per_m * 10e-6 * d.omega_e_rad_s) / 4.5e8;
    assert!((dte0 - want).abs() < 1e-14, "{dte0} vs {want}");
    let run = simulate(&m, &y0, &opts(1e-9, 400, 200, 64), &Progress::none()).unwrap();
    assert!(run.steady, "poincaré change {}", run.poincare_change);
    let h = run.dte_harmonics(6);
    let want = [53.707, 1.1979, 1.4177, 0.4346, 0.1110, 0.0540, 0.0173];
    for (k, (g, w)) in h.iter().map(|x| x * 1e6).zip(want).enumerate() {
        assert!(
            (g - w).abs() < 1e-3 * w.max(0.1),
            "harmonic {k}: {g} µm vs {w} µm; all {h:?}"
        );
    }
    assert!(h[2] > h[1], "superharmonic resonance: 2× > 1×");
    assert!(run.dte_non_harmonic() < 1e-10, "{}", run.dte_non_harmonic());
}

fn backlash_scene() -> Scene {
    let mut s = asset("backlash_oscillator.toml");
    let d = s.derived("b").unwrap();
    // Fm = F0/(k b) = 0.1 exactly
    s.operating.input_torque_Nm = 0.1 * 3.8252e8 * 50e-6 * d.geometry.rb_m[0];
    s
}

fn amp_at(points: &[SweepPoint], om: f64) -> f64 {
    points
        .iter()
        .find(|p| (p.omega_ratio - om).abs() < 1e-9)
        .unwrap()
        .dte_half_pp_m
        / 50e-6
}

#[test]
fn backlash_oscillator_jump_and_coexistence() {
    let s = backlash_scene();
    let d = s.derived("b").unwrap();
    assert!((d.c_m_n_s_per_m / (2.0 * (d.k_mean_n_per_m * d.m_e_kg).sqrt()) - 0.05).abs() < 1e-12);
    let o = opts(1e-8, 300, 20, 128);
    // closed-form contact loss of the linear branch
    let up = sdof_contact_loss_ratio(0.05, 0.1, 0.05, 1e-12).unwrap();
    assert!((up - 0.82063).abs() < 1e-5, "{up}");
    // sweep up: linear FRF below the jump, jump between 0.82 and 0.84
    let upw = sweep(
        &s,
        "b",
        &[0.5, 0.8, 0.82, 0.84],
        &o,
        None,
        &Progress::none(),
    )
    .unwrap();
    let frf = |w: f64| 0.05 * w * w / ((1.0 - w * w).powi(2) + (0.1 * w).powi(2)).sqrt();
    assert!(
        (amp_at(&upw, 0.5) - 0.0166).abs() < 2e-4
            && rel(upw[0].dte_first_harmonic_m / 50e-6, frf(0.5)) < 1e-5,
        "{upw:?}"
    );
    assert!(
        rel(amp_at(&upw, 0.8), 0.0868) < 0.02
            && rel(upw[1].dte_first_harmonic_m / 50e-6, frf(0.8)) < 1e-5,
        "{upw:?}"
    );
    assert!(rel(amp_at(&upw, 0.82), 0.0996) < 0.02, "{upw:?}");
    assert!(rel(amp_at(&upw, 0.84), 0.2613) < 0.02, "{upw:?}");
    // sweep down from the impacting branch: stays on it to 0.72, drops by 0.70
    let down = sweep(
        &s,
        "b",
        &[0.84, 0.80, 0.76, 0.72, 0.70],
        &o,
        None,
        &Progress::none(),
    )
    .unwrap();
    assert!(rel(amp_at(&down, 0.76), 0.3119) < 0.02, "{down:?}");
    assert!(rel(amp_at(&down, 0.72), 0.3345) < 0.02, "{down:?}");
    assert!(rel(amp_at(&down, 0.70), 0.0476) < 0.02, "{down:?}");
    // coexistence at 0.76: from rest (static state) the non-impacting branch
    let rest = sweep(&s, "b", &[0.76], &o, None, &Progress::none()).unwrap();
    assert!(rel(amp_at(&rest, 0.76), 0.0673) < 0.02, "{rest:?}");
    assert!(rest[0].contact_loss_fraction == 0.0 && down[2].contact_loss_fraction > 0.0);
}

#[test]
fn energy_balance_over_100_mesh_periods() {
    let s = Scene::parse(SDOF_6000, "sdof", Format::Toml).unwrap();
    let (m, _) = s.build("sdof").unwrap();
    let y0 = static_state(&m, 1e-9);
    let rtol = 1e-8;
    let (de, src, jumps) = energy_audit(&m, &y0, 100.0 * m.mesh.t0, rtol, 1e-16).unwrap();
    // the parametric jumps ΔE = Δk Φ at the switching instants are a real part of the balance
    assert!(jumps.abs() > 1e-3 * de.abs().max(src.abs()), "{jumps}");
    let scale = src.abs().max(jumps.abs()).max(de.abs());
    let err = (de - src - jumps).abs() / scale;
    assert!(
        err <= 10.0 * rtol,
        "ΔE = {de}, ∫sources = {src}, jumps = {jumps}, rel err {err}"
    );
    // without the jumps the balance fails (Oh, Grosh & Barber 2005)
    assert!((de - src).abs() / scale > 1e3 * rtol);
}

#[test]
fn hertz_bearing_numbers() {
    use ncgear::analysis::dynamics::model::HertzBearing;
    let omega = 1500.0 * std::f64::consts::PI / 30.0;
    let ratio = 18.5 / (18.5 + 31.5);
    let b = HertzBearing {
        label: "b".into(),
        idx: [None, None],
        kc: 7.055e9,
        nb: 9,
        gamma0: 5e-6,
        p: 1.5,
        omega_cage: omega * ratio,
    };
    let cage_hz = b.omega_cage / (2.0 * std::f64::consts::PI);
    assert!((cage_hz - 9.250).abs() < 5e-4, "{cage_hz}");
    assert!((9.0 * cage_hz - 83.25).abs() < 5e-3);
    // static radial load 1000 N along y at t = 0 (balls at 2π(j−1)/9): Newton on Fy(y) = 1000
    let fy = |y: f64| b.force(0.0, 0.0, y).1;
    let mut x = 20e-6;
    for _ in 0..50 {
        let k = (fy(x + 1e-10) - fy(x - 1e-10)) / 2e-10;
        x -= (fy(x) - 1000.0) / k;
    }
    assert!((x * 1e6 - 22.80).abs() < 0.005, "{}", x * 1e6);
    let kt = (fy(x + 1e-10) - fy(x - 1e-10)) / 2e-10;
    assert!(rel(kt, 8.90e7) < 2e-3, "{kt}");
    // at fixed displacement the force ripple has order Nb per cage revolution
    let tc = 2.0 * std::f64::consts::PI / b.omega_cage;
    let n = 900;
    let fx: Vec<f64> = (0..n)
        .map(|i| b.force(tc * i as f64 / n as f64, x, 0.0).0)
        .collect();
    let h = harmonics(&fx, n, 20);
    let (kmax, _) = h
        .iter()
        .enumerate()
        .skip(1)
        .fold((0, 0.0), |a, (k, &v)| if v > a.1 { (k, v) } else { a });
    assert_eq!(kmax, 9, "{h:?}");
    assert!(
        h.iter()
            .enumerate()
            .skip(1)
            .filter(|(k, _)| k % 9 != 0)
            .all(|(_, v)| *v < 1e-6 * h[9])
    );
}

#[test]
fn free_vibration_peaks_match_eigenvalues_4dof() {
    // undamped linear torsional chain, released from a displaced state
    let text = with_effects(TORSION, "auto")
        .replace("zeta = 0.05", "zeta = 0.0")
        .replace("input_torque_Nm = 50.0", "input_torque_Nm = 0.0");
    let s = Scene::parse(&text, "f", Format::Toml).unwrap();
    let (m, _) = s.build("f").unwrap();
    assert!(m.is_linear());
    let f = natural_frequencies_hz(&m).unwrap();
    let n = m.n();
    let mut y = vec![0.0; 2 * n];
    y[m.index_of("theta1").unwrap()] = 1e-4;
    y[m.index_of("theta_p").unwrap()] = -2e-4;
    let dt = 1.0 / 40_000.0;
    let ns = 1 << 16;
    let mut q1 = Vec::with_capacity(ns);
    let solver = ode::Dopri5::new(1e-10, 1e-16).unwrap();
    let i1 = m.index_of("theta1").unwrap();
    let mut buf = vec![0.0; 2 * n];
    let mut k = 0usize;
    q1.push(y[i1]);
    k += 1;
    solver
        .integrate(
            &ode::OdeProblem::new(&m, 0.0, dt * (ns - 1) as f64),
            &mut y,
            &mut |d| {
                while k < ns && dt * k as f64 <= d.t_end() + 1e-15 {
                    d.eval(dt * k as f64, &mut buf);
                    q1.push(buf[i1]);
                    k += 1;
                }
            },
        )
        .unwrap();
    // Hann window + parabolic interpolation of the log spectrum
    let w: Vec<f64> = q1
        .iter()
        .enumerate()
        .map(|(i, v)| v * (0.5 - 0.5 * (2.0 * std::f64::consts::PI * i as f64 / ns as f64).cos()))
        .collect();
    let c = ncgear::math::periodic::fft_coefficients(&w);
    let mag: Vec<f64> = c.iter().map(|z| z.norm().max(1e-300).ln()).collect();
    let df = 1.0 / (dt * ns as f64);
    for &fe in &f[1..] {
        let b = (fe / df).round() as usize;
        let j = (b - 3..=b + 3)
            .max_by(|&a, &bb| mag[a].total_cmp(&mag[bb]))
            .unwrap();
        let (a, bb, cc) = (mag[j - 1], mag[j], mag[j + 1]);
        let p = 0.5 * (a - cc) / (a - 2.0 * bb + cc);
        let fp = (j as f64 + p) * df;
        assert!(rel(fp, fe) < 1e-3, "peak {fp} Hz vs eigen {fe} Hz");
    }
}

#[test]
fn dof_pruning_and_run_log() {
    let (m16, _) = asset("full16.toml").build("full16").unwrap();
    assert_eq!(m16.n(), 16);
    assert_eq!(m16.dof_names()[0], "theta_p");
    let names: Vec<String> = m16.terms.iter().map(|t| t.name()).collect();
    assert!(
        names.iter().any(|n| n.starts_with("friction"))
            && names.iter().any(|n| n.contains("tip_relief")),
        "{names:?}"
    );
    let (m4, _) = asset("torsional4.toml").build("t4").unwrap();
    assert_eq!(m4.dof_names(), ["theta_p", "theta1", "theta2", "theta_q"]);
    assert!(m4.is_linear());
    // bearings on the gears, no shafts, friction → 6-DOF lateral–torsional
    let six = with_effects(
        "bearings = { law = \"linear\", kb = 2e8 }\nfriction = { mu = 0.05, direction = \"pitch_switch\" }",
        "auto",
    );
    let (m6, _) = Scene::parse(&six, "six", Format::Toml)
        .unwrap()
        .build("six")
        .unwrap();
    assert_eq!(m6.dof_names(), ["x1", "y1", "theta1", "x2", "y2", "theta2"]);
    // nothing forces x → pruned
    let four = with_effects("bearings = { law = \"linear\", kb = 2e8 }", "auto");
    let (m4l, _) = Scene::parse(&four, "four", Format::Toml)
        .unwrap()
        .build("four")
        .unwrap();
    assert_eq!(m4l.dof_names(), ["y1", "theta1", "y2", "theta2"]);
    // effects off unless named: the plain SDOF has only mesh + load and no breakpoints
    let (m1, _) = Scene::parse(&with_effects("", "auto"), "one", Format::Toml)
        .unwrap()
        .build("one")
        .unwrap();
    assert_eq!(m1.terms.len(), 2);
    assert!(m1.breakpoints(0.0, 1.0).is_empty());
    let (mr, _) = Scene::parse(SDOF_6000, "r", Format::Toml)
        .unwrap()
        .build("r")
        .unwrap();
    let bp = mr.breakpoints(0.0, 10.0 * mr.mesh.t0);
    assert_eq!(bp.len(), 19); // j t0 (j = 1..9) and j t0 + (ε−1) t0 (j = 0..9)
    // linear fast path: the FRF equals the time-domain steady state (SDOF with STE)
    let (ml, _) = Scene::parse(
        &with_effects("static_te = { er_um = 10.0 }", "auto"),
        "l",
        Format::Toml,
    )
    .unwrap()
    .build("l")
    .unwrap();
    assert!(ml.is_linear());
    let amp = linear_dte_amplitude(&ml).unwrap();
    let run = simulate(
        &ml,
        &static_state(&ml, 1e-9),
        &opts(1e-10, 3000, 20, 64),
        &Progress::none(),
    )
    .unwrap();
    assert!(
        rel(run.dte_harmonics(1)[1], amp) < 1e-6,
        "{} vs {amp}",
        run.dte_harmonics(1)[1]
    );
    assert!(linear_dte_amplitude(&m4).unwrap() > 0.0);
}

#[test]
fn friction_power_is_dissipative_for_every_pair() {
    let (m, d) = asset("full16.toml").build("full16").unwrap();
    let fr = m
        .terms
        .iter()
        .find(|t| t.name().starts_with("friction"))
        .unwrap();
    let _ = fr;
    let core = m.mesh.clone();
    let term = FrictionTerm {
        core,
        mu: 0.05,
        direction: model::FrictionDirection::PitchSwitch,
        geom: d.geometry,
        omega: m.omega,
        idx: [None, None, None, None],
    };
    let n = m.n();
    let mut q = vec![0.0; n];
    q[m.index_of("theta1").unwrap()] = 60e-6 / d.geometry.rb_m[0]; // compressed mesh
    let v = vec![0.0; n];
    for i in 0..1000 {
        let t = m.mesh.t0 * 3.0 * i as f64 / 1000.0;
        for (ff, _, _, vs) in term.pair_friction(t, &q, &v) {
            assert!(ff * vs <= 0.0, "t = {t}: F_f = {ff}, v_s = {vs}");
        }
    }
}

#[test]
fn scene_errors_name_the_key_and_expected_form() {
    let unknown = SDOF_6000.replace("z1 = 25", "z1 = 25\nteeth = 3");
    let e = Scene::parse(&unknown, "u.toml", Format::Toml)
        .unwrap_err()
        .to_string();
    assert!(e.contains("u.toml") && e.contains("teeth"), "{e}");
    let missing = SDOF_6000.replace(", zeta = 0.05", "");
    let e = Scene::parse(&missing, "m.toml", Format::Toml)
        .unwrap_err()
        .to_string();
    assert!(e.contains("zeta"), "{e}");
    let bad = SDOF_6000.replace("kmin = 2.5e8", "kmin = 5.5e8");
    let e = Scene::parse(&bad, "b.toml", Format::Toml)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("effects.mesh_stiffness.kmin") && e.contains("kmin ≤ kmax"),
        "{e}"
    );
    let neg = SDOF_6000.replace("half_gap_um = 50.0", "half_gap_um = -5.0");
    let e = Scene::parse(&neg, "n.toml", Format::Toml)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("effects.backlash.half_gap_um") && e.contains("positive"),
        "{e}"
    );
    let kind = SDOF_6000.replace("\"rectangular\"", "\"square\"");
    let e = Scene::parse(&kind, "k.toml", Format::Toml)
        .unwrap_err()
        .to_string();
    // an unknown kind: the file, the line, the bad value and the known kinds
    assert!(
        e.starts_with("k.toml: ")
            && e.contains("line ")
            && e.contains("`square`")
            && e.contains("`pairs`"),
        "{e}"
    );
    for (effect, bad, known) in [
        (
            "bearings = { law = \"magnetic\", kb = 2e8 }",
            "`magnetic`",
            "`hertz`",
        ),
        (
            "friction = { mu = 0.05, direction = \"sideways\" }",
            "`sideways`",
            "`pitch_switch`",
        ),
    ] {
        let text = with_effects(effect, "auto");
        let e = Scene::parse(&text, "x.toml", Format::Toml)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("x.toml: ") && e.contains(bad) && e.contains(known),
            "{e}"
        );
    }
    let grav = SDOF_6000.replace("backlash = ", "gravity = { g = [0.0, -9.81] }\nbacklash = ");
    let e = Scene::parse(&grav, "g.toml", Format::Toml)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("effects.gravity") && e.contains("lateral"),
        "{e}"
    );
    let json = r#"{"scene": {"name": "j", "model": "spur_pair"}, "gears": {"z1": 25, "z2": 40, "module_mm": 3.0,
        "pressure_angle_deg": 20.0, "face_width_mm": 20.0}, "operating": {"n1_rpm": 6000.0, "input_torque_Nm": 50.0},
        "effects": {"mesh_stiffness": {"kind": "constant", "k": 3.8252e8, "zeta": 0.05}, "wind": {}}}"#;
    let e = Scene::parse(json, "j.json", Format::Json)
        .unwrap_err()
        .to_string();
    assert!(e.contains("wind") && e.contains("line"), "{e}");
    let ok = json.replace(", \"wind\": {}", "");
    let (m, _) = Scene::parse(&ok, "j.json", Format::Json)
        .unwrap()
        .build("j.json")
        .unwrap();
    assert_eq!(m.n(), 1);
}

/// docs/math/companion.md §B.11 in miniature: max DTE error (µm) over mesh periods 40..60 vs a tight reference (SDOF 6000 rpm scene).
fn rk4_error(aligned: bool, steps: u32) -> f64 {
    let s = asset("sdof_6000.toml");
    let (m, _) = s.build("sdof").unwrap();
    let y0 = static_state(&m, 1e-9);
    let o = |method| RunOptions::window(method, 60, steps);
    let reference = simulate(
        &m,
        &y0,
        &o(Method::Dopri5 {
            rtol: 1e-12,
            atol: 1e-18,
            breakpoints: true,
            events: true,
        }),
        &Progress::none(),
    )
    .unwrap();
    let r = simulate(
        &m,
        &y0,
        &o(Method::Rk4 {
            steps_per_mesh: steps,
            aligned,
        }),
        &Progress::none(),
    )
    .unwrap();
    let tail = 40 * steps as usize;
    r.dte_m[tail..]
        .iter()
        .zip(&reference.dte_m[tail..])
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max)
        / 1e-6
}

#[test]
fn rk4_regains_fourth_order_only_when_aligned_to_switches() {
    let (a40, a80) = (rk4_error(true, 40), rk4_error(true, 80));
    let (u40, u80) = (rk4_error(false, 40), rk4_error(false, 80));
    assert!(a40 / a80 > 10.0, "aligned: {a40} → {a80}");
    assert!(u40 / u80 < 4.0, "not aligned: {u40} → {u80}");
    assert!(u80 > 100.0 * a80, "{u80} vs {a80}");
}

#[test]
fn quasi_static_dte_equals_b_plus_f0_over_k() {
    // ω → 0 and no excitation: constant stiffness, backlash, no STE
    let text = with_effects("backlash = { half_gap_um = 50.0 }", "auto")
        .replace("n1_rpm = 6000.0", "n1_rpm = 1.0");
    let (m, d) = Scene::parse(&text, "q", Format::Toml)
        .unwrap()
        .build("q")
        .unwrap();
    let run = simulate(&m, &[0.0; 2], &opts(1e-10, 50, 1, 16), &Progress::none()).unwrap();
    let want = 50e-6 + d.f0_n / 3.8252e8;
    assert!((want * 1e6 - 53.709).abs() < 1e-3);
    assert!(
        run.dte_m.iter().all(|x| (x - want).abs() < 1e-12),
        "{:?} vs {want}",
        &run.dte_m[..3]
    );
}

#[test]
fn cli_runs_a_scene_and_rejects_bad_input() {
    let exe = env!("CARGO_BIN_EXE_ncgear");
    let dir = std::env::temp_dir().join(format!("ncgear_dyn_{}", std::process::id()));
    let out = crate::cli::succeed(
        std::process::Command::new(exe)
            .args([
                "dynamics",
                &format!("{ASSETS}/backlash_oscillator.toml"),
                "--sweep",
                "0.80:0.84:0.04",
                "--json",
                "--out",
            ])
            .arg(&dir),
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["dofs"], serde_json::json!(["u"]));
    let up = v["sweep_up"].as_array().unwrap();
    let a = |p: &serde_json::Value| p["dte_half_pp_m"].as_f64().unwrap() / 50e-6;
    assert!(a(&up[0]) < 0.1 && a(&up[1]) > 0.25, "{up:?}");
    assert!(dir.join("sweep.svg").exists() && dir.join("sweep.csv").exists());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("DOFs (1): u") && stderr.contains("backlash(b = 50.000 µm)"),
        "{stderr}"
    );
    let bad = dir.join("bad.toml");
    std::fs::write(&bad, SDOF_6000.replace("kmax = 4.5e8", "kmax = -4.5e8")).unwrap();
    let out = std::process::Command::new(exe)
        .args(["dynamics"])
        .arg(&bad)
        .arg("--out")
        .arg(&dir)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("effects.mesh_stiffness.kmax"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn library_run_reports_what_the_cli_prints() {
    // linear fast path: header + amplitude, no run record
    let r = run(&asset("torsional4.toml"), "t4", &AnalysisOptions::default()).unwrap();
    assert_eq!(r.header.dofs, ["theta_p", "theta1", "theta2", "theta_q"]);
    assert!(r.linear_dte_amplitude_m.unwrap() > 0.0);
    assert!(r.run.is_none() && r.recording.is_none() && r.sweep_up.is_none());
    let v = serde_json::to_value(&r).unwrap();
    let keys: Vec<&str> = v.as_object().unwrap().keys().map(String::as_str).collect();
    assert_eq!(
        keys,
        [
            "derived",
            "dofs",
            "linear_dte_amplitude_m",
            "natural_frequencies_hz",
            "scene",
            "solver",
            "terms"
        ]
    );
    // an output signal that is not a DOF is an error naming the key, before any integration
    let mut s = Scene::parse(SDOF_6000, "sdof", Format::Toml).unwrap();
    s.output.signals = vec!["x9".into()];
    let e = run(&s, "sdof", &AnalysisOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("output.signals: `x9` is not a DOF") && e.contains("DOFs: u"),
        "{e}"
    );
    // unreadable file: the path in the message
    let e = Scene::from_path(std::path::Path::new("/nonexistent/s.toml"))
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("cannot read scene file /nonexistent/s.toml"),
        "{e}"
    );
}

/// Without `steady_state.max_periods` the transient is 2000 mesh periods, however long the
/// Poincaré period: the bundled 16-DOF scene (eccentricity on a 25/40 pair: the hunting period,
/// lcm(25, 40) = 200 mesh periods) gets 10 Poincaré periods, a mesh-only scene 2000; a value the
/// scene gives is kept.
#[test]
fn default_transient_is_counted_in_mesh_periods() {
    let full16 = include_str!("../../assets/dynamics/full16.toml");
    let line = "steady_state = { poincare_tol = 1e-6, max_periods = 20 }";
    assert!(full16.contains(line));
    let prepared = |text: &str| {
        let scene = Scene::parse(text, "s.toml", Format::Toml).unwrap();
        Prepared::new(scene, "s.toml").unwrap()
    };
    let p = prepared(&full16.replace(line, ""));
    assert!((p.model.poincare_period / p.model.mesh.t0 - 200.0).abs() < 1e-9);
    assert_eq!(p.options.max_periods, 10);
    assert_eq!(default_transient_periods(&p.model), 10);
    assert_eq!(prepared(full16).options.max_periods, 20);
    let sdof = prepared(SDOF_6000);
    assert!((sdof.model.poincare_period / sdof.model.mesh.t0 - 1.0).abs() < 1e-12);
    assert_eq!(sdof.options.max_periods, DEFAULT_TRANSIENT_MESH_PERIODS);
}
