//! Transplanter tolerance analysis (companion spec C.6): exact perturbed kinematics, closed forms,
//! the circular-gear phasor limit, linear vs exact, Monte Carlo stability, file errors.
use ncgear::analysis::montecarlo::McOptions;
use ncgear::analysis::tolerance::{ToleranceError, phasor_sum};
use ncgear::analysis::transplanter::*;
use ncgear::assembly::Assembly;
use ncgear::config::Format;
use ncgear::golden::{ellipse_ratio, g1_mechanism};
use ncgear::simulate::{FeatureOptions, Simulation, features};
use rand::SeedableRng;
use rand::rngs::ChaCha8Rng;
use std::f64::consts::{FRAC_PI_2, PI};

const ERRORS: &str = include_str!("../../assets/transplanter/g1_errors.toml");

fn g1(direction: i8) -> Assembly {
    Assembly::from_mechanism(&g1_mechanism(), [10.0, -5.0], direction, 720).unwrap()
}

/// All three gears circles of radius r = a/2 = 22.5 mm (ratio 1: the needle translates).
fn circular() -> Assembly {
    let mut m = g1_mechanism();
    m.ratio = ellipse_ratio(0.0);
    Assembly::from_mechanism(&m, [0.0, 0.0], 1, 720).unwrap()
}

fn inventory() -> Inventory {
    ErrorInventory::parse(ERRORS, "g1_errors.toml", Format::Toml).unwrap()
}

/// Monte Carlo options: `samples`, `seed`, histogram `bins`.
fn mc(samples: usize, seed: u64, bins: usize) -> McOptions {
    let mut o = McOptions::default();
    (o.samples, o.seed, o.bins) = (samples, seed, bins);
    o
}

fn e(a: f64) -> [f64; 2] {
    [a.cos(), a.sin()]
}
fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}
fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

const ZERO: ErrorVector = [0.0; N_COORDS];

#[test]
fn zero_errors_reproduce_the_rebuilt_train_and_give_zero_deviation() {
    for dir in [1, -1] {
        let asm = g1(dir);
        let m = ExactModel::new(&asm, 20f64.to_radians(), 1).unwrap();
        let rb = asm.rebuild();
        let mut worst: f64 = 0.0;
        for p in m.grid(360) {
            let s = m.state(p, &ZERO).unwrap();
            worst = worst.max(dist(s.tip_mm, rb.pose(p).tip_mm));
        }
        // The flank-line solve with zero errors is the rolling of the design tables.
        assert!(worst < 1e-7, "direction {dir}: {worst} mm");
    }
    // Whole pipeline with an empty inventory: every deviation is zero.
    let inv = Inventory::zero(20f64.to_radians(), 1, 360);
    let mut opts = TransplanterOptions::default();
    opts.mc = mc(1000, 3, 10);
    opts.validation_samples = 10;
    opts.feature_samples = 0;
    let r = analyse(&g1(1), &inv, &opts, &|_| {}).unwrap();
    assert!(
        r.max_deviation_um.max < 1e-9 * 1e3,
        "{}",
        r.max_deviation_um.max
    );
    assert!(r.nominal_errors_exact_um < 1e-6 && r.envelope_max_um < 1e-6);
    assert!(r.assembly.is_none());
}

