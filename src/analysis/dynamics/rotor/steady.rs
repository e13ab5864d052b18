//! The periodic steady state of the rotor: whole turns integrated from the quasi-static state
//! until the state at φ = 0 repeats (a Poincaré section once a turn), each turn sampled at the
//! loads' travel angles and its contact changes recorded.
//!
//! Residual of a turn: `max_i |y_i(T) − y_i(0)| / max_i |y_i|`, the deviations and their rates
//! taken separately (the larger of the two).

use super::RotorError;
use super::model::{GapFn, RotorModel};
use super::scene::Settings;
use super::spec::RotorMethod;
use crate::analysis::dynamics::ode::{self, DenseStep, Dopri5, EventFn, OdeProblem, OdeStats};
use crate::progress::Progress;

/// A change of a mesh's contact flank (+1, −1, 0) at a time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Transition {
    /// Time, s.
    pub t: f64,
    /// Mesh 0 or 1.
    pub mesh: usize,
    /// Flank before.
    pub from: i8,
    /// Flank after.
    pub to: i8,
    /// Approach speed of the new flank (of +1 when the contact is lost), m/s.
    pub speed_m_s: f64,
    /// The largest force of the mesh from this change until the next one or the window, N.
    pub peak_n: f64,
}

/// One turn: the states at the samples and the contact changes.
#[derive(Debug, Clone, Default)]
pub(crate) struct Turn {
    /// Start time, s.
    pub t0: f64,
    /// States at the samples `t0 + k·T/n` (the model's whole state: with a drive, every arm's
    /// and the drive's).
    pub states: Vec<Vec<f64>>,
    /// Contact changes.
    pub transitions: Vec<Transition>,
}

/// The settled result.
#[derive(Debug, Clone)]
pub(crate) struct Steady {
    /// The last turn.
    pub turn: Turn,
    /// Turns integrated.
    pub turns: u32,
    /// The last residual.
    pub residual: f64,
    /// Whether it fell below the tolerance.
    pub settled: bool,
    /// The state at the end (for a warm start).
    pub end_state: Vec<f64>,
    /// Integrator counters.
    pub stats: OdeStats,
}

fn flanks(model: &RotorModel, t: f64, y: &[f64]) -> [i8; 2] {
    [0, 1].map(|j| {
        if model.gap(t, y, 2 * j) > 0.0 {
            1
        } else if model.gap(t, y, 2 * j + 1) > 0.0 {
            -1
        } else {
            0
        }
    })
}

/// Tracks samples and contact changes over the dense output of one turn.
struct Recorder<'a> {
    model: &'a RotorModel,
    turn: Turn,
    n: usize,
    dt: f64,
    next: usize,
    flank: [i8; 2],
    /// Open windows: (transition index, end time).
    open: Vec<(usize, f64)>,
    window_s: f64,
    buf: Vec<f64>,
}

impl Recorder<'_> {
    fn sample_until(&mut self, t_end: f64, eval: &mut dyn FnMut(f64, &mut [f64])) {
        while self.next < self.n {
            let ts = self.turn.t0 + self.dt * self.next as f64;
            if ts > t_end + 1e-12 * self.dt {
                break;
            }
            eval(ts, &mut self.buf);
            self.turn.states.push(self.buf.clone());
            self.next += 1;
        }
    }

    fn peaks(&mut self, ta: f64, tb: f64, eval: &mut dyn FnMut(f64, &mut [f64])) {
        if self.open.is_empty() {
            return;
        }
        for q in 1..=8 {
            let t = ta + (tb - ta) * f64::from(q) / 8.0;
            eval(t, &mut self.buf);
            let inst = self.model.instant(t, &self.buf);
            for &(i, end) in &self.open {
                if t <= end {
                    let tr = &mut self.turn.transitions[i];
                    tr.peak_n = tr.peak_n.max(inst.mesh[tr.mesh].force_n);
                }
            }
        }
        self.open.retain(|&(_, end)| end > tb);
    }

    fn contact(&mut self, t: f64, y: &[f64]) {
        let now = flanks(self.model, t, y);
        for (j, &flank_now) in now.iter().enumerate() {
            if flank_now != self.flank[j] {
                let inst = self.model.instant(t, y);
                self.open
                    .retain(|&(i, _)| self.turn.transitions[i].mesh != j);
                self.turn.transitions.push(Transition {
                    t,
                    mesh: j,
                    from: self.flank[j],
                    to: flank_now,
                    speed_m_s: inst.mesh[j].speed_m_s,
                    peak_n: inst.mesh[j].force_n,
                });
                if flank_now != 0 {
                    self.open
                        .push((self.turn.transitions.len() - 1, t + self.window_s));
                }
                self.flank[j] = flank_now;
            }
        }
    }

    fn on_dense(&mut self, d: &DenseStep) {
        let mut eval = |t: f64, out: &mut [f64]| d.eval(t, out);
        self.peaks(d.t_start(), d.t_end(), &mut eval);
        self.sample_until(d.t_end(), &mut eval);
        let mut y = vec![0.0; self.buf.len()];
        d.eval(d.t_end(), &mut y);
        self.contact(d.t_end(), &y);
    }
}

