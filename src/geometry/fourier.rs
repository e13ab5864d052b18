//! The sun ratio as a closed Fourier series (docs/math/chain.md §8.1).
//!
//! ```text
//! i21(θ) = 1 + Σ_{k=1}^{K} ( a_k cos kθ + b_k sin kθ )          (dimensionless, θ in rad)
//! Φ(θ)   = ∫_0^θ i21 = θ + Σ ( a_k sin kθ + b_k (1 − cos kθ) ) / k
//! ```
//!
//! The constant term is fixed to 1, so the closure `Φ(2π) = 2π` (equal tooth counts, docs/math/chain.md §5) holds
//! exactly for every coefficient vector (check C1).
//!
//! ```
//! use ncgear::geometry::fourier::SunRatio;
//! let i21 = SunRatio::new(vec![0.1], vec![0.0]).unwrap();
//! assert!((i21.value(0.0) - 1.1).abs() < 1e-15);
//! assert!((i21.integral(std::f64::consts::TAU) - std::f64::consts::TAU).abs() < 1e-12);
//! ```

use crate::math::periodic::fft_coefficients;
use crate::math::roots::invert_increasing;
use std::f64::consts::{PI, TAU};

/// Block length of [`SunRatio::inverse_integral_along`]: warm starts inside, parallel across.
pub const ALONG_BLOCK: usize = 128;

/// Largest Halley step (rad) [`SunRatio::inverse_integral_with_slopes`] takes without a second
/// evaluation (the ratio's Taylor terms there stay accurate to ~1e-12).
pub const HALLEY_ACCEPT_RAD: f64 = 1e-5;

/// The Halley step is taken when its estimated error is below this fraction of the tolerance
/// (the third derivative is estimated at the guess, not bounded).
const HALLEY_SAFETY: f64 = 0.1;

/// A positive 2π-periodic sun ratio `i21(θ)` with mean exactly 1, as a truncated Fourier series.
#[derive(Debug, Clone, PartialEq)]
pub struct SunRatio {
    a: Vec<f64>,
    b: Vec<f64>,
    /// Bound on |Φ(θ) − θ| (rad), used to bracket Φ⁻¹.
    drift_bound: f64,
}

/// Why a set of Fourier coefficients is not a usable sun ratio.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum RatioError {
    /// `a` and `b` differ in length.
    #[error("cosine and sine coefficient lists differ in length ({a} vs {b})")]
    LengthMismatch {
        /// Number of cosine coefficients.
        a: usize,
        /// Number of sine coefficients.
        b: usize,
    },
    /// A coefficient is NaN or infinite.
    #[error("Fourier coefficient {index} is not finite")]
    NotFinite {
        /// Harmonic number (1-based).
        index: usize,
    },
    /// The ratio is not strictly positive somewhere.
    #[error(
        "the sun ratio reaches {min_ratio:.4} ≤ 0 at {at_deg:.2}°; gear ratios must stay positive"
    )]
    NotPositive {
        /// Smallest sampled ratio.
        min_ratio: f64,
        /// Where, degrees.
        at_deg: f64,
    },
}

impl SunRatio {
    /// Builds `i21 = 1 + Σ a_k cos kθ + b_k sin kθ` (`a[k−1]`, `b[k−1]` are harmonic k) and checks
    /// that it is strictly positive (sampled at 64·K + 256 points).
    pub fn new(a: Vec<f64>, b: Vec<f64>) -> Result<Self, RatioError> {
        if a.len() != b.len() {
            return Err(RatioError::LengthMismatch {
                a: a.len(),
                b: b.len(),
            });
        }
        if let Some(i) = a
            .iter()
            .zip(&b)
            .position(|(x, y)| !(x.is_finite() && y.is_finite()))
        {
            return Err(RatioError::NotFinite { index: i + 1 });
        }
        let s = Self::new_unchecked(a, b);
        let (min_ratio, at) = s.sampled_extreme(64 * s.order() + 256, false);
        if min_ratio <= 0.0 {
            return Err(RatioError::NotPositive {
                min_ratio,
                at_deg: at.to_degrees(),
            });
        }
        Ok(s)
    }