/// Pure radial pin error δ of A on the circular train: A moves by δ along OA, the centre distance
/// of the intermediate–planet mesh grows by δ and the flank condition gives the planet rotation
/// `σ₂Δ = asin((1 + δ/r)·sin α) − α` (σ₂ = −load_side), exactly; the tip is
/// `B + δ·e(φH) + l3·(e(β + Δ) − e(β))`.
#[test]
fn radial_pin_error_of_a_matches_the_closed_form() {
    let asm = circular();
    let r = asm.a_mm / 2.0;
    let l3 = asm.l3_mm;
    for (side, alpha_deg, delta) in [(1i8, 20.0f64, 0.05), (-1, 20.0, 0.05), (1, 25.0, -0.03)] {
        let alpha = alpha_deg.to_radians();
        let m = ExactModel::new(&asm, alpha, side).unwrap();
        let mut x = ZERO;
        x[PIN_A[0]] = delta;
        let s2 = -f64::from(side);
        let big = s2 * (((1.0 + delta / r) * alpha.sin()).asin() - alpha);
        let mut worst: f64 = 0.0;
        let mut moved: f64 = 0.0;
        for p in m.grid(360) {
            let nom = m.state(p, &ZERO).unwrap();
            let per = m.state(p, &x).unwrap();
            let b = nom.needle_angle_rad;
            let expect = [
                nom.tip_mm[0] + delta * p.cos() + l3 * ((b + big).cos() - b.cos()),
                nom.tip_mm[1] + delta * p.sin() + l3 * ((b + big).sin() - b.sin()),
            ];
            worst = worst.max(dist(per.tip_mm, expect));
            moved = moved.max(dist(per.tip_mm, nom.tip_mm));
            // The planet centre moves by δ along OA.
            let a0 = nom.planet_center_mm;
            let a1 = per.planet_center_mm;
            assert!((a1[0] - a0[0] - delta * p.cos()).abs() < 1e-12);
            assert!((a1[1] - a0[1] - delta * p.sin()).abs() < 1e-12);
        }
        println!(
            "radial pin closed form, side {side}, α {alpha_deg}°, δ {delta} mm: {worst:.2e} mm"
        );
        assert!(worst < 1e-9, "side {side}: {worst} mm");
        // Not a rigid translation: the rotation adds l3·Δ ≈ l3·δ·tan α / r.
        let rigid_plus_rotation = (delta.abs() + l3 * big.abs()) * 1.0001;
        assert!(
            moved > delta.abs() * 1.5 && moved < rigid_plus_rotation,
            "{moved}"
        );
    }
}

/// Circular gears: the planet's angle error is the line-of-action sum of the eccentricities and
/// backlashes over the base radius r_b = r·cos α (the non-circular ρ_b), and — every term having
/// order 1 in φH — a single phasor (C-1) plus the accumulated lost motion.
#[test]
fn circular_train_reduces_to_the_phasor_model() {
    let asm = circular();
    let r = asm.a_mm / 2.0;
    let alpha = 20f64.to_radians();
    let rb = r * alpha.cos();
    let (e1, g1_, e2, g2, e3, g3): (f64, f64, f64, f64, f64, f64) =
        (0.010, 0.4, 0.008, 2.0, 0.006, -1.1);
    let (j1, j2) = (0.004, 0.003);
    let mut x = ZERO;
    x[ecc_index(0)] = e1 * g1_.cos();
    x[ecc_index(0) + 1] = e1 * g1_.sin();
    x[ecc_index(1)] = e2 * g2.cos();
    x[ecc_index(1) + 1] = e2 * g2.sin();
    x[ecc_index(2)] = e3 * g3.cos();
    x[ecc_index(2) + 1] = e3 * g3.sin();
    x[BACKLASH[0]] = j1;
    x[BACKLASH[1]] = j2;
    for side in [1i8, -1] {
        let s = f64::from(side);
        let m = ExactModel::new(&asm, alpha, side).unwrap();
        let grid = m.grid(720);
        let mut exact = Vec::new();
        let mut worst: f64 = 0.0;
        let mut th0 = (0.0, 0.0);
        for (k, &p) in grid.iter().enumerate() {
            let nom = m.state(p, &ZERO).unwrap();
            let per = m.state(p, &x).unwrap();
            // Angles are reported modulo 2π.
            let d3 = (per.planet_angle_rad - nom.planet_angle_rad + PI).rem_euclid(2.0 * PI) - PI;
            exact.push(d3);
            let (t2, t3) = (nom.intermediate_angle_rad, nom.planet_angle_rad);
            if k == 0 {
                th0 = (t2, t3);
            }
            let n = |sig: f64| {
                let a = e(p + FRAC_PI_2);
                let b = e(p);
                [
                    sig * alpha.cos() * a[0] + alpha.sin() * b[0],
                    sig * alpha.cos() * a[1] + alpha.sin() * b[1],
                ]
            };
            let (n1, n2) = (n(s), n(-s));
            let v1 = e(g1_);
            let v2 = e(t2 + g2);
            let v3 = e(t3 + g3);
            let d2 = ((e2 * dot(v2, n1) - e1 * dot(v1, n1)) - j1 / 2.0) / (s * rb);
            let model = -d2 + ((e3 * dot(v3, n2) - e2 * dot(v2, n2)) - j2 / 2.0) / (-s * rb);
            worst = worst.max((d3 - model).abs());
        }
        let amp = exact.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        println!("circular LOA sum, side {side}: residual {worst:.2e} rad of {amp:.2e} rad");
        assert!(
            worst < 1e-3 * amp,
            "side {side}: {worst} vs amplitude {amp}"
        );
        if side == 1 {
            // Phasor form: Δθ3 = (j1 + j2)/(2 r_b) + B·sin(φH + ξ)/r_b with (B, ξ) = Σ A_k e^{iφ_k}.
            let (t20, t30) = th0;
            let terms = [
                (e1, PI - g1_ - alpha),
                (-e2, t20 + g2 + alpha),
                (-e3, alpha - t30 - g3),
                (e2, PI + t20 + g2 - alpha),
            ];
            let (b, xi) = phasor_sum(&terms);
            let lost = (j1 + j2) / (2.0 * rb);
            let mut w: f64 = 0.0;
            for (&p, d) in grid.iter().zip(&exact) {
                w = w.max((d - lost - b * (p + xi).sin() / rb).abs());
            }
            println!(
                "phasor C-1: residual {w:.2e} rad of B/r_b = {:.2e} rad",
                b / rb
            );
            assert!(w < 1e-3 * b / rb, "phasor: {w} vs {}", b / rb);
            let (lo, hi) = exact
                .iter()
                .fold((f64::MAX, f64::MIN), |(l, h), v| (l.min(*v), h.max(*v)));
            assert!(((hi - lo) / 2.0 - b / rb).abs() < 1e-3 * b / rb);
            assert!(((hi + lo) / 2.0 - lost).abs() < 1e-3 * b / rb);
            // The linear model's planet transmission error: max |Δθ3| = lost motion + B/r_b.
            let lin = LinearModel::build(&m, 720, FdSteps::default()).unwrap();
            let te = lin.max_planet_angle_error_rad(&x);
            assert!((te - (lost + b / rb)).abs() < 1e-3 * b / rb, "{te}");
        }
    }
}

