//! Mesh verification of two toothed outlines: roll them through a full cycle of the motion law
//! and measure interference, backlash and transmission error (issue 3, "Verification").
//!
//! Setup: driver (gear 1) centre at the origin, rotated CCW by φ; driven (gear 2) centre at
//! `(a, 0)`, rotated CW by `ψ(φ) + δ` (so its body angle `π + ψ` faces the driver). The clearance of
//! a vertex of one outline against the other is its signed distance to the other polyline
//! (negative inside; exact within `cap = 0.02·m` via a segment grid, clipped to `±cap` beyond).
//! `f(δ)` is the minimum clearance over both outlines' vertices near the contact. Per φ:
//! - working contact `ε(φ)`: the root of `f` with the working (larger-s) flanks touching; the
//!   transmission error is `ε(φ)` (rad) — the driven angle error of the toothed pair;
//! - coast contact `δc(φ)`: the other root; backlash on the pitch curve `(δc − ε)·r₂`, mm;
//! - interference: `f < 0` for every δ (no free position), or penetration at `ε`.
use super::overlap::{Rigid, inside_term};
use rayon::prelude::*;
use serde::Serialize;
use std::f64::consts::{PI, TAU};

/// Errors of mesh verification.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MeshError {
    /// An outline is not star-shaped about its centre (polar angle not increasing).
    #[error("outline `{which}` is not star-shaped about its centre (vertex {index})")]
    NotStarShaped {
        /// Which outline.
        which: &'static str,
        /// First vertex where the polar angle decreases.
        index: usize,
    },
    /// Bad parameter.
    #[error("invalid mesh parameter `{name}` = {value}: {expected}")]
    InvalidParameter {
        /// Name.
        name: &'static str,
        /// Value.
        value: f64,
        /// Expectation.
        expected: &'static str,
    },
}

/// A star-shaped closed outline in polar form, for fast point-inside tests.
#[derive(Debug, Clone)]
pub struct StarShape {
    theta: Vec<f64>,
    r: Vec<f64>,
}

impl StarShape {
    /// From a CCW closed polyline (mm) about the origin. Vertices are sorted by polar angle; a
    /// polyline whose polar angle folds back slightly (flank bottoms of non-circular gears) is
    /// accepted — the radial test is then only a coarse inside/outside sign far from the fold.
    pub fn new(points_mm: &[[f64; 2]], which: &'static str) -> Result<Self, MeshError> {
        if points_mm.len() < 3 {
            return Err(MeshError::NotStarShaped {
                which,
                index: points_mm.len(),
            });
        }
        let mut tr: Vec<(f64, f64)> = points_mm
            .iter()
            .map(|p| (p[1].atan2(p[0]), p[0].hypot(p[1])))
            .collect();
        tr.sort_by(|a, b| a.0.total_cmp(&b.0));
        tr.dedup_by(|a, b| a.0 <= b.0);
        Ok(Self {
            theta: tr.iter().map(|v| v.0).collect(),
            r: tr.iter().map(|v| v.1).collect(),
        })
    }

    /// Boundary radius at polar angle `t` (rad), mm.
    #[must_use]
    pub fn radius_at(&self, t: f64) -> f64 {
        let t0 = self.theta[0];
        let x = t0 + (t - t0).rem_euclid(TAU);
        let n = self.theta.len();
        let j = self.theta.partition_point(|&v| v <= x);
        let (ta, ra, tb, rb) = if j == 0 || j == n {
            (
                self.theta[n - 1] - if j == 0 { TAU } else { 0.0 },
                self.r[n - 1],
                self.theta[0] + if j == n { TAU } else { 0.0 },
                self.r[0],
            )
        } else {
            (self.theta[j - 1], self.r[j - 1], self.theta[j], self.r[j])
        };
        ra + (rb - ra) * (x - ta) / (tb - ta)
    }

    /// Indices of the vertices with polar angle within `half_width` of `t`.
    fn window(&self, t: f64, half_width: f64) -> Vec<usize> {
        let t0 = self.theta[0];
        let n = self.theta.len();
        let lo = t0 + (t - half_width - t0).rem_euclid(TAU);
        let hi = lo + 2.0 * half_width;
        let mut out = Vec::new();
        let a = self.theta.partition_point(|&v| v < lo);
        let mut j = a;
        while j < n && self.theta[j] <= hi {
            out.push(j);
            j += 1;
        }
        if hi > t0 + TAU {
            let hi2 = hi - TAU;
            let mut j = 0;
            while j < a && self.theta[j] <= hi2 {
                out.push(j);
                j += 1;
            }
        }
        out
    }

