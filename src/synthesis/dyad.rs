//! Stage A of the synthesis: the dyad O–A–B (carrier axis, carrier arm, needle) through key poses.
//!
//! A pose k gives the needle tip `B_k` and the needle's direction `θ_k` (the world direction of
//! A → B). For a needle of length `l3` the planet axis is then
//!
//! ```text
//! A_k(l3) = B_k − l3·e(θ_k),      e(θ) = (cos θ, sin θ),
//! ```
//!
//! and the arm reaches every pose when all `A_k` lie on one circle about O, of radius `l1`:
//! `|A_k − O| = l1` (an RR dyad; Burmester's counting). With O free there are four unknowns
//! (O, l1, l3):
//!
//! - **three poses**: one circle through the three `A_k` for every `l3` — a one-parameter
//!   family ([`DyadSolutions::Family`], sampled over `l3`);
//! - **four poses**: the four `A_k` are concyclic where
//!   `det[|A_k|², A_k,x, A_k,y, 1] = 0`, a polynomial of degree ≤ 4 in `l3` (the first column is
//!   quadratic in `l3`, the next two linear): at most four arms, found as the sign changes of the
//!   determinant over a scan of `l3`, each refined to the accuracy asked for;
//! - **five or more**: least squares — the local minima over `l3` of the algebraic circle fit's
//!   geometric residual, each refined by Levenberg–Marquardt on the geometric residuals
//!   `r_k = |A_k(l3) − O| − l1` in `(O, l1, l3)`.
//!
//! With O fixed by the machine layout the unknowns are `(l1, l3)`: two poses suffice, more are
//! fitted the same way. Written by hand: it is the synthesis's own geometry (a 4×4 normal matrix).

use crate::math::Point;
use crate::math::least_squares::{LeastSquares, LmOptions, levenberg_marquardt};
use nalgebra::{DMatrix, DVector, Matrix3, Matrix4, Vector3};
use serde::{Deserialize, Serialize};

/// One key pose of the needle.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Pose {
    /// Needle tip B, mm.
    pub tip_mm: Point,
    /// World direction of the line planet axis A → tip B, rad (counter-clockwise from +x).
    pub needle_rad: f64,
}

impl Pose {
    /// The planet axis `A = B − l3·e(θ)` for a needle of `l3_mm`, mm.
    #[must_use]
    pub fn planet_axis(&self, l3_mm: f64) -> Point {
        Point::new(
            self.tip_mm.x - l3_mm * self.needle_rad.cos(),
            self.tip_mm.y - l3_mm * self.needle_rad.sin(),
        )
    }
}

/// An arm O–A–B: carrier axis, carrier arm, needle.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Dyad {
    /// Carrier axis O, mm.
    pub center_mm: Point,
    /// Carrier arm `l1 = |OA|`, mm.
    pub l1_mm: f64,
    /// Needle `l3 = |AB|`, mm.
    pub l3_mm: f64,
    /// Largest `| |A_k − O| − l1 |` over the poses, mm: 0 when the arm reaches every pose.
    pub max_residual_mm: f64,
}

impl Dyad {
    /// The dyad of needle `l3_mm` and circle (`center_mm`, `l1_mm`), its residual over `poses`.
    fn new(poses: &[Pose], center_mm: Point, l1_mm: f64, l3_mm: f64) -> Self {
        let max_residual_mm = poses
            .iter()
            .map(|p| {
                let a = p.planet_axis(l3_mm);
                (a.distance(center_mm) - l1_mm).abs()
            })
            .fold(0.0, f64::max);
        Self {
            center_mm,
            l1_mm,
            l3_mm,
            max_residual_mm,
        }
    }

    /// The carrier angle at each pose, `arg(A_k − O)`, rad in (−π, π].
    #[must_use]
    pub fn carrier_angles_rad(&self, poses: &[Pose]) -> Vec<f64> {
        poses
            .iter()
            .map(|p| {
                let a = p.planet_axis(self.l3_mm);
                (a - self.center_mm).atan2()
            })
            .collect()
    }
}

