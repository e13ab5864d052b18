//! Stage B over the candidate arms: each arm's timing side by side, a family's members ranked and
//! the best timed again with the gear limits and the target bands.

use super::{FAMILY_DESIGNED, TIMING_ORDER};
use crate::design::DesignOptions;
use crate::geometry::limits::GearLimits;
use crate::geometry::mechanism::Mechanism;
use crate::simulate::{FeatureOptions, features_of_turn};
use crate::synthesis::dyad::{Dyad, Pose};
use crate::synthesis::targets::{SEARCH_SAMPLES, band_shortfalls, turn_of};
use crate::synthesis::timing::{
    Timing, TimingError, TimingGoals, carrier_angles, check_planet_turns, fit_timing,
};
use rayon::prelude::*;

/// What Stage B (the timing of a candidate arm) keeps to: the poses and their tolerances, the
/// carrier sense, the gear limits and the target bands.
pub(super) struct TimingStage<'a> {
    pub(super) poses: &'a [Pose],
    /// Direction tolerance of each pose, rad.
    pub(super) tol_rad: &'a [f64],
    /// Carrier sense asked for (±1), or either.
    pub(super) sense: Option<i8>,
    pub(super) fopts: &'a FeatureOptions,
    pub(super) opts: &'a DesignOptions,
    /// The design chain's gear limits.
    pub(super) limits: GearLimits,
    /// The target bands `(index, [low, high])`.
    pub(super) bands: Vec<(&'static str, [f64; 2])>,
}

impl TimingStage<'_> {
    /// The timing of `dyad`; with `full`, kept within the gear limits and the bands too.
    fn timed(&self, dyad: Dyad, full: bool) -> Result<Timing, TimingError> {
        let poses = self.poses;
        let (direction, angles) = carrier_angles(poses, &dyad, self.sense)?;
        check_planet_turns(
            poses,
            direction,
            &angles,
            self.opts.refine_options.ratio_bounds,
        )?;
        // The bands' rows: the indices of the train's two arms at SEARCH_SAMPLES instants.
        let o = dyad.center_mm;
        let bands = &self.bands;
        let band_rows = |m: &Mechanism| -> Vec<f64> {
            features_of_turn(
                &turn_of(m, o, direction, SEARCH_SAMPLES),
                o,
                direction,
                self.fopts,
            )
            // Indices that cannot be evaluated (no planting level): each band 1000 units out.
            .map_or(vec![1e3; bands.len()], |f| band_shortfalls(bands, &f))
        };
        let goals = TimingGoals {
            limits: full.then_some(&self.limits),
            bands: (full && !bands.is_empty()).then_some(&band_rows),
        };
        Ok(fit_timing(
            poses,
            &dyad,
            direction,
            &angles,
            TIMING_ORDER,
            self.tol_rad,
            &goals,
        ))
    }

    /// Each candidate's timing on its own (side by side); a family's members first without the
    /// gear-limit and band rows (cheaper), ranked, the [`FAMILY_DESIGNED`] kept then timed again
    /// with them when they break a limit or there are bands.
    pub(super) fn time_candidates(
        &self,
        pick: Vec<Dyad>,
        family: bool,
    ) -> Vec<(Dyad, Result<Timing, TimingError>)> {
        let mut timings: Vec<(Dyad, Result<Timing, TimingError>)> = pick
            .into_par_iter()
            .map(|d| (d, self.timed(d, !family)))
            .collect();
        // The family's members that go on to the design chain: those whose timing passes the
        // poses best (to 1e-6 rad), then keeps within the gear limits, then the most compact arm.
        if family {
            rank_family(&mut timings, &self.limits);
            timings.truncate(FAMILY_DESIGNED);
            timings = timings
                .into_par_iter()
                .map(|(d, t)| match t {
                    Ok(t)
                        if !self.limits.contains(&t.mechanism.ratio, t.mechanism.a_mm)
                            || !self.bands.is_empty() =>
                    {
                        (d, self.timed(d, true))
                    }
                    t => (d, t),
                })
                .collect();
        }
        timings
    }
}

/// A family's timed members in the order they go on to the design chain: those whose timing
/// passes the poses best (to 1e-6 rad), then keeps within the gear limits, then the most compact
/// arm.
fn rank_family(timings: &mut [(Dyad, Result<Timing, TimingError>)], limits: &GearLimits) {
    let key = |(dyad, t): &(Dyad, Result<Timing, TimingError>)| match t {
        Ok(t) => (
            (t.residuals_rad.iter().map(|r| r.abs()).fold(0.0, f64::max) * 1e6).round(),
            !limits.contains(&t.mechanism.ratio, t.mechanism.a_mm),
            dyad.l1_mm + dyad.l3_mm,
        ),
        Err(_) => (f64::INFINITY, true, f64::INFINITY),
    };
    timings.sort_by(|a, b| {
        let (ka, kb) = (key(a), key(b));
        ka.0.total_cmp(&kb.0)
            .then(ka.1.cmp(&kb.1))
            .then(ka.2.total_cmp(&kb.2))
    });
}
