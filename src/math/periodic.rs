//! Periodic functions sampled on a grid: periodic cubic splines, spectral (FFT) differentiation and
//! integration, and monotone periodic inversion.
//!
//! Everything in the design chain is periodic in an angle (carrier angle, polar angle of a pitch
//! curve), so this module is the shared numerical vocabulary of the crate. Angles are in radians.
//!
//! Reference: design-chain spec §3.1 (periodic C² interpolation), §3.3 (spectral i31),
//! §14 (Φ⁻¹ robustness: Newton with a bisection safeguard).

use realfft::RealFftPlanner;
use realfft::num_complex::Complex;
use std::f64::consts::TAU;

/// A periodic C² cubic spline `y(x)` with `y(x + period) = y(x)`, through knots `x_0 < … < x_{n−1}`
/// (`x_{n−1} < x_0 + period`).
///
/// The second derivatives at the knots solve the cyclic tridiagonal system
/// `h_{i−1} M_{i−1} + 2(h_{i−1}+h_i) M_i + h_i M_{i+1} = 6[(y_{i+1}−y_i)/h_i − (y_i−y_{i−1})/h_{i−1}]`
/// (Sherman–Morrison on the cyclic part). Interpolation error is `O(h⁴)` on smooth data.
///
/// ```
/// use ncgear::math::periodic::PeriodicSpline;
/// use std::f64::consts::TAU;
/// let n = 64;
/// let x: Vec<f64> = (0..n).map(|k| TAU * k as f64 / n as f64).collect();
/// let y: Vec<f64> = x.iter().map(|t| t.sin()).collect();
/// let s = PeriodicSpline::new(x, y, TAU).unwrap();
/// assert!((s.value(1.0) - 1.0f64.sin()).abs() < 1e-6);
/// assert!((s.value(1.0 + TAU) - 1.0f64.sin()).abs() < 1e-6);
/// ```
#[derive(Debug, Clone)]
pub struct PeriodicSpline {
    x: Vec<f64>,
    y: Vec<f64>,
    m: Vec<f64>,
    period: f64,
    uniform: bool,
    /// Non-uniform knots: for each of `n` equal cells of the period, the last knot at or before
    /// its start — the start of a short walk instead of a bisection (empty when uniform).
    guide: Vec<u32>,
}

/// Why a periodic spline could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SplineError {
    /// Fewer than 4 knots, or `x` and `y` of different lengths.
    #[error(
        "a periodic spline needs at least 4 knots with one value each (got {knots} knots, {values} values)"
    )]
    TooFewKnots {
        /// Number of knots.
        knots: usize,
        /// Number of values.
        values: usize,
    },
    /// Knots not strictly increasing within one period, or not finite.
    #[error("spline knots must be finite and strictly increasing within one period (knot {index})")]
    BadKnots {
        /// Index of the first offending knot.
        index: usize,
    },
    /// A value is NaN or infinite.
    #[error("spline value {index} is not finite")]
    NonFinite {
        /// Index of the offending value.
        index: usize,
    },
}

impl PeriodicSpline {
    /// Builds the interpolating periodic spline. `period` is in the unit of `x`.
    pub fn new(x: Vec<f64>, y: Vec<f64>, period: f64) -> Result<Self, SplineError> {
        let n = x.len();
        if n < 4 || y.len() != n {
            return Err(SplineError::TooFewKnots {
                knots: n,
                values: y.len(),
            });
        }
        if let Some(i) = y.iter().position(|v| !v.is_finite()) {
            return Err(SplineError::NonFinite { index: i });
        }
        for i in 0..n {
            let next = if i + 1 < n { x[i + 1] } else { x[0] + period };
            if !x[i].is_finite() || !(next > x[i]) {
                return Err(SplineError::BadKnots { index: i });
            }
        }
        let h: Vec<f64> = (0..n)
            .map(|i| {
                if i + 1 < n {
                    x[i + 1] - x[i]
                } else {
                    x[0] + period - x[i]
                }
            })
            .collect();
        let h_mean = period / n as f64;
        let uniform = h.iter().all(|hi| (hi - h_mean).abs() <= 1e-12 * h_mean);
        // Cyclic tridiagonal: a_i M_{i-1} + b_i M_i + c_i M_{i+1} = d_i.
        let mut a = vec![0.0; n];
        let mut b = vec![0.0; n];
        let mut c = vec![0.0; n];
        let mut d = vec![0.0; n];
        for i in 0..n {
            let hm = h[(i + n - 1) % n];
            let hp = h[i];
            a[i] = hm;
            b[i] = 2.0 * (hm + hp);
            c[i] = hp;
            d[i] = 6.0 * ((y[(i + 1) % n] - y[i]) / hp - (y[i] - y[(i + n - 1) % n]) / hm);
        }
        let m = solve_cyclic_tridiagonal(&a, &b, &c, &d);
        let guide = if uniform {
            Vec::new()
        } else {
            let mut i = 0usize;
            (0..n)
                .map(|k| {
                    let start = x[0] + period * k as f64 / n as f64;
                    while i + 1 < n && x[i + 1] <= start {
                        i += 1;
                    }
                    i as u32
                })
                .collect()
        };
        Ok(Self {
            x,
            y,
            m,
            period,
            uniform,
            guide,
        })
    }

