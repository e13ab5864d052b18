//! Time integration of a model: the static equilibrium, the transient until the Poincaré map
//! settles, the recorded window ([`Run`]) with its DTE harmonics, and the energy audit (docs/math/companion.md §B.9-5).

use super::model::{self, Model, PairState};
use super::ode::{self, Dopri5, OdeProblem, OdeStats, OdeSystem};
use super::{DynamicsError, Method, RunOptions};
use crate::progress::Progress;
use nalgebra::DMatrix;
use serde::Serialize;

/// A recorded run.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct Run {
    /// Sample times, s (integer samples per mesh period over an integer number of periods).
    pub t_s: Vec<f64>,
    /// Dynamic transmission error δ = (y1−y2) + rb1θ1 − rb2θ2 − e(t), m.
    pub dte_m: Vec<f64>,
    /// Total mesh force, N.
    pub mesh_force_n: Vec<f64>,
    /// Full states [q, v] at the samples.
    pub states: Vec<Vec<f64>>,
    /// Integrator counters (transient + record).
    pub stats: OdeStats,
    /// Transient length, Poincaré periods.
    pub transient_periods: u32,
    /// Whether the Poincaré criterion was met.
    pub steady: bool,
    /// Last relative Poincaré change.
    pub poincare_change: f64,
    /// Samples per mesh period.
    pub samples_per_mesh: u32,
}

impl Run {
    /// Harmonic amplitudes of the DTE at k·f_mesh, k = 0..=kmax (k = 0: mean), m.
    #[must_use]
    pub fn dte_harmonics(&self, kmax: usize) -> Vec<f64> {
        harmonics(&self.dte_m, self.samples_per_mesh as usize, kmax)
    }

    /// Largest non-harmonic line of the DTE spectrum (not at a multiple of f_mesh), m.
    #[must_use]
    pub fn dte_non_harmonic(&self) -> f64 {
        let c = crate::math::periodic::fft_coefficients(&self.dte_m);
        let p = self.dte_m.len() / self.samples_per_mesh as usize;
        c.iter()
            .enumerate()
            .skip(1)
            .filter(|(i, _)| i % p != 0)
            .map(|(_, z)| 2.0 * z.norm())
            .fold(0.0, f64::max)
    }

    /// Half peak-to-peak DTE, m.
    #[must_use]
    pub fn dte_half_pp(&self) -> f64 {
        let (lo, hi) = min_max(&self.dte_m);
        0.5 * (hi - lo)
    }
}

fn min_max(v: &[f64]) -> (f64, f64) {
    v.iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        })
}

/// Amplitudes of the harmonics k·(1/period) of a signal sampled `spp` times per period over an
/// integer number of periods: `A_0 = mean`, `A_k = 2|c_{kP}|`.
#[must_use]
pub fn harmonics(y: &[f64], spp: usize, kmax: usize) -> Vec<f64> {
    let c = crate::math::periodic::fft_coefficients(y);
    let p = y.len() / spp.max(1);
    (0..=kmax)
        .map(|k| {
            c.get(k * p)
                .map_or(0.0, |z| if k == 0 { z.re } else { 2.0 * z.norm() })
        })
        .collect()
}

/// Mesh-level outputs at one state.
fn mesh_outputs(model: &Model, t: f64, y: &[f64]) -> (f64, f64) {
    let n = model.n();
    let mut ps = [PairState::default(); 2];
    let (np, _) = model.mesh.pairs(t, &y[..n], &y[n..], &mut ps);
    (
        model.mesh.dte(t, &y[..n]),
        ps[..np].iter().map(|p| p.force).sum(),
    )
}

/// Static equilibrium at t = 0 (no velocity): chord/Newton iteration on the force residual with a
/// finite-difference Jacobian and SVD pseudo-inverse (rigid-body modes get no correction); steps
/// are limited to 5 µm / 5 mrad. `tol_n`: residual tolerance, N.
#[must_use]
pub fn static_state(model: &Model, tol_n: f64) -> Vec<f64> {
    let n = model.n();
    let mut y = vec![0.0; 2 * n];
    let mut dy = vec![0.0; 2 * n];
    let force = |y: &[f64], dy: &mut [f64]| -> Vec<f64> {
        model.rhs(0.0, y, dy);
        (0..n).map(|i| dy[n + i] * model.mass[i]).collect()
    };
    for _ in 0..200 {
        let r = force(&y, &mut dy);
        let rn = r.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
        if rn < tol_n {
            break;
        }
        let h = 1e-9;
        let mut jac = DMatrix::zeros(n, n);
        for j in 0..n {
            let mut yp = y.clone();
            yp[j] += h;
            let rp = force(&yp, &mut dy);
            for i in 0..n {
                jac[(i, j)] = -(rp[i] - r[i]) / h;
            }
        }
        // mean stiffness where the tangent vanishes (backlash gap, bearing clearance)
        if let Some((k, _)) = model.linear_matrices() {
            for i in 0..n {
                if jac[(i, i)].abs() < 1e-6 * k[(i, i)].abs() {
                    jac += &k;
                    break;
                }
            }
        }
        let svd = jac.svd(true, true);
        let smax = svd.singular_values.max();
        let Ok(pinv) = svd.pseudo_inverse(1e-12 * smax) else {
            break;
        };
        let step = pinv * nalgebra::DVector::from_vec(r);
        let sm = step.amax();
        let scale = if sm > 5e-6 { 5e-6 / sm } else { 1.0 };
        for i in 0..n {
            y[i] += scale * step[i];
        }
    }
    y
}

