//! Transmission-error harmonics, phase (coupling) compensation and Monte Carlo tolerance analysis
//! (companion spec part C, seed 003).
//!
//! Each error term is an equivalent line-of-action error `e_k = A_k sin(ω_k t + φ_k)` (µm, rad/s).
//! A term's phase is fixed, or free (an assembly choice): `φ_k = s_k·β_k + c_k` with the assembly
//! angle β_k. The transmission error is `Δθ = e/r_b` (rad; ×206 264.806 for arc seconds).
//!
//! - same-frequency terms add as phasors (C-1); zero-frequency terms are constants `A sin φ`;
//! - the peak of the sum is the **certified** peak over the common period ([`super::peak`]);
//! - the paper's phase scan (n equal steps) and greedy sequential assembly (C.3), a joint
//!   optimiser (multistart Nelder–Mead, argmin) for the gap to greedy;
//! - always reported: the certified peak, the sum-of-amplitudes bound `Σ|A_k|` and the
//!   phase-independent floor `sqrt(D_min² + Σ_j B_j,min²/2)` (RMS over a period; `B_j,min` the
//!   smallest phasor sum each frequency group can reach, `D_min` the smallest constant), which no
//!   choice of assembly phases can beat;
//! - Monte Carlo over random assembly phases (and amplitudes when distributions are given).

use super::montecarlo::{self, McError, McOptions, McStats};
use super::peak::{Peak, PeakGrid, PeakOptions};
use argmin::core::{CostFunction, Executor};
use argmin::solver::neldermead::NelderMead;
use nalgebra::DVector;
use rand::RngExt;
use rand::SeedableRng;
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;
use std::path::Path;

/// Arc seconds per radian.
pub const ARCSEC_PER_RAD: f64 = 206_264.806_247_096_36;

/// Amplitude distribution for Monte Carlo.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum AmplitudeDist {
    /// Uniform in `[lo, hi]` µm.
    UniformUm([f64; 2]),
    /// Magnitude of a 2-D Gaussian eccentricity vector (Rayleigh) with σ in µm.
    RayleighSigmaUm(f64),
}

/// One error term of the file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ErrorTerm {
    /// Label.
    #[serde(default)]
    pub name: String,
    /// Amplitude A, µm (the sign is kept: `−A sin x = A sin(x + π)`).
    pub amplitude_um: f64,
    /// Angular frequency ω, rad/s (0 for a constant term).
    pub omega_rad_s: f64,
    /// Fixed phase, or the constant part `c` of a free phase, degrees.
    #[serde(default)]
    pub phase_deg: f64,
    /// Whether the phase is an assembly choice `φ = sign·β + phase`.
    #[serde(default)]
    pub free: bool,
    /// `s` in `φ = s·β + c` (±1).
    #[serde(default = "one")]
    pub sign: f64,
    /// Amplitude distribution for Monte Carlo (default: the nominal amplitude).
    #[serde(default)]
    pub amplitude_dist: Option<AmplitudeDist>,
}

fn one() -> f64 {
    1.0
}

/// Base circle given by gear data instead of a radius.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BaseCircle {
    /// Module, mm.
    pub module_mm: f64,
    /// Tooth count.
    pub teeth: f64,
    /// Pressure angle, degrees.
    pub pressure_angle_deg: f64,
}

/// An error file (JSON or TOML).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ErrorFile {
    /// Base radius r_b, mm (or give `base_circle`).
    #[serde(default)]
    pub base_radius_mm: Option<f64>,
    /// Base circle from module, teeth and pressure angle.
    #[serde(default)]
    pub base_circle: Option<BaseCircle>,
    /// Steps of the phase scan (the paper: 100).
    #[serde(default = "hundred")]
    pub scan_steps: usize,
    /// Error terms, in assembly order.
    pub terms: Vec<ErrorTerm>,
}

fn hundred() -> usize {
    100
}

/// Why an error file is unusable.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ToleranceError {
    /// Unreadable file.
    #[error("{file}: cannot read the error file: {message}")]
    Unreadable {
        /// File.
        file: String,
        /// Message.
        message: String,
    },
    /// Syntax or schema error (the parser names the key).
    #[error("{file}: {message}")]
    Parse {
        /// File.
        file: String,
        /// Message.
        message: String,
    },
    /// An impossible value.
    #[error("{file}: `{key}`: {message}")]
    BadValue {
        /// File.
        file: String,
        /// Key path.
        key: String,
        /// What is expected.
        message: String,
    },
}

