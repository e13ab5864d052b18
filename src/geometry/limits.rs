//! Gear-quality limits of a train: what makes its pitch curves cuttable and able to transmit
//! motion, as constraints on the sun ratio `i(θ)` and the centre distance `a`.
//!
//! With `s = 1 + i`, the sun and intermediate pitch curves at one contact are (see
//! [`ContactGeometry`]) `r1 = a·i/s` against the sun angle θ and `r2 = a/s` against the
//! intermediate's own angle (`dθ2/dθ = i`); the planet is a copy of the sun. Four limits:
//!
//! ```text
//! ratio bounds       i_min ≤ i(θ) ≤ i_max                        (so i31 = i(t)/i(S(t)) > 0)
//! pressure angle     α + atan|r_θ/r| ≤ α_max,   |r1_θ/r1| = |r2_θ/r2| = |i′| / (i·s)
//! concave radius     κ(θ) ≥ −1/R_min for sun and intermediate,   κ = Δ / (r² + r_θ²)^{3/2},
//!                    Δ = r² + 2r_θ² − r·r_θθ   (concave where Δ < 0; |ρ| = 1/|κ| ≥ R_min)
//! convex radius      κ(θ) ≤ 1/ρ_min for sun and intermediate (only when set: the undercut
//!                    limit of a module, [`GearLimits::with_min_convex_radius`])
//! ```
//!
//! The pressure-angle limit is one on `i′/(i·s)`: the same for sun and intermediate, and
//! independent of `a`. The curvature scales as `1/a`: with `κ̂` the curvature at `a = 1`, the
//! concave limit reads `κ̂ ≥ −a/R_min`. Above `α_max ≈ 45°` the contact force turns a gear more
//! than it drives it; a concave arc tighter than the pitch radius of the smallest shaper cutter
//! that cuts cleanly cannot be generated.
//!
//! A ratio is made to satisfy the limits by [`GearLimits::project`]: the largest `λ ≤ 1` with
//! `1 + λ(i − 1)` within them (a circle, `λ = 0`, always is, unless a convex-radius limit exceeds its radius a/2). Shrinking `i − 1` keeps the closure
//! `Φ(2π) = 2π` (the mean of the ratio stays 1).
//!
//! ```
//! use ncgear::geometry::{fourier::SunRatio, limits::GearLimits};
//! let limits = GearLimits::new([0.3, 3.3], 20f64.to_radians(), 45f64.to_radians(), 10.0).unwrap();
//! // i = 1 + 0.6 cos 3θ: |i′|/(i(1+i)) reaches 0.8 > tan 25° — too steep.
//! let steep = SunRatio::new(vec![0.0, 0.0, 0.6], vec![0.0; 3]).unwrap();
//! assert!(limits.measure(&steep, 45.0).max_pressure_angle_rad > 45f64.to_radians());
//! let ok = limits.project(&steep, 45.0);
//! let m = limits.measure(&ok, 45.0);
//! assert!(m.max_pressure_angle_rad <= 45f64.to_radians() && m.within);
//! ```

use crate::geometry::fourier::SunRatio;
use crate::geometry::mechanism::ContactGeometry;
use crate::geometry::perimeter::unit_speed;
use serde::Serialize;
use std::f64::consts::TAU;

/// Relative margin kept inside each limit by [`GearLimits::project`]: the projected ratio is
/// checked on a finite grid, the output tables on a finer one.
pub const PROJECTION_MARGIN: f64 = 2e-3;

/// Tolerance of the shrink factor λ of [`GearLimits::shrink_factor`].
const SHRINK_TOL: f64 = 1e-7;

/// The gear-quality limits of a train (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GearLimits {
    ratio_bounds: [f64; 2],
    rack_pressure_angle_rad: f64,
    max_pressure_angle_rad: f64,
    /// `tan(α_max − α)`; infinite without a pressure-angle limit.
    max_slope: f64,
    /// `1/R_min`, 1/mm; 0 for "convex only", infinite without a concave limit.
    min_concave_radius_mm: f64,
    /// Smallest convex radius of curvature ρ_min, mm; 0 without a convex limit.
    min_convex_radius_mm: f64,
}

