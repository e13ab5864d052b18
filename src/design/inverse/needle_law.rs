//! The needle law `ψ3(t)`: what step 1 produces and every later stage reads (docs/math/chain.md §3.3–§4).
//! On its own so that the stages that read it (compatibility, the patent route, the refinement)
//! do not depend on step 1 itself.

use crate::math::periodic::{PeriodicSpline, spectral_derivative};
use std::f64::consts::TAU;

/// The needle's relative rotation `ψ3(t)` (rad) as a function of the carrier angle `t` (rad)
/// measured from the reference instant: stored as the periodic part `p(t) = ψ3(t) − t`.
#[derive(Debug, Clone)]
pub struct NeedleLaw {
    p: PeriodicSpline,
    samples: Vec<f64>,
}

impl NeedleLaw {
    /// From uniform samples `p_n = ψ3(2πn/N) − 2πn/N` (rad).
    #[must_use]
    pub fn from_samples(samples: Vec<f64>) -> Self {
        let p = PeriodicSpline::uniform(0.0, samples.clone(), TAU).expect("grid has ≥ 8 samples");
        Self { p, samples }
    }

    /// From a function `ψ3(t)` sampled at `n` uniform angles.
    #[must_use]
    pub fn from_fn(n: usize, psi3: impl Fn(f64) -> f64) -> Self {
        let s = (0..n)
            .map(|k| TAU * k as f64 / n as f64)
            .map(|t| psi3(t) - t)
            .collect();
        Self::from_samples(s)
    }

    /// `ψ3(t)`, rad, any real t (`ψ3(t + 2π) = ψ3(t) + 2π`).
    #[must_use]
    pub fn psi3(&self, t: f64) -> f64 {
        t + self.p.value(t)
    }

    /// `i31(t) = dψ3/dt = 1 − i3H` (docs/math/chain.md §4).
    #[must_use]
    pub fn i31(&self, t: f64) -> f64 {
        1.0 + self.p.derivative(t)
    }

    /// The uniform samples of `p = ψ3 − t` (rad).
    #[must_use]
    pub fn samples(&self) -> &[f64] {
        &self.samples
    }

    /// `i31` on the sample grid, spectrally (docs/math/chain.md §3.3).
    #[must_use]
    pub fn i31_samples(&self) -> Vec<f64> {
        spectral_derivative(&self.samples)
            .into_iter()
            .map(|d| 1.0 + d)
            .collect()
    }
}
