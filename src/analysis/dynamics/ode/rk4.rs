//! Fixed-step classical RK4 (docs/math/companion.md §B.11), with steps optionally aligned to the breakpoints.

use super::{NUDGE, OdeStats, OdeSystem};

/// Fixed-step classical RK4: `steps` equal steps per interval between consecutive breakpoints
/// when `align` (restores 4th order across switches), otherwise `ceil((t1−t0)/h)` uniform steps
/// of nominal size `h` ignoring the switches. `on_step(t, y)` is called after every step.
pub fn rk4(
    sys: &dyn OdeSystem,
    t0: f64,
    t1: f64,
    h: f64,
    y: &mut [f64],
    breakpoints: Option<&[f64]>,
    on_step: &mut dyn FnMut(f64, &[f64]),
) -> OdeStats {
    let n = sys.dim();
    let mut st = OdeStats::default();
    let mut knots = vec![t0];
    if let Some(bps) = breakpoints {
        knots.extend(
            bps.iter()
                .copied()
                .filter(|&b| b > t0 + 1e-12 * h && b < t1 - 1e-12 * h),
        );
    }
    knots.push(t1);
    let (mut k1, mut k2, mut k3, mut k4, mut yt) = (
        vec![0.0; n],
        vec![0.0; n],
        vec![0.0; n],
        vec![0.0; n],
        vec![0.0; n],
    );
    for w in knots.windows(2) {
        let (a, b) = (w[0], w[1]);
        let m = ((b - a) / h - 1e-9).ceil().max(1.0) as usize;
        let hh = (b - a) / m as f64;
        for s in 0..m {
            let t = a + s as f64 * hh;
            let (ta, tb) = if breakpoints.is_some() {
                (
                    if s == 0 { t + NUDGE * hh } else { t },
                    if s + 1 == m {
                        t + hh * (1.0 - NUDGE)
                    } else {
                        t + hh
                    },
                )
            } else {
                (t, t + hh)
            };
            sys.rhs(ta, y, &mut k1);
            for i in 0..n {
                yt[i] = y[i] + 0.5 * hh * k1[i];
            }
            sys.rhs(t + 0.5 * hh, &yt, &mut k2);
            for i in 0..n {
                yt[i] = y[i] + 0.5 * hh * k2[i];
            }
            sys.rhs(t + 0.5 * hh, &yt, &mut k3);
            for i in 0..n {
                yt[i] = y[i] + hh * k3[i];
            }
            sys.rhs(tb, &yt, &mut k4);
            for i in 0..n {
                y[i] += hh / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
            st.rhs_evals += 4;
            st.accepted += 1;
            on_step(if s + 1 == m { b } else { t + hh }, y);
        }
    }
    st
}
