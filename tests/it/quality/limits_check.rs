//! Independent evaluation of the gear-quality limits from a design's output pitch tables.
//!
//! Input: `design.report.gears.{sun,intermediate,planet}.pitch = [θ_deg, r_mm]` at `n` uniform
//! angles. The polar derivatives are spectral (FFT of the samples, wavenumbers κ ∈ (−n/2, n/2),
//! Nyquist term dropped), not the library's `PitchCurve`:
//!
//! ```text
//! r_θ  = F⁻¹[ iκ·F[r] ],   r_θθ = F⁻¹[ −κ²·F[r] ]                      (mm per rad, per rad²)
//! slope         = max_θ |atan(r_θ / r)|                                (deg)
//! pressure      = α + slope,  α = 20°                                   (deg, limit 45°)
//! Δ             = r² + 2r_θ² − r·r_θθ                                   (mm²; concave where Δ < 0)
//! |ρ|           = (r² + r_θ²)^{3/2} / |Δ|   on the concave samples      (mm, limit ≥ R_min)
//! i21           = r_sun / (a − r_sun)                                   (sun table, a = centre distance)
//! ```

use ncgear::design::DesignReport;
use rustfft::FftPlanner;
use rustfft::num_complex::Complex;

/// The gear-quality limits.
#[derive(Debug, Clone, Copy)]
pub struct Limits {
    /// Rack pressure angle α, deg.
    pub alpha_deg: f64,
    /// Upper bound of the effective pressure angle α + max|atan(r_θ/r)|, deg.
    pub max_pressure_deg: f64,
    /// Smallest admissible radius of a concave arc, mm (10·m with a module m).
    pub min_concave_radius_mm: f64,
    /// Admissible sun ratio range `[i_min, i_max]`.
    pub ratio: [f64; 2],
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            alpha_deg: 20.0,
            max_pressure_deg: 45.0,
            min_concave_radius_mm: 10.0,
            ratio: [0.3, 3.3],
        }
    }
}

/// What the table of one gear shows.
#[derive(Debug, Clone, Copy)]
pub struct GearQuality {
    /// `max|atan(r_θ/r)|`, deg.
    pub slope_deg: f64,
    /// Tightest concave radius `min |ρ|` over samples with Δ < 0, mm; `None` when convex.
    pub tightest_concave_mm: Option<f64>,
}

/// The three gears and the ratio range.
#[derive(Debug, Clone, Copy)]
pub struct Quality {
    /// Sun, intermediate, planet.
    pub gears: [GearQuality; 3],
    /// `[min, max]` of i21 from the sun table.
    pub ratio_range: [f64; 2],
}

/// Gear names in the order of [`Quality::gears`].
pub const GEAR_NAMES: [&str; 3] = ["sun", "intermediate", "planet"];

impl Quality {
    /// Effective pressure angle α + the largest slope of the three gears, deg.
    pub fn pressure_deg(&self, lim: &Limits) -> f64 {
        lim.alpha_deg + self.gears.iter().map(|g| g.slope_deg).fold(0.0, f64::max)
    }
}

/// `(r_θ, r_θθ)` of uniform samples `r` of a 2π-periodic function (spectral).
pub fn polar_derivatives(r: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let n = r.len();
    let mut planner = FftPlanner::<f64>::new();
    let mut spec: Vec<Complex<f64>> = r.iter().map(|&v| Complex::new(v, 0.0)).collect();
    planner.plan_fft_forward(n).process(&mut spec);
    let kappa = |k: usize| -> f64 {
        match k {
            _ if 2 * k < n => k as f64,
            _ if 2 * k > n => k as f64 - n as f64,
            _ => 0.0, // Nyquist: dropped
        }
    };
    let mut d1: Vec<Complex<f64>> = (0..n)
        .map(|k| spec[k] * Complex::new(0.0, kappa(k)))
        .collect();
    let mut d2: Vec<Complex<f64>> = (0..n).map(|k| spec[k] * -(kappa(k).powi(2))).collect();
    let inv = planner.plan_fft_inverse(n);
    inv.process(&mut d1);
    inv.process(&mut d2);
    let s = 1.0 / n as f64;
    (
        d1.iter().map(|c| c.re * s).collect(),
        d2.iter().map(|c| c.re * s).collect(),
    )
}

