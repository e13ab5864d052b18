//! The perimeter of the train's pitch curves as a function of the sun ratio: what a tooth count
//! at a module asks of the design.
//!
//! The sun pitch curve is `r1(θ) = a·i/(1 + i)`, so its perimeter is `L = a·L̂(i)` with the unit
//! perimeter
//!
//! ```text
//! L̂ = ∮ √(r̂² + r̂_θ²) dθ,   r̂ = i/(1 + i),   r̂_θ = i′/(1 + i)²
//! ```
//!
//! (the intermediate and the planet roll on the sun without slip: the same perimeter). `z` teeth
//! of module `m` need `L = zπm`, hence `a = zπm/L̂(i)`: the centre distance follows from the ratio.
//! The integrand is smooth and 2π-periodic, so the trapezoid rule on a uniform grid converges
//! geometrically; at 32 samples per period of the highest harmonic (at least 2048) it is exact to
//! rounding for the admissible ratios. The gradient with respect to the Fourier coefficients
//! (`i = 1 + Σ a_k cos kθ + b_k sin kθ`) is the same sum of
//!
//! ```text
//! ∂√(r̂² + r̂_θ²)/∂i  = (r̂/(1+i)² − 2 r̂_θ i′/(1+i)³)/√…,   ∂√…/∂i′ = r̂_θ/((1+i)²·√…)
//! ∂i/∂a_k = cos kθ,  ∂i′/∂a_k = −k sin kθ,  ∂i/∂b_k = sin kθ,  ∂i′/∂b_k = k cos kθ
//! ```
//!
//! ```
//! use ncgear::geometry::{fourier::SunRatio, perimeter::unit_perimeter};
//! // i = 1: the sun is a circle of radius a/2, perimeter πa.
//! let circle = SunRatio::new(vec![0.0], vec![0.0]).unwrap();
//! assert!((unit_perimeter(&circle) - std::f64::consts::PI).abs() < 1e-14);
//! ```

use crate::geometry::fourier::SunRatio;
use std::f64::consts::TAU;

/// Trapezoid nodes for a ratio of order `k`.
fn nodes(k: usize) -> usize {
    (32 * k).max(2048)
}

/// The integrand `√(r̂² + r̂_θ²)` from `(i, i′)`.
#[inline]
pub(crate) fn unit_speed(i: f64, d: f64) -> f64 {
    let s = 1.0 + i;
    let (r, rt) = (i / s, d / (s * s));
    (r * r + rt * rt).sqrt()
}

/// Unit perimeter `L̂` of the sun pitch curve (perimeter at centre distance 1; the perimeter at
/// centre distance `a` mm is `a·L̂` mm).
#[must_use]
pub fn unit_perimeter(ratio: &SunRatio) -> f64 {
    let n = nodes(ratio.order());
    let h = TAU / n as f64;
    (0..n)
        .map(|j| {
            let [i, d, _] = ratio.eval3(h * j as f64);
            unit_speed(i, d)
        })
        .sum::<f64>()
        * h
}

/// `L̂` and its gradient with respect to `[a_1..a_K, b_1..b_K]` (module documentation).
#[must_use]
pub fn unit_perimeter_gradient(ratio: &SunRatio) -> (f64, Vec<f64>) {
    let k = ratio.order();
    let n = nodes(k);
    let h = TAU / n as f64;
    let mut grad = vec![0.0; 2 * k];
    let mut total = 0.0;
    for j in 0..n {
        let th = h * j as f64;
        let [i, d, _] = ratio.eval3(th);
        let s = 1.0 + i;
        let (r, rt) = (i / s, d / (s * s));
        let sp = (r * r + rt * rt).sqrt();
        total += sp;
        let gi = (r / (s * s) - 2.0 * rt * d / (s * s * s)) / sp;
        let gd = rt / (s * s * sp);
        for kk in 0..k {
            let kf = (kk + 1) as f64;
            let (sn, cs) = (kf * th).sin_cos();
            grad[kk] += gi * cs - gd * kf * sn;
            grad[k + kk] += gi * sn + gd * kf * cs;
        }
    }
    grad.iter_mut().for_each(|g| *g *= h);
    (total * h, grad)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::mechanism::Mechanism;

    fn ratio() -> SunRatio {
        SunRatio::new(vec![0.25, 0.04, -0.02], vec![0.03, 0.0, 0.01]).unwrap()
    }

    #[test]
    fn matches_the_pitch_curves_perimeter() {
        let m = Mechanism {
            a_mm: 44.0,
            l3_mm: 170.0,
            ratio: ratio(),
            sun_phase_rad: 0.0,
            needle_angle_rad: 0.0,
            idler_offset_rad: 0.0,
        };
        let sun = m.sun_curve(7200).unwrap().perimeter_mm(1e-10);
        let mid = m.intermediate_curve(7200).unwrap().perimeter_mm(1e-10);
        let l = 44.0 * unit_perimeter(&ratio());
        assert!((sun - l).abs() < 1e-8 * l, "{sun} vs {l}");
        assert!((mid - l).abs() < 1e-7 * l, "{mid} vs {l}");
    }

    #[test]
    fn gradient_matches_central_differences() {
        let r = ratio();
        let (l, g) = unit_perimeter_gradient(&r);
        assert!((l - unit_perimeter(&r)).abs() < 1e-13);
        let (a, b) = (r.cos_coefficients().to_vec(), r.sin_coefficients().to_vec());
        for c in 0..6 {
            let eps = 1e-6;
            let shifted = |s: f64| {
                let (mut a, mut b) = (a.clone(), b.clone());
                if c < 3 {
                    a[c] += s;
                } else {
                    b[c - 3] += s;
                }
                unit_perimeter(&SunRatio::new(a, b).unwrap())
            };
            let fd = (shifted(eps) - shifted(-eps)) / (2.0 * eps);
            assert!(
                (fd - g[c]).abs() < 1e-7,
                "coefficient {c}: {fd} vs {}",
                g[c]
            );
        }
    }
}
