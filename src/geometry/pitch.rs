//! Closed polar pitch curves `r(θ)` of non-circular gears.
//!
//! A [`PitchCurve`] is closed and strictly positive by construction: it holds `n ≥ 8` radii sampled
//! uniformly in the body polar angle `θ_k = 2πk/n` (CCW, radians, about the gear's rotation centre)
//! and interpolates them with a periodic C² cubic spline. Radii are in mm.
//!
//! Reference: docs/math/chain.md §5 (polar derivatives, convexity `Δ = r² + 2r_θ² − r r_θθ`,
//! radius of curvature `ρc = (r² + r_θ²)^{3/2}/Δ`, pressure-angle deviation `atan(r_θ/r)`), docs/math/chain.md §9.

use crate::math::Point;
use crate::math::periodic::{PeriodicSpline, uniform_angles};
use std::f64::consts::TAU;

/// A closed, positive polar pitch curve `r(θ)` in mm, θ in radians CCW in the body frame.
#[derive(Debug, Clone)]
pub struct PitchCurve {
    spline: PeriodicSpline,
}

/// Why a pitch curve is invalid.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum PitchError {
    /// Fewer than 8 samples.
    #[error("a pitch curve needs at least 8 radius samples (got {0})")]
    TooFewSamples(usize),
    /// A radius is not finite or not strictly positive.
    #[error("pitch radius sample {index} is {value} mm; radii must be finite and > 0")]
    NonPositive {
        /// Sample index.
        index: usize,
        /// Offending value in mm.
        value: f64,
    },
}

/// Local differential geometry of a polar curve at one angle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PolarGeometry {
    /// Radius `r`, mm.
    pub r_mm: f64,
    /// `dr/dθ`, mm/rad.
    pub dr_mm: f64,
    /// `d²r/dθ²`, mm/rad².
    pub ddr_mm: f64,
}

impl From<[f64; 3]> for PolarGeometry {
    /// `[r, r_θ, r_θθ]` (mm, mm/rad, mm/rad²).
    fn from([r_mm, dr_mm, ddr_mm]: [f64; 3]) -> Self {
        Self {
            r_mm,
            dr_mm,
            ddr_mm,
        }
    }
}

impl PolarGeometry {
    /// Convexity indicator `Δ = r² + 2 r_θ² − r r_θθ` (mm²); convex where `Δ > 0` (docs/math/chain.md §5).
    #[must_use]
    pub fn convexity_mm2(&self) -> f64 {
        self.r_mm * self.r_mm + 2.0 * self.dr_mm * self.dr_mm - self.r_mm * self.ddr_mm
    }

    /// Signed radius of curvature `ρc = (r² + r_θ²)^{3/2} / Δ` in mm (negative = concave).
    #[must_use]
    pub fn radius_of_curvature_mm(&self) -> f64 {
        let ds = self.speed_mm();
        ds * ds * ds / self.convexity_mm2()
    }

    /// Arc-length speed `ds/dθ = √(r² + r_θ²)`, mm/rad.
    #[must_use]
    #[inline]
    pub fn speed_mm(&self) -> f64 {
        // Radii in mm are far from overflow and underflow: the plain root is as accurate
        // (≤ 1 ulp) as `hypot` and several times cheaper (arc-length tables take ~10⁵ calls).
        (self.r_mm * self.r_mm + self.dr_mm * self.dr_mm).sqrt()
    }

    /// Deviation of the tangent from the normal to the radius, `π/2 − μ = atan(r_θ / r)`, rad.
    #[must_use]
    pub fn pressure_deviation_rad(&self) -> f64 {
        (self.dr_mm / self.r_mm).atan()
    }
}

impl PitchCurve {
    /// Builds a pitch curve from radii (mm) at uniform angles `θ_k = 2πk/n`.
    pub fn from_uniform_radii(radii_mm: Vec<f64>) -> Result<Self, PitchError> {
        let n = radii_mm.len();
        if n < 8 {
            return Err(PitchError::TooFewSamples(n));
        }
        if let Some((index, &value)) = radii_mm
            .iter()
            .enumerate()
            .find(|(_, r)| !(r.is_finite() && **r > 0.0))
        {
            return Err(PitchError::NonPositive { index, value });
        }
        let spline = PeriodicSpline::uniform(0.0, radii_mm, TAU)
            .map_err(|_| PitchError::TooFewSamples(n))?;
        Ok(Self { spline })
    }

    /// Samples `r(θ)` (mm) at `n` uniform angles.
    pub fn from_fn(n: usize, r: impl Fn(f64) -> f64) -> Result<Self, PitchError> {
        Self::from_uniform_radii(uniform_angles(n).into_iter().map(r).collect())
    }

