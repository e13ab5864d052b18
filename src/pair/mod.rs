//! A single non-circular gear pair from a law (the job of the Python `ncgears` package):
//! a motion law `ψ(φ)`, a drive centrode `r(φ)` (centre distance solved for closure), or a CSV
//! table of `(φ, ψ)` in degrees; then teeth, mesh verification and exports.
//!
//! Conventions (design-chain §5): driver centre at the origin, rotating CCW by φ; driven centre at
//! `(a, 0)`, rotating CW by ψ; ratio `i = dψ/dφ > 0`. Contact on the centre line:
//! `r1 = a·i/(1+i)` at driver body angle `−φ`, `r2 = a/(1+i)` at driven body angle `π + ψ`.
//! One driven turn per driver turn: `ψ(φ+2π) = ψ(φ) + 2π` (equal tooth counts).
pub mod expr;

pub use expr::{Expr, ExprError};

use crate::export::{Contour, Marker, Sheet};
use crate::geometry::pitch::PitchCurve;
use crate::math::periodic::{PeriodicSpline, invert_increasing, spectral_integral, uniform_angles};
use crate::teeth::mesh::{MeshCheck, MeshReport, verify_mesh};
use crate::teeth::{
    ArcFrame, Outline, OutlineOptions, RackParams, TeethError, UndercutReport, outline,
};
use serde::Serialize;
use std::f64::consts::{PI, TAU};

/// Errors of the pair designer.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PairError {
    /// Expression syntax.
    #[error(transparent)]
    Expr(#[from] ExprError),
    /// The law is not usable.
    #[error("law: {0}")]
    Law(String),
    /// CSV law file problem.
    #[error("{path}:{line}: {message}")]
    Csv {
        /// File.
        path: String,
        /// 1-based line.
        line: usize,
        /// What was expected.
        message: String,
    },
    /// Teeth.
    #[error(transparent)]
    Teeth(#[from] TeethError),
    /// Mesh check.
    #[error(transparent)]
    Mesh(#[from] crate::teeth::mesh::MeshError),
    /// Bad parameter.
    #[error("invalid parameter `{name}` = {value}: {expected}")]
    InvalidParameter {
        /// Name.
        name: &'static str,
        /// Value.
        value: f64,
        /// Expectation.
        expected: &'static str,
    },
}

/// The law of the pair.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub enum Law {
    /// Motion law ψ(φ), rad → rad.
    Motion(Expr),
    /// Drive pitch radius at the contact `r(φ)` (any length unit; the shape is scaled to the teeth).
    Centrode(Expr),
    /// Table of (φ, ψ) in radians, φ strictly increasing over one turn `[φ0, φ0 + 2π)`.
    Table(Vec<[f64; 2]>),
}

impl Law {
    /// Reads a CSV law file with header `phi_deg,psi_deg` (degrees; one driver turn, φ strictly
    /// increasing and spanning less than 360°; ψ strictly increasing).
    pub fn from_csv(path: &std::path::Path) -> Result<Self, PairError> {
        let p = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| PairError::Csv {
            path: p.clone(),
            line: 0,
            message: e.to_string(),
        })?;
        Self::parse_csv(&text, &p)
    }

    /// Parses CSV law text (format of [`Law::from_csv`]); `file` names the source in errors.
    ///
    /// # Errors
    /// [`PairError::Csv`] naming the file, the 1-based line and what was expected.
    pub fn parse_csv(text: &str, file: &str) -> Result<Self, PairError> {
        let p = file.to_string();
        let mut rows = Vec::new();
        for (k, line) in text.lines().enumerate() {
            let line = line.trim();
            if k == 0 {
                if line.replace(' ', "") != "phi_deg,psi_deg" {
                    return Err(PairError::Csv {
                        path: p,
                        line: 1,
                        message: "expected header `phi_deg,psi_deg`".into(),
                    });
                }
                continue;
            }
            if line.is_empty() {
                continue;
            }
            let parts: Vec<&str> = line.split(',').map(str::trim).collect();
            let vals: Option<Vec<f64>> = parts
                .iter()
                .map(|s| s.parse::<f64>().ok().filter(|v| v.is_finite()))
                .collect();
            match vals {
                Some(v) if v.len() == 2 => rows.push([v[0].to_radians(), v[1].to_radians()]),
                _ => {
                    return Err(PairError::Csv {
                        path: p,
                        line: k + 1,
                        message: format!(
                            "expected two finite numbers `phi_deg,psi_deg`, got `{line}`"
                        ),
                    });
                }
            }
        }
        if rows.len() < 8 {
            return Err(PairError::Csv {
                path: p,
                line: rows.len() + 1,
                message: "need at least 8 rows".into(),
            });
        }
        for k in 1..rows.len() {
            if rows[k][0] <= rows[k - 1][0] || rows[k][1] <= rows[k - 1][1] {
                return Err(PairError::Csv {
                    path: p,
                    line: k + 2,
                    message: "phi and psi must be strictly increasing".into(),
                });
            }
        }
        if rows[rows.len() - 1][0] - rows[0][0] >= TAU {
            return Err(PairError::Csv {
                path: p,
                line: rows.len() + 1,
                message: "phi must span less than 360° (one turn, no repeated end row)".into(),
            });
        }
        Ok(Law::Table(rows))
    }
}

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