/// Why a set of limits is invalid.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum LimitsError {
    /// A limit is out of its range.
    #[error("invalid gear limit `{name}` = {value}: expected {expected}")]
    Invalid {
        /// The limit's name.
        name: &'static str,
        /// The value given.
        value: f64,
        /// What is expected.
        expected: &'static str,
    },
}

/// How a ratio and centre distance stand against the limits ([`GearLimits::measure`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct LimitMeasure {
    /// Smallest and largest sun ratio.
    pub ratio_range: [f64; 2],
    /// Largest effective pressure angle `α + atan max|r_θ/r|` of the three gears, rad.
    pub max_pressure_angle_rad: f64,
    /// Tightest concave radius of curvature of the sun (and planet), mm; `None` when convex.
    pub sun_min_concave_radius_mm: Option<f64>,
    /// Tightest concave radius of curvature of the intermediate, mm; `None` when convex.
    pub intermediate_min_concave_radius_mm: Option<f64>,
    /// Smallest convex radius of curvature of the sun and the intermediate, mm.
    pub min_convex_radius_mm: f64,
    /// Whether every limit holds.
    pub within: bool,
}

/// The values `(i, i′, i″)` of `1 + λ(i − 1)` on a grid, from `(i − 1, i′, i″)` stored once.
struct Grid {
    h: Vec<[f64; 3]>,
}

impl Grid {
    fn new(ratio: &SunRatio) -> Self {
        let n = grid_size(ratio.order());
        let h = (0..n)
            .map(|j| {
                let [i, d, dd] = ratio.eval3(TAU * j as f64 / n as f64);
                [i - 1.0, d, dd]
            })
            .collect();
        Self { h }
    }

    /// Unit perimeter of the sun at `λ` (trapezoid on the grid, [`crate::geometry::perimeter`]).
    fn unit_perimeter(&self, lambda: f64) -> f64 {
        let sum: f64 = self.scaled(lambda).map(|[i, d, _]| unit_speed(i, d)).sum();
        sum * TAU / self.h.len() as f64
    }

    fn scaled(&self, lambda: f64) -> impl Iterator<Item = [f64; 3]> + '_ {
        self.h
            .iter()
            .map(move |[h, d, dd]| [1.0 + lambda * h, lambda * d, lambda * dd])
    }
}

/// Grid size of the limit scans for a ratio of order `k`: at least 32 samples per period of the
/// highest harmonic.
fn grid_size(k: usize) -> usize {
    (32 * k).clamp(1024, 4096)
}

/// Signed curvature `Δ/(r² + r_θ²)^{3/2}` of a polar curve from `[r, r_θ, r_θθ]`.
fn curvature([r, r1, r2]: [f64; 3]) -> f64 {
    let q = r * r + r1 * r1;
    (r * r + 2.0 * r1 * r1 - r * r2) / (q * q.sqrt())
}

/// The constraint values at one contact, each `≥ 0` when within (at the relative `margin`):
/// `[i − i_min, i_max − i, T − |i′|/(i s), κ̂_sun + a/R, κ̂_int + a/R, a/ρ − κ̂_sun,
/// a/ρ − κ̂_int]`, dimensionless. Curvatures at unit centre distance (`κ̂ = a·κ`).
pub(crate) fn constraint_values(
    limits: &GearLimits,
    [i, d, dd]: [f64; 3],
    a_mm: f64,
    margin: f64,
) -> [f64; 7] {
    let [lo, hi] = limits.ratio_bounds;
    let m = 1.0 - margin;
    let slope = d.abs() / (i * (1.0 + i));
    let g = ContactGeometry::new(1.0, [i, d, dd]);
    let floor = limits.curvature_floor(a_mm) * m;
    let ceiling = limits.curvature_ceiling(a_mm) * m;
    [
        i - lo * (1.0 + margin),
        hi * m - i,
        limits.max_slope * m - slope,
        curvature(g.sun) - floor,
        curvature(g.intermediate) - floor,
        ceiling - curvature(g.sun),
        ceiling - curvature(g.intermediate),
    ]
}

