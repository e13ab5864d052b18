//! Spur-gear pair nonlinear dynamics driven by scene files (spec `companion-methods.md` part B,
//! seed 001 = CN110162909B): the 16-DOF lumped-mass model with time-varying mesh stiffness,
//! static transmission error, tip relief, backlash, sliding friction, eccentricity, gravity,
//! shafts and nonlinear (Hertz) bearings. Every effect is off unless the scene names it (B.10);
//! the loader prunes the DOF set (16 / 6 / 4 / 2 / 1), builds the force-term list and the
//! breakpoint/event sets once.
//!
//! Units: scene files speak mm, µm, degrees, rpm; the library works in SI (m, kg, s, rad, N).

pub mod model;
pub mod ode;
pub mod scene;
pub mod tvms;

use model::{Model, PairState};
use nalgebra::{Complex, DMatrix};
use ode::{Dopri5, OdeError, OdeStats, OdeSystem};
use serde::Serialize;

pub use scene::{Derived, Scene, SceneError};

/// Errors of a dynamics run.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DynamicsError {
    /// Bad scene.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// Integrator failure or bad settings.
    #[error(transparent)]
    Ode(#[from] OdeError),
    /// The requested analysis needs a linear model.
    #[error("the linear analysis needs a linear model, but term `{0}` has no linear form")]
    NotLinear(String),
    /// A non-finite state appeared (diverging response).
    #[error("the response diverged (non-finite state) at t = {0} s")]
    Diverged(f64),
    /// A bad option value.
    #[error("option `{name}` = {value}: expected {expected}")]
    BadOption {
        /// Option.
        name: &'static str,
        /// Value.
        value: String,
        /// Expected form.
        expected: &'static str,
    },
}

/// Largest number of recorded samples of a run (`record_mesh_periods × samples_per_mesh`).
pub const MAX_RECORDED_SAMPLES: u64 = 2_000_000;

/// Largest transient length, Poincaré periods.
pub const MAX_TRANSIENT_PERIODS: u32 = 100_000;

/// Time integrator choice (B.11).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    /// Adaptive DOPRI5 with dense output.
    Dopri5 {
        /// Relative tolerance.
        rtol: f64,
        /// Absolute tolerance.
        atol: f64,
        /// Split at the known switch times.
        breakpoints: bool,
        /// Locate backlash contact loss / re-contact.
        events: bool,
    },
    /// Fixed-step classical RK4.
    Rk4 {
        /// Steps per mesh period.
        steps_per_mesh: u32,
        /// Align the steps to the switch times.
        aligned: bool,
    },
}

/// Run options (solver, steady state, recording).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunOptions {
    /// Integrator.
    pub method: Method,
    /// Poincaré steady-state tolerance (relative change per Poincaré period).
    pub poincare_tol: f64,
    /// Maximal transient, Poincaré periods (0: no transient).
    pub max_periods: u32,
    /// Recorded mesh periods.
    pub record_mesh_periods: u32,
    /// Samples per mesh period.
    pub samples_per_mesh: u32,
}

impl RunOptions {
    /// Options from the scene's `[solver]` and `[output]` tables.
    pub fn from_scene(s: &Scene) -> Result<Self, DynamicsError> {
        let v = &s.solver;
        let method = match v.method.as_str() {
            "auto" | "dopri5" | "linear" => Method::Dopri5 {
                rtol: v.rtol,
                atol: v.atol,
                breakpoints: v.breakpoints,
                events: v.events,
            },
            "rk4" => Method::Rk4 {
                steps_per_mesh: v.rk4_steps_per_mesh,
                aligned: v.breakpoints,
            },
            o => {
                return Err(DynamicsError::BadOption {
                    name: "solver.method",
                    value: o.into(),
                    expected: "\"auto\" | \"dopri5\" | \"rk4\" | \"linear\"",
                });
            }
        };
        let o = Self {
            method,
            poincare_tol: v.steady_state.poincare_tol,
            max_periods: v.steady_state.max_periods,
            record_mesh_periods: v.record_mesh_periods,
            samples_per_mesh: s.output.samples_per_mesh,
        };
        o.validate()?;
        Ok(o)
    }

