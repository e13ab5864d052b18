//! Step 1 in one frame (docs/math/chain.md §3.3–§3.5): the closed-form two-circle inversion of
//! the spline through the points, its monotonicity test, and the coarse pass that rejects a
//! frame early.

use super::{InverseError, InverseOptions, Inversion, MIN_AXIS_DISTANCE_L3};
use crate::design::inverse::needle_law::NeedleLaw;
use crate::design::trajectory::ClosedSpline;
use crate::math::Point;
use crate::math::periodic::wrap_pi;
use crate::math::roots::{bracketed_root, secant_root};
use rayon::prelude::*;
use std::f64::consts::TAU;

/// One frame's outcome.
pub(super) enum Solved {
    Done(Box<Inversion>),
    /// The carrier angle does not advance by +2π in this frame; carries the diagnosis.
    WrongSense(InverseError),
    /// The coarse pass of [`coarse_rejects`] rejected the frame and the other frame succeeded:
    /// not solved.
    Skipped,
}

/// Dense samples of the interpolant for `points` trajectory points: the option, at least four
/// per point.
pub(super) fn dense_count(opts: &InverseOptions, points: usize) -> usize {
    opts.dense_samples.max(4 * points)
}

/// The extreme of ρ(s) = |P(s)| near grid sample `j` of step `ds` (mm of chord): the root of
/// d(ρ²)/ds = 2 P·P′ within one step either side, to `tol` (mm), on the interpolant (docs/math/chain.md §3.5a).
fn refine_extreme(spline: &ClosedSpline, j: usize, ds: f64, tol: f64) -> f64 {
    let pdot = |s: f64| {
        let [p, d, _] = spline.eval(s);
        p.x * d.x + p.y * d.y
    };
    bracketed_root(pdot, (j as f64 - 1.0) * ds, (j as f64 + 1.0) * ds, tol)
}

/// Unit direction `e(φH)` of the carrier arm at which an arm of `l1`, `l3` (mm) reaches tip `p`
/// (mm, relative to O): `P/ρ` turned by `σ·δ`, `cos δ = q = (l1² + ρ² − l3²)/(2 l1 ρ)` (docs/math/chain.md §3.3),
/// `sin δ = √((1 − q)(1 + q))`; the cosine clamped into [−1, 1] against rounding at the extremes
/// (where it is ±1). Algebraic: no angle is taken, so the elbow `A = l1·e` costs no sine or cosine.
pub(super) fn arm_direction(p: Point, l1: f64, l3: f64, sigma: f64) -> Point {
    let r = p.norm();
    let q = ((l1 * l1 + r * r - l3 * l3) / (2.0 * l1 * r)).clamp(-1.0, 1.0);
    let sd = sigma * ((1.0 - q) * (1.0 + q)).sqrt();
    let (c, s) = (p.x / r, p.y / r);
    Point::new(c * q - s * sd, s * q + c * sd)
}

/// Carrier angle φH (rad, in (−π, π], not unwrapped) of [`arm_direction`]:
/// `atan2 P + σ·arccos q` as one `atan2`.
pub(super) fn carrier_angle(p: Point, l1: f64, l3: f64, sigma: f64) -> f64 {
    let e = arm_direction(p, l1, l3, sigma);
    e.atan2()
}

/// Samples of the coarse test: one in [`COARSE_DIVISOR`] of the dense samples.
const COARSE_DIVISOR: usize = 16;

/// A backwards stretch of the carrier angle the coarse test takes as clear, rad: far above the
/// rounding of the angles it compares (the arm lengths come from refined extremes as in the
/// full pass).
const CLEAR_BACKWARDS_RAD: f64 = 1e-3;

