//! The chain's last stage: every parameter fitted to the points as read (restarts, the elliptic
//! restart, or one fit from a warm start), and its summary for the report.

use crate::design::error::DesignError;
use crate::design::fit;
use crate::design::fit::FitOptions;
use crate::design::fit::{FitSummary, fit_summary};
use crate::design::hypothesis::segmented::Segmented;
use crate::design::options::{IdlerOffset, RefineMode};
use crate::design::strategy::arms::ArmTrains;
use crate::design::strategy::ellipse::from_an_ellipse;
use crate::design::strategy::warm;
use crate::design::trajectory::Trajectory;
use crate::geometry::fourier::SunRatio;
use crate::geometry::mechanism::Mechanism;

/// The fit aims at this fraction of `tol_mm` on the points, and runs (refine auto) when the
/// chain's result is farther: room for the table rebuild and for the curve between the points.
pub(in crate::design) const FIT_TOL_FRACTION: f64 = 0.2;

/// What the fit stage hands on: the mechanism, each point's carrier angle, and the summary.
pub(in crate::design) struct FitStage {
    pub mechanism: Mechanism,
    pub angles: Vec<f64>,
    pub summary: Option<FitSummary>,
    /// The fit's result replaced the chain's.
    pub replaced: bool,
    /// The fit started from a warm start ([`warm`]).
    pub warm: bool,
}

/// Where the fit stage starts: the chain's train, and a warm start's train ([`warm`]) with the
/// tooth count `(z, m)` it was designed for, when given.
pub(in crate::design) struct FitStart<'a> {
    pub chain: Mechanism,
    pub warm: Option<(&'a Mechanism, Option<(u32, f64)>)>,
}

/// The last stage ([`crate::design::fit`]): every parameter fitted to the points as read, when
/// the chain's result is not within [`FIT_TOL_FRACTION`]·tol of them, leaves the ratio bounds,
/// or came from smoothed points (refine auto), with restarts from the patent route at order 2.
pub(in crate::design) fn fit_stage(
    traj: &Trajectory,
    trains: &ArmTrains,
    seg: &Segmented,
    tau: f64,
    from: FitStart,
    start_smoothing: Option<usize>,
    noise_sigma: f64,
) -> Result<FitStage, DesignError> {
    let FitStart { chain: mech, warm } = from;
    let opts = trains.opts;
    let points = traj.relative_to(opts.center_mm, trains.inv.direction < 0);
    let admissible = |m: &Mechanism| trains.limits.contains(&m.ratio, m.a_mm);
    let start = fit::measure(&points, &mech);
    let (start_max, start_rms) = (start.max_mm, start.rms_mm);
    let run_fit = opts.fit
        && match opts.refine {
            RefineMode::Off => false,
            RefineMode::On => true,
            RefineMode::Auto => {
                start_smoothing.is_some()
                    || !admissible(&mech)
                    || start_max > FIT_TOL_FRACTION * opts.tol_mm
            }
        };
    let kept = |summary| FitStage {
        mechanism: mech.clone(),
        angles: start.carrier_angles_rad.clone(),
        summary,
        replaced: false,
        warm: false,
    };
    if !run_fit {
        return Ok(kept(None));
    }
    let fit_opts = fit_options(trains, noise_sigma);
    let warm_fit = warm.and_then(|(m, teeth)| warm::warm_fit(&points, m, &fit_opts, teeth));
    if let Some(f) = warm_fit {
        return Ok(FitStage {
            summary: Some(fit_summary(
                &f,
                start_rms,
                start_max,
                noise_sigma,
                start_smoothing,
            )),
            mechanism: f.mechanism,
            angles: f.carrier_angles_rad,
            replaced: true,
            warm: true,
        });
    }
    let restarts = [2]
        .into_iter()
        .filter_map(|k| {
            SunRatio::fit_uniform(&seg.samples, k)
                .or_else(|_| SunRatio::fit_uniform(&seg.samples, 1))
                .ok()
                .map(|r| {
                    trains
                        .build(r.admissible(opts.refine_options.ratio_bounds), tau)
                        .0
                })
        })
        .collect();
    let f = fit::fit_with_restarts(&points, &mech, restarts, &fit_opts, opts.tol_mm)
        .map_err(|e| DesignError::Internal(e.to_string()))?;
    let f = from_an_ellipse(
        &points,
        &|r| trains.build(r, tau),
        opts.tol_mm,
        &fit_opts,
        f,
    );
    let summary = fit_summary(&f, start_rms, start_max, noise_sigma, start_smoothing);
    if f.rms_mm < start_rms || !admissible(&mech) {
        Ok(FitStage {
            mechanism: f.mechanism,
            angles: f.carrier_angles_rad,
            summary: Some(summary),
            replaced: true,
            warm: false,
        })
    } else {
        Ok(kept(Some(summary)))
    }
}

/// The options of the fit to the points: the chain's order, gear limits and noise level; aims at
/// [`FIT_TOL_FRACTION`] of the tolerance.
pub(in crate::design) fn fit_options(trains: &ArmTrains, noise_sigma: f64) -> FitOptions {
    let opts = trains.opts;
    FitOptions {
        order: opts.order,
        limits: trains.limits,
        tol_mm: FIT_TOL_FRACTION * opts.tol_mm,
        noise_sigma_mm: noise_sigma,
        // At Auto, the free design a module design starts from leaves the line too
        // ([`IdlerOffset::Auto`]).
        free_idler_offset: opts.idler_offset == IdlerOffset::Free
            || (opts.idler_offset == IdlerOffset::Auto && opts.module_mm.is_some()),
        sun_planet_gap_mm: opts.sun_planet_gap_mm(),
        ..opts.fit_options.clone()
    }
}