/// Reads a configuration file: its text, its name for messages, and whether it is JSON (`.json`
/// extension; otherwise TOML unless the text starts with `{`).
pub fn read_config_text(path: &Path) -> Result<(String, String, bool), ToleranceError> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| ToleranceError::Unreadable {
        file: file.clone(),
        message: e.to_string(),
    })?;
    let json = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"));
    Ok((text, file, json))
}

/// Deserialises JSON (`json`, or text starting with `{`) or TOML; the parser's message names the
/// key (and line for TOML).
pub fn parse_config<T: serde::de::DeserializeOwned>(
    text: &str,
    file: &str,
    json: bool,
) -> Result<T, ToleranceError> {
    let parse_err = |message: String| ToleranceError::Parse {
        file: file.into(),
        message,
    };
    if json || text.trim_start().starts_with('{') {
        serde_json::from_str(text).map_err(|e| parse_err(e.to_string()))
    } else {
        toml::from_str(text).map_err(|e| parse_err(e.to_string()))
    }
}

impl ErrorFile {
    /// Reads a JSON (`.json` or content starting with `{`) or TOML error file and validates it.
    pub fn read(path: &Path) -> Result<Self, ToleranceError> {
        let (text, file, json) = read_config_text(path)?;
        Self::parse(&text, &file, json)
    }

    /// Parses error-file text; `file` names it in messages.
    pub fn parse(text: &str, file: &str, json: bool) -> Result<Self, ToleranceError> {
        let parsed: Self = parse_config(text, file, json)?;
        parsed.validate(file)?;
        Ok(parsed)
    }

    fn validate(&self, file: &str) -> Result<(), ToleranceError> {
        let bad = |key: String, message: &str| {
            Err(ToleranceError::BadValue {
                file: file.into(),
                key,
                message: message.into(),
            })
        };
        if self.terms.is_empty() {
            return bad("terms".into(), "at least one error term is needed");
        }
        if self.terms.len() > 64 {
            return bad("terms".into(), "at most 64 terms");
        }
        if !(1..=100_000).contains(&self.scan_steps) {
            return bad("scan_steps".into(), "must be in 1..=100000");
        }
        match (self.base_radius_mm, self.base_circle) {
            (Some(r), None) if r.is_finite() && r > 0.0 => {}
            (None, Some(b))
                if b.module_mm > 0.0
                    && b.teeth > 0.0
                    && (0.0..90.0).contains(&b.pressure_angle_deg) => {}
            (Some(_), Some(_)) => {
                return bad(
                    "base_radius_mm".into(),
                    "give either base_radius_mm or base_circle, not both",
                );
            }
            _ => {
                return bad(
                    "base_radius_mm".into(),
                    "a positive base radius in mm (or base_circle = {module_mm, teeth, pressure_angle_deg})",
                );
            }
        }
        let rb = self.base_radius();
        if !(rb.is_finite() && rb > 0.0) {
            return bad(
                "base_circle".into(),
                "a finite positive base radius 0.5·module_mm·teeth·cos(pressure_angle_deg), mm",
            );
        }
        for (k, t) in self.terms.iter().enumerate() {
            let key = |f: &str| format!("terms[{k}].{f}");
            if !t.amplitude_um.is_finite() {
                return bad(key("amplitude_um"), "a finite amplitude in µm");
            }
            if !(t.omega_rad_s.is_finite() && t.omega_rad_s >= 0.0) {
                return bad(
                    key("omega_rad_s"),
                    "a finite angular frequency ≥ 0 in rad/s",
                );
            }
            if !t.phase_deg.is_finite() {
                return bad(key("phase_deg"), "a finite phase in degrees");
            }
            if !(t.sign == 1.0 || t.sign == -1.0) {
                return bad(key("sign"), "1 or -1");
            }
            match t.amplitude_dist {
                Some(AmplitudeDist::UniformUm([lo, hi]))
                    if !(lo.is_finite() && hi.is_finite() && lo <= hi) =>
                {
                    return bad(
                        key("amplitude_dist.uniform_um"),
                        "[lo, hi] with lo ≤ hi, µm",
                    );
                }
                Some(AmplitudeDist::RayleighSigmaUm(s)) if !(s.is_finite() && s > 0.0) => {
                    return bad(
                        key("amplitude_dist.rayleigh_sigma_um"),
                        "a positive σ in µm",
                    );
                }
                _ => {}
            }
        }
        Ok(())
    }