    /// Builds a series without the positivity check (for optimizers that penalise bounds
    /// themselves). Lengths must match; non-finite values are replaced by 0.
    #[must_use]
    pub fn new_unchecked(mut a: Vec<f64>, mut b: Vec<f64>) -> Self {
        let k = a.len().min(b.len());
        a.truncate(k);
        b.truncate(k);
        for v in a.iter_mut().chain(b.iter_mut()) {
            if !v.is_finite() {
                *v = 0.0;
            }
        }
        let drift_bound = a
            .iter()
            .zip(&b)
            .enumerate()
            .map(|(k, (x, y))| (x.abs() + 2.0 * y.abs()) / (k + 1) as f64)
            .sum::<f64>()
            + 1e-9;
        Self { a, b, drift_bound }
    }

    /// Least-squares fit of order `K` to uniform samples `y_n = i(2πn/N)` (docs/math/chain.md §8.1): the truncated
    /// DFT with the mean forced to 1 (exact closure). Requires `N ≥ 2K + 1`.
    pub fn fit_uniform(samples: &[f64], order: usize) -> Result<Self, RatioError> {
        let (a, b) = Self::dft_coefficients(samples, order);
        Self::new(a, b)
    }

    /// [`SunRatio::fit_uniform`] without the positivity check (for a start that is made
    /// admissible afterwards, [`SunRatio::admissible`]).
    #[must_use]
    pub fn fit_uniform_unchecked(samples: &[f64], order: usize) -> Self {
        let (a, b) = Self::dft_coefficients(samples, order);
        Self::new_unchecked(a, b)
    }

    /// Cosine and sine coefficients 1..=K of the truncated DFT of uniform samples.
    fn dft_coefficients(samples: &[f64], order: usize) -> (Vec<f64>, Vec<f64>) {
        let c = fft_coefficients(samples);
        let k_max = order
            .min(c.len().saturating_sub(1))
            .min((samples.len().saturating_sub(1)) / 2);
        (
            (1..=k_max).map(|k| 2.0 * c[k].re).collect(),
            (1..=k_max).map(|k| -2.0 * c[k].im).collect(),
        )
    }

    /// The same series at order `k`: truncated, or padded with zero coefficients.
    #[must_use]
    pub fn with_order(&self, k: usize) -> Self {
        let mut a = self.a.clone();
        let mut b = self.b.clone();
        a.resize(k, 0.0);
        b.resize(k, 0.0);
        Self::new_unchecked(a, b)
    }

    /// Fourier order K.
    #[must_use]
    pub fn order(&self) -> usize {
        self.a.len()
    }

    /// Cosine coefficients `a_1..a_K`.
    #[must_use]
    pub fn cos_coefficients(&self) -> &[f64] {
        &self.a
    }

    /// Sine coefficients `b_1..b_K`.
    #[must_use]
    pub fn sin_coefficients(&self) -> &[f64] {
        &self.b
    }

