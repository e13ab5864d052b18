//! A carrier-speed sweep: the steady state at each speed, warm-started from the previous
//! speed's, and the figures of where the knock begins. The speeds run as [`SWEEP_CHAINS`]
//! contiguous chains side by side (each chain's first speed from the quasi-static state, the
//! others warm-started within their chain): a fixed count, so the rows do not depend on the
//! machine's cores.

use super::{Prepared, RotorError};
use crate::progress::Progress;
use rayon::prelude::*;
use serde::Serialize;

/// Most speeds a sweep may run.
pub const MAX_SWEEP_SPEEDS: usize = 200;

/// The chains a sweep runs side by side (module docs).
pub const SWEEP_CHAINS: usize = 2;

/// One speed of a sweep.
#[derive(Debug, Clone, Copy, Serialize, schemars::JsonSchema)]
pub struct SweepRow {
    /// Carrier speed, r/min.
    pub carrier_rpm: f64,
    /// Dynamic factor of `[sun–intermediate, intermediate–planet]`.
    pub dynamic_factor: [f64; 2],
    /// Impacts per turn (one train, both meshes).
    pub impacts_per_turn: usize,
    /// Largest impact speed, m/s.
    pub max_impact_speed_m_s: f64,
    /// Largest tip deviation from the static path, mm.
    pub max_tip_deviation_mm: f64,
    /// Turns to the steady state.
    pub turns: u32,
    /// Whether it settled.
    pub settled: bool,
}

/// The steady state of `prepared` at each carrier speed of `rpm` (r/min, in (0, 3000]), each
/// warm-started from the previous one of its chain (module docs); `progress` hears every speed.
///
/// # Errors
/// [`RotorError`]: a run's (the first in speed order).
pub fn sweep_rpm(
    prepared: &Prepared,
    rpm: &[f64],
    progress: &Progress,
) -> Result<Vec<SweepRow>, RotorError> {
    let per_chain = rpm.len().div_ceil(SWEEP_CHAINS).max(1);
    let chains: Vec<Result<Vec<SweepRow>, RotorError>> = rpm
        .par_chunks(per_chain)
        .map(|speeds| chain(prepared, speeds, progress))
        .collect();
    let mut rows = Vec::with_capacity(rpm.len());
    for c in chains {
        rows.extend(c?);
    }
    Ok(rows)
}

/// One chain of a sweep, each speed warm-started from the previous.
fn chain(
    prepared: &Prepared,
    rpm: &[f64],
    progress: &Progress,
) -> Result<Vec<SweepRow>, RotorError> {
    let mut warm: Option<Vec<f64>> = None;
    let mut rows = Vec::with_capacity(rpm.len());
    for &n in rpm {
        let run = prepared.run_at_rpm(n, warm.as_deref(), &Progress::none())?;
        let s = &run.report.summary;
        rows.push(SweepRow {
            carrier_rpm: n,
            dynamic_factor: [
                s.meshes.sun_intermediate.dynamic_factor,
                s.meshes.intermediate_planet.dynamic_factor,
            ],
            impacts_per_turn: s.impacts_per_turn,
            max_impact_speed_m_s: s.max_impact_speed_m_s,
            max_tip_deviation_mm: s.max_tip_deviation_mm,
            turns: run.report.steady.turns,
            settled: run.report.steady.settled,
        });
        warm = Some(run.end_state);
        progress.advance(1);
    }
    Ok(rows)
}
