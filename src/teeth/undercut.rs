//! Undercut and concavity report of a rack-cut pitch curve (docs/math/teeth.md §12.4): per flank,
//! the sign of the envelope speed factor over its generating range.

use super::blank::OutlineOptions;
use super::frame::{ArcFrame, FramePoint};
use super::{FlankUndercut, GearBlank, RackParams, TeethError, UndercutReport};
use crate::geometry::pitch::PitchCurve;

/// Undercut and concavity report of a toothed pitch curve (docs/math/teeth.md §12.4).
///
/// For each flank the sign of `sin α + η κ(s)/sin α` (the envelope speed factor) is checked over
/// the generating range below the pitch curve; a sign change is an undercut (cusp at depth
/// `ρc·sin²α`). A flank whose generating range meets `κ < 0` is concave (cannot be rack-cut).
pub fn undercut_report(
    curve: &PitchCurve,
    rack: &RackParams,
    z: u32,
    module_mm: f64,
    opts: &OutlineOptions,
) -> Result<UndercutReport, TeethError> {
    let frame = ArcFrame::new(curve);
    Ok(report_on(&GearBlank::new(
        &frame, *rack, z, module_mm, *opts,
    )))
}

pub(super) fn report_on(blank: &GearBlank<'_>) -> UndercutReport {
    let (frame, rack, z, m, opts) = (
        blank.frame,
        &blank.rack,
        blank.z,
        blank.module_mm,
        &blank.opts,
    );
    let p = opts
        .open_pitch_mm
        .unwrap_or(frame.length_mm() / f64::from(z));
    let (sa, ca) = rack.alpha_rad().sin_cos();
    let sc = sa * ca;
    let hs = rack.straight_depth() * m;
    let ha = rack.addendum() * m;
    let mut flanks = Vec::with_capacity(2 * z as usize);
    for k in 0..z as usize {
        let sk = opts.phase_mm + k as f64 * p;
        for (side, sign, sf) in [
            ("left", -1.0, sk - 0.25 * p + opts.thin_left_mm),
            ("right", 1.0, sk + 0.25 * p - opts.thin_right_mm),
        ] {
            let mut worst = f64::INFINITY;
            let mut kmax = f64::NEG_INFINITY;
            let mut kmin = f64::INFINITY;
            let n = 48;
            for j in 0..=n {
                // η from +ha (tip) down to −hs
                let eta = ha - (ha + hs) * j as f64 / n as f64;
                let s = sf - sign * eta / sc;
                let fp: FramePoint = frame.at(s);
                kmax = kmax.max(fp.kappa);
                kmin = kmin.min(fp.kappa);
                if eta < 0.0 {
                    worst = worst.min(sa + eta * fp.kappa / sa);
                }
            }
            let rho = 1.0 / kmax;
            let cusp = if kmax > 0.0 {
                rho * sa * sa
            } else {
                f64::INFINITY
            };
            let undercut = worst < 0.0;
            flanks.push(FlankUndercut {
                tooth: k,
                side,
                s_mm: sf,
                min_rho_mm: if kmin <= 0.0 { 1.0 / kmin } else { rho },
                cusp_depth_mm: cusp,
                flank_depth_mm: hs,
                undercut,
                undercut_mm: if undercut { (hs - cusp).max(0.0) } else { 0.0 },
                concave: kmin <= 0.0,
                form_depth_mm: hs,
                contact_ratio_loss: 0.0,
                root_thickness_mm: None,
            });
        }
    }
    let required = rack.undercut_limit_rho_mm(m);
    let rho_convex = flanks
        .iter()
        .filter(|f| !f.concave)
        .map(|f| f.min_rho_mm)
        .fold(f64::INFINITY, f64::min);
    let mut report = UndercutReport {
        undercut_count: 0,
        concave_count: 0,
        min_rho_mm: f64::INFINITY,
        required_rho_mm: required,
        max_module_mm: m * rho_convex / required,
        flanks,
        max_undercut_mm: 0.0,
        max_contact_ratio_loss: 0.0,
        min_root_thickness_mm: None,
    };
    report.summarize();
    report
}
