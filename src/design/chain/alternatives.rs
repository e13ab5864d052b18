//! What would pass: when a design fails its verification, the nearest alternatives the chain can
//! evaluate in one more design each, with their figures, so that a user reads not only that the
//! target is missed but what would reach it — "off the carrier line (`--idler-offset free`) the
//! same limits trace it within 0.081 mm".
//!
//! The candidates, in order, each tried only where it applies and changes something: the other
//! idler layout (off the carrier line, ε free in every fit, the same limits: another housing),
//! a pressure-angle limit 5° looser (where that limit binds), the next smaller standard module
//! (designing for a module). The first that applies is designed — one more design for a failing
//! design, nothing for a passing one — only when asked ([`DesignOptions::alternatives`], the
//! CLI's `--alternatives`, Python's `alternatives=True`): each alternative is a full design, as
//! long as the failed one, and a warm start from the failed train does not reach the
//! alternative's own optimum (the kidney off the line: 1.83 mm warm against 0.081 mm designed),
//! so a figure is given only as the alternative's own command reaches it. Unasked, a failed
//! design names the candidates that apply and how to have them designed ([`untried_note`]), at
//! no cost.

use crate::design::options::{DesignOptions, IdlerOffset};
pub use crate::design::report::Alternative;
use crate::design::report::DesignReport;
use crate::design::trajectory::Trajectory;

/// Most alternatives designed for one failed design.
pub const MAX_ALTERNATIVES: usize = 1;

/// The standard modules below which a smaller one is looked for, mm (ISO 54, series I and 1.25).
const MODULES_MM: [f64; 12] = [0.5, 0.6, 0.8, 1.0, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0];

/// The candidates that apply to a design made with `opts` whose report is `report`:
/// `(label, flags, options)`.
fn candidates(opts: &DesignOptions, report: &DesignReport) -> Vec<(String, String, DesignOptions)> {
    let mut out = Vec::new();
    let base = opts.clone().with_alternatives(false);
    if opts.idler_offset != IdlerOffset::Free {
        out.push((
            "off the carrier line, the same limits".into(),
            "--idler-offset free".into(),
            base.clone().with_idler_offset(IdlerOffset::Free),
        ));
    }
    let limit_deg = opts.max_pressure_angle_rad.to_degrees();
    if opts.limits && report.limits.binding.iter().any(|b| b == "pressure angle") {
        let looser = (limit_deg + 5.0).round();
        out.push((
            format!("a pressure-angle limit of {looser}°"),
            format!("--max-pressure-angle {looser}"),
            base.clone()
                .with_max_pressure_angle_rad(looser.to_radians()),
        ));
    }
    if let Some(m) = opts.module_mm
        && let Some(&smaller) = MODULES_MM.iter().rev().find(|&&x| x < m * (1.0 - 1e-9))
    {
        out.push((
            format!("module {smaller} mm"),
            format!("--module {smaller}"),
            base.with_module_mm(Some(smaller)),
        ));
    }
    out
}

/// The alternatives of a failed design (module docs): designed in order, at most
/// [`MAX_ALTERNATIVES`], until one passes. A candidate whose design fails to run is skipped.
///
/// ```no_run
/// use ncgear::design::{DesignOptions, design, trajectory::Trajectory};
/// let t = Trajectory::from_path(std::path::Path::new("assets/trajectories/designer_kidney.csv"))?;
/// let d = design(&t, &DesignOptions::default().with_alternatives(true))?;
/// // The collinear train misses the drawn loop by 1.57 mm; off the line it reaches 0.081 mm.
/// assert!(d.report.alternatives[0].max_deviation_mm < 0.1);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[must_use]
pub fn alternatives(
    traj: &Trajectory,
    opts: &DesignOptions,
    report: &DesignReport,
) -> Vec<Alternative> {
    let mut out: Vec<Alternative> = Vec::new();
    for (label, flags, o) in candidates(opts, report) {
        if out.len() == MAX_ALTERNATIVES || out.last().is_some_and(|a| a.passed) {
            break;
        }
        let Ok(d) = crate::design::design(traj, &o) else {
            continue;
        };
        let r = &d.report;
        out.push(Alternative {
            label,
            flags,
            max_deviation_mm: r.roundtrip.max_deviation_mm,
            pressure_angle_deg: r.limits.pressure_angle_deg,
            idler_offset_deg: r.idler_offset_deg,
            passed: r.verdict.passed,
            failures: r.verdict.failures.clone(),
        });
    }
    out
}

/// The line naming the alternatives that apply to a failed design made with `opts`, not designed:
/// "what may pass, not designed: off the carrier line, the same limits (--idler-offset free);
/// --alternatives designs the first (one more design)"; `None` when the design passed, its
/// alternatives were designed, or none applies.
#[must_use]
pub fn untried_note(opts: &DesignOptions, report: &DesignReport) -> Option<String> {
    if report.verdict.passed || opts.alternatives {
        return None;
    }
    let named: Vec<String> = candidates(opts, report)
        .into_iter()
        .map(|(label, flags, _)| format!("{label} ({flags})"))
        .collect();
    (!named.is_empty()).then(|| {
        format!(
            "what may pass, not designed: {}; --alternatives designs the first (one more design, about as long as this one)",
            named.join("; ")
        )
    })
}

/// The line naming a failed design's nearest alternative — "what would pass: …" when one
/// passes, else "nearest alternative: …" when it traces closer than the design; `None` when
/// no alternative was designed or none comes closer.
#[must_use]
pub fn nearest_note(report: &DesignReport) -> Option<String> {
    let a = report
        .alternatives
        .iter()
        .min_by(|a, b| a.max_deviation_mm.total_cmp(&b.max_deviation_mm))?;
    if a.passed {
        Some(format!("what would pass: {}", a.line()))
    } else if a.max_deviation_mm < report.roundtrip.max_deviation_mm {
        Some(format!("nearest alternative: {}", a.line()))
    } else {
        None
    }
}

/// The line a failed design's failure message ends with: its nearest alternative's
/// ([`nearest_note`]) when alternatives were designed, else the untried ones' ([`untried_note`]).
#[must_use]
pub fn failure_note(opts: &DesignOptions, report: &DesignReport) -> Option<String> {
    nearest_note(report).or_else(|| untried_note(opts, report))
}
