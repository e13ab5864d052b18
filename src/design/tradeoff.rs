//! What accuracy costs: the same target designed under a ladder of gear limits and modules.
//!
//! The gear limits ([`DesignOptions::limits`]) trade the design's deviation from the target
//! for gears that can be cut and run: a looser pressure-angle limit lets the pitch curves bend
//! more and the tip come closer; a larger module needs a larger cutter (a larger smallest concave
//! radius) and an integer tooth count. [`trade_off`] runs one full [`design`] per rung — the
//! pressure-angle limits of [`PRESSURE_ANGLE_LIMITS_DEG`] and no limit, then the modules of
//! [`MODULES_MM`] at the default limit — side by side, and tabulates deviation against limit.
//! One more row prices the layout rather than the gears: the default limits with the
//! intermediate axis free to leave the carrier line ([`IdlerOffset::Free`]; a housing with the
//! intermediate shaft off the line through the sun and planet shafts), which takes a target no
//! collinear train traces much closer (docs/performance.md, "The idler offset").
//! A refused design is a row with its error; it does not stop the others.
//!
//! ```no_run
//! use ncgear::design::{DesignOptions, trajectory::Trajectory, tradeoff::trade_off};
//! use ncgear::progress::Progress;
//! let traj = Trajectory::from_path(std::path::Path::new("assets/trajectories/designer_kidney.csv")).unwrap();
//! let t = trade_off(&traj, &DesignOptions::default(), &Progress::none()).unwrap();
//! println!("{}", t.markdown(false));
//! ```

use super::{DesignError, DesignOptions, IdlerOffset, design, trajectory::Trajectory};
use crate::math::Point;
use crate::progress::Progress;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;

/// Pressure-angle limits of the limit rows, degrees (then one row without limits).
pub const PRESSURE_ANGLE_LIMITS_DEG: [f64; 4] = [35.0, 40.0, 45.0, 50.0];

/// Modules of the module rows, mm (each at the base options' pressure-angle limit).
pub const MODULES_MM: [f64; 5] = [1.0, 1.5, 2.0, 2.5, 3.0];

/// Rows of the ladder: the limit rows, the unlimited row, the off-line row, the module rows.
pub const ROWS: usize = PRESSURE_ANGLE_LIMITS_DEG.len() + 2 + MODULES_MM.len();

/// Largest deviation of the unlimited design at which the target counts as exactly traceable,
/// mm (the chain's default round-trip tolerance).
pub const EXACT_DEVIATION_MM: f64 = 0.05;

/// The trade-off table of one target (`tradeoff.json`). Deterministic: the same bytes for any
/// thread count (design times are kept out of it).
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
#[non_exhaustive]
pub struct TradeOff {
    /// Target points read.
    pub points: usize,
    /// Carrier axis O, mm.
    pub center_mm: Point,
    /// The rows: the limit rows (tightest first, then unlimited), the off-line row, then the
    /// module rows.
    pub rows: Vec<TradeOffRow>,
    /// Set when the target is exactly traceable but its exact gears break a default limit.
    pub exact_needs: Option<ExactNeeds>,
    /// The module sized by strength for a loads scene (`ncgear tradeoff --loads`): the
    /// standard modules rated in turn up to the first that carries the loads.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sizing: Option<crate::design::report::sizing::ModuleSizing>,
}