    /// Base radius r_b, mm.
    #[must_use]
    pub fn base_radius(&self) -> f64 {
        match (self.base_radius_mm, self.base_circle) {
            (Some(r), _) => r,
            (None, Some(b)) => {
                0.5 * b.module_mm * b.teeth * b.pressure_angle_deg.to_radians().cos()
            }
            (None, None) => f64::NAN,
        }
    }
}

/// Transmission error in arc seconds of a line-of-action error `e_um` (µm) at base radius `rb_mm`.
#[must_use]
pub fn arcsec(e_um: f64, rb_mm: f64) -> f64 {
    e_um * 1e-3 / rb_mm * ARCSEC_PER_RAD
}

/// The phasor sum of same-frequency terms (C-1).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Phasor {
    /// ω, rad/s.
    pub omega_rad_s: f64,
    /// Amplitude B, µm.
    pub amplitude_um: f64,
    /// Phase ξ, rad.
    pub phase_rad: f64,
}

/// Combines `A e^{iφ}` terms: `B e^{iξ} = Σ A_k e^{iφ_k}` (C-1).
#[must_use]
pub fn phasor_sum(terms: &[(f64, f64)]) -> (f64, f64) {
    let (c, s) = terms.iter().fold((0.0, 0.0), |(c, s), (a, p)| {
        (c + a * p.cos(), s + a * p.sin())
    });
    (c.hypot(s), s.atan2(c))
}

/// The error set with its sampling grid.
#[derive(Debug, Clone)]
pub struct Analysis {
    terms: Vec<ErrorTerm>,
    grid: PeakGrid,
    free: Vec<usize>,
}

/// One step of the greedy assembly.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GreedyStep {
    /// Term name.
    pub term: String,
    /// Best scan index i (β = 2πi/n).
    pub index: usize,
    /// β, rad.
    pub beta_rad: f64,
    /// Certified peak with the terms assembled so far, µm.
    pub peak_um: f64,
    /// All indices within 1e-9 relative of the best (ties from time-shift invariance, C.2).
    pub ties: Vec<usize>,
}

/// Result of the joint optimiser.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Joint {
    /// Free-phase angles β, rad (assembly order of the free terms).
    pub betas_rad: Vec<f64>,
    /// Certified peak, µm.
    pub peak_um: f64,
    /// Starts used.
    pub starts: usize,
}

struct JointCost<'a> {
    a: &'a Analysis,
}

impl CostFunction for JointCost<'_> {
    type Param = DVector<f64>;
    type Output = f64;
    fn cost(&self, p: &DVector<f64>) -> Result<f64, argmin::core::Error> {
        Ok(self.a.peak(p.as_slice(), None).value)
    }
}

impl Analysis {
    /// Prepares the analysis of a validated file.
    #[must_use]
    pub fn new(file: &ErrorFile, opts: PeakOptions) -> Self {
        let omegas: Vec<f64> = file.terms.iter().map(|t| t.omega_rad_s).collect();
        let free = file
            .terms
            .iter()
            .enumerate()
            .filter(|(_, t)| t.free)
            .map(|(k, _)| k)
            .collect();
        Self {
            terms: file.terms.clone(),
            grid: PeakGrid::new(&omegas, opts),
            free,
        }
    }

    /// Number of free phases.
    #[must_use]
    pub fn free_count(&self) -> usize {
        self.free.len()
    }

    /// Phases (rad) for assembly angles `betas` (one per free term, in order).
    fn phases(&self, betas: &[f64]) -> Vec<f64> {
        let mut j = 0;
        self.terms
            .iter()
            .map(|t| {
                let c = t.phase_deg.to_radians();
                if t.free {
                    let b = betas.get(j).copied().unwrap_or(0.0);
                    j += 1;
                    t.sign * b + c
                } else {
                    c
                }
            })
            .collect()
    }

