//! Explicit integrators for the dynamics module (docs/math/companion.md §B.11): an adaptive Dormand–Prince 5(4)
//! with Hairer's 4th-order dense output, integration split at known breakpoints (the RK is
//! restarted with a fresh first stage after every switch), state-event location on the dense
//! output (Illinois false position), and a fixed-step classical RK4 whose steps can be aligned to
//! the breakpoints.
//!
//! This is a compact own implementation (≈ 300 lines) rather than the `differential-equations`
//! crate: splitting at breakpoints, restarting after events and counting right-hand-side
//! evaluations needs full control of the step loop.

//!
//! [`rk4`](fn@rk4) lives in `rk4`, the event location on the dense output in `events`.

mod events;
mod rk4;

pub use rk4::rk4;

use events::{locate, restrict};

/// A first-order system `y' = f(t, y)`.
pub trait OdeSystem {
    /// State dimension.
    fn dim(&self) -> usize;
    /// Writes `f(t, y)` into `dy`.
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]);
}

/// Step-size control settings of [`Dopri5`].
#[derive(Debug, Clone, Copy)]
pub struct Dopri5 {
    rtol: f64,
    atol: f64,
    h_max: f64,
    max_steps: u64,
}

/// Invalid integrator configuration.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum OdeError {
    /// A tolerance or step bound is not a positive finite number.
    #[error("integrator setting `{name}` must be a positive finite number, got {value}")]
    BadSetting {
        /// Setting name.
        name: &'static str,
        /// Offending value.
        value: f64,
    },
    /// The step size underflowed or the step budget ran out.
    #[error("integration failed at t = {t} s: {reason}")]
    Failed {
        /// Time reached, s.
        t: f64,
        /// Why.
        reason: String,
    },
}

/// Counters of one integration.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct OdeStats {
    /// Right-hand-side evaluations.
    pub rhs_evals: u64,
    /// Accepted steps.
    pub accepted: u64,
    /// Rejected steps.
    pub rejected: u64,
    /// Located state events.
    pub events: u64,
}

impl std::ops::AddAssign for OdeStats {
    fn add_assign(&mut self, o: Self) {
        self.rhs_evals += o.rhs_evals;
        self.accepted += o.accepted;
        self.rejected += o.rejected;
        self.events += o.events;
    }
}

/// Relative offset used to evaluate a piecewise right-hand side on the correct side of a switch.
const NUDGE: f64 = 1e-9;
const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const A71: f64 = 35.0 / 384.0;
const A73: f64 = 500.0 / 1113.0;
const A74: f64 = 125.0 / 192.0;
const A75: f64 = -2187.0 / 6784.0;
const A76: f64 = 11.0 / 84.0;
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

/// Dense output of one accepted step on `[t, t + h]` (Hairer's 4th-order continuous extension).
#[derive(Debug, Clone)]
pub struct DenseStep {
    t: f64,
    h: f64,
    r: [Vec<f64>; 5],
}

impl DenseStep {
    /// Start of the step, s.
    pub fn t_start(&self) -> f64 {
        self.t
    }
    /// End of the step, s.
    pub fn t_end(&self) -> f64 {
        self.t + self.h
    }
    /// Interpolated state at `t` (inside the step) into `out`.
    pub fn eval(&self, t: f64, out: &mut [f64]) {
        let th = if self.h == 0.0 {
            0.0
        } else {
            (t - self.t) / self.h
        };
        let th1 = 1.0 - th;
        let [r1, r2, r3, r4, r5] = &self.r;
        for i in 0..out.len() {
            out[i] = r1[i] + th * (r2[i] + th1 * (r3[i] + th * (r4[i] + th1 * r5[i])));
        }
    }
}

/// A scalar state-event function `g(t, y)`; an event is a sign change of `g` inside a step.
pub type EventFn<'a> = &'a dyn Fn(f64, &[f64]) -> f64;

