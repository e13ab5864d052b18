//! Steps 3–4: the patent's segmented-ratio design (docs/math/chain.md §7), in the τ-shifted frame.
//!
//! Front segment `F(u) = Φ(u)`, back segment `G(v) = Φ(π + v) − π`, both on `[0, π]` with half
//! closure `F(π) = G(π) = π`. From a Fourier hypothesis
//! `F′₀(u) = 1 + Σ A_n sin(2n u + φ_n)` (ω = 2, so `∫_0^π F′₀ = π` exactly), route "ac" solves
//! `G = F∘Ψf⁻¹`, i.e. `G′(u) = F′(h(u))·h′(u)` with `h = Ψf⁻¹`; route "bd" solves `G = F∘Ψb`.
//! Then the mirror/weight iteration (docs/math/chain.md §7.3):
//!
//! ```text
//! J0 = max(|F′(0) − G′(π)|, |F′(π) − G′(0)|);  stop at the first J0 ≤ tol_J
//! F′ ← w1·G′(π − u) + (1 − w1)·F′
//! ```
//!
//! capped at `k_max` iterations (the interior degenerates if continued on asymmetric targets).

use crate::design::inverse::needle_law::NeedleLaw;
use crate::math::roots::invert_increasing;
use std::f64::consts::PI;

/// Which three of the patent's four relations are solved exactly (docs/math/chain.md §15 item 4).
#[derive(
    Debug,
    Clone,
    Copy,
    PartialEq,
    Eq,
    Default,
    serde::Serialize,
    serde::Deserialize,
    schemars::JsonSchema,
)]
#[serde(rename_all = "lowercase")]
pub enum Route {
    /// Front half exact, relation (b) as the residual (default).
    #[default]
    Ac,
    /// Back half exact.
    Bd,
}

/// Parameters of the segmented design (docs/math/chain.md §7).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct SegmentedOptions {
    /// Hypothesis harmonics `(A_n, φ_n rad)` of `sin(2n u + φ_n)`, n = 1, 2, …; empty (default) for `F′₀ ≡ 1`.
    pub hypothesis: Vec<(f64, f64)>,
    /// Mirror weight `w1` (0.5, the default, converges the junctions in one step).
    pub w1: f64,
    /// Junction tolerance `tol_J`, relative to mean(F′) = 1. Default 1e-6.
    pub tol_j: f64,
    /// Iteration cap `k_max`. Default 20.
    pub k_max: usize,
    /// Route. Default [`Route::Ac`].
    pub route: Route,
}

crate::builder::with_fields!(SegmentedOptions {
    with_hypothesis => hypothesis: Vec<(f64, f64)>,
    with_w1 => w1: f64,
    with_tol_j => tol_j: f64,
    with_k_max => k_max: usize,
    with_route => route: Route,
});

impl Default for SegmentedOptions {
    fn default() -> Self {
        Self {
            hypothesis: Vec::new(),
            w1: 0.5,
            tol_j: 1e-6,
            k_max: 20,
            route: Route::Ac,
        }
    }
}

/// Why the hypothesis is unusable.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SegmentedError {
    /// `Σ|A_n| ≥ 1` would let the ratio reach zero.
    #[error(
        "the Fourier hypothesis amplitudes sum to {0:.4} ≥ 1; F′ must stay positive (Σ|A_n| < 1)"
    )]
    HypothesisTooLarge(f64),
    /// The mirror weight is outside (0, 1].
    #[error("mirror weight w1 = {0} must be in (0, 1]")]
    BadWeight(f64),
}

/// Result of the segmented design: the ratio polyline on a uniform grid of the τ-frame.
#[derive(Debug, Clone, PartialEq, serde::Serialize, schemars::JsonSchema)]
pub struct Segmented {
    /// `i21(t′_n)`, `t′_n = 2πn/N` (front samples for `t′ < π`, back samples after).
    #[serde(skip)]
    pub samples: Vec<f64>,
    /// Junction value mismatch of the returned iterate.
    pub j0: f64,
    /// Junction slope mismatch (reported only, docs/math/chain.md §7.3).
    pub j1: f64,
    /// Iterations done.
    pub iterations: usize,
    /// Whether `J0 ≤ tol_J` was reached.
    pub converged: bool,
}