/// How the dyads are searched. (De)serialisable (a missing field takes its default, an unknown one is an error) and
/// built with `with_*`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct DyadOptions {
    /// Carrier axis fixed by the machine layout, mm; `None` (default): solved for.
    pub center_mm: Option<Point>,
    /// Longest needle searched, mm (default 1000: planting arms are well below a metre).
    pub max_l3_mm: f64,
    /// Needle lengths scanned over `(0, max_l3_mm]` (default 4000).
    pub samples: usize,
    /// Accuracy of a solution's `l3` and residual, mm (default 1e-9).
    pub accuracy_mm: f64,
}

crate::builder::with_fields!(DyadOptions {
    with_center_mm => center_mm: Option<Point>,
    with_max_l3_mm => max_l3_mm: f64,
    with_samples => samples: usize,
    with_accuracy_mm => accuracy_mm: f64,
});

impl Default for DyadOptions {
    fn default() -> Self {
        Self {
            center_mm: None,
            max_l3_mm: 1000.0,
            samples: 4000,
            accuracy_mm: 1e-9,
        }
    }
}

/// The arms through the poses.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum DyadSolutions {
    /// Finitely many arms, best (smallest residual) first: the exact ones of four poses, or the
    /// least-squares optima of more (or of O fixed).
    Finite(Vec<Dyad>),
    /// Three poses with O free: one arm per needle length, sampled in increasing `l3`.
    Family(Vec<Dyad>),
}

/// Why no dyad could be searched for.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum DyadError {
    /// Too few poses for the unknowns.
    #[error(
        "{given} pose(s) given; at least {needed} are needed {}",
        if *needed == 3 { "with the carrier axis free (or fix it: then two)" } else { "with the carrier axis fixed" }
    )]
    TooFewPoses {
        /// Poses given.
        given: usize,
        /// Poses needed.
        needed: usize,
    },
    /// A pose or an option is not a finite number.
    #[error("pose {index}: its tip and needle direction must be finite numbers")]
    NotFinite {
        /// Pose index (0-based).
        index: usize,
    },
    /// An option out of range.
    #[error("{field} = {value}: {expected}")]
    BadOption {
        /// Option name.
        field: &'static str,
        /// Value given.
        value: String,
        /// What is admissible.
        expected: &'static str,
    },
}

/// The dyads through `poses` (module documentation), best first.
///
/// ```
/// use ncgear::geometry::golden::g1_mechanism;
/// use ncgear::synthesis::{DyadOptions, DyadSolutions, Pose, solve_dyads};
/// // Five poses of the G1 train (l1 = 90 mm, l3 = 170 mm, O at the origin).
/// let g1 = g1_mechanism();
/// let poses: Vec<Pose> = [0.0f64, 72.0, 144.0, 216.0, 288.0]
///     .iter()
///     .map(|t| Pose { tip_mm: g1.tip(t.to_radians()), needle_rad: g1.needle_direction(t.to_radians()) })
///     .collect();
/// let DyadSolutions::Finite(arms) = solve_dyads(&poses, &DyadOptions::default())? else { panic!() };
/// let best = arms[0];
/// assert!((best.l1_mm - 90.0).abs() < 1e-6 && (best.l3_mm - 170.0).abs() < 1e-6);
/// assert!(best.center_mm.hypot() < 1e-6);
/// # Ok::<(), ncgear::synthesis::DyadError>(())
/// ```
///
/// Errors: [`DyadError`].
pub fn solve_dyads(poses: &[Pose], opts: &DyadOptions) -> Result<DyadSolutions, DyadError> {
    solve_dyads_weighted(poses, &vec![1.0; poses.len()], opts)
}

