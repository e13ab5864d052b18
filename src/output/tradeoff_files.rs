//! Files written by `ncgear tradeoff`: `tradeoff.json`, `tradeoff.md` (the table, no times) and
//! `tradeoff.svg` (deviation against the pressure-angle limit and against the module).

use super::error::{OutputError, create_dir, remove_stale, write};
use super::plot::{ChartLabels, Series, panels_chart};
use crate::design::tradeoff::{RowNumbers, TradeOff, TradeOffRow};
use std::path::{Path, PathBuf};

/// Writes `tradeoff.json`, `tradeoff.md` and `tradeoff.svg` into `dir` (created if needed);
/// returns the paths written. Every file is the same bytes for the same table.
pub fn write_tradeoff(t: &TradeOff, dir: &Path) -> Result<Vec<PathBuf>, OutputError> {
    create_dir(dir)?;
    let json = super::json::to_string(t).map_err(|e| OutputError::Io {
        path: "tradeoff.json".into(),
        message: e.to_string(),
    })?;
    let paths: Vec<PathBuf> = ["tradeoff.json", "tradeoff.md", "tradeoff.svg"]
        .iter()
        .map(|f| dir.join(f))
        .collect();
    // The report last, an earlier run's removed first ([`crate::files`]).
    remove_stale(&paths[0])?;
    write(&paths[1], &t.markdown(false))?;
    tradeoff_plot(t, &paths[2])?;
    write(&paths[0], &json)?;
    Ok(paths)
}

/// The two panels of `tradeoff.svg`: max deviation against the pressure-angle limit (the
/// unlimited and the off-line designs at the pressure angles they reached) and against the
/// module; the default design marked in both. Refused designs are left out.
pub fn tradeoff_plot(t: &TradeOff, path: &Path) -> Result<(), OutputError> {
    let designed = |keep: fn(&TradeOffRow) -> bool| -> Vec<(&TradeOffRow, &RowNumbers)> {
        t.rows
            .iter()
            .filter(|r| keep(r))
            .filter_map(|r| r.numbers().map(|n| (r, n)))
            .collect()
    };
    let limited =
        designed(|r| r.module_mm.is_none() && r.max_pressure_angle_deg.is_some() && !r.off_line);
    let off_line = designed(|r| r.off_line);
    let free = designed(|r| r.max_pressure_angle_deg.is_none());
    let modules = designed(|r| r.module_mm.is_some());
    let default = designed(|r| r.is_default);
    let all_dev: Vec<f64> = t
        .rows
        .iter()
        .filter_map(|r| r.numbers().map(|n| n.max_deviation_mm))
        .collect();
    let (lo, hi) = all_dev
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let mut angle = vec![Series::line(
        "within the limit",
        limited
            .iter()
            .map(|(r, n)| {
                (
                    r.max_pressure_angle_deg.unwrap_or(f64::NAN),
                    n.max_deviation_mm,
                )
            })
            .collect(),
    )];
    angle.push(Series::markers(
        "no limits (at the angle it needs)",
        free.iter()
            .map(|(_, n)| (n.pressure_angle_deg, n.max_deviation_mm))
            .collect(),
    ));
    angle.push(Series::markers(
        "intermediate axis off the line (at the angle it reached)",
        off_line
            .iter()
            .map(|(_, n)| (n.pressure_angle_deg, n.max_deviation_mm))
            .collect(),
    ));
    let mut module = vec![Series::line(
        "for the module",
        modules
            .iter()
            .map(|(r, n)| (r.module_mm.unwrap_or(f64::NAN), n.max_deviation_mm))
            .collect(),
    )];
    if let Some((r, n)) = default.first() {
        let x = r.max_pressure_angle_deg.unwrap_or(f64::NAN);
        angle.push(Series::line(
            format!("default ({x}°): {:.3} mm", n.max_deviation_mm),
            vec![(x, lo), (x, hi)],
        ));
        let span = modules.iter().filter_map(|(r, _)| r.module_mm);
        let (m0, m1) = span.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), m| {
            (a.min(m), b.max(m))
        });
        module.push(Series::line(
            format!("default (no module): {:.3} mm", n.max_deviation_mm),
            vec![(m0, n.max_deviation_mm), (m1, n.max_deviation_mm)],
        ));
    }
    let panel = |title: &str, x: &str| ChartLabels {
        title: title.into(),
        x: x.into(),
        y: "max tip deviation (mm)".into(),
        equal_aspect: false,
    };
    panels_chart(
        path,
        &[
            (
                panel(
                    "Deviation vs pressure-angle limit",
                    "pressure-angle limit (deg)",
                ),
                angle,
            ),
            (
                panel("Deviation vs module (default limit)", "module (mm)"),
                module,
            ),
        ],
        (1400, 520),
    )?;
    Ok(())
}