    fn point(&self, i: usize) -> [f64; 2] {
        let (s, c) = self.theta[i].sin_cos();
        [self.r[i] * c, self.r[i] * s]
    }
}

/// Multiplicative hash for grid cells (the default SipHash dominated the profile).
#[derive(Debug, Clone, Copy, Default)]
pub struct FxBuild;

/// Hasher of [`FxBuild`].
#[derive(Debug, Clone, Copy, Default)]
pub struct FxHasher(u64);

impl std::hash::Hasher for FxHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.write_u64(u64::from(*b));
        }
    }
    fn write_i64(&mut self, v: i64) {
        self.write_u64(v as u64);
    }
    fn write_u64(&mut self, v: u64) {
        self.0 = (self.0.rotate_left(5) ^ v).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
}

impl std::hash::BuildHasher for FxBuild {
    type Hasher = FxHasher;
    fn build_hasher(&self) -> FxHasher {
        FxHasher(0)
    }
}

/// A closed CCW polyline with a uniform-grid segment index for signed distances near the
/// boundary, and a polar table for the coarse inside/outside sign away from it.
#[derive(Debug, Clone)]
pub struct Shape {
    pts: Vec<[f64; 2]>,
    polar: StarShape,
    bands: super::inside::Bands,
    cell: f64,
    grid: std::collections::HashMap<(i64, i64), Vec<u32>, FxBuild>,
    /// Polar angle of each vertex of `pts`, rad.
    ang: Vec<f64>,
}

impl Shape {
    /// Indexes `points_mm` with grid cell `cap_mm` (the largest distance reported exactly).
    pub fn new(
        points_mm: &[[f64; 2]],
        cap_mm: f64,
        which: &'static str,
    ) -> Result<Self, MeshError> {
        let polar = StarShape::new(points_mm, which)?;
        let n = points_mm.len();
        let mut grid: std::collections::HashMap<(i64, i64), Vec<u32>, FxBuild> =
            std::collections::HashMap::default();
        for i in 0..n {
            let (a, b) = (points_mm[i], points_mm[(i + 1) % n]);
            let (x0, x1) = (
                (a[0].min(b[0]) / cap_mm).floor() as i64,
                (a[0].max(b[0]) / cap_mm).floor() as i64,
            );
            let (y0, y1) = (
                (a[1].min(b[1]) / cap_mm).floor() as i64,
                (a[1].max(b[1]) / cap_mm).floor() as i64,
            );
            for cx in x0..=x1 {
                for cy in y0..=y1 {
                    grid.entry((cx, cy)).or_default().push(i as u32);
                }
            }
        }
        Ok(Self {
            pts: points_mm.to_vec(),
            polar,
            bands: super::inside::Bands::new(points_mm, cap_mm),
            cell: cap_mm,
            grid,
            ang: points_mm.iter().map(|p| p[1].atan2(p[0])).collect(),
        })
    }

    /// The outline's vertices (body frame, mm), in order.
    pub(crate) fn points(&self) -> &[[f64; 2]] {
        &self.pts
    }

    /// Start indices of the edges `i → i+1` whose both ends have a polar angle within
    /// `half_width` (rad) of `t` (in polyline order, so they form chains).
    pub(crate) fn window_edges(&self, t: f64, half_width: f64) -> Vec<usize> {
        let n = self.pts.len();
        let within = |i: usize| ((self.ang[i] - t + PI).rem_euclid(TAU) - PI).abs() <= half_width;
        (0..n)
            .filter(|&i| within(i) && within((i + 1) % n))
            .collect()
    }