#[test]
fn idler_clocking_is_invisible_and_planet_clocking_is_an_arm_error() {
    let asm = g1(1);
    let m = ExactModel::new(&asm, 20f64.to_radians(), 1).unwrap();
    let k = 0.1f64.to_radians();
    let mut idler = ZERO;
    idler[clock_index(1)] = k;
    let mut planet = ZERO;
    planet[clock_index(2)] = k;
    let mut arm = ZERO;
    arm[ARM] = -k;
    let mut sun = ZERO;
    sun[clock_index(0)] = k;
    let (mut w_idler, mut w_pa, mut sun_dev): (f64, f64, f64) = (0.0, 0.0, 0.0);
    for p in m.grid(180) {
        let n = m.state(p, &ZERO).unwrap().tip_mm;
        w_idler = w_idler.max(dist(m.state(p, &idler).unwrap().tip_mm, n));
        w_pa = w_pa.max(dist(
            m.state(p, &planet).unwrap().tip_mm,
            m.state(p, &arm).unwrap().tip_mm,
        ));
        sun_dev = sun_dev.max(dist(m.state(p, &sun).unwrap().tip_mm, n));
    }
    assert!(w_idler < 1e-9, "{w_idler}");
    assert!(w_pa < 1e-9, "{w_pa}");
    // The sun's clocking shifts the ratio phase: a real error (≈ l3·κ·|i31 − 1| scale).
    assert!(sun_dev > 0.05, "{sun_dev}");
}

#[test]
fn clockwise_design_mirrors_the_deviations() {
    let (ccw, cw) = (g1(1), g1(-1));
    let (mc, mw) = (
        ExactModel::new(&ccw, 20f64.to_radians(), 1).unwrap(),
        ExactModel::new(&cw, 20f64.to_radians(), 1).unwrap(),
    );
    let inv = inventory();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let x = inv.draw_three_sigma(&mut rng);
    let grid = mc.grid(90);
    let dc = mc.deviations(&grid, &x).unwrap();
    let mirrored: Vec<f64> = grid.iter().map(|p| -p).collect();
    let dw = mw.deviations(&mirrored, &x).unwrap();
    for (a, b) in dc.iter().zip(&dw) {
        assert!((a[0] - b[0]).abs() < 1e-9 && (a[1] + b[1]).abs() < 1e-9);
    }
}