/// Whether a coarse pass (every [`COARSE_DIVISOR`]-th dense parameter) clearly rejects the
/// frame: the carrier angle advances by other than +2π over the loop, or runs backwards by more
/// than [`CLEAR_BACKWARDS_RAD`] on a stretch (the monotonicity criterion of docs/math/chain.md §3.3 at a
/// margin). A step of the unwrapping larger than π/2 (ambiguous) answers false, as does anything
/// unclear: the frame is then solved in full.
pub(super) fn coarse_rejects(spline: &ClosedSpline, ns: usize, tol: f64) -> bool {
    let n = (ns / COARSE_DIVISOR).max(64);
    let len = spline.period();
    let ds = len / n as f64;
    let pts: Vec<Point> = (0..n).map(|j| spline.point(j as f64 * ds)).collect();
    let rho: Vec<f64> = pts.iter().map(|&p| p.norm()).collect();
    let arg =
        |f: fn(f64, f64) -> bool| (0..n).fold(0, |b, j| if f(rho[j], rho[b]) { j } else { b });
    let (jmax, jmin) = (arg(|a, b| a > b), arg(|a, b| a < b));
    // The extremes refined as in the full pass.
    let refined = |j: usize| {
        let s = refine_extreme(spline, j, ds, tol);
        let p = spline.point(s);
        (s, p.norm())
    };
    let ((s_max, r_max), (s_min, r_min)) = (refined(jmax), refined(jmin));
    let (r_max, r_min) = (r_max.max(rho[jmax]), r_min.min(rho[jmin]));
    let (l1, l3) = (0.5 * (r_max - r_min), 0.5 * (r_max + r_min));
    if !(l1 > 0.0) {
        return false;
    }
    let s_min_rel = (s_min - s_max).rem_euclid(len);
    // The angle at parameter u from s_max (σ = +1 until s_min, as in the full pass).
    let phi = |u: f64| {
        let sigma = if u <= s_min_rel { 1.0 } else { -1.0 };
        carrier_angle(spline.point(s_max + u), l1, l3, sigma)
    };
    let (mut total, mut prev, mut back) = (0.0, phi(0.0), 0.0f64);
    let mut clear_backwards = false;
    for i in 1..=n {
        let u = if i == n { len } else { i as f64 * ds };
        let step = wrap_pi(phi(u) - prev);
        if step.abs() > 0.5 * std::f64::consts::PI {
            return false;
        }
        back = if step < 0.0 { back + step } else { 0.0 };
        clear_backwards |= back < -CLEAR_BACKWARDS_RAD;
        total += step;
        prev += step;
    }
    clear_backwards || (total - TAU).abs() > std::f64::consts::PI
}

/// Keeps the first `k` harmonics of uniform periodic samples.
fn low_pass(y: &[f64], k: usize) -> Vec<f64> {
    let mut c = crate::math::periodic::fft_coefficients(y);
    for (j, v) in c.iter_mut().enumerate() {
        if j > k {
            *v = realfft::num_complex::Complex::new(0.0, 0.0);
        }
    }
    crate::math::periodic::fft_synthesis(&c, y.len())
}

/// Winding number of a closed polyline about the origin.
pub(super) fn winding_number(pts: &[Point]) -> i64 {
    let n = pts.len();
    let mut total = 0.0;
    for k in 0..n {
        let a = pts[k].atan2();
        let b = pts[(k + 1) % n].atan2();
        total += wrap_pi(b - a);
    }
    (total / TAU).round() as i64
}

