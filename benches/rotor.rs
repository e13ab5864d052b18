//! Rotor dynamics benchmarks (divan): the bundled G1 rotor (assets/dynamics/rotor_g1.toml, every
//! effect: ISO stiffness with the pairs alternating, mesh damping, the teeth's backlash,
//! vibration damping) settled at 300 r/min; the same train with a constant stiffness, the same
//! dampings and no backlash (the scene builds only what it names, so it must cost less); the
//! bundled scene on a compliant drive (5000 N·m/rad, the carrier a degree of freedom, both arms
//! integrated together); a sweep of 30 speeds (100–390 r/min, each warm-started from the last).
//!
//! Run: `cargo bench --bench rotor`
use ncgear::analysis::dynamics::rotor::{Drive, Effects, Prepared, build, run_model, sweep_rpm};
use ncgear::progress::Progress;
use std::path::PathBuf;

fn main() {
    divan::main();
}

fn bundled() -> Prepared {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/dynamics/rotor_g1.toml");
    Prepared::from_path(&path).expect("the bundled rotor scene")
}

/// Times the bundled scene's tables settled with `effects` instead of its own.
fn settle_with(bencher: divan::Bencher, p: &Prepared, effects: &Effects) {
    let built = build(&p.source.rotor(), &p.case.loads, effects, p.teeth, "bench").expect("model");
    bencher.bench_local(|| {
        divan::black_box(
            run_model(
                &built.model,
                &p.case.loads,
                &p.case.settings,
                p.teeth,
                None,
                &Progress::none(),
            )
            .expect("run"),
        )
    });
}

#[divan::bench(sample_count = 10)]
fn g1_every_effect_settled_300_rpm(bencher: divan::Bencher) {
    let p = bundled();
    bencher.bench_local(|| divan::black_box(p.run(&Progress::none()).expect("run")));
}

#[divan::bench(sample_count = 10)]
fn g1_constant_stiffness_no_backlash_settled_300_rpm(bencher: divan::Bencher) {
    let p = bundled();
    // ISO's c′ of steel, ≈ 14 000 N/mm per mm, over the 25 mm face
    let effects = Effects::constant([14_000.0 * 25.0 * 1e3; 2])
        .with_zeta([0.05; 2])
        .with_vibration_zeta(0.05);
    settle_with(bencher, &p, &effects);
}

#[divan::bench(sample_count = 3)]
fn g1_every_effect_on_a_compliant_drive_settled_300_rpm(bencher: divan::Bencher) {
    let p = bundled();
    let drive = Drive {
        stiffness_nm_per_rad: 5000.0,
        damping_nms_per_rad: 2.0,
        carrier_inertia_kg_m2: 0.02,
    };
    let effects = p.case.effects.with_drive(Some(drive));
    settle_with(bencher, &p, &effects);
}

#[divan::bench(sample_count = 1, sample_size = 1)]
fn g1_sweep_30_speeds(bencher: divan::Bencher) {
    let p = bundled();
    let rpm: Vec<f64> = (0..30).map(|k| 100.0 + 10.0 * f64::from(k)).collect();
    bencher
        .bench_local(|| divan::black_box(sweep_rpm(&p, &rpm, &Progress::none()).expect("sweep")));
}