#[test]
fn linear_model_agrees_with_the_exact_model_at_three_sigma() {
    let asm = g1(1);
    let inv = inventory();
    let m = ExactModel::new(&asm, inv.pressure_angle_rad, inv.load_side).unwrap();
    let lin = LinearModel::build(&m, 360, FdSteps::default()).unwrap();
    let mut max_rel: f64 = 0.0;
    for i in 0..100 {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        rng.set_stream(i);
        let x = inv.draw_three_sigma(&mut rng);
        let ex = m.deviations(&lin.phis_rad, &x).unwrap();
        let li = lin.deviations(&x);
        let peak = ex.iter().fold(0.0f64, |a, d| a.max(d[0].hypot(d[1])));
        let err = ex
            .iter()
            .zip(&li)
            .fold(0.0f64, |a, (d, l)| a.max(dist(*d, *l)));
        assert!(peak > 0.01, "3σ errors move the tip by tens of µm: {peak}");
        max_rel = max_rel.max(err / peak);
    }
    println!("linear vs exact at 3σ: max relative error {max_rel:.3e}");
    assert!(max_rel < 0.05, "{max_rel}");
}

fn run(seed: u64, samples: usize, feature_samples: usize) -> TransplanterReport {
    let mut opts = TransplanterOptions::default();
    opts.mc = mc(samples, seed, 40);
    opts.feature_samples = feature_samples;
    opts.starts = 6;
    analyse(&g1(1), &inventory(), &opts, &|_| {}).unwrap()
}

#[test]
fn monte_carlo_is_stable_between_seeds() {
    let (a, b) = (run(1, 50_000, 0), run(2, 50_000, 0));
    for r in [&a, &b] {
        assert_eq!(r.validation.model_used, "linear");
        assert!(r.validation.max_relative_error < 0.05);
    }
    let (sa, sb) = (&a.max_deviation_um, &b.max_deviation_um);
    println!(
        "max|ΔB| µm: seed 1 mean {:.3} P95 {:.3} std {:.3}; seed 2 mean {:.3} P95 {:.3} std {:.3}",
        sa.mean, sa.p95, sa.std, sb.mean, sb.p95, sb.std
    );
    assert!((sa.mean / sb.mean - 1.0).abs() < 0.01);
    assert!((sa.p95 / sb.p95 - 1.0).abs() < 0.01);
    assert!((sa.std / sb.std - 1.0).abs() < 0.02);
    // The 3σ envelope bounds the Monte Carlo's P99.73 from above only loosely (the maximum over
    // φH of a sum is not the sum of maxima) but must be of the same order.
    assert!(a.envelope_max_um > 0.5 * sa.p9973 && a.envelope_max_um < 3.0 * sa.max);
    let opt = a.assembly.as_ref().unwrap();
    assert!(opt.joint_um <= opt.greedy_um + 1e-9 && opt.greedy_um <= opt.as_given_um + 1e-9);
    assert!((opt.joint_exact_um / opt.joint_um - 1.0).abs() < 0.05);
    let ob = b.assembly.as_ref().unwrap();
    assert!((opt.random.mean / ob.random.mean - 1.0).abs() < 0.01);
    // Ranking is sorted and the shares add to 100 %.
    let share: f64 = a.ranking.iter().map(|c| c.share_percent).sum();
    assert!((share - 100.0).abs() < 1e-9);
    assert!(
        a.ranking
            .windows(2)
            .all(|w| w[0].max_deviation_um >= w[1].max_deviation_um)
    );
    // The idler's clocking contributes nothing.
    let idler = a
        .ranking
        .iter()
        .find(|c| c.error == "intermediate clocking")
        .unwrap();
    assert!(idler.sensitivity_um_per_unit < 1e-3, "{idler:?}");
}