/// Integrates `model` from state `y0` at t = 0: transient until the Poincaré map settles (or
/// `max_periods`), then records `record_mesh_periods` mesh periods at `samples_per_mesh`.
/// `progress` hears each finished Poincaré period.
pub fn simulate(
    model: &Model,
    y0: &[f64],
    opts: &RunOptions,
    progress: &Progress,
) -> Result<Run, DynamicsError> {
    opts.validate()?;
    let mut y = y0.to_vec();
    let tr = settle(model, &mut y, opts, progress)?;
    let spm = opts.samples_per_mesh as usize;
    let ns = spm * opts.record_mesh_periods as usize;
    let mut run = Run {
        t_s: Vec::with_capacity(ns),
        dte_m: Vec::with_capacity(ns),
        mesh_force_n: Vec::with_capacity(ns),
        states: Vec::with_capacity(ns),
        stats: tr.stats,
        transient_periods: tr.periods,
        steady: tr.steady,
        poincare_change: tr.change,
        samples_per_mesh: opts.samples_per_mesh,
    };
    record(model, tr.t_s, &mut y, opts, &mut run)?;
    Ok(run)
}

/// The end of the transient: where the Poincaré map settled (or gave up).
struct Transient {
    /// Time reached, s (a whole number of Poincaré periods).
    t_s: f64,
    /// Integrator counters of the transient.
    stats: OdeStats,
    /// Poincaré periods integrated.
    periods: u32,
    /// Whether the last change fell below `poincare_tol`.
    steady: bool,
    /// Relative change of the state over the last period.
    change: f64,
}

/// Integrates `y` Poincaré period by period from t = 0 until its relative change over a
/// period falls below `poincare_tol` (or `max_periods`); `progress` hears each period.
fn settle(
    model: &Model,
    y: &mut [f64],
    opts: &RunOptions,
    progress: &Progress,
) -> Result<Transient, DynamicsError> {
    let tp = model.poincare_period;
    let mut tr = Transient {
        t_s: 0.0,
        stats: OdeStats::default(),
        periods: 0,
        steady: false,
        change: f64::INFINITY,
    };
    let mut prev = y.to_vec();
    for k in 0..opts.max_periods {
        let t = tr.t_s;
        let st = advance(model, t, t + tp, y, opts, &mut |_, _| {})?;
        tr.stats += st;
        tr.t_s += tp;
        tr.periods = k + 1;
        if y.iter().any(|x| !x.is_finite()) {
            return Err(DynamicsError::Diverged(tr.t_s));
        }
        tr.change = poincare_change(&prev, y);
        prev.copy_from_slice(y);
        progress.advance(1);
        if tr.change < opts.poincare_tol {
            tr.steady = true;
            break;
        }
    }
    Ok(tr)
}

/// Records `record_mesh_periods` mesh periods at `samples_per_mesh` from `(t_rec, y)` into
/// `run` (time, dynamic transmission error, mesh force, state), sampling the dense output.
fn record(
    model: &Model,
    t_rec: f64,
    y: &mut [f64],
    opts: &RunOptions,
    run: &mut Run,
) -> Result<(), DynamicsError> {
    let spm = opts.samples_per_mesh as usize;
    let ns = spm * opts.record_mesh_periods as usize;
    let dt = model.mesh.t0 / spm as f64;
    let push = |run: &mut Run, ts: f64, ys: &[f64]| {
        let (dte, fm) = mesh_outputs(model, ts, ys);
        run.t_s.push(ts);
        run.dte_m.push(dte);
        run.mesh_force_n.push(fm);
        run.states.push(ys.to_vec());
    };
    push(run, t_rec, y);
    let mut k = 1usize;
    let mut buf = vec![0.0; model.dim()];
    let t_end = t_rec + dt * ns as f64;
    let st = advance(
        model,
        t_rec,
        t_rec + dt * (ns - 1) as f64,
        y,
        opts,
        &mut |d, yend| {
            // d = (t_start, t_end, dense) ; sample inside
            match d {
                Sample::Dense(ds) => {
                    while k < ns {
                        let ts = t_rec + dt * k as f64;
                        if ts > ds.t_end() + 1e-12 * dt {
                            break;
                        }
                        ds.eval(ts, &mut buf);
                        push(run, ts, &buf);
                        k += 1;
                    }
                }
                Sample::Point(tt) => {
                    let ts = t_rec + dt * k as f64;
                    if k < ns && (tt - ts).abs() < 1e-9 * dt {
                        push(run, ts, yend);
                        k += 1;
                    }
                }
            }
        },
    )?;
    run.stats += st;
    if run.t_s.len() != ns
        || run
            .dte_m
            .iter()
            .chain(&run.mesh_force_n)
            .chain(run.states.iter().flatten())
            .any(|x| !x.is_finite())
    {
        return Err(DynamicsError::Diverged(t_end));
    }
    Ok(())
}

