//! The design chain, stage by stage: step 1, compatibility, the patent route, the docs/math/chain.md §8.3
//! refinement, the fit to the points, then the tables, checks and report.

pub mod alternatives;
pub(in crate::design) mod redesign;
pub(in crate::design) mod start;
pub(in crate::design) mod train_routes;

use crate::design::chain::start::invert_for_start;
use crate::design::chain::train_routes::{Chain, chain_routes};
use crate::design::error::DesignError;
use crate::design::fit::noise;
use crate::design::inverse::Inversion;
use crate::design::inverse::compat;
use crate::design::inverse::compat::Compatibility;
use crate::design::options::{DesignOptions, validate};
use crate::design::report::checks::{Finished, finish};
use crate::design::report::*;
use crate::design::strategy::arms::ArmTrains;
use crate::design::strategy::free::{FitStage, FitStart, fit_options, fit_stage};
use crate::design::strategy::module::design_for_module;
use crate::design::trajectory::Trajectory;
use crate::geometry::fourier::SunRatio;
use crate::geometry::mechanism::Mechanism;
use std::time::Instant;

/// Runs the whole chain on a trajectory.
pub fn design(traj: &Trajectory, opts: &DesignOptions) -> Result<Design, DesignError> {
    design_from(traj, opts, None)
}

/// The chain, its fit stage started from `warm`'s train when given ([`warm`]).
pub(in crate::design) fn design_from(
    traj: &Trajectory,
    opts: &DesignOptions,
    warm: Option<&DesignReport>,
) -> Result<Design, DesignError> {
    validate(opts)?;
    let t_all = Instant::now();
    let mut timings = Timings::default();
    let mut warnings = Vec::new();

    let noise_sigma = traj.noise_sigma_mm();
    let (inv, start_smoothing, compat, n) =
        invert_and_analyse(traj, opts, noise_sigma, &mut timings, &mut warnings)?;
    let trains = ArmTrains {
        inv: &inv,
        opts,
        limits: opts.limits_in_force(),
    };

    let routes = chain_routes(&trains, &compat, n, &mut timings, &mut warnings)?;
    let (patent, refine_summary, mut pending) =
        (routes.patent, routes.refine_summary, routes.pending);

    let (fitted, module, chosen) = fit(
        traj,
        &trains,
        routes.chain,
        warm,
        start_smoothing,
        noise_sigma,
        &mut timings,
    )?;
    let best_dev = best_deviation(&fitted, refine_summary.as_ref(), &patent.summary);
    if best_dev > opts.tol_mm {
        let residual_mm = compat.residual_rad * inv.l3_mm;
        pending.push((
            warnings.len(),
            not_traced(best_dev, opts.tol_mm, residual_mm),
        ));
    }

    // Outputs, checks, round trip.
    let t0 = Instant::now();
    let [imin, imax] = ratio_within_bounds(&fitted.mechanism, opts)?;
    let out = finish(
        traj,
        &inv,
        &compat,
        fitted.mechanism,
        &fitted.angles,
        opts,
        &mut warnings,
    )?;
    timings.outputs = ms(t0);
    timings.total = ms(t_all);
    closing_warnings(&out, opts, pending, &mut warnings);
    let mechanism = &out.mechanism;
    let mut report = DesignReport {
        schema_version: SCHEMA_VERSION,
        units: Units::mm_deg(),
        l1_mm: mechanism.l1_mm(),
        l3_mm: mechanism.l3_mm,
        center_distance_mm: mechanism.a_mm,
        idler_offset_deg: f64::from(inv.direction) * mechanism.idler_offset_rad.to_degrees(),
        needle_angle_deg: f64::from(inv.direction) * mechanism.needle_angle_rad.to_degrees(),
        carrier: Carrier {
            center_mm: opts.center_mm,
            direction: inv.direction,
        },
        gears: out.gears,
        roundtrip: out.roundtrip,
        trajectory: trajectory_summary(traj, &inv, noise_sigma),
        compatibility: compat_summary(&compat, inv.l3_mm),
        patent_route: patent.summary,
        refinement: refine_summary,
        fit: fitted.summary,
        chosen: chosen.into(),
        fourier: fourier_summary(mechanism, &inv, [imin, imax]),
        module,
        limits: out.limits,
        checks: out.checks,
        target_points: traj.points().to_vec(),
        warnings,
        teeth: None,
        alternatives: Vec::new(),
        sizing: None,
        timings_ms: timings,
        verdict: crate::verdict::Verdict::default(),
    };
    report.update_verdict();
    if opts.alternatives && !report.verdict.passed {
        let t0 = Instant::now();
        report.alternatives = crate::design::chain::alternatives::alternatives(traj, opts, &report);
        // The nearest alternative, when it traces closer, in the warnings the console prints.
        if let Some(note) = crate::design::chain::alternatives::nearest_note(&report) {
            report.warnings.push(note);
        }
        report.timings_ms.alternatives = ms(t0);
    } else if let Some(note) = crate::design::chain::alternatives::untried_note(opts, &report) {
        report.warnings.push(note);
    }
    Ok(Design {
        report,
        mechanism: out.mechanism,
        assembly: out.assembly,
        rebuilt: out.rebuilt,
        inversion: inv,
        traced_mm: out.traced,
        point_angles_rad: out.angles,
    })
}

