//! The motion of a pair from its law: ψ(φ) and i(φ), the closing centre distance of a centrode,
//! and the two pitch curves at a given centre distance.
use super::{Expr, Law, PairError};
use crate::geometry::pitch::PitchCurve;
use crate::math::periodic::{PeriodicSpline, invert_increasing, spectral_integral, uniform_angles};
use std::f64::consts::{PI, TAU};

/// The motion of the pair: ψ(φ) and i(φ) at unit centre distance.
#[derive(Debug, Clone)]
pub struct Motion {
    /// ψ(φ) − φ as a periodic spline, rad.
    excess: PeriodicSpline,
    /// i(φ) samples source, when analytic.
    ratio: RatioSource,
    /// Centre distance for unit scale (centrode units; 1 for motion laws).
    pub unit_centre_distance: f64,
}

#[derive(Debug, Clone)]
enum RatioSource {
    Expr(Expr),
    Centrode(Expr, f64),
    Spline,
}

impl Motion {
    /// ψ(φ), rad.
    #[must_use]
    pub fn psi(&self, phi: f64) -> f64 {
        phi + self.excess.value(phi)
    }
    /// i(φ) = dψ/dφ.
    #[must_use]
    pub fn ratio(&self, phi: f64) -> f64 {
        match &self.ratio {
            RatioSource::Expr(d) => d.eval(phi.rem_euclid(TAU)),
            RatioSource::Centrode(r, a) => {
                let r = r.eval(phi.rem_euclid(TAU));
                r / (a - r)
            }
            RatioSource::Spline => 1.0 + self.excess.derivative(phi),
        }
    }

    /// Builds the motion from a law with `n` samples per turn.
    pub fn from_law(law: &Law, n: usize) -> Result<Self, PairError> {
        let phis = uniform_angles(n);
        match law {
            Law::Motion(e) => {
                let d = e.derivative();
                let p0 = e.eval(0.0);
                let adv = e.eval(TAU) - p0;
                if (adv - TAU).abs() > 1e-9 * TAU {
                    return Err(PairError::Law(format!(
                        "ψ(2π) − ψ(0) = {:.6} rad; only one driven turn per driver turn (2π) is supported",
                        adv
                    )));
                }
                let mut ex = Vec::with_capacity(n);
                for &f in &phis {
                    let i = d.eval(f);
                    if !(i.is_finite() && i > 0.0) {
                        return Err(PairError::Law(format!(
                            "dψ/dφ = {i} at φ = {:.4}°; it must be finite and > 0",
                            f.to_degrees()
                        )));
                    }
                    ex.push(e.eval(f) - f);
                }
                let excess = PeriodicSpline::uniform(0.0, ex, TAU)
                    .map_err(|e| PairError::Law(e.to_string()))?;
                Ok(Self {
                    excess,
                    ratio: RatioSource::Expr(d),
                    unit_centre_distance: 1.0,
                })
            }
            Law::Centrode(e) => {
                let r: Vec<f64> = phis.iter().map(|&f| e.eval(f)).collect();
                if let Some((k, v)) = r
                    .iter()
                    .enumerate()
                    .find(|(_, v)| !(v.is_finite() && **v > 0.0))
                {
                    return Err(PairError::Law(format!(
                        "r = {v} at φ = {:.4}°; the centrode must be finite and > 0",
                        phis[k].to_degrees()
                    )));
                }
                let rmax = r.iter().copied().fold(0.0, f64::max);
                let mean = |a: f64| r.iter().map(|v| v / (a - v)).sum::<f64>() / n as f64 - 1.0;
                let (mut lo, mut hi) = (rmax * (1.0 + 1e-12), 2.0 * rmax);
                while mean(hi) > 0.0 {
                    hi *= 2.0;
                }
                for _ in 0..200 {
                    let mid = 0.5 * (lo + hi);
                    if mean(mid) > 0.0 {
                        lo = mid
                    } else {
                        hi = mid
                    }
                    if hi - lo <= 1e-15 * hi {
                        break;
                    }
                }
                let a = 0.5 * (lo + hi);
                let i: Vec<f64> = r.iter().map(|v| v / (a - v)).collect();
                if !(a.is_finite() && i.iter().all(|v| v.is_finite() && *v > 0.0)) {
                    return Err(PairError::Law(format!(
                        "the centrode (max r = {rmax:e}) gives no finite closing centre distance \
                         (a = {a:e}); scale it to ordinary lengths"
                    )));
                }
                let (_, f) = spectral_integral(&i);
                let excess = PeriodicSpline::uniform(0.0, f, TAU)
                    .map_err(|e| PairError::Law(e.to_string()))?;
                Ok(Self {
                    excess,
                    ratio: RatioSource::Centrode(e.clone(), a),
                    unit_centre_distance: a,
                })
            }
            Law::Table(rows) => {
                let phi0 = rows[0][0];
                let psi0 = rows[0][1];
                let x: Vec<f64> = rows.iter().map(|r| r[0] - phi0).collect();
                let y: Vec<f64> = rows.iter().map(|r| r[1] - psi0 - (r[0] - phi0)).collect();
                let sp =
                    PeriodicSpline::new(x, y, TAU).map_err(|e| PairError::Law(e.to_string()))?;
                // Resample on the uniform grid (φ measured from the first row).
                let ex: Vec<f64> = phis.iter().map(|&f| sp.value(f)).collect();
                let excess = PeriodicSpline::uniform(0.0, ex, TAU)
                    .map_err(|e| PairError::Law(e.to_string()))?;
                let m = Self {
                    excess,
                    ratio: RatioSource::Spline,
                    unit_centre_distance: 1.0,
                };
                if let Some(f) = phis.iter().find(|&&f| m.ratio(f) <= 0.0) {
                    return Err(PairError::Law(format!(
                        "the interpolated ratio is ≤ 0 near φ = {:.3}°",
                        f.to_degrees()
                    )));
                }
                Ok(m)
            }
        }
    }

    /// Driver and driven pitch curves (`n` samples each) at centre distance `a_mm`.
    pub fn pitch_curves(&self, a_mm: f64, n: usize) -> Result<(PitchCurve, PitchCurve), PairError> {
        let th = uniform_angles(n);
        let r1: Vec<f64> = th
            .iter()
            .map(|&t| {
                let i = self.ratio(-t);
                a_mm * i / (1.0 + i)
            })
            .collect();
        let r2: Vec<f64> = th
            .iter()
            .map(|&t| {
                // Solve π + ψ(φ) = t (mod 2π) for φ.
                let target = (t - PI - self.psi(0.0)).rem_euclid(TAU) + self.psi(0.0);
                let f = |x: f64| (self.psi(x), self.ratio(x));
                let phi =
                    invert_increasing(f, target, -TAU, 2.0 * TAU, target - self.psi(0.0), 1e-14);
                a_mm / (1.0 + self.ratio(phi))
            })
            .collect();
        let bad = |e: crate::geometry::pitch::PitchError| PairError::Law(e.to_string());
        Ok((
            PitchCurve::from_uniform_radii(r1).map_err(bad)?,
            PitchCurve::from_uniform_radii(r2).map_err(bad)?,
        ))
    }
}