    /// Uniform knots `x_k = x0 + k·period/n`.
    pub fn uniform(x0: f64, y: Vec<f64>, period: f64) -> Result<Self, SplineError> {
        let n = y.len();
        let x = (0..n).map(|k| x0 + period * k as f64 / n as f64).collect();
        Self::new(x, y, period)
    }

    /// The period, in the unit of `x`.
    #[must_use]
    pub fn period(&self) -> f64 {
        self.period
    }

    /// The knots.
    #[must_use]
    pub fn knots(&self) -> &[f64] {
        &self.x
    }

    /// The values at the knots.
    #[must_use]
    pub fn values(&self) -> &[f64] {
        &self.y
    }

    #[inline]
    fn locate(&self, x: f64) -> (usize, f64, f64) {
        let n = self.x.len();
        let mut u = x - self.x[0];
        // Within the first period already (the common case): `rem_euclid` would return `u`
        // itself, so skip its library `fmod`.
        if !(u >= 0.0 && u < self.period) {
            u = u.rem_euclid(self.period);
            if !u.is_finite() {
                u = 0.0;
            }
        }
        let i = if self.uniform {
            let h = self.period / n as f64;
            ((u / h) as usize).min(n - 1)
        } else {
            // The last knot at or before the target, walked to from the guide (the same
            // index a bisection finds: the knots increase strictly).
            let target = self.x[0] + u;
            let k = ((u / self.period * n as f64) as usize).min(n - 1);
            let mut i = self.guide[k] as usize;
            while i > 0 && self.x[i] > target {
                i -= 1;
            }
            while i + 1 < n && self.x[i + 1] <= target {
                i += 1;
            }
            i
        };
        let xi = self.x[i] - self.x[0];
        let h = if i + 1 < n {
            self.x[i + 1] - self.x[i]
        } else {
            self.x[0] + self.period - self.x[i]
        };
        (i, u - xi, h)
    }

    /// Value, first and second derivative at `x` (any real `x`: wrapped into the period).
    #[must_use]
    #[inline]
    pub fn eval3(&self, x: f64) -> [f64; 3] {
        let n = self.x.len();
        let (i, t, h) = self.locate(x);
        let j = if i + 1 == n { 0 } else { i + 1 };
        let (yi, yj, mi, mj) = (self.y[i], self.y[j], self.m[i], self.m[j]);
        let s = h - t;
        let v = (mi * s * s * s + mj * t * t * t) / (6.0 * h)
            + (yi / h - mi * h / 6.0) * s
            + (yj / h - mj * h / 6.0) * t;
        let d1 = (-mi * s * s + mj * t * t) / (2.0 * h) + (yj - yi) / h - (mj - mi) * h / 6.0;
        let d2 = (mi * s + mj * t) / h;
        [v, d1, d2]
    }

    /// Value at `x`.
    #[must_use]
    #[inline]
    pub fn value(&self, x: f64) -> f64 {
        self.eval3(x)[0]
    }

    /// First derivative at `x`.
    #[must_use]
    #[inline]
    pub fn derivative(&self, x: f64) -> f64 {
        self.eval3(x)[1]
    }
}