/// Runs of indices where `bad(j)` holds, as `[first, last]` pairs.
fn runs(n: usize, bad: impl Fn(usize) -> bool) -> Vec<[usize; 2]> {
    let mut out = Vec::new();
    let mut start = None;
    for j in 0..n {
        match (bad(j), start) {
            (true, None) => start = Some(j),
            (false, Some(s)) => {
                out.push([s, j - 1]);
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start {
        out.push([s, n - 1]);
    }
    out
}

/// Step 1 in one frame, on the closed spline through its points `pts`: the extremes of ρ give
/// the arms ([`arms`]), the arms the carrier and needle angles at the dense samples
/// ([`dense_angles`]), which must advance ([`check_monotone`]); the needle law is resampled on a
/// uniform carrier-angle grid ([`resample_law`]).
pub(super) fn solve_frame(
    spline: &ClosedSpline,
    pts: &[Point],
    opts: &InverseOptions,
    direction: i8,
    center: Point,
) -> Result<Solved, InverseError> {
    let len = spline.period();
    let ns = dense_count(opts, pts.len());
    let tol = opts.tol_relative * len;
    let arms = arms(spline, ns, tol, direction, center)?;
    let (phi, beta) = dense_angles(spline, &arms, ns);
    if let Some(wrong_sense) = check_monotone(&arms, &phi, &beta, direction)? {
        return Ok(Solved::WrongSense(wrong_sense));
    }
    let samples = resample_law(spline, &arms, &phi, &beta, opts.grid.max(16), tol);
    Ok(Solved::Done(Box::new(Inversion {
        l1_mm: arms.l1,
        l3_mm: arms.l3,
        rho_max_mm: arms.rho_max,
        rho_min_mm: arms.rho_min,
        direction,
        phi_h0_rad: phi[0].rem_euclid(TAU),
        law: NeedleLaw::from_samples(match opts.law_harmonics {
            Some(k) => low_pass(&samples, k),
            None => samples,
        }),
        points: pts.to_vec(),
        other_sense_traceable: false,
    })))
}

/// The arm lengths of one frame and where on the spline the tip is farthest and nearest.
struct Arms {
    /// Spline parameters (mm of chord) of ρmax and ρmin.
    s_max: f64,
    s_min: f64,
    /// ρmax, ρmin (mm).
    rho_max: f64,
    rho_min: f64,
    /// `l1 = (ρmax − ρmin)/2`, `l3 = (ρmax + ρmin)/2` (mm).
    l1: f64,
    l3: f64,
    /// Dense samples of the spline and their spacing (mm of chord).
    ns: usize,
    ds: f64,
}

impl Arms {
    /// σ at parameter `u` from `s_max` in travel order: +1 until `s_min`, −1 after.
    fn sigma_at(&self, u: f64, len: f64) -> f64 {
        if u <= (self.s_min - self.s_max).rem_euclid(len) {
            1.0
        } else {
            -1.0
        }
    }
}

/// The arms from the extremes of ρ on `ns` dense samples, refined on the interpolant
/// (d(ρ²)/ds = 2 P·P′ = 0, docs/math/chain.md §3.5a); several separate global maxima
/// (docs/math/chain.md §3.2) and a trajectory too close to the axis are refused.
fn arms(
    spline: &ClosedSpline,
    ns: usize,
    tol: f64,
    direction: i8,
    center: Point,
) -> Result<Arms, InverseError> {
    let len = spline.period();
    let ds = len / ns as f64;
    let rho = |s: f64| spline.point(s).norm();
    // Independent samples: evaluated in parallel (same values, same order).
    let dense: Vec<f64> = (0..ns)
        .into_par_iter()
        .map(|j| rho(j as f64 * ds))
        .collect();
    let (jmax, _) = dense
        .iter()
        .enumerate()
        .fold((0, f64::MIN), |b, (j, &r)| if r > b.1 { (j, r) } else { b });
    let (jmin, _) = dense
        .iter()
        .enumerate()
        .fold((0, f64::MAX), |b, (j, &r)| if r < b.1 { (j, r) } else { b });
    // Several separate global maxima (docs/math/chain.md §3.2).
    let rmax_dense = dense[jmax];
    let sep = ns / 20;
    let mut maxima = vec![jmax];
    for j in 0..ns {
        let (prev, next) = (dense[(j + ns - 1) % ns], dense[(j + 1) % ns]);
        let cyc = |a: usize, b: usize| {
            let d = a.abs_diff(b);
            d.min(ns - d)
        };
        if dense[j] >= prev
            && dense[j] > next
            && dense[j] >= rmax_dense * (1.0 - 1e-4)
            && maxima.iter().all(|&m| cyc(m, j) > sep)
        {
            maxima.push(j);
        }
    }
    if maxima.len() > 1 {
        let sy = f64::from(direction);
        return Err(InverseError::SeveralMaxima {
            rho_max_mm: rmax_dense,
            count: maxima.len(),
            at: maxima
                .iter()
                .map(|&j| {
                    let p = spline.point(j as f64 * ds);
                    Point::new(p.x + center.x, sy * p.y + center.y)
                })
                .collect(),
        });
    }
    // Refine the extremes: d(ρ²)/ds = 2 P·P′ = 0 (Brent/bisection on the same interpolant, docs/math/chain.md §3.5a).
    let (s_max, s_min) = (
        refine_extreme(spline, jmax, ds, tol),
        refine_extreme(spline, jmin, ds, tol),
    );
    let (rho_max, rho_min) = (rho(s_max).max(rmax_dense), rho(s_min).min(dense[jmin]));
    let l1 = 0.5 * (rho_max - rho_min);
    let l3 = 0.5 * (rho_max + rho_min);
    if rho_min < MIN_AXIS_DISTANCE_L3 * l3 {
        return Err(InverseError::TooCloseToAxis {
            rho_min_mm: rho_min,
            limit_mm: MIN_AXIS_DISTANCE_L3 * l3,
        });
    }
    Ok(Arms {
        s_max,
        s_min,
        rho_max,
        rho_min,
        l1,
        l3,
        ns,
        ds,
    })
}

/// The carrier angle φH and the needle direction β at the dense tips `u_j = j·ds` from `s_max`
/// (the last one a whole period on), each unwrapped along the samples (rad).
fn dense_angles(spline: &ClosedSpline, arms: &Arms, ns: usize) -> (Vec<f64>, Vec<f64>) {
    let len = spline.period();
    let (l1, l3, ds) = (arms.l1, arms.l3, arms.ds);
    let u_at = |j: usize| if j == ns { len } else { j as f64 * ds };
    // The raw carrier and needle angles at the dense tips (the needle from the elbow
    // A = l1·e(φH)) are independent: computed in one parallel pass; the unwrapping runs in order.
    let angles: Vec<[f64; 2]> = (0..=ns)
        .into_par_iter()
        .map(|j| {
            let (u, tip) = (u_at(j), spline.point(arms.s_max + u_at(j)));
            let e = arm_direction(tip, l1, l3, arms.sigma_at(u, len));
            [e.atan2(), (tip.y - l1 * e.y).atan2(tip.x - l1 * e.x)]
        })
        .collect();
    // Angle c (0: carrier, 1: needle) unwrapped along the samples.
    let unwrapped = |c: usize| {
        let mut out = Vec::with_capacity(angles.len());
        let mut prev = angles[0][c];
        out.push(prev);
        for a in &angles[1..] {
            prev += wrap_pi(a[c] - prev);
            out.push(prev);
        }
        out
    };
    (unwrapped(0), unwrapped(1))
}

/// The carrier angle must advance by +2π over the loop (else this is the other sense: the
/// diagnosis is returned) and on every stretch (docs/math/chain.md §3.3), and ψ3 must increase
/// (i31 > 0); the stretches where either fails are named in degrees of the carrier angle.
fn check_monotone(
    arms: &Arms,
    phi: &[f64],
    beta: &[f64],
    direction: i8,
) -> Result<Option<InverseError>, InverseError> {
    let ns = arms.ns;
    let total = phi[ns] - phi[0];
    let to_deg = |a: f64| (f64::from(direction) * a).to_degrees().rem_euclid(360.0);
    let bad = runs(ns, |j| phi[j + 1] <= phi[j]);
    let not_monotone = InverseError::NotMonotone {
        l1_mm: arms.l1,
        l3_mm: arms.l3,
        stretches_deg: bad
            .iter()
            .map(|r| [to_deg(phi[r[0]]), to_deg(phi[r[1] + 1])])
            .collect(),
    };
    if (total - TAU).abs() > 1e-6 {
        return Ok(Some(not_monotone));
    }
    if !bad.is_empty() {
        return Err(not_monotone);
    }
    // Needle direction and ψ3 on the dense samples: ψ3 must increase (i31 > 0).
    let psi = |j: usize| (phi[j] - phi[0]) - (beta[j] - beta[0]);
    let bad = runs(ns, |j| psi(j + 1) <= psi(j));
    if !bad.is_empty() {
        return Err(InverseError::NeedleReverses {
            stretches_deg: bad
                .iter()
                .map(|r| [to_deg(phi[r[0]]), to_deg(phi[r[1] + 1])])
                .collect(),
        });
    }
    Ok(None)
}

/// The needle law ψ3 − t at `n` uniform carrier angles `t_n = 2πn/N` from φH0: `φH(u) = φH0 + t_n`
/// solved on the interpolant itself (secant within the dense bracket, to `tol` mm of chord),
/// no second interpolation (docs/math/chain.md §3.5).
fn resample_law(
    spline: &ClosedSpline,
    arms: &Arms,
    phi: &[f64],
    beta: &[f64],
    n: usize,
    tol: f64,
) -> Vec<f64> {
    let len = spline.period();
    let (l1, l3, ns, ds) = (arms.l1, arms.l3, arms.ns, arms.ds);
    let phi0 = phi[0];
    let raw_phi =
        |u: f64| carrier_angle(spline.point(arms.s_max + u), l1, l3, arms.sigma_at(u, len));
    // The needle direction at the tip of parameter u for carrier angle ph (rad).
    let beta_at = |u: f64, ph: f64| {
        let p = spline.point(arms.s_max + u);
        (p.y - l1 * ph.sin()).atan2(p.x - l1 * ph.cos())
    };
    (0..n)
        .into_par_iter()
        .map(|k| {
            let t = TAU * k as f64 / n as f64;
            let target = phi0 + t;
            let j = phi.partition_point(|&v| v <= target).clamp(1, ns) - 1;
            let (u_lo, u_hi) = (j as f64 * ds, ((j + 1) as f64 * ds).min(len));
            let unwrap_near = |u: f64| phi[j] + wrap_pi(raw_phi(u) - phi[j]);
            // The ends are dense samples: their angles are known.
            let u = if k == 0 {
                0.0
            } else {
                secant_root(
                    |u| unwrap_near(u) - target,
                    u_lo,
                    u_hi,
                    phi[j] - target,
                    phi[j + 1] - target,
                    tol,
                )
            };
            let b = beta[j] + wrap_pi(beta_at(u, target) - beta[j]);
            -(b - beta[0])
        })
        .collect()
}
