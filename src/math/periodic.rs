//! Periodic functions sampled on a grid: periodic cubic splines, spectral (FFT) differentiation and
//! integration, angle wrapping.
//!
//! Everything in the design chain is periodic in an angle (carrier angle, polar angle of a pitch
//! curve), so this module is the shared numerical vocabulary of the crate. Angles are in radians.
//!
//! Reference: docs/math/chain.md §3.1 (periodic C² interpolation), docs/math/chain.md §3.3
//! (spectral i31). Root finding is in [`super::roots`].

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
    /// `n/period`, the reciprocal of the uniform knot spacing (unused when not uniform).
    inv_h: f64,
    /// Non-uniform knots: for each of `n` equal cells of the period, the last knot at or before
    /// its start — the start of a short walk instead of a bisection (empty when uniform).
    guide: Vec<u32>,
}

/// A piece of a [`PeriodicSpline`]: knot index `i`, offset `t = x − x_i` and length `h` (unit of `x`).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Piece {
    i: usize,
    t: f64,
    h: f64,
}

/// One piece of a [`PeriodicSpline`] as the cubic `a + b·t + c·t² + d·t³` in the offset `t` from
/// its first knot.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Cubic([f64; 4]);

impl Cubic {
    /// Value, first and second derivative at offset `t` (Horner).
    #[inline]
    pub(crate) fn eval3(&self, t: f64) -> [f64; 3] {
        let [a, b, c, d] = self.0;
        [
            a + t * (b + t * (c + t * d)),
            b + t * (2.0 * c + t * (3.0 * d)),
            2.0 * c + t * (6.0 * d),
        ]
    }

    /// Value at offset `t`.
    #[inline]
    pub(crate) fn value(&self, t: f64) -> f64 {
        let [a, b, c, d] = self.0;
        a + t * (b + t * (c + t * d))
    }
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
            inv_h: n as f64 / period,
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

    /// The piece holding `x` (wrapped into the period): its knot index, `t = x − x_i` and its
    /// length `h`.
    #[inline]
    pub(crate) fn locate(&self, x: f64) -> Piece {
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
            ((u * self.inv_h) as usize).min(n - 1)
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
        Piece { i, t: u - xi, h }
    }

    /// Value, first and second derivative at `x` (any real `x`: wrapped into the period).
    ///
    /// On the piece `[x_i, x_i + h]`, with `t = x − x_i` and `M` the knot second derivatives,
    /// the spline is the cubic `y_i + b·t + (M_i/2)·t² + d·t³` with
    /// `b = (y_{i+1} − y_i)/h − h(2M_i + M_{i+1})/6` and `d = (M_{i+1} − M_i)/(6h)`, evaluated by
    /// Horner's rule with one reciprocal of `h` (the usual two-sided form takes seven divisions).
    #[must_use]
    #[inline]
    pub fn eval3(&self, x: f64) -> [f64; 3] {
        self.eval3_on(self.locate(x))
    }

    /// The cubic of the piece holding `p` (from [`Self::locate`]).
    #[inline]
    fn cubic(&self, p: Piece) -> Cubic {
        let n = self.x.len();
        let i = p.i;
        let j = if i + 1 == n { 0 } else { i + 1 };
        let (yi, yj, mi, mj) = (self.y[i], self.y[j], self.m[i], self.m[j]);
        let inv_h = if self.uniform { self.inv_h } else { 1.0 / p.h };
        let b = (yj - yi) * inv_h - p.h * (2.0 * mi + mj) * (1.0 / 6.0);
        let d = (mj - mi) * inv_h * (1.0 / 6.0);
        Cubic([yi, b, 0.5 * mi, d])
    }

    /// Piece `i` (from knot `x_i` to the next): `(x_i, h, its cubic in t = x − x_i)`, for loops
    /// that evaluate many points of one piece (quadrature, dense checks) without locating each.
    #[inline]
    pub(crate) fn piece(&self, i: usize) -> (f64, f64, Cubic) {
        let n = self.x.len();
        let h = if i + 1 < n {
            self.x[i + 1] - self.x[i]
        } else {
            self.x[0] + self.period - self.x[i]
        };
        (self.x[i], h, self.cubic(Piece { i, t: 0.0, h }))
    }

