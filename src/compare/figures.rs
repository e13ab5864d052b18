//! What the registered track says about the built mechanism: the smooth deviation `d(φ)` by
//! carrier angle, its RMS, largest and Hausdorff figures, the agronomic figures of
//! [`crate::simulate::features_of_turn`] on the track's path `B(φ) + d(φ)` beside the design's
//! `B(φ)`, and the same turn by turn.
//!
//! The needle angle of the track: with a second marker on the needle's axis, the direction from
//! it to the tip, `α_d(φ) + δα(φ)` with `δα` the smooth (order K) fit of the frames' departures
//! from the design's `α_d`; without, the direction from the design's planet centre `A(φ)` to
//! the track's tip.

use super::design_path::{DesignPath, feature_pose};
use super::report::{AngleDeviation, DeviationReport, TurnFigures};
use super::smooth::Fourier;
use crate::math::Point;
use crate::math::periodic::wrap_pi;
use crate::simulate::{FeatureOptions, Features, SimulateError, TwoArms, features_of_turn};
use std::f64::consts::PI;

/// Samples of a turn for the figures.
pub const TURN_SAMPLES: usize = 3600;

/// A path by carrier angle: the design's plus a smooth deviation (and needle-angle departure).
#[derive(Debug, Clone)]
pub struct SmoothPath<'a> {
    path: &'a DesignPath,
    /// `d(φ)`: x and y series, or `None` for the design itself.
    dev: Option<[Fourier; 2]>,
    /// `δα(φ)` of the marker, rad.
    needle: Option<Fourier>,
}

impl<'a> SmoothPath<'a> {
    /// The design path itself.
    #[must_use]
    pub fn design(path: &'a DesignPath) -> Self {
        Self {
            path,
            dev: None,
            needle: None,
        }
    }

    /// The smooth path of the frames `use_frame` (residuals `r`, carrier angles `phi`, needle
    /// angles `needle` when measured, rad), order `order`; `None` when they do not determine it.
    #[must_use]
    pub fn fit(
        path: &'a DesignPath,
        phi: &[f64],
        r: &[Point],
        needle: Option<&[f64]>,
        use_frame: &[bool],
        order: usize,
    ) -> Option<Self> {
        let w: Vec<f64> = use_frame.iter().map(|u| f64::from(u8::from(*u))).collect();
        let comps = vec![
            r.iter().map(|p| p.x).collect(),
            r.iter().map(|p| p.y).collect::<Vec<_>>(),
        ];
        let mut d = Fourier::fit(phi, &comps, &w, order)?;
        let needle = match needle {
            Some(a) => {
                let da: Vec<f64> = a
                    .iter()
                    .zip(phi)
                    .map(|(a, p)| wrap_pi(a - path.needle_angle(*p)))
                    .collect();
                Some(Fourier::fit(phi, &[da], &w, order)?.remove(0))
            }
            None => None,
        };
        let dy = d.pop()?;
        let dx = d.pop()?;
        Some(Self {
            path,
            dev: Some([dx, dy]),
            needle,
        })
    }

    /// `d(φ)`, mm.
    #[must_use]
    pub fn deviation(&self, phi: f64) -> Point {
        self.dev.as_ref().map_or(Point::default(), |[x, y]| {
            Point::new(x.value(phi), y.value(phi))
        })
    }

    /// Planet centre (on the needle's axis) and tip at φ, mm.
    fn arm(&self, phi: f64) -> (Point, Point) {
        let b = self.path.tip(phi).0 + self.deviation(phi);
        let a = self.path.planet_center(phi);
        match &self.needle {
            Some(n) => {
                let alpha = self.path.needle_angle(phi) + n.value(phi);
                (b - Point::unit(alpha) * (b - a).norm(), b)
            }
            None => (a, b),
        }
    }

    /// Both arms at `n` instants of a turn (arm 2 is arm 1 half a turn later).
    #[must_use]
    pub fn turn(&self, n: usize) -> Vec<TwoArms> {
        (0..n)
            .map(|k| {
                let phi = self.path.angle_at(k, n);
                let (a1, b1) = self.arm(phi);
                let (a2, b2) = self.arm(phi + PI);
                TwoArms {
                    arm1: feature_pose(phi, a1, b1),
                    arm2: feature_pose(phi + PI, a2, b2),
                }
            })
            .collect()
    }

    /// The agronomic features of this path.
    ///
    /// # Errors
    /// [`SimulateError`] for a bad option (level, depth).
    pub fn features(&self, opts: &FeatureOptions) -> Result<Features, SimulateError> {
        features_of_turn(
            &self.turn(TURN_SAMPLES),
            self.path.center_mm,
            self.path.direction,
            opts,
        )
    }