/// What the sampler receives from a step.
enum Sample<'a> {
    Dense(&'a ode::DenseStep),
    Point(f64),
}

fn advance(
    model: &Model,
    t0: f64,
    t1: f64,
    y: &mut [f64],
    opts: &RunOptions,
    on: &mut dyn FnMut(Sample<'_>, &[f64]),
) -> Result<OdeStats, DynamicsError> {
    match opts.method {
        Method::Dopri5 {
            rtol,
            atol,
            breakpoints,
            events,
        } => {
            let solver = Dopri5::new(rtol, atol)?;
            let solver = if model.max_step.is_finite() {
                solver.with_max_step(model.max_step)?
            } else {
                solver
            };
            let bps = if breakpoints {
                model.breakpoints(t0, t1)
            } else {
                Vec::new()
            };
            let n = model.n();
            let evs_q: Vec<model::StateEvent<'_>> = if events {
                model.terms.iter().flat_map(|t| t.events()).collect()
            } else {
                Vec::new()
            };
            // the model's events see the coordinates only
            let wrapped: Vec<model::StateEvent<'_>> = evs_q
                .iter()
                .map(|g| Box::new(move |t: f64, y: &[f64]| g(t, &y[..n])) as model::StateEvent<'_>)
                .collect();
            let refs: Vec<ode::EventFn<'_>> = wrapped
                .iter()
                .map(|b| b.as_ref() as ode::EventFn<'_>)
                .collect();
            let empty: [f64; 0] = [];
            let problem = OdeProblem::new(model, t0, t1)
                .with_breakpoints(&bps)
                .with_events(&refs);
            Ok(solver.integrate(&problem, y, &mut |d| on(Sample::Dense(d), &empty))?)
        }
        Method::Rk4 {
            steps_per_mesh,
            aligned,
        } => {
            // integrate sample interval by sample interval (samples are step ends); with
            // `aligned`, each interval is further split at the switches
            let h = model.mesh.t0 / f64::from(steps_per_mesh);
            let dt = model.mesh.t0 / f64::from(opts.samples_per_mesh);
            let nchunks = ((t1 - t0) / dt).round().max(1.0) as usize;
            let mut st = OdeStats::default();
            for c in 0..nchunks {
                let a = t0 + dt * c as f64;
                let b = if c + 1 == nchunks { t1 } else { a + dt };
                let bps = if aligned {
                    Some(model.breakpoints(a, b))
                } else {
                    None
                };
                st += ode::rk4(model, a, b, h, y, bps.as_deref(), &mut |_, _| {});
                on(Sample::Point(b), y);
            }
            Ok(st)
        }
    }
}

fn poincare_change(prev: &[f64], y: &[f64]) -> f64 {
    let n = y.len() / 2;
    let part = |r: std::ops::Range<usize>| {
        let scale = y[r.clone()]
            .iter()
            .fold(0.0_f64, |a, x| a.max(x.abs()))
            .max(1e-300);
        r.map(|i| (y[i] - prev[i]).abs()).fold(0.0, f64::max) / scale
    };
    part(0..n).max(part(n..2 * n))
}

/// Energy audit over `[0, t_end]` (docs/math/companion.md §B.9-5): integrates the model augmented with the energy source
/// `Σ(P + dV/dt)` and returns `(E(t_end) − E(0), ∫ sources, Σ jumps ΔV at the stiffness switches)`, J.
pub fn energy_audit(
    model: &Model,
    y0: &[f64],
    t_end: f64,
    rtol: f64,
    atol: f64,
) -> Result<(f64, f64, f64), DynamicsError> {
    let aug = model::EnergyAugmented(model);
    let m = model.dim();
    let mut y = y0.to_vec();
    y.push(0.0);
    let bps = model.breakpoints(0.0, t_end);
    let e0 = model.energy(1e-9 * model.mesh.t0, y0);
    let solver = Dopri5::new(rtol, atol)?;
    let mut jumps = 0.0;
    let mut t = 0.0;
    let mut knots = bps.clone();
    knots.push(t_end);
    let dt0 = 1e-9 * model.mesh.t0;
    for &tb in &knots {
        solver.integrate(&OdeProblem::new(&aug, t, tb), &mut y, &mut |_| {})?;
        if tb < t_end {
            jumps += model.energy(tb + dt0, &y[..m]) - model.energy(tb - dt0, &y[..m]);
        }
        t = tb;
    }
    // evaluate the end state on the side of the last piece (t_end may itself be a switch)
    Ok((model.energy(t_end - dt0, &y[..m]) - e0, y[m], jumps))
}