    /// The harmonics at `θ`: `(k, a_k, b_k, sin kθ, cos kθ)` for `k = 1..=K`, the sines and
    /// cosines by the rotation recurrence from one `sin_cos` (every evaluation below walks them).
    fn harmonics(&self, theta: f64) -> impl Iterator<Item = (f64, f64, f64, f64, f64)> + '_ {
        let (s1, c1) = theta.sin_cos();
        self.a
            .iter()
            .zip(&self.b)
            .enumerate()
            .scan((s1, c1), move |(s, c), (k, (&a, &b))| {
                let term = ((k + 1) as f64, a, b, *s, *c);
                (*s, *c) = (*s * c1 + *c * s1, *c * c1 - *s * s1);
                Some(term)
            })
    }

    /// `i21`, `i21′`, `i21″` from one harmonic.
    #[inline]
    fn add_eval3(out: &mut [f64; 3], (k, a, b, s, c): (f64, f64, f64, f64, f64)) {
        out[0] += a * c + b * s;
        out[1] += k * (b * c - a * s);
        out[2] -= k * k * (a * c + b * s);
    }

    /// `(i21, di21/dθ, d²i21/dθ²)` at `θ` (rad).
    #[must_use]
    pub fn eval3(&self, theta: f64) -> [f64; 3] {
        let mut out = [1.0, 0.0, 0.0];
        for h in self.harmonics(theta) {
            Self::add_eval3(&mut out, h);
        }
        out
    }

    /// `i21(θ)`.
    #[must_use]
    pub fn value(&self, theta: f64) -> f64 {
        self.eval3(theta)[0]
    }

    /// `Φ(θ) = ∫_0^θ i21` (rad), for any real θ (not wrapped: `Φ(θ + 2π) = Φ(θ) + 2π`).
    #[must_use]
    pub fn integral(&self, theta: f64) -> f64 {
        self.integral_and_value(theta).0
    }

    /// `(Φ(θ), i21(θ))`.
    #[must_use]
    pub fn integral_and_value(&self, theta: f64) -> (f64, f64) {
        let (mut phi, mut i) = (theta, 1.0);
        for (k, a, b, s, c) in self.harmonics(theta) {
            phi += (a * s + b * (1.0 - c)) / k;
            i += a * c + b * s;
        }
        (phi, i)
    }

    /// `(Φ(θ), [i21, i21′, i21″](θ))`: [`Self::integral`] and [`Self::eval3`] from one sine and
    /// cosine and one pass over the harmonics.
    #[must_use]
    pub fn integral_and_eval3(&self, theta: f64) -> (f64, [f64; 3]) {
        let (mut phi, mut out) = (theta, [1.0, 0.0, 0.0]);
        for h @ (k, a, b, s, c) in self.harmonics(theta) {
            phi += (a * s + b * (1.0 - c)) / k;
            Self::add_eval3(&mut out, h);
        }
        (phi, out)
    }

    /// `Φ⁻¹(y)` (rad): Newton with bisection safeguard to `tol_rad` (docs/math/chain.md §14, "Φ⁻¹ robustness").
    #[must_use]
    pub fn inverse_integral(&self, y: f64, tol_rad: f64) -> f64 {
        self.inverse_integral_from(y, y, tol_rad)
    }

    /// [`Self::inverse_integral`] started from `guess_rad` (clamped into the bracket
    /// `y ± drift`): a nearby earlier solution saves most Newton steps along a curve.
    #[must_use]
    pub fn inverse_integral_from(&self, y: f64, guess_rad: f64, tol_rad: f64) -> f64 {
        let m = self.drift_bound;
        let guess = if guess_rad.is_finite() { guess_rad } else { y };
        invert_increasing(
            |x| self.integral_and_value(x),
            y,
            y - m,
            y + m,
            guess,
            tol_rad,
        )
    }

    /// `S = Φ⁻¹(y)` (rad) from a close `guess_rad`, with `[i21(S), i21′(S)]`: what a curve's
    /// evaluation needs at the contact angle, from one pass over the harmonics where the guess
    /// is close.
    ///
    /// At the guess `x₀` one pass gives `f = Φ(x₀) − y`, `f′ = i21`, `f″ = i21′` and `i21″`.
    /// Halley's step `d = −2ff′/(2f′² − ff″)` has error `≈ (f‴/(6f′) − (f″/(2f′))²)·d³`
    /// (`f‴ = i21″`): when that is below a tenth of `tol_rad` and `|d| ≤` [`HALLEY_ACCEPT_RAD`],
    /// `S = x₀ + d` is taken, and the ratio there follows from its Taylor terms at `x₀`
    /// (`i21 + i21′d + i21″d²/2`, `i21′ + i21″d`). A farther guess falls back to the safeguarded
    /// solve ([`Self::inverse_integral_from`], to `tol_rad`) and one more pass for the ratio.
    #[must_use]
    pub fn inverse_integral_with_slopes(
        &self,
        y: f64,
        guess_rad: f64,
        tol_rad: f64,
    ) -> (f64, [f64; 2]) {
        if guess_rad.is_finite() {
            let (phi, [i, di, ddi]) = self.integral_and_eval3(guess_rad);
            let f = phi - y;
            let den = 2.0 * i * i - f * di;
            if i > 0.0 && den > 0.0 {
                let d = -2.0 * f * i / den;
                // Halley's error, `(f‴/(6f′) − (f″/(2f′))²)·d³`, with `f‴ = i21″` taken at x₀.
                let c = ddi.abs() / (6.0 * i) + (di / (2.0 * i)).powi(2);
                if d.abs() <= HALLEY_ACCEPT_RAD && c * d.abs().powi(3) <= HALLEY_SAFETY * tol_rad {
                    let i_s = i + d * (di + 0.5 * d * ddi);
                    return (guess_rad + d, [i_s, di + d * ddi]);
                }
            }
        }
        let s = self.inverse_integral_from(y, guess_rad, tol_rad);
        let [i, di, _] = self.eval3(s);
        (s, [i, di])
    }

    /// `Φ⁻¹(y_k)` (rad) for `k = 0..n`, where `y_k` (rad) runs smoothly with `k` (a curve's
    /// samples). Solved in fixed blocks of [`ALONG_BLOCK`] (in parallel, the same numbers for any
    /// thread count); inside a block each solve starts from the linear extrapolation of the two
    /// before it, which saves most Newton steps. Each value meets `tol_rad` as
    /// [`Self::inverse_integral`] does.
    #[must_use]
    pub fn inverse_integral_along(
        &self,
        n: usize,
        y: impl Fn(usize) -> f64 + Sync,
        tol_rad: f64,
    ) -> Vec<f64> {
        use rayon::prelude::*;
        let mut out = vec![0.0; n];
        out.par_chunks_mut(ALONG_BLOCK)
            .enumerate()
            .for_each(|(b, block)| {
                let mut y_prev = f64::NAN;
                for j in 0..block.len() {
                    let yk = y(b * ALONG_BLOCK + j);
                    let guess = match j {
                        0 => yk,
                        // Φ′ = i21 ≈ 1 on average: the step in y is the first guess of the step in x.
                        1 => block[0] + (yk - y_prev),
                        _ => 2.0 * block[j - 1] - block[j - 2],
                    };
                    block[j] = self.inverse_integral_from(yk, guess, tol_rad);
                    y_prev = yk;
                }
            });
        out
    }

    /// `S(t_k) = Φ⁻¹(Φ(t_k) + c)` (rad) at the `n` uniform angles `t_k = t0 + 2πk/n`
    /// ([`Self::contact_map`] along a turn, by [`Self::inverse_integral_along`]).
    #[must_use]
    pub fn contact_map_uniform(
        &self,
        t0_rad: f64,
        shift_rad: f64,
        n: usize,
        tol_rad: f64,
    ) -> Vec<f64> {
        let t = |k: usize| t0_rad + TAU * k as f64 / n as f64;
        self.inverse_integral_along(n, |k| self.integral(t(k)) + shift_rad, tol_rad)
    }

    /// Planet contact map of the collinear train `S(t) = Φ⁻¹(Φ(t) + π)`, rad
    /// (docs/math/chain.md §6.2): [`Self::contact_map`] at `c = π`.
    #[must_use]
    pub fn half_turn_map(&self, t: f64, tol_rad: f64) -> f64 {
        self.contact_map(t, PI, tol_rad)
    }

    /// Planet contact map `S(t) = Φ⁻¹(Φ(t) + c)`, rad: the sun angle whose contact with the
    /// intermediate gear sits `c` (rad) further round the intermediate gear than the contact at
    /// `t` — `c = π + 2ε` for an intermediate axis `ε` off the carrier line
    /// ([`crate::geometry::mechanism`]), `π` on it.
    #[must_use]
    pub fn contact_map(&self, t: f64, shift_rad: f64, tol_rad: f64) -> f64 {
        self.inverse_integral(self.integral(t) + shift_rad, tol_rad)
    }

    /// Smallest and largest value of the ratio over the turn: the extremes of a grid of 64·K + 512
    /// angles refined by Newton steps on `i21′ = 0` (exact to rounding for the global extremes).
    #[must_use]
    pub fn range(&self) -> [f64; 2] {
        let ratio = self;
        let n = 64 * ratio.order() + 512;
        let h = TAU / n as f64;
        let refine = |th0: f64, v0: f64, max: bool| {
            let mut th = th0;
            let mut best = v0;
            for _ in 0..8 {
                let [v, d1, d2] = ratio.eval3(th);
                if (max && v > best) || (!max && v < best) {
                    best = v;
                }
                if d2 == 0.0 {
                    break;
                }
                let step = (-d1 / d2).clamp(-h, h);
                th += step;
                if step.abs() < 1e-14 {
                    break;
                }
            }
            let v = ratio.value(th);
            if max { best.max(v) } else { best.min(v) }
        };
        let [(lo, at_lo), (hi, at_hi)] = ratio.sampled_extremes(n);
        [refine(at_lo, lo, false), refine(at_hi, hi, true)]
    }

    /// Makes a ratio admissible by shrinking `i21 − 1` (closure kept): the factor is the largest
    /// `s ≤ 1` with `1 + s(i − 1)` inside `bounds` narrowed by 1e-9 relative ([`SunRatio::range`]).
    #[must_use]
    pub fn admissible(&self, bounds: [f64; 2]) -> SunRatio {
        let ratio = self;
        let [lo, hi] = ratio.range();
        let (blo, bhi) = (bounds[0] * (1.0 + 1e-9), bounds[1] * (1.0 - 1e-9));
        let mut s: f64 = 1.0;
        if hi > bhi && hi > 1.0 {
            s = s.min((bhi - 1.0) / (hi - 1.0));
        }
        if lo < blo && lo < 1.0 {
            s = s.min((1.0 - blo) / (1.0 - lo));
        }
        if s >= 1.0 {
            return ratio.clone();
        }
        SunRatio::new_unchecked(
            ratio.cos_coefficients().iter().map(|v| v * s).collect(),
            ratio.sin_coefficients().iter().map(|v| v * s).collect(),
        )
    }

    /// Smallest (or, with `max = true`, largest) sampled ratio on `n` uniform angles, and where (rad).
    #[must_use]
    pub fn sampled_extreme(&self, n: usize, max: bool) -> (f64, f64) {
        self.sampled_extremes(n)[usize::from(max)]
    }

    /// Both [`Self::sampled_extreme`]s from one pass over the `n` angles: `[(min, at), (max, at)]`
    /// (values dimensionless, angles rad; the first angle of a tie, or of a NaN, is kept).
    #[must_use]
    pub fn sampled_extremes(&self, n: usize) -> [(f64, f64); 2] {
        let (mut lo, mut hi) = ((f64::INFINITY, 0.0), (f64::NEG_INFINITY, 0.0));
        for j in 0..n {
            let th = TAU * j as f64 / n as f64;
            let v = self.value(th);
            if v < lo.0 || v.is_nan() {
                lo = (v, th);
            }
            if v > hi.0 || v.is_nan() {
                hi = (v, th);
            }
        }
        [lo, hi]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fit_recovers_a_trig_polynomial_and_closes() {
        let f = |t: f64| 1.0 + 0.2 * (2.0 * t).cos() - 0.1 * (3.0 * t + 0.4).sin();
        let y: Vec<f64> = (0..64).map(|n| f(TAU * n as f64 / 64.0)).collect();
        let r = SunRatio::fit_uniform(&y, 8).unwrap();
        for j in 0..50 {
            let t = 0.37 * j as f64;
            assert!((r.value(t) - f(t)).abs() < 1e-13);
        }
        assert!((r.integral(TAU) - TAU).abs() < 1e-13);
        // Φ⁻¹ ∘ Φ = id and S∘S = shift by 2π (docs/math/chain.md §6.2).
        for j in 0..20 {
            let t = -3.0 + 0.41 * j as f64;
            assert!((r.inverse_integral(r.integral(t), 1e-14) - t).abs() < 1e-12);
            let s = r.half_turn_map(r.half_turn_map(t, 1e-14), 1e-14);
            assert!((s - t - TAU).abs() < 1e-11);
            // A warm start, near or wild (or not finite), converges to the same inverse.
            for guess in [t + 1e-3, t - 2.5, t + 40.0, f64::NAN] {
                let u = r.inverse_integral_from(r.integral(t), guess, 1e-14);
                assert!((u - t).abs() < 1e-12, "guess {guess}: {u} vs {t}");
            }
        }
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let r = SunRatio::new(vec![0.1, -0.05, 0.02], vec![0.03, 0.04, -0.01]).unwrap();
        let h = 1e-5;
        for j in 0..10 {
            let t = 0.6 * j as f64;
            let [_, d1, d2] = r.eval3(t);
            assert!((d1 - (r.value(t + h) - r.value(t - h)) / (2.0 * h)).abs() < 1e-8);
            let fd2 = (r.eval3(t + h)[1] - r.eval3(t - h)[1]) / (2.0 * h);
            assert!((d2 - fd2).abs() < 1e-7);
            // The one-pass forms are the separate ones, bit for bit.
            assert_eq!(r.integral_and_eval3(t), (r.integral(t), r.eval3(t)));
            assert_eq!(r.integral_and_value(t).1, r.value(t));
        }
        let [(lo, at_lo), (hi, at_hi)] = r.sampled_extremes(777);
        assert_eq!((lo, at_lo), r.sampled_extreme(777, false));
        assert_eq!((hi, at_hi), r.sampled_extreme(777, true));
        assert!(lo < 1.0 && hi > 1.0);
    }

    #[test]
    fn admissible_ratio_keeps_closure_and_bounds() {
        let r = SunRatio::new(vec![0.9], vec![0.0]).unwrap();
        let s = r.admissible([0.3, 1.5]);
        let (hi, _) = s.sampled_extreme(4096, true);
        assert!(hi <= 1.5 && hi > 1.5 - 1e-6, "{hi}");
        assert!(s.range()[1] <= 1.5);
        assert!((s.integral(TAU) - TAU).abs() < 1e-12);
    }

    /// A fitted designer ratio (K = 12, i21 ∈ [0.32, 2.21]) on which plain Newton ping-ponged
    /// between the ends of its bracket and left Φ⁻¹ 0.3 rad off (one spiked intermediate sample).
    #[test]
    fn inverse_integral_converges_where_newton_ping_pongs() {
        let a = vec![
            -0.36529485812796775,
            0.13576318266093604,
            -0.06291100670698704,
            -0.07628032101683976,
            -0.22710598281158342,
            -0.004644858097947298,
            0.22913764468035558,
            -0.2182444576421202,
            0.1411391373181318,
            -0.07581659971500242,
            0.03529120643136863,
            -0.014224779015298953,
        ];
        let b = vec![
            -0.008118720069198806,
            0.010767139255749085,
            -0.012953904096046137,
            -0.008444694610768768,
            0.041993377322530494,
            0.04069284919866566,
            0.08080059854125095,
            -0.06518153989327644,
            0.007521923774909562,
            0.07589043826079249,
            -0.04339152917992613,
            0.0324362768438573,
        ];
        let r = SunRatio::new(a, b).unwrap();
        for k in 0..3600 {
            let y = PI - TAU * k as f64 / 3600.0;
            let x = r.inverse_integral(y, 1e-13);
            assert!(
                (r.integral(x) - y).abs() < 1e-11,
                "k = {k}: Φ(x) − y = {}",
                r.integral(x) - y
            );
        }
    }

    #[test]
    fn non_positive_ratio_is_rejected() {
        assert!(matches!(
            SunRatio::new(vec![1.2], vec![0.0]),
            Err(RatioError::NotPositive { .. })
        ));
    }
}
