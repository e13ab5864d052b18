//! Files written by `ncgear dynamics` for a rotor scene: of a run `dynamics.json` (the report,
//! last) and the charts `forces` and `tip` ([`super::rotor_plots`]); of a carrier-speed sweep
//! `sweep.csv` and the chart `sweep`. SVG always, PNG copies on request; and the sweep's table
//! for the run log.

use super::error::{OutputError, create_dir, remove_stale, write, write_json};
use super::rotor_plots::{forces_chart, sweep_chart, tip_chart};
use crate::analysis::dynamics::rotor::{RotorReport, SweepRow};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The chart formats written: SVG, and PNG with `png`.
fn exts(png: bool) -> &'static [&'static str] {
    if png { &["svg", "png"] } else { &["svg"] }
}

/// Writes the files of a rotor run `report` into `dir` (created if needed): `forces.svg`,
/// `tip.svg` (and `.png` with `png`), `dynamics.json` last; returns the paths written.
///
/// # Errors
/// [`OutputError`] when a file cannot be written or drawn.
pub fn write_rotor(
    report: &RotorReport,
    dir: &Path,
    png: bool,
) -> Result<Vec<PathBuf>, OutputError> {
    create_dir(dir)?;
    let json_path = dir.join("dynamics.json");
    remove_stale(&json_path)?;
    let mut paths = Vec::new();
    for ext in exts(png) {
        let path = dir.join(format!("forces.{ext}"));
        forces_chart(report, &path)?;
        paths.push(path);
        let path = dir.join(format!("tip.{ext}"));
        tip_chart(report, &path)?;
        paths.push(path);
    }
    write_json(&json_path, report)?;
    paths.push(json_path);
    Ok(paths)
}

/// Writes the files of a carrier-speed sweep `rows` into `dir` (created if needed): `sweep.csv`
/// ([`rotor_sweep_csv`]) first, then `sweep.svg` (and `.png` with `png`); returns the paths
/// written.
///
/// # Errors
/// [`OutputError`] when a file cannot be written or drawn.
pub fn write_rotor_sweep(
    rows: &[SweepRow],
    dir: &Path,
    png: bool,
) -> Result<Vec<PathBuf>, OutputError> {
    create_dir(dir)?;
    let csv = dir.join("sweep.csv");
    write(&csv, &rotor_sweep_csv(rows))?;
    let mut paths = vec![csv];
    for ext in exts(png) {
        let path = dir.join(format!("sweep.{ext}"));
        sweep_chart(rows, &path)?;
        paths.push(path);
    }
    Ok(paths)
}

/// `sweep.csv`: one row per carrier speed (r/min) — each mesh's dynamic factor, impacts per
/// turn, the largest impact speed (m/s) and tip deviation (mm), turns to the steady state and
/// whether it settled.
#[must_use]
pub fn rotor_sweep_csv(rows: &[SweepRow]) -> String {
    let mut csv = String::from(
        "carrier_rpm,dynamic_factor_sun,dynamic_factor_planet,impacts_per_turn,max_impact_speed_m_s,max_tip_deviation_mm,turns,settled\n",
    );
    for r in rows {
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{},{}",
            r.carrier_rpm,
            r.dynamic_factor[0],
            r.dynamic_factor[1],
            r.impacts_per_turn,
            r.max_impact_speed_m_s,
            r.max_tip_deviation_mm,
            r.turns,
            r.settled
        );
    }
    csv
}

/// The sweep's table for the run log: a header line and one line per speed (r/min, the
/// dynamic factors, impacts per turn, impact speed m/s, tip deviation mm; an unsettled speed
/// says so), each ending in a newline.
#[must_use]
pub fn rotor_sweep_table(rows: &[SweepRow]) -> String {
    let mut s =
        String::from("   r/min  K_dyn sun  K_dyn planet  impacts/turn  v_impact m/s  tip dev mm\n");
    for r in rows {
        let _ = writeln!(
            s,
            "{:8.1}  {:9.4}  {:12.4}  {:12}  {:12.4}  {:10.4}{}",
            r.carrier_rpm,
            r.dynamic_factor[0],
            r.dynamic_factor[1],
            r.impacts_per_turn,
            r.max_impact_speed_m_s,
            r.max_tip_deviation_mm,
            if r.settled { "" } else { "  (not settled)" }
        );
    }
    s
}