    /// The stored radii (mm) at `θ_k = 2πk/n`.
    #[must_use]
    pub fn radii_mm(&self) -> &[f64] {
        self.spline.values()
    }

    /// Number of stored samples.
    #[must_use]
    pub fn len(&self) -> usize {
        self.spline.values().len()
    }

    /// Always false: a pitch curve has at least 8 samples.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Radius at body angle `theta_rad` (any real angle), mm.
    #[must_use]
    pub fn radius_mm(&self, theta_rad: f64) -> f64 {
        self.spline.value(theta_rad)
    }

    /// `r`, `r_θ`, `r_θθ` at `theta_rad`.
    #[must_use]
    #[inline]
    pub fn geometry(&self, theta_rad: f64) -> PolarGeometry {
        self.spline.eval3(theta_rad).into()
    }

    /// Cartesian point of the curve in the body frame, mm.
    #[must_use]
    pub fn point_mm(&self, theta_rad: f64) -> Point {
        let r = self.radius_mm(theta_rad);
        Point::new(r * theta_rad.cos(), r * theta_rad.sin())
    }

    /// Perimeter `L = ∮ √(r² + r_θ²) dθ` in mm, to within `accuracy_mm`.
    ///
    /// Composite Gauss–Legendre (5 points) per knot interval, checked against the 3-point rule
    /// on the same intervals; when they differ by more than `accuracy_mm`, the intervals are
    /// halved until two successive 5-point estimates agree to it (the integrand is smooth within
    /// each spline piece).
    #[must_use]
    pub fn perimeter_mm(&self, accuracy_mm: f64) -> f64 {
        // On the knot intervals the speed is smooth: 5-point Gauss–Legendre there, accepted when
        // the 3-point rule on the same intervals (sharing the midpoint) agrees within the
        // accuracy — the 3-point rule's error, O(h⁶), bounds the 5-point one's, O(h¹⁰).
        let n = self.len();
        let (g5, g3) = (0..n)
            .map(|p| {
                // The nodes of one piece share its cubic: evaluated in the offset from its knot.
                let (_, h, cubic) = self.spline.piece(p);
                gauss_legendre_5_3(|t| PolarGeometry::from(cubic.eval3(t)).speed_mm(), 0.0, h)
            })
            .fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y));
        if (g5 - g3).abs() <= accuracy_mm.max(1e-15 * g5) {
            return g5;
        }
        self.arc_length_between_mm(0.0, TAU, accuracy_mm)
    }

    /// Arc length between body angles `from_rad ≤ to_rad`, mm, to within `accuracy_mm`.
    #[must_use]
    pub fn arc_length_between_mm(&self, from_rad: f64, to_rad: f64, accuracy_mm: f64) -> f64 {
        let integrate = |pieces: usize| {
            let h = (to_rad - from_rad) / pieces as f64;
            (0..pieces)
                .map(|p| {
                    let lo = from_rad + p as f64 * h;
                    gauss_legendre5(|t| self.geometry(t).speed_mm(), lo, lo + h)
                })
                .sum::<f64>()
        };
        let mut pieces = self.len().max(8);
        let mut prev = integrate(pieces);
        for _ in 0..8 {
            pieces *= 2;
            let next = integrate(pieces);
            if (next - prev).abs() <= accuracy_mm.max(1e-15 * next.abs()) {
                return next;
            }
            prev = next;
        }
        prev
    }

    /// Minimum of the convexity indicator `Δ` (mm²) and minimum signed radius of curvature (mm)
    /// over `n_check` uniform angles.
    #[must_use]
    pub fn curvature_extremes(&self, n_check: usize) -> CurvatureSummary {
        let mut s = CurvatureSummary {
            min_convexity_mm2: f64::INFINITY,
            min_radius_of_curvature_mm: f64::INFINITY,
            max_pressure_deviation_rad: 0.0,
            concave_fraction: 0.0,
            min_concave_radius_mm: f64::INFINITY,
        };
        let mut concave = 0usize;
        // max |atan(r_θ/r)| = atan(max |r_θ/r|): atan increases, so one call at the end.
        let mut max_slope = 0.0f64;
        let mut visit = |g: PolarGeometry| {
            let d = g.convexity_mm2();
            s.min_convexity_mm2 = s.min_convexity_mm2.min(d);
            if d > 0.0 {
                s.min_radius_of_curvature_mm =
                    s.min_radius_of_curvature_mm.min(g.radius_of_curvature_mm());
            } else {
                concave += 1;
                s.min_concave_radius_mm = s
                    .min_concave_radius_mm
                    .min(g.radius_of_curvature_mm().abs());
            }
            max_slope = max_slope.max((g.dr_mm / g.r_mm).abs());
        };
        let (n, angle) = (self.len(), |k: usize| TAU * k as f64 / n_check as f64);
        if n_check.is_multiple_of(n) {
            // The angles of one piece share its cubic (the same angles, without a search each).
            let per = n_check / n;
            for i in 0..n {
                let (x_i, _, cubic) = self.spline.piece(i);
                for k in i * per..(i + 1) * per {
                    visit(cubic.eval3(angle(k) - x_i).into());
                }
            }
        } else {
            for k in 0..n_check {
                visit(self.geometry(angle(k)));
            }
        }
        s.max_pressure_deviation_rad = max_slope.atan();
        s.concave_fraction = concave as f64 / n_check as f64;
        s
    }

    /// Radii (mm) at `n` uniform angles `θ_k = 2πk/n`: the stored samples when `n` is their
    /// number (the spline at its own knots), else the spline's values.
    #[must_use]
    pub fn radii_at_uniform_mm(&self, n: usize) -> std::borrow::Cow<'_, [f64]> {
        if self.len() == n {
            std::borrow::Cow::Borrowed(self.radii_mm())
        } else {
            uniform_angles(n)
                .into_iter()
                .map(|t| self.radius_mm(t))
                .collect()
        }
    }

    /// Polar samples `(θ in degrees, r in mm)` at `n` uniform angles, for files
    /// ([`Self::radii_at_uniform_mm`]).
    #[must_use]
    pub fn polar_table_deg(&self, n: usize) -> Vec<[f64; 2]> {
        uniform_angles(n)
            .into_iter()
            .zip(self.radii_at_uniform_mm(n).iter())
            .map(|(t, &r)| [t.to_degrees(), r])
            .collect()
    }
}