/// [`solve_dyads`] with pose k's geometric residual divided by `scales_mm[k]` (> 0) in the
/// least-squares refinement: an approximate pose given its position tolerance and an exact one a
/// small scale takes the misfit of over-determined poses onto the approximate ones. The scan
/// that finds the starts is unweighted.
///
/// Errors: [`DyadError`], and `BadOption` for scales that are not positive and finite, one per
/// pose.
pub fn solve_dyads_weighted(
    poses: &[Pose],
    scales_mm: &[f64],
    opts: &DyadOptions,
) -> Result<DyadSolutions, DyadError> {
    if scales_mm.len() != poses.len() || !scales_mm.iter().all(|w| *w > 0.0 && w.is_finite()) {
        return Err(DyadError::BadOption {
            field: "scales_mm",
            value: format!("{scales_mm:?}"),
            expected: "one positive finite scale per pose",
        });
    }
    if let Some(index) = poses
        .iter()
        .position(|p| !(p.tip_mm.is_finite() && p.needle_rad.is_finite()))
    {
        return Err(DyadError::NotFinite { index });
    }
    if !(opts.max_l3_mm > 0.0 && opts.max_l3_mm.is_finite()) {
        return Err(DyadError::BadOption {
            field: "max_l3_mm",
            value: opts.max_l3_mm.to_string(),
            expected: "a positive length in mm",
        });
    }
    if !(16..=1_000_000).contains(&opts.samples) {
        return Err(DyadError::BadOption {
            field: "samples",
            value: opts.samples.to_string(),
            expected: "16..=1000000 needle lengths",
        });
    }
    let needed = if opts.center_mm.is_some() { 2 } else { 3 };
    if poses.len() < needed {
        return Err(DyadError::TooFewPoses {
            given: poses.len(),
            needed,
        });
    }
    let step = opts.max_l3_mm / opts.samples as f64;
    let grid = (1..=opts.samples).map(|j| step * j as f64);
    if let Some(o) = opts.center_mm {
        // O fixed: the spread of the distances |A_k − O| is minimal at the arm.
        let spread = |l3: f64| circle_about(poses, o, l3).1;
        let starts = local_minima(grid.map(|l3| (l3, spread(l3))));
        return Ok(DyadSolutions::Finite(ranked(
            starts
                .into_iter()
                .map(|l3| {
                    refine(
                        poses,
                        scales_mm,
                        [o.x, o.y, circle_about(poses, o, l3).0, l3],
                        true,
                        opts,
                    )
                })
                .collect(),
            opts,
        )));
    }
    if poses.len() == 3 {
        let family = grid
            .filter_map(|l3| {
                let a: Vec<Point> = poses.iter().map(|p| p.planet_axis(l3)).collect();
                let (o, r) = circumcircle(a[0], a[1], a[2])?;
                Some(Dyad::new(poses, o, r, l3))
            })
            .collect();
        return Ok(DyadSolutions::Family(family));
    }
    let starts: Vec<f64> = if poses.len() == 4 {
        // The concyclicity determinant changes sign at each arm.
        let det = |l3: f64| concyclic_det(poses, l3);
        let samples: Vec<(f64, f64)> = grid.map(|l3| (l3, det(l3))).collect();
        samples
            .windows(2)
            .filter(|w| w[0].1 == 0.0 || w[0].1.signum() != w[1].1.signum())
            .map(|w| bisect(&det, w[0].0, w[1].0, opts.accuracy_mm))
            .collect()
    } else {
        local_minima(grid.map(|l3| (l3, kasa(poses, l3).map_or(f64::INFINITY, |c| c.2))))
    };
    let dyads = starts
        .into_iter()
        .filter_map(|l3| {
            let (o, r, _) = kasa(poses, l3)?;
            Some(refine(poses, scales_mm, [o.x, o.y, r, l3], false, opts))
        })
        .collect();
    Ok(DyadSolutions::Finite(ranked(dyads, opts)))
}

