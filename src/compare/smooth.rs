//! A weighted least-squares Fourier series of a periodic quantity sampled at scattered carrier
//! angles: `f(φ) = c₀ + Σ_{k=1}^{K} (a_k cos kφ + b_k sin kφ)`, from the normal equations
//! (Cholesky). The systematic deviation of a track from its design is such a smooth function
//! of the carrier angle; the frames' noise averages out in it (standard error
//! `σ·√((2K+1)/n)` for `n` frames spread over the turn).

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