#[test]
fn feature_distributions_start_from_the_simulated_features() {
    let r = run(4, 2000, 16);
    let f = r.features.as_ref().unwrap();
    let sim = Simulation::new(g1(1));
    let nominal = features(
        &sim,
        &FeatureOptions {
            samples: 720,
            ..FeatureOptions::default()
        },
    )
    .unwrap();
    assert!((f.nominal.height_mm - nominal.height_mm).abs() < 1e-6);
    assert!((f.nominal.hole_width_mm - nominal.hole_width_mm).abs() < 1e-6);
    assert!((f.nominal.needle_angle_plant_deg - nominal.needle_angle_plant_deg).abs() < 1e-6);
    assert_eq!(f.samples, 16);
    // µm-level errors change the height by at most about the tip deviation.
    assert!(f.height_mm.max.abs() < 2.0 * r.max_deviation_um.max * 1e-3);
    assert!(f.height_mm.std > 0.0);
}

#[test]
fn bad_error_files_name_the_key() {
    let unknown = ErrorInventory::parse(
        "[pin_a]\nradial = { sigma_mm = 5 }\n",
        "e.toml",
        Format::Toml,
    )
    .unwrap_err();
    assert!(unknown.to_string().contains("sigma_mm"), "{unknown}");
    let neg = ErrorInventory::parse(
        "[pin_a]\nradial = { sigma_um = -1 }\n",
        "e.toml",
        Format::Toml,
    )
    .unwrap_err();
    assert!(
        matches!(&neg, TransplanterError::File(ToleranceError::BadValue { key, .. }) if key == "pin_a.radial.sigma_um"),
        "{neg}"
    );
    let keyed = ErrorInventory::parse(
        "[sun.eccentricity]\nmagnitude_um = 5\nkeyed_positions = 4\n",
        "e.toml",
        Format::Toml,
    )
    .unwrap_err();
    assert!(
        keyed
            .to_string()
            .contains("sun.eccentricity.keyed_positions"),
        "{keyed}"
    );
    let both = ErrorInventory::parse(
        "{\"arm_mounting\": {\"sigma_deg\": 0.1, \"half_width_deg\": 0.1}}",
        "e.json",
        Format::Json,
    )
    .unwrap_err();
    assert!(
        both.to_string().contains("arm_mounting.sigma_deg"),
        "{both}"
    );
    let alpha =
        ErrorInventory::parse("pressure_angle_deg = 70\n", "e.toml", Format::Toml).unwrap_err();
    assert!(alpha.to_string().contains("pressure_angle_deg"), "{alpha}");
    // Errors far too large for the geometry: a typed error, not a panic.
    let asm = g1(1);
    let m = ExactModel::new(&asm, 20f64.to_radians(), 1).unwrap();
    let mut x = ZERO;
    x[PIN_A[0]] = 100.0;
    assert!(matches!(
        m.state(0.3, &x),
        Err(TransplanterError::NoContact { .. })
    ));
}

#[test]
fn cli_writes_the_report_and_plots_and_rejects_bad_files() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("transplanter_cli");
    let _ = std::fs::remove_dir_all(&dir);
    let asset = |n: &str| format!("{}/assets/transplanter/{n}", env!("CARGO_MANIFEST_DIR"));
    let v = crate::cli::succeed_json(
        crate::cli::ncgear()
            .args([
                "tolerance",
                &asset("g1_design.json"),
                "--errors",
                &asset("g1_errors.toml"),
                "--samples",
                "2000",
                "--feature-samples",
                "4",
                "--json",
                "--out",
            ])
            .arg(&dir),
    );
    assert_eq!(v["validation"]["model_used"], "linear");
    assert_eq!(v["max_deviation_um"]["n"], 2000);
    assert_eq!(v["envelope"].as_array().unwrap().len(), 720);
    for f in [
        "transplanter.json",
        "envelope.png",
        "envelope.svg",
        "band.png",
        "histogram.png",
    ] {
        assert!(dir.join(f).is_file(), "{f}");
    }
    // A bad inventory is an input error (exit 2) naming the key.
    let bad = dir.join("bad.toml");
    std::fs::write(&bad, "[planet.eccentricity]\nmagnitude_um = -3\n").unwrap();
    let out = crate::cli::ncgear()
        .args(["tolerance", &asset("g1_design.json"), "--errors"])
        .arg(&bad)
        .arg("--out")
        .arg(&dir)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("planet.eccentricity.magnitude_um"), "{err}");
}

