//! The curve a train traces, seen from the target points: tip, velocity and acceleration in the
//! carrier angle, the projection of a point on the curve, the signed distance and its
//! gradient in the design parameters (formulas in the [`crate::design::fit`] module doc).

use crate::design::fit::scan::Samples;
use crate::geometry::mechanism::{INVERSE_TOL_RAD, Mechanism};
use crate::math::Point;
use crate::math::polyline::SegmentGrid;
use rayon::prelude::*;
use std::f64::consts::{PI, TAU};

/// Tip, velocity and acceleration w.r.t. φ, and the quantities the Jacobian needs.
#[derive(Debug, Clone)]
pub(super) struct TipEval {
    /// Carrier angle φ, rad.
    pub(super) phi: f64,
    pub(super) b: Point,
    pub(super) v: Point,
    pub(super) acc: Point,
    pub(super) beta: f64,
    pub(super) t: f64,
    pub(super) s: f64,
    pub(super) i_t: f64,
    pub(super) i_s: f64,
}

pub(super) fn tip_eval(m: &Mechanism, phi: f64) -> TipEval {
    tip_eval_near(m, phi, f64::NAN)
}

/// [`tip_eval`] at `phi + step` from the evaluation `e` at `phi`: the contact angle `S` is solved
/// from its first-order prediction `S + S′·step` (`S′ = i(t)/i(S)`).
pub(super) fn tip_eval_next(m: &Mechanism, e: &TipEval, step: f64) -> TipEval {
    tip_eval_near(m, e.phi + step, e.s + step * e.i_t / e.i_s)
}

/// The evaluation at carrier angle `phi` with the contact angle `S` solved from
/// `contact_guess_rad` (NaN: no guess, a cold solve): one Halley step where the guess is close,
/// else Newton ([`crate::geometry::fourier::SunRatio::inverse_integral_with_slopes`]).
fn tip_eval_near(m: &Mechanism, phi: f64, contact_guess_rad: f64) -> TipEval {
    let t = m.contact_angle(phi);
    let (fi_t, i_t) = m.ratio.integral_and_eval3(t);
    let (s, i_s) = m.ratio.inverse_integral_with_slopes(
        fi_t + m.contact_shift_rad(),
        contact_guess_rad,
        INVERSE_TOL_RAD,
    );
    tip_eval_with(m, phi, (t, i_t), (s, i_s))
}

/// The evaluation at carrier angle `phi` (`t = phi + ε − φ_ref`, with the ratio's `[i, i′, i″]`
/// there) with the contact angle `s = S(t)` and the ratio's `[i, i′]` there.
fn tip_eval_with(
    m: &Mechanism,
    phi: f64,
    (t, [i_t, di_t, _]): (f64, [f64; 3]),
    (s, [i_s, di_s]): (f64, [f64; 2]),
) -> TipEval {
    let beta = phi + PI - m.idler_offset_rad - s + m.needle_angle_rad;
    let (sp, cp) = phi.sin_cos();
    let (sb, cb) = beta.sin_cos();
    let (l1, l3) = (m.l1_mm(), m.l3_mm);
    let ds = i_t / i_s;
    let db = 1.0 - ds;
    // β″ = −d/dφ (i(t)/i(S)) = −(i′(t)·i(S) − i(t)·i′(S)·S′)/i(S)².
    let ddb = -(di_t * i_s - i_t * di_s * ds) / (i_s * i_s);
    TipEval {
        phi,
        b: Point::new(l1 * cp + l3 * cb, l1 * sp + l3 * sb),
        v: Point::new(-l1 * sp - l3 * sb * db, l1 * cp + l3 * cb * db),
        acc: Point::new(
            -l1 * cp - l3 * cb * db * db - l3 * sb * ddb,
            -l1 * sp - l3 * sb * db * db + l3 * cb * ddb,
        ),
        beta,
        t,
        s,
        i_t,
        i_s,
    }
}

