//! The Levenberg–Marquardt solver of the fit: residual rows (point distances, coverage, ratio
//! bounds, smoothness), Marquardt-scaled damped steps, every trial made admissible before it is
//! judged.

use super::FitOptions;
use super::curve::{TipEval, coverage, curve_evals, normal_residual, point_row, project_near};
use crate::geometry::fourier::SunRatio;
use crate::geometry::limits::{PROJECTION_MARGIN, constraint_gradients, constraint_values};
use crate::geometry::mechanism::Mechanism;
use crate::geometry::perimeter::{unit_perimeter, unit_perimeter_gradient};
use crate::math::Point;
use crate::math::polyline::SegmentGrid;
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;
use std::f64::consts::TAU;

/// Parameters ↔ mechanism: `[a, l3, γ, φ_ref, a_1..a_K, b_1..b_K]`, and the idler offset ε
/// last when it is free (`free_offset`).
pub(super) fn to_params(m: &Mechanism, free_offset: bool) -> Vec<f64> {
    let mut p = vec![m.a_mm, m.l3_mm, m.needle_angle_rad, m.sun_phase_rad];
    p.extend_from_slice(m.ratio.cos_coefficients());
    p.extend_from_slice(m.ratio.sin_coefficients());
    if free_offset {
        p.push(m.idler_offset_rad);
    }
    p
}

/// The mechanism of parameters `p` at order `k` ([`to_params`]); ε is `p`'s last entry when it
/// has one, else `fixed_offset_rad`.
pub(super) fn from_params(p: &[f64], k: usize, fixed_offset_rad: f64) -> Mechanism {
    Mechanism {
        a_mm: p[0],
        l3_mm: p[1],
        needle_angle_rad: p[2],
        sun_phase_rad: p[3],
        ratio: SunRatio::new_unchecked(p[4..4 + k].to_vec(), p[4 + k..4 + 2 * k].to_vec()),
        idler_offset_rad: p.get(4 + 2 * k).copied().unwrap_or(fixed_offset_rad),
    }
}

/// The same ratio at order `k` (truncated or padded with zeros).
pub(super) fn with_order(m: &Mechanism, k: usize) -> Mechanism {
    Mechanism {
        ratio: m.ratio.with_order(k),
        ..m.clone()
    }
}

/// Angles at which the limit penalty is sampled.
const LIMIT_SAMPLES: usize = 512;

/// Constraint values per angle ([`constraint_values`]).
const LIMIT_ROWS: usize = 7;

/// Relative margin at which the limit penalty starts: a little inside the projection's.
const PENALTY_MARGIN: f64 = 3.0 * PROJECTION_MARGIN;

/// Carrier angles at which the traced curve is held to the target (coverage rows).
pub(super) const COVERAGE_SAMPLES: usize = 256;

/// A limit-penalty row in force at one evaluation.
struct ActiveLimit {
    /// Row within the limit block (`sample·LIMIT_ROWS + constraint`).
    row: usize,
    /// Sample angle, rad.
    theta: f64,
    /// The ratio's `[i, i′, i″]` there.
    values: [f64; 3],
    /// The constraint value (negative: inside the penalty margin or beyond).
    value: f64,
}

/// What the Jacobian of one evaluation needs: each point's projection and normal, each coverage
/// sample with its residual and direction, the limit rows in force.
struct Linearisation {
    points: Vec<(TipEval, Point)>,
    coverage: Vec<(TipEval, f64, Point)>,
    active: Vec<ActiveLimit>,
}

pub(super) struct Lm<'a> {
    pub(super) pts: &'a [Point],
    pub(super) k: usize,
    pub(super) opts: &'a FitOptions,
    /// Square roots of per-point weights (IRLS towards the minimax fit), or all ones.
    pub(super) weights: Option<&'a [f64]>,
    /// The segments of `pts` (the target polyline of the coverage rows), bucketed once.
    pub(super) grid: &'a SegmentGrid<'a>,
    /// Square roots of the coverage samples' weights (IRLS towards the minimax fit): each row is
    /// then its sample's whole distance from the target, weighted, as in the Hausdorff distance
    /// the minimax lowers. `None`: the distance beyond the chord allowance
    /// ([`super::curve::CoverageSample::excess_mm`]), unweighted.
    pub(super) coverage_weights: Option<&'a [f64]>,
}