    /// A fixed window without transient: integrate `mesh_periods` from the initial state and
    /// record them at `samples_per_mesh` (used for accuracy studies and benchmarks).
    #[must_use]
    pub fn window(method: Method, mesh_periods: u32, samples_per_mesh: u32) -> Self {
        Self {
            method,
            poincare_tol: 1.0,
            max_periods: 0,
            record_mesh_periods: mesh_periods,
            samples_per_mesh,
        }
    }

    fn validate(&self) -> Result<(), DynamicsError> {
        if self.samples_per_mesh < 2 {
            return Err(DynamicsError::BadOption {
                name: "output.samples_per_mesh",
                value: self.samples_per_mesh.to_string(),
                expected: "an integer ≥ 2",
            });
        }
        let samples = u64::from(self.record_mesh_periods) * u64::from(self.samples_per_mesh);
        if samples > MAX_RECORDED_SAMPLES {
            return Err(DynamicsError::BadOption {
                name: "solver.record_mesh_periods × output.samples_per_mesh",
                value: samples.to_string(),
                expected: "at most 2 000 000 recorded samples",
            });
        }
        if self.max_periods > MAX_TRANSIENT_PERIODS {
            return Err(DynamicsError::BadOption {
                name: "solver.steady_state.max_periods",
                value: self.max_periods.to_string(),
                expected: "at most 100 000 Poincaré periods",
            });
        }
        if self.record_mesh_periods < 1 {
            return Err(DynamicsError::BadOption {
                name: "solver.record_mesh_periods",
                value: "0".into(),
                expected: "an integer ≥ 1",
            });
        }
        if !(self.poincare_tol > 0.0) {
            return Err(DynamicsError::BadOption {
                name: "solver.steady_state.poincare_tol",
                value: self.poincare_tol.to_string(),
                expected: "a positive number",
            });
        }
        match self.method {
            Method::Dopri5 { rtol, atol, .. } => {
                Dopri5::new(rtol, atol)?;
            }
            Method::Rk4 { steps_per_mesh, .. } if !(4..=1_000_000).contains(&steps_per_mesh) => {
                return Err(DynamicsError::BadOption {
                    name: "solver.rk4_steps_per_mesh",
                    value: steps_per_mesh.to_string(),
                    expected: "an integer in 4..=1000000",
                });
            }
            Method::Rk4 { .. } => {}
        }
        Ok(())
    }
}