    /// [`Self::eval3`] on a located piece (splines sharing their knots locate once).
    #[inline]
    pub(crate) fn eval3_on(&self, p: Piece) -> [f64; 3] {
        self.cubic(p).eval3(p.t)
    }

    /// The value on a located piece.
    #[inline]
    pub(crate) fn value_on(&self, p: Piece) -> f64 {
        self.cubic(p).value(p.t)
    }

    /// Value at `x`.
    #[must_use]
    #[inline]
    pub fn value(&self, x: f64) -> f64 {
        self.value_on(self.locate(x))
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
    // Already in (−π, π] (the unwrapping of neighbouring samples): x itself, without the
    // library `fmod` (and without the rounding of x + 2π − 2π for small negative x).
    if x > -std::f64::consts::PI && x <= std::f64::consts::PI {
        return x;
    }
    let y = x.rem_euclid(TAU);
    if y > std::f64::consts::PI { y - TAU } else { y }
}

/// Uniform grid `x_k = 2πk/n`, `k = 0..n`, in radians.
#[must_use]
pub fn uniform_angles(n: usize) -> Vec<f64> {
    (0..n).map(|k| TAU * k as f64 / n as f64).collect()
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
    fn wrap_pi_fast_path_agrees_with_the_wrapped_definition() {
        for k in 0..20_000 {
            let x = (f64::from(k) * 0.754_877_666_246_692_7).sin() * 40.0;
            let w = wrap_pi(x);
            assert!(
                w > -std::f64::consts::PI && w <= std::f64::consts::PI,
                "{x} → {w}"
            );
            let turns = (x - w) / TAU;
            assert!((turns - turns.round()).abs() < 1e-12, "{x} → {w}");
        }
        assert_eq!(wrap_pi(-1e-20), -1e-20);
        assert_eq!(wrap_pi(std::f64::consts::PI), std::f64::consts::PI);
    }

    #[test]
    fn horner_pieces_interpolate_and_match_the_two_sided_form() {
        // The cubic of each piece passes through both knots, and its derivatives are the
        // textbook two-sided expressions to rounding.
        let x: Vec<f64> = (0..40)
            .map(|k| TAU * (f64::from(k) + 0.3 * f64::from(k).sin()) / 40.0)
            .collect();
        let y: Vec<f64> = x.iter().map(|t| (2.0 * t).sin() + 0.1 * t.cos()).collect();
        let s = PeriodicSpline::new(x.clone(), y.clone(), TAU).unwrap();
        for k in 0..40 {
            assert!((s.value(x[k]) - y[k]).abs() < 1e-14);
            let (xi, xj) = (x[k], if k + 1 < 40 { x[k + 1] } else { x[0] + TAU });
            let h = xj - xi;
            let (mi, mj) = (s.m[k], s.m[(k + 1) % 40]);
            let (yi, yj) = (y[k], y[(k + 1) % 40]);
            for f in [0.1, 0.5, 0.9] {
                let (t, u) = (f * h, (1.0 - f) * h);
                let v = (mi * u * u * u + mj * t * t * t) / (6.0 * h)
                    + (yi / h - mi * h / 6.0) * u
                    + (yj / h - mj * h / 6.0) * t;
                let d1 =
                    (-mi * u * u + mj * t * t) / (2.0 * h) + (yj - yi) / h - (mj - mi) * h / 6.0;
                let d2 = (mi * u + mj * t) / h;
                let got = s.eval3(xi + t);
                for (a, b) in got.iter().zip([v, d1, d2]) {
                    assert!(
                        (a - b).abs() < 1e-12 * (1.0 + b.abs()),
                        "{k} {f}: {a} vs {b}"
                    );
                }
            }
        }
    }
}
