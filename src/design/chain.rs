//! The design chain, stage by stage: step 1, compatibility, the patent route, the §8.3
//! refinement, the fit to the points, then the tables, checks and report.

use super::checks::finish;
use super::error::DesignError;
use super::options::validate;
use super::options::{ADAPTIVE_ORDERS, DesignOptions, RefineMode};
use super::report::*;
use super::start::invert_for_start;
use super::{compat, fit, refine, segmented};
use crate::design::compat::Compatibility;
use crate::design::fit::FitOptions;
use crate::design::trajectory::Trajectory;
use crate::geometry::fourier::SunRatio;
use crate::geometry::mechanism::Mechanism;
use std::f64::consts::{PI, TAU};
use std::time::Instant;

fn ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

/// Runs the whole chain on a trajectory.
pub fn design(traj: &Trajectory, opts: &DesignOptions) -> Result<Design, DesignError> {
    validate(opts)?;
    let t_all = Instant::now();
    let mut timings = Timings::default();
    let mut warnings = Vec::new();

    let t0 = Instant::now();
    let noise_sigma = traj.noise_sigma_mm();
    let (inv, start_smoothing) = invert_for_start(traj, opts, noise_sigma)?;
    timings.inverse = ms(t0);
    if let Some(h) = start_smoothing.filter(|_| opts.smoothing.is_none()) {
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
    let law = &inv.law;
    let (l3, a) = (inv.l3_mm, 0.5 * inv.l1_mm);
    let n = opts.inverse.grid.max(64) / 2 * 2;

    let t0 = Instant::now();
    let compat: Compatibility = compat::analyse(law, n, 1e-13);
    timings.compat = ms(t0);
    let tau = compat.tau_rad;

    // Patent route: segmented hypothesis, then the Fourier fit at fixed or adaptive order.
    let t0 = Instant::now();
    let seg = segmented::design(law, tau, n, &opts.segmented)?;
    if !seg.converged {
        warnings.push(format!(
            "patent iteration did not close the junctions (J0 = {:.3e} after {} steps): the target is not compatible with the train (E_c·l3 = {:.3} mm)",
            seg.j0,
            seg.iterations,
            compat.residual_rad * l3
        ));
    }
    let beta = |p: f64| inv.beta(p);
    let mk = |ratio: SunRatio, tau_s: f64| {
        let mut m = Mechanism {
            a_mm: a,
            l3_mm: l3,
            ratio,
            sun_phase_rad: inv.phi_h0_rad + tau_s,
            needle_angle_rad: 0.0,
        };
        let phis: Vec<f64> = (0..opts.check_samples)
            .map(|k| TAU * k as f64 / opts.check_samples as f64)
            .collect();
        m.fit_needle_angle(&phis, beta);
        let dev = m.synchronous_deviation_mm(opts.check_samples, beta);
        (m, dev)
    };
    let orders: Vec<usize> = match opts.order {
        Some(k) => vec![k],
        None => ADAPTIVE_ORDERS
            .iter()
            .copied()
            .filter(|&k| 4 * k <= n)
            .collect(),
    };
    let mut scan = Vec::new();
    let mut patent: Option<(Mechanism, f64, usize)> = None;
    let mut out_of_bounds: Option<(Mechanism, usize)> = None;
    for &k in &orders {
        let ratio = match SunRatio::fit_uniform(&seg.samples, k) {
            Ok(r) => r,
            Err(_) => SunRatio::new_unchecked(vec![0.0; k], vec![0.0; k]),
        };
        let (lo, hi) = (
            ratio.sampled_extreme(4096, false).0,
            ratio.sampled_extreme(4096, true).0,
        );
        let [blo, bhi] = opts.refine_options.ratio_bounds;
        if lo < blo || hi > bhi {
            // Outside the admissible ratios (spec §14): not a candidate, but kept as the
            // refinement's last-resort start.
            if out_of_bounds.is_none() {
                out_of_bounds = Some((mk(ratio, tau).0, k));
            }
            continue;
        }
        let (m, dev) = mk(ratio, tau);
        scan.push([k as f64, dev]);
        let better = patent.as_ref().is_none_or(|p| dev < p.1);
        if better {
            patent = Some((m, dev, k));
        }
        if dev <= opts.tol_tip_mm {
            break;
        }
    }
    let (patent_m, patent_dev, patent_k) = match (patent, out_of_bounds) {
        (Some(p), _) => p,
        (None, Some((m, k))) => {
            warnings.push("no Fourier order of the patent route stays within the ratio bounds; the refinement (with its bound penalty) decides".into());
            (m, f64::INFINITY, k)
        }
        (None, None) => {
            return Err(DesignError::Internal(
                "no Fourier order was tried (grid too small)".into(),
            ));
        }
    };
    timings.patent = ms(t0);
    let patent_summary = RouteSummary {
        order: patent_k,
        max_deviation_mm: patent_dev,
        j0: Some(seg.j0),
        j1: Some(seg.j1),
        iterations: seg.iterations,
        note: format!(
            "route {:?}, w1 = {}, {}",
            opts.segmented.route,
            opts.segmented.w1,
            if seg.converged {
                "junctions closed"
            } else {
                "junctions not closed"
            }
        ),
        order_scan: if opts.order.is_none() {
            scan
        } else {
            Vec::new()
        },
    };

    // Refinement (§8.3).
    let t0 = Instant::now();
    let run_refine = match opts.refine {
        RefineMode::On => true,
        RefineMode::Off => false,
        // The fit to the points (below) is the default refinement; §8.3 runs when asked for.
        RefineMode::Auto => false,
    };
    let mut refined = None;
    if run_refine {
        let k = opts.order.unwrap_or(opts.refine_order);
        // The patent route's ratio made admissible (spec §14): the refinement starts inside the bounds.
        let start = SunRatio::fit_uniform_unchecked(&seg.samples, k)
            .admissible(opts.refine_options.ratio_bounds);
        let (m0, _) = mk(start.clone(), tau);
        // C = π + γ for the start.
        let c0 = PI + m0.needle_angle_rad;
        let r = refine::refine(law, l3, a, &start, tau, c0, &opts.refine_options);
        match SunRatio::new(
            r.ratio.cos_coefficients().to_vec(),
            r.ratio.sin_coefficients().to_vec(),
        ) {
            Ok(ratio) => {
                let (m, dev) = mk(ratio, r.tau_rad);
                refined = Some((m, dev, k, r.evaluations, r.termination));
            }
            Err(e) => warnings.push(format!(
                "refinement left the admissible ratios ({e}); kept the patent route"
            )),
        }
    }
    timings.refine = ms(t0);
    let refine_summary = refined.as_ref().map(|(_, dev, k, ev, term)| RouteSummary {
        order: *k,
        max_deviation_mm: *dev,
        j0: None,
        j1: None,
        iterations: *ev,
        note: format!("Levenberg–Marquardt: {term}"),
        order_scan: Vec::new(),
    });
    let (mut mech, mut chosen) = match refined {
        Some((m, dev, ..)) if dev < patent_dev => (m, "refined"),
        _ => (patent_m, "patent"),
    };

    // The final stage: every parameter fitted to the points themselves (orthogonal distances).
    let t0 = Instant::now();
    let [lo, hi] = opts.refine_options.ratio_bounds;
    let points = traj.relative_to(opts.center_mm, inv.direction < 0);
    let admissible = |m: &Mechanism| {
        let [rlo, rhi] = m.ratio.range();
        rlo >= lo && rhi <= hi
    };
    let start = fit::measure(&points, &mech);
    let (start_max, start_rms) = (start.max_mm, start.rms_mm);
    let mut angles = start.carrier_angles_rad;
    let run_fit = opts.fit_to_points
        && match opts.refine {
            RefineMode::Off => false,
            RefineMode::On => true,
            RefineMode::Auto => {
                start_smoothing.is_some()
                    || !admissible(&mech)
                    || start_max > FIT_TOL_FRACTION * opts.tol_tip_mm
            }
        };
    let mut fit_summary = None;
    if run_fit {
        let fit_opts = FitOptions {
            order: opts.order,
            ratio_bounds: opts.refine_options.ratio_bounds,
            tol_mm: FIT_TOL_FRACTION * opts.tol_tip_mm,
            noise_sigma_mm: noise_sigma,
            ..FitOptions::default()
        };
        let restarts = [2]
            .into_iter()
            .filter_map(|k| {
                SunRatio::fit_uniform(&seg.samples, k)
                    .or_else(|_| SunRatio::fit_uniform(&seg.samples, 1))
                    .ok()
                    .map(|r| mk(r.admissible(opts.refine_options.ratio_bounds), tau).0)
            })
            .collect();
        let f = fit::fit_with_restarts(&points, &mech, restarts, &fit_opts, opts.tol_tip_mm)
            .map_err(|e| DesignError::Internal(e.to_string()))?;
        fit_summary = Some(FitSummary {
            order: f.mechanism.ratio.order(),
            rms_mm: f.rms_mm,
            max_mm: f.max_mm,
            start_rms_mm: start_rms,
            start_max_mm: start_max,
            noise_sigma_mm: noise_sigma,
            start_smoothing_harmonics: start_smoothing,
            iterations: f.iterations,
            order_scan: f.order_scan.clone(),
        });
        if f.rms_mm < start_rms || !admissible(&mech) {
            mech = f.mechanism;
            angles = f.carrier_angles_rad;
            chosen = "fit";
        }
    }
    timings.fit = ms(t0);
    let best_dev = fit_summary.as_ref().map_or_else(
        || {
            refine_summary
                .as_ref()
                .map_or(patent_dev, |r| r.max_deviation_mm.min(patent_dev))
        },
        |f| if chosen == "fit" { f.max_mm } else { start_max },
    );
    if best_dev > opts.tol_tip_mm && noise_sigma < FIT_TOL_FRACTION * opts.tol_tip_mm {
        warnings.push(format!(
            "the best design deviates {best_dev:.3} mm from the target (tolerance {} mm): no train of this type traces it exactly (E_c·l3 = {:.3} mm); this is the closest admissible design found",
            opts.tol_tip_mm,
            compat.residual_rad * l3
        ));
    }

    // Outputs, checks, round trip.
    let t0 = Instant::now();
    let [imin, imax] = mech.ratio.range();
    if imin < lo || imax > hi {
        return Err(DesignError::RatioOutOfBounds {
            min: imin,
            max: imax,
            lo,
            hi,
        });
    }
    let out = finish(traj, &inv, &compat, mech, &angles, opts, &mut warnings)?;
    timings.outputs = ms(t0);
    timings.total = ms(t_all);
    let (mechanism, assembly, traced, checks, roundtrip, gears) = out;
    let i31 = law.i31_samples();
    let swing = law
        .samples()
        .iter()
        .fold([f64::MAX, f64::MIN], |m, v| [m[0].min(*v), m[1].max(*v)]);
    let sign = f64::from(inv.direction);
    let report = DesignReport {
        units: Units {
            length: "mm".into(),
            angle: "deg".into(),
        },
        l1: mechanism.l1_mm(),
        l3: mechanism.l3_mm,
        center_distance: mechanism.a_mm,
        needle_angle_deg: sign * mechanism.needle_angle_rad.to_degrees(),
        carrier: Carrier {
            center: opts.center_mm,
            direction: inv.direction,
        },
        gears,
        roundtrip,
        trajectory: TrajectorySummary {
            points: traj.len(),
            rho_max_mm: inv.rho_max_mm,
            rho_min_mm: inv.rho_min_mm,
            reference_carrier_angle_deg: inv.file_angle_deg(inv.phi_h0_rad),
            needle_swing_deg: 0.5 * (swing[1] - swing[0]).to_degrees(),
            i31_range: i31
                .iter()
                .fold([f64::MAX, f64::MIN], |m, v| [m[0].min(*v), m[1].max(*v)]),
            noise_sigma_mm: noise_sigma,
        },
        compatibility: CompatSummary {
            tau_deg: compat.tau_rad.to_degrees(),
            residual_rad: compat.residual_rad,
            tip_equivalent_mm: compat.residual_rad * l3,
            endpoint_product: compat.endpoint_product,
            origins_deg: compat.origins_rad.iter().map(|t| t.to_degrees()).collect(),
        },
        patent_route: patent_summary,
        refinement: refine_summary,
        fit: fit_summary,
        chosen: chosen.into(),
        fourier: FourierSummary {
            order: mechanism.ratio.order(),
            a: mechanism.ratio.cos_coefficients().to_vec(),
            b: mechanism.ratio.sin_coefficients().to_vec(),
            sun_phase_deg: inv.file_angle_deg(mechanism.sun_phase_rad),
            i21_range: [imin, imax],
        },
        checks,
        target_points: traj.points().to_vec(),
        warnings,
        teeth: None,
        timings_ms: timings,
    };
    Ok(Design {
        report,
        mechanism,
        assembly,
        inversion: inv,
        traced_mm: traced,
    })
}

/// The fit aims at this fraction of `tol_tip_mm` on the points, and runs (refine auto) when the
/// chain's result is farther: room for the table rebuild and for the curve between the points.
const FIT_TOL_FRACTION: f64 = 0.2;
