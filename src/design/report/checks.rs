//! Pitch tables, assembly, checks C1–C13 and the round trip from the output tables (docs/math/chain.md §9–§10).

use crate::design::error::DesignError;
use crate::design::fit::noise;
use crate::design::inverse::Inversion;
use crate::design::inverse::compat::Compatibility;
use crate::design::options::{DesignOptions, SUN_PLANET_GAP_MODULES};
use crate::design::report::*;
use crate::design::trajectory::Trajectory;
use crate::design::trajectory::roundtrip::{target_hausdorff_mm, tip_deviations, trace};
use crate::geometry::assembly::{Assembly, Rebuilt};
use crate::geometry::mechanism::{INVERSE_TOL_RAD, Mechanism};
use crate::geometry::pitch::{CurvatureSummary, PitchCurve};
use crate::math::Point;
use std::f64::consts::TAU;

fn rms(v: &[f64]) -> f64 {
    (v.iter().map(|d| d * d).sum::<f64>() / v.len().max(1) as f64).sqrt()
}

/// What [`finish`] hands back to the chain.
pub(in crate::design) struct Finished {
    pub mechanism: Mechanism,
    pub assembly: Assembly,
    /// The kinematics rebuilt from the tables (the round trip).
    pub rebuilt: Rebuilt,
    /// The traced tip path, world frame, mm.
    pub traced: Vec<Point>,
    /// The carrier angle at which the tip passes each point, rad (solved frame).
    pub angles: Vec<f64>,
    pub checks: Vec<Check>,
    pub roundtrip: RoundTrip,
    pub gears: Gears,
    pub limits: LimitsSummary,
}

/// Pitch curves, assembly, checks C1–C13 and the round trip from the output tables.
pub(in crate::design) fn finish(
    traj: &Trajectory,
    inv: &Inversion,
    compat: &Compatibility,
    mech: Mechanism,
    angles: &[f64],
    opts: &DesignOptions,
    warnings: &mut Vec<String>,
) -> Result<Finished, DesignError> {
    let n = opts.samples;
    let sign = f64::from(inv.direction);
    let assembly = Assembly::from_mechanism(&mech, opts.center_mm, inv.direction, n)?;
    let (sun, mid, planet) = (
        assembly.sun.clone(),
        assembly.intermediate.clone(),
        assembly.planet.clone(),
    );
    // Round trip from the tables only (C12), with mesh errors (C3, C4).
    let rebuilt = assembly.rebuild();
    let m = opts.check_samples;
    let (traced, mesh) = trace(&rebuilt, m, sign);
    let dev = tip_deviations(&rebuilt, traj.points(), angles, sign);
    let sync = dev.iter().copied().fold(0.0, f64::max);
    // On measured points C12 judges the estimated deviation from the curve under the noise.
    let noise_sigma_mm = traj.noise_sigma_mm();
    let params = noise::fitted_parameters(mech.ratio.order());
    let estimated = noise::curve_deviation_mm(noise_sigma_mm, rms(&dev), dev.len(), params);
    let g = measure([&sun, &mid, &planet], &mech, n, || {
        target_hausdorff_mm(&traced, traj.points(), angles, 2 * m)
    });
    let roundtrip = RoundTrip {
        max_deviation_mm: sync,
        rms_deviation_mm: rms(&dev),
        hausdorff_mm: g.hausdorff_mm,
        max_mesh_error_mm: mesh[0].max(mesh[1]),
        estimated_curve_deviation_mm: estimated,
        samples: m,
    };
    let c12 = noise::c12_measure(sync, estimated, noise_sigma_mm);
    let checks = geometry_checks(&mech, &rebuilt, mesh, &g, opts, compat, c12);
    let (alpha, tightest_concave) = (opts.pressure_angle_rad, g.tightest_concave_mm());
    if g.min_convexity_mm2() <= 0.0 && tightest_concave >= opts.min_concave_radius_in_force_mm() {
        warnings.push(format!(
            "a pitch curve is concave somewhere (tightest concave radius {tightest_concave:.2} mm): a rack cannot cut it; a shaper cutter of pitch radius below that radius is needed"
        ));
    }
    warnings.extend(checks.iter().filter(|c| !c.pass).map(|c| {
        format!(
            "check {} failed: {} = {:.4e} (limit {:.4e})",
            c.id, c.name, c.value, c.limit
        )
    }));
    let ([ls, lm, lp], [cs, cm]) = (g.perimeters_mm, &g.curvature);
    let gear = |c: &PitchCurve, angle: Option<f64>, perim: f64, k: &CurvatureSummary| {
        gear_report(c.polar_table_deg(n), angle, perim, k, alpha)
    };
    let gears = Gears {
        sun: gear(&sun, None, ls, cs),
        intermediate: gear(&mid, Some(assembly.intermediate_angle_at_zero_rad), lm, cm),
        // The planet is the sun's copy: the same curvature.
        planet: gear(&planet, Some(assembly.planet_angle_at_zero_rad), lp, cs),
    };
    let effective = g.effective_pressure_angle_rad(alpha);
    let ratio_range = mech.ratio.range();
    let limits = limits_summary(
        opts,
        effective,
        [tightest_concave, g.min_rho_mm()],
        ratio_range,
    );
    Ok(Finished {
        mechanism: mech,
        assembly,
        rebuilt,
        traced,
        angles: angles.to_vec(),
        checks,
        roundtrip,
        gears,
        limits,
    })
}

