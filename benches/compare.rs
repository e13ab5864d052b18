//! Benchmarks of `ncgear compare` (divan). Run: `cargo bench --bench compare`.
//!
//! A 3-turn record filmed at 1000 frames/s of the bundled G1 design (pixels, a rotation, an
//! offset, 0.3 mm noise, 2 % glitch frames, the speed drifting ±2 %), read from its CSV text,
//! registered with the scale fitted and compared: at 300 rpm (600 frames a turn) and at 60 rpm
//! (3000). Target: ≤ 1 s.
use ncgear::compare::{CompareOptions, ReadOptions, Scale, compare, parse_track};
use ncgear::geometry::assembly::Rebuilt;
use ncgear::math::Point;
use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};
use std::f64::consts::TAU;
use std::path::Path;

fn main() {
    divan::main();
}

fn design() -> Rebuilt {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/transplanter/g1_design.json");
    ncgear::simulate::DesignFile::from_path(&p)
        .expect("bundled design")
        .1
        .rebuild()
}

/// The CSV text of 3 turns (and 3 %) at `rpm`, 1000 frames/s.
fn record(built: &Rebuilt, rpm: f64) -> String {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let w0 = TAU * rpm / 60.0;
    let span = 3.09 * 60.0 / rpm;
    let mut csv = String::from("time (s),x (px),y (px)\n");
    for i in 0..(span * 1000.0) as usize {
        let t = i as f64 / 1000.0;
        let phi = 0.7 + w0 * (t + 0.02 * (t * t / span - t));
        let g = |r: &mut ChaCha8Rng| {
            let (u, v): (f64, f64) = (r.random::<f64>().max(1e-300), r.random());
            (-2.0 * u.ln()).sqrt() * (TAU * v).cos() * 0.3
        };
        let mut q = built.pose(phi).tip_mm + Point::new(g(&mut rng), g(&mut rng));
        if rng.random::<f64>() < 0.02 {
            q += Point::unit(rng.random_range(0.0..TAU)) * 8.0;
        }
        let p = (q - Point::new(-400.0, 230.0)).rotate(-0.3) / 0.31;
        csv.push_str(&format!("{t:.6},{:.4},{:.4}\n", p.x, -p.y));
    }
    csv
}

fn run(b: divan::Bencher, rpm: f64) {
    let built = design();
    let csv = record(&built, rpm);
    let opts = CompareOptions {
        scale: Scale::Fit,
        ..CompareOptions::default()
    };
    b.bench(|| {
        let track = parse_track(&csv, "bench.csv", &ReadOptions::default()).expect("track");
        compare(&track, &built, &opts).expect("comparison").report
    });
}

/// 3 turns at 300 rpm: 618 frames.
#[divan::bench(sample_count = 10)]
fn compare_3_turns_300rpm_1000fps(b: divan::Bencher) {
    run(b, 300.0);
}

/// 3 turns at 60 rpm: 3090 frames.
#[divan::bench(sample_count = 5)]
fn compare_3_turns_60rpm_1000fps(b: divan::Bencher) {
    run(b, 60.0);
}
