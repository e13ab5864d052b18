//! Monte Carlo of the paper's four-term example (50 000 random assemblies, certified peaks) at
//! several grid densities. Run: `cargo bench --bench tolerance`. Compare with
//! `python3 benches/python/mc_numpy.py` (the same loop, vectorised numpy).
use ncgear::analysis::peak::PeakOptions;
use ncgear::analysis::tolerance::{Analysis, ErrorFile};
use ncgear::config::Format;
use ncgear::math::monte_carlo::McOptions;

fn main() {
    divan::main();
}

fn paper() -> ErrorFile {
    let text = include_str!("../assets/tolerance/paper_3k.toml");
    ErrorFile::parse(text, "paper_3k.toml", Format::Toml).expect("bundled example")
}

/// 50 000 samples; `args` = grid points per shortest period (20 = the default).
#[divan::bench(args = [20, 40, 80], sample_count = 3)]
fn monte_carlo_50k(b: divan::Bencher, per_period: usize) {
    let peak = PeakOptions::default().with_samples_per_min_period(per_period);
    let a = Analysis::new(&paper(), peak);
    let opts = McOptions::default()
        .with_samples(50_000)
        .with_seed(1)
        .with_bins(60);
    b.bench(|| {
        a.monte_carlo(&opts, &ncgear::progress::Progress::none())
            .expect("finite")
    });
}

/// One certified peak of the four-term sum.
#[divan::bench]
fn certified_peak_one(b: divan::Bencher) {
    let a = Analysis::new(&paper(), PeakOptions::default());
    b.bench(|| a.peak(divan::black_box(&[1.0, 2.0, 3.0]), None));
}

/// The Monte Carlo kernel alone: 1 000 certified peaks of the paper's four frequencies on one
/// precomputed grid (grid sum, candidate intervals, refinement), no random draws or statistics.
#[divan::bench(sample_count = 5)]
fn monte_carlo_kernel_1k_peaks(b: divan::Bencher) {
    let grid =
        ncgear::analysis::peak::PeakGrid::new(&[75.0, 525.0, 275.0, 63.0], PeakOptions::default());
    let amps = [-0.699, -13.0, -8.778, -25.887];
    b.bench(|| {
        (0..1000)
            .map(|i| {
                let x = f64::from(i) * 0.001;
                let ph = [0.0, 6.0 * x, 1.5 - 3.1 * x, 0.35 + 5.0 * x];
                grid.peak(&amps, &ph).value
            })
            .sum::<f64>()
    });
}