/// Closest point of the traced curve to `p` near carrier angle `phi` (Newton on `(B − P)·B′ = 0`
/// with a Gauss–Newton fallback and a step cap). Returns `(φ, evaluation at φ)`.
pub(super) fn project(m: &Mechanism, p: Point, phi: f64) -> (f64, TipEval) {
    project_near(m, p, phi, f64::NAN)
}

/// [`project`] with a guess of the contact angle `S` at `phi` (rad; NaN: none): the contact angle
/// an earlier, nearby train had there, which saves most of the first evaluation's solve.
pub(super) fn project_near(
    m: &Mechanism,
    p: Point,
    mut phi: f64,
    contact_guess_rad: f64,
) -> (f64, TipEval) {
    let mut e = tip_eval_near(m, phi, contact_guess_rad);
    let dist2 = |e: &TipEval| (e.b - p).norm_squared();
    let mut best = (phi, dist2(&e), e.clone());
    for _ in 0..30 {
        let r = e.b - p;
        let g = r.dot(e.v);
        let vv = e.v.dot(e.v);
        // Summed left to right as written: grouped as `vv + r.dot(e.acc)` it rounds differently
        // and moves the last bits of some designs.
        let h = vv + r.x * e.acc.x + r.y * e.acc.y;
        let mut step = if h > 0.1 * vv {
            -g / h
        } else {
            -g / (vv + 1e-300)
        };
        step = step.clamp(-0.2, 0.2);
        phi += step;
        e = tip_eval_next(m, &e, step);
        let d2 = dist2(&e);
        if d2 < best.1 {
            best = (phi, d2, e.clone());
        }
        if step.abs() < 1e-13 {
            break;
        }
    }
    // Near a cusp (tip nearly at rest) Newton may wander: keep the closest point seen.
    if best.0 != phi {
        return (best.0, best.2);
    }
    (phi, e)
}

/// Signed distance of `p` from the curve at the projection `e` and its unit direction: `|P − B|`
/// signed by the side of the curve (the tangent's normal), along `(P − B)/|P − B|`. At a converged
/// projection this is the normal distance; where a projection is not converged (a cusp, where the
/// tip is at rest and the tangent is undefined) it still is the true distance, never less.
pub(super) fn normal_residual(e: &TipEval, p: Point) -> (f64, Point) {
    let r = p - e.b;
    let rn = r.norm();
    let side = -e.v.y * r.x + e.v.x * r.y;
    let s = if side < 0.0 { -1.0 } else { 1.0 };
    if rn > 0.0 {
        (s * rn, r * s / rn)
    } else {
        let vn = e.v.norm().max(1e-300);
        (0.0, Point::new(-e.v.y / vn, e.v.x / vn))
    }
}

/// Jacobian row of the signed distance `d = n·(P − B)` (see the module doc); a row one longer
/// than `4 + 2K` also gets the idler offset's column, last.
pub(super) fn point_row(m: &Mechanism, e: &TipEval, n: Point, row: &mut [f64]) {
    let k = m.ratio.order();
    let l3 = m.l3_mm;
    let (sp, cp) = e.phi.sin_cos();
    let (sb, cb) = e.beta.sin_cos();
    let ne_phi = n.x * cp + n.y * sp;
    let ne_beta = n.x * cb + n.y * sb;
    let ne_perp = -n.x * sb + n.y * cb;
    let (se, ce) = m.idler_offset_rad.sin_cos();
    row[0] = -2.0 * ce * ne_phi;
    if let Some(r) = row.get_mut(4 + 2 * k) {
        // ∂B/∂ε = −2a·sin ε·e(φ) + l3·e⊥(β)·∂β/∂ε, ∂β/∂ε = −1 − (i(t) + 2)/i(S).
        *r = 2.0 * m.a_mm * se * ne_phi + l3 * ne_perp * (1.0 + (e.i_t + 2.0) / e.i_s);
    }
    row[1] = -ne_beta;
    row[2] = -l3 * ne_perp;
    row[3] = -l3 * ne_perp * (e.i_t / e.i_s);
    let f = l3 * ne_perp / e.i_s;
    let (s1t, c1t) = e.t.sin_cos();
    let (s1s, c1s) = e.s.sin_cos();
    let (mut st, mut ct, mut ss, mut cs) = (s1t, c1t, s1s, c1s);
    for kk in 0..k {
        let kf = (kk + 1) as f64;
        row[4 + kk] = f * (st - ss) / kf;
        row[4 + k + kk] = f * (cs - ct) / kf;
        (st, ct) = (st * c1t + ct * s1t, ct * c1t - st * s1t);
        (ss, cs) = (ss * c1s + cs * s1s, cs * c1s - ss * s1s);
    }
}

