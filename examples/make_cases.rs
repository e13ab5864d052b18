//! Writes a few generated robustness cases (one per family) and their truth polylines from the
//! suite's independent forward model (`tests/it/robust/forward.rs`, no code shared with the
//! design chain):
//!
//! - `assets/cases/exact_sparse_200.csv`: exactly traceable, 200 points uniform in arc length.
//! - `assets/cases/exact_cw_offset.csv`: exactly traceable, clockwise carrier, carrier axis off
//!   the origin (given in the `# center: X,Y` comment line; pass it with the centre option).
//! - `assets/cases/noisy_030um_400.csv`: 400 points with Gaussian noise σ = 0.03 mm on x and y.
//! - `assets/cases/designer_odd2.csv`: the G1 focus-ellipse law with the needle direction
//!   perturbed by c·sin(2t + φp): not exactly traceable.
//!
//! `assets/cases/truth/<name>.csv` holds the clean curve (3600 points uniform in carrier angle).
//! Header `x_mm,y_mm`, 6 decimals; the parameters are in the `#` comment lines.
//!
//! Run: `cargo run --release --example make_cases`
#[path = "../tests/it/robust/forward.rs"]
mod forward;

use forward::{Family, SampleOptions, Sampling, Wobble, build_case, draw_harmonic_train, g1_like};
use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};

fn main() -> std::io::Result<()> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/cases");
    std::fs::create_dir_all(dir.join("truth"))?;
    let base = SampleOptions {
        m: 200,
        sampling: Sampling::Arc,
        start: 0.0,
        cw: false,
        center: [0.0, 0.0],
        sigma: 0.0,
    };
    let mut cases = Vec::new();

    let seed = 501;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let train = draw_harmonic_train(&mut rng);
    let opts = SampleOptions {
        start: rng.random_range(0.0..std::f64::consts::TAU),
        ..base
    };
    cases.push((
        "exact_sparse_200",
        build_case(Family::Sparse, seed, train, opts, &mut rng),
    ));

    let seed = 502;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let train = draw_harmonic_train(&mut rng);
    let opts = SampleOptions {
        m: 720,
        sampling: Sampling::Time,
        start: rng.random_range(0.0..std::f64::consts::TAU),
        cw: true,
        center: [
            rng.random_range(-300.0..300.0),
            rng.random_range(-300.0..300.0),
        ],
        ..base
    };
    cases.push((
        "exact_cw_offset",
        build_case(Family::Exact, seed, train, opts, &mut rng),
    ));

    let seed = 503;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let train = draw_harmonic_train(&mut rng);
    let opts = SampleOptions {
        m: 400,
        start: rng.random_range(0.0..std::f64::consts::TAU),
        sigma: 0.03,
        ..base
    };
    cases.push((
        "noisy_030um_400",
        build_case(Family::Noisy, seed, train, opts, &mut rng),
    ));

    let seed = 504;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut train = g1_like(0.15, rng.random_range(0.0..std::f64::consts::TAU));
    train.wobble = Some(Wobble {
        c: 0.02,
        n: 2.0,
        phase: rng.random_range(0.0..std::f64::consts::TAU),
    });
    let opts = SampleOptions {
        m: 600,
        sampling: Sampling::Time,
        start: rng.random_range(0.0..std::f64::consts::TAU),
        ..base
    };
    cases.push((
        "designer_odd2",
        build_case(Family::Designer, seed, train, opts, &mut rng),
    ));

    for (name, case) in &cases {
        assert!(
            case.closure_error.abs() < 1e-7,
            "{name}: model does not close"
        );
        std::fs::write(dir.join(format!("{name}.csv")), case.points_csv())?;
        std::fs::write(
            dir.join("truth").join(format!("{name}.csv")),
            case.truth_csv(),
        )?;
        println!("{name}: {} points; {}", case.points.len(), case.describe());
    }
    Ok(())
}
