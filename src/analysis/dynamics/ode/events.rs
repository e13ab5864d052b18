//! State-event location on DOPRI5's dense output: restriction of the quartic interpolant to a
//! sub-interval and Illinois false position on an event function.

use super::{DenseStep, EventFn};

#[allow(clippy::needless_range_loop)] // one index over ten parallel coefficient arrays
pub(super) fn restrict(d: &DenseStep, te: f64) -> [Vec<f64>; 5] {
    // y(θ) = r1 + θ r2 + θ(1−θ) r3 + θ²(1−θ) r4 + θ²(1−θ)² r5 is a quartic in θ; on the
    // sub-interval θ = s·θ', so expand in powers, scale by s^j and convert back.
    let n = d.r[0].len();
    let s = (te - d.t) / d.h;
    let mut out: [Vec<f64>; 5] = std::array::from_fn(|_| vec![0.0; n]);
    for i in 0..n {
        let (r1, r2, r3, r4, r5) = (d.r[0][i], d.r[1][i], d.r[2][i], d.r[3][i], d.r[4][i]);
        let p = [r1, r2 + r3, -r3 + r4 + r5, -r4 - 2.0 * r5, r5];
        let q: Vec<f64> = (0..5).map(|j| p[j] * s.powi(j as i32)).collect();
        let b5 = q[4];
        let b4 = -q[3] - 2.0 * b5;
        let b3 = b4 + b5 - q[2];
        let b2 = q[1] - b3;
        out[0][i] = q[0];
        out[1][i] = b2;
        out[2][i] = b3;
        out[3][i] = b4;
        out[4][i] = b5;
    }
    out
}

/// Illinois false position on the dense output.
pub(super) fn locate(
    g: EventFn<'_>,
    d: &DenseStep,
    mut a: f64,
    mut b: f64,
    mut ga: f64,
    mut gb: f64,
    y: &mut [f64],
) -> f64 {
    let mut side = 0;
    for _ in 0..100 {
        let c = (a * gb - b * ga) / (gb - ga);
        if !(c > a && c < b) || (b - a) <= 1e-15 * b.abs().max(1e-12) {
            break;
        }
        d.eval(c, y);
        let gc = g(c, y);
        if gc == 0.0 {
            return c;
        }
        if gc.signum() == gb.signum() {
            b = c;
            gb = gc;
            if side == 1 {
                ga *= 0.5;
            }
            side = 1;
        } else {
            a = c;
            ga = gc;
            if side == -1 {
                gb *= 0.5;
            }
            side = -1;
        }
        if (b - a) < 1e-13 * d.h.abs() {
            break;
        }
    }
    b
}