/// One design of the ladder.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
#[non_exhaustive]
pub struct TradeOffRow {
    /// What was varied: `"pressure angle ≤ 35°"`, `"no limits"`, `"module 2 mm"`.
    pub label: String,
    /// Pressure-angle limit, degrees; `None`: no gear limits (the ratio bounds alone). Read
    /// under its old name `pressure_angle_limit_deg` too (one layout version).
    #[serde(alias = "pressure_angle_limit_deg")]
    pub max_pressure_angle_deg: Option<f64>,
    /// Concave-radius limit in force, mm; `None` without gear limits. Read under its old name
    /// `concave_radius_limit_mm` too (one layout version).
    #[serde(alias = "concave_radius_limit_mm")]
    pub min_concave_radius_mm: Option<f64>,
    /// Module the design was made for, mm.
    pub module_mm: Option<f64>,
    /// Whether this row is the default design (`ncgear design` with its defaults).
    pub is_default: bool,
    /// Whether the intermediate axis was free to leave the carrier line (the off-line row,
    /// `--idler-offset free`: the default limits, another housing).
    #[serde(default)]
    pub off_line: bool,
    /// A limit row or the unlimited row only: the label of the closest tighter-limit design when
    /// it is closer than this one — it is within this row's limits too, so this row's fit
    /// settled in a local optimum (the trade-off curve is then not monotone).
    pub closer_tighter_design: Option<String>,
    /// The design's numbers, or why it was refused.
    #[serde(flatten)]
    pub outcome: RowOutcome,
    /// Wall-clock time of the design, ms (not serialized: it varies from run to run).
    #[serde(skip)]
    pub design_time_ms: f64,
}

/// A row's result: the design's numbers, or the error that refused it.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum RowOutcome {
    /// The design was made.
    Designed(RowNumbers),
    /// The design was refused: the error message.
    Refused(String),
}

/// The numbers of one design.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[non_exhaustive]
pub struct RowNumbers {
    /// Round trip: max synchronous tip deviation, mm.
    pub max_deviation_mm: f64,
    /// Round trip: Hausdorff distance of the traced path from the target, mm.
    pub hausdorff_mm: f64,
    /// Largest effective pressure angle of the three gears, degrees.
    pub pressure_angle_deg: f64,
    /// Tightest concave radius of curvature, mm; `None`: every pitch curve convex.
    pub tightest_concave_radius_mm: Option<f64>,
    /// The limits the design sits on.
    pub binding: Vec<String>,
    /// Teeth per gear (module rows).
    pub teeth: Option<u32>,
    /// Idler offset ε of the design, degrees (0: the intermediate axis on the carrier line;
    /// [`crate::geometry::mechanism`]).
    #[serde(default)]
    pub idler_offset_deg: f64,
}

/// What the exact design of an exactly traceable target needs beyond the default limits.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[non_exhaustive]
pub struct ExactNeeds {
    /// Max deviation of the unlimited design, mm (≤ [`EXACT_DEVIATION_MM`]).
    pub max_deviation_mm: f64,
    /// Its pressure angle, degrees.
    pub pressure_angle_deg: f64,
    /// Its tightest concave radius, mm (`None`: convex).
    pub concave_radius_mm: Option<f64>,
    /// Max deviation of the default design, mm (`None` when refused).
    pub default_max_deviation_mm: Option<f64>,
    /// The sentence: "the exact design needs …".
    pub message: String,
}