    /// Certified peak (µm) for assembly angles `betas`; `active` limits the sum to the first terms.
    #[must_use]
    pub fn peak(&self, betas: &[f64], active: Option<usize>) -> Peak {
        let ph = self.phases(betas);
        let n = active.unwrap_or(self.terms.len());
        let amps: Vec<f64> = self
            .terms
            .iter()
            .enumerate()
            .map(|(k, t)| if k < n { t.amplitude_um } else { 0.0 })
            .collect();
        self.grid.peak(&amps, &ph)
    }

    /// The paper's scan: the free term number `which` (0-based among the free terms) over
    /// β = 2πi/n, i = 1..=n, with the earlier free terms at `fixed` and only the terms up to and
    /// including that term active. Returns the peaks (µm), index i − 1.
    #[must_use]
    pub fn scan(&self, which: usize, fixed: &[f64], n: usize) -> Vec<f64> {
        let upto = self.free.get(which).map_or(self.terms.len(), |k| k + 1);
        (1..=n)
            .map(|i| {
                let mut betas = fixed[..which.min(fixed.len())].to_vec();
                betas.resize(which, 0.0);
                betas.push(TAU * i as f64 / n as f64);
                self.peak(&betas, Some(upto)).value
            })
            .collect()
    }

    /// Greedy sequential assembly (C.3): each free term in order takes the scan's best angle.
    #[must_use]
    pub fn greedy(&self, n: usize) -> Vec<GreedyStep> {
        let mut betas = Vec::new();
        let mut steps = Vec::new();
        for w in 0..self.free.len() {
            let peaks = self.scan(w, &betas, n);
            let best = peaks.iter().copied().fold(f64::INFINITY, f64::min);
            let ties: Vec<usize> = peaks
                .iter()
                .enumerate()
                .filter(|(_, p)| **p <= best * (1.0 + 1e-9))
                .map(|(i, _)| i + 1)
                .collect();
            let i = ties[0];
            let beta = TAU * i as f64 / n as f64;
            betas.push(beta);
            steps.push(GreedyStep {
                term: self.terms[self.free[w]].name.clone(),
                index: i,
                beta_rad: beta,
                peak_um: best,
                ties,
            });
        }
        steps
    }

    /// Joint optimisation of all free phases: multistart Nelder–Mead from `starts` seeded points
    /// (plus `extra_start`, e.g. the greedy angles).
    #[must_use]
    pub fn joint(&self, starts: usize, seed: u64, extra_start: Option<&[f64]>) -> Joint {
        let d = self.free.len();
        if d == 0 {
            return Joint {
                betas_rad: vec![],
                peak_um: self.peak(&[], None).value,
                starts: 0,
            };
        }
        let mut rng = rand::rngs::ChaCha8Rng::seed_from_u64(seed);
        let mut inits: Vec<Vec<f64>> = (0..starts)
            .map(|_| (0..d).map(|_| rng.random::<f64>() * TAU).collect())
            .collect();
        if let Some(e) = extra_start {
            inits.push(e.to_vec());
        }
        let mut best = (f64::INFINITY, vec![0.0; d]);
        for p in nelder_mead_starts(|| JointCost { a: self }, &inits, 0.3, 1e-10, 400) {
            let v = self.peak(&p, None).value;
            if v < best.0 {
                best = (v, p.iter().map(|b| b.rem_euclid(TAU)).collect());
            }
        }
        Joint {
            betas_rad: best.1,
            peak_um: best.0,
            starts: inits.len(),
        }
    }

    /// Same-frequency phasor sums (C-1) at assembly angles `betas`.
    #[must_use]
    pub fn groups(&self, betas: &[f64]) -> Vec<Phasor> {
        let ph = self.phases(betas);
        let mut omegas: Vec<f64> = self.terms.iter().map(|t| t.omega_rad_s).collect();
        omegas.sort_by(f64::total_cmp);
        omegas.dedup();
        omegas
            .into_iter()
            .map(|w| {
                let members: Vec<(f64, f64)> = self
                    .terms
                    .iter()
                    .zip(&ph)
                    .filter(|(t, _)| t.omega_rad_s == w)
                    .map(|(t, p)| (t.amplitude_um, *p))
                    .collect();
                let (b, xi) = phasor_sum(&members);
                Phasor {
                    omega_rad_s: w,
                    amplitude_um: b,
                    phase_rad: xi,
                }
            })
            .collect()
    }