/// The finished design's measures: perimeters (sun, intermediate, planet, mm), curvature
/// summaries (sun, intermediate; the planet is the sun's copy), the Hausdorff distance to the
/// target (mm) and the smallest i31.
struct Measures {
    perimeters_mm: [f64; 3],
    curvature: [CurvatureSummary; 2],
    hausdorff_mm: f64,
    i31_min: f64,
}

impl Measures {
    /// Smallest convexity Δ = r² + 2r′² − r r″ of sun and intermediate, mm².
    fn min_convexity_mm2(&self) -> f64 {
        let [cs, cm] = &self.curvature;
        cs.min_convexity_mm2.min(cm.min_convexity_mm2)
    }

    /// Smallest radius of curvature of sun and intermediate, mm.
    fn min_rho_mm(&self) -> f64 {
        let [cs, cm] = &self.curvature;
        cs.min_radius_of_curvature_mm
            .min(cm.min_radius_of_curvature_mm)
    }

    /// Tightest concave radius of curvature, mm: ∞ (written as null) when both curves are convex.
    fn tightest_concave_mm(&self) -> f64 {
        let [cs, cm] = &self.curvature;
        cs.min_concave_radius_mm.min(cm.min_concave_radius_mm)
    }

    /// Effective pressure angle α + max|atan(r_θ/r)| at rack pressure angle `alpha` (rad), rad.
    fn effective_pressure_angle_rad(&self, alpha: f64) -> f64 {
        let [cs, cm] = &self.curvature;
        alpha
            + cs.max_pressure_deviation_rad
                .max(cm.max_pressure_deviation_rad)
    }
}

/// The independent integrals and scans of the three `curves` (sun, intermediate, planet; `n`
/// samples each) side by side, with the Hausdorff distance `hausdorff` (mm) beside them.
fn measure(
    [sun, mid, planet]: [&PitchCurve; 3],
    mech: &Mechanism,
    n: usize,
    hausdorff: impl FnOnce() -> f64 + Send,
) -> Measures {
    // Serial, as is the Hausdorff distance: both run beside the geometry integrals below.
    let i31_scan = || min_i31(&mech.ratio, mech.contact_shift_rad());
    let acc = 1e-9 * mech.a_mm;
    let (((ls, lm), (lp, (cs, cm))), (hausdorff_mm, i31_min)) = rayon::join(
        || {
            rayon::join(
                || rayon::join(|| sun.perimeter_mm(acc), || mid.perimeter_mm(acc)),
                || {
                    rayon::join(
                        || planet.perimeter_mm(acc),
                        || {
                            rayon::join(
                                || sun.curvature_extremes(8 * n),
                                || mid.curvature_extremes(8 * n),
                            )
                        },
                    )
                },
            )
        },
        || rayon::join(hausdorff, i31_scan),
    );
    Measures {
        perimeters_mm: [ls, lm, lp],
        curvature: [cs, cm],
        hausdorff_mm,
        i31_min,
    }
}