/// Carrier angle of each point on the curve traced by `m`: projected from each of the
/// [`CANDIDATES`] nearest local minima of the distance to 4096 curve samples, the closest
/// projection kept. (Near a crossing or a close approach of two stretches, the nearest sample can
/// lie on the other stretch: a fast tip spaces its own samples farther apart than the gap.)
pub(super) fn initial_angles(m: &Mechanism, pts: &[Point]) -> Vec<f64> {
    initial_projections_on(m, &curve_evals(m, INITIAL_SAMPLES), pts)
        .into_iter()
        .map(|(phi, _)| phi)
        .collect()
}

/// Samples of the traced curve that [`initial_angles`] scans.
pub(super) const INITIAL_SAMPLES: usize = 4096;

/// [`initial_angles`] on the traced curve's `curve` samples at uniform carrier angles, with each
/// projection's evaluation.
pub(super) fn initial_projections_on(
    m: &Mechanism,
    curve: &[TipEval],
    pts: &[Point],
) -> Vec<(f64, TipEval)> {
    let n = curve.len();
    let tips: Vec<Point> = curve.iter().map(|e| e.b).collect();
    let samples = Samples::new(&tips);
    pts.par_iter()
        .map(|p| {
            // The CANDIDATES smallest local minima, in increasing distance.
            let minima = samples.nearest_minima::<CANDIDATES>(*p);
            minima
                .iter()
                .filter(|m| m.1 != usize::MAX)
                .map(|&(_, k)| {
                    let (phi, e) = project_near(m, *p, TAU * k as f64 / n as f64, curve[k].s);
                    let d2 = (e.b.x - p.x).powi(2) + (e.b.y - p.y).powi(2);
                    (phi, e, d2)
                })
                .fold(None, |b: Option<(f64, TipEval, f64)>, c| match b {
                    Some(b) if b.2 <= c.2 => Some(b),
                    _ => Some(c),
                })
                .map_or_else(|| project(m, *p, 0.0), |(phi, e, _)| (phi, e))
        })
        .collect()
}

/// Samples per block of [`curve_evals`]: a cold solve starts each block, warm ones follow.
const CURVE_BLOCK: usize = 256;

/// The evaluations at `n` uniform carrier angles `2πk/n`, each contact angle solved from the
/// previous one within blocks of [`CURVE_BLOCK`] (the blocks in parallel; the same numbers for
/// any thread count).
pub(super) fn curve_evals(m: &Mechanism, n: usize) -> Vec<TipEval> {
    let h = TAU / n as f64;
    (0..n.div_ceil(CURVE_BLOCK))
        .into_par_iter()
        .flat_map_iter(|b| {
            let (k0, k1) = (b * CURVE_BLOCK, ((b + 1) * CURVE_BLOCK).min(n));
            let mut out: Vec<TipEval> = Vec::with_capacity(k1 - k0);
            out.push(tip_eval(m, h * k0 as f64));
            for j in 1..k1 - k0 {
                let e = tip_eval_next(m, &out[j - 1], h);
                out.push(e);
            }
            out
        })
        .collect()
}

