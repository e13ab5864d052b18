//! A weighted least-squares Fourier series of a periodic quantity sampled at scattered carrier
//! angles: `f(φ) = c₀ + Σ_{k=1}^{K} (a_k cos kφ + b_k sin kφ)`, from the normal equations
//! (Cholesky). The systematic deviation of a track from its design is such a smooth function
//! of the carrier angle; the frames' noise averages out in it (standard error
//! `σ·√((2K+1)/n)` for `n` frames spread over the turn). [`bic_order`] chooses K from the
//! frames: the harmonics the deviation has, not those the noise would fill.

use nalgebra::{DMatrix, DVector};

/// A fitted Fourier series (of a scalar).
#[derive(Debug, Clone, PartialEq)]
pub struct Fourier {
    /// `[c₀, a₁, b₁, …, a_K, b_K]`.
    pub coeffs: Vec<f64>,
}

fn basis(phi: f64, order: usize, out: &mut [f64]) {
    out[0] = 1.0;
    let (s1, c1) = phi.sin_cos();
    let (mut s, mut c) = (0.0, 1.0);
    for k in 1..=order {
        (s, c) = (s * c1 + c * s1, c * c1 - s * s1);
        out[2 * k - 1] = c;
        out[2 * k] = s;
    }
}

impl Fourier {
    /// The series of order `order` fitted to `values[i]` at `phi[i]` (rad) with weights
    /// `weight[i]` (0 drops a sample), one per entry of `values`; `None` when the samples do not
    /// determine it (too few, or all in a gap of the turn).
    #[must_use]
    pub fn fit(
        phi: &[f64],
        values: &[Vec<f64>],
        weight: &[f64],
        order: usize,
    ) -> Option<Vec<Self>> {
        let m = 2 * order + 1;
        let mut ata = DMatrix::<f64>::zeros(m, m);
        let mut atb = vec![DVector::<f64>::zeros(m); values.len()];
        let mut row = vec![0.0; m];
        for (i, (&p, &w)) in phi.iter().zip(weight).enumerate() {
            if w <= 0.0 {
                continue;
            }
            basis(p, order, &mut row);
            for a in 0..m {
                let wa = w * row[a];
                for b in a..m {
                    ata[(a, b)] += wa * row[b];
                }
                for (v, rhs) in values.iter().zip(atb.iter_mut()) {
                    rhs[a] += wa * v[i];
                }
            }
        }
        for a in 0..m {
            for b in 0..a {
                ata[(a, b)] = ata[(b, a)];
            }
        }
        // A ridge of 1e-9 of the diagonal keeps a barely determined harmonic finite.
        let scale = (0..m).map(|a| ata[(a, a)]).fold(0.0, f64::max);
        for a in 0..m {
            ata[(a, a)] += 1e-9 * scale;
        }
        let chol = ata.cholesky()?;
        Some(
            atb.iter()
                .map(|rhs| Self {
                    coeffs: chol.solve(rhs).iter().copied().collect(),
                })
                .collect(),
        )
    }

    /// The order K.
    #[must_use]
    pub fn order(&self) -> usize {
        (self.coeffs.len() - 1) / 2
    }

    /// `f(φ)`.
    #[must_use]
    pub fn value(&self, phi: f64) -> f64 {
        let mut row = vec![0.0; self.coeffs.len()];
        basis(phi, self.order(), &mut row);
        row.iter().zip(&self.coeffs).map(|(a, b)| a * b).sum()
    }
}

/// The order `K ∈ [min, max]` of the series over `values` (every entry fitted at the same K)
/// that minimises Schwarz's Bayesian information criterion `N·ln(RSS/N) + P·ln N`, where `N`
/// is the number of weighted samples over all entries, `RSS` their weighted residual sum of
/// squares and `P = (2K + 1)·values.len()` the coefficients (Schwarz 1978; for Gaussian noise
/// of unknown σ). A harmonic stays when it lowers `RSS` by more than a factor `N^(−2/N)` per
/// pair of coefficients, about `2σ²·ln N` of the sum: on a track of an exactly built train, the
/// noise alone, the lowest order; on a real deviation, the harmonics it has. `min` when no order
/// can be fitted.
#[must_use]
pub fn bic_order(
    phi: &[f64],
    values: &[Vec<f64>],
    weight: &[f64],
    min: usize,
    max: usize,
) -> usize {
    let used = weight.iter().filter(|w| **w > 0.0).count();
    let n = (used * values.len()) as f64;
    let mut best = (f64::INFINITY, min);
    for k in min..=max.max(min) {
        let p = ((2 * k + 1) * values.len()) as f64;
        if p >= n {
            break;
        }
        let Some(fits) = Fourier::fit(phi, values, weight, k) else {
            continue;
        };
        let rss: f64 = fits
            .iter()
            .zip(values)
            .map(|(f, v)| {
                phi.iter()
                    .zip(v)
                    .zip(weight)
                    .filter(|(_, w)| **w > 0.0)
                    .map(|((p, x), w)| w * (x - f.value(*p)).powi(2))
                    .sum::<f64>()
            })
            .sum();
        let bic = n * (rss.max(1e-300) / n).ln() + p * n.ln();
        if bic < best.0 {
            best = (bic, k);
        }
    }
    best.1
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    /// Samples over a turn of `f` plus seeded Gaussian noise σ (Box–Muller).
    fn samples(n: usize, sigma: f64, f: impl Fn(f64) -> f64) -> (Vec<f64>, Vec<f64>) {
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut uniform = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let phi: Vec<f64> = (0..n).map(|i| TAU * i as f64 / n as f64).collect();
        let v = phi
            .iter()
            .map(|p| {
                let (u, w) = (uniform().max(1e-300), uniform());
                f(*p) + sigma * (-2.0 * u.ln()).sqrt() * (TAU * w).cos()
            })
            .collect();
        (phi, v)
    }

    #[test]
    fn the_information_criterion_keeps_the_harmonics_a_deviation_has_and_no_more() {
        let w = vec![1.0; 600];
        // Noise alone: the lowest order.
        let (phi, v) = samples(600, 0.3, |_| 0.0);
        assert_eq!(bic_order(&phi, &[v], &w, 2, 8), 2);
        // A deviation of harmonics 1 and 5 (0.2 mm each) under 0.3 mm of noise: order 5.
        let (phi, v) = samples(600, 0.3, |p| 0.2 * p.cos() + 0.2 * (5.0 * p).sin());
        assert_eq!(bic_order(&phi, &[v], &w, 2, 8), 5);
    }
}
