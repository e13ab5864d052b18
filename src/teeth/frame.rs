//! Arc-length frame of a pitch curve (docs/math/teeth.md §12.2): `P(s)`, unit tangent `T(s)`, outward normal
//! `N(s) = (T_y, −T_x)`, curvature `κ(s)` (> 0 convex), `s ∈ [0, L)` CCW from body angle 0.
use crate::geometry::pitch::PitchCurve;
use crate::math::Point;
use std::f64::consts::TAU;

/// Arc-length parametrisation of a [`PitchCurve`] (mm).
///
/// A table of `(θ_j, s_j)` on a uniform θ grid aligned with the curve's spline knots (5-point
/// Gauss–Legendre per interval, exact to rounding for the smooth speed within a spline piece);
/// `θ(s)` is a cubic Hermite interpolant using `dθ/ds = 1/√(r² + r_θ²)`, error `O(h⁴)` with
/// `h = 2π/(8n)`.
#[derive(Debug, Clone)]
pub struct ArcFrame {
    curve: PitchCurve,
    theta: Vec<f64>,
    s: Vec<f64>,
    dtheta: Vec<f64>,
    length: f64,
}

/// Frame at one arc-length position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FramePoint {
    /// Point on the pitch curve, mm.
    pub p: Point,
    /// Unit tangent (CCW).
    pub t: Point,
    /// Outward unit normal.
    pub n: Point,
    /// Curvature, 1/mm (> 0 convex).
    pub kappa: f64,
    /// Body polar angle, rad.
    pub theta: f64,
}

impl ArcFrame {
    /// Builds the arc-length table.
    #[must_use]
    pub fn new(curve: &PitchCurve) -> Self {
        let n = curve.len() * (32768 / curve.len()).max(4);
        let h = TAU / n as f64;
        let mut theta = Vec::with_capacity(n + 1);
        let mut s = Vec::with_capacity(n + 1);
        let mut dtheta = Vec::with_capacity(n + 1);
        let mut acc = 0.0;
        for j in 0..=n {
            let th = j as f64 * h;
            theta.push(th);
            s.push(acc);
            dtheta.push(1.0 / curve.geometry(th).speed_mm());
            acc += crate::geometry::pitch::gauss_legendre5(
                |t| curve.geometry(t).speed_mm(),
                th,
                th + h,
            );
        }
        let length = s[n];
        Self {
            curve: curve.clone(),
            theta,
            s,
            dtheta,
            length,
        }
    }

    /// Perimeter `L`, mm.
    #[must_use]
    pub fn length_mm(&self) -> f64 {
        self.length
    }

    /// The pitch curve.
    #[must_use]
    pub fn curve(&self) -> &PitchCurve {
        &self.curve
    }

    /// Body polar angle at arc length `s_mm` (any real; periodic in `L`), rad.
    #[must_use]
    pub fn theta_at(&self, s_mm: f64) -> f64 {
        let turns = (s_mm / self.length).floor();
        let s = s_mm - turns * self.length;
        let n = self.s.len() - 1;
        // The last table interval starting at or before `s` (a bisection: on a curve of varying
        // speed the uniform guess `s/L·n` can be thousands of entries off).
        let j = self.s[..n].partition_point(|&v| v <= s).saturating_sub(1);
        let (s0, s1) = (self.s[j], self.s[j + 1]);
        let hs = s1 - s0;
        let u = (s - s0) / hs;
        let (u2, u3) = (u * u, u * u * u);
        let th = (2.0 * u3 - 3.0 * u2 + 1.0) * self.theta[j]
            + (u3 - 2.0 * u2 + u) * hs * self.dtheta[j]
            + (-2.0 * u3 + 3.0 * u2) * self.theta[j + 1]
            + (u3 - u2) * hs * self.dtheta[j + 1];
        th + turns * TAU
    }

    /// Frame at arc length `s_mm`.
    #[must_use]
    pub fn at(&self, s_mm: f64) -> FramePoint {
        let theta = self.theta_at(s_mm);
        let g = self.curve.geometry(theta);
        let (sn, cs) = theta.sin_cos();
        let p = Point::new(g.r_mm * cs, g.r_mm * sn);
        let d = Point::new(g.dr_mm * cs - g.r_mm * sn, g.dr_mm * sn + g.r_mm * cs);
        let v = g.speed_mm();
        let t = d / v;
        let n = -t.perp();
        let kappa = g.convexity_mm2() / (v * v * v);
        FramePoint {
            p,
            t,
            n,
            kappa,
            theta,
        }
    }

    /// Maps rack coordinates `(ξ, η)` (ξ along the rolling arc, η along the outward normal) with
    /// the rack tangent at `P(s)` to the body frame: `P(s) + (ξ − s)T(s) + ηN(s)` (docs/math/teeth.md §12.3).
    #[must_use]
    pub fn rack_to_body(f: &FramePoint, s_mm: f64, xi: f64, eta: f64) -> Point {
        let u = xi - s_mm;
        f.p + f.t * u + f.n * eta
    }
}