impl Lm<'_> {
    /// Parameters of the fit: `4 + 2K`, and ε when it is free.
    fn n_params(&self) -> usize {
        4 + 2 * self.k + usize::from(self.opts.free_idler_offset)
    }

    fn n_rows(&self) -> usize {
        self.pts.len() + COVERAGE_SAMPLES + LIMIT_SAMPLES * LIMIT_ROWS + 2 * self.k
    }

    /// Residuals at `m` (points projected from `phis`, updated in place), with what their
    /// Jacobian needs ([`Self::jacobian`], asked for only where a step is accepted: three trials
    /// in four are rejected, and their rows would be thrown away).
    ///
    /// `near`: the evaluation this one is a trial step from (its contact angles start the
    /// projections' first solves).
    fn evaluate(
        &self,
        m: &Mechanism,
        phis: &mut [f64],
        near: Option<&Linearisation>,
    ) -> (DVector<f64>, Linearisation) {
        let mut r = DVector::zeros(self.n_rows());
        let guess = |idx: usize| near.map_or(f64::NAN, |l| l.points[idx].0.s);
        let projected: Vec<(f64, f64, TipEval, Point)> = self
            .pts
            .par_iter()
            .zip(phis.par_iter())
            .enumerate()
            .map(|(idx, (p, &phi0))| {
                let (phi, e) = project_near(m, *p, phi0, guess(idx));
                let (d, n) = normal_residual(&e, *p);
                (phi, d, e, n)
            })
            .collect();
        let mut points = Vec::with_capacity(projected.len());
        for (idx, (phi, d, e, n)) in projected.into_iter().enumerate() {
            phis[idx] = phi;
            r[idx] = self.weight(idx) * d;
            points.push((e, n));
        }
        // Coverage: the traced curve may not leave the target where no point watches it (a
        // one-sided point-to-curve fit would allow a loop between two points).
        let m0 = self.pts.len();
        let coverage: Vec<(TipEval, f64, Point)> = curve_evals(m, COVERAGE_SAMPLES)
            .into_par_iter()
            .enumerate()
            .map(|(i, e)| {
                let c = coverage(self.grid, &e);
                let r = match self.coverage_weights {
                    Some(w) => w[i] * c.distance_mm,
                    None => c.excess_mm(),
                };
                (e, r, c.direction)
            })
            .collect();
        for (i, (_, ri, _)) in coverage.iter().enumerate() {
            r[m0 + i] = *ri;
        }
        let m0 = m0 + COVERAGE_SAMPLES;
        // Limit penalty: w·max(0, −g) for each constraint value g of the gear limits (ratio
        // bounds, pressure angle, concave radius) at LIMIT_SAMPLES angles, active a little inside
        // the limits so the projection of the trials rarely has to act.
        let w = self.limit_weight(m);
        let limits = &self.opts.limits;
        let active: Vec<ActiveLimit> = (0..LIMIT_SAMPLES)
            .into_par_iter()
            .flat_map_iter(|b| {
                let th = TAU * b as f64 / LIMIT_SAMPLES as f64;
                let v = m.ratio.eval3(th);
                let g = constraint_values(limits, v, m.a_mm, PENALTY_MARGIN);
                (0..LIMIT_ROWS)
                    .filter(move |&c| g[c] < 0.0)
                    .map(move |c| ActiveLimit {
                        row: b * LIMIT_ROWS + c,
                        theta: th,
                        values: v,
                        value: g[c],
                    })
            })
            .collect();
        for a in &active {
            r[m0 + a.row] = -w * a.value;
        }
        // Smoothness: √λ·l3·k²·(a_k, b_k).
        let (ca, cb) = (m.ratio.cos_coefficients(), m.ratio.sin_coefficients());
        for kk in 0..self.k {
            let (row, h) = self.smoothness_row(m, kk);
            r[row] = h * ca[kk];
            r[row + 1] = h * cb[kk];
        }
        let lin = Linearisation {
            points,
            coverage,
            active,
        };
        (r, lin)
    }

    /// Square root of point `idx`'s weight (1 without weights).
    fn weight(&self, idx: usize) -> f64 {
        self.weights.map_or(1.0, |w| w[idx])
    }

    /// The first of the two smoothness rows of harmonic `kk + 1` and its weight `√λ·l3·k²`.
    fn smoothness_row(&self, m: &Mechanism, kk: usize) -> (usize, f64) {
        let ws = self.opts.smoothness * m.l3_mm.abs();
        let row = self.pts.len() + COVERAGE_SAMPLES + LIMIT_SAMPLES * LIMIT_ROWS + 2 * kk;
        (row, ((kk + 1) * (kk + 1)) as f64 * ws)
    }

    /// Weight of the limit-penalty rows, `10·l3` (mm per unit of constraint value).
    fn limit_weight(&self, m: &Mechanism) -> f64 {
        10.0 * m.l3_mm.abs().max(1.0)
    }

    /// The Jacobian of [`Self::evaluate`]'s residuals at `m` into `j` (every row rewritten).
    fn jacobian(&self, m: &Mechanism, lin: &Linearisation, j: &mut DMatrix<f64>) {
        let k = self.k;
        let np = self.n_params();
        let point_rows: Vec<Vec<f64>> = lin
            .points
            .par_iter()
            .enumerate()
            .map(|(idx, (e, n))| {
                let mut row = vec![0.0; np];
                point_row(m, e, *n, &mut row);
                let w = self.weight(idx);
                row.iter_mut().for_each(|v| *v *= w);
                row
            })
            .collect();
        let coverage_rows: Vec<Vec<f64>> = lin
            .coverage
            .par_iter()
            .enumerate()
            .map(|(i, (e, ri, u))| {
                let mut row = vec![0.0; np];
                if *ri > 0.0 {
                    point_row(m, e, -*u, &mut row);
                    let w = self.coverage_weights.map_or(1.0, |w| w[i]);
                    row.iter_mut().for_each(|v| *v *= w);
                }
                row
            })
            .collect();
        for (i, row) in point_rows.into_iter().chain(coverage_rows).enumerate() {
            for (c, v) in row.into_iter().enumerate() {
                j[(i, c)] = v;
            }
        }
        let m0 = self.pts.len() + COVERAGE_SAMPLES;
        // Inactive rows are zero (the matrix is reused between evaluations).
        j.rows_mut(m0, LIMIT_SAMPLES * LIMIT_ROWS).fill(0.0);
        let w = self.limit_weight(m);
        let limits = &self.opts.limits;
        for a in &lin.active {
            let c = a.row % LIMIT_ROWS;
            let [gi, gd, gdd, ga] = constraint_gradients(limits, a.values, m.a_mm)[c];
            let row = m0 + a.row;
            j[(row, 0)] = -w * ga;
            let (s1, c1) = a.theta.sin_cos();
            let (mut sn, mut cs) = (s1, c1);
            for kk in 0..k {
                let kf = (kk + 1) as f64;
                if kk > 0 {
                    (sn, cs) = (sn * c1 + cs * s1, cs * c1 - sn * s1);
                }
                j[(row, 4 + kk)] = -w * (gi * cs - gd * kf * sn - gdd * kf * kf * cs);
                j[(row, 4 + k + kk)] = -w * (gi * sn + gd * kf * cs - gdd * kf * kf * sn);
            }
        }
        for kk in 0..k {
            let (row, h) = self.smoothness_row(m, kk);
            j[(row, 4 + kk)] = h;
            j[(row + 1, 4 + k + kk)] = h;
        }
        if self.opts.perimeter_mm.is_some() {
            // a = L/L̂(c) is not free: its column moves onto the coefficients' by the chain rule,
            // ∂a/∂c = −(a/L̂)·∂L̂/∂c (zero column: the damped step leaves a where it is).
            let (l, grad) = unit_perimeter_gradient(&m.ratio);
            let da: Vec<f64> = grad.iter().map(|g| -m.a_mm / l * g).collect();
            for row in 0..j.nrows() {
                let ja = j[(row, 0)];
                if ja != 0.0 {
                    for (c, d) in da.iter().enumerate() {
                        j[(row, 4 + c)] += ja * d;
                    }
                    j[(row, 0)] = 0.0;
                }
            }
        }
    }

    /// Levenberg–Marquardt from `m`; returns the best admissible mechanism and iterations used.
    pub(super) fn run(&self, mut m: Mechanism, phis: &mut [f64]) -> (Mechanism, usize) {
        let np = self.n_params();
        let free = self.opts.free_idler_offset;
        let mut jac = DMatrix::zeros(self.n_rows(), np);
        let (mut r, mut current) = self.evaluate(&m, phis, None);
        self.jacobian(&m, &current, &mut jac);
        let mut cost = r.norm_squared();
        let mut lambda = 1e-3;
        let mut iters = 0;
        for _ in 0..self.opts.max_iterations {
            iters += 1;
            let a = normal_matrix(&jac);
            let g = jac.tr_mul(&r);
            let p0 = to_params(&m, free);
            let mut accepted = false;
            while lambda < 1e12 {
                let mut h = a.clone();
                for c in 0..np {
                    h[(c, c)] += lambda * a[(c, c)].max(1e-12);
                }
                let Some(ch) = h.cholesky() else {
                    lambda *= 10.0;
                    continue;
                };
                let delta = ch.solve(&(-&g));
                let p: Vec<f64> = p0.iter().zip(delta.iter()).map(|(x, d)| x + d).collect();
                let mut trial = from_params(&p, self.k, m.idler_offset_rad);
                if !(trial.a_mm > 0.0 && trial.l3_mm > 0.0) {
                    lambda *= 4.0;
                    continue;
                }
                admit(&mut trial, self.opts);
                let mut trial_phis = phis.to_vec();
                let (rt, lin) = self.evaluate(&trial, &mut trial_phis, Some(&current));
                let ct = rt.norm_squared();
                if ct.is_finite() && ct < cost {
                    let gain = (cost - ct) / cost.max(1e-300);
                    m = trial;
                    phis.copy_from_slice(&trial_phis);
                    lambda = (lambda / 3.0).max(1e-12);
                    accepted = true;
                    r = rt;
                    cost = ct;
                    let rms =
                        (r.rows(0, self.pts.len()).norm_squared() / self.pts.len() as f64).sqrt();
                    if gain < 1e-4 || (self.weights.is_none() && rms < 0.01 * self.opts.tol_mm) {
                        return (m, iters);
                    }
                    self.jacobian(&m, &lin, &mut jac);
                    current = lin;
                    break;
                }
                lambda *= 4.0;
            }
            if !accepted {
                break;
            }
        }
        (m, iters)
    }
}

