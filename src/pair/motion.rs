//! The motion of a pair from its law: ψ(φ) and i(φ), the closing centre distance of a centrode,
//! and the two pitch curves at a given centre distance.
//!
//! The law advances the driven gear by a constant `Δ = ψ(φ + 2π) − ψ(φ)` per driver turn (the
//! *cycle advance*; `Δ = 2π` for equal gears, `π` for a 1:2 pair). With `Δ/2π = p/q` in lowest
//! terms the driven gear closes after `q` driver turns of `p` driven turns, which needs
//! `ψ(φ) − Δφ/2π` to repeat every `2π/p` (checked by [`Motion::driven_closure_defect_rad`]).
use super::{Expr, Law, PairError};
use crate::geometry::pitch::PitchCurve;
use crate::math::periodic::{PeriodicSpline, spectral_integral, uniform_angles};
use crate::math::roots::invert_increasing;
use std::f64::consts::{PI, TAU};

/// Largest relative mismatch of i(0) and i(2π) of a motion law that still closes the driver.
const RATIO_PERIOD_TOL: f64 = 1e-9;
/// Relative tolerance and largest denominator of the turn ratio read as a fraction p/q.
const FRACTION_TOL: f64 = 1e-9;
const FRACTION_MAX_DENOMINATOR: u32 = 360;