    /// Indices of the segments listed in the grid cells that the box of `p`–`q` touches
    /// (sorted, without repeats) into `out`.
    pub(crate) fn segments_near(&self, p: [f64; 2], q: [f64; 2], out: &mut Vec<u32>) {
        out.clear();
        let cell = |v: f64| (v / self.cell).floor() as i64;
        let (x0, x1) = (cell(p[0].min(q[0])), cell(p[0].max(q[0])));
        let (y0, y1) = (cell(p[1].min(q[1])), cell(p[1].max(q[1])));
        let boxed = (x1 - x0 + 1).saturating_mul(y1 - y0 + 1);
        if boxed > self.grid.len() as i64 {
            // A long edge over a fine grid: scan the occupied cells instead of the box.
            for (&(gx, gy), list) in &self.grid {
                if (x0..=x1).contains(&gx) && (y0..=y1).contains(&gy) {
                    out.extend_from_slice(list);
                }
            }
        } else {
            for gx in x0..=x1 {
                for gy in y0..=y1 {
                    if let Some(list) = self.grid.get(&(gx, gy)) {
                        out.extend_from_slice(list);
                    }
                }
            }
        }
        out.sort_unstable();
        out.dedup();
    }

    /// Signed clearance of `x` (body frame, mm): distance to the outline, negative inside;
    /// clipped to `±cap`.
    #[must_use]
    pub fn clearance(&self, x: [f64; 2]) -> f64 {
        let n = self.pts.len();
        let (cx, cy) = (
            (x[0] / self.cell).floor() as i64,
            (x[1] / self.cell).floor() as i64,
        );
        // Squared distances; one square root at the end.
        let mut best = (f64::INFINITY, 0usize, 0.5);
        for gx in cx - 1..=cx + 1 {
            for gy in cy - 1..=cy + 1 {
                if let Some(list) = self.grid.get(&(gx, gy)) {
                    for &i in list {
                        let (a, b) = (self.pts[i as usize], self.pts[(i as usize + 1) % n]);
                        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
                        let (px, py) = (x[0] - a[0], x[1] - a[1]);
                        let t = ((px * dx + py * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
                        let (ex, ey) = (px - t * dx, py - t * dy);
                        let d2 = ex * ex + ey * ey;
                        if d2 < best.0 {
                            best = (d2, i as usize, t);
                        }
                    }
                }
            }
        }
        let best = (best.0.sqrt(), best.1, best.2);
        if best.0 > self.cell {
            // Far from the boundary: the exact crossing rule (a polar test would misread the
            // pocket under a leaning, overhanging tooth).
            return if self.bands.contains(x) {
                -self.cell
            } else {
                self.cell
            };
        }
        let (d, i, t) = best;
        let left = |j: usize| {
            let (a, b) = (self.pts[j % n], self.pts[(j + 1) % n]);
            (b[0] - a[0]) * (x[1] - a[1]) - (b[1] - a[1]) * (x[0] - a[0]) > 0.0
        };
        let inside = if t > 0.0 && t < 1.0 {
            left(i)
        } else {
            // Closest point is a vertex v between edges e1 = (u→v) and e2 = (v→w).
            let v = if t >= 1.0 { (i + 1) % n } else { i };
            let prev = (v + n - 1) % n;
            let (u, vv, w) = (self.pts[prev], self.pts[v], self.pts[(v + 1) % n]);
            let convex = (vv[0] - u[0]) * (w[1] - vv[1]) - (vv[1] - u[1]) * (w[0] - vv[0]) > 0.0;
            if convex {
                left(prev) && left(v)
            } else {
                left(prev) || left(v)
            }
        };
        if inside { -d } else { d }
    }
}

/// Parameters of [`verify_mesh`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MeshCheck {
    /// Centre distance, mm.
    pub centre_distance_mm: f64,
    /// Number of driver positions over one turn.
    pub steps: usize,
    /// Nominal circumferential backlash of the pair on the pitch curve, mm (> 0).
    pub backlash_mm: f64,
    /// Module, mm (sets the contact window).
    pub module_mm: f64,
    /// Root-finding tolerance on δ, rad.
    pub angle_tol_rad: f64,
}

/// Result of [`verify_mesh`] (all over the sampled cycle).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MeshReport {
    /// Driver positions checked.
    pub steps: usize,
    /// Positions with interference (no contact-free position of the driven gear).
    pub interference_steps: usize,
    /// Largest penetration found at the working contact position, mm (0 = none).
    pub max_penetration_mm: f64,
    /// Minimum clearance at the nominal position (ψ from the law), mm; ≈ 0 at the working contact.
    pub min_nominal_clearance_mm: f64,
    /// Minimum backlash on the pitch curve over the cycle, mm.
    pub min_backlash_mm: f64,
    /// Maximum backlash on the pitch curve over the cycle, mm.
    pub max_backlash_mm: f64,
    /// Largest overlap (interference) area of the two outlines at the motion law's position
    /// (driven angle `ψ(φ)`, no correction), over the teeth within ±1.75 pitches of the contact,
    /// mm² (0 = the outlines do not overlap; ~1e-9 mm² is the transmission error's touch).
    pub max_overlap_area_mm2: f64,
    /// Driver angle of the largest overlap, degrees.
    pub max_overlap_at_deg: f64,
    /// Maximum |transmission error| of the driven gear, degrees.
    pub max_transmission_error_deg: f64,
    /// Peak-to-peak transmission error, degrees.
    pub transmission_error_p2p_deg: f64,
}