/// Radii of a `[θ_deg, r_mm]` table, checked to be at uniform angles `360k/n` from its first angle.
pub fn uniform_radii(table: &[[f64; 2]]) -> Vec<f64> {
    let n = table.len();
    assert!(n >= 64, "pitch table has only {n} rows");
    let step = 360.0 / n as f64;
    for (k, row) in table.iter().enumerate() {
        let want = table[0][0] + step * k as f64;
        assert!(
            (row[0] - want).abs() < 1e-6,
            "pitch table row {k}: θ = {}° where uniform spacing gives {want}°",
            row[0]
        );
    }
    table.iter().map(|row| row[1]).collect()
}

/// Slope and tightest concave radius of the curve with uniform radii `r` (mm).
pub fn gear_quality(r: &[f64]) -> GearQuality {
    let (r1, r2) = polar_derivatives(r);
    let mut slope: f64 = 0.0;
    let mut tightest: Option<f64> = None;
    for k in 0..r.len() {
        let (r0, r1, r2) = (r[k], r1[k], r2[k]);
        slope = slope.max((r1 / r0).atan().abs());
        let delta = r0 * r0 + 2.0 * r1 * r1 - r0 * r2;
        if delta < 0.0 {
            let rho = (r0 * r0 + r1 * r1).powf(1.5) / -delta;
            tightest = Some(tightest.map_or(rho, |t| t.min(rho)));
        }
    }
    GearQuality {
        slope_deg: slope.to_degrees(),
        tightest_concave_mm: tightest,
    }
}

/// Evaluates a design report's three pitch tables and its sun ratio range.
pub fn evaluate(report: &DesignReport) -> Quality {
    let g = &report.gears;
    let tables = [&g.sun.pitch, &g.intermediate.pitch, &g.planet.pitch];
    let gears = tables.map(|t| gear_quality(&uniform_radii(t)));
    let a = report.center_distance_mm;
    let ratio_range = uniform_radii(&g.sun.pitch)
        .iter()
        .map(|&r| r / (a - r))
        .fold([f64::INFINITY, f64::NEG_INFINITY], |[lo, hi], i| {
            [lo.min(i), hi.max(i)]
        });
    Quality { gears, ratio_range }
}

/// Every way `q` leaves the limits, as readable messages (empty: within the limits).
pub fn violations(q: &Quality, lim: &Limits) -> Vec<String> {
    let mut v = Vec::new();
    let slope_max = lim.max_pressure_deg - lim.alpha_deg;
    for (g, name) in q.gears.iter().zip(GEAR_NAMES) {
        if !(g.slope_deg <= slope_max) {
            v.push(format!(
                "{name}: effective pressure angle {:.3}° = {}° + {:.3}° > {}°",
                lim.alpha_deg + g.slope_deg,
                lim.alpha_deg,
                g.slope_deg,
                lim.max_pressure_deg
            ));
        }
        if let Some(rho) = g.tightest_concave_mm
            && !(rho >= lim.min_concave_radius_mm)
        {
            v.push(format!(
                "{name}: concave arc of radius {rho:.3} mm < {} mm",
                lim.min_concave_radius_mm
            ));
        }
    }
    let [lo, hi] = q.ratio_range;
    if !(lo >= lim.ratio[0] && hi <= lim.ratio[1]) {
        v.push(format!(
            "sun ratio i21 ∈ [{lo:.4}, {hi:.4}] leaves [{}, {}]",
            lim.ratio[0], lim.ratio[1]
        ));
    }
    v
}