/// A recorded run.
#[derive(Debug, Clone, Serialize)]
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
/// `progress(k)` receives the number of finished Poincaré periods.
pub fn simulate(
    model: &Model,
    y0: &[f64],
    opts: &RunOptions,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Run, DynamicsError> {
    opts.validate()?;
    let n2 = model.dim();
    let mut y = y0.to_vec();
    let mut stats = OdeStats::default();
    let tp = model.poincare_period;
    let t0 = model.mesh.t0;
    let mut t = 0.0;
    let mut prev = y.clone();
    let mut change = f64::INFINITY;
    let mut steady = false;
    let mut done = 0;
    for k in 0..opts.max_periods {
        let st = advance(model, t, t + tp, &mut y, opts, &mut |_, _| {})?;
        stats += st;
        t += tp;
        done = k + 1;
        if y.iter().any(|x| !x.is_finite()) {
            return Err(DynamicsError::Diverged(t));
        }
        change = poincare_change(&prev, &y);
        prev.copy_from_slice(&y);
        progress(u64::from(done));
        if change < opts.poincare_tol {
            steady = true;
            break;
        }
    }
    // record
    let spm = opts.samples_per_mesh as usize;
    let ns = spm * opts.record_mesh_periods as usize;
    let dt = t0 / spm as f64;
    let mut run = Run {
        t_s: Vec::with_capacity(ns),
        dte_m: Vec::with_capacity(ns),
        mesh_force_n: Vec::with_capacity(ns),
        states: Vec::with_capacity(ns),
        stats,
        transient_periods: done,
        steady,
        poincare_change: change,
        samples_per_mesh: opts.samples_per_mesh,
    };
    let t_rec = t;
    let push = |run: &mut Run, ts: f64, ys: &[f64]| {
        let (dte, fm) = mesh_outputs(model, ts, ys);
        run.t_s.push(ts);
        run.dte_m.push(dte);
        run.mesh_force_n.push(fm);
        run.states.push(ys.to_vec());
    };
    push(&mut run, t, &y);
    let mut k = 1usize;
    let mut buf = vec![0.0; n2];
    let t_end = t_rec + dt * ns as f64;
    let st = advance(
        model,
        t_rec,
        t_rec + dt * (ns - 1) as f64,
        &mut y,
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
                        push(&mut run, ts, &buf);
                        k += 1;
                    }
                }
                Sample::Point(tt) => {
                    let ts = t_rec + dt * k as f64;
                    if k < ns && (tt - ts).abs() < 1e-9 * dt {
                        push(&mut run, ts, yend);
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
    Ok(run)
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
            Ok(solver.integrate(model, t0, t1, y, &bps, &refs, &mut |d| {
                on(Sample::Dense(d), &empty)
            })?)
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

/// Undamped natural frequencies of the mean-stiffness linearisation, Hz (ascending; rigid-body
/// modes give 0): generalized symmetric eigenproblem `K φ = ω² M φ` via `M^{-1/2} K M^{-1/2}`.
pub fn natural_frequencies_hz(model: &Model) -> Result<Vec<f64>, DynamicsError> {
    let (k, _) = linear_or_err(model)?;
    let n = model.n();
    let s = DMatrix::from_fn(n, n, |i, j| {
        k[(i, j)] / (model.mass[i] * model.mass[j]).sqrt()
    });
    let s = (&s + s.transpose()) * 0.5;
    let ev = s.symmetric_eigen().eigenvalues;
    let mut f: Vec<f64> = ev
        .iter()
        .map(|&l| l.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
        .collect();
    f.sort_by(f64::total_cmp);
    Ok(f)
}

fn linear_or_err(model: &Model) -> Result<(DMatrix<f64>, DMatrix<f64>), DynamicsError> {
    model.linear_matrices().ok_or_else(|| {
        let name = model.terms.iter().find(|t| {
            t.is_nonlinear()
                && !t.linear_matrices(
                    &mut DMatrix::zeros(model.n(), model.n()),
                    &mut DMatrix::zeros(model.n(), model.n()),
                )
        });
        DynamicsError::NotLinear(name.map_or_else(|| "?".into(), |t| t.name()))
    })
}

/// Linear fast path (B.10): steady-state DTE amplitude (m) of an LTI scene under its static-TE
/// harmonic at the mesh frequency, from the complex frequency response
/// `(K − ω²M + iωC) q̂ = (k + iωc_m) ê · c`, DTE = cᵀq̂ − ê.
pub fn linear_dte_amplitude(model: &Model) -> Result<f64, DynamicsError> {
    let (k, c) = linear_or_err(model)?;
    if !model.is_linear() {
        return Err(DynamicsError::NotLinear(
            "time-varying or nonlinear mesh".into(),
        ));
    }
    let Some(ste) = model.mesh.ste else {
        return Ok(0.0);
    };
    let n = model.n();
    let w = model.mesh.omega_e;
    let a = DMatrix::from_fn(n, n, |i, j| {
        let m = if i == j { model.mass[i] } else { 0.0 };
        Complex::new(k[(i, j)] - w * w * m, w * c[(i, j)])
    });
    let e_hat = Complex::from_polar(ste.er, ste.phase - std::f64::consts::FRAC_PI_2);
    let km = Complex::new(model.mesh.mean_k(), w * model.mesh.c_m) * e_hat;
    let mut f = nalgebra::DVector::from_element(n, Complex::new(0.0, 0.0));
    for &(i, cc) in &model.mesh.coeffs {
        f[i] += km * cc;
    }
    let q = a.lu().solve(&f).ok_or(DynamicsError::NotLinear(
        "singular dynamic stiffness (undamped rigid-body mode)".into(),
    ))?;
    let g: Complex<f64> = model.mesh.coeffs.iter().map(|&(i, cc)| q[i] * cc).sum();
    Ok((g - e_hat).norm())
}

/// Energy audit over `[0, t_end]` (B.9-5): integrates the model augmented with the energy source
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
        solver.integrate(&aug, t, tb, &mut y, &[], &[], &mut |_| {})?;
        if tb < t_end {
            jumps += model.energy(tb + dt0, &y[..m]) - model.energy(tb - dt0, &y[..m]);
        }
        t = tb;
    }
    // evaluate the end state on the side of the last piece (t_end may itself be a switch)
    Ok((model.energy(t_end - dt0, &y[..m]) - e0, y[m], jumps))
}

/// One point of a frequency sweep.
#[derive(Debug, Clone, Serialize)]
pub struct SweepPoint {
    /// Pinion speed, rpm.
    pub n1_rpm: f64,
    /// Ω = ωe/ωn.
    pub omega_ratio: f64,
    /// Half peak-to-peak DTE, m.
    pub dte_half_pp_m: f64,
    /// Mean DTE, m.
    pub dte_mean_m: f64,
    /// Amplitude of the DTE at the mesh frequency, m.
    pub dte_first_harmonic_m: f64,
    /// Fraction of samples with |δ| ≤ b (contact loss), 0 without backlash.
    pub contact_loss_fraction: f64,
    /// Poincaré criterion met.
    pub steady: bool,
}

/// Frequency sweep over `omega_ratios` (Ω = ωe/ωn, in the given order: ascending = sweep up,
/// descending = sweep down), each point starting from the previous point's final state so that
/// the jump phenomenon shows. The first point starts from `y0` (or the static state).
pub fn sweep(
    scene: &Scene,
    file: &str,
    omega_ratios: &[f64],
    opts: &RunOptions,
    y0: Option<&[f64]>,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<SweepPoint>, DynamicsError> {
    let d = scene.derived(file)?;
    let mut state: Option<Vec<f64>> = y0.map(<[f64]>::to_vec);
    let mut out = Vec::with_capacity(omega_ratios.len());
    for (i, &om) in omega_ratios.iter().enumerate() {
        if !(om.is_finite() && om > 0.0) {
            return Err(DynamicsError::BadOption {
                name: "omega_ratio",
                value: om.to_string(),
                expected: "a positive frequency ratio",
            });
        }
        let mut s = scene.clone();
        s.operating.n1_rpm =
            om * d.omega_n * 60.0 / (2.0 * std::f64::consts::PI * scene.gears.z1 as f64);
        let (model, _) = s.build(file)?;
        let y = state.clone().unwrap_or_else(|| static_state(&model, 1e-6));
        let run = simulate(&model, &y, opts, &|_| {})?;
        let b = model.mesh.backlash.map_or(0.0, |b| b.b);
        let h = run.dte_harmonics(1);
        let loss = if b > 0.0 {
            run.dte_m.iter().filter(|d| d.abs() <= b).count() as f64 / run.dte_m.len() as f64
        } else {
            0.0
        };
        out.push(SweepPoint {
            n1_rpm: s.operating.n1_rpm,
            omega_ratio: om,
            dte_half_pp_m: run.dte_half_pp(),
            dte_mean_m: h[0],
            dte_first_harmonic_m: h[1],
            contact_loss_fraction: loss,
            steady: run.steady,
        });
        state = run.states.last().cloned();
        progress(i as u64 + 1);
    }
    Ok(out)
}

/// Contact-loss (jump-up) frequency ratio of the dimensionless backlash oscillator (B.7, B.9-3):
/// the smallest Ω where the linear branch amplitude `Fe Ω²/sqrt((1−Ω²)² + (2ζΩ)²)` reaches the
/// mean load `Fm`, found by bisection to `tol`. `None` if it never does below Ω = 1.
#[must_use]
pub fn sdof_contact_loss_ratio(zeta: f64, fm: f64, fe: f64, tol: f64) -> Option<f64> {
    let g = |w: f64| fe * w * w / ((1.0 - w * w).powi(2) + (2.0 * zeta * w).powi(2)).sqrt() - fm;
    let (mut a, mut b) = (1e-6, 1.0);
    if !(tol > 0.0) || g(b) < 0.0 {
        return None;
    }
    while b - a > tol {
        let c = 0.5 * (a + b);
        if g(c) < 0.0 { a = c } else { b = c }
    }
    Some(0.5 * (a + b))
}
