//! Seeded, parallel Monte Carlo with summary statistics (docs/math/companion.md §C.5).
//!
//! Sample `i` draws from its own stream `ChaCha8Rng::seed_from_u64(seed)` with `set_stream(i)`,
//! so results are identical for any thread count and any chunking. Mean and variance are
//! accumulated with Welford's update over the samples in index order ([`summarize`], also usable
//! on any sample); quantiles come from the sorted sample.

use crate::progress::Progress;
use rand::SeedableRng;
use rand::rngs::ChaCha8Rng;
use rayon::prelude::*;

/// Largest accepted sample count of one run.
pub const MAX_SAMPLES: usize = 50_000_000;

/// Largest accepted histogram bin count.
pub const MAX_BINS: usize = 100_000;

/// Why a Monte Carlo run has no result.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum McError {
    /// A bad option value.
    #[error("Monte Carlo option `{name}` = {value}: expected {expected}")]
    BadOption {
        /// Option.
        name: &'static str,
        /// Given value.
        value: usize,
        /// What is expected.
        expected: &'static str,
    },
    /// The samples would need more memory than [`crate::bounds::memory_ceiling_bytes`].
    #[error(transparent)]
    Memory(#[from] crate::bounds::OutOfBounds),
    /// The sampler returned a non-finite value (a bug of the sampler or of its input).
    #[error("Monte Carlo sample {index} is not finite")]
    NonFinite {
        /// Sample index.
        index: usize,
    },
}

/// Options of a Monte Carlo run. (De)serialisable (a missing field takes its default, an unknown one is an error) and
/// built with `with_*`.
#[derive(
    Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct McOptions {
    /// Number of samples, `1..=MAX_SAMPLES` (default 50 000).
    pub samples: usize,
    /// Seed of the sample streams (default 1).
    pub seed: u64,
    /// Histogram bins, `1..=MAX_BINS` (default 60).
    pub bins: usize,
}

crate::builder::with_fields!(McOptions {
    with_samples => samples: usize,
    with_seed => seed: u64,
    with_bins => bins: usize,
});

impl Default for McOptions {
    fn default() -> Self {
        Self {
            samples: 50_000,
            seed: 1,
            bins: 60,
        }
    }
}

/// Summary statistics of a sample.
#[derive(Debug, Clone, PartialEq, serde::Serialize, schemars::JsonSchema)]
pub struct McStats {
    /// Sample size.
    pub n: usize,
    /// Minimum.
    pub min: f64,
    /// Maximum.
    pub max: f64,
    /// Mean.
    pub mean: f64,
    /// Standard deviation (n − 1).
    pub std: f64,
    /// Standard error of the mean, `std/√n`.
    pub mean_std_error: f64,
    /// Median.
    pub p50: f64,
    /// 95th percentile.
    pub p95: f64,
    /// 99.73rd percentile (3σ-equivalent).
    pub p9973: f64,
    /// Histogram `[lower edge, upper edge, count]`.
    pub histogram: Vec<[f64; 3]>,
}

impl McStats {
    /// The statistics of the sample multiplied by `factor` > 0 (a change of unit, e.g. µm to arc
    /// seconds); `n` and the counts are kept.
    #[must_use]
    pub fn scaled(&self, factor: f64) -> Self {
        let f = factor;
        Self {
            n: self.n,
            min: self.min * f,
            max: self.max * f,
            mean: self.mean * f,
            std: self.std * f,
            mean_std_error: self.mean_std_error * f,
            p50: self.p50 * f,
            p95: self.p95 * f,
            p9973: self.p9973 * f,
            histogram: self
                .histogram
                .iter()
                .map(|h| [h[0] * f, h[1] * f, h[2]])
                .collect(),
        }
    }

    /// The histogram's step outline for plotting: `(edge, count)` at both edges of every bin.
    #[must_use]
    pub fn step_outline(&self) -> Vec<(f64, f64)> {
        self.histogram
            .iter()
            .flat_map(|h| [(h[0], h[2]), (h[1], h[2])])
            .collect()
    }
}

#[derive(Clone, Copy)]
struct Welford {
    n: f64,
    mean: f64,
    m2: f64,
}