/// One integration task of [`Dopri5::integrate`]: a system over a time span, with its switches.
#[derive(Clone, Copy)]
pub struct OdeProblem<'a> {
    /// The right-hand side.
    pub system: &'a dyn OdeSystem,
    /// Start time, s.
    pub t0: f64,
    /// End time, s (> `t0`).
    pub t1: f64,
    /// Known switch times of the right-hand side, s, sorted (those outside `(t0, t1)` are
    /// ignored): the integration stops and restarts with a fresh first stage at each.
    pub breakpoints: &'a [f64],
    /// State-event functions: a step is cut at the first located zero and restarted there.
    pub events: &'a [EventFn<'a>],
}

impl<'a> OdeProblem<'a> {
    /// `system` on `[t0, t1]` (s) without breakpoints or events.
    #[must_use]
    pub fn new(system: &'a dyn OdeSystem, t0: f64, t1: f64) -> Self {
        Self {
            system,
            t0,
            t1,
            breakpoints: &[],
            events: &[],
        }
    }

    /// With the switch times `breakpoints` (s, sorted).
    #[must_use]
    pub fn with_breakpoints(mut self, breakpoints: &'a [f64]) -> Self {
        self.breakpoints = breakpoints;
        self
    }

    /// With the state-event functions `events`.
    #[must_use]
    pub fn with_events(mut self, events: &'a [EventFn<'a>]) -> Self {
        self.events = events;
        self
    }
}

/// The scratch vectors of [`Dopri5::integrate`], one state long each.
struct Workspace {
    /// The seven stage derivatives (FSAL: `k[6]` becomes the next step's `k[0]`).
    k: Vec<Vec<f64>>,
    /// The argument of the current stage.
    ytmp: Vec<f64>,
    /// The 5th-order solution at the end of the step.
    ynew: Vec<f64>,
    /// The state at a located event.
    yev: Vec<f64>,
}

impl Workspace {
    fn new(n: usize) -> Self {
        Self {
            k: (0..7).map(|_| vec![0.0; n]).collect(),
            ytmp: vec![0.0; n],
            ynew: vec![0.0; n],
            yev: vec![0.0; n],
        }
    }
}

/// The step after an accepted one of `h_used` s with error norm `err`: `h·0.9·err^(−1/5)`,
/// growing at most 5× and shrinking at most 5×; a step that ended on a switch does not shrink.
fn next_step(err: f64, h_used: f64, hit_stop: bool) -> f64 {
    let fac = (0.9 * err.max(1e-10).powf(-0.2)).clamp(0.2, 5.0);
    let h = h_used * fac;
    if hit_stop { h.max(h_used) } else { h }
}