/// Designs `traj` once per rung of the ladder (module documentation) from `base` (its carrier
/// axis and accuracy knobs; its pressure-angle limit is the default row's and the module rows'),
/// in parallel; `progress` advances by one as each design finishes. The rows are in ladder order
/// whatever the thread count. Errors only when every design is refused (the first row's error).
pub fn trade_off(
    traj: &Trajectory,
    base: &DesignOptions,
    progress: &Progress,
) -> Result<TradeOff, DesignError> {
    let default_limit_deg = base.max_pressure_angle_rad.to_degrees();
    let mut rungs: Vec<(String, DesignOptions)> = Vec::new();
    for deg in PRESSURE_ANGLE_LIMITS_DEG {
        let mut o = base.clone();
        o.limits = true;
        o.module_mm = None;
        o.max_pressure_angle_rad = deg.to_radians();
        rungs.push((format!("pressure angle ≤ {deg}°"), o));
    }
    let mut unlimited = base.clone();
    unlimited.limits = false;
    unlimited.module_mm = None;
    rungs.push(("no limits".into(), unlimited));
    let mut off_line = base.clone();
    off_line.limits = true;
    off_line.module_mm = None;
    off_line.idler_offset = IdlerOffset::Free;
    rungs.push(("intermediate axis off the line".into(), off_line));
    for m in MODULES_MM {
        let mut o = base.clone();
        o.limits = true;
        o.module_mm = Some(m);
        rungs.push((format!("module {m} mm"), o));
    }
    let results: Vec<(Result<RowNumbers, DesignError>, f64)> = rungs
        .par_iter()
        .map(|(_, o)| {
            let start = std::time::Instant::now();
            let r = design(traj, o).map(|d| {
                let (l, rt) = (&d.report.limits, &d.report.roundtrip);
                RowNumbers {
                    max_deviation_mm: rt.max_deviation_mm,
                    hausdorff_mm: rt.hausdorff_mm,
                    pressure_angle_deg: l.pressure_angle_deg,
                    tightest_concave_radius_mm: l.tightest_concave_radius_mm,
                    binding: l.binding.clone(),
                    teeth: d.report.module.as_ref().map(|m| m.teeth),
                    idler_offset_deg: d.report.idler_offset_deg,
                }
            });
            progress.advance(1);
            (r, 1e3 * start.elapsed().as_secs_f64())
        })
        .collect();
    if results.iter().all(|(r, _)| r.is_err())
        && let Some((Err(first), _)) = results.first()
    {
        return Err(first.clone());
    }
    let default_default = DesignOptions::default();
    let rows: Vec<TradeOffRow> = rungs
        .into_iter()
        .zip(results)
        .map(|((label, o), (r, ms))| TradeOffRow {
            label,
            max_pressure_angle_deg: o.limits.then(|| o.max_pressure_angle_rad.to_degrees()),
            min_concave_radius_mm: o.limits.then(|| o.min_concave_radius_in_force_mm()),
            module_mm: o.module_mm,
            is_default: o.limits
                && o.module_mm.is_none()
                && o.idler_offset != IdlerOffset::Free
                && o.max_pressure_angle_rad == default_default.max_pressure_angle_rad,
            off_line: o.idler_offset == IdlerOffset::Free,
            outcome: match r {
                Ok(n) => RowOutcome::Designed(n),
                Err(e) => RowOutcome::Refused(e.to_string()),
            },
            closer_tighter_design: None,
            design_time_ms: ms,
        })
        .collect();
    let rows = flag_closer_tighter(rows);
    let exact_needs = exact_needs(
        &rows,
        default_limit_deg,
        base.min_concave_radius_in_force_mm(),
    );
    Ok(TradeOff {
        points: traj.points().len(),
        center_mm: base.center_mm,
        rows,
        exact_needs,
        sizing: None,
    })
}

/// Sets [`TradeOffRow::closer_tighter_design`] on each limit row that a design under a tighter
/// pressure-angle limit (same concave-radius limit, no module) beats, and on the unlimited row
/// that any limited design beats (every one is within its absent limits); the off-line row is
/// another layout, not a tighter limit, and is left out.
fn flag_closer_tighter(mut rows: Vec<TradeOffRow>) -> Vec<TradeOffRow> {
    // (row, pressure-angle limit, concave-radius limit (None: any), deviation)
    let limit_rows: Vec<(usize, f64, Option<f64>, f64)> = rows
        .iter()
        .enumerate()
        .filter(|(_, r)| r.module_mm.is_none() && !r.off_line)
        .filter_map(|(k, r)| {
            let dev = r.numbers()?.max_deviation_mm;
            Some(match r.max_pressure_angle_deg {
                Some(limit) => (k, limit, Some(r.min_concave_radius_mm?), dev),
                None => (k, f64::INFINITY, None, dev),
            })
        })
        .collect();
    for &(k, limit, radius, dev) in &limit_rows {
        let best = limit_rows
            .iter()
            .filter(|&&(_, l, r, d)| l < limit && (radius.is_none() || r == radius) && d < dev)
            .min_by(|a, b| a.3.total_cmp(&b.3));
        rows[k].closer_tighter_design = best.map(|&(j, ..)| rows[j].label.clone());
    }
    rows
}

