//! The adaptive Dormand–Prince 5(4) stepper of [`Dopri5`]: its tableau, the step loop split at
//! breakpoints and events, the embedded error estimate and Hairer's dense output.

use super::events::{locate, restrict};
use super::{DenseStep, Dopri5, EventFn, NUDGE, OdeError, OdeProblem, OdeStats, OdeSystem};

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
/// `g_start` holds the functions' values at `ta` when known (the last step's `g_end`), `g_end`
/// receives them at `tb`; `yev` is scratch.
fn first_event(
    events: &[EventFn<'_>],
    dense: &DenseStep,
    (ta, ya): (f64, &[f64]),
    (tb, yb): (f64, &[f64]),
    (g_start, g_end): (Option<&[f64]>, &mut [f64]),
    yev: &mut [f64],
) -> Option<f64> {
    let h = dense.h;
    let mut t_ev: Option<f64> = None;
    for (i, g) in events.iter().enumerate() {
        let ga = g_start.map_or_else(|| g(ta, ya), |v| v[i]);
        let gb = g(tb, yb);
        g_end[i] = gb;
        if ga != 0.0 && ga.signum() != gb.signum() && gb != 0.0 || (ga != 0.0 && gb == 0.0) {
            let te = locate(*g, dense, ta, tb, ga, gb, yev);
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
        let mut shrunk_at_stop = false;
        // the event functions at the end of the last accepted step, while it is the start of
        // this one (not after a restart)
        let mut g_prev = vec![0.0; events.len()];
        let mut g_next = vec![0.0; events.len()];
        let mut g_known = false;
        let mut bp = breakpoints
            .iter()
            .copied()
            .filter(|&b| b > t0 && b < t1)
            .peekable();
        let tiny = 1e-13 * (t1 - t0).abs().max(t1.abs());
        while t < t1 - tiny {
            // A switch within `tiny` ahead is reached by a restart on its far side: a step across
            // it would hold its jump, which no step size resolves at tight tolerances (the state
            // moves by less than `tiny·|y′|` meanwhile).
            while let Some(b) = bp.next_if(|&b| b <= t + tiny) {
                if b > t {
                    t = b;
                    fresh = true;
                    g_known = false;
                }
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
            // A step that nearly reaches the switch is stretched onto it, unless a step onto it
            // was just rejected: stretching the shrunk step back would retry the same rejected
            // step for ever (a switch closer than `tiny` plus the shrunk step).
            if t + h >= t_stop || (!shrunk_at_stop && t + h >= t_stop - tiny) {
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
                shrunk_at_stop = hit_stop;
                continue;
            }
            if err > 1.0 {
                st.rejected += 1;
                h *= (0.9 * err.powf(-0.2)).max(0.2);
                shrunk_at_stop = hit_stop;
                continue;
            }
            shrunk_at_stop = false;
            st.accepted += 1;
            let dense = self.dense(t, h, y, &ws.ynew, &ws.k);
            let h_used = h;
            let t_ev = first_event(
                events,
                &dense,
                (t, y),
                (t + h, &ws.ynew),
                (g_known.then_some(&g_prev[..]), &mut g_next),
                &mut ws.yev,
            );
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
                g_known = false;
                h = (te - part.t).max(h_used * 0.1);
                continue;
            }
            on_step(&dense);
            y.copy_from_slice(&ws.ynew);
            t += h;
            std::mem::swap(&mut g_prev, &mut g_next);
            g_known = !hit_stop;
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