/// The final stage: every parameter fitted to the points themselves (from the `chain`'s result,
/// or a `warm` start designed for the same module, refitted at its tooth count directly), then,
/// designing for a module, the tooth count a constraint of one more fit. Returns the fitted
/// train, the module summary and the name of the stage that chose it.
fn fit(
    traj: &Trajectory,
    trains: &ArmTrains,
    chain: Chain,
    warm: Option<&DesignReport>,
    start_smoothing: Option<usize>,
    noise_sigma: f64,
    timings: &mut Timings,
) -> Result<(FitStage, Option<crate::design::ModuleSummary>, &'static str), DesignError> {
    let t0 = Instant::now();
    let warm = warm.and_then(|r| warm_start(r, trains.inv, trains.opts));
    let warm_teeth = warm
        .as_ref()
        .and_then(|(_, s)| s.as_ref().map(|s| (s.teeth, s.module_mm)));
    let fitted = fit_stage(
        traj,
        trains,
        &chain.seg,
        chain.tau_rad,
        FitStart {
            chain: chain.mech,
            warm: warm.as_ref().map(|(m, _)| (m, warm_teeth)),
        },
        start_smoothing,
        noise_sigma,
    )?;
    timings.fit = ms(t0);
    let chosen = if fitted.replaced { "fit" } else { chain.chosen };
    // Designing for a module: the tooth count a constraint of one more fit.
    let t0 = Instant::now();
    let warm_module = warm.and_then(|(_, s)| s);
    let (fitted, module) = for_module(traj, trains, fitted, warm_module, noise_sigma)?;
    timings.module = ms(t0);
    let chosen = if module.is_some() { "module" } else { chosen };
    Ok((fitted, module, chosen))
}

/// Step 1 and the compatibility: l1, l3 and the needle law (from a smoothed copy for measured
/// points of noise `noise_sigma`, mm), the harmonics it was smoothed to, the half-closure origin
/// τ and the residual E_c, on the chain's grid of the returned size.
fn invert_and_analyse(
    traj: &Trajectory,
    opts: &DesignOptions,
    noise_sigma: f64,
    timings: &mut Timings,
    warnings: &mut Vec<String>,
) -> Result<(Inversion, Option<usize>, Compatibility, usize), DesignError> {
    let t0 = Instant::now();
    let (inv, start_smoothing) = invert_for_start(traj, opts, noise_sigma)?;
    timings.inverse = ms(t0);
    start_warnings(&inv, start_smoothing, opts, noise_sigma, warnings);
    let n = opts.inverse.grid.max(64) / 2 * 2;
    let t0 = Instant::now();
    let compat: Compatibility = compat::analyse(&inv.law, n, 1e-13);
    timings.compat = ms(t0);
    Ok((inv, start_smoothing, compat, n))
}

