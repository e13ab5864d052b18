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
//! The Dormand–Prince stepper lives in `dopri5`, [`rk4`](fn@rk4) in `rk4`, the event location on
//! the dense output in `events`.

mod dopri5;
mod events;
mod rk4;

pub use rk4::rk4;

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
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, schemars::JsonSchema)]
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

    /// `y′ = cos t`, except that the force cannot be evaluated (NaN) in the last 5 % of `tiny`
    /// before the breakpoint `BP`: the step onto it evaluates its last stages there and is
    /// rejected.
    struct NearSwitch;
    const NEAR_T0: f64 = 1.0;
    const NEAR_T1: f64 = 2.0;
    const NEAR_TINY: f64 = 1e-13 * NEAR_T1; // the integrator's own `tiny`
    const NEAR_BP: f64 = NEAR_T0 + 1.1 * NEAR_TINY;
    impl OdeSystem for NearSwitch {
        fn dim(&self) -> usize {
            1
        }
        fn rhs(&self, t: f64, _y: &[f64], dy: &mut [f64]) {
            let bad = t > NEAR_BP - 0.05 * NEAR_TINY && t <= NEAR_BP;
            dy[0] = if bad { f64::NAN } else { t.cos() };
        }
    }

    /// A step rejected just before a breakpoint (within `tiny` of it) shrinks below it and is
    /// taken; stretching the shrunk step back onto the breakpoint retried the same rejected
    /// step until the step budget ran out (the rotor at `rtol = 1e-7` spent 6 minutes so).
    #[test]
    fn a_step_rejected_just_before_a_breakpoint_shrinks_below_it() {
        let s = Dopri5::new(1e-10, 1e-12).unwrap();
        let mut y = [NEAR_T0.sin()];
        let st = s
            .integrate(
                &OdeProblem::new(&NearSwitch, NEAR_T0, NEAR_T1).with_breakpoints(&[NEAR_BP]),
                &mut y,
                &mut |_| {},
            )
            .unwrap();
        assert!(st.rejected >= 1 && st.rejected < 20, "{st:?}");
        assert!((y[0] - NEAR_T1.sin()).abs() < 1e-9, "{}", y[0]);
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