    /// `(RMS, max, carrier angle of the max)` of `|d(φ)|` over the turn, mm, mm, rad.
    #[must_use]
    pub fn deviation_stats(&self) -> (f64, f64, f64) {
        let (mut s2, mut mx, mut at) = (0.0, 0.0, 0.0);
        for k in 0..TURN_SAMPLES {
            let phi = self.path.angle_at(k, TURN_SAMPLES);
            let d = self.deviation(phi).norm();
            s2 += d * d;
            if d > mx {
                (mx, at) = (d, phi);
            }
        }
        ((s2 / TURN_SAMPLES as f64).sqrt(), mx, at)
    }

    /// The main figures (and the deviation RMS) of this path.
    ///
    /// # Errors
    /// As [`Self::features`].
    pub fn figures(&self, opts: &FeatureOptions) -> Result<TurnFigures, SimulateError> {
        Ok(figures_of(&self.features(opts)?, self.deviation_stats().0))
    }
}

/// The main figures of a feature set.
#[must_use]
pub fn figures_of(f: &Features, deviation_rms_mm: f64) -> TurnFigures {
    TurnFigures {
        take_angle_deg: f.take_angle_deg,
        push_angle_deg: f.push_angle_deg,
        hole_width_mm: f.hole_width_mm,
        height_mm: f.height_mm,
        static_width_at_depth_mm: f.static_width_at_depth_mm,
        deviation_rms_mm,
    }
}

/// `a − b` of each figure.
#[must_use]
pub fn difference(a: &TurnFigures, b: &TurnFigures) -> TurnFigures {
    TurnFigures {
        take_angle_deg: a.take_angle_deg - b.take_angle_deg,
        push_angle_deg: a.push_angle_deg - b.push_angle_deg,
        hole_width_mm: a.hole_width_mm - b.hole_width_mm,
        height_mm: a.height_mm - b.height_mm,
        static_width_at_depth_mm: a.static_width_at_depth_mm - b.static_width_at_depth_mm,
        deviation_rms_mm: a.deviation_rms_mm - b.deviation_rms_mm,
    }
}

/// The sample standard deviation of each figure over the turns (≥ 2).
#[must_use]
pub fn spread(turns: &[TurnFigures]) -> Option<TurnFigures> {
    if turns.len() < 2 {
        return None;
    }
    let sd = |f: fn(&TurnFigures) -> f64| {
        let n = turns.len() as f64;
        let m = turns.iter().map(f).sum::<f64>() / n;
        (turns.iter().map(|t| (f(t) - m).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
    };
    Some(TurnFigures {
        take_angle_deg: sd(|t| t.take_angle_deg),
        push_angle_deg: sd(|t| t.push_angle_deg),
        hole_width_mm: sd(|t| t.hole_width_mm),
        height_mm: sd(|t| t.height_mm),
        static_width_at_depth_mm: sd(|t| t.static_width_at_depth_mm),
        deviation_rms_mm: sd(|t| t.deviation_rms_mm),
    })
}

/// The deviation report of a smooth track path: frame figures from the inlier residuals
/// `r` (at carrier angles `phi`), noise σ (mm) and the smooth path's figures.
#[must_use]
pub fn deviation_report(
    smooth: &SmoothPath<'_>,
    phi: &[f64],
    r: &[Point],
    inlier: &[bool],
    sigma_mm: f64,
    order: usize,
) -> DeviationReport {
    let used: Vec<f64> = r
        .iter()
        .zip(inlier)
        .filter(|(_, u)| **u)
        .map(|(p, _)| p.norm())
        .collect();
    let n = used.len().max(1) as f64;
    let path = smooth.path;
    let (rms, mx, at) = smooth.deviation_stats();
    let design = path.turn(TURN_SAMPLES);
    let track: Vec<Point> = (0..TURN_SAMPLES)
        .map(|k| {
            let p = path.angle_at(k, TURN_SAMPLES);
            path.tip(p).0 + smooth.deviation(p)
        })
        .collect();
    let by_angle = (0..72)
        .map(|k| {
            let deg = 5.0 * k as f64;
            let p = deg.to_radians();
            let (b, db) = path.tip(p);
            let t = db * f64::from(path.direction) / db.norm().max(1e-300);
            let d = smooth.deviation(p);
            let frames = phi
                .iter()
                .zip(inlier)
                .filter(|(f, u)| **u && wrap_pi(**f - p).abs() <= 2.5f64.to_radians())
                .count();
            AngleDeviation {
                carrier_deg: deg,
                design_mm: [b.x, b.y],
                deviation_mm: [d.x, d.y],
                normal_mm: d.dot(t.perp()),
                tangential_mm: d.dot(t),
                frames,
            }
        })
        .collect();
    DeviationReport {
        frame_rms_mm: (used.iter().map(|d| d * d).sum::<f64>() / n).sqrt(),
        frame_max_mm: used.iter().copied().fold(0.0, f64::max),
        smooth_order: order,
        noise_floor_mm: sigma_mm * ((2 * order + 1) as f64 / n).sqrt(),
        rms_mm: rms,
        max_mm: mx,
        max_at_carrier_deg: at.to_degrees().rem_euclid(360.0),
        hausdorff_mm: crate::math::polyline::hausdorff_mm(&track, &design),
        by_angle,
    }
}