#[test]
fn exact_fallback_agrees_with_the_linear_monte_carlo() {
    let go = |tol: f64| {
        let mut opts = TransplanterOptions::default();
        opts.mc = mc(200, 9, 10);
        opts.validation_samples = 10;
        opts.linear_tolerance = tol;
        opts.feature_samples = 0;
        opts.starts = 2;
        analyse(&g1(1), &inventory(), &opts, &|_| {}).unwrap()
    };
    let (lin, exact) = (go(0.05), go(1e-9));
    assert_eq!(lin.validation.model_used, "linear");
    assert_eq!(exact.validation.model_used, "exact");
    // Same seed, same samples: per-sample agreement within the validated linear error.
    let (a, b) = (&lin.max_deviation_um, &exact.max_deviation_um);
    println!("MC mean: linear {:.4} µm, exact {:.4} µm", a.mean, b.mean);
    assert!((a.mean / b.mean - 1.0).abs() < 0.01);
    assert!((a.max / b.max - 1.0).abs() < 0.01);
}

/// Non-circular G1: a radial pin error δ of A changes the intermediate–planet centre distance;
/// to first order (spec C.6 item 2) the planet turns by `Δθ3 = −δ·(u·N)/ρ_b`, with u the line of
/// centres, N the line of action through the contact (pitch tangent t and normal n of the
/// intermediate, `N = σ cos α t + sin α n`, σ = −load_side) and `ρ_b = (R⁺(W − A))·N` the moment
/// arm about A; the tip moves by `δ·u + l3·Δθ3·e(β + π/2)`. Computed here from the pitch tables.
#[test]
fn radial_pin_error_on_g1_follows_the_first_order_line_of_action_formula() {
    let asm = g1(1);
    let alpha = 20f64.to_radians();
    let m = ExactModel::new(&asm, alpha, 1).unwrap();
    let rb = asm.rebuild();
    let [_, mid, _] = rb.ccw_curves();
    let (a, l3) = (asm.a_mm, asm.l3_mm);
    let delta = 1e-3;
    let mut x = ZERO;
    x[PIN_A[0]] = delta;
    let (mut worst, mut peak): (f64, f64) = (0.0, 0.0);
    for p in m.grid(240) {
        let th2 = rb.ccw_intermediate_angle(p);
        let c2 = p - th2; // intermediate body angle facing A
        let g = mid.geometry(c2);
        let u = e(p);
        let t = {
            let (r, dr) = (g.r_mm, g.dr_mm);
            let v = [dr * u[0] - r * u[1], dr * u[1] + r * u[0]];
            let l = v[0].hypot(v[1]);
            [v[0] / l, v[1] / l]
        };
        let mut n = [-t[1], t[0]];
        if dot(n, u) < 0.0 {
            n = [-n[0], -n[1]];
        }
        let sigma = -1.0;
        let nl = [
            sigma * alpha.cos() * t[0] + alpha.sin() * n[0],
            sigma * alpha.cos() * t[1] + alpha.sin() * n[1],
        ];
        // Contact W = D + ρ2 u; lever of the planet about A: W − A = (ρ2 − a) u.
        let w_a = [(g.r_mm - a) * u[0], (g.r_mm - a) * u[1]];
        let arm = dot([-w_a[1], w_a[0]], nl);
        let dth3 = -delta * dot(u, nl) / arm;
        let nom = m.state(p, &ZERO).unwrap();
        let per = m.state(p, &x).unwrap();
        let b = nom.needle_angle_rad;
        let pred = [
            delta * u[0] - l3 * dth3 * b.sin(),
            delta * u[1] + l3 * dth3 * b.cos(),
        ];
        let got = [per.tip_mm[0] - nom.tip_mm[0], per.tip_mm[1] - nom.tip_mm[1]];
        worst = worst.max(dist(got, pred));
        peak = peak.max(got[0].hypot(got[1]));
    }
    println!(
        "G1 radial pin δ = 1 µm: first-order formula residual {worst:.2e} mm of {peak:.2e} mm"
    );
    assert!(
        peak > 2.0 * delta,
        "the planet rotation amplifies the pin error: {peak}"
    );
    assert!(worst < 1e-3 * peak, "{worst} vs {peak}");
}