/// The motion of the pair: ψ(φ) and i(φ) at unit centre distance.
#[derive(Debug, Clone)]
pub struct Motion {
    /// ψ(φ) − kφ as a periodic spline (k = Δ/2π), rad.
    excess: PeriodicSpline,
    /// Cycle advance Δ = ψ(φ + 2π) − ψ(φ), rad (2π for equal gears).
    pub advance_rad: f64,
    /// i(φ) samples source, when analytic.
    ratio: RatioSource,
    /// Centre distance for unit scale (centrode units; 1 for motion laws).
    pub unit_center_distance: f64,
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
        self.turn_ratio() * phi + self.excess.value(phi)
    }

    /// Driven turns per driver turn, `k = Δ/2π` (mean of i).
    #[must_use]
    pub fn turn_ratio(&self) -> f64 {
        self.advance_rad / TAU
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
            RatioSource::Spline => self.turn_ratio() + self.excess.derivative(phi),
        }
    }

    /// Builds the motion from a law with `n` samples per turn; a centrode closes with one driven
    /// turn per driver turn (see [`Motion::from_law_advancing`]).
    pub fn from_law(law: &Law, n: usize) -> Result<Self, PairError> {
        Self::from_law_advancing(law, n, TAU)
    }

    /// [`Motion::from_law`] with the cycle advance `centrode_advance_rad` (Δ, rad) that a centrode's
    /// centre distance is solved for: `mean over φ of r/(a − r) = Δ/2π`. A motion law brings its own
    /// advance `ψ(2π) − ψ(0)` (any Δ > 0); a table law is one turn of equal gears (Δ = 2π).
    pub fn from_law_advancing(
        law: &Law,
        n: usize,
        centrode_advance_rad: f64,
    ) -> Result<Self, PairError> {
        let phis = uniform_angles(n);
        match law {
            Law::Motion(e) => Self::from_motion(e, &phis),
            Law::Centrode(e) => Self::from_centrode(e, &phis, centrode_advance_rad),
            Law::Table(rows) => Self::from_table(rows, &phis),
        }
    }

    /// A motion law ψ(φ) sampled at `phis` (rad): the excess ψ − k·φ, `k` its mean ratio.
    fn from_motion(e: &Expr, phis: &[f64]) -> Result<Self, PairError> {
        let n = phis.len();
        let d = e.derivative();
        let p0 = e.eval(0.0);
        let adv = e.eval(TAU) - p0;
        if !(adv.is_finite() && adv > 0.0) {
            return Err(PairError::Law(format!(
                "ψ(2π) − ψ(0) = {adv:.6} rad; the driven gear must advance (> 0) over a driver turn"
            )));
        }
        let (i0, i1) = (d.eval(0.0), d.eval(TAU));
        if (i1 - i0).abs() > RATIO_PERIOD_TOL * i0.abs().max(1.0) {
            return Err(PairError::Law(format!(
                "dψ/dφ is {i0:.9} at φ = 0 but {i1:.9} at φ = 360°: the ratio must repeat every \
                 driver turn for the driver gear to close"
            )));
        }
        let k = adv / TAU;
        let mut ex = Vec::with_capacity(n);
        for &f in phis {
            let i = d.eval(f);
            if !(i.is_finite() && i > 0.0) {
                return Err(PairError::Law(format!(
                    "dψ/dφ = {i} at φ = {:.4}°; it must be finite and > 0",
                    f.to_degrees()
                )));
            }
            ex.push(e.eval(f) - k * f);
        }
        let excess =
            PeriodicSpline::uniform(0.0, ex, TAU).map_err(|e| PairError::Law(e.to_string()))?;
        Ok(Self {
            excess,
            advance_rad: adv,
            ratio: RatioSource::Expr(d),
            unit_center_distance: 1.0,
        })
    }

    /// A centrode r(φ) (unit-free) sampled at `phis` (rad), the driven gear advancing
    /// `advance_rad` per driver turn: the centre distance that closes it (bisection of the mean
    /// ratio) and the excess of the ratio's integral.
    fn from_centrode(e: &Expr, phis: &[f64], centrode_advance_rad: f64) -> Result<Self, PairError> {
        let n = phis.len();
        if !(centrode_advance_rad.is_finite() && centrode_advance_rad > 0.0) {
            return Err(PairError::InvalidParameter {
                name: "centrode_advance_rad",
                value: centrode_advance_rad,
                expected: "finite and > 0",
            });
        }
        let k = centrode_advance_rad / TAU;
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
        let mean = |a: f64| r.iter().map(|v| v / (a - v)).sum::<f64>() / n as f64 - k;
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
        let excess =
            PeriodicSpline::uniform(0.0, f, TAU).map_err(|e| PairError::Law(e.to_string()))?;
        Ok(Self {
            excess,
            advance_rad: centrode_advance_rad,
            ratio: RatioSource::Centrode(e.clone(), a),
            unit_center_distance: a,
        })
    }

    /// A table law of `(φ, ψ)` rows (rad), resampled at `phis` (φ measured from the first row).
    fn from_table(rows: &[[f64; 2]], phis: &[f64]) -> Result<Self, PairError> {
        let phi0 = rows[0][0];
        let psi0 = rows[0][1];
        let x: Vec<f64> = rows.iter().map(|r| r[0] - phi0).collect();
        let y: Vec<f64> = rows.iter().map(|r| r[1] - psi0 - (r[0] - phi0)).collect();
        let sp = PeriodicSpline::new(x, y, TAU).map_err(|e| PairError::Law(e.to_string()))?;
        // Resample on the uniform grid (φ measured from the first row).
        let ex: Vec<f64> = phis.iter().map(|&f| sp.value(f)).collect();
        let excess =
            PeriodicSpline::uniform(0.0, ex, TAU).map_err(|e| PairError::Law(e.to_string()))?;
        let m = Self {
            excess,
            advance_rad: TAU,
            ratio: RatioSource::Spline,
            unit_center_distance: 1.0,
        };
        if let Some(f) = phis.iter().find(|&&f| m.ratio(f) <= 0.0) {
            return Err(PairError::Law(format!(
                "the interpolated ratio is ≤ 0 near φ = {:.3}°",
                f.to_degrees()
            )));
        }
        Ok(m)
    }

    /// The turn ratio as a fraction `k = Δ/2π = p/q` in lowest terms with `q ≤ 360`, within
    /// 1e-9·k; `None` for an irrational-looking advance (no closed driven gear).
    #[must_use]
    pub fn turn_fraction(&self) -> Option<(u32, u32)> {
        let k = self.turn_ratio();
        (1..=FRACTION_MAX_DENOMINATOR).find_map(|q| {
            let p = (k * f64::from(q)).round();
            ((p >= 1.0) && (k * f64::from(q) - p).abs() <= FRACTION_TOL * k * f64::from(q))
                .then_some((p as u32, q))
        })
    }

    /// The driven gear's closure defect, rad: with `k = p/q` the driven gear turns once per `2π/k`
    /// of φ, so it closes iff `ψ(φ) − kφ` repeats every `2π/p` (its period is already 2π);
    /// returns `max_φ |ψ(φ + 2π/p) − ψ(φ) − 2πk/p|` over `n` samples (0 for p = 1).
    #[must_use]
    pub fn driven_closure_defect_rad(&self, p: u32, n: usize) -> f64 {
        let shift = TAU / f64::from(p);
        uniform_angles(n)
            .iter()
            .map(|&f| (self.excess.value(f + shift) - self.excess.value(f)).abs())
            .fold(0.0, f64::max)
    }

    /// Driver and driven pitch curves (`n` samples each) at centre distance `a_mm`.
    pub fn pitch_curves(&self, a_mm: f64, n: usize) -> Result<(PitchCurve, PitchCurve), PairError> {
        let (r1, r2) = self.unit_pitch_radii(n);
        Self::curves_at(&r1, &r2, a_mm)
    }

    /// Radii of the driver and driven pitch curves at unit centre distance, at the `n` uniform
    /// polar angles of [`uniform_angles`]: `r₁(θ) = i(−θ)/(1 + i(−θ))` and `r₂(θ) = 1/(1 + i(φ))`
    /// with `π + ψ(φ) = θ`. Every radius scales with the centre distance.
    #[must_use]
    pub fn unit_pitch_radii(&self, n: usize) -> (Vec<f64>, Vec<f64>) {
        use rayon::prelude::*;
        let th = uniform_angles(n);
        let r1: Vec<f64> = th
            .iter()
            .map(|&t| {
                let i = self.ratio(-t);
                i / (1.0 + i)
            })
            .collect();
        let psi0 = self.psi(0.0);
        let turn = TAU / self.turn_ratio();
        // One inversion per sample, independent of the others: side by side.
        let r2: Vec<f64> = th
            .par_iter()
            .map(|&t| {
                // Solve π + ψ(φ) = t (mod 2π) for φ within one driven turn (2π/k of φ).
                let target = (t - PI - psi0).rem_euclid(TAU) + psi0;
                let f = |x: f64| (self.psi(x), self.ratio(x));
                let guess = (target - psi0) / self.turn_ratio();
                let phi = invert_increasing(f, target, -turn, 2.0 * turn, guess, 1e-14);
                1.0 / (1.0 + self.ratio(phi))
            })
            .collect();
        (r1, r2)
    }

    /// The pitch curves of [`Self::unit_pitch_radii`] `(r1, r2)` at centre distance `a_mm`.
    pub fn curves_at(
        r1: &[f64],
        r2: &[f64],
        a_mm: f64,
    ) -> Result<(PitchCurve, PitchCurve), PairError> {
        let scale = |r: &[f64]| r.iter().map(|&x| a_mm * x).collect::<Vec<f64>>();
        let (r1, r2) = (scale(r1), scale(r2));
        let bad = |e: crate::geometry::pitch::PitchError| PairError::Law(e.to_string());
        Ok((
            PitchCurve::from_uniform_radii(r1).map_err(bad)?,
            PitchCurve::from_uniform_radii(r2).map_err(bad)?,
        ))
    }
}