/// The unlimited row when it is exact but breaks the default limits (`limit_deg`, `radius_mm`).
fn exact_needs(rows: &[TradeOffRow], limit_deg: f64, radius_mm: f64) -> Option<ExactNeeds> {
    let free = rows
        .iter()
        .find(|r| r.max_pressure_angle_deg.is_none())?
        .numbers()?;
    let too_tight = free.tightest_concave_radius_mm.filter(|&r| r < radius_mm);
    let too_steep = free.pressure_angle_deg > limit_deg;
    if free.max_deviation_mm > EXACT_DEVIATION_MM || !(too_steep || too_tight.is_some()) {
        return None;
    }
    let default = rows.iter().find(|r| r.is_default).and_then(|r| r.numbers());
    let mut needs = Vec::new();
    if too_steep {
        needs.push(format!(
            "a pressure angle of {:.1}° (limit {limit_deg}°)",
            free.pressure_angle_deg
        ));
    }
    if let Some(r) = too_tight {
        needs.push(format!(
            "a concave radius of {r:.2} mm (limit {radius_mm} mm)"
        ));
    }
    let mut message = format!(
        "the exact design ({:.4} mm without limits) needs {}",
        free.max_deviation_mm,
        needs.join(" and ")
    );
    if let Some(d) = default {
        let _ = write!(
            message,
            "; within the limits the closest design deviates {:.3} mm",
            d.max_deviation_mm
        );
    }
    Some(ExactNeeds {
        max_deviation_mm: free.max_deviation_mm,
        pressure_angle_deg: free.pressure_angle_deg,
        concave_radius_mm: free.tightest_concave_radius_mm,
        default_max_deviation_mm: default.map(|d| d.max_deviation_mm),
        message,
    })
}

impl TradeOffRow {
    /// The design's numbers; `None` when it was refused.
    #[must_use]
    pub fn numbers(&self) -> Option<&RowNumbers> {
        match &self.outcome {
            RowOutcome::Designed(n) => Some(n),
            RowOutcome::Refused(_) => None,
        }
    }
}

