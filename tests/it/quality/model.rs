//! The reference's own forward model: the train with the sun ratio given as uniform samples of
//! `(i, i′, i″)` against the sun's design angle `u_j = 2πj/N`, and the log-ratio as a periodic
//! cubic spline through `K` control values.
//!
//! ```text
//! g(u)  = periodic cubic spline through (2πk/K, c_k)           log-ratio, dimensionless
//! i(u)  = e^{g(u)} / mean_j e^{g(u_j)}                          mean 1: closure Φ(2π) = 2π
//! i′ = i·g′,   i″ = i·(g″ + g′²)
//! Φ_{j+1} = Φ_j + h(i_j + i_{j+1})/2 + h²(i′_j − i′_{j+1})/12     (Hermite-corrected trapezoid)
//! S(u_j) = Φ⁻¹(Φ_j + π)   (cubic Hermite inverse, Newton)
//! φ_j = u_j + φ_ref,   β_j = φ_j + π − S(u_j) + γ,   B_j = 2a·e(φ_j) + l3·e(β_j)      (mm)
//! ```
//!
//! Limits from `(i, i′, i″)` (sun r = a·i/(1+i); intermediate r2 = a/(1+i) against θ2, dθ2/du = i):
//!
//! ```text
//! |r_θ/r| = |i′| / (i(1 + i))                                  (both gears)
//! sun:   r_θ = a i′/(1+i)²,  r_θθ = a (i″(1+i) − 2i′²)/(1+i)³
//! int.:  r_θ = −a i′/(i(1+i)²),  r_θθ = −a (i″ i(1+i) − i′²(1+i) − 2 i i′²) / (i³(1+i)³)
//! concave curvature κ = max(0, −Δ)/(r² + r_θ²)^{3/2},  Δ = r² + 2r_θ² − r r_θθ   (1/mm)
//! ```

use ncgear::math::Point;
use std::f64::consts::{PI, TAU};

/// Samples of the sun ratio and its first two derivatives at `u_j = 2πj/N`.
#[derive(Debug, Clone)]
pub struct Ratio {
    pub i: Vec<f64>,
    pub di: Vec<f64>,
    pub ddi: Vec<f64>,
}

impl Ratio {
    /// From a function `u ↦ (i, i′, i″)` at `n` uniform angles.
    pub fn from_fn(n: usize, f: impl Fn(f64) -> [f64; 3]) -> Self {
        let v: Vec<[f64; 3]> = (0..n).map(|j| f(TAU * j as f64 / n as f64)).collect();
        Self {
            i: v.iter().map(|x| x[0]).collect(),
            di: v.iter().map(|x| x[1]).collect(),
            ddi: v.iter().map(|x| x[2]).collect(),
        }
    }

    /// `Φ_j = ∫_0^{u_j} i`, j = 0..=N (the last is 2π up to rounding when the mean is 1).
    pub fn integral(&self) -> Vec<f64> {
        let n = self.i.len();
        let h = TAU / n as f64;
        let mut phi = Vec::with_capacity(n + 1);
        phi.push(0.0);
        for j in 0..n {
            let k = (j + 1) % n;
            let step = 0.5 * h * (self.i[j] + self.i[k]) + h * h / 12.0 * (self.di[j] - self.di[k]);
            phi.push(phi[j] + step);
        }
        phi
    }

    /// `(i, i′)` at any `u` (cubic Hermite of the samples) — for the intermediate's table.
    fn value_at(&self, u: f64) -> f64 {
        let n = self.i.len();
        let h = TAU / n as f64;
        let x = u.rem_euclid(TAU) / h;
        let m = (x.floor() as usize).min(n - 1);
        let (s, k) = (x - m as f64, (m + 1) % n);
        let (h00, h10, h01, h11) = hermite(s);
        h00 * self.i[m] + h10 * h * self.di[m] + h01 * self.i[k] + h11 * h * self.di[k]
    }
}

fn hermite(s: f64) -> (f64, f64, f64, f64) {
    let (s2, s3) = (s * s, s * s * s);
    (
        2.0 * s3 - 3.0 * s2 + 1.0,
        s3 - 2.0 * s2 + s,
        -2.0 * s3 + 3.0 * s2,
        s3 - s2,
    )
}