/// A guess of the contact angle at carrier angle `phi` (rad) from the nearest of `curve`'s
/// samples at the uniform angles `2πk/n` (a turn later the contact angle is 2π on):
/// `S_k + (φ − φ_k)·i(t_k)/i(S_k)`, first order in a step of at most half a sample.
pub(super) fn contact_guess(curve: &[TipEval], phi: f64) -> f64 {
    let n = curve.len();
    let h = TAU / n as f64;
    let turns = phi.div_euclid(TAU);
    let k = (phi.rem_euclid(TAU) / h).round();
    let e = &curve[k as usize % n];
    let wrapped = if k as usize >= n { TAU } else { 0.0 };
    let d = phi - turns * TAU - k * h;
    e.s + turns * TAU + wrapped + d * e.i_t / e.i_s
}

/// Local minima of the sample distance tried per point by [`initial_angles`].
const CANDIDATES: usize = 3;

/// Distance (mm) of the traced curve's sample `e` from the target polyline, the length of the
/// nearest chord (mm) and the distance's gradient direction.
pub(super) fn coverage(q: &SegmentGrid, e: &TipEval) -> CoverageSample {
    let near = q.nearest(e.b);
    let (c, chord) = (near.point, q.segment_length_mm(near.segment));
    let r = e.b - c;
    let d = r.norm();
    let u = if d > 0.0 { r / d } else { Point::ZERO };
    CoverageSample {
        distance_mm: d,
        chord_mm: chord,
        direction: u,
    }
}

/// A traced-curve sample's distance from the target polyline ([`coverage`]).
#[derive(Debug, Clone, Copy)]
pub(super) struct CoverageSample {
    /// Distance from the polyline, mm.
    pub distance_mm: f64,
    /// Length of the nearest segment, mm.
    pub chord_mm: f64,
    /// Unit vector from the nearest polyline point to the sample.
    pub direction: Point,
}

impl CoverageSample {
    /// The distance beyond what the polyline's chords can explain (0.6 of the nearest chord:
    /// even round a sharp, coarsely sampled nose a smooth curve through two points bulges at
    /// most about half their distance beyond their chord), mm.
    pub fn excess_mm(&self) -> f64 {
        (self.distance_mm - 0.6 * self.chord_mm).max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::fit::solver::{from_params, to_params};
    use crate::design::fit::tests::mech;

    #[test]
    fn jacobian_matches_finite_differences() {
        // The collinear train and one with its intermediate axis 0.2 rad off the carrier line.
        for eps in [0.0, 0.2] {
            let m = Mechanism {
                idler_offset_rad: eps,
                ..mech()
            };
            let p = Point::new(150.0, -120.0);
            let (phi, e) = project(&m, p, 5.0);
            let (_, n) = normal_residual(&e, p);
            let mut row = vec![0.0; 4 + 2 * 3 + 1];
            point_row(&m, &e, n, &mut row);
            let q = to_params(&m, true);
            for c in 0..q.len() {
                let h = 1e-6;
                let d = |s: f64| {
                    let mut qq = q.clone();
                    qq[c] += s * h;
                    let mm = from_params(&qq, 3, f64::NAN);
                    let b = mm.tip(phi);
                    n.x * (p.x - b.x) + n.y * (p.y - b.y)
                };
                let fd = (d(1.0) - d(-1.0)) / (2.0 * h);
                assert!(
                    (fd - row[c]).abs() < 1e-5 * (1.0 + fd.abs()),
                    "ε = {eps}, param {c}: {fd} vs {}",
                    row[c]
                );
            }
        }
    }

    #[test]
    fn projection_is_orthogonal() {
        let m = mech();
        let p = Point::new(150.0, -120.0);
        let (_, e) = project(&m, p, 5.0);
        let r = p - e.b;
        let cos = (r.dot(e.v)) / (r.hypot() * e.v.hypot());
        assert!(cos.abs() < 1e-10, "{cos}");
    }
}