/// Options of [`design_pair`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PairOptions {
    /// Tooth count (same on both gears); `None`: from the centrode's own size rounded up
    /// (centrode only).
    pub teeth: Option<u32>,
    /// Module, mm.
    pub module_mm: f64,
    /// Basic rack.
    pub rack: RackParams,
    /// Circumferential backlash of the pair on the pitch curve, mm (each gear's coast flank is
    /// thinned by half; the working flanks stay exactly conjugate).
    pub backlash_mm: f64,
    /// Samples per turn of the law and of the pitch curves.
    pub samples: usize,
    /// Chord tolerance of the exported outlines, mm (default 1e-3·m).
    pub chord_tol_mm: f64,
    /// Chord tolerance of the outlines used by the mesh verification, mm.
    pub verify_chord_tol_mm: f64,
    /// Driver positions in the mesh verification (0 = skip).
    pub verify_steps: usize,
}

impl PairOptions {
    /// Defaults for `module_mm`: 20° rack, backlash 0.04·m, 4096 samples, chord 1e-3·m,
    /// verification at chord 1e-6·m over 90 steps (every 4°).
    #[must_use]
    pub fn new(teeth: Option<u32>, module_mm: f64) -> Self {
        Self {
            teeth,
            module_mm,
            rack: RackParams::default(),
            backlash_mm: 0.04 * module_mm,
            samples: 4096,
            chord_tol_mm: 1e-3 * module_mm,
            verify_chord_tol_mm: 1e-6 * module_mm,
            verify_steps: 90,
        }
    }
}

/// A designed pair.
#[derive(Debug, Clone, Serialize)]
pub struct PairDesign {
    /// Centre distance, mm.
    pub centre_distance_mm: f64,
    /// Tooth count of each gear.
    pub z: u32,
    /// Module, mm.
    pub module_mm: f64,
    /// Pitch-curve perimeter, mm (= zπm).
    pub perimeter_mm: f64,
    /// Ratio range `[min, max]` of i = dψ/dφ.
    pub ratio_range: [f64; 2],
    /// Driver outline (export tolerance).
    pub driver: Outline,
    /// Driven outline (export tolerance).
    pub driven: Outline,
    /// Undercut report of the driver.
    pub driver_undercut: UndercutReport,
    /// Undercut report of the driven gear.
    pub driven_undercut: UndercutReport,
    /// Mesh verification (if run).
    pub mesh: Option<MeshReport>,
    /// Driven rotation at φ = 0, ψ(0), rad.
    pub psi0_rad: f64,
    /// Driver pitch polyline (body frame), mm.
    pub driver_pitch_mm: Vec<[f64; 2]>,
    /// Driven pitch polyline (body frame), mm.
    pub driven_pitch_mm: Vec<[f64; 2]>,
}

/// Designs the toothed pair: pitch curves scaled so that `L = zπm`, rack-generated outlines with
/// the mating phase (driver tooth 0 centred at the contact of φ = 0, a driven space facing it),
/// and the mesh verification over one turn.
pub fn design_pair(law: &Law, opts: &PairOptions) -> Result<PairDesign, PairError> {
    design_pair_with_progress(law, opts, &|_| {})
}