/// Partial derivatives `[∂/∂i, ∂/∂i′, ∂/∂i″, ∂/∂a]` of each of [`constraint_values`] at the
/// penalty's margin: central differences in `(i, i′, i″)` (steps 1e-7 relative), exact in `a`
/// (only the curvature floor `−a/R_min` and ceiling `a/ρ_min` depend on it).
pub(crate) fn constraint_gradients(limits: &GearLimits, v: [f64; 3], a_mm: f64) -> [[f64; 4]; 7] {
    let mut out = [[0.0; 4]; 7];
    for c in 0..3 {
        let h = 1e-7 * (1.0 + v[c].abs());
        let (mut up, mut down) = (v, v);
        up[c] += h;
        down[c] -= h;
        let (gu, gd) = (
            constraint_values(limits, up, a_mm, 0.0),
            constraint_values(limits, down, a_mm, 0.0),
        );
        for (row, (u, d)) in out.iter_mut().zip(gu.iter().zip(&gd)) {
            row[c] = if u.is_finite() && d.is_finite() {
                (u - d) / (2.0 * h)
            } else {
                0.0
            };
        }
    }
    if limits.min_concave_radius_mm > 0.0 {
        let da = 1.0 / limits.min_concave_radius_mm;
        out[3][3] = da;
        out[4][3] = da;
    }
    let c = limits.curvature_ceiling(1.0);
    if c.is_finite() {
        out[5][3] = c;
        out[6][3] = c;
    }
    out
}

impl GearLimits {
    /// Limits from the ratio bounds `[i_min, i_max]`, the rack pressure angle α and the largest
    /// effective pressure angle `α_max` (rad), and the smallest concave radius of curvature
    /// `R_min` (mm; `f64::INFINITY` admits convex curves only).
    pub fn new(
        ratio_bounds: [f64; 2],
        rack_pressure_angle_rad: f64,
        max_pressure_angle_rad: f64,
        min_concave_radius_mm: f64,
    ) -> Result<Self, LimitsError> {
        let [lo, hi] = ratio_bounds;
        let bad = |name, value, expected| {
            Err(LimitsError::Invalid {
                name,
                value,
                expected,
            })
        };
        if !(lo > 0.0 && lo < 1.0 && hi > 1.0 && hi.is_finite()) {
            return bad("ratio_bounds", lo, "0 < min < 1 < max");
        }
        let alpha = rack_pressure_angle_rad;
        if !(alpha > 0.0 && alpha < std::f64::consts::FRAC_PI_2) {
            return bad("rack_pressure_angle_rad", alpha, "an angle in (0°, 90°)");
        }
        let pa = max_pressure_angle_rad;
        if !(pa > alpha && pa < std::f64::consts::FRAC_PI_2) {
            return bad(
                "max_pressure_angle_rad",
                pa,
                "an angle above the rack's pressure angle and below 90°",
            );
        }
        if !(min_concave_radius_mm > 0.0) {
            return bad(
                "min_concave_radius_mm",
                min_concave_radius_mm,
                "a radius > 0 mm",
            );
        }
        Ok(Self {
            ratio_bounds,
            rack_pressure_angle_rad: alpha,
            max_pressure_angle_rad: pa,
            max_slope: (pa - alpha).tan(),
            min_concave_radius_mm,
            min_convex_radius_mm: 0.0,
        })
    }

