//! Roots of scalar functions on a bracket: ITP, secant steps with a certificate, and
//! safeguarded Newton for increasing functions.
//!
//! [`bracketed_root`] (ITP) for any sign change, [`secant_root`] when both end values are known
//! already, [`invert_increasing`] for `f(x) = y` with `f` increasing and its derivative at hand.
//!
//! Hand-written: they are the inner loops of step 1, the train's angle solves and Φ⁻¹, where a
//! solver object per call would cost more than the function evaluated. Reference:
//! docs/math/chain.md §14 (Φ⁻¹ robustness).

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
pub fn bracketed_root(g: impl Fn(f64) -> f64, lo: f64, hi: f64, tol: f64) -> f64 {
    if hi - lo <= tol {
        return 0.5 * (lo + hi);
    }
    // Orient g so that g(lo) ≤ 0 ≤ g(hi) (zero counts as the low side, as in bisection).
    let g_lo = g(lo);
    let sign = if g_lo > 0.0 { -1.0 } else { 1.0 };
    let f = |x: f64| sign * g(x);
    let g_hi = f(hi);
    itp(f, lo, hi, sign * g_lo, g_hi, tol)
}

/// The ITP iteration of [`bracketed_root`] on an oriented `f` (`f(lo) = ya ≤ 0`, `f(hi) = yb`).
fn itp(
    f: impl Fn(f64) -> f64,
    mut lo: f64,
    mut hi: f64,
    mut ya: f64,
    mut yb: f64,
    tol: f64,
) -> f64 {
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

/// Root of `g` on `[lo, hi]` where the end values `g(lo) = g_lo ≤ 0 ≤ g_hi = g(hi)` are known
/// (from a sampled pass), to `tol` in `x`: secant steps from the regula-falsi point; once a step
/// falls below `tol/4`, the root is certified by a sign change of `g` across
/// `[x − tol/2, x + tol/2]` — the guarantee of [`bracketed_root`]'s final bracket. A step that
/// leaves the bracket, or a failed certificate, hands the bracket narrowed so far to the ITP
/// iteration of [`bracketed_root`]; ends of the wrong sign go to [`bracketed_root`] itself.
///
/// For a smooth `g` on a short bracket (step 1 solves `φH(u) = φH0 + t` between dense samples)
/// this takes four or five evaluations where ITP takes ten to twelve.
///
/// ```
/// use ncgear::math::roots::secant_root;
/// let g = |x: f64| x.cos() - x;
/// let x = secant_root(g, 0.7, 0.8, g(0.7), g(0.8), 1e-14);
/// assert!((x - 0.739_085_133_215_160_6).abs() <= 1e-14);
/// ```
#[must_use]
pub fn secant_root(
    g: impl Fn(f64) -> f64,
    lo: f64,
    hi: f64,
    g_lo: f64,
    g_hi: f64,
    tol: f64,
) -> f64 {
    if !(g_lo <= 0.0 && g_hi >= 0.0) || hi - lo <= tol {
        return bracketed_root(g, lo, hi, tol);
    }
    if g_lo == 0.0 {
        return lo;
    }
    let (mut a, mut b, mut fa, mut fb) = (lo, hi, g_lo, g_hi);
    let (mut x0, mut f0) = (a, fa);
    let mut x1 = a - fa * (b - a) / (fb - fa);
    // Six steps: from a short bracket of a smooth g the secant settles in two or three; a
    // seventh would mean g is not smooth there, and ITP's guarantee takes over.
    for _ in 0..6 {
        if !(x1 > a && x1 < b) {
            break;
        }
        let f1 = g(x1);
        if f1 < 0.0 {
            (a, fa) = (x1, f1);
        } else if f1 > 0.0 {
            (b, fb) = (x1, f1);
        } else if f1 == 0.0 {
            return x1;
        } else {
            break;
        }
        let x2 = x1 - f1 * (x1 - x0) / (f1 - f0);
        if (x2 - x1).abs() <= 0.25 * tol && x2 > a && x2 < b {
            let (l, h) = (x2 - 0.5 * tol, x2 + 0.5 * tol);
            let fl = if l <= a { fa } else { g(l) };
            let fh = if h >= b { fb } else { g(h) };
            if fl <= 0.0 && fh >= 0.0 {
                return x2;
            }
            if fl > 0.0 {
                (b, fb) = (l, fl);
            } else if fh < 0.0 {
                (a, fa) = (h, fh);
            }
            break;
        }
        (x0, f0, x1) = (x1, f1, x2);
    }
    itp(g, a, b, fa, fb, tol)
}

/// Solves `f(x) = y` for a strictly increasing `f` on `[lo, hi]` with `f(lo) ≤ y ≤ f(hi)`:
/// Newton steps with a bisection safeguard, to `tol` in `x`.
///
/// `f` returns `(value, derivative)`. Always converges for strictly increasing `f`
/// (docs/math/chain.md §14, "Φ⁻¹ robustness"). Returns the best bracketed estimate after `max_iter` steps.
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
    fn newton_bisection_inverts() {
        let f = |x: f64| (x + 0.5 * x.sin(), 1.0 + 0.5 * x.cos());
        let x = invert_increasing(f, 2.0, 0.0, 4.0, 0.0, 1e-14);
        assert!((f(x).0 - 2.0).abs() < 1e-13);
    }

    #[test]
    fn secant_root_is_certified_like_itp() {
        // Smooth, steep and flat-ended functions on short and long brackets: the root within
        // tol of the exact one, as bracketed_root's.
        // (g, lo, hi, exact root)
        type Case = (fn(f64) -> f64, f64, f64, f64);
        let cases: [Case; 4] = [
            (|x| x.cos() - x, 0.0, 1.5, 0.739_085_133_215_160_6),
            (|x| x * x * x - 2.0, 1.0, 2.0, 2f64.cbrt()),
            (|x| (x - 0.3).powi(3) * 1e3, 0.0, 1.0, 0.3),
            (|x| (20.0 * (x - 1.1)).tanh(), 1.0, 1.2, 1.1),
        ];
        for (g, lo, hi, root) in cases {
            for tol in [1e-6, 1e-12, 1e-14] {
                let x = secant_root(g, lo, hi, g(lo), g(hi), tol);
                assert!((x - root).abs() <= tol, "{x} vs {root} at {tol}");
                assert!((bracketed_root(g, lo, hi, tol) - root).abs() <= tol);
            }
        }
        // Ends of the wrong sign: the plain bracketed search decides.
        let g = |x: f64| 1.0 - x;
        let x = secant_root(g, 0.0, 2.0, g(0.0), g(2.0), 1e-12);
        assert!((x - 1.0).abs() <= 1e-12);
    }
}