/// Panics with every violation of `q` against `lim`, naming the case.
pub fn assert_within(case: &str, q: &Quality, lim: &Limits) {
    let v = violations(q, lim);
    assert!(
        v.is_empty(),
        "{case}: outside the gear-quality limits: {}",
        v.join("; ")
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    fn samples(n: usize, f: impl Fn(f64) -> f64) -> Vec<f64> {
        (0..n).map(|k| f(TAU * k as f64 / n as f64)).collect()
    }

    /// `r = R(1 + ε cos 2θ)`: r_θ = −2Rε sin 2θ, r_θθ = −4Rε cos 2θ; max|r_θ/r| = 2ε/√(1 − ε²)
    /// (at cos 2θ = −ε); concave at θ = 90° for ε > 0.2 with |ρ| = R(1 − ε)²/(5ε − 1).
    fn ellipse_like(radius: f64, eps: f64, n: usize) -> (Vec<f64>, f64, Option<f64>) {
        let exact = |t: f64| {
            let (s, c) = (2.0 * t).sin_cos();
            let r = radius * (1.0 + eps * c);
            (r, -2.0 * radius * eps * s, -4.0 * radius * eps * c)
        };
        // Analytic derivatives on a grid 100× finer than the table.
        let mut tight: Option<f64> = None;
        for k in 0..100 * n {
            let (r, r1, r2) = exact(TAU * k as f64 / (100 * n) as f64);
            let delta = r * r + 2.0 * r1 * r1 - r * r2;
            if delta < 0.0 {
                let rho = (r * r + r1 * r1).powf(1.5) / -delta;
                tight = Some(tight.map_or(rho, |t| t.min(rho)));
            }
        }
        let slope = (2.0 * eps / (1.0 - eps * eps).sqrt()).atan().to_degrees();
        (samples(n, |t| exact(t).0), slope, tight)
    }

    #[test]
    fn circle_has_no_slope_and_is_convex() {
        let q = gear_quality(&samples(720, |_| 23.5));
        assert!(q.slope_deg.abs() < 1e-9, "slope {}", q.slope_deg);
        assert!(q.tightest_concave_mm.is_none());
    }

    #[test]
    fn derivatives_match_closed_forms() {
        let r = samples(360, |t| 20.0 + 3.0 * (3.0 * t).sin());
        let (d1, d2) = polar_derivatives(&r);
        for k in 0..360 {
            let t = TAU * k as f64 / 360.0;
            assert!((d1[k] - 9.0 * (3.0 * t).cos()).abs() < 1e-9, "r_θ at {k}");
            assert!((d2[k] + 27.0 * (3.0 * t).sin()).abs() < 1e-9, "r_θθ at {k}");
        }
    }

    #[test]
    fn ellipse_like_convex_matches_analytic() {
        let (r, slope, tight) = ellipse_like(25.0, 0.1, 720);
        assert!(tight.is_none(), "ε = 0.1 is convex");
        let q = gear_quality(&r);
        // The table's max is at a sample; the analytic max lies within half a step of one.
        assert!(
            (q.slope_deg - slope).abs() < 1e-3,
            "{} vs {slope}",
            q.slope_deg
        );
        assert!(q.tightest_concave_mm.is_none());
    }

    #[test]
    fn ellipse_like_concave_matches_analytic_and_is_flagged() {
        let (eps, radius) = (0.3, 8.0);
        let (r, slope, tight) = ellipse_like(radius, eps, 3600);
        let vertex = radius * (1.0 - eps).powi(2) / (5.0 * eps - 1.0);
        let tight = tight.expect("ε = 0.3 is concave");
        assert!(
            tight <= vertex + 1e-9,
            "the vertex is concave: {tight} vs {vertex}"
        );
        let q = gear_quality(&r);
        let got = q.tightest_concave_mm.expect("concave");
        assert!(
            (got - tight).abs() < 1e-4 * tight,
            "{got} vs analytic {tight}"
        );
        assert!(
            (q.slope_deg - slope).abs() < 1e-3,
            "{} vs {slope}",
            q.slope_deg
        );
        // 20° + 32.2° > 45° and |ρ| ≤ 7.84 mm < 10 mm: both flagged, the ratio range too.
        let quality = Quality {
            gears: [q; 3],
            ratio_range: [0.2, 1.0],
        };
        let v = violations(&quality, &Limits::default());
        assert_eq!(v.len(), 7, "{v:?}");
        let ok = Quality {
            gears: [gear_quality(&ellipse_like(25.0, 0.1, 720).0); 3],
            ratio_range: [0.5, 2.0],
        };
        assert!(violations(&ok, &Limits::default()).is_empty());
    }
}
