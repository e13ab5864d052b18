//! The chain's routes to a train before the fit: the patent route (segmented ratio, mirror and
//! weights) and, when asked for, the docs/math/chain.md §8.3 refinement; the better of them.

use crate::design::error::DesignError;
use crate::design::hypothesis::refine;
use crate::design::hypothesis::segmented::{self, Segmented};
use crate::design::inverse::compat::Compatibility;
use crate::design::options::{ADAPTIVE_ORDERS, RefineMode};
use crate::design::report::*;
use crate::design::strategy::arms::ArmTrains;
use crate::design::strategy::module::check_module;
use crate::geometry::fourier::SunRatio;
use crate::geometry::mechanism::{MAX_IDLER_OFFSET_RAD, Mechanism};
use std::f64::consts::PI;
use std::time::Instant;
/// What the chain's routes leave for the fit: the patent route's segmented law and result, the
/// refinement's summary, the better mechanism and its name, and the warnings that wait for the
/// round trip `(position, text)`.
pub(in crate::design) struct Routes {
    pub(in crate::design) chain: Chain,
    pub(in crate::design) patent: Patent,
    pub(in crate::design) refine_summary: Option<RouteSummary>,
    pub(in crate::design) pending: Vec<(usize, String)>,
}

/// The chain's result the fit starts from: the segmented law on the half-closure origin
/// `tau_rad`, the better route's mechanism and its name.
pub(in crate::design) struct Chain {
    pub(in crate::design) seg: Segmented,
    pub(in crate::design) tau_rad: f64,
    pub(in crate::design) mech: Mechanism,
    pub(in crate::design) chosen: &'static str,
}

/// The patent route on an `n`-point grid, then the docs/math/chain.md §8.3 refinement when asked
/// for; the better of them.
pub(in crate::design) fn chain_routes(
    trains: &ArmTrains,
    compat: &Compatibility,
    n: usize,
    timings: &mut Timings,
    warnings: &mut Vec<String>,
) -> Result<Routes, DesignError> {
    let t0 = Instant::now();
    let seg = segmented::design(&trains.inv.law, compat.tau_rad, n, &trains.opts.segmented)?;
    // Warnings that the noise of measured points can explain wait for the round trip (C12), at
    // the place they would have had.
    let mut pending: Vec<(usize, String)> = Vec::new();
    let incompatible_at = warnings.len();
    let mut patent = patent_route(trains, &seg, compat, n, warnings)?;
    pending.extend(patent.incompatibility.take().map(|w| (incompatible_at, w)));
    timings.patent = ms(t0);
    if let Some(m) = trains.opts.module_mm {
        check_module(&patent.mechanism, m)?;
    }
    check_convex_limit(trains)?;
    let t0 = Instant::now();
    let refined = refine_route(trains, &seg, compat.tau_rad, warnings);
    timings.refine = ms(t0);
    let (mech, chosen, refine_summary) = chain_choice(&patent, refined);
    Ok(Routes {
        chain: Chain {
            seg,
            tau_rad: compat.tau_rad,
            mech,
            chosen,
        },
        patent,
        refine_summary,
        pending,
    })
}

/// Slack on the arm length `l1` of step 1 in [`check_convex_limit`]: the fit moves it by less
/// (within 1 % on the 13 bundled targets, the kidney 0.6 %).
const L1_SLACK: f64 = 1.1;

/// Refuses a convex-radius limit no train tracing the target can meet. Its gears turn at a
/// centre distance `a = l1/(2·cos ε) ≤ L1_SLACK·l1/(2·cos 30°)` ([`MAX_IDLER_OFFSET_RAD`]), where
/// no ratio within the limits has a convex arc flatter than
/// [`crate::geometry::limits::GearLimits::flattest_convex_radius_mm`]: every fit would shrink
/// the ratio to a circle and the design would miss the target by the size of the loop.
fn check_convex_limit(trains: &ArmTrains) -> Result<(), DesignError> {
    let Some(limit_mm) = trains.limits.min_convex_radius_mm() else {
        return Ok(());
    };
    let a_max_mm = L1_SLACK * trains.inv.l1_mm / (2.0 * MAX_IDLER_OFFSET_RAD.cos());
    let flattest_mm = trains.limits.flattest_convex_radius_mm(a_max_mm);
    if limit_mm <= flattest_mm {
        return Ok(());
    }
    let opts = trains.opts;
    Err(DesignError::ConvexLimitUnreachable {
        limit_mm,
        module_mm: opts
            .module_mm
            .filter(|_| opts.min_convex_radius_mm.is_none()),
        flattest_mm,
        a_max_mm,
    })
}