impl Welford {
    fn push(&mut self, x: f64) {
        self.n += 1.0;
        let d = x - self.mean;
        self.mean += d / self.n;
        self.m2 += d * (x - self.mean);
    }
}

/// Quantile of sorted data by linear interpolation (type 7).
fn quantile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let x = q * (sorted.len() - 1) as f64;
    let i = x.floor() as usize;
    let f = x - i as f64;
    if i + 1 < sorted.len() {
        sorted[i] * (1.0 - f) + sorted[i + 1] * f
    } else {
        sorted[i]
    }
}

fn check_bins(bins: usize) -> Result<(), McError> {
    if (1..=MAX_BINS).contains(&bins) {
        Ok(())
    } else {
        Err(McError::BadOption {
            name: "bins",
            value: bins,
            expected: "a bin count in 1..=100000",
        })
    }
}

/// Runs `sample(rng, i)` for `i = 0..samples` in parallel; `progress` hears the samples of each
/// chunk as it finishes. Returns the statistics and the samples in index order.
///
/// # Errors
/// [`McError::BadOption`] for `samples` outside `1..=MAX_SAMPLES` or `bins` outside
/// `1..=MAX_BINS`; [`McError::NonFinite`] naming the first non-finite sample.
///
/// ```
/// use ncgear::math::monte_carlo::{McOptions, run};
/// use ncgear::progress::Progress;
/// use rand::RngExt;
/// let opts = McOptions::default().with_samples(20_000).with_seed(7).with_bins(10);
/// let (stats, values) = run(&opts, |rng, _| rng.random::<f64>(), &Progress::none()).unwrap();
/// // Uniform on [0, 1): mean 1/2 within 4 standard errors, std √(1/12).
/// assert!((stats.mean - 0.5).abs() < 4.0 * stats.mean_std_error);
/// assert!((stats.std - (1.0f64 / 12.0).sqrt()).abs() < 0.01);
/// // Same seed, same samples.
/// let (_, again) = run(&opts, |rng, _| rng.random::<f64>(), &Progress::none()).unwrap();
/// assert_eq!(values, again);
/// ```
pub fn run<F>(
    opts: &McOptions,
    sample: F,
    progress: &Progress,
) -> Result<(McStats, Vec<f64>), McError>
where
    F: Fn(&mut ChaCha8Rng, usize) -> f64 + Sync,
{
    if !(1..=MAX_SAMPLES).contains(&opts.samples) {
        return Err(McError::BadOption {
            name: "samples",
            value: opts.samples,
            expected: "a sample count in 1..=50000000",
        });
    }
    check_bins(opts.bins)?;
    let chunk = 1024;
    let n = opts.samples;
    // The samples are held three times at the peak (the chunks, their concatenation, the sorted
    // copy of the quantiles), 8 bytes each.
    crate::bounds::check_memory(&format!("{n} Monte Carlo samples"), 3.0 * 8.0 * n as f64)?;
    let parts: Vec<Vec<f64>> = (0..n.div_ceil(chunk))
        .into_par_iter()
        .map(|c| {
            let lo = c * chunk;
            let hi = (lo + chunk).min(n);
            let mut vals = Vec::with_capacity(hi - lo);
            for i in lo..hi {
                let mut rng = ChaCha8Rng::seed_from_u64(opts.seed);
                rng.set_stream(i as u64);
                vals.push(sample(&mut rng, i));
            }
            progress.advance((hi - lo) as u64);
            vals
        })
        .collect();
    let all: Vec<f64> = parts.into_iter().flatten().collect();
    Ok((summarize(&all, opts.bins)?, all))
}