/// Checks C1–C13 of the finished design: `mesh` the largest centre-distance errors of the two
/// meshes (mm), `c12` the name and value (mm) of the round-trip check.
fn geometry_checks(
    mech: &Mechanism,
    rebuilt: &Rebuilt,
    mesh: [f64; 2],
    g: &Measures,
    opts: &DesignOptions,
    compat: &Compatibility,
    (c12_name, c12_value): (String, f64),
) -> Vec<Check> {
    let ([ls, lm, lp], [cs, cm]) = (g.perimeters_mm, &g.curvature);
    let i31_min = g.i31_min;
    let means = rebuilt.ratio_means();
    let [imin, imax] = mech.ratio.range();
    let (min_conv, min_rho) = (g.min_convexity_mm2(), g.min_rho_mm());
    let alpha = opts.pressure_angle_rad;
    let [lo, hi] = opts.refine_options.ratio_bounds;
    let check = |id: &str, name: String, value: f64, limit: f64, pass: bool| Check {
        id: id.into(),
        name,
        value,
        limit,
        pass,
    };
    let closure = (mech.ratio.integral(TAU) - TAU).abs();
    let table_closure = (means[0] - 1.0).abs().max((means[1] - 1.0).abs()) * TAU * mech.a_mm;
    let mesh_limit = 1e-6 * mech.a_mm;
    let slip = (ls - lm).abs().max((ls - lp).abs()) / ls;
    let rack_module = if min_conv > 0.0 {
        min_rho * alpha.sin().powi(2)
    } else {
        0.0
    };
    let effective = g.effective_pressure_angle_rad(alpha);
    let limit_deg = opts.max_pressure_angle_rad.to_degrees();
    let concave_limit = opts.min_concave_radius_in_force_mm();
    let convex_limit = opts.min_convex_radius_in_force_mm();
    let tightest_concave = g.tightest_concave_mm();
    let compat_mm = compat.residual_rad * mech.l3_mm;
    let tol = opts.tol_mm;
    let (gap, gap_limit) = (mech.sun_planet_gap_mm(), opts.sun_planet_gap_mm());
    #[rustfmt::skip]
    let checks = vec![
        check("C1", "closure of the ratio |Φ(2π) − 2π|, rad".into(),
            closure, 1e-12, closure <= 1e-12),
        check("C2", "closure of the output tables: max |mean r/(a−r) − 1|·2π·a, mm".into(),
            table_closure, 1e-6, table_closure <= 1e-6),
        check("C3", "centre distance sun–intermediate max |r1 + ρ2 − a|, mm".into(),
            mesh[0], mesh_limit, mesh[0] <= mesh_limit),
        check("C4", "centre distance intermediate–planet max |r3 + ρ2 − a|, mm".into(),
            mesh[1], mesh_limit, mesh[1] <= mesh_limit),
        check("C5", "rolling without slip: max relative perimeter difference".into(),
            slip, 1e-7, slip <= 1e-7),
        check("C6", format!("ratio bounds: i21 in [{lo}, {hi}] (value: min i21), i31 > 0 (min i31 = {i31_min:.4})"),
            imin, lo, imin >= lo && imax <= hi && i31_min > 0.0),
        check("C7", "convexity: min Δ = r² + 2r′² − r r″ of sun and intermediate, mm²".into(),
            min_conv, 0.0, true),
        check("C8", match convex_limit {
                Some(_) => format!("undercut: smallest convex radius of curvature of the sun, intermediate and planet, mm, at least the undercut limit (largest rack module without any undercut ρ·sin²α = {rack_module:.3} mm at α = {:.1}°)", alpha.to_degrees()),
                None => format!("undercut: smallest convex radius of curvature, mm (report without a module: largest rack module without undercut ρ·sin²α = {rack_module:.3} mm at α = {:.1}°)", alpha.to_degrees()),
            },
            min_rho, convex_limit.unwrap_or(0.0), min_rho >= convex_limit.unwrap_or(0.0)),
        check("C9", format!("concave arcs: tightest concave radius of curvature of the sun, intermediate and planet, mm (∞/null = convex; concave fraction {:.3}), at least the smallest shaper cutter's pitch radius", cs.concave_fraction.max(cm.concave_fraction)),
            tightest_concave, concave_limit, tightest_concave >= concave_limit),
        check("C10", "max effective pressure angle α + max|atan(r_θ/r)|, deg".into(),
            effective.to_degrees(), limit_deg, effective <= opts.max_pressure_angle_rad),
        check("C11", "compatibility l3·E_c, mm (report)".into(),
            compat_mm, tol, true),
        check("C12", c12_name, c12_value, tol, c12_value <= tol),
        check("C13", format!("sun–planet clearance: l1 − 2·(largest sun and planet pitch radius), mm (idler offset {:.3}°), above {SUN_PLANET_GAP_MODULES}·m (two addenda and a root clearance) with a module", mech.idler_offset_rad.to_degrees()),
            gap, gap_limit, gap > 0.0 && gap >= gap_limit),
    ];
    checks
}