impl TradeOff {
    /// The table as Markdown, one line per row; `with_times` adds the design time column (the
    /// console's; without it the text is deterministic). The exact-design note follows.
    #[must_use]
    pub fn markdown(&self, with_times: bool) -> String {
        let mut s = String::from(
            "| design | max deviation (mm) | Hausdorff (mm) | pressure angle (°) | tightest concave radius (mm) | binding | teeth | idler offset (°) |",
        );
        s.push_str(if with_times { " time (ms) |\n" } else { "\n" });
        s.push_str("|---|---:|---:|---:|---:|---|---:|---:|");
        s.push_str(if with_times { "---:|\n" } else { "\n" });
        for r in &self.rows {
            let label = if r.is_default {
                format!("**{} (default)**", r.label)
            } else {
                r.label.clone()
            };
            let cells = match &r.outcome {
                RowOutcome::Designed(n) => format!(
                    "{:.4} | {:.4} | {:.2} | {} | {} | {} | {}",
                    n.max_deviation_mm,
                    n.hausdorff_mm,
                    n.pressure_angle_deg,
                    n.tightest_concave_radius_mm
                        .map_or_else(|| "convex".into(), |v| format!("{v:.2}")),
                    if n.binding.is_empty() {
                        "–".into()
                    } else {
                        n.binding.join(", ")
                    },
                    n.teeth.map_or_else(|| "–".into(), |z| z.to_string()),
                    if n.idler_offset_deg == 0.0 {
                        "–".into()
                    } else {
                        format!("{:.2}", n.idler_offset_deg)
                    },
                ),
                RowOutcome::Refused(e) => {
                    format!("refused: {} | | | | | |", e.replace('|', "/"))
                }
            };
            let _ = write!(s, "| {label} | {cells} |");
            if with_times {
                let _ = write!(s, " {:.0} |", r.design_time_ms);
            }
            s.push('\n');
        }
        for r in &self.rows {
            if let (Some(by), Some(n)) = (&r.closer_tighter_design, r.numbers()) {
                let within = match r.max_pressure_angle_deg {
                    Some(_) => format!("is within the `{}` limits too and", r.label),
                    None => "is".into(),
                };
                let _ = writeln!(
                    s,
                    "\nNote: the `{by}` design {within} closer than the `{}` design's {:.4} mm: \
                     the fit at `{}` settled in a local optimum.",
                    r.label, n.max_deviation_mm, r.label
                );
            }
        }
        if self
            .rows
            .iter()
            .any(|r| r.numbers().is_some_and(|n| n.idler_offset_deg != 0.0))
        {
            let _ = writeln!(
                s,
                "\nNote: a design with an idler offset has its intermediate axis turned off the \
                 carrier line by that angle (l1 = 2a·cos ε): at a whole number of teeth the arm \
                 keeps its length, and the train traces paths a collinear one cannot. The rule of \
                 `--idler-offset auto` (every row but the off-line one): {}.",
                IdlerOffset::AUTO_RULE
            );
        }
        if let Some(x) = &self.exact_needs {
            let _ = write!(s, "\nNote: {}.\n", x.message);
        }
        if let Some(z) = &self.sizing {
            let _ = write!(
                s,
                "\nThe module sized by strength (S_H ≥ {}, S_F ≥ {}, face width {}; \
                 docs/loads.md):\n\n{}",
                z.s_h_min,
                z.s_f_min,
                z.face_width,
                z.markdown()
            );
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(label: &str, limit_deg: Option<f64>, dev_mm: f64, pa_deg: f64) -> TradeOffRow {
        TradeOffRow {
            label: label.into(),
            max_pressure_angle_deg: limit_deg,
            min_concave_radius_mm: limit_deg.map(|_| 10.0),
            module_mm: None,
            is_default: limit_deg == Some(45.0),
            off_line: false,
            closer_tighter_design: None,
            outcome: RowOutcome::Designed(RowNumbers {
                max_deviation_mm: dev_mm,
                hausdorff_mm: dev_mm,
                pressure_angle_deg: pa_deg,
                tightest_concave_radius_mm: Some(4.5),
                binding: vec![],
                teeth: None,
                idler_offset_deg: 0.0,
            }),
            design_time_ms: 1.0,
        }
    }

    #[test]
    fn an_exact_target_beyond_the_limits_says_what_it_needs() {
        let rows = vec![
            row("pressure angle ≤ 45°", Some(45.0), 3.0, 44.9),
            row("no limits", None, 0.01, 52.5),
        ];
        let x = exact_needs(&rows, 45.0, 10.0).unwrap();
        assert_eq!(x.default_max_deviation_mm, Some(3.0));
        assert_eq!(
            x.message,
            "the exact design (0.0100 mm without limits) needs a pressure angle of 52.5° \
             (limit 45°) and a concave radius of 4.50 mm (limit 10 mm); within the limits the \
             closest design deviates 3.000 mm"
        );
        // Not exact: no note.
        let rows = vec![row("no limits", None, 0.06, 52.5)];
        assert_eq!(exact_needs(&rows, 45.0, 10.0), None);
        // Exact within the limits: no note.
        assert_eq!(exact_needs(&rows, 60.0, 4.0), None);
    }

    #[test]
    fn a_tighter_limit_design_that_is_closer_is_named() {
        let rows = flag_closer_tighter(vec![
            row("pressure angle ≤ 35°", Some(35.0), 1.7, 34.9),
            row("pressure angle ≤ 40°", Some(40.0), 1.9, 39.9),
            row("pressure angle ≤ 45°", Some(45.0), 1.8, 42.0),
            row("pressure angle ≤ 50°", Some(50.0), 1.6, 49.0),
            // Another layout at the 45° limit, closer than all: not a tighter limit.
            TradeOffRow {
                off_line: true,
                is_default: false,
                ..row("intermediate axis off the line", Some(45.0), 0.1, 44.0)
            },
        ]);
        let by: Vec<Option<&str>> = rows
            .iter()
            .map(|r| r.closer_tighter_design.as_deref())
            .collect();
        assert_eq!(
            by,
            [
                None,
                Some("pressure angle ≤ 35°"),
                Some("pressure angle ≤ 35°"),
                None,
                None
            ]
        );
        let md = TradeOff {
            points: 3,
            center_mm: Point::ZERO,
            rows,
            exact_needs: None,
            sizing: None,
        }
        .markdown(false);
        assert!(
            md.contains("| **pressure angle ≤ 45° (default)** | 1.8000 |"),
            "{md}"
        );
        assert!(!md.contains("time"));
    }
}