/// Centre distance `a` (mm) at which a driver curve `r(θ)` has a closed conjugate with the same
/// number of teeth: the root of `(1/2π)∫ r/(a − r) dθ = 1` (docs/math/chain.md §5, §11.2 (G2)), solved by bisection to
/// `tol_mm` on the curve's uniform samples (trapezoid = spectrally accurate for periodic data).
#[must_use]
pub fn conjugate_center_distance(curve: &PitchCurve, tol_mm: f64) -> f64 {
    let r = curve.radii_mm();
    let rmax = r.iter().copied().fold(0.0, f64::max);
    let f = |a: f64| r.iter().map(|ri| ri / (a - ri)).sum::<f64>() / r.len() as f64 - 1.0;
    // f decreases in a; f → +∞ as a → rmax⁺ and f(2·rmax) ≤ 0.
    let (mut lo, mut hi) = (rmax, 2.0 * rmax);
    while hi - lo > tol_mm.max(1e-15 * rmax) {
        let mid = 0.5 * (lo + hi);
        if f(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Curvature statistics of a pitch curve (see [`PitchCurve::curvature_extremes`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, schemars::JsonSchema)]
pub struct CurvatureSummary {
    /// Minimum of `Δ`, mm²; negative means a concave stretch.
    pub min_convexity_mm2: f64,
    /// Minimum radius of curvature over the convex part, mm.
    pub min_radius_of_curvature_mm: f64,
    /// Maximum `|atan(r_θ/r)|`, rad.
    pub max_pressure_deviation_rad: f64,
    /// Fraction of the checked angles where the curve is concave.
    pub concave_fraction: f64,
    /// Smallest |radius of curvature| over the concave part, mm (∞ when the curve is convex): a
    /// shaper cutter's pitch radius must stay below it.
    pub min_concave_radius_mm: f64,
}

/// `∫ f` over `[lo, hi]` by 5-point Gauss–Legendre (exact for polynomials of degree ≤ 9).
/// The 5-point and the 3-point Gauss–Legendre rules on `[lo, hi]` from 7 values of `f` (the
/// midpoint is a node of both).
fn gauss_legendre_5_3(f: impl Fn(f64) -> f64, lo: f64, hi: f64) -> (f64, f64) {
    const X5: [f64; 2] = [0.906_179_845_938_664, 0.538_469_310_105_683];
    const W5: [f64; 3] = [
        0.236_926_885_056_189,
        0.478_628_670_499_366,
        0.568_888_888_888_889,
    ];
    const X3: f64 = 0.774_596_669_241_483;
    let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
    let fm = f(mid);
    let pair = |x: f64| f(mid - half * x) + f(mid + half * x);
    let g5 = W5[0] * pair(X5[0]) + W5[1] * pair(X5[1]) + W5[2] * fm;
    let g3 = (5.0 * pair(X3) + 8.0 * fm) / 9.0;
    (half * g5, half * g3)
}

/// `∫_lo^hi f` by the 5-point Gauss–Legendre rule (exact for polynomials of degree ≤ 9).
///
/// `#[inline]`, as are [`PitchCurve::geometry`] and [`PolarGeometry::speed_mm`]: the arc-length
/// frame's table (`teeth::frame::ArcFrame::new`) calls them 5 times on each of 32 768 intervals,
/// and out of line they cost the teeth stage 14–18 % (docs/performance.md).
#[inline]
pub(crate) fn gauss_legendre5(f: impl Fn(f64) -> f64, lo: f64, hi: f64) -> f64 {
    const X: [f64; 5] = [
        -0.906_179_845_938_664,
        -0.538_469_310_105_683,
        0.0,
        0.538_469_310_105_683,
        0.906_179_845_938_664,
    ];
    const W: [f64; 5] = [
        0.236_926_885_056_189,
        0.478_628_670_499_366,
        0.568_888_888_888_889,
        0.478_628_670_499_366,
        0.236_926_885_056_189,
    ];
    let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
    half * X
        .iter()
        .zip(W)
        .map(|(x, w)| w * f(mid + half * x))
        .sum::<f64>()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tightest_concave_radius_is_the_smallest_concave_curvature_radius() {
        // r = 20(1 + 0.15 cos 3θ) is concave around θ = π/3 (Δ = r² + 2r_θ² − r·r_θθ < 0 there):
        // at θ = π/3, r = 17, r_θ = 0, r_θθ = 27, so ρ = 17³/(17² − 17·27) = −28.9 mm.
        let c = PitchCurve::from_fn(2048, |t| 20.0 * (1.0 + 0.15 * (3.0 * t).cos())).unwrap();
        let s = c.curvature_extremes(4096);
        let rho_mid = c
            .geometry(std::f64::consts::PI / 3.0)
            .radius_of_curvature_mm();
        assert!((rho_mid + 28.9).abs() < 0.01, "{rho_mid}");
        // Brute force on a 16× finer grid: the sampled minimum is within its sampling error.
        let brute = (0..65536)
            .map(|k| c.geometry(TAU * k as f64 / 65536.0))
            .filter(|g| g.convexity_mm2() < 0.0)
            .map(|g| g.radius_of_curvature_mm().abs())
            .fold(f64::INFINITY, f64::min);
        assert!(brute <= 28.9 + 0.01);
        assert!(
            (s.min_concave_radius_mm - brute).abs() < 1e-4 * brute,
            "{} vs {brute}",
            s.min_concave_radius_mm
        );
        assert!(s.concave_fraction > 0.0);
        // A convex curve has none.
        let e = PitchCurve::from_fn(512, focus_ellipse(30.0, 0.2)).unwrap();
        assert_eq!(
            e.curvature_extremes(1024).min_concave_radius_mm,
            f64::INFINITY
        );
    }

    fn focus_ellipse(a: f64, e: f64) -> impl Fn(f64) -> f64 {
        move |t: f64| a * (1.0 - e * e) / (1.0 - e * t.cos())
    }

    #[test]
    fn ellipse_perimeter_and_curvature_match_golden() {
        // docs/math/chain.md §11.1 (G1): A = 22.5, e = 0.15 → L = 140.57306651 mm, min ρc = A(1−e²) = 21.99375 mm.
        let c = PitchCurve::from_fn(4096, focus_ellipse(22.5, 0.15)).unwrap();
        assert!((c.perimeter_mm(1e-10) - 140.573_066_51).abs() < 1e-6);
        let s = c.curvature_extremes(4096);
        assert!((s.min_radius_of_curvature_mm - 21.993_75).abs() < 1e-5);
        // The piece-by-piece scan (8 angles a piece) finds what located evaluations find.
        let fine = c.curvature_extremes(8 * 4096);
        let (mut min_rho, mut min_conv) = (f64::INFINITY, f64::INFINITY);
        for k in 0..8 * 4096 {
            let g = c.geometry(std::f64::consts::TAU * f64::from(k) / f64::from(8 * 4096));
            min_rho = min_rho.min(g.radius_of_curvature_mm());
            min_conv = min_conv.min(g.convexity_mm2());
        }
        assert!((fine.min_radius_of_curvature_mm - min_rho).abs() < 1e-12 * min_rho);
        assert!((fine.min_convexity_mm2 - min_conv).abs() < 1e-12 * min_conv);
        assert!((s.max_pressure_deviation_rad.to_degrees() - 8.626_926_558_678_639).abs() < 1e-4);
        assert!(s.min_convexity_mm2 > 0.0);
    }

    #[test]
    fn rejects_nonpositive_radius() {
        let err = PitchCurve::from_uniform_radii(vec![1.0, 2.0, 0.0, 1.0, 1.0, 1.0, 1.0, 1.0])
            .unwrap_err();
        assert_eq!(
            err,
            PitchError::NonPositive {
                index: 2,
                value: 0.0
            }
        );
    }
}