/// The earliest located zero (s) inside the accepted step `(ta, ya)` → `(tb, yb)` of any event
/// function that changes sign over it (or reaches zero at its end), on its dense output;
/// `yev` is scratch.
fn first_event(
    events: &[EventFn<'_>],
    dense: &DenseStep,
    (ta, ya): (f64, &[f64]),
    (tb, yb): (f64, &[f64]),
    yev: &mut [f64],
) -> Option<f64> {
    let h = dense.h;
    let mut t_ev: Option<f64> = None;
    for g in events {
        let ga = g(ta, ya);
        let gb = g(tb, yb);
        if ga != 0.0 && ga.signum() != gb.signum() && gb != 0.0 || (ga != 0.0 && gb == 0.0) {
            let te = locate(g, dense, ta, tb, ga, gb, yev);
            if te > ta + 1e-9 * h && t_ev.is_none_or(|x| te < x) {
                t_ev = Some(te);
            }
        }
    }
    t_ev
}

impl Dopri5 {
    /// Adaptive DOPRI5 with relative and absolute tolerances (per component:
    /// `sc = atol + rtol·max(|y0|, |y1|)`, RMS norm).
    pub fn new(rtol: f64, atol: f64) -> Result<Self, OdeError> {
        for (name, value) in [("rtol", rtol), ("atol", atol)] {
            if !(value.is_finite() && value > 0.0) {
                return Err(OdeError::BadSetting { name, value });
            }
        }
        Ok(Self {
            rtol,
            atol,
            h_max: f64::INFINITY,
            max_steps: 50_000_000,
        })
    }

    /// Bounds the step, s (used for smooth but fast-varying forces such as Hertz bearings).
    pub fn with_max_step(mut self, h_max: f64) -> Result<Self, OdeError> {
        if !(h_max > 0.0) {
            return Err(OdeError::BadSetting {
                name: "h_max",
                value: h_max,
            });
        }
        self.h_max = h_max;
        Ok(self)
    }

    /// Integrates `problem` from its `t0` to its `t1`, restarting at every breakpoint and at
    /// every located zero of an event function. `y` holds the initial state and receives the
    /// final one; `on_step` receives every accepted step's dense output.
    pub fn integrate(
        &self,
        problem: &OdeProblem<'_>,
        y: &mut [f64],
        on_step: &mut dyn FnMut(&DenseStep),
    ) -> Result<OdeStats, OdeError> {
        let &OdeProblem {
            system: sys,
            t0,
            t1,
            breakpoints,
            events,
        } = problem;
        let mut st = OdeStats::default();
        let mut ws = Workspace::new(sys.dim());
        let mut t = t0;
        let mut h = 0.0_f64;
        let mut fresh = true;
        let mut bp = breakpoints
            .iter()
            .copied()
            .filter(|&b| b > t0 && b < t1)
            .peekable();
        let tiny = 1e-13 * (t1 - t0).abs().max(t1.abs());
        while t < t1 - tiny {
            while bp.peek().is_some_and(|&b| b <= t + tiny) {
                bp.next();
            }
            let t_stop = bp.peek().copied().unwrap_or(t1);
            if fresh {
                // restart after a switch: evaluate just inside the new piece
                sys.rhs(t + NUDGE * (t_stop - t), y, &mut ws.k[0]);
                st.rhs_evals += 1;
                if h == 0.0 {
                    h = self.initial_step(t, y, &ws.k[0]);
                }
                fresh = false;
            }
            h = h.min(self.h_max);
            let mut hit_stop = false;
            if t + h >= t_stop - tiny {
                h = t_stop - t;
                hit_stop = true;
            }
            self.check_step(&st, t, h)?;
            // a step that ends on a switch evaluates its last stages just before it
            let t_end_eval = if hit_stop {
                t + h * (1.0 - NUDGE)
            } else {
                t + h
            };
            self.stages(sys, t, h, t_end_eval, y, &mut ws);
            st.rhs_evals += 6;
            let err = self.error_norm(h, y, &ws);
            if !err.is_finite() {
                st.rejected += 1;
                h *= 0.2;
                continue;
            }
            if err > 1.0 {
                st.rejected += 1;
                h *= (0.9 * err.powf(-0.2)).max(0.2);
                continue;
            }
            st.accepted += 1;
            let dense = self.dense(t, h, y, &ws.ynew, &ws.k);
            let h_used = h;
            let t_ev = first_event(events, &dense, (t, y), (t + h, &ws.ynew), &mut ws.yev);
            if let Some(te) = t_ev.filter(|&te| te < t + h) {
                dense.eval(te, &mut ws.yev);
                let part = DenseStep {
                    t,
                    h: te - t,
                    r: restrict(&dense, te),
                };
                on_step(&part);
                y.copy_from_slice(&ws.yev);
                t = te;
                st.events += 1;
                fresh = true;
                h = (te - part.t).max(h_used * 0.1);
                continue;
            }
            on_step(&dense);
            y.copy_from_slice(&ws.ynew);
            t += h;
            if hit_stop {
                t = t_stop;
                fresh = true;
            } else {
                ws.k.swap(0, 6);
            }
            h = next_step(err, h_used, hit_stop);
        }
        Ok(st)
    }

    /// Refuses a step below `1e-14·max(|t|, 1e-9)` s or beyond the step budget.
    fn check_step(&self, st: &OdeStats, t: f64, h: f64) -> Result<(), OdeError> {
        if st.accepted + st.rejected > self.max_steps || h < 1e-14 * t.abs().max(1e-9) {
            return Err(OdeError::Failed {
                t,
                reason: format!("step size {h:e} s too small or step budget exhausted"),
            });
        }
        Ok(())
    }

    /// Stages 2–7 of one Dormand–Prince step of size `h` (s) from `(t, y)`, `ws.k[0]` holding
    /// `f(t, y)`: fills `ws.k[1..7]` and the 5th-order solution `ws.ynew`; the last two stages
    /// are evaluated at `t_end_eval` (just before a switch that ends the step).
    fn stages(
        &self,
        sys: &dyn OdeSystem,
        t: f64,
        h: f64,
        t_end_eval: f64,
        y: &[f64],
        ws: &mut Workspace,
    ) {
        let n = y.len();
        let Workspace { k, ytmp, ynew, .. } = ws;
        let (k1, rest) = k.split_at_mut(1);
        let k1 = &k1[0];
        for i in 0..n {
            ytmp[i] = y[i] + h * A21 * k1[i];
        }
        sys.rhs(t + C2 * h, ytmp, &mut rest[0]);
        for i in 0..n {
            ytmp[i] = y[i] + h * (A31 * k1[i] + A32 * rest[0][i]);
        }
        sys.rhs(t + C3 * h, ytmp, &mut rest[1]);
        for i in 0..n {
            ytmp[i] = y[i] + h * (A41 * k1[i] + A42 * rest[0][i] + A43 * rest[1][i]);
        }
        sys.rhs(t + C4 * h, ytmp, &mut rest[2]);
        for i in 0..n {
            ytmp[i] =
                y[i] + h * (A51 * k1[i] + A52 * rest[0][i] + A53 * rest[1][i] + A54 * rest[2][i]);
        }
        sys.rhs(t + C5 * h, ytmp, &mut rest[3]);
        for i in 0..n {
            ytmp[i] = y[i]
                + h * (A61 * k1[i]
                    + A62 * rest[0][i]
                    + A63 * rest[1][i]
                    + A64 * rest[2][i]
                    + A65 * rest[3][i]);
        }
        sys.rhs(t_end_eval, ytmp, &mut rest[4]);
        for i in 0..n {
            ynew[i] = y[i]
                + h * (A71 * k1[i]
                    + A73 * rest[1][i]
                    + A74 * rest[2][i]
                    + A75 * rest[3][i]
                    + A76 * rest[4][i]);
        }
        sys.rhs(t_end_eval, ynew, &mut rest[5]);
    }

    /// RMS of the embedded 4th/5th-order difference over `sc = atol + rtol·max(|y|, |y_new|)`
    /// (a step is accepted at ≤ 1).
    fn error_norm(&self, h: f64, y: &[f64], ws: &Workspace) -> f64 {
        let n = y.len();
        let k = &ws.k;
        let mut err = 0.0;
        for i in 0..n {
            let e = h
                * (E1 * k[0][i]
                    + E3 * k[2][i]
                    + E4 * k[3][i]
                    + E5 * k[4][i]
                    + E6 * k[5][i]
                    + E7 * k[6][i]);
            let sc = self.atol + self.rtol * y[i].abs().max(ws.ynew[i].abs());
            err += (e / sc) * (e / sc);
        }
        (err / n as f64).sqrt()
    }

    fn initial_step(&self, t: f64, y: &[f64], f0: &[f64]) -> f64 {
        let n = y.len() as f64;
        let (mut d0, mut d1) = (0.0, 0.0);
        for i in 0..y.len() {
            let sc = self.atol + self.rtol * y[i].abs();
            d0 += (y[i] / sc).powi(2);
            d1 += (f0[i] / sc).powi(2);
        }
        let (d0, d1) = ((d0 / n).sqrt(), (d1 / n).sqrt());
        let h = if d0 < 1e-5 || d1 < 1e-5 {
            1e-6
        } else {
            0.01 * d0 / d1
        };
        let _ = t;
        h.min(self.h_max)
    }

    fn dense(&self, t: f64, h: f64, y: &[f64], ynew: &[f64], k: &[Vec<f64>]) -> DenseStep {
        let n = y.len();
        let mut r: [Vec<f64>; 5] = std::array::from_fn(|_| vec![0.0; n]);
        for i in 0..n {
            let ydiff = ynew[i] - y[i];
            let bspl = h * k[0][i] - ydiff;
            r[0][i] = y[i];
            r[1][i] = ydiff;
            r[2][i] = bspl;
            r[3][i] = ydiff - h * k[6][i] - bspl;
            r[4][i] = h
                * (D1 * k[0][i]
                    + D3 * k[2][i]
                    + D4 * k[3][i]
                    + D5 * k[4][i]
                    + D6 * k[5][i]
                    + D7 * k[6][i]);
        }
        DenseStep { t, h, r }
    }
}

/// Re-parametrises a dense step onto `[t, te]` (exact: the interpolant is a quartic in θ).
#[cfg(test)]
mod tests {
    use super::*;

    struct Osc;
    impl OdeSystem for Osc {
        fn dim(&self) -> usize {
            2
        }
        fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
            dy[0] = y[1];
            dy[1] = -y[0];
        }
    }

    #[test]
    fn dopri5_harmonic_oscillator_and_dense_output() {
        let s = Dopri5::new(1e-10, 1e-12).unwrap();
        let mut y = [1.0, 0.0];
        let mut max_dense_err = 0.0_f64;
        let mut out = [0.0; 2];
        let st = s
            .integrate(
                &OdeProblem::new(&Osc, 0.0, 10.0).with_breakpoints(&[3.0, 7.0]),
                &mut y,
                &mut |d| {
                    let tm = 0.5 * (d.t_start() + d.t_end());
                    d.eval(tm, &mut out);
                    max_dense_err = max_dense_err.max((out[0] - tm.cos()).abs());
                },
            )
            .unwrap();
        assert!((y[0] - 10f64.cos()).abs() < 1e-8, "{y:?}");
        assert!(max_dense_err < 1e-8, "{max_dense_err}");
        assert!(st.rhs_evals > 100);
    }

    #[test]
    fn event_location_and_restricted_dense() {
        let s = Dopri5::new(1e-10, 1e-12).unwrap();
        let mut y = [1.0, 0.0];
        let g = |_t: f64, y: &[f64]| y[0];
        let mut last_end = 0.0;
        let mut max_err = 0.0_f64;
        let mut out = [0.0; 2];
        let st = s
            .integrate(
                &OdeProblem::new(&Osc, 0.0, 2.0).with_events(&[&g]),
                &mut y,
                &mut |d| {
                    last_end = d.t_end();
                    for j in 0..=4 {
                        let tt = d.t_start() + (d.t_end() - d.t_start()) * j as f64 / 4.0;
                        d.eval(tt, &mut out);
                        max_err = max_err.max((out[0] - tt.cos()).abs());
                    }
                },
            )
            .unwrap();
        assert_eq!(st.events, 1);
        assert!(max_err < 1e-8, "{max_err}");
        assert!((y[0] - 2f64.cos()).abs() < 1e-8);
    }

    #[test]
    fn rk4_is_fourth_order() {
        let e = |h: f64| {
            let mut y = [1.0, 0.0];
            rk4(&Osc, 0.0, 5.0, h, &mut y, None, &mut |_, _| {});
            (y[0] - 5f64.cos()).abs()
        };
        let r = e(0.02) / e(0.01);
        assert!((r - 16.0).abs() < 1.0, "{r}");
    }
}