/// [`design_pair`] reporting mesh-verification progress (`progress(1)` per driver position).
pub fn design_pair_with_progress(
    law: &Law,
    opts: &PairOptions,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<PairDesign, PairError> {
    let m = opts.module_mm;
    if !(m.is_finite() && m > 0.0) {
        return Err(PairError::InvalidParameter {
            name: "module_mm",
            value: m,
            expected: "finite and > 0",
        });
    }
    if opts.samples < 64 {
        return Err(PairError::InvalidParameter {
            name: "samples",
            value: opts.samples as f64,
            expected: "≥ 64",
        });
    }
    if !(opts.backlash_mm.is_finite() && opts.backlash_mm > 0.0) {
        return Err(PairError::InvalidParameter {
            name: "backlash_mm",
            value: opts.backlash_mm,
            expected: "finite and > 0",
        });
    }
    let motion = Motion::from_law(law, opts.samples)?;
    let a1 = motion.unit_centre_distance;
    let (c1, _) = motion.pitch_curves(a1, opts.samples)?;
    let l1 = c1.perimeter_mm(1e-12 * a1);
    let z = match (opts.teeth, law) {
        (Some(z), _) => z,
        (None, Law::Centrode(_)) => (l1 / (PI * m)).ceil() as u32,
        (None, _) => {
            return Err(PairError::InvalidParameter {
                name: "teeth",
                value: 0.0,
                expected: "a tooth count for a motion or table law",
            });
        }
    };
    if z < 3 {
        return Err(PairError::InvalidParameter {
            name: "teeth",
            value: f64::from(z),
            expected: "≥ 3",
        });
    }
    let a = a1 * f64::from(z) * PI * m / l1;
    let (c1, c2) = motion.pitch_curves(a, opts.samples)?;
    let f1 = ArcFrame::new(&c1);
    let f2 = ArcFrame::new(&c2);
    let p = f1.length_mm() / f64::from(z);
    // Driven phase: a space faces driver tooth 0 at body angle π + ψ(0).
    let th2 = (PI + motion.psi(0.0)).rem_euclid(TAU);
    let s2 = c2.arc_length_between_mm(0.0, th2, 1e-12 * a);
    let half = 0.5 * opts.backlash_mm;
    let mk = |phase: f64, tol: f64| OutlineOptions {
        phase_mm: phase,
        thin_left_mm: half,
        thin_right_mm: 0.0,
        chord_tol_mm: tol,
    };
    let o1 = mk(0.0, opts.chord_tol_mm);
    let o2 = mk(s2 + 0.5 * p, opts.chord_tol_mm);
    let driver = outline::generate_on(&f1, &opts.rack, z, m, &o1)?;
    let driven = outline::generate_on(&f2, &opts.rack, z, m, &o2)?;
    let mesh = if opts.verify_steps > 0 {
        let v1 = outline::generate_on(
            &f1,
            &opts.rack,
            z,
            m,
            &OutlineOptions {
                chord_tol_mm: opts.verify_chord_tol_mm,
                ..o1
            },
        )?;
        let v2 = outline::generate_on(
            &f2,
            &opts.rack,
            z,
            m,
            &OutlineOptions {
                chord_tol_mm: opts.verify_chord_tol_mm,
                ..o2
            },
        )?;
        let check = MeshCheck {
            centre_distance_mm: a,
            steps: opts.verify_steps,
            backlash_mm: opts.backlash_mm,
            module_mm: m,
            angle_tol_rad: 1e-13,
        };
        let psi = |phi: f64| motion.psi(phi);
        Some(verify_mesh(
            &v1.points_mm,
            &v2.points_mm,
            &psi,
            &check,
            progress,
        )?)
    } else {
        None
    };
    let ratios: Vec<f64> = uniform_angles(opts.samples)
        .iter()
        .map(|&f| motion.ratio(f))
        .collect();
    let pitch_poly = |c: &PitchCurve| {
        uniform_angles(720)
            .iter()
            .map(|&t| c.point_mm(t))
            .collect::<Vec<_>>()
    };
    Ok(PairDesign {
        centre_distance_mm: a,
        z,
        module_mm: m,
        perimeter_mm: f1.length_mm(),
        ratio_range: [
            ratios.iter().copied().fold(f64::INFINITY, f64::min),
            ratios.iter().copied().fold(0.0, f64::max),
        ],
        driver_undercut: driver.undercut.clone(),
        driven_undercut: driven.undercut.clone(),
        driver,
        driven,
        mesh,
        psi0_rad: motion.psi(0.0),
        driver_pitch_mm: pitch_poly(&c1),
        driven_pitch_mm: pitch_poly(&c2),
    })
}

impl PairDesign {
    /// The assembly sheet at φ = 0: driver at the origin, driven at `(a, 0)` rotated by ψ(0)
    /// (driven body angle π + ψ(0) faces the driver), layers `DRIVER_OUTLINE`, `DRIVER_PITCH`,
    /// `DRIVEN_OUTLINE`, `DRIVEN_PITCH`, `CENTRES`.
    #[must_use]
    pub fn assembly_sheet(&self) -> Sheet {
        let a = self.centre_distance_mm;
        let (s, c) = self.psi0_rad.sin_cos();
        let place = |v: &[[f64; 2]]| {
            v.iter()
                .map(|p| [c * p[0] + s * p[1] + a, -s * p[0] + c * p[1]])
                .collect::<Vec<_>>()
        };
        let contour = |name: &str, layer: &str, pts: Vec<[f64; 2]>| Contour {
            name: name.into(),
            layer: layer.into(),
            points_mm: pts,
            closed: true,
        };
        Sheet {
            contours: vec![
                contour(
                    "driver_outline",
                    "DRIVER_OUTLINE",
                    self.driver.points_mm.clone(),
                ),
                contour("driver_pitch", "DRIVER_PITCH", self.driver_pitch_mm.clone()),
                contour(
                    "driven_outline",
                    "DRIVEN_OUTLINE",
                    place(&self.driven.points_mm),
                ),
                contour("driven_pitch", "DRIVEN_PITCH", place(&self.driven_pitch_mm)),
            ],
            markers: vec![
                Marker {
                    name: "driver_centre".into(),
                    layer: "CENTRES".into(),
                    at_mm: [0.0, 0.0],
                },
                Marker {
                    name: "driven_centre".into(),
                    layer: "CENTRES".into(),
                    at_mm: [a, 0.0],
                },
            ],
        }
    }
}