/// `dyads` within the search, duplicates (same `l3` to 1e-6 mm) removed, best first.
fn ranked(mut dyads: Vec<Dyad>, opts: &DyadOptions) -> Vec<Dyad> {
    dyads.retain(|d| {
        d.l3_mm > 0.0 && d.l3_mm <= opts.max_l3_mm && d.l1_mm > 0.0 && d.max_residual_mm.is_finite()
    });
    dyads.sort_by(|a, b| a.max_residual_mm.total_cmp(&b.max_residual_mm));
    let mut out: Vec<Dyad> = Vec::new();
    for d in dyads {
        if out.iter().all(|k| (k.l3_mm - d.l3_mm).abs() > 1e-6) {
            out.push(d);
        }
    }
    out
}

/// `det[|A_k|², A_k,x, A_k,y, 1]` of the first four poses' planet axes at needle `l3`, scaled by
/// the points' size so that its sign is meaningful at any scale.
fn concyclic_det(poses: &[Pose], l3: f64) -> f64 {
    let a: Vec<Point> = poses.iter().take(4).map(|p| p.planet_axis(l3)).collect();
    let c = [
        a.iter().map(|p| p.x).sum::<f64>() / 4.0,
        a.iter().map(|p| p.y).sum::<f64>() / 4.0,
    ];
    let s = a
        .iter()
        .map(|p| (p.x - c[0]).hypot(p.y - c[1]))
        .fold(1e-300, f64::max);
    let m = Matrix4::from_fn(|i, j| {
        let (x, y) = ((a[i].x - c[0]) / s, (a[i].y - c[1]) / s);
        [x * x + y * y, x, y, 1.0][j]
    });
    m.determinant()
}

/// The algebraic (Kåsa) circle through the planet axes at needle `l3`: centre, radius and the
/// RMS geometric residual; `None` when they are collinear.
fn kasa(poses: &[Pose], l3: f64) -> Option<(Point, f64, f64)> {
    let a: Vec<Point> = poses.iter().map(|p| p.planet_axis(l3)).collect();
    let (mut n, mut b) = (Matrix3::zeros(), Vector3::zeros());
    for p in &a {
        let row = Vector3::new(p.x, p.y, 1.0);
        n += row * row.transpose();
        b -= row * (p.dot(*p));
    }
    let s = n.try_inverse()? * b;
    let o = Point::new(-0.5 * s[0], -0.5 * s[1]);
    let r2 = o.norm_squared() - s[2];
    if !(r2 > 0.0 && r2.is_finite()) {
        return None;
    }
    let r = r2.sqrt();
    let rms = (a.iter().map(|p| (p.distance(o) - r).powi(2)).sum::<f64>() / a.len() as f64).sqrt();
    Some((o, r, rms))
}

/// Mean distance of the planet axes from `o` at needle `l3`, and their RMS spread about it.
fn circle_about(poses: &[Pose], o: Point, l3: f64) -> (f64, f64) {
    let d: Vec<f64> = poses
        .iter()
        .map(|p| {
            let a = p.planet_axis(l3);
            a.distance(o)
        })
        .collect();
    let mean = d.iter().sum::<f64>() / d.len() as f64;
    let var = d.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / d.len() as f64;
    (mean, var.sqrt())
}

/// The circle through three points, `None` when they are (nearly) collinear.
fn circumcircle(a: Point, b: Point, c: Point) -> Option<(Point, f64)> {
    let (bx, by, cx, cy) = (b.x - a.x, b.y - a.y, c.x - a.x, c.y - a.y);
    let d = 2.0 * (bx * cy - by * cx);
    let scale = (bx * bx + by * by).max(cx * cx + cy * cy);
    if d.abs() <= 1e-12 * scale {
        return None;
    }
    let (b2, c2) = (bx * bx + by * by, cx * cx + cy * cy);
    let ux = (cy * b2 - by * c2) / d;
    let uy = (bx * c2 - cx * b2) / d;
    Some((Point::new(a.x + ux, a.y + uy), ux.hypot(uy)))
}

