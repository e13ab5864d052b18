//! The whole analysis of an error file as one serialisable report (what `ncgear tolerance`
//! prints and writes to `tolerance.json`).

use super::{Analysis, ErrorFile, GreedyStep, Joint, Phasor, ToleranceError, arcsec};
use crate::analysis::peak::PeakOptions;
use crate::math::monte_carlo::{McOptions, McStats};
use crate::progress::Progress;
use serde::Serialize;

/// Options of [`analyse`]. (De)serialisable (a missing field takes its default, an unknown one is an error) and
/// built with `with_*`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct ToleranceOptions {
    /// Monte Carlo of random assembly; `None` skips it (default: [`McOptions::default`], 50 000
    /// samples, seed 1, 60 bins).
    pub monte_carlo: Option<McOptions>,
    /// Random starts of the joint optimizer, besides the greedy angles (default 24).
    pub joint_starts: usize,
    /// Seed of the joint optimizer's random starts (default 1).
    pub joint_seed: u64,
    /// Accuracy of the certified peak (default [`PeakOptions::default`]).
    pub peak: PeakOptions,
}

crate::builder::with_fields!(ToleranceOptions {
    with_monte_carlo => monte_carlo: Option<McOptions>,
    with_joint_starts => joint_starts: usize,
    with_joint_seed => joint_seed: u64,
    with_peak => peak: PeakOptions,
});

impl Default for ToleranceOptions {
    fn default() -> Self {
        Self {
            monte_carlo: Some(McOptions::default()),
            joint_starts: 24,
            joint_seed: 1,
            peak: PeakOptions::default(),
        }
    }
}

/// A full report of `ncgear tolerance` on an error file (the keys of `tolerance.json`).
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
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
    /// Greedy's final certified peak, µm.
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

impl ToleranceReport {
    /// A line-of-action error `e_um` (µm) as transmission error at this report's base radius,
    /// arc seconds ([`arcsec`]).
    #[must_use]
    pub fn arcsec(&self, e_um: f64) -> f64 {
        arcsec(e_um, self.base_radius_mm)
    }
}

/// Runs the whole analysis: peaks, bounds, greedy, joint, optionally Monte Carlo.
/// `progress` counts Monte Carlo samples.
///
/// # Errors
/// [`ToleranceError::BadValue`] (key `samples`) when the Monte Carlo options are out of range.
pub fn analyse(
    file: &ErrorFile,
    opts: &ToleranceOptions,
    progress: &Progress,
) -> Result<ToleranceReport, ToleranceError> {
    let a = Analysis::new(file, opts.peak);
    let rb = file.base_radius();
    let nominal = a.peak(&vec![0.0; a.free_count()], None);
    let greedy = a.greedy(file.scan_steps);
    let betas: Vec<f64> = greedy.iter().map(|s| s.beta_rad).collect();
    let greedy_peak = a.peak(&betas, None).value;
    // The joint optimum and the Monte Carlo are independent: side by side (rayon), so that the
    // starts that finish late overlap the samples instead of leaving a core idle.
    let (joint, mc) = rayon::join(
        || a.joint(opts.joint_starts, opts.joint_seed, Some(&betas)),
        || {
            opts.monte_carlo
                .as_ref()
                .map(|o| a.monte_carlo(o, progress))
        },
    );
    let (mc_um, p_beats) = match mc {
        Some(r) => {
            let (s, v) = r.map_err(|e| ToleranceError::BadValue {
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
        monte_carlo_arcsec: mc_um.as_ref().map(|s| s.scaled(arcsec(1.0, rb))),
        monte_carlo_um: mc_um,
        p_random_beats_greedy: p_beats,
    })
}
