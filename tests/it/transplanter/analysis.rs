//! The analysis report: Monte Carlo stability, feature distributions, the exact fallback, bad
//! error files and the CLI.
use super::*;
use ncgear::progress::Progress;

fn run(seed: u64, samples: usize, feature_samples: usize) -> TransplanterReport {
    let opts = TransplanterOptions::default()
        .with_mc(
            McOptions::default()
                .with_samples(samples)
                .with_seed(seed)
                .with_bins(40),
        )
        .with_feature_samples(feature_samples)
        .with_starts(6);
    analyse(&g1(1), &inventory(), &opts, &Progress::none()).unwrap()
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
    let nominal = features(&sim, &FeatureOptions::default().with_samples(720)).unwrap();
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
        let opts = TransplanterOptions::default()
            .with_mc(
                McOptions::default()
                    .with_samples(200)
                    .with_seed(9)
                    .with_bins(10),
            )
            .with_validation_samples(10)
            .with_linear_tolerance(tol)
            .with_feature_samples(0)
            .with_starts(2);
        analyse(&g1(1), &inventory(), &opts, &Progress::none()).unwrap()
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