    /// The same limits with every convex arc of the sun and intermediate no tighter than
    /// `radius_mm` (> 0): the undercut limit of a module, under which a rack cuts too few
    /// teeth on the arc to keep the contact ([`crate::design::UNDERCUT_RADIUS_MODULES`]).
    /// Without gear limits ([`Self::ratio_only`]) unchanged.
    pub fn with_min_convex_radius(mut self, radius_mm: f64) -> Result<Self, LimitsError> {
        if !(radius_mm > 0.0 && radius_mm.is_finite()) {
            return Err(LimitsError::Invalid {
                name: "min_convex_radius_mm",
                value: radius_mm,
                expected: "a finite radius > 0 mm",
            });
        }
        if self.limits_gears() {
            self.min_convex_radius_mm = radius_mm;
        }
        Ok(self)
    }

    /// The ratio bounds alone (no pressure-angle or curvature limit): research use.
    pub fn ratio_only(ratio_bounds: [f64; 2]) -> Result<Self, LimitsError> {
        let mut l = Self::new(ratio_bounds, 20f64.to_radians(), 45f64.to_radians(), 1.0)?;
        l.max_slope = f64::INFINITY;
        l.max_pressure_angle_rad = std::f64::consts::FRAC_PI_2;
        l.min_concave_radius_mm = 0.0;
        Ok(l)
    }

    /// The same limits tightened for a continuation start: the pressure-angle limit 10° lower
    /// (at least 5° above the rack's), convex pitch curves only. `None` for [`Self::ratio_only`].
    #[must_use]
    pub fn tightened(&self) -> Option<Self> {
        if !self.limits_gears() {
            return None;
        }
        let alpha = self.rack_pressure_angle_rad;
        let pa = (self.max_pressure_angle_rad - 10f64.to_radians()).max(alpha + 5f64.to_radians());
        let mut tight = Self::new(self.ratio_bounds, alpha, pa, f64::INFINITY).ok()?;
        tight.min_convex_radius_mm = self.min_convex_radius_mm;
        Some(tight)
    }

    /// `[i_min, i_max]`.
    #[must_use]
    pub fn ratio_bounds(&self) -> [f64; 2] {
        self.ratio_bounds
    }

    /// Largest effective pressure angle, rad (90° when unlimited).
    #[must_use]
    pub fn max_pressure_angle_rad(&self) -> f64 {
        self.max_pressure_angle_rad
    }

    /// Smallest admissible concave radius of curvature, mm (0 when unlimited).
    #[must_use]
    pub fn min_concave_radius_mm(&self) -> f64 {
        self.min_concave_radius_mm
    }

    /// Smallest admissible convex radius of curvature, mm (`None` when unlimited).
    #[must_use]
    pub fn min_convex_radius_mm(&self) -> Option<f64> {
        (self.min_convex_radius_mm > 0.0).then_some(self.min_convex_radius_mm)
    }

    /// Whether the pressure angle and the curvature are limited (not [`Self::ratio_only`]).
    #[must_use]
    pub fn limits_gears(&self) -> bool {
        self.max_slope.is_finite()
    }

    /// The flattest convex arc any ratio within these limits can give a gear at centre distance
    /// `a_mm`: an upper bound on the smallest convex radius of curvature, mm (∞ without a
    /// pressure-angle limit).
    ///
    /// ```text
    /// r ≤ r_max = a·max(i_max/(1 + i_max), 1/(1 + i_min))     (sun r1 = a·i/s, intermediate a/s)
    /// |r_θ| ≤ r·T,   T = tan(α_max − α)                        (the pressure-angle limit)
    /// L = ∮ √(r² + r_θ²) dθ ≤ 2π·r_max·√(1 + T²)               (perimeter)
    /// L ≥ ∫_convex ρ dψ ≥ ρ_min·2π                             (the tangent turns ≥ 2π on convex arcs)
    /// ⇒ ρ_min ≤ r_max·√(1 + T²) = r_max / cos(α_max − α)
    /// ```
    ///
    /// A convex-radius limit above it cannot be met by any ratio: the projection would shrink
    /// every ratio to a circle and still miss it.
    ///
    /// ```
    /// use ncgear::geometry::limits::GearLimits;
    /// let l = GearLimits::new([0.3, 3.3], 20f64.to_radians(), 45f64.to_radians(), 10.0).unwrap();
    /// // r_max = a/1.3, 1/cos 25° = 1.1034: 0.8488·a.
    /// assert!((l.flattest_convex_radius_mm(100.0) - 84.875).abs() < 1e-3);
    /// ```
    #[must_use]
    pub fn flattest_convex_radius_mm(&self, a_mm: f64) -> f64 {
        let [lo, hi] = self.ratio_bounds;
        let r_max = a_mm * (hi / (1.0 + hi)).max(1.0 / (1.0 + lo));
        r_max * self.max_slope.hypot(1.0)
    }

