//! Transmission-error harmonics, phase (coupling) compensation and Monte Carlo tolerance analysis
//! (docs/math/companion.md §C, after a paper on the coupling compensation of eccentricity errors
//! in a 3K planetary train).
//!
//! Each error term is an equivalent line-of-action error `e_k = A_k sin(ω_k t + φ_k)` (µm, rad/s).
//! A term's phase is fixed, or free (an assembly choice): `φ_k = s_k·β_k + c_k` with the assembly
//! angle β_k. The transmission error is `Δθ = e/r_b` (rad; ×206 264.806 for arc seconds).
//!
//! - same-frequency terms add as phasors (docs/math/companion.md §C.2 eq. C-1); zero-frequency terms are constants `A sin φ`;
//! - the peak of the sum is the **certified** peak over the common period ([`super::peak`]);
//! - the paper's phase scan (n equal steps) and greedy sequential assembly (docs/math/companion.md §C.3), a joint
//!   optimizer (multistart Nelder–Mead, argmin) for the gap to greedy;
//! - always reported: the certified peak, the sum-of-amplitudes bound `Σ|A_k|` and the
//!   phase-independent floor `sqrt(D_min² + Σ_j B_j,min²/2)` (RMS over a period; `B_j,min` the
//!   smallest phasor sum each frequency group can reach, `D_min` the smallest constant), which no
//!   choice of assembly phases can beat;
//! - Monte Carlo over random assembly phases (and amplitudes when distributions are given).
//!
//! Files: [`ErrorFile`] (the error file and its validation), [`Analysis`] (peaks, bounds and
//! compensation), [`Analysis::monte_carlo`] (random assembly), [`analyse`] (the whole report).

mod compensation;
mod error_file;
mod monte_carlo;
mod report;

pub use compensation::{Analysis, GreedyStep, Joint, Phasor, phasor_sum};
pub use error_file::{AmplitudeDist, BaseCircle, ErrorFile, ErrorTerm};
pub use report::{ToleranceOptions, ToleranceReport, analyse};

use crate::config::ConfigError;

/// Arc seconds per radian.
pub const ARCSEC_PER_RAD: f64 = 206_264.806_247_096_36;

/// Transmission error in arc seconds of a line-of-action error `e_um` (µm) at base radius `rb_mm`:
/// `e·10⁻³/r_b·206 264.8″`.
#[must_use]
pub fn arcsec(e_um: f64, rb_mm: f64) -> f64 {
    e_um * 1e-3 / rb_mm * ARCSEC_PER_RAD
}

/// Why an error file is unusable.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ToleranceError {
    /// Unreadable file.
    #[error("{file}: cannot read the error file: {message}")]
    Unreadable {
        /// File.
        file: String,
        /// Message.
        message: String,
    },
    /// Syntax or schema error (the parser names the key).
    #[error("{file}: {message}")]
    Parse {
        /// File.
        file: String,
        /// Message.
        message: String,
    },
    /// An impossible value.
    #[error("{file}: `{key}`: {message}")]
    BadValue {
        /// File.
        file: String,
        /// Key path.
        key: String,
        /// What is expected.
        message: String,
    },
}

impl From<ConfigError> for ToleranceError {
    fn from(e: ConfigError) -> Self {
        match e {
            ConfigError::Unreadable { file, message } => Self::Unreadable { file, message },
            ConfigError::Parse { file, message } => Self::Parse { file, message },
        }
    }
}