/// The chain's mechanism before the fit: the refined one when it deviates less than the patent
/// route's, with its name and the refinement's summary.
fn chain_choice(
    patent: &Patent,
    refined: Option<(Mechanism, RouteSummary)>,
) -> (Mechanism, &'static str, Option<RouteSummary>) {
    match refined {
        Some((m, r)) if r.max_deviation_mm < patent.summary.max_deviation_mm => {
            (m, "refined", Some(r))
        }
        refined => (patent.mechanism.clone(), "patent", refined.map(|(_, r)| r)),
    }
}

/// The patent route's result: its best mechanism and summary, and the warning that the junctions
/// did not close (the target is not compatible with the train), if they did not.
pub(in crate::design) struct Patent {
    pub(in crate::design) mechanism: Mechanism,
    pub(in crate::design) summary: RouteSummary,
    pub(in crate::design) incompatibility: Option<String>,
}

/// The patent route (docs/math/chain.md §7–§8.2): the segmented hypothesis fitted by a Fourier series at the
/// fixed order, or at the adaptive orders until the deviation is within tolerance; orders whose
/// ratio leaves the bounds are not candidates (the first is kept as a last resort).
fn patent_route(
    trains: &ArmTrains,
    seg: &Segmented,
    compat: &Compatibility,
    n: usize,
    warnings: &mut Vec<String>,
) -> Result<Patent, DesignError> {
    let opts = trains.opts;
    let tau = compat.tau_rad;
    let incompatibility = (!seg.converged).then(|| {
        format!(
            "patent iteration did not close the junctions (J0 = {:.3e} after {} steps): the target is not compatible with the train (E_c·l3 = {:.3} mm)",
            seg.j0,
            seg.iterations,
            compat.residual_rad * trains.inv.l3_mm
        )
    });
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
        let [(lo, _), (hi, _)] = ratio.sampled_extremes(4096);
        let [blo, bhi] = opts.refine_options.ratio_bounds;
        if lo < blo || hi > bhi {
            // Outside the admissible ratios (docs/math/chain.md §14): not a candidate, but kept as the
            // refinement's last-resort start.
            if out_of_bounds.is_none() {
                out_of_bounds = Some((trains.build(ratio, tau).0, k));
            }
            continue;
        }
        let (m, dev) = trains.build(ratio, tau);
        scan.push([k as f64, dev]);
        let better = patent.as_ref().is_none_or(|p| dev < p.1);
        if better {
            patent = Some((m, dev, k));
        }
        if dev <= opts.tol_mm {
            break;
        }
    }
    let (mechanism, dev, order) = match (patent, out_of_bounds) {
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
    let summary = RouteSummary {
        order,
        max_deviation_mm: dev,
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
    Ok(Patent {
        mechanism,
        summary,
        incompatibility,
    })
}

/// The refinement of docs/math/chain.md §8.3 (only with [`RefineMode::On`]: the fit to the points is the default
/// refinement), from the patent route's ratio made admissible (docs/math/chain.md §14).
fn refine_route(
    trains: &ArmTrains,
    seg: &Segmented,
    tau: f64,
    warnings: &mut Vec<String>,
) -> Option<(Mechanism, RouteSummary)> {
    let opts = trains.opts;
    if opts.refine != RefineMode::On {
        return None;
    }
    let k = opts.order.unwrap_or(opts.refine_order);
    let start = SunRatio::fit_uniform_unchecked(&seg.samples, k)
        .admissible(opts.refine_options.ratio_bounds);
    let (m0, _) = trains.build(start.clone(), tau);
    // C = π + γ for the start.
    let c0 = PI + m0.needle_angle_rad;
    let inv = trains.inv;
    let r = refine::refine(
        &inv.law,
        inv.l3_mm,
        0.5 * inv.l1_mm,
        &start,
        tau,
        c0,
        &opts.refine_options,
    );
    match SunRatio::new(
        r.ratio.cos_coefficients().to_vec(),
        r.ratio.sin_coefficients().to_vec(),
    ) {
        Ok(ratio) => {
            let (m, dev) = trains.build(ratio, r.tau_rad);
            let summary = RouteSummary {
                order: k,
                max_deviation_mm: dev,
                j0: None,
                j1: None,
                iterations: r.evaluations,
                note: format!("Levenberg–Marquardt: {}", r.termination),
                order_scan: Vec::new(),
            };
            Some((m, summary))
        }
        Err(e) => {
            warnings.push(format!(
                "refinement left the admissible ratios ({e}); kept the patent route"
            ));
            None
        }
    }
}