/// Summary statistics (Welford mean/variance, sorted quantiles, histogram with `bins` bins) of
/// a sample.
///
/// # Errors
/// [`McError::BadOption`] for `bins` outside `1..=MAX_BINS`; [`McError::NonFinite`] naming the
/// first non-finite value.
pub fn summarize(all: &[f64], bins: usize) -> Result<McStats, McError> {
    check_bins(bins)?;
    let mut w = Welford {
        n: 0.0,
        mean: 0.0,
        m2: 0.0,
    };
    for &v in all {
        w.push(v);
    }
    let n = all.len();
    if let Some(index) = all.iter().position(|v| !v.is_finite()) {
        return Err(McError::NonFinite { index });
    }
    let mut sorted = all.to_vec();
    sorted.sort_by(f64::total_cmp);
    let (min, max) = (
        sorted.first().copied().unwrap_or(f64::NAN),
        sorted.last().copied().unwrap_or(f64::NAN),
    );
    let width = ((max - min) / bins as f64).max(f64::MIN_POSITIVE);
    let mut counts = vec![0u64; bins];
    for v in &sorted {
        let b = (((v - min) / width) as usize).min(bins - 1);
        counts[b] += 1;
    }
    let std = if w.n > 1.0 {
        (w.m2 / (w.n - 1.0)).sqrt()
    } else {
        0.0
    };
    Ok(McStats {
        n,
        min,
        max,
        mean: w.mean,
        std,
        mean_std_error: std / w.n.max(1.0).sqrt(),
        p50: quantile(&sorted, 0.5),
        p95: quantile(&sorted, 0.95),
        p9973: quantile(&sorted, 0.9973),
        histogram: counts
            .iter()
            .enumerate()
            .map(|(k, c)| {
                [
                    min + k as f64 * width,
                    min + (k + 1) as f64 * width,
                    *c as f64,
                ]
            })
            .collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::RngExt;

    #[test]
    fn uniform_statistics_and_thread_independence() {
        let opts = McOptions {
            samples: 20_000,
            seed: 7,
            bins: 10,
        };
        let (s, v) = run(&opts, |r, _| r.random::<f64>(), &Progress::none()).unwrap();
        assert!((s.mean - 0.5).abs() < 4.0 * (1.0 / 12f64).sqrt() / (20_000f64).sqrt());
        assert!((s.std - (1.0 / 12f64).sqrt()).abs() < 0.01);
        assert!((s.p50 - 0.5).abs() < 0.02 && (s.p95 - 0.95).abs() < 0.01);
        // Same result on one thread.
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let (_, v1) =
            pool.install(|| run(&opts, |r, _| r.random::<f64>(), &Progress::none()).unwrap());
        assert_eq!(v, v1);
        assert_eq!(s.histogram.iter().map(|h| h[2]).sum::<f64>(), 20_000.0);
    }

    /// The sink hears every sample once, in chunks (20 chunks of 1024 and one of 480).
    #[test]
    fn progress_hears_each_sample_once() {
        use std::sync::Arc;
        use std::sync::atomic::{AtomicU64, Ordering};
        let (samples, calls) = (Arc::new(AtomicU64::new(0)), Arc::new(AtomicU64::new(0)));
        let (s, c) = (Arc::clone(&samples), Arc::clone(&calls));
        let sink = Progress::new(move |n| {
            s.fetch_add(n, Ordering::Relaxed);
            c.fetch_add(1, Ordering::Relaxed);
        });
        let opts = McOptions::default().with_samples(20_960);
        run(&opts, |r, _| r.random::<f64>(), &sink).unwrap();
        assert_eq!(samples.load(Ordering::Relaxed), 20_960);
        assert_eq!(calls.load(Ordering::Relaxed), 21);
    }

    #[test]
    fn degenerate_counts_are_typed_errors() {
        let f = |r: &mut ChaCha8Rng, _: usize| r.random::<f64>();
        for (samples, bins) in [(0, 10), (MAX_SAMPLES + 1, 10), (10, 0), (10, usize::MAX)] {
            let o = McOptions {
                samples,
                seed: 1,
                bins,
            };
            assert!(matches!(
                run(&o, f, &Progress::none()),
                Err(McError::BadOption { .. })
            ));
        }
        let o = McOptions {
            samples: 3000,
            seed: 1,
            bins: 5,
        };
        assert_eq!(
            run(
                &o,
                |_, i| if i == 2500 { f64::NAN } else { 1.0 },
                &Progress::none()
            ),
            Err(McError::NonFinite { index: 2500 })
        );
        // One sample: exact statistics, zero spread.
        let o = McOptions {
            samples: 1,
            seed: 1,
            bins: 3,
        };
        let (s, _) = run(&o, |_, _| 2.5, &Progress::none()).unwrap();
        assert_eq!(
            (s.min, s.max, s.mean, s.std, s.p50),
            (2.5, 2.5, 2.5, 0.0, 2.5)
        );
    }
}