    /// `a/ρ_min`: the largest admissible curvature at unit centre distance (∞ without a
    /// convex limit).
    fn curvature_ceiling(&self, a_mm: f64) -> f64 {
        if self.min_convex_radius_mm > 0.0 {
            a_mm / self.min_convex_radius_mm
        } else {
            f64::INFINITY
        }
    }

    /// `−a/R_min`: the smallest admissible curvature at unit centre distance.
    fn curvature_floor(&self, a_mm: f64) -> f64 {
        if self.min_concave_radius_mm == 0.0 {
            f64::NEG_INFINITY
        } else {
            -a_mm / self.min_concave_radius_mm
        }
    }

    /// How `ratio` at centre distance `a_mm` stands against the limits, on a grid of at least
    /// 32 samples per period of its highest harmonic (without margin).
    #[must_use]
    pub fn measure(&self, ratio: &SunRatio, a_mm: f64) -> LimitMeasure {
        let grid = Grid::new(ratio);
        let (mut lo, mut hi, mut slope) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64);
        let (mut ks, mut km) = (f64::INFINITY, f64::INFINITY);
        let (mut ks_max, mut km_max) = (f64::NEG_INFINITY, f64::NEG_INFINITY);
        let mut within = true;
        for v in grid.scaled(1.0) {
            let [i, d, _] = v;
            lo = lo.min(i);
            hi = hi.max(i);
            slope = slope.max(d.abs() / (i * (1.0 + i)));
            let g = ContactGeometry::new(1.0, v);
            ks = ks.min(curvature(g.sun));
            km = km.min(curvature(g.intermediate));
            ks_max = ks_max.max(curvature(g.sun));
            km_max = km_max.max(curvature(g.intermediate));
            within &= constraint_values(self, v, a_mm, 0.0)
                .iter()
                .all(|c| *c >= 0.0);
        }
        let concave = |k: f64| (k < 0.0).then(|| a_mm / -k);
        let convex = |k: f64| if k > 0.0 { a_mm / k } else { f64::INFINITY };
        LimitMeasure {
            ratio_range: [lo, hi],
            max_pressure_angle_rad: self.rack_pressure_angle_rad + slope.atan(),
            sun_min_concave_radius_mm: concave(ks),
            intermediate_min_concave_radius_mm: concave(km),
            min_convex_radius_mm: convex(ks_max).min(convex(km_max)),
            within,
        }
    }

    /// Whether `ratio` at `a_mm` is within every limit (at the projection's margin).
    #[must_use]
    pub fn contains(&self, ratio: &SunRatio, a_mm: f64) -> bool {
        self.shrink_factor(ratio, |_| a_mm) >= 1.0
    }

    /// The largest `λ ∈ [0, 1]` with `1 + λ(i − 1)` within the limits at centre distance
    /// `a_of(λ)` (mm), to 1e-9 in λ, at the relative margin [`PROJECTION_MARGIN`]. Bisection from
    /// the circle (`λ = 0`), which is always within.
    pub fn shrink_factor(&self, ratio: &SunRatio, a_of: impl Fn(f64) -> f64) -> f64 {
        self.shrink(&Grid::new(ratio), |_, lambda| a_of(lambda))
    }

    /// The bisection of [`Self::shrink_factor`] on a grid, with `a_of(grid, λ)`: first on the
    /// samples outside the limits at `λ = 1` (usually a few), then the whole grid verified at
    /// the result and, should another sample leave the limits on the way, bisected whole.
    fn shrink(&self, grid: &Grid, a_of: impl Fn(&Grid, f64) -> f64) -> f64 {
        let within = |v: [f64; 3], a: f64| {
            constraint_values(self, v, a, PROJECTION_MARGIN)
                .iter()
                .all(|c| *c >= 0.0)
        };
        let a1 = a_of(grid, 1.0);
        let outside: Vec<[f64; 3]> = grid
            .h
            .iter()
            .copied()
            .filter(|&[h, d, dd]| !within([1.0 + h, d, dd], a1))
            .collect();
        if outside.is_empty() {
            return 1.0;
        }
        let bisect = |samples: &[[f64; 3]], hi: f64| {
            let ok = |lambda: f64| {
                let a = a_of(grid, lambda);
                samples
                    .iter()
                    .all(|&[h, d, dd]| within([1.0 + lambda * h, lambda * d, lambda * dd], a))
            };
            let (mut lo, mut hi) = (0.0, hi);
            while hi - lo > SHRINK_TOL {
                let mid = 0.5 * (lo + hi);
                if ok(mid) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            (lo, ok(lo))
        };
        let (lambda, _) = bisect(&outside, 1.0);
        let a = a_of(grid, lambda);
        if grid.scaled(lambda).all(|v| within(v, a)) {
            lambda
        } else {
            bisect(&grid.h, lambda).0
        }
    }

    /// `ratio` made to satisfy the limits when the centre distance follows from it through
    /// the pitch perimeter `perimeter_mm` (`a = L/L̂(i)`, a tooth count at a module), by
    /// shrinking `i − 1`; unchanged when it already does.
    #[must_use]
    pub fn project_at_perimeter(&self, ratio: &SunRatio, perimeter_mm: f64) -> SunRatio {
        let lambda = self.shrink(&Grid::new(ratio), |g, l| perimeter_mm / g.unit_perimeter(l));
        scale_ratio(ratio, lambda)
    }

    /// `ratio` made to satisfy the limits at centre distance `a_mm` by shrinking `i − 1`
    /// ([`Self::shrink_factor`]); unchanged when it already does.
    #[must_use]
    pub fn project(&self, ratio: &SunRatio, a_mm: f64) -> SunRatio {
        scale_ratio(ratio, self.shrink_factor(ratio, |_| a_mm))
    }
}