/// Runs the segmented design for origin τ (rad) on a grid of `n` (even) samples per turn.
pub fn design(
    law: &NeedleLaw,
    tau: f64,
    n: usize,
    opts: &SegmentedOptions,
) -> Result<Segmented, SegmentedError> {
    let amp: f64 = opts.hypothesis.iter().map(|h| h.0.abs()).sum();
    if amp >= 1.0 {
        return Err(SegmentedError::HypothesisTooLarge(amp));
    }
    if !(opts.w1 > 0.0 && opts.w1 <= 1.0) {
        return Err(SegmentedError::BadWeight(opts.w1));
    }
    let m = n / 2;
    let du = PI / m as f64;
    let base = law.psi3(tau);
    let psi_f = |u: f64| (law.psi3(tau + u) - base, law.i31(tau + u));
    let psi_b = |u: f64| (law.psi3(tau + PI + u) - base - PI, law.i31(tau + PI + u));
    // The map that carries F′ to G′: G′(u) = F′(w(u))·w′(u).
    let (w, dw): (Vec<f64>, Vec<f64>) = (0..=m)
        .map(|j| {
            let u = j as f64 * du;
            match opts.route {
                Route::Ac => {
                    let h = invert_increasing(psi_f, u, 0.0, PI, u, 1e-13);
                    (h, 1.0 / psi_f(h).1)
                }
                Route::Bd => {
                    let (v, d) = psi_b(u);
                    (v, d)
                }
            }
        })
        .unzip();
    let mut f: Vec<f64> = (0..=m)
        .map(|j| {
            let u = j as f64 * du;
            1.0 + opts
                .hypothesis
                .iter()
                .enumerate()
                .map(|(k, (a, ph))| a * (2.0 * (k + 1) as f64 * u + ph).sin())
                .sum::<f64>()
        })
        .collect();
    let interp = |f: &[f64], x: f64| {
        let y = (x / du).clamp(0.0, m as f64);
        let i = (y.floor() as usize).min(m - 1);
        let fr = y - i as f64;
        f[i] * (1.0 - fr) + f[i + 1] * fr
    };
    let trapz = |f: &[f64]| du * (f.iter().sum::<f64>() - 0.5 * (f[0] + f[m]));
    // (error, scale, ratio samples, angle samples, order)
    #[allow(clippy::type_complexity)]
    let mut best: Option<(f64, f64, Vec<f64>, Vec<f64>, usize)> = None;
    for k in 0..=opts.k_max {
        let scale = PI / trapz(&f);
        f.iter_mut().for_each(|v| *v *= scale);
        let g: Vec<f64> = (0..=m).map(|j| interp(&f, w[j]) * dw[j]).collect();
        let j0 = (f[0] - g[m]).abs().max((f[m] - g[0]).abs());
        let slope = |v: &[f64], at_end: bool| {
            if at_end {
                (v[m] - v[m - 1]) / du
            } else {
                (v[1] - v[0]) / du
            }
        };
        let j1 = (slope(&f, false) - slope(&g, true))
            .abs()
            .max((slope(&f, true) - slope(&g, false)).abs());
        if best.as_ref().is_none_or(|b| j0 < b.0) {
            best = Some((j0, j1, f.clone(), g.clone(), k));
        }
        if j0 <= opts.tol_j {
            break;
        }
        let w1 = opts.w1;
        f = (0..=m).map(|j| w1 * g[m - j] + (1.0 - w1) * f[j]).collect();
    }
    let (j0, j1, f, g, iterations) = best.expect("at least one iterate");
    let samples = (0..n)
        .map(|i| if i < m { f[i] } else { g[i - m] })
        .collect();
    Ok(Segmented {
        samples,
        j0,
        j1,
        iterations,
        converged: j0 <= opts.tol_j,
    })
}