/// `Φ⁻¹(y)` from the table `phi` (j = 0..=N) of a ratio; `hint` is the interval of the last call.
fn invert(r: &Ratio, phi: &[f64], y: f64, hint: &mut usize) -> f64 {
    let n = r.i.len();
    let h = TAU / n as f64;
    let wraps = (y / TAU).floor();
    let y0 = y - wraps * TAU;
    let mut m = (*hint).min(n - 1);
    while m + 1 < n && phi[m + 1] <= y0 {
        m += 1;
    }
    while m > 0 && phi[m] > y0 {
        m -= 1;
    }
    *hint = m;
    let k = (m + 1) % n;
    let (p0, p1) = (phi[m], phi[m + 1]);
    let mut s = ((y0 - p0) / (p1 - p0)).clamp(0.0, 1.0);
    for _ in 0..2 {
        let (h00, h10, h01, h11) = hermite(s);
        let v = h00 * p0 + h10 * h * r.i[m] + h01 * p1 + h11 * h * r.i[k];
        let s2 = s * s;
        let dv = (6.0 * s2 - 6.0 * s) * (p0 - p1)
            + (3.0 * s2 - 4.0 * s + 1.0) * h * r.i[m]
            + (3.0 * s2 - 2.0 * s) * h * r.i[k];
        s = (s - (v - y0) / dv).clamp(0.0, 1.0);
    }
    (m as f64 + s) * h + wraps * TAU
}

/// Largest values over the grid of the quantities the limits bound.
#[derive(Debug, Clone, Copy)]
pub struct Extremes {
    /// `max |r_θ/r|` of sun and intermediate (= tan of the slope).
    pub slope_tan: f64,
    /// Largest concave curvature of sun and intermediate, 1/mm (0: convex).
    pub concave_curvature: f64,
    /// `[min, max]` of i.
    pub ratio: [f64; 2],
}

/// A train of the reference's model.
#[derive(Debug, Clone)]
pub struct Train {
    pub a: f64,
    pub l3: f64,
    pub gamma: f64,
    pub phi_ref: f64,
    pub ratio: Ratio,
}

impl Train {
    /// Tip positions at the carrier angles `φ_j = u_j + φ_ref`, mm.
    pub fn tips(&self) -> Vec<Point> {
        let r = &self.ratio;
        let n = r.i.len();
        let phi = r.integral();
        let mut hint = phi.partition_point(|&p| p <= PI).saturating_sub(1);
        // e(φ_j) = e(φ_ref)·e(u_j) (rotation), one sin_cos per needle direction.
        let (sr, cr) = self.phi_ref.sin_cos();
        let l1 = 2.0 * self.a;
        (0..n)
            .map(|j| {
                let s = invert(r, &phi, phi[j] + PI, &mut hint);
                let u = TAU * j as f64 / n as f64;
                let (su, cu) = u.sin_cos();
                let (sb, cb) = (u + self.phi_ref + PI - s + self.gamma).sin_cos();
                Point::new(
                    l1 * (cu * cr - su * sr) + self.l3 * cb,
                    l1 * (su * cr + cu * sr) + self.l3 * sb,
                )
            })
            .collect()
    }

    /// The limit quantities over the grid.
    pub fn extremes(&self) -> Extremes {
        let (a, r) = (self.a, &self.ratio);
        let mut e = Extremes {
            slope_tan: 0.0,
            concave_curvature: 0.0,
            ratio: [f64::INFINITY, f64::NEG_INFINITY],
        };
        let kappa = |r: f64, r1: f64, r2: f64| {
            let delta = r * r + 2.0 * r1 * r1 - r * r2;
            if delta >= 0.0 {
                return 0.0;
            }
            let q = r * r + r1 * r1;
            -delta / (q * q.sqrt())
        };
        for j in 0..r.i.len() {
            let (i, di, ddi) = (r.i[j], r.di[j], r.ddi[j]);
            let s = 1.0 + i;
            e.ratio = [e.ratio[0].min(i), e.ratio[1].max(i)];
            e.slope_tan = e.slope_tan.max(di.abs() / (i * s));
            let sun = kappa(
                a * i / s,
                a * di / (s * s),
                a * (ddi * s - 2.0 * di * di) / (s * s * s),
            );
            let int = kappa(
                a / s,
                -a * di / (i * s * s),
                -a * (ddi * i * s - di * di * s - 2.0 * i * di * di) / (i.powi(3) * s.powi(3)),
            );
            e.concave_curvature = e.concave_curvature.max(sun).max(int);
        }
        e
    }

    /// Pitch tables (radii at `n` uniform angles of each body, mm) of sun, intermediate and planet,
    /// for the independent limit check. The intermediate's radius at its angle `ϑ = Φ(u)` is
    /// `a/(1 + i(u))` (a reflection of its body frame, which changes no |slope| nor curvature).
    pub fn tables(&self) -> [Vec<f64>; 3] {
        let r = &self.ratio;
        let n = r.i.len();
        let sun: Vec<f64> = r.i.iter().map(|i| self.a * i / (1.0 + i)).collect();
        let phi = r.integral();
        let mut hint = 0;
        let int: Vec<f64> = (0..n)
            .map(|m| {
                let u = invert(r, &phi, TAU * m as f64 / n as f64, &mut hint);
                self.a / (1.0 + r.value_at(u))
            })
            .collect();
        [sun.clone(), int, sun]
    }
}

