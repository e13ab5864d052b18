//! Peaks, bounds and phase compensation of an error set: same-frequency phasor sums (docs/math/companion.md §C.2 eq. C-1), the
//! paper's phase scan and greedy assembly (docs/math/companion.md §C.3), the joint optimum, `Σ|A|` and the
//! phase-independent floor.

use super::ErrorFile;
use super::error_file::ErrorTerm;
use crate::analysis::peak::{Peak, PeakGrid, PeakOptions};
use crate::math::optimize::nelder_mead_starts;
use argmin::core::CostFunction;
use nalgebra::DVector;
use rand::RngExt;
use rand::SeedableRng;
use serde::Serialize;
use std::f64::consts::TAU;

/// The phasor sum of same-frequency terms (docs/math/companion.md §C.2 eq. C-1).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Phasor {
    /// ω, rad/s.
    pub omega_rad_s: f64,
    /// Amplitude B, µm.
    pub amplitude_um: f64,
    /// Phase ξ, rad.
    pub phase_rad: f64,
}

/// Combines `A e^{iφ}` terms: `B e^{iξ} = Σ A_k e^{iφ_k}` (docs/math/companion.md §C.2 eq. C-1).
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
    pub(super) terms: Vec<ErrorTerm>,
    pub(super) grid: PeakGrid,
    /// `prefix[n − 1]`: the grid of the first `n < K` terms alone, for the scan's partial sums.
    /// Their common period can be far shorter than the whole set's (the paper's first term alone
    /// repeats 75 times in the full period), and a grid over the full period would hold that many
    /// equal maxima, each refined for the certificate.
    prefix: Vec<PeakGrid>,
    free: Vec<usize>,
}

/// One step of the greedy assembly.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct GreedyStep {
    /// Term name.
    pub term: String,
    /// Best scan index i (β = 2πi/n).
    pub index: usize,
    /// β, rad.
    pub beta_rad: f64,
    /// Certified peak with the terms assembled so far, µm.
    pub peak_um: f64,
    /// All indices within 1e-9 relative of the best (ties from time-shift invariance, docs/math/companion.md §C.2).
    pub ties: Vec<usize>,
}

/// Result of the joint optimizer.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
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
            prefix: (1..omegas.len())
                .map(|n| PeakGrid::new(&omegas[..n], opts))
                .collect(),
            free,
        }
    }

    /// Number of free phases.
    #[must_use]
    pub fn free_count(&self) -> usize {
        self.free.len()
    }

    /// Phases (rad) for assembly angles `betas` (one per free term, in order).
    pub(super) fn phases(&self, betas: &[f64]) -> Vec<f64> {
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

    /// Certified peak (µm) for assembly angles `betas`; `active` limits the sum to the first terms
    /// (its period is then the common period of those terms).
    #[must_use]
    pub fn peak(&self, betas: &[f64], active: Option<usize>) -> Peak {
        let ph = self.phases(betas);
        let mut amps: Vec<f64> = self.terms.iter().map(|t| t.amplitude_um).collect();
        match active {
            Some(n) if n > 0 && n < amps.len() => self.prefix[n - 1].peak(&amps[..n], &ph[..n]),
            Some(0) => {
                amps.fill(0.0);
                self.grid.peak(&amps, &ph)
            }
            _ => self.grid.peak(&amps, &ph),
        }
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

    /// Greedy sequential assembly (docs/math/companion.md §C.3): each free term in order takes the scan's best angle.
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

    /// Joint optimization of all free phases: multistart Nelder–Mead from `starts` seeded points
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

    /// Same-frequency phasor sums (docs/math/companion.md §C.2 eq. C-1) at assembly angles `betas`.
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
}