/// The warning of a target no train traces within `tol_mm`: the best design's deviation and the
/// compatibility residual E_c·l3, mm.
fn not_traced(best_dev_mm: f64, tol_mm: f64, residual_mm: f64) -> String {
    format!(
        "the best design deviates {best_dev_mm:.3} mm from the target (tolerance {tol_mm} mm): no train of this type traces it exactly (E_c·l3 = {residual_mm:.3} mm); this is the closest admissible design found"
    )
}

/// The report's Fourier block: the ratio's coefficients, the sun's phase in the file's angles
/// (deg) and the ratio's range `i21_range`.
fn fourier_summary(mech: &Mechanism, inv: &Inversion, i21_range: [f64; 2]) -> FourierSummary {
    FourierSummary {
        order: mech.ratio.order(),
        a: mech.ratio.cos_coefficients().to_vec(),
        b: mech.ratio.sin_coefficients().to_vec(),
        sun_phase_deg: inv.file_angle_deg(mech.sun_phase_rad),
        i21_range,
    }
}

/// The train and module summary a warm start's report gives the fit stage (its module only when
/// it is the one the options ask for).
fn warm_start(
    r: &DesignReport,
    inv: &Inversion,
    opts: &DesignOptions,
) -> Option<(Mechanism, Option<crate::design::ModuleSummary>)> {
    let m = start_mechanism(r, inv.direction)?;
    let module = r
        .module
        .as_ref()
        .filter(|s| Some(s.module_mm) == opts.module_mm);
    Some((m, module.cloned()))
}

/// The train of `report` in the solved frame of a target whose carrier turns `direction`
/// (+1 CCW, −1 CW); `None` when the report's carrier sense differs or its ratio is not valid.
fn start_mechanism(report: &DesignReport, direction: i8) -> Option<Mechanism> {
    if report.carrier.direction != direction {
        return None;
    }
    let f = &report.fourier;
    let ratio = SunRatio::new(f.a.clone(), f.b.clone()).ok()?;
    let sense = f64::from(direction);
    let m = Mechanism {
        a_mm: report.center_distance_mm,
        l3_mm: report.l3_mm,
        ratio,
        // The report's angles are file-frame degrees: the solved angle times the sense.
        sun_phase_rad: sense * f.sun_phase_deg.to_radians(),
        needle_angle_rad: sense * report.needle_angle_deg.to_radians(),
        idler_offset_rad: sense * report.idler_offset_deg.to_radians(),
    };
    (m.a_mm.is_finite() && m.a_mm > 0.0 && m.l3_mm.is_finite() && m.l3_mm > 0.0).then_some(m)
}

/// The sun ratio's range `[i_min, i_max]`, refused when it leaves the bounds.
fn ratio_within_bounds(mech: &Mechanism, opts: &DesignOptions) -> Result<[f64; 2], DesignError> {
    let [lo, hi] = opts.refine_options.ratio_bounds;
    let [imin, imax] = mech.ratio.range();
    if imin < lo || imax > hi {
        return Err(DesignError::RatioOutOfBounds {
            min: imin,
            max: imax,
            lo,
            hi,
        });
    }
    Ok([imin, imax])
}

/// The warnings the round trip decides: those held `pending` (at the places they would have
/// had) unless the noise of measured points explains the deviation, and the binding gear limits
/// of a design that misses the tolerance.
fn closing_warnings(
    out: &Finished,
    opts: &DesignOptions,
    pending: Vec<(usize, String)>,
    warnings: &mut Vec<String>,
) {
    if !noise::explained_by_noise(out.roundtrip.estimated_curve_deviation_mm, opts.tol_mm) {
        for (at, w) in pending.into_iter().rev() {
            warnings.insert(at, w);
        }
    }
    if out.limits.enabled
        && !out.limits.binding.is_empty()
        && out.roundtrip.max_deviation_mm > opts.tol_mm
    {
        warnings.push(format!(
            "the gear limits bind ({}): this is the closest design whose gears can be cut and run; `ncgear tradeoff` shows the deviation reached at other pressure-angle limits and modules",
            out.limits.binding.join(", ")
        ));
    }
}