/// Solves a cyclic tridiagonal system `a_i x_{i−1} + b_i x_i + c_i x_{i+1} = d_i` (indices mod n)
/// by Sherman–Morrison. Requires diagonal dominance (true for spline systems).
fn solve_cyclic_tridiagonal(a: &[f64], b: &[f64], c: &[f64], d: &[f64]) -> Vec<f64> {
    let n = b.len();
    let gamma = -b[0];
    let mut bb = b.to_vec();
    bb[0] = b[0] - gamma;
    bb[n - 1] = b[n - 1] - a[0] * c[n - 1] / gamma;
    let x = solve_tridiagonal(a, &bb, c, d);
    let mut u = vec![0.0; n];
    u[0] = gamma;
    u[n - 1] = c[n - 1];
    let z = solve_tridiagonal(a, &bb, c, &u);
    let fact = (x[0] + a[0] * x[n - 1] / gamma) / (1.0 + z[0] + a[0] * z[n - 1] / gamma);
    x.iter().zip(&z).map(|(xi, zi)| xi - fact * zi).collect()
}

/// Thomas algorithm; `a[0]` and `c[n−1]` are ignored.
fn solve_tridiagonal(a: &[f64], b: &[f64], c: &[f64], d: &[f64]) -> Vec<f64> {
    let n = b.len();
    let mut cp = vec![0.0; n];
    let mut dp = vec![0.0; n];
    cp[0] = c[0] / b[0];
    dp[0] = d[0] / b[0];
    for i in 1..n {
        let den = b[i] - a[i] * cp[i - 1];
        cp[i] = c[i] / den;
        dp[i] = (d[i] - a[i] * dp[i - 1]) / den;
    }
    let mut x = vec![0.0; n];
    x[n - 1] = dp[n - 1];
    for i in (0..n - 1).rev() {
        x[i] = dp[i] - cp[i] * x[i + 1];
    }
    x
}

/// Real-to-complex FFT of a periodic sample vector, normalised so that
/// `y_n = Σ_k c_k e^{i k 2πn/N}` over `k = −N/2..N/2` with `c_{−k} = conj(c_k)`; returns `c_0..c_{N/2}`.
#[must_use]
pub fn fft_coefficients(y: &[f64]) -> Vec<Complex<f64>> {
    let n = y.len();
    let mut planner = RealFftPlanner::<f64>::new();
    let fft = planner.plan_fft_forward(n);
    let mut input = y.to_vec();
    let mut out = fft.make_output_vec();
    // Lengths match by construction, so the FFT cannot fail.
    fft.process(&mut input, &mut out)
        .expect("FFT buffer lengths are consistent");
    let scale = 1.0 / n as f64;
    out.iter().map(|c| c * scale).collect()
}

/// Inverse of [`fft_coefficients`] for an even or odd length `n`.
#[must_use]
pub fn fft_synthesis(coeffs: &[Complex<f64>], n: usize) -> Vec<f64> {
    let mut planner = RealFftPlanner::<f64>::new();
    let ifft = planner.plan_fft_inverse(n);
    let mut input = coeffs.to_vec();
    // The DC and (even n) Nyquist bins must be real for a real signal.
    input[0].im = 0.0;
    if n.is_multiple_of(2) {
        let last = input.len() - 1;
        input[last].im = 0.0;
    }
    let mut out = ifft.make_output_vec();
    ifft.process(&mut input, &mut out)
        .expect("FFT buffer lengths are consistent");
    out
}

/// Spectral derivative of uniformly sampled periodic data `y_n = y(2πn/N)` (period 2π).
///
/// Exact for trigonometric polynomials of degree < N/2 (the Nyquist term is dropped).
#[must_use]
pub fn spectral_derivative(y: &[f64]) -> Vec<f64> {
    let n = y.len();
    let mut c = fft_coefficients(y);
    let last = c.len() - 1;
    for (k, ck) in c.iter_mut().enumerate() {
        *ck *= Complex::new(0.0, k as f64);
    }
    if n.is_multiple_of(2) {
        c[last] = Complex::new(0.0, 0.0);
    }
    fft_synthesis(&c, n)
}

