//! Tolerance analysis (docs/math/companion.md §C): the peak-search grid (certified vs a naive fixed grid)
//! and the Monte Carlo sample count, measured against references (a 400-points-per-period
//! certified peak; a 200 000-sample Monte Carlo mean).
use super::Row;
use ncgear::analysis::peak::{PeakOptions, Sinusoid, fixed_grid_peak};
use ncgear::analysis::tolerance::{Analysis, ErrorFile};
use ncgear::config::Format;
use ncgear::math::monte_carlo::McOptions;
use std::f64::consts::TAU;
use std::time::Instant;

/// Certified-peak options with `per` grid points per shortest period.
fn peak_options(per: usize) -> PeakOptions {
    PeakOptions::default().with_samples_per_min_period(per)
}

/// The tolerance-analysis rows.
pub fn rows() -> Vec<Row> {
    let file = ErrorFile::parse(
        include_str!("../../assets/tolerance/paper_3k.toml"),
        "paper_3k.toml",
        Format::Toml,
    )
    .expect("bundled");
    let mut rows = Vec::new();
    // 1. Peak grid density: 200 random phase sets, worst error vs the 400-point reference.
    // Additive-recurrence (Weyl) phases; the multipliers only need to be irrational-looking.
    #[allow(clippy::approx_constant)]
    let sets: Vec<[f64; 3]> = (0..200)
        .map(|k| {
            let x = k as f64;
            [
                (x * 1.618_034).fract() * TAU,
                (x * 2.718_281).fract() * TAU,
                (x * 3.141_593).fract() * TAU,
            ]
        })
        .collect();
    let reference = Analysis::new(&file, peak_options(400));
    let refs: Vec<f64> = sets.iter().map(|b| reference.peak(b, None).value).collect();
    for per in [4, 8, 20, 40, 80] {
        let a = Analysis::new(&file, peak_options(per));
        let t = Instant::now();
        let worst = sets
            .iter()
            .zip(&refs)
            .map(|(b, r)| (a.peak(b, None).value - r).abs())
            .fold(0.0, f64::max);
        let us = t.elapsed().as_secs_f64() * 1e6 / sets.len() as f64;
        rows.push(Row::new(
            "certified peak: grid points per shortest period",
            per.to_string(),
            "max |peak − reference|, µm",
            worst,
            us / 1e3,
        ));
    }
    // The naive alternative: a fixed time grid without refinement over the full period.
    for dt in [1e-3, 1e-4, 1e-5] {
        let t = Instant::now();
        let worst = sets
            .iter()
            .zip(&refs)
            .map(|(b, r)| {
                let ph = [
                    0.0,
                    b[0] + 20f64.to_radians(),
                    -b[1] + 90f64.to_radians(),
                    -b[2] + 20f64.to_radians(),
                ];
                let terms: Vec<Sinusoid> = file
                    .terms
                    .iter()
                    .zip(ph)
                    .map(|(t, p)| Sinusoid {
                        amplitude: t.amplitude_um,
                        omega_rad_s: t.omega_rad_s,
                        phase_rad: p,
                    })
                    .collect();
                (fixed_grid_peak(&terms, dt, TAU) - r).abs()
            })
            .fold(0.0, f64::max);
        let us = t.elapsed().as_secs_f64() * 1e6 / sets.len() as f64;
        rows.push(Row::new(
            "naive fixed grid over [0, 2π] s (no refinement)",
            format!("dt = {dt:e} s"),
            "max |peak − reference|, µm",
            worst,
            us / 1e3,
        ));
    }
    // 2. Monte Carlo sample count: error of the mean against a 200 000-sample reference.
    let a = Analysis::new(&file, PeakOptions::default());
    let (reference, _) = a
        .monte_carlo(
            &McOptions::default()
                .with_samples(200_000)
                .with_seed(99)
                .with_bins(10),
            &ncgear::progress::Progress::none(),
        )
        .expect("finite");
    for n in [1_000, 5_000, 20_000, 50_000] {
        let t = Instant::now();
        let (s, _) = a
            .monte_carlo(
                &McOptions::default()
                    .with_samples(n)
                    .with_seed(1)
                    .with_bins(10),
                &ncgear::progress::Progress::none(),
            )
            .expect("finite");
        let ms = t.elapsed().as_secs_f64() * 1e3;
        rows.push(Row::new(
            "Monte Carlo samples (paper example)",
            n.to_string(),
            "|mean − 200k mean|, µm (± 2 s.e.)",
            (s.mean - reference.mean).abs(),
            ms,
        ));
    }
    rows
}