/// The `x` of the local minima of sampled `(x, f(x))` (interior samples no larger than both
/// neighbours, and finite).
fn local_minima(samples: impl Iterator<Item = (f64, f64)>) -> Vec<f64> {
    let s: Vec<(f64, f64)> = samples.collect();
    s.windows(3)
        .filter(|w| w[1].1.is_finite() && w[1].1 <= w[0].1 && w[1].1 <= w[2].1)
        .map(|w| w[1].0)
        .collect()
}

/// A root of `f` in `[lo, hi]` (a sign change) to `tol`.
fn bisect(f: &dyn Fn(f64) -> f64, mut lo: f64, mut hi: f64, tol: f64) -> f64 {
    let mut flo = f(lo);
    for _ in 0..200 {
        if hi - lo <= tol {
            break;
        }
        let mid = 0.5 * (lo + hi);
        let fm = f(mid);
        if fm == 0.0 {
            return mid;
        }
        if fm.signum() == flo.signum() {
            (lo, flo) = (mid, fm);
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The arm's least squares: the geometric residuals `r_k = (|A_k(l3) − O| − l1) / s_k` of
/// `x = [Ox, Oy, l1, l3]`, with their Jacobian; with `center_fixed` O has none (it stays).
struct ArmResiduals<'a> {
    poses: &'a [Pose],
    scales_mm: &'a [f64],
    center_fixed: bool,
}

impl ArmResiduals<'_> {
    /// Pose `p`'s residual and its gradient in `x`, each over the pose's scale `s`, mm.
    fn row(&self, p: &Pose, s: f64, x: &[f64]) -> (f64, [f64; 4]) {
        let a = p.planet_axis(x[3]);
        let d = [a.x - x[0], a.y - x[1]];
        let n = d[0].hypot(d[1]).max(1e-300);
        let u = [d[0] / n, d[1] / n];
        let e = [p.needle_rad.cos(), p.needle_rad.sin()];
        let along = -(u[0] * e[0] + u[1] * e[1]);
        let row = if self.center_fixed {
            [0.0, 0.0, -1.0, along]
        } else {
            [-u[0], -u[1], -1.0, along]
        };
        ((n - x[2]) / s, row.map(|v| v / s))
    }
}

impl LeastSquares for ArmResiduals<'_> {
    fn residuals(&self, x: &[f64]) -> Option<DVector<f64>> {
        let rows = self.poses.iter().zip(self.scales_mm);
        Some(DVector::from_iterator(
            self.poses.len(),
            rows.map(|(p, &s)| self.row(p, s, x).0),
        ))
    }

    fn jacobian(&self, x: &[f64], _r: &DVector<f64>) -> Option<DMatrix<f64>> {
        let mut j = DMatrix::zeros(self.poses.len(), 4);
        for (k, (p, &s)) in self.poses.iter().zip(self.scales_mm).enumerate() {
            for (c, v) in self.row(p, s, x).1.into_iter().enumerate() {
                j[(k, c)] = v;
            }
        }
        Some(j)
    }
}

/// Levenberg–Marquardt ([`levenberg_marquardt()`]) on the arm's geometric residuals from
/// `x = [Ox, Oy, l1, l3]`; with `center_fixed` O stays. Stops at a step of `opts.accuracy_mm`.
fn refine(
    poses: &[Pose],
    scales_mm: &[f64],
    x: [f64; 4],
    center_fixed: bool,
    opts: &DyadOptions,
) -> Dyad {
    let problem = ArmResiduals {
        poses,
        scales_mm,
        center_fixed,
    };
    let lm = LmOptions::default()
        .with_initial_damping(1e-6)
        .with_min_damping(1e-12)
        .with_max_damping_steps(20)
        .with_step_tol(opts.accuracy_mm);
    let x = levenberg_marquardt(&problem, x.to_vec(), &lm);
    Dyad::new(poses, Point::new(x[0], x[1]), x[2], x[3])
}