impl MeshReport {
    /// One-line human summary (interference, overlap, backlash range, transmission error).
    #[must_use]
    pub fn summary(&self) -> String {
        format!(
            "{} interference steps of {}, max overlap {:.3e} mm², backlash {:.4}..{:.4} mm, \
             max transmission error {:.2e}°",
            self.interference_steps,
            self.steps,
            self.max_overlap_area_mm2,
            self.min_backlash_mm,
            self.max_backlash_mm,
            self.max_transmission_error_deg
        )
    }
}

struct Sample {
    overlap: f64,
    eps: f64,
    coast: f64,
    nominal: f64,
    r2: f64,
    interference: bool,
    penetration: f64,
}

impl Sample {
    /// A position without a contact-free driven angle.
    fn interference(overlap: f64, nominal: f64, r2: f64, penetration: f64) -> Self {
        Self {
            overlap,
            eps: 0.0,
            coast: 0.0,
            nominal,
            r2,
            interference: true,
            penetration,
        }
    }
}

/// Rolls `driver` (gear 1) and `driven` (gear 2) outlines (mm, CCW, body frames) through one driver
/// turn with the motion law `psi(φ)` (driven CW rotation, rad; `psi(φ+2π) = psi(φ) + 2π`).
///
/// `progress(1)` is called after each driver position.
///
/// Complexity: O(steps · window vertices · root iterations); parallel over steps (rayon),
/// deterministic.
pub fn verify_mesh(
    driver: &[[f64; 2]],
    driven: &[[f64; 2]],
    psi: &(dyn Fn(f64) -> f64 + Sync),
    check: &MeshCheck,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<MeshReport, MeshError> {
    for (name, v) in [
        ("centre_distance_mm", check.centre_distance_mm),
        ("backlash_mm", check.backlash_mm),
        ("module_mm", check.module_mm),
        ("angle_tol_rad", check.angle_tol_rad),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(MeshError::InvalidParameter {
                name,
                value: v,
                expected: "finite and > 0",
            });
        }
    }
    if check.steps == 0 {
        return Err(MeshError::InvalidParameter {
            name: "steps",
            value: 0.0,
            expected: "≥ 1",
        });
    }
    let a = check.centre_distance_mm;
    let m = check.module_mm;
    let cap = 0.02 * m;
    let h1 = Shape::new(driver, cap, "driver")?;
    let h2 = Shape::new(driven, cap, "driven")?;
    let (g1, g2) = (&h1.polar, &h2.polar);
    // Coarse copies (every 16th vertex) index the initial pruning at a larger reach.
    let rmax = g1.r.iter().chain(g2.r.iter()).copied().fold(0.0, f64::max);
    let r2min = g2.r.iter().copied().fold(f64::INFINITY, f64::min).max(m);
    let lip = rmax + 2.0 * m;
    let reach = 4.0 * check.backlash_mm / r2min * lip + 0.05 * m;
    let coarse = |v: &[[f64; 2]]| v.iter().step_by(16).copied().collect::<Vec<_>>();
    let k1 = Shape::new(&coarse(driver), reach, "driver")?;
    let k2 = Shape::new(&coarse(driven), reach, "driven")?;
    let sample = |k: usize| {
        let phi = TAU * k as f64 / check.steps as f64;
        let psi0 = psi(phi);
        let r1 = g1.radius_at(-phi);
        let r2 = (a - r1).max(m);
        // Candidate vertices near the contact (±1.75 pitches).
        let w1 = (1.75 * PI * m / r1).min(PI);
        let w2 = (1.75 * PI * m / r2).min(PI);
        let c1 = g1.window(-phi, w1);
        let c2 = g2.window(PI + psi0, w2);
        // Per-vertex clearances at driven offset δ against shapes (s1 for gear-2 vertices in
        // the gear-1 frame, s2 for gear-1 vertices in the gear-2 frame).
        let eval = |delta: f64, set1: &[usize], set2: &[usize], s1: &Shape, s2: &Shape| {
            let ang2 = psi0 + delta;
            let (sn1, co1) = phi.sin_cos();
            let (sn2, co2) = ang2.sin_cos();
            let v2: Vec<f64> = set2
                .iter()
                .map(|&i| {
                    let b = g2.point(i);
                    let w = [co2 * b[0] + sn2 * b[1] + a, -sn2 * b[0] + co2 * b[1]];
                    s1.clearance([co1 * w[0] + sn1 * w[1], -sn1 * w[0] + co1 * w[1]])
                })
                .collect();
            let v1: Vec<f64> = set1
                .iter()
                .map(|&i| {
                    let b = g1.point(i);
                    let w = [co1 * b[0] - sn1 * b[1] - a, sn1 * b[0] + co1 * b[1]];
                    s2.clearance([co2 * w[0] - sn2 * w[1], sn2 * w[0] + co2 * w[1]])
                })
                .collect();
            (v1, v2)
        };
        // Overlap area at the law's position (δ = 0), in the world frame.
        let to_world1 = Rigid::new(phi, [0.0, 0.0]);
        let to_world2 = Rigid::new(-psi0, [a, 0.0]);
        let overlap = inside_term(
            &h1,
            &h1.window_edges(-phi, w1),
            &to_world2.inverse().after(&to_world1),
            &to_world1,
            &h2,
        ) + inside_term(
            &h2,
            &h2.window_edges(PI + psi0, w2),
            &to_world1.inverse().after(&to_world2),
            &to_world2,
            &h1,
        );
        let db = check.backlash_mm / r2;
        // Coarse pruning: every 16th window vertex against the coarse shapes, then the fine
        // vertices within ±16 of each kept coarse one (16 vertices span ≤ 0.1·m here).
        let d1: Vec<usize> = c1.iter().step_by(16).copied().collect();
        let d2: Vec<usize> = c2.iter().step_by(16).copied().collect();
        let (p1, p2) = eval(0.0, &d1, &d2, &k1, &k2);
        let expand = |c: &[usize], p: &[f64]| {
            let mut flag = vec![false; c.len()];
            for (j, v) in p.iter().enumerate() {
                if *v < reach + 0.1 * m {
                    let lo = (j * 16).saturating_sub(16);
                    let hi = (j * 16 + 17).min(c.len());
                    flag[lo..hi].iter_mut().for_each(|f| *f = true);
                }
            }
            c.iter()
                .zip(flag)
                .filter(|(_, f)| *f)
                .map(|(i, _)| *i)
                .collect::<Vec<usize>>()
        };
        let keep1 = expand(&c1, &p1);
        let keep2 = expand(&c2, &p2);
        let fmin = |v: &(Vec<f64>, Vec<f64>)| {
            v.0.iter()
                .chain(v.1.iter())
                .copied()
                .fold(f64::INFINITY, f64::min)
        };
        let f = |d: f64, s1: &[usize], s2: &[usize]| eval(d, s1, s2, &h1, &h2);
        let nominal = fmin(&f(0.0, &keep1, &keep2));
        let mid = 0.5 * db;
        let fmid = fmin(&f(mid, &keep1, &keep2));
        if fmid <= 0.0 {
            return Sample::interference(overlap, nominal, r2, -fmid);
        }
        let eps = root_pruned(&f, &keep1, &keep2, -db, mid, lip, check.angle_tol_rad);
        let coast = root_pruned(&f, &keep1, &keep2, mid, 3.0 * db, lip, check.angle_tol_rad);
        let (eps, coast) = match (eps, coast) {
            (Some(e), Some(c)) => (e, c),
            _ => {
                return Sample::interference(overlap, nominal, r2, 0.0);
            }
        };
        Sample {
            overlap,
            eps,
            coast,
            nominal,
            r2,
            interference: false,
            penetration: 0.0,
        }
    };
    let samples: Vec<Sample> = (0..check.steps)
        .into_par_iter()
        .map(|k| {
            let s = sample(k);
            progress(1);
            s
        })
        .collect();
    let ok: Vec<&Sample> = samples.iter().filter(|s| !s.interference).collect();
    let te: Vec<f64> = ok.iter().map(|s| s.eps).collect();
    let bl: Vec<f64> = ok.iter().map(|s| (s.coast - s.eps) * s.r2).collect();
    let max = |v: &[f64]| v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let min = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
    let (k_max, max_overlap) = samples
        .iter()
        .enumerate()
        .fold((0, 0.0f64), |(kb, vb), (k, s)| {
            if s.overlap > vb {
                (k, s.overlap)
            } else {
                (kb, vb)
            }
        });
    Ok(MeshReport {
        steps: check.steps,
        max_overlap_area_mm2: max_overlap,
        max_overlap_at_deg: 360.0 * k_max as f64 / check.steps as f64,
        interference_steps: samples.len() - ok.len(),
        max_penetration_mm: samples.iter().map(|s| s.penetration).fold(0.0, f64::max),
        min_nominal_clearance_mm: samples
            .iter()
            .map(|s| s.nominal)
            .fold(f64::INFINITY, f64::min),
        min_backlash_mm: min(&bl),
        max_backlash_mm: max(&bl),
        max_transmission_error_deg: te.iter().fold(0.0f64, |a, e| a.max(e.abs())).to_degrees(),
        transmission_error_p2p_deg: (max(&te) - min(&te)).max(0.0).to_degrees(),
    })
}

