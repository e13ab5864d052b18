//! The rotor model of `ncgear dynamics` (docs/dynamics.md, "The rotor"): the stiff limit against
//! the rigid loads, the energy balance of a settled turn, the circular limit's frequencies.

use ncgear::analysis::dynamics::rotor::energy::energy_audit;
use ncgear::analysis::dynamics::rotor::{Effects, Prepared, RotorRun, build};
use ncgear::geometry::assembly::Assembly;
use ncgear::geometry::pitch::PitchCurve;
use ncgear::loads::{Rotor, Scene};
use ncgear::math::Point;
use ncgear::progress::Progress;
use std::path::{Path, PathBuf};

fn asset(p: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(p)
}

/// The bundled G1 rotor scene's tables with `effects` (TOML lines) in a temporary scene file.
pub(crate) fn g1_scene(name: &str, effects: &str, max_turns: u32) -> PathBuf {
    scene_for(
        &asset("assets/loads/g1_m2_design.json"),
        name,
        effects,
        max_turns,
    )
}

/// The bundled rotor scene's tables on the design file `design`.
fn scene_for(design: &Path, name: &str, effects: &str, max_turns: u32) -> PathBuf {
    let text = format!(
        "[scene]\nname = \"{name}\"\nmodel = \"rotor\"\ndesign = {design:?}\n\
         [operation]\ncarrier_rpm = 300.0\narms = 2\ngravity = [0.0, -1.0]\n\
         [arm]\nmass_kg = 0.55\ncom_mm = [35.0, -70.0]\ninertia_kg_mm2 = 2100.0\n\
         [gears]\nface_width_mm = 25.0\ndensity_kg_m3 = 7100.0\nbore_mm = 10.0\n\
         [needle]\nprofile = \"planting\"\n[effects]\n{effects}\n\
         [steady]\npoincare_tol = 1e-7\nmax_turns = {max_turns}\n"
    );
    let dir = std::env::temp_dir().join(format!("ncgear_rotor_{}_{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    path
}

pub(crate) fn run(path: &Path) -> (Prepared, RotorRun) {
    let p = Prepared::from_path(path).unwrap();
    let r = p.run(&Progress::none()).unwrap();
    (p, r)
}

/// Largest `|F_dyn − F_rigid|` of both meshes relative to each mesh's rigid peak.
fn stiff_error(r: &RotorRun) -> f64 {
    let m = &r.report.summary.meshes;
    m.sun_intermediate
        .largest_deviation_of_peak
        .max(m.intermediate_planet.largest_deviation_of_peak)
}

/// Stiff limit on the bundled G1 rotor: at 100× ISO's (mean) mesh stiffness, no backlash,
/// ζ = 0.05, the dynamic mesh forces equal the rigid loads' within 1 % of their peak at every
/// sample of the settled turn, and the tip deviation falls with the compliance (100× stiffer:
/// about 100× smaller).
#[test]
fn the_stiff_g1_rotor_carries_the_rigid_loads() {
    let soft = g1_scene(
        "soft",
        "mesh_stiffness = { kind = \"iso\", pairs = \"mean\" }\nmesh_damping = { zeta = 0.05 }",
        20,
    );
    let stiff = g1_scene(
        "stiff",
        "mesh_stiffness = { kind = \"iso\", scale = 100.0, pairs = \"mean\" }\n\
         mesh_damping = { zeta = 0.05 }",
        20,
    );
    let (_, rs) = run(&soft);
    let (_, rk) = run(&stiff);
    assert!(rk.report.steady.settled && rs.report.steady.settled);
    let e = stiff_error(&rk);
    assert!(e < 0.01, "stiff limit: {e}");
    let (ts, tk) = (
        rs.report.summary.max_tip_deviation_mm,
        rk.report.summary.max_tip_deviation_mm,
    );
    assert!(tk < 0.02 * ts && tk < 1e-3, "tip deviation {ts} → {tk} mm");
    // the rigid forces are the loads' of the same tables
    let peak = rk.report.summary.meshes.intermediate_planet.peak_rigid_n;
    assert!(peak > 10.0, "{peak}");
}

/// A module-2 design of `trajectory` (the CLI, `extra` arguments) in a temporary directory: its
/// design.json.
fn designed(name: &str, trajectory: &str, extra: &[&str]) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("ncgear_rotor_{}_{name}_design", std::process::id()));
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_ncgear"))
        .args([
            "design",
            &asset(trajectory).display().to_string(),
            "--module",
            "2",
        ])
        .args(extra)
        .arg("--out")
        .arg(&dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    dir.join("design.json")
}

const STIFF: &str = "mesh_stiffness = { kind = \"iso\", scale = 100.0, pairs = \"mean\" }\n\
                     mesh_damping = { zeta = 0.05 }";
const SOFT: &str =
    "mesh_stiffness = { kind = \"iso\", pairs = \"mean\" }\nmesh_damping = { zeta = 0.05 }";

/// Stiff limit on designs nobody here made. An exact two-harmonic target (counter-clockwise, its
/// idler on the carrier line): at 100× ISO's stiffness the dynamic forces equal the rigid loads'
/// within 1 % of their peak. A clockwise target with its own carrier axis and the idler off the
/// line (−8.2°), whose rigid peak is small (207 N) beside the planting pulse's 200 N rise over 5°:
/// within 1 % too at 100×, and at most 0.15 of the 1× error; the tip deviation falls as 1/k. With
/// the pulses as triangles (before 2026-12-02) their corners rang the stiffened train and it was
/// 1.25 % (the raised cosine has none: src/loads/needle.rs).
#[test]
fn the_stiff_limit_holds_on_other_designs() {
    let exact = designed("exact", "assets/cases/exact_two_harmonic.csv", &[]);
    let (_, r) = run(&scene_for(&exact, "exact_stiff", STIFF, 20));
    assert!(r.report.steady.settled);
    assert!(stiff_error(&r) < 0.01, "exact: {}", stiff_error(&r));
    assert!(r.report.summary.max_tip_deviation_mm < 1e-3);
    let cw = designed(
        "cw",
        "assets/cases/exact_cw_offset.csv",
        &["--center=-181.577382,-37.369661"],
    );
    let (_, soft) = run(&scene_for(&cw, "cw_soft", SOFT, 30));
    let (_, stiff) = run(&scene_for(&cw, "cw_stiff", STIFF, 30));
    assert!(soft.report.steady.settled && stiff.report.steady.settled);
    let (es, ek) = (stiff_error(&soft), stiff_error(&stiff));
    assert!(
        ek < 0.15 * es && ek < 0.01,
        "clockwise off-line: {es} → {ek}"
    );
    let (ts, tk) = (
        soft.report.summary.max_tip_deviation_mm,
        stiff.report.summary.max_tip_deviation_mm,
    );
    assert!(tk < 0.02 * ts, "tip deviation {ts} → {tk} mm");
    // The dynamic tip by carrier angle (`compare --dynamics`' reference) on this clockwise
    // train: travel sample k at carrier angle −2πk/n, in the design's world frame, so the
    // stiff run's tip sits on the static tip at the same angle.
    let rebuilt = ncgear::simulate::DesignFile::from_path(&cw)
        .unwrap()
        .1
        .rebuild();
    let path = ncgear::compare::design_path::DesignPath::new(&rebuilt);
    assert_eq!(path.direction, -1);
    let moved = path.moved_to(&stiff.report.tip_mm).unwrap();
    let n = stiff.report.tip_mm.len();
    let apart = (0..n)
        .map(|k| {
            let phi = path.angle_at(k, n) + 0.3 * std::f64::consts::TAU / n as f64;
            moved.tip(phi).0.distance(path.tip(phi).0)
        })
        .fold(0.0, f64::max);
    assert!(apart < 0.01, "same-angle tip distance {apart} mm");
}

/// Energy: over the settled turn of the G1 rotor with every effect (ISO stiffness with the
/// pairs alternating, mesh damping, the teeth's backlash: impacts at the torque reversals,
/// vibration damping), the drive's work equals the mesh damping's, the impacts' and the vibration
/// dampers' dissipation plus the needle's and gravity's work and the energy's change, within
/// 1e-4 of the drive's largest power × the period.
#[test]
fn the_settled_turn_balances_its_energy() {
    let path = g1_scene(
        "energy",
        "mesh_stiffness = { kind = \"iso\" }\nmesh_damping = { zeta = 0.05 }\nbacklash = \"teeth\"\n\
         vibration_damping = { zeta = 0.05 }\n[solver]\nrtol = 1e-10\natol = 1e-14",
        8,
    );
    let (p, r) = run(&path);
    assert!(r.report.steady.settled, "{:?}", r.report.steady);
    assert!(r.report.summary.impacts_per_turn > 0);
    assert_turn_balances(&p, &r);
}

/// The settled turn of `r` audited at rtol 1e-10: the residual within 1e-4 of the drive's
/// largest power × the period, the damping dissipating and the needle taking work.
pub(crate) fn assert_turn_balances(p: &Prepared, r: &RotorRun) {
    let m = &p.built.model;
    let t0 = r.start_time_s;
    let a = energy_audit(m, t0, t0 + m.period_s(), &r.start_state, 1e-10, 1e-14).unwrap();
    let scale = a.max_drive_power_w * a.span_s;
    assert!(a.max_drive_power_w > 1.0, "{a:?}");
    assert!(a.residual_j.abs() < 1e-4 * scale, "{a:?}");
    // the damping dissipates, the needle takes work
    assert!(a.damping_j > 0.0 && a.needle_j < 0.0, "{a:?}");
}

/// The knock on the bundled rotor (assets/dynamics/rotor_g1.toml): it settles, and every impact
/// harder than 5 mm/s on the planet's mesh follows one of the rigid loads' two torque reversals
/// (where `ncgear loads` puts the planet mesh's force through zero) within 40° of travel: the
/// arm crossing the backlash and bouncing. The hardest strikes at least 3× the rigid peak.
#[test]
fn the_bundled_rotor_knocks_after_its_torque_reversals() {
    let (_, r) = run(&asset("assets/dynamics/rotor_g1.toml"));
    let rep = &r.report;
    assert!(
        rep.steady.settled && rep.steady.turns <= 4,
        "{:?}",
        rep.steady
    );
    let mesh = &rep.meshes.intermediate_planet;
    // the rigid force's zeros: the samples where the rigid flank changes
    let n = rep.travel_deg.len();
    let rigid = &mesh.rigid_force_n;
    let minima: Vec<f64> = (0..n)
        .filter(|&i| {
            let (a, b, c) = (rigid[(i + n - 1) % n], rigid[i], rigid[(i + 1) % n]);
            b <= a && b <= c && b < 0.05 * mesh_peak(rigid)
        })
        .map(|i| rep.travel_deg[i])
        .collect();
    assert!(!minima.is_empty(), "no reversal in the rigid loads");
    let s = &rep.summary.meshes.intermediate_planet;
    let hard: Vec<_> = s.impacts.iter().filter(|i| i.speed_m_s > 5e-3).collect();
    assert!(!hard.is_empty());
    for i in &hard {
        let after = minima
            .iter()
            .map(|&m| (i.travel_deg - m).rem_euclid(360.0))
            .fold(f64::INFINITY, f64::min);
        assert!(
            after < 60.0,
            "impact at {}° is {after}° after a reversal {minima:?}",
            i.travel_deg
        );
    }
    assert!(s.dynamic_factor > 3.0, "{}", s.dynamic_factor);
}

pub(crate) fn mesh_peak(f: &[f64]) -> f64 {
    f.iter().fold(0.0_f64, |m, &x| m.max(x.abs()))
}

/// A train of three equal circles of radius `r_mm` (i ≡ 1), CCW about the origin, the arm
/// 100 mm long at 0.3 rad.
pub(crate) fn circle_train(r_mm: f64) -> Assembly {
    let circle = || PitchCurve::from_fn(720, |_| r_mm).unwrap();
    Assembly {
        center_mm: Point::ZERO,
        direction: 1,
        a_mm: 2.0 * r_mm,
        idler_offset_rad: 0.0,
        l3_mm: 100.0,
        needle_angle_rad: 0.3,
        sun: circle(),
        intermediate: circle(),
        intermediate_angle_at_zero_rad: 0.0,
        planet: circle(),
        planet_angle_at_zero_rad: 0.0,
    }
}

/// Circular limit: a train of three equal circles (i ≡ 1) with constant mesh stiffness has the
/// two-mesh torsional chain's frequencies, ground–k1–J2–k2–J3 on the base radius r_b = r·cos α:
/// `ω² = ½[(k1+k2)/m2 + k2/m3 ± √(((k1+k2)/m2 + k2/m3)² − 4k1k2/(m2m3))]`, `m_i = J_i/r_b²`,
/// within 0.1 %.
#[test]
fn the_circular_train_has_the_torsional_chain_frequencies() {
    let r_mm = 25.0;
    let asm = circle_train(r_mm);
    let scene: Scene = toml::from_str(
        "[operation]\ncarrier_rpm = 200.0\n[gears]\nface_width_mm = 20.0\n\
         [arm]\nmass_kg = 0.4\ncom_mm = [0.0, 0.0]\ninertia_kg_mm2 = 3000.0",
    )
    .unwrap();
    let case = scene.validate("circle.toml").unwrap();
    let k = [3.0e8, 2.0e8];
    let rotor = Rotor::pitch(&asm).with_pressure_angle_rad(20f64.to_radians());
    let built = build(&rotor, &case, &Effects::constant(k), None, "circle.toml").unwrap();
    let f = built.model.natural_frequencies_hz();
    let [j2, j3] = built.model.inertias_kg_m2();
    let rb = r_mm * 1e-3 * 20f64.to_radians().cos();
    let (m2, m3) = (j2 / (rb * rb), j3 / (rb * rb));
    let s = (k[0] + k[1]) / m2 + k[1] / m3;
    let d = (s * s - 4.0 * k[0] * k[1] / (m2 * m3)).sqrt();
    let closed = [0.5 * (s - d), 0.5 * (s + d)].map(|w2: f64| w2.sqrt() / std::f64::consts::TAU);
    for i in 0..2 {
        assert!((f[i] / closed[i] - 1.0).abs() < 1e-3, "{f:?} vs {closed:?}");
    }
}

/// Bad input names the field and stops before any work: a negative stiffness, a damping ratio
/// above 1, a negative backlash, an unknown field (with its line), a drive without the
/// carrier's inertia, `"teeth"` backlash or ISO stiffness on a design without teeth.
#[test]
fn bad_rotor_scenes_name_their_field() {
    use ncgear::analysis::dynamics::rotor::RotorScene;
    let message = |effects: &str| {
        let path = g1_scene("bad", effects, 5);
        let file = path.display().to_string();
        match RotorScene::from_path(&path).and_then(|s| s.validate(&file)) {
            Err(e) => e.to_string(),
            Ok(_) => panic!("{effects}: accepted"),
        }
    };
    let m = message("mesh_stiffness = { kind = \"constant\", c_n_per_mm_mm = -5.0 }");
    assert!(
        m.contains("effects.mesh_stiffness.c_n_per_mm_mm") && m.contains("-5"),
        "{m}"
    );
    let m = message("mesh_stiffness = { kind = \"iso\" }\nmesh_damping = { zeta = 1.5 }");
    assert!(m.contains("effects.mesh_damping.zeta"), "{m}");
    let m = message("mesh_stiffness = { kind = \"iso\" }\nbacklash = -0.1");
    assert!(m.contains("effects.backlash"), "{m}");
    let m = message("mesh_stiffness = { kind = \"iso\", stifness = 2.0 }");
    assert!(m.contains("stifness") && m.contains("line"), "{m}");
    let m = message("mesh_stiffness = { kind = \"iso\" }\ndrive = { stiffness_nm_per_rad = 1e4 }");
    assert!(m.contains("effects.drive.carrier_inertia_kg_mm2"), "{m}");
    let m = message("mesh_stiffness = { kind = \"iso\" }\nvibration_damping = { zeta = -0.1 }");
    assert!(
        m.contains("effects.vibration_damping.zeta") && m.contains("-0.1"),
        "{m}"
    );
    let m = message("mesh_stiffness = { kind = \"iso\", scale = nan }");
    assert!(m.contains("effects.mesh_stiffness.scale"), "{m}");
    // a pitch-only train: the teeth's backlash and ISO's stiffness are not there to read
    let circle = || PitchCurve::from_fn(360, |_| 25.0).unwrap();
    let asm = Assembly {
        center_mm: Point::ZERO,
        direction: 1,
        a_mm: 50.0,
        idler_offset_rad: 0.0,
        l3_mm: 100.0,
        needle_angle_rad: 0.0,
        sun: circle(),
        intermediate: circle(),
        intermediate_angle_at_zero_rad: 0.0,
        planet: circle(),
        planet_angle_at_zero_rad: 0.0,
    };
    let scene: Scene =
        toml::from_str("[operation]\ncarrier_rpm = 100.0\n[gears]\nface_width_mm = 10.0").unwrap();
    let case = scene.validate("c.toml").unwrap();
    let rotor = Rotor::pitch(&asm);
    let fx = Effects::constant([1e8; 2]).with_backlash(Some(
        ncgear::analysis::dynamics::rotor::scene::Backlash::Teeth,
    ));
    let e = build(&rotor, &case, &fx, None, "c.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("effects.backlash") && e.contains("no"), "{e}");
    let fx = Effects::iso(
        1.0,
        ncgear::analysis::dynamics::rotor::spec::PairsMode::Mean,
    );
    let e = build(&rotor, &case, &fx, None, "c.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("effects.mesh_stiffness"), "{e}");
}

/// Circular limit with backlash, where the rotor and the spur model coincide: three equal circles
/// (i ≡ 1: the planet translates), no gravity, the arm's centre of mass on the planet axis, a
/// sun mesh 10⁴× stiffer than the planet mesh (the intermediate follows its kinematic law), a
/// needle torque `M = r_b·k·b·(F_m + F_e·Ω²·cos φ)` on the planet: the planet mesh is then the
/// Kahraman–Singh backlash oscillator of the spur model's `assets/dynamics/backlash_oscillator.toml`
/// — half gap b = 50 µm, ζ = 0.05 on the mode (vibration damping), F_m = 0.1, F_e = 0.05, forcing
/// at Ω = ω/ω_n — with the carrier turn as the forcing period. From the quasi-static start, at
/// Ω = 0.76 both stay on the branch without impacts (amplitude ≈ 0.067 b) and at Ω = 0.84, past
/// the linear branch's contact loss (0.8206), both jump to the impacting branch (≈ 0.26 b): the
/// rotor's half peak-to-peak planet-mesh deflection equals the spur model's DTE within 0.1 %
/// (measured 2e-4: 0.06729 against 0.06728, 0.26128 against 0.26123), and contact is lost at
/// 0.84 only.
#[test]
fn the_circular_rotor_is_the_spur_models_backlash_oscillator() {
    use ncgear::analysis::dynamics::rotor::run_model;
    use ncgear::analysis::dynamics::rotor::scene::{Backlash, Settings};
    use ncgear::analysis::dynamics::{Method, RunOptions, sweep};
    use ncgear::loads::motion::TrainMotion;
    let r_mm = 25.0;
    let asm = circle_train(r_mm);
    let alpha = 20f64.to_radians();
    let rb = r_mm * 1e-3 * alpha.cos();
    let rotor = Rotor::pitch(&asm).with_pressure_angle_rad(alpha);
    let (k, b) = (1.0e4, 50e-6);
    let effects = Effects::constant([1e4 * k, k])
        .with_zeta([0.05, 0.0])
        .with_vibration_zeta(0.05)
        .with_backlash(Some(Backlash::Normal([0.0, 2.0 * b])));
    let tables = "[gears]\nface_width_mm = 20.0\n[arm]\nmass_kg = 0.4\ncom_mm = [0.0, 0.0]\n\
                  inertia_kg_mm2 = 3000.0\n[operation]\ngravity = [0.0, 0.0]\n";
    let case_at = |rpm: f64, needle: &str| {
        let s: Scene = toml::from_str(&format!("{tables}carrier_rpm = {rpm}\n{needle}")).unwrap();
        s.validate("circle.toml").unwrap()
    };
    let probe = build(&rotor, &case_at(100.0, ""), &effects, None, "circle.toml").unwrap();
    let f1_hz = probe.model.natural_frequencies_hz()[0];
    // the needle force perpendicular to the (constant) arm B − A, giving the planet the torque M
    let m0 = TrainMotion::at(&asm.rebuild(), 0.0);
    let arm = (m0.tip_mm - m0.a_mm) * 1e-3;
    let perp = arm.perp() / arm.norm();
    let spur_scene = {
        let mut s = ncgear::analysis::dynamics::Scene::from_path(&asset(
            "assets/dynamics/backlash_oscillator.toml",
        ))
        .unwrap();
        let d = s.derived("b").unwrap();
        s.operating.input_torque_Nm = 0.1 * 3.8252e8 * 50e-6 * d.geometry.rb_m[0];
        s
    };
    let spur_opts = RunOptions::default()
        .with_method(Method::Dopri5 {
            rtol: 1e-8,
            atol: 1e-14,
            breakpoints: true,
            events: true,
        })
        .with_poincare_tol(1e-9)
        .with_max_periods(300)
        .with_record_mesh_periods(20)
        .with_samples_per_mesh(128);
    for (ratio, impacting) in [(0.76, false), (0.84, true)] {
        let rpm = ratio * f1_hz * 60.0;
        let rows: Vec<String> = (0..360)
            .map(|d| {
                let phi = f64::from(d).to_radians();
                let m = rb * k * b * (0.1 + 0.05 * ratio * ratio * phi.cos());
                let f = perp * (m / arm.norm());
                format!("[{d}.0, {}, {}]", f.x, f.y)
            })
            .collect();
        let needle = format!("[needle]\nforce_N = [{}]\n", rows.join(", "));
        let case = case_at(rpm, &needle);
        let built = build(&rotor, &case, &effects, None, "circle.toml").unwrap();
        let run = run_model(
            &built.model,
            &case,
            &Settings::default().with_steady(1e-8, 400),
            None,
            None,
            &Progress::none(),
        )
        .unwrap();
        assert!(
            run.report.steady.settled,
            "{ratio}: {:?}",
            run.report.steady
        );
        let defl = &run.report.meshes.intermediate_planet.deflection_um;
        let (lo, hi) = defl
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, c), &x| (a.min(x), c.max(x)));
        let rotor_amp = 0.5 * (hi - lo) * 1e-6 / b;
        let spur = sweep(
            &spur_scene,
            "b",
            &[ratio],
            &spur_opts,
            None,
            &Progress::none(),
        )
        .unwrap()
        .remove(0);
        let spur_amp = spur.dte_half_pp_m / 50e-6;
        assert!(
            (rotor_amp / spur_amp - 1.0).abs() < 1e-3,
            "Ω = {ratio}: rotor {rotor_amp}, spur {spur_amp}"
        );
        let lost = !run
            .report
            .summary
            .meshes
            .intermediate_planet
            .contact_loss_deg
            .is_empty();
        assert_eq!(lost, impacting, "Ω = {ratio}");
        assert_eq!(spur.contact_loss_fraction > 0.0, impacting, "Ω = {ratio}");
    }
}