/// Integrates one turn from `(t0, y)`, recording `n` samples.
fn one_turn(
    model: &RotorModel,
    t0: f64,
    y: &mut [f64],
    n: usize,
    s: &Settings,
    window_s: f64,
) -> Result<(Turn, OdeStats), RotorError> {
    let tp = model.period_s();
    let t1 = t0 + tp;
    let mut rec = Recorder {
        model,
        turn: Turn {
            t0,
            states: Vec::with_capacity(n),
            transitions: Vec::new(),
        },
        n,
        dt: tp / n as f64,
        next: 0,
        flank: flanks(model, t0, y),
        open: Vec::new(),
        window_s,
        buf: vec![0.0; model.state_len()],
    };
    let bps = if s.breakpoints {
        model.breakpoints(t0, t1)
    } else {
        Vec::new()
    };
    let stats = match s.method {
        RotorMethod::Dopri5 => {
            let gaps: Vec<GapFn<'_>> = if s.events && model.has_backlash() {
                (0..model.gap_count())
                    .map(|w| Box::new(move |t: f64, y: &[f64]| model.gap(t, y, w)) as GapFn<'_>)
                    .collect()
            } else {
                Vec::new()
            };
            let refs: Vec<EventFn<'_>> = gaps.iter().map(|b| b.as_ref() as EventFn<'_>).collect();
            let solver = Dopri5::new(s.rtol, s.atol)?;
            let problem = OdeProblem::new(model, t0, t1)
                .with_breakpoints(&bps)
                .with_events(&refs);
            solver.integrate(&problem, y, &mut |d| rec.on_dense(d))?
        }
        RotorMethod::Rk4 => {
            let h = tp / f64::from(s.rk4_steps_per_turn);
            let mut st = OdeStats::default();
            let dt = tp / n as f64;
            rec.turn.states.push(y.to_vec());
            rec.next = 1;
            for c in 0..n {
                let a = t0 + dt * c as f64;
                let b = if c + 1 == n { t1 } else { a + dt };
                let local: Vec<f64> = bps.iter().copied().filter(|&x| x > a && x < b).collect();
                st += ode::rk4(
                    model,
                    a,
                    b,
                    h,
                    y,
                    s.breakpoints.then_some(local.as_slice()),
                    &mut |_, _| {},
                );
                if c + 1 < n {
                    rec.turn.states.push(y.to_vec());
                    rec.next += 1;
                }
                rec.contact(b, y);
            }
            st
        }
    };
    if y.iter().any(|v| !v.is_finite()) || rec.turn.states.len() != n {
        return Err(RotorError::Diverged(t1));
    }
    Ok((rec.turn, stats))
}

/// Relative change of the state over a turn (module docs); `omega` the carrier's nominal speed
/// (rad/s), for a drive's carrier speed `w`, taken as `w − Ω`.
pub(crate) fn residual(prev: &[f64], y: &[f64], omega: f64) -> f64 {
    let part = |idx: &[usize], offset: f64| {
        let scale = idx
            .iter()
            .fold(0.0_f64, |a, &i| a.max((y[i] - offset).abs()))
            .max(1e-300);
        idx.iter()
            .map(|&i| (y[i] - prev[i]).abs())
            .fold(0.0, f64::max)
            / scale
    };
    if y.len() == 4 {
        return part(&[0, 1], 0.0).max(part(&[2, 3], 0.0));
    }
    // with a drive: [the arms' four each, ψ, w]
    let arms = (y.len() - 2) / 4;
    let mut angles: Vec<usize> = (0..arms).flat_map(|k| [4 * k, 4 * k + 1]).collect();
    angles.push(4 * arms);
    let rates: Vec<usize> = (0..arms).flat_map(|k| [4 * k + 2, 4 * k + 3]).collect();
    part(&angles, 0.0)
        .max(part(&rates, 0.0))
        .max(part(&[4 * arms + 1], omega))
}

/// Turns from the state `y0` at t = 0 until the residual is below `s.poincare_tol` or
/// `s.max_turns`; `n` samples a turn; `window_s` the impact peaks' window, s; `progress` hears
/// every turn.
pub(crate) fn settle(
    model: &RotorModel,
    y0: &[f64],
    n: usize,
    s: &Settings,
    window_s: f64,
    progress: &Progress,
) -> Result<Steady, RotorError> {
    let mut y = y0.to_vec();
    let mut stats = OdeStats::default();
    let tp = model.period_s();
    let mut out = Steady {
        turn: Turn::default(),
        turns: 0,
        residual: f64::INFINITY,
        settled: false,
        end_state: y.clone(),
        stats,
    };
    for k in 0..s.max_turns {
        let prev = y.clone();
        let t0 = f64::from(k) * tp;
        let (turn, st) = one_turn(model, t0, &mut y, n, s, window_s)?;
        stats += st;
        out.turn = turn;
        out.turns = k + 1;
        out.residual = residual(&prev, &y, model.omega);
        progress.advance(1);
        if out.residual < s.poincare_tol {
            out.settled = true;
            break;
        }
    }
    out.end_state = y;
    out.stats = stats;
    Ok(out)
}