/// The smallest i31 = i(t)/i(S(t)) along the turn (4096 samples), each contact angle
/// S = Φ⁻¹(Φ(t) + c) (`shift_rad` = c = π + 2ε) solved from the previous one (S′ = i(t)/i(S)):
/// a step or two of Newton instead of a cold start.
fn min_i31(ratio: &crate::geometry::fourier::SunRatio, shift_rad: f64) -> f64 {
    let mut s_prev = f64::NAN;
    (0..4096)
        .map(|k| {
            let t = TAU * k as f64 / 4096.0;
            let (fi, it) = ratio.integral_and_value(t);
            let s = ratio.inverse_integral_from(fi + shift_rad, s_prev, INVERSE_TOL_RAD);
            let is = ratio.value(s);
            s_prev = s + TAU / 4096.0 * it / is;
            it / is
        })
        .fold(f64::INFINITY, f64::min)
}

/// A gear's entry in the report: its pitch table, its angle at φH = 0 (rad), perimeter (mm) and
/// curvature summary, its largest effective pressure angle for rack pressure angle `alpha` (rad).
fn gear_report(
    pitch: Vec<[f64; 2]>,
    angle: Option<f64>,
    perimeter_mm: f64,
    k: &CurvatureSummary,
    alpha: f64,
) -> Gear {
    Gear {
        pitch,
        angle_at_zero_deg: angle.map(|a| a.to_degrees().rem_euclid(360.0)),
        perimeter_mm,
        min_radius_of_curvature_mm: k.min_radius_of_curvature_mm,
        min_concave_radius_mm: k
            .min_concave_radius_mm
            .is_finite()
            .then_some(k.min_concave_radius_mm),
        concave_fraction: k.concave_fraction,
        max_pressure_angle_deg: (alpha + k.max_pressure_deviation_rad).to_degrees(),
    }
}

/// Where the design stands against its gear limits, and which of them it sits on (within 1 %).
fn limits_summary(
    opts: &DesignOptions,
    pressure_angle_rad: f64,
    [tightest_concave_mm, tightest_convex_mm]: [f64; 2],
    ratio_range: [f64; 2],
) -> LimitsSummary {
    let limits = opts.limits_in_force();
    let [lo, hi] = limits.ratio_bounds();
    let (pa_max, r_min) = (
        opts.max_pressure_angle_rad,
        opts.min_concave_radius_in_force_mm(),
    );
    let near = |v: f64, limit: f64| (v - limit).abs() <= 0.01 * limit;
    let binding = [
        ("pressure angle", near(pressure_angle_rad, pa_max)),
        ("concave radius", near(tightest_concave_mm, r_min)),
        (
            "convex radius (undercut)",
            opts.min_convex_radius_in_force_mm()
                .is_some_and(|r| near(tightest_convex_mm, r)),
        ),
        (
            "ratio bounds",
            near(ratio_range[0], lo) || near(ratio_range[1], hi),
        ),
    ]
    .into_iter()
    .filter(|b| b.1)
    .map(|b| b.0.to_string())
    .collect();
    LimitsSummary {
        enabled: limits.limits_gears(),
        max_pressure_angle_deg: pa_max.to_degrees(),
        min_concave_radius_mm: r_min,
        min_convex_radius_mm: opts.min_convex_radius_in_force_mm(),
        ratio_bounds: [lo, hi],
        pressure_angle_deg: pressure_angle_rad.to_degrees(),
        tightest_concave_radius_mm: tightest_concave_mm
            .is_finite()
            .then_some(tightest_concave_mm),
        tightest_convex_radius_mm: tightest_convex_mm,
        ratio_range,
        binding,
    }
}