/// `1 + λ(i − 1)`: every coefficient times λ (the same series when λ = 1).
#[must_use]
pub fn scale_ratio(ratio: &SunRatio, lambda: f64) -> SunRatio {
    if lambda == 1.0 {
        return ratio.clone();
    }
    let k = |v: &[f64]| v.iter().map(|x| x * lambda).collect();
    SunRatio::new_unchecked(k(ratio.cos_coefficients()), k(ratio.sin_coefficients()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::pitch::PitchCurve;

    fn limits() -> GearLimits {
        GearLimits::new([0.3, 3.3], 20f64.to_radians(), 45f64.to_radians(), 10.0).unwrap()
    }

    #[test]
    fn slope_is_the_pitch_curves_pressure_deviation() {
        // The sun's pitch curve sampled finely: max |atan(r_θ/r)| equals the ratio form.
        let ratio = SunRatio::new(vec![0.1, 0.05], vec![0.02, 0.0]).unwrap();
        let a = 40.0;
        let sun = PitchCurve::from_fn(7200, |t| {
            let i = ratio.value(t);
            a * i / (1.0 + i)
        })
        .unwrap();
        let c = sun.curvature_extremes(7200);
        let m = limits().measure(&ratio, a);
        let expected = 20f64.to_radians() + c.max_pressure_deviation_rad;
        assert!((m.max_pressure_angle_rad - expected).abs() < 1e-6);
    }

    #[test]
    fn concave_radius_matches_the_pitch_curve() {
        // k²ε > 1: the sun is concave near θ = 0 (a dent at the radius minimum).
        let ratio = SunRatio::new(vec![0.0, 0.0, -0.2], vec![0.0; 3]).unwrap();
        let a = 45.0;
        let sun = PitchCurve::from_fn(7200, |t| {
            let i = ratio.value(t);
            a * i / (1.0 + i)
        })
        .unwrap();
        let c = sun.curvature_extremes(7200);
        let m = GearLimits::ratio_only([0.3, 3.3])
            .unwrap()
            .measure(&ratio, a);
        let r = m.sun_min_concave_radius_mm.expect("concave");
        assert!(
            (r - c.min_concave_radius_mm).abs() < 1e-3 * r,
            "{r} vs {c:?}"
        );
    }

    #[test]
    fn projection_lands_on_the_binding_limit() {
        let l = limits();
        let steep = SunRatio::new(vec![0.0, 0.0, 0.6], vec![0.0; 3]).unwrap();
        let p = l.project(&steep, 45.0);
        let m = l.measure(&p, 45.0);
        assert!(m.within);
        // The pressure angle binds: within the margin of 45°, not far below.
        let tan_max = 25f64.to_radians().tan();
        let slope = (m.max_pressure_angle_rad - 20f64.to_radians()).tan();
        assert!(slope <= tan_max && slope > tan_max * (1.0 - 3.0 * PROJECTION_MARGIN));
        // A ratio within the limits is kept as it is.
        let mild = SunRatio::new(vec![0.1], vec![0.0]).unwrap();
        assert_eq!(l.project(&mild, 45.0), mild);
    }

    #[test]
    fn no_ratio_within_the_limits_has_a_flatter_convex_arc_than_the_bound() {
        use rand::{RngExt, SeedableRng};
        // Random ratios of 1–4 harmonics, steep ones shrunk into the limits: the flattest convex
        // arc of each (sun or intermediate) stays under the bound, and a circle, a/2, too.
        let (l, a) = (limits(), 45.0);
        let bound = l.flattest_convex_radius_mm(a);
        assert!((bound - a / 1.3 / 25f64.to_radians().cos()).abs() < 1e-12);
        let mut rng = rand::rngs::ChaCha8Rng::seed_from_u64(7);
        let circle = SunRatio::new(vec![0.0], vec![0.0]).unwrap();
        let mut flattest = l.measure(&circle, a).min_convex_radius_mm;
        for _ in 0..400 {
            let k = rng.random_range(1..=4);
            let h = 0.35 / k as f64;
            let c: Vec<f64> = (0..k).map(|_| rng.random_range(-h..h)).collect();
            let s: Vec<f64> = (0..k).map(|_| rng.random_range(-h..h)).collect();
            let p = l.project(&SunRatio::new(c, s).unwrap(), a);
            let m = l.measure(&p, a);
            assert!(m.within && m.min_convex_radius_mm <= bound, "{m:?}");
            flattest = flattest.max(m.min_convex_radius_mm);
        }
        // No sample beat the circle (a/2 = 22.5 mm against the bound's 38.2 mm): the bound is
        // safe, not tight.
        assert!((flattest - a / 2.0).abs() < 1e-9, "{flattest}");
    }

    #[test]
    fn invalid_limits_are_named() {
        let e = GearLimits::new([0.3, 3.3], 0.35, 0.3, 10.0).unwrap_err();
        assert!(e.to_string().contains("max_pressure_angle_rad"), "{e}");
        assert!(GearLimits::new([1.2, 3.3], 0.35, 0.8, 10.0).is_err());
        assert!(GearLimits::new([0.3, 3.3], 0.35, 0.8, 0.0).is_err());
    }
}
