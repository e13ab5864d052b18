//! Evaluation of sun-displacement sensor records (docs/math/companion.md §A.7–§A.8).
//!
//! Pipeline of [`Extractor::extract`]:
//!
//! 1. **Frame** (docs/math/companion.md §A.7): the model lives in the carrier frame. Housing-fixed sensors on a rotating
//!    carrier are either de-rotated with the measured carrier angle, `z_c = e^{−iθ_c} z_r`
//!    ([`Frame::HousingDerotate`]), or analysed in the full (complex) spectrum of `z_r = x_r + i y_r`,
//!    reading Z₊ at the signed frequency `ω_c + ω_p` and Z₋ at `ω_c − ω_p`
//!    ([`Frame::HousingFullSpectrum`]).
//! 2. **Collision check**: every pair of analysed lines closer than `min_separation_bins / T_rec`
//!    (Hz) gives a warning; the least-squares fit refuses a condition number above `max_condition`
//!    ([`OrbitError::Collision`](super::OrbitError::Collision)).
//! 3. **Extraction** at the known planet frequency ([`Method`]): linear least squares with the
//!    regressors `[1, t, sin ω_k t, cos ω_k t …]` for the planet line(s) and every nuisance line
//!    (default; exact for any non-integer number of periods, with drift, and gives the covariance
//!    `σ̂² (MᵀM)⁻¹`), or the Hann-windowed DTFT at the exact frequency, or synchronous resampling to
//!    an integer number of planet revolutions, or — for contrast only — the nearest plain FFT bin.
//! 4. Ellipse, sense and filtered orbit from the resulting [`Orbit`](super::Orbit) (docs/math/companion.md §A.6, §A.8 step 6).
//!
//! One file per idea: `record` (the [`Record`] and its CSV), `frame` ([`Frame`], detrend,
//! de-rotation), `extract` ([`ExtractOptions`], [`Extractor`], [`Measurement`]), `least_squares`
//! (the regression, its conditioning and covariance), `tsqr` (the blocked QR), `spectrum` (DTFT, Hann, synchronous average, [`full_spectrum`]),
//! `frequency` ([`Extractor::estimate_frequency`]) and `compare` ([`Comparison`]).
//!
//! ```
//! use ncgear::analysis::orbit::measure::{ExtractOptions, Extractor, Method, Record};
//! let w = std::f64::consts::TAU * 2.0; // ω_p, rad/s
//! let t: Vec<f64> = (0..400).map(|k| k as f64 * 0.01).collect();
//! let x = t.iter().map(|t| 5.0 * (w * t).sin()).collect();
//! let y = t.iter().map(|t| -5.0 * (w * t).cos()).collect(); // z = x + iy = −5i e^{iω_p t}
//! let rec = Record::new(t, x, y, None).unwrap();
//! let opts = ExtractOptions::default().with_method(Method::LeastSquares);
//! let m = Extractor::new(w, opts).unwrap().extract(&rec).unwrap();
//! assert!((m.orbit.z_plus_um.norm() - 5.0).abs() < 1e-9);
//! ```

mod compare;
mod extract;
mod frame;
mod frequency;
mod least_squares;
mod record;
mod spectrum;
mod tsqr;

pub use compare::Comparison;
pub use extract::{ExtractOptions, Extractor, Measurement, Method, Uncertainty};
pub use frame::Frame;
pub use frequency::FrequencyEstimate;
pub use record::{MAX_ABS_DISPLACEMENT_UM, MAX_ABS_TIME_S, MIN_SAMPLES, Record};
pub use spectrum::full_spectrum;