/// The periodic cubic spline's basis: values, first and second derivatives of the spline through
/// each unit control vector, at the `N` grid angles (`basis[d][j·K + m]`).
pub struct Spline {
    pub n: usize,
    pub k: usize,
    basis: [Vec<f64>; 3],
}

impl Spline {
    pub fn new(n: usize, k: usize) -> Self {
        let h = TAU / k as f64;
        // Cyclic system M_{m−1} + 4M_m + M_{m+1} = 6(c_{m−1} − 2c_m + c_{m+1})/h², inverted once.
        let mut a = vec![vec![0.0f64; 2 * k]; k];
        for m in 0..k {
            a[m][m] = 4.0;
            a[m][(m + 1) % k] += 1.0;
            a[m][(m + k - 1) % k] += 1.0;
            a[m][k + m] = 1.0;
        }
        for col in 0..k {
            let p = (col..k)
                .max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs()))
                .unwrap();
            a.swap(col, p);
            let d = a[col][col];
            a[col].iter_mut().for_each(|v| *v /= d);
            for row in 0..k {
                if row != col {
                    let f = a[row][col];
                    let pivot = a[col].clone();
                    a[row].iter_mut().zip(&pivot).for_each(|(v, p)| *v -= f * p);
                }
            }
        }
        let mut basis = [vec![0.0; n * k], vec![0.0; n * k], vec![0.0; n * k]];
        for b in 0..k {
            let c: Vec<f64> = (0..k).map(|m| f64::from(u8::from(m == b))).collect();
            let rhs: Vec<f64> = (0..k)
                .map(|m| 6.0 * (c[(m + k - 1) % k] - 2.0 * c[m] + c[(m + 1) % k]) / (h * h))
                .collect();
            let mm: Vec<f64> = (0..k)
                .map(|r| (0..k).map(|q| a[r][k + q] * rhs[q]).sum())
                .collect();
            for j in 0..n {
                let u = TAU * j as f64 / n as f64;
                let seg = ((u / h).floor() as usize).min(k - 1);
                let t = u - seg as f64 * h;
                let nx = (seg + 1) % k;
                let (m0, m1, c0, c1) = (mm[seg], mm[nx], c[seg], c[nx]);
                let (p, q) = (c0 / h - m0 * h / 6.0, c1 / h - m1 * h / 6.0);
                let w = h - t;
                basis[0][j * k + b] =
                    m0 * w.powi(3) / (6.0 * h) + m1 * t.powi(3) / (6.0 * h) + p * w + q * t;
                basis[1][j * k + b] = -m0 * w * w / (2.0 * h) + m1 * t * t / (2.0 * h) - p + q;
                basis[2][j * k + b] = (m0 * w + m1 * t) / h;
            }
        }
        Self { n, k, basis }
    }

    /// The ratio of control values `c` (log i at the knots, before normalisation).
    pub fn ratio(&self, c: &[f64]) -> Ratio {
        let k = self.k;
        let g = |d: usize, j: usize| -> f64 {
            self.basis[d][j * k..(j + 1) * k]
                .iter()
                .zip(c)
                .map(|(b, c)| b * c)
                .sum()
        };
        let g0: Vec<[f64; 3]> = (0..self.n).map(|j| [g(0, j), g(1, j), g(2, j)]).collect();
        let e: Vec<f64> = g0.iter().map(|g| g[0].exp()).collect();
        let mean = e.iter().sum::<f64>() / self.n as f64;
        let i: Vec<f64> = e.iter().map(|e| e / mean).collect();
        Ratio {
            di: i.iter().zip(&g0).map(|(i, g)| i * g[1]).collect(),
            ddi: i
                .iter()
                .zip(&g0)
                .map(|(i, g)| i * (g[2] + g[1] * g[1]))
                .collect(),
            i,
        }
    }

    /// Least-squares control values whose spline is closest to `log_i` (samples on the grid).
    pub fn project(&self, log_i: &[f64]) -> Vec<f64> {
        let k = self.k;
        let b = &self.basis[0];
        let mut a = vec![vec![0.0; k + 1]; k];
        for j in 0..self.n {
            let row = &b[j * k..(j + 1) * k];
            for p in 0..k {
                for q in 0..k {
                    a[p][q] += row[p] * row[q];
                }
                a[p][k] += row[p] * log_i[j];
            }
        }
        for col in 0..k {
            let d = a[col][col];
            a[col].iter_mut().for_each(|v| *v /= d);
            for row in 0..k {
                if row != col {
                    let f = a[row][col];
                    let pivot = a[col].clone();
                    a[row].iter_mut().zip(&pivot).for_each(|(v, p)| *v -= f * p);
                }
            }
        }
        a.iter().map(|r| r[k]).collect()
    }
}
