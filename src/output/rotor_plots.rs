//! The charts of a rotor scene (`ncgear dynamics` with `[scene] model = "rotor"`): the mesh forces
//! of the settled turn with its contact losses and impacts (`forces`), the needle tip's distance
//! from its static path (`tip`), and of a carrier-speed sweep the knock's figures against the
//! speed (`sweep`). Drawn by [`super::plot::panels_chart`]; the format follows the extension.

use super::plot::{ChartLabels, PlotError, Series, line_chart, panels_chart};
use crate::analysis::dynamics::rotor::report::{MeshSeries, MeshSummary};
use crate::analysis::dynamics::rotor::{RotorReport, SweepRow};
use std::path::Path;

/// Size of the forces chart (two panels side by side), px.
const FORCES_PX: (u32, u32) = (1800, 560);
/// Size of the tip chart, px.
const TIP_PX: (u32, u32) = (1000, 480);
/// Size of the sweep chart (four panels side by side), px.
const SWEEP_PX: (u32, u32) = (2000, 440);

/// One full turn, degrees of travel.
const TURN_DEG: f64 = 360.0;

fn labels(title: impl Into<String>, x: &str, y: &str) -> ChartLabels {
    ChartLabels {
        title: title.into(),
        x: x.into(),
        y: y.into(),
        equal_aspect: false,
    }
}

/// `(travel, value)` over the turn, closed at 360° by the first sample (the turn is periodic);
/// samples beyond the shorter of the two slices are dropped.
fn over_turn(travel_deg: &[f64], values: &[f64]) -> Vec<(f64, f64)> {
    let mut pts: Vec<(f64, f64)> = travel_deg
        .iter()
        .copied()
        .zip(values.iter().copied())
        .collect();
    if let (Some(&(x0, y0)), true) = (pts.first(), pts.len() > 1) {
        pts.push((x0 + TURN_DEG, y0));
    }
    pts
}

/// The contact-loss intervals `[from, to]` (travel degrees) as x intervals of the chart: one
/// band each, two for an interval across φ = 0 (`to < from`: `[from, 360]` and `[0, to]`).
fn loss_bands(intervals: &[[f64; 2]]) -> Vec<(f64, f64)> {
    intervals
        .iter()
        .flat_map(|&[a, b]| {
            if b < a {
                vec![(a, TURN_DEG), (0.0, b)]
            } else {
                vec![(a, b)]
            }
        })
        .collect()
}

/// One mesh's panel: dynamic and rigid normal force (N) over the travel (degrees), the
/// contact losses shaded, each impact's peak force marked at its travel.
fn mesh_panel(
    name: &str,
    travel_deg: &[f64],
    series: &MeshSeries,
    summary: &MeshSummary,
) -> (ChartLabels, Vec<Series>) {
    let impacts: Vec<(f64, f64)> = summary
        .impacts
        .iter()
        .map(|i| (i.travel_deg, i.peak_force_n))
        .collect();
    let hardest = summary
        .impacts
        .iter()
        .map(|i| i.speed_m_s)
        .fold(0.0_f64, f64::max);
    let title = format!(
        "{name}: dynamic factor {:.2}, {} impacts/turn (≤ {:.3} m/s)",
        summary.dynamic_factor, summary.impacts_per_turn, hardest
    );
    (
        labels(title, "carrier travel (deg)", "normal force (N)"),
        vec![
            Series::line("dynamic", over_turn(travel_deg, &series.dynamic_force_n)),
            Series::line(
                "rigid (loads)",
                over_turn(travel_deg, &series.rigid_force_n),
            ),
            Series::bands("contact lost", loss_bands(&summary.contact_loss_deg)),
            Series::markers("impact (peak force)", impacts),
        ],
    )
}

/// `forces` chart of `report` at `path`: one panel per mesh (sun–intermediate,
/// intermediate–planet), travel in degrees, force in N.
///
/// # Errors
/// [`PlotError`] when the chart cannot be drawn or written.
pub fn forces_chart(report: &RotorReport, path: &Path) -> Result<(), PlotError> {
    let (m, s) = (&report.meshes, &report.summary.meshes);
    let t = &report.travel_deg;
    panels_chart(
        path,
        &[
            mesh_panel(
                "sun–intermediate",
                t,
                &m.sun_intermediate,
                &s.sun_intermediate,
            ),
            mesh_panel(
                "intermediate–planet",
                t,
                &m.intermediate_planet,
                &s.intermediate_planet,
            ),
        ],
        FORCES_PX,
    )
}

/// `tip` chart of `report` at `path`: the needle tip's distance from its static path (mm) over
/// the travel (degrees).
///
/// # Errors
/// [`PlotError`] when the chart cannot be drawn or written.
pub fn tip_chart(report: &RotorReport, path: &Path) -> Result<(), PlotError> {
    line_chart(
        path,
        &labels(
            format!(
                "Needle tip off its static path at {:.0} r/min (largest {:.4} mm at {:.1}°)",
                report.carrier_rpm,
                report.summary.max_tip_deviation_mm,
                report.summary.max_tip_deviation_at_deg
            ),
            "carrier travel (deg)",
            "tip deviation (mm)",
        ),
        &[Series::line(
            "",
            over_turn(&report.travel_deg, &report.tip_deviation_mm),
        )],
        TIP_PX,
    )
}

/// `(carrier r/min, f(row))` of each row: a line, or a marker when the sweep has one speed.
fn against_speed(name: &str, rows: &[SweepRow], f: impl Fn(&SweepRow) -> f64) -> Series {
    let pts: Vec<(f64, f64)> = rows.iter().map(|r| (r.carrier_rpm, f(r))).collect();
    if pts.len() == 1 {
        Series::markers(name, pts)
    } else {
        Series::line(name, pts)
    }
}

/// `sweep` chart of `rows` at `path`: four panels against the carrier speed (r/min) — each
/// mesh's dynamic factor, impacts per turn, the largest impact speed (m/s) and the largest tip
/// deviation (mm).
///
/// # Errors
/// [`PlotError`] when the chart cannot be drawn or written.
pub fn sweep_chart(rows: &[SweepRow], path: &Path) -> Result<(), PlotError> {
    let x = "carrier speed (r/min)";
    let factors = vec![
        against_speed("sun–intermediate", rows, |r| r.dynamic_factor[0]),
        against_speed("intermediate–planet", rows, |r| r.dynamic_factor[1]),
    ];
    panels_chart(
        path,
        &[
            (labels("Dynamic factor", x, "F_dyn / F_rigid (-)"), factors),
            (
                labels("Impacts per turn", x, "impacts (-)"),
                vec![against_speed("", rows, |r| r.impacts_per_turn as f64)],
            ),
            (
                labels("Largest impact speed", x, "speed (m/s)"),
                vec![against_speed("", rows, |r| r.max_impact_speed_m_s)],
            ),
            (
                labels("Largest tip deviation", x, "deviation (mm)"),
                vec![against_speed("", rows, |r| r.max_tip_deviation_mm)],
            ),
        ],
        SWEEP_PX,
    )
}
