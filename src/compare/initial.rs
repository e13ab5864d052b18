//! The starting point of the registration: the period (the given speed, or [`super::period`]),
//! the scale (given, or the ratio of the radii of gyration), a check that track and design run
//! the same way round (the signed area, shoelace formula), and the phase φ₀ from a grid of
//! closed-form similarity fits (Umeyama, IEEE TPAMI 13(4), 1991): for each φ₀ of a 1° grid
//! the rotation `θ = atan2(Σ u_i × b_i, Σ u_i · b_i)` of the centred track `u_i` onto the design
//! points `b_i = B(φ₀ + ω·(t_i − t_m)) − b̄` and its residual; the φ₀ of the least one wins.

use super::design_path::DesignPath;
use super::{CompareError, period};
use crate::math::Point;
use std::f64::consts::TAU;

/// The starting values (see [`super::register`] for the model).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Start {
    /// Rotation θ, rad.
    pub rotation_rad: f64,
    /// Where the track's reference point lands, mm.
    pub translation_mm: Point,
    /// Scale, mm per track unit.
    pub scale: f64,
    /// Carrier angle at the mid time, rad.
    pub phase_rad: f64,
    /// Carrier speed, rad/s (signed: the design's direction).
    pub omega_rad_s: f64,
}

/// What is known before the fit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Known {
    /// The scale, mm per track unit (`None`: fitted).
    pub scale: Option<f64>,
    /// The track is relative to the carrier axis as filmed (the translation is O).
    pub datum: bool,
    /// The rotation, rad (`None`: fitted).
    pub rotation: Option<f64>,
}

/// Twice the signed area of a closed polygon (shoelace), > 0 counter-clockwise.
fn signed_area2(p: &[Point]) -> f64 {
    (0..p.len()).map(|k| p[k].cross(p[(k + 1) % p.len()])).sum()
}

fn gyration(p: &[Point]) -> f64 {
    let c = p.iter().fold(Point::default(), |a, q| a + *q) / p.len() as f64;
    (p.iter().map(|q| (*q - c).norm_squared()).sum::<f64>() / p.len() as f64).sqrt()
}

/// The period (s): `60/rpm`, or found in the frames; refused when the record is shorter.
pub fn period(
    file: &str,
    time_s: &[f64],
    u: &[Point],
    rpm: Option<f64>,
) -> Result<f64, CompareError> {
    let span = time_s[time_s.len() - 1] - time_s[0];
    let t = match rpm {
        Some(r) => 60.0 / r,
        None => period::period_s(time_s, u).ok_or_else(|| CompareError::TooShort {
            file: file.into(),
            message: format!(
                "{} frames over {span:.4} s never come back onto themselves (give the carrier speed with --rpm if the record is a whole turn exactly)",
                time_s.len()
            ),
        })?,
    };
    let step = span / (time_s.len() - 1) as f64;
    if span + step < t * 0.999 {
        return Err(CompareError::TooShort {
            file: file.into(),
            message: format!(
                "{} frames over {:.4} s: {:.2} of a {t:.4} s carrier turn",
                time_s.len(),
                span + step,
                (span + step) / t
            ),
        });
    }
    Ok(t)
}

/// The starting values of the registration of track points `u` (mirrored and flipped already,
/// relative to the reference point: the centroid, or the carrier axis `datum`) at times
/// carrier-angle offsets `offset_rad` from the mid frame (`ω·(t − t_m)`, or the encoder's), speed
/// `omega_rad_s` (signed), with what is `known`.
///
/// # Errors
/// [`CompareError::Mismatch`] when the track runs the other way round than the design, or its
/// size is off the design's by more than a factor 2 at a fixed scale.
pub fn start(
    file: &str,
    path: &DesignPath,
    u: &[Point],
    offset_rad: &[f64],
    omega_rad_s: f64,
    known: Known,
) -> Result<Start, CompareError> {
    let Known {
        scale,
        datum,
        rotation,
    } = known;
    let omega = omega_rad_s;
    let design = path.turn(1024);
    let first: Vec<Point> = u
        .iter()
        .zip(offset_rad)
        .filter(|(_, o)| (**o - offset_rad[0]).abs() < TAU)
        .map(|(p, _)| *p)
        .collect();
    let (a_track, a_design) = (signed_area2(&first), signed_area2(&design));
    if a_track * a_design < 0.0 {
        return Err(CompareError::Mismatch {
            file: file.into(),
            message: format!(
                "the track runs {} and the design {}: filmed from the other side? add --mirror (or drop it), or check --y-up/--y-down",
                if a_track > 0.0 {
                    "counter-clockwise"
                } else {
                    "clockwise"
                },
                if a_design > 0.0 {
                    "counter-clockwise"
                } else {
                    "clockwise"
                },
            ),
        });
    }
    let ratio = gyration(&design) / gyration(&first);
    let s = match scale {
        Some(s) if !(0.5..=2.0).contains(&(ratio / s)) => {
            return Err(CompareError::Mismatch {
                file: file.into(),
                message: format!(
                    "the track is {:.4} mm across (radius of gyration), the design {:.4} mm: wrong --units, --px-per-mm or --calibration?",
                    gyration(&first) * s,
                    gyration(&design)
                ),
            });
        }
        Some(s) => s,
        None => ratio,
    };
    let mut best = (
        f64::INFINITY,
        Start {
            rotation_rad: 0.0,
            translation_mm: Point::default(),
            scale: s,
            phase_rad: 0.0,
            omega_rad_s: omega,
        },
    );
    let su2: f64 = u.iter().map(|p| p.norm_squared()).sum::<f64>() * s * s;
    for k in 0..360 {
        let phase = (k as f64).to_radians();
        let b: Vec<Point> = offset_rad.iter().map(|o| path.tip(phase + o).0).collect();
        let anchor = if datum {
            path.center_mm
        } else {
            b.iter().fold(Point::default(), |a, q| a + *q) / b.len() as f64
        };
        let (mut dot, mut cross, mut b2) = (0.0, 0.0, 0.0);
        for (p, q) in u.iter().zip(&b) {
            let q = *q - anchor;
            dot += p.dot(q) * s;
            cross += p.cross(q) * s;
            b2 += q.norm_squared();
        }
        let theta = rotation.unwrap_or_else(|| cross.atan2(dot));
        let cost = b2 + su2 - 2.0 * (theta.cos() * dot + theta.sin() * cross);
        if cost < best.0 {
            best = (
                cost,
                Start {
                    rotation_rad: theta,
                    translation_mm: anchor,
                    scale: s,
                    phase_rad: phase,
                    omega_rad_s: omega,
                },
            );
        }
    }
    Ok(best.1)
}