/// The warnings of step 1: measured points whose smoothed loop gave the start, and a path both
/// carrier senses can trace.
fn start_warnings(
    inv: &Inversion,
    start_smoothing: Option<usize>,
    opts: &DesignOptions,
    noise_sigma: f64,
    warnings: &mut Vec<String>,
) {
    if let Some(h) = start_smoothing.filter(|_| opts.smooth.is_none()) {
        warnings.push(format!(
            "measured points (estimated noise σ = {noise_sigma:.4} mm): the start of the design was taken from the loop smoothed to {h} harmonics; the gears are fitted to the points as read"
        ));
    }
    if inv.other_sense_traceable {
        warnings.push(format!(
            "both carrier senses can trace this path (the other one with the arm's elbow flipped); chose {} as the better-realisable law",
            if inv.direction > 0 { "CCW" } else { "CW" }
        ));
    }
}

/// The module stage ([`design_for_module`]) on the fit stage's train when the options ask for a
/// module; a warm start designed for the same module was refitted at its tooth count already
/// (`warm_module`: its summary, with that fit as the one candidate).
fn for_module(
    traj: &Trajectory,
    trains: &ArmTrains,
    fitted: FitStage,
    warm_module: Option<crate::design::ModuleSummary>,
    noise_sigma: f64,
) -> Result<(FitStage, Option<crate::design::ModuleSummary>), DesignError> {
    let opts = trains.opts;
    let warm_module = match (warm_module, &fitted.summary) {
        (Some(s), Some(f)) if fitted.warm => Some(crate::design::ModuleSummary {
            candidates: vec![[f64::from(s.teeth), f.max_mm, f.rms_mm]],
            ..s
        }),
        _ => None,
    };
    Ok(match opts.module_mm {
        Some(_) if warm_module.is_some() => (fitted, warm_module),
        Some(m) => {
            let points = traj.relative_to(opts.center_mm, trains.inv.direction < 0);
            let fm = design_for_module(
                &points,
                &fitted.mechanism,
                m,
                &fit_options(trains, noise_sigma),
                opts.idler_offset,
            )?;
            let fitted = FitStage {
                mechanism: fm.mechanism,
                angles: fm.angles,
                ..fitted
            };
            (fitted, Some(fm.summary))
        }
        None => (fitted, None),
    })
}

/// The largest point distance of the design the chain settled on, mm: the fit's when it
/// replaced the routes' result, else the better route's.
fn best_deviation(fitted: &FitStage, refine: Option<&RouteSummary>, patent: &RouteSummary) -> f64 {
    fitted.summary.as_ref().map_or_else(
        || {
            refine.map_or(patent.max_deviation_mm, |r| {
                r.max_deviation_mm.min(patent.max_deviation_mm)
            })
        },
        |f| {
            if fitted.replaced {
                f.max_mm
            } else {
                f.start_max_mm
            }
        },
    )
}

/// The report's account of the compatibility analysis; `l3_mm` turns the residual into mm at the
/// tip.
fn compat_summary(compat: &Compatibility, l3_mm: f64) -> CompatSummary {
    CompatSummary {
        tau_deg: compat.tau_rad.to_degrees(),
        residual_rad: compat.residual_rad,
        tip_equivalent_mm: compat.residual_rad * l3_mm,
        endpoint_product: compat.endpoint_product,
        origins_deg: compat.origins_rad.iter().map(|t| t.to_degrees()).collect(),
    }
}

/// The trajectory part of the report: size, extreme distances, the reference instant, the needle
/// swing, the i31 range and the estimated noise.
fn trajectory_summary(traj: &Trajectory, inv: &Inversion, noise_sigma: f64) -> TrajectorySummary {
    let range = |v: &[f64]| {
        v.iter()
            .fold([f64::MAX, f64::MIN], |m, v| [m[0].min(*v), m[1].max(*v)])
    };
    let swing = range(inv.law.samples());
    TrajectorySummary {
        points: traj.len(),
        rho_max_mm: inv.rho_max_mm,
        rho_min_mm: inv.rho_min_mm,
        reference_carrier_angle_deg: inv.file_angle_deg(inv.phi_h0_rad),
        needle_swing_deg: 0.5 * (swing[1] - swing[0]).to_degrees(),
        i31_range: range(&inv.law.i31_samples()),
        noise_sigma_mm: noise_sigma,
    }
}
