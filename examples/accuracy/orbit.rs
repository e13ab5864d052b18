//! Orbit extraction (docs/math/companion.md §A.8): record length (= FFT size at a fixed sample rate) and
//! method, against the known true orbit of a synthetic record. The record holds the planet orbit
//! (Z₊ = 6 + 2i µm, Z₋ = −3 + 4i µm at ω_p = 2π·3.37 rad/s), a 5 µm sun-runout line at 4.91 Hz,
//! forward and backward mesh lines at 12·3.37 Hz, a DC offset and a linear drift, sampled at
//! 500 Hz over a non-integer number of planet periods. Error = max(|Z₊ − true|, |Z₋ − true|), µm.
use super::{Row, timed};
use ncgear::analysis::orbit::measure::{ExtractOptions, Extractor, Method, Record};
use ncgear::analysis::orbit::model::{Line, LineKind};
use ncgear::analysis::orbit::{C64, Orbit};
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};
use std::f64::consts::TAU;

const FS_HZ: f64 = 500.0;

fn truth() -> Orbit {
    Orbit {
        omega_p_rad_s: TAU * 3.37,
        z_plus_um: C64::new(6.0, 2.0),
        z_minus_um: C64::new(-3.0, 4.0),
    }
}

/// Extra circular lines `Z e^{iωt}`: (signed ω, Z).
fn lines() -> [(f64, C64); 3] {
    [
        (TAU * 4.91, C64::new(3.0, 4.0)),
        (TAU * 3.37 * 12.0, C64::new(2.0, 0.0)),
        (-TAU * 3.37 * 12.0, C64::new(0.0, 1.5)),
    ]
}

fn record(periods: f64, sigma_um: f64, seed: u64) -> Record {
    let o = truth();
    let duration = periods * TAU / o.omega_p_rad_s;
    let n = (duration * FS_HZ).round() as usize;
    let mut rng = rand::rngs::ChaCha8Rng::seed_from_u64(seed);
    let noise = Normal::new(0.0, sigma_um.max(1e-300)).expect("σ > 0");
    let (mut t, mut x, mut y) = (Vec::new(), Vec::new(), Vec::new());
    for k in 0..n {
        let tk = k as f64 / FS_HZ;
        let (ox, oy) = o.position_um(tk);
        let mut z = C64::new(ox, oy);
        for (w, a) in lines() {
            z += a * C64::from_polar(1.0, w * tk);
        }
        let (nx, ny) = if sigma_um > 0.0 {
            (noise.sample(&mut rng), noise.sample(&mut rng))
        } else {
            (0.0, 0.0)
        };
        t.push(tk);
        x.push(z.re + 30.0 + 4.0 * tk + nx);
        y.push(z.im - 12.0 - 2.5 * tk + ny);
    }
    Record::new(t, x, y, None).expect("synthetic record")
}

fn error(m: &Orbit) -> f64 {
    let o = truth();
    (m.z_plus_um - o.z_plus_um)
        .norm()
        .max((m.z_minus_um - o.z_minus_um).norm())
}

/// The orbit rows.
pub fn rows() -> Vec<Row> {
    let wp = truth().omega_p_rad_s;
    let nuisance: Vec<Line> = lines()
        .iter()
        .map(|(w, _)| Line::new(format!("{w:.2}"), *w, LineKind::Nuisance))
        .collect();
    let mut rows = Vec::new();
    let periods = [2.5, 5.5, 10.5, 26.185, 52.5, 105.5];
    let samples = |p: f64| (p * TAU / wp * FS_HZ).round() as usize;
    // Windowed / FFT estimators: bias only (no noise), the lines leak into the planet bins.
    for (label, method) in [
        ("plain FFT bin (rectangular window)", Method::PlainFft),
        ("Hann-window DTFT at the exact line", Method::HannDtft),
        ("least squares (lines + drift known)", Method::LeastSquares),
    ] {
        let lines = if method == Method::LeastSquares {
            nuisance.clone()
        } else {
            Vec::new()
        };
        let opts = ExtractOptions::default()
            .with_method(method)
            .with_nuisance(lines);
        let ex = Extractor::new(wp, opts).expect("valid extractor");
        for p in periods {
            let rec = record(p, 0.0, 1);
            let (ms, m) = timed(3, || ex.extract(&rec).expect("extraction"));
            rows.push(Row::new(
                format!("orbit record length: {label}"),
                format!("{p} periods ({} samples)", samples(p)),
                "max |Z± − true|, µm (no noise)",
                error(&m.orbit).max(1e-16),
                ms,
            ));
        }
    }
    // Least squares with σ = 2 µm sensor noise: RMS error over 16 seeds (vs the CRLB ≈ σ√(2/N)).
    let opts = ExtractOptions::default().with_nuisance(nuisance);
    let ex = Extractor::new(wp, opts).expect("valid extractor");
    for p in periods {
        let mut ms_all = Vec::new();
        let mut sq = 0.0;
        for seed in 0..16 {
            let rec = record(p, 2.0, 100 + seed);
            let (ms, m) = timed(1, || ex.extract(&rec).expect("extraction"));
            ms_all.push(ms);
            sq += error(&m.orbit).powi(2);
        }
        ms_all.sort_by(f64::total_cmp);
        rows.push(Row::new(
            "orbit record length: least squares with σ = 2 µm noise",
            format!(
                "{p} periods ({} samples; CRLB {:.3} µm)",
                samples(p),
                2.0 * (2.0 / samples(p) as f64).sqrt()
            ),
            "RMS over 16 seeds of max |Z± − true|, µm",
            (sq / 16.0).sqrt(),
            ms_all[ms_all.len() / 2],
        ));
    }
    rows
}