/// Spectral antiderivative of uniformly sampled periodic data over period 2π:
/// returns `(mean, F)` with `F(x) = ∫_0^x (y − mean)`, sampled on the same grid (`F_0 = 0`).
#[must_use]
pub fn spectral_integral(y: &[f64]) -> (f64, Vec<f64>) {
    let n = y.len();
    let mut c = fft_coefficients(y);
    let mean = c[0].re;
    c[0] = Complex::new(0.0, 0.0);
    let last = c.len() - 1;
    for (k, ck) in c.iter_mut().enumerate().skip(1) {
        *ck /= Complex::new(0.0, k as f64);
    }
    if n.is_multiple_of(2) {
        c[last] = Complex::new(0.0, 0.0);
    }
    let f = fft_synthesis(&c, n);
    let f0 = f[0];
    (mean, f.into_iter().map(|v| v - f0).collect())
}

/// Wraps an angle to (−π, π], rad: `x − 2πk` for the integer k that lands there. Used for
/// angle differences and for unwrapping sampled angles.
///
/// ```
/// use ncgear::math::periodic::wrap_pi;
/// use std::f64::consts::PI;
/// assert!((wrap_pi(0.1 - (2.0 * PI - 0.1)) - 0.2).abs() < 1e-15);
/// assert_eq!(wrap_pi(-PI), PI);
/// assert!((wrap_pi(7.0 * PI / 2.0) + PI / 2.0).abs() < 1e-15);
/// ```
#[must_use]
pub fn wrap_pi(x: f64) -> f64 {
    let y = x.rem_euclid(TAU);
    if y > std::f64::consts::PI { y - TAU } else { y }
}

/// Uniform grid `x_k = 2πk/n`, `k = 0..n`, in radians.
#[must_use]
pub fn uniform_angles(n: usize) -> Vec<f64> {
    (0..n).map(|k| TAU * k as f64 / n as f64).collect()
}

/// Root of a continuous `g` on `[lo, hi]` with a sign change, to `tol` in `x`, by the ITP method
/// (interpolate, truncate, project: Oliveira & Takahashi, ACM TOMS 47(1), 2020).
///
/// Each step takes the regula-falsi point, truncated towards the midpoint and projected into the
/// minmax disc of radius `r_j = ε·2^(n_max − j) − (b − a)/2` (`ε = tol/2`, `n_max = ⌈log2((hi −
/// lo)/tol)⌉ + 1`): never more than one step beyond bisection's count, and superlinear on smooth
/// functions (a handful of evaluations where bisection needs 30–50). Without a sign change it
/// still stops within `n_max` steps, at a point of the interval. Hand-written: the inner loop of
/// step 1 and the train's angle solves, where a solver object per call would cost more than `g`.
#[must_use]
pub fn bracketed_root(g: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64, tol: f64) -> f64 {
    if hi - lo <= tol {
        return 0.5 * (lo + hi);
    }
    // Orient g so that g(lo) ≤ 0 ≤ g(hi) (zero counts as the low side, as in bisection).
    let g_lo = g(lo);
    let sign = if g_lo > 0.0 { -1.0 } else { 1.0 };
    let f = |x: f64| sign * g(x);
    let (mut ya, mut yb) = (sign * g_lo, f(hi));
    let eps = 0.5 * tol;
    let n_max = ((hi - lo) / tol).log2().ceil().max(0.0) + 1.0;
    let mut scaled = eps * n_max.exp2();
    let k1 = 0.2 / (hi - lo);
    for _ in 0..200 {
        if hi - lo <= tol {
            break;
        }
        let mid = 0.5 * (lo + hi);
        let r = scaled - 0.5 * (hi - lo);
        let xf = (yb * lo - ya * hi) / (yb - ya);
        let sigma = mid - xf;
        let delta = k1 * (hi - lo) * (hi - lo);
        let xt = if delta <= sigma.abs() {
            xf + delta.copysign(sigma)
        } else {
            mid
        };
        let x = if (xt - mid).abs() <= r {
            xt
        } else {
            mid - r.copysign(sigma)
        };
        let y = f(x);
        if y > 0.0 {
            hi = x;
            yb = y;
        } else if y < 0.0 || y.is_nan() {
            lo = x;
            ya = if y.is_nan() { ya } else { y };
        } else {
            return x;
        }
        scaled *= 0.5;
    }
    0.5 * (lo + hi)
}