/// `JᵀJ` over the rows of `j` that are not zero: of the ~4 700 rows most are limit-penalty and
/// coverage rows that are not active, and a dense product spent three quarters of its time on
/// them (a fifth of a whole design at order 32). The upper triangle by column dot products
/// (columns in parallel), mirrored.
fn normal_matrix(j: &DMatrix<f64>) -> DMatrix<f64> {
    let rows: Vec<usize> = (0..j.nrows())
        .filter(|&r| j.row(r).iter().any(|v| *v != 0.0))
        .collect();
    let jc = j.select_rows(&rows);
    let np = j.ncols();
    let upper: Vec<Vec<f64>> = (0..np)
        .into_par_iter()
        .map(|c| (c..np).map(|d| jc.column(c).dot(&jc.column(d))).collect())
        .collect();
    let mut a = DMatrix::zeros(np, np);
    for (c, row) in upper.into_iter().enumerate() {
        for (off, v) in row.into_iter().enumerate() {
            a[(c, c + off)] = v;
            a[(c + off, c)] = v;
        }
    }
    a
}

/// Makes `m` admissible: its ratio within the gear limits, with a given pitch perimeter its
/// centre distance `a = L/L̂(i)` ([`crate::geometry::perimeter`]), and its idler offset within
/// what keeps the sun and the planet apart ([`max_idler_offset_rad`]).
pub(super) fn admit(m: &mut Mechanism, opts: &FitOptions) {
    match opts.perimeter_mm {
        Some(l) => {
            m.ratio = opts.limits.project_at_perimeter(&m.ratio, l);
            m.a_mm = l / unit_perimeter(&m.ratio);
        }
        None => m.ratio = opts.limits.project(&m.ratio, m.a_mm),
    }
    if m.idler_offset_rad != 0.0 {
        let max = m.max_idler_offset_rad(opts.sun_planet_gap_mm);
        m.idler_offset_rad = m.idler_offset_rad.clamp(-max, max);
    }
}