type PerVertex = (Vec<f64>, Vec<f64>);

/// Root of the minimum clearance on `[lo, hi]` (Illinois regula falsi), to `tol`, pruning after
/// each evaluation the vertices that cannot be the minimiser anywhere in the bracket: a vertex's
/// clearance changes by at most `lip·|Δδ|`, so it is dropped when `c_i(x) > min c(x) + 2·lip·(hi − lo)`.
#[allow(clippy::too_many_arguments)]
fn root_pruned(
    f: &dyn Fn(f64, &[usize], &[usize]) -> PerVertex,
    k1: &[usize],
    k2: &[usize],
    mut lo: f64,
    mut hi: f64,
    lip: f64,
    tol: f64,
) -> Option<f64> {
    let mut s1 = k1.to_vec();
    let mut s2 = k2.to_vec();
    let min = |v: &PerVertex| {
        v.0.iter()
            .chain(v.1.iter())
            .copied()
            .fold(f64::INFINITY, f64::min)
    };
    let (mut flo, mut fhi) = (min(&f(lo, &s1, &s2)), min(&f(hi, &s1, &s2)));
    if flo * fhi > 0.0 {
        return None;
    }
    let mut side = 0i8;
    for _ in 0..100 {
        let x = (lo * fhi - hi * flo) / (fhi - flo);
        let x = if x.is_finite() && x > lo && x < hi {
            x
        } else {
            0.5 * (lo + hi)
        };
        let v = f(x, &s1, &s2);
        let fx = min(&v);
        if fx * fhi > 0.0 {
            hi = x;
            fhi = fx;
            if side == 1 {
                flo *= 0.5;
            }
            side = 1;
        } else {
            lo = x;
            flo = fx;
            if side == -1 {
                fhi *= 0.5;
            }
            side = -1;
        }
        if hi - lo <= tol || fx.abs() <= 1e-11 {
            return Some(x);
        }
        let thresh = fx + 2.0 * lip * (hi - lo);
        s1 = s1
            .iter()
            .zip(&v.0)
            .filter(|(_, c)| **c <= thresh)
            .map(|(i, _)| *i)
            .collect();
        s2 = s2
            .iter()
            .zip(&v.1)
            .filter(|(_, c)| **c <= thresh)
            .map(|(i, _)| *i)
            .collect();
    }
    Some(0.5 * (lo + hi))
}
