//! Realizability of a target needle law by the patent's train (docs/math/chain.md §6.4).
//!
//! The train can produce `ψ3` exactly iff `S_c = ψ3 + c` satisfies `S_c∘S_c = shift by 2π`.
//! Test: the half-closure origins τ are the roots of `D(τ) = ψ3(τ + π) − ψ3(τ) − π`; for each,
//!
//! ```text
//! Ψf(u) = ψ3(τ + u) − ψ3(τ),   Ψb(u) = ψ3(τ + π + u) − ψ3(τ) − π,   u ∈ [0, π]
//! E_c(τ) = max_u |Ψb(Ψf(u)) − u|            (rad; tip-equivalent ≈ l3·E_c mm)
//! ```
//!
//! and the origin with the smallest `E_c` is chosen (docs/math/chain.md §15 item 5).

use crate::design::inverse::needle_law::NeedleLaw;
use crate::math::roots::bracketed_root;
use std::f64::consts::{PI, TAU};

/// Compatibility of a target with the train.
#[derive(Debug, Clone, PartialEq, serde::Serialize, schemars::JsonSchema)]
pub struct Compatibility {
    /// Chosen half-closure origin τ, rad from the reference instant.
    pub tau_rad: f64,
    /// `E_c(τ)`, rad.
    pub residual_rad: f64,
    /// `i31(τ)·i31(τ + π)`; 1 for a compatible target.
    pub endpoint_product: f64,
    /// All half-closure origins found, rad in [0, 2π).
    pub origins_rad: Vec<f64>,
    /// `E_c` at each origin, rad.
    pub residuals_rad: Vec<f64>,
}

/// Finds the half-closure origins and compatibility residuals on a grid of `n` carrier angles
/// (roots refined by [`bracketed_root`] to `tol_rad`).
#[must_use]
pub fn analyse(law: &NeedleLaw, n: usize, tol_rad: f64) -> Compatibility {
    let d = |tau: f64| law.psi3(tau + PI) - law.psi3(tau) - PI;
    let grid: Vec<f64> = (0..n).map(|k| TAU * k as f64 / n as f64).collect();
    let dv: Vec<f64> = grid.iter().map(|&t| d(t)).collect();
    let scale = dv.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let mut origins = Vec::new();
    if scale < 1e-12 {
        // D ≡ 0: every τ is a half-closure origin; use a coarse candidate set (docs/math/chain.md §6.4).
        origins.extend((0..8).map(|k| TAU * k as f64 / 8.0));
    } else {
        for k in 0..n {
            let (a, b) = (dv[k], dv[(k + 1) % n]);
            if a == 0.0 {
                origins.push(grid[k]);
            } else if a * b < 0.0 {
                let root = bracketed_root(d, grid[k], grid[k] + TAU / n as f64, tol_rad);
                origins.push(root.rem_euclid(TAU));
            }
        }
    }
    let residuals: Vec<f64> = origins
        .iter()
        .map(|&tau| residual(law, tau, n / 2))
        .collect();
    let best = residuals
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))
        .map_or(0, |(i, _)| i);
    let tau = origins.get(best).copied().unwrap_or(0.0);
    Compatibility {
        tau_rad: tau,
        residual_rad: residuals.get(best).copied().unwrap_or(f64::INFINITY),
        endpoint_product: law.i31(tau) * law.i31(tau + PI),
        origins_rad: origins,
        residuals_rad: residuals,
    }
}

/// `E_c(τ) = max_u |Ψb(Ψf(u)) − u|` on `m + 1` points of `[0, π]`, rad.
#[must_use]
pub fn residual(law: &NeedleLaw, tau: f64, m: usize) -> f64 {
    let base = law.psi3(tau);
    (0..=m)
        .map(|j| {
            let u = PI * j as f64 / m as f64;
            let v = law.psi3(tau + u) - base;
            let back = law.psi3(tau + PI + v) - base - PI;
            (back - u).abs()
        })
        .fold(0.0, f64::max)
}