    /// `Σ|A_k|`, µm: the peak when every term peaks together.
    #[must_use]
    pub fn amplitude_sum(&self) -> f64 {
        self.terms.iter().map(|t| t.amplitude_um.abs()).sum()
    }

    /// Phase-independent floor (µm): `sqrt(D_min² + Σ_j B_j,min²/2)`; no assembly can beat it.
    #[must_use]
    pub fn floor(&self) -> f64 {
        let groups = self.groups(&vec![0.0; self.free.len()]);
        let mut total = 0.0;
        for g in groups {
            let members: Vec<&ErrorTerm> = self
                .terms
                .iter()
                .filter(|t| t.omega_rad_s == g.omega_rad_s)
                .collect();
            let fixed: Vec<(f64, f64)> = members
                .iter()
                .filter(|t| !t.free)
                .map(|t| (t.amplitude_um, t.phase_deg.to_radians()))
                .collect();
            let free_amps: Vec<f64> = members
                .iter()
                .filter(|t| t.free)
                .map(|t| t.amplitude_um.abs())
                .collect();
            if g.omega_rad_s == 0.0 {
                let d: f64 = fixed.iter().map(|(a, p)| a * p.sin()).sum();
                let m = (d.abs() - free_amps.iter().sum::<f64>()).max(0.0);
                total += m * m;
            } else {
                // Polygon inequality on the phasors: the fixed part is one side.
                let (bf, _) = phasor_sum(&fixed);
                let mut sides = free_amps.clone();
                sides.push(bf);
                let sum: f64 = sides.iter().sum();
                let max = sides.iter().copied().fold(0.0, f64::max);
                let bmin = (2.0 * max - sum).max(0.0);
                total += 0.5 * bmin * bmin;
            }
        }
        total.sqrt()
    }