/// Solves `f(x) = y` for a strictly increasing `f` on `[lo, hi]` with `f(lo) ≤ y ≤ f(hi)`:
/// Newton steps with a bisection safeguard, to `tol` in `x`.
///
/// `f` returns `(value, derivative)`. Always converges for strictly increasing `f`
/// (spec §14, "Φ⁻¹ robustness"). Returns the best bracketed estimate after `max_iter` steps.
#[must_use]
pub fn invert_increasing(
    f: impl Fn(f64) -> (f64, f64),
    y: f64,
    mut lo: f64,
    mut hi: f64,
    guess: f64,
    tol: f64,
) -> f64 {
    let mut x = guess.clamp(lo, hi);
    // Newton, with bisection when the step leaves the bracket or when the residual did not at
    // least halve since the last step: plain Newton can ping-pong between the two ends of a
    // bracket that shrinks by a hair per step and stop unconverged. Where Newton converges
    // normally (the residual falls quadratically) the path is plain Newton.
    let mut r_prev = f64::INFINITY;
    for _ in 0..200 {
        let (fx, dfx) = f(x);
        let r = fx - y;
        if r == 0.0 {
            return x;
        }
        if r > 0.0 {
            hi = x;
        } else {
            lo = x;
        }
        let mut next = if dfx > 0.0 && dfx.is_finite() {
            x - r / dfx
        } else {
            f64::NAN
        };
        // A Newton step below `tol` that stays in the bracket is convergence, even where the
        // residual sits at the rounding floor and no longer halves (a bisection there would only
        // throw the converged iterate away).
        if (next - x).abs() <= tol && next >= lo && next <= hi {
            return next;
        }
        if !(next > lo && next < hi) || r.abs() > 0.5 * r_prev {
            next = 0.5 * (lo + hi);
        }
        r_prev = r.abs();
        if (next - x).abs() <= tol || (hi - lo) <= tol {
            return next;
        }
        x = next;
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spline_converges_fourth_order() {
        let f = |t: f64| (t.sin() + 0.3 * (2.0 * t).cos()).exp();
        let err = |n: usize| {
            let s = PeriodicSpline::uniform(
                0.0,
                uniform_angles(n).iter().map(|&t| f(t)).collect(),
                TAU,
            )
            .unwrap();
            (0..1000)
                .map(|k| {
                    let t = TAU * (k as f64 + 0.37) / 1000.0;
                    (s.value(t) - f(t)).abs()
                })
                .fold(0.0, f64::max)
        };
        let (e1, e2) = (err(64), err(128));
        let order = (e1 / e2).log2();
        assert!(
            order > 3.7 && order < 4.5,
            "order {order}, errors {e1} {e2}"
        );
    }

    #[test]
    fn nonuniform_spline_matches_function() {
        let x: Vec<f64> = (0..200)
            .map(|k| TAU * (k as f64 + 0.3 * (k as f64).sin()) / 200.0)
            .collect();
        let y: Vec<f64> = x.iter().map(|t| t.cos()).collect();
        let s = PeriodicSpline::new(x, y, TAU).unwrap();
        for k in 0..50 {
            let t = -3.0 + 0.31 * k as f64;
            assert!((s.value(t) - t.cos()).abs() < 1e-7);
            assert!((s.derivative(t) + t.sin()).abs() < 1e-4);
        }
    }

    #[test]
    fn spectral_calculus_is_exact_on_trig_polynomials() {
        let n = 64;
        let t = uniform_angles(n);
        let y: Vec<f64> = t
            .iter()
            .map(|&x| 2.0 + (3.0 * x).sin() - 0.5 * (5.0 * x + 1.0).cos())
            .collect();
        let dy = spectral_derivative(&y);
        let (mean, iy) = spectral_integral(&y);
        assert!((mean - 2.0).abs() < 1e-14);
        for (k, &x) in t.iter().enumerate() {
            let d = 3.0 * (3.0 * x).cos() + 2.5 * (5.0 * x + 1.0).sin();
            assert!((dy[k] - d).abs() < 1e-12);
            let i = (1.0 - (3.0 * x).cos()) / 3.0 - 0.1 * ((5.0 * x + 1.0).sin() - 1.0f64.sin());
            assert!((iy[k] - i).abs() < 1e-13);
        }
    }

    #[test]
    fn newton_bisection_inverts() {
        let f = |x: f64| (x + 0.5 * x.sin(), 1.0 + 0.5 * x.cos());
        let x = invert_increasing(f, 2.0, 0.0, 4.0, 0.0, 1e-14);
        assert!((f(x).0 - 2.0).abs() < 1e-13);
    }
}
