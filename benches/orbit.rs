//! Benchmarks of `ncgear orbit`: evaluation of a 1-million-sample two-channel record.
//!
//! Run: `cargo bench --bench orbit`
use ncgear::analysis::orbit::measure::{ExtractOptions, Extractor, Method, Record};
use ncgear::analysis::orbit::model::{Line, LineKind};
use std::f64::consts::TAU;

fn main() {
    divan::main();
}

const N: usize = 1_000_000;

/// 1 M samples at 10 kHz (100 s, 337.3 planet periods): orbit + runout + mesh line + drift + a
/// deterministic pseudo-noise.
fn record() -> Record {
    let wp = TAU * 3.373;
    let (mut t, mut x, mut y) = (
        Vec::with_capacity(N),
        Vec::with_capacity(N),
        Vec::with_capacity(N),
    );
    let mut s: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut noise = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    for k in 0..N {
        let tk = k as f64 * 1e-4;
        t.push(tk);
        x.push(
            4.7 * (wp * tk + 2.97).sin()
                + 5.0 * (TAU * 4.91 * tk).cos()
                + 2.0 * (TAU * 40.4 * tk).sin()
                + 0.1 * tk
                + noise(),
        );
        y.push(16.4 * (wp * tk - 0.47).sin() + 5.0 * (TAU * 4.91 * tk).sin() + 3.0 + noise());
    }
    Record::new(t, x, y, None).expect("valid synthetic record")
}

fn lines() -> Vec<Line> {
    [4.91, 40.4, -40.4, 2.0 * 3.373]
        .iter()
        .map(|f| Line::new(format!("{f} Hz"), TAU * f, LineKind::Nuisance))
        .collect()
}

/// Least squares with drift and 3 distinct nuisance lines (10 regressors) on 1 M samples × 2 channels.
#[divan::bench(sample_count = 10)]
fn least_squares_1m(bencher: divan::Bencher) {
    let rec = record();
    let ex = Extractor::new(
        TAU * 3.373,
        ExtractOptions::default().with_nuisance(lines()),
    )
    .expect("valid extractor");
    bencher.bench_local(|| ex.extract(divan::black_box(&rec)).expect("extraction"));
}

/// Hann-windowed DTFT at ±ω_p on 1 M samples.
#[divan::bench(sample_count = 10)]
fn hann_dtft_1m(bencher: divan::Bencher) {
    let rec = record();
    let ex = Extractor::new(
        TAU * 3.373,
        ExtractOptions::default().with_method(Method::HannDtft),
    )
    .expect("valid extractor");
    bencher.bench_local(|| ex.extract(divan::black_box(&rec)).expect("extraction"));
}

/// CSV parsing is not part of the timed evaluation; this measures it separately (100 k rows).
#[divan::bench(sample_count = 5)]
fn csv_parse_100k(bencher: divan::Bencher) {
    let mut text = String::from("t_s,x_um,y_um\n");
    for k in 0..100_000 {
        let t = k as f64 * 1e-4;
        text.push_str(&format!("{t},{},{}\n", (t * 21.0).sin(), (t * 21.0).cos()));
    }
    bencher.bench_local(|| {
        Record::from_csv_reader(divan::black_box(text.as_bytes()), "bench.csv").expect("parse")
    });
}