    /// Monte Carlo over random assembly angles (uniform) and amplitude distributions: certified
    /// peak per sample, µm.
    pub fn monte_carlo(
        &self,
        opts: &McOptions,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<(McStats, Vec<f64>), McError> {
        let d = self.free.len();
        montecarlo::run(
            opts,
            |rng, _| {
                let betas: Vec<f64> = (0..d).map(|_| rng.random::<f64>() * TAU).collect();
                let ph = self.phases(&betas);
                let amps: Vec<f64> = self
                    .terms
                    .iter()
                    .map(|t| match t.amplitude_dist {
                        None => t.amplitude_um,
                        Some(AmplitudeDist::UniformUm([lo, hi])) => {
                            lo + (hi - lo) * rng.random::<f64>()
                        }
                        Some(AmplitudeDist::RayleighSigmaUm(s)) => {
                            let u: f64 = rng.random::<f64>();
                            s * (-2.0 * (1.0 - u).ln()).sqrt()
                        }
                    })
                    .collect();
                self.grid.peak(&amps, &ph).value
            },
            progress,
        )
    }
}

/// Multistart Nelder–Mead (argmin): from each start an axis-aligned simplex with edge `step`,
/// stopped when the simplex values' standard deviation falls below `sd_tolerance` or after
/// `max_iters` iterations. Returns the best parameter of every start that ran (the caller
/// projects it onto its domain and re-evaluates).
pub fn nelder_mead_starts<C>(
    make_cost: impl Fn() -> C,
    starts: &[Vec<f64>],
    step: f64,
    sd_tolerance: f64,
    max_iters: u64,
) -> Vec<Vec<f64>>
where
    C: CostFunction<Param = DVector<f64>, Output = f64>,
{
    let mut out = Vec::new();
    for x0 in starts {
        let mut simplex = vec![DVector::from_vec(x0.clone())];
        for k in 0..x0.len() {
            let mut v = x0.clone();
            v[k] += step;
            simplex.push(DVector::from_vec(v));
        }
        let Ok(solver) = NelderMead::new(simplex).with_sd_tolerance(sd_tolerance) else {
            continue;
        };
        if let Ok(r) = Executor::new(make_cost(), solver)
            .configure(|s| s.max_iters(max_iters))
            .run()
            && let Some(p) = r.state().best_param.as_ref()
        {
            out.push(p.as_slice().to_vec());
        }
    }
    out
}

/// A full report of `ncgear tolerance` on an error file.
#[derive(Debug, Clone, Serialize)]
pub struct ToleranceReport {
    /// Base radius, mm.
    pub base_radius_mm: f64,
    /// Common period of the terms, s.
    pub period_s: f64,
    /// Whether the frequencies are commensurate.
    pub commensurate: bool,
    /// Certified peak with every free angle at 0, µm.
    pub nominal_peak_um: f64,
    /// Σ|A|, µm.
    pub amplitude_sum_um: f64,
    /// Phase-independent floor, µm.
    pub floor_um: f64,
    /// Greedy assembly steps.
    pub greedy: Vec<GreedyStep>,
    /// Greedy's final certified peak, µm, and in arc seconds.
    pub greedy_peak_um: f64,
    /// The same in arc seconds.
    pub greedy_peak_arcsec: f64,
    /// Joint optimum.
    pub joint: Joint,
    /// How much greedy leaves on the table, µm.
    pub greedy_gap_um: f64,
    /// Same-frequency groups at the greedy angles.
    pub groups: Vec<Phasor>,
    /// Monte Carlo of random assembly (µm), when run.
    pub monte_carlo_um: Option<McStats>,
    /// The same in arc seconds.
    pub monte_carlo_arcsec: Option<McStats>,
    /// Probability that a random assembly beats greedy compensation.
    pub p_random_beats_greedy: Option<f64>,
}

fn scale_stats(s: &McStats, f: f64) -> McStats {
    McStats {
        n: s.n,
        min: s.min * f,
        max: s.max * f,
        mean: s.mean * f,
        std: s.std * f,
        mean_std_error: s.mean_std_error * f,
        p50: s.p50 * f,
        p95: s.p95 * f,
        p9973: s.p9973 * f,
        histogram: s
            .histogram
            .iter()
            .map(|h| [h[0] * f, h[1] * f, h[2]])
            .collect(),
    }
}

/// Runs the whole analysis: peaks, bounds, greedy, joint, optionally Monte Carlo.
pub fn analyse(
    file: &ErrorFile,
    mc: Option<&McOptions>,
    joint_starts: usize,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<ToleranceReport, ToleranceError> {
    let a = Analysis::new(file, PeakOptions::default());
    let rb = file.base_radius();
    let nominal = a.peak(&vec![0.0; a.free_count()], None);
    let greedy = a.greedy(file.scan_steps);
    let betas: Vec<f64> = greedy.iter().map(|s| s.beta_rad).collect();
    let greedy_peak = a.peak(&betas, None).value;
    let joint = a.joint(joint_starts, 1, Some(&betas));
    let (mc_um, p_beats) = match mc {
        Some(o) => {
            let (s, v) = a
                .monte_carlo(o, progress)
                .map_err(|e| ToleranceError::BadValue {
                    file: "monte carlo".into(),
                    key: "samples".into(),
                    message: e.to_string(),
                })?;
            let p = v.iter().filter(|x| **x < greedy_peak).count() as f64 / v.len().max(1) as f64;
            (Some(s), Some(p))
        }
        None => (None, None),
    };
    Ok(ToleranceReport {
        base_radius_mm: rb,
        period_s: nominal.period_s,
        commensurate: nominal.commensurate,
        nominal_peak_um: nominal.value,
        amplitude_sum_um: a.amplitude_sum(),
        floor_um: a.floor(),
        greedy_peak_um: greedy_peak,
        greedy_peak_arcsec: arcsec(greedy_peak, rb),
        greedy_gap_um: greedy_peak - joint.peak_um,
        groups: a.groups(&betas),
        greedy,
        joint,
        monte_carlo_arcsec: mc_um.as_ref().map(|s| scale_stats(s, arcsec(1.0, rb))),
        monte_carlo_um: mc_um,
        p_random_beats_greedy: p_beats,
    })
}
