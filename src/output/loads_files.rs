//! Files written by `ncgear loads`: `loads.json` (the report, last), `loads.csv` (one row per
//! sample, for a spreadsheet) and the charts over the turn — `torque.svg` (carrier, sun and
//! planet mesh torques), `forces.svg` (the mesh normal forces, the frame and bearing forces),
//! with a rating `stress.svg` (contact and root stresses, the reversals marked), and
//! `overview.svg` (the torques beside the stresses, or the forces without a rating); `png` adds
//! PNG copies.

use super::error::{OutputError, create_dir, remove_stale, write, write_json};
use super::plot::{ChartLabels, Series, line_chart, panels_chart};
use crate::loads::LoadsReport;
use crate::math::Point;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Writes the files of `report` into `dir` (created if needed); returns the paths written, the
/// report last.
///
/// # Errors
/// [`OutputError`] when a file cannot be written.
pub fn write_loads(
    report: &LoadsReport,
    dir: &Path,
    png: bool,
) -> Result<Vec<PathBuf>, OutputError> {
    create_dir(dir)?;
    let json_path = dir.join("loads.json");
    remove_stale(&json_path)?;
    let mut paths = Vec::new();
    let csv = dir.join("loads.csv");
    write(&csv, &loads_csv(report))?;
    paths.push(csv);
    let exts: &[&str] = if png { &["svg", "png"] } else { &["svg"] };
    let charts = charts(report);
    for ext in exts {
        for (name, labels, series) in &charts {
            let path = dir.join(format!("{name}.{ext}"));
            line_chart(&path, labels, series, (1000, 560))?;
            paths.push(path);
        }
        // The torques beside the stresses (the last chart: forces without a rating).
        let path = dir.join(format!("overview.{ext}"));
        let pick = |i: usize| (charts[i].1.clone(), charts[i].2.clone());
        panels_chart(&path, &[pick(0), pick(charts.len() - 1)], (1800, 560))?;
        paths.push(path);
    }
    write_json(&json_path, report)?;
    paths.push(json_path);
    Ok(paths)
}

/// `loads.csv`: travel, torques, frame force, the meshes' normal forces and flanks, and the
/// stresses when rated.
#[must_use]
pub fn loads_csv(r: &LoadsReport) -> String {
    let (m1, m2) = (&r.meshes.sun_intermediate, &r.meshes.intermediate_planet);
    let roots = |m: &crate::loads::report::MeshLoads| -> Vec<(String, Vec<f64>)> {
        m.root_stress_mpa
            .iter()
            .flatten()
            .map(|(g, v)| (g.clone(), v.clone()))
            .collect()
    };
    let mut extra: Vec<(String, Vec<f64>)> = Vec::new();
    for (name, m) in [("sun_intermediate", m1), ("intermediate_planet", m2)] {
        if let Some(c) = &m.contact_stress_mpa {
            extra.push((format!("{name}_contact_stress_MPa"), c.clone()));
        }
        for (g, v) in roots(m) {
            extra.push((format!("{name}_{g}_root_stress_MPa"), v));
        }
    }
    let mut s = String::from(
        "travel_deg,carrier_torque_Nm,sun_torque_Nm,planet_mesh_torque_Nm,frame_force_x_N,\
         frame_force_y_N,sun_intermediate_normal_force_N,sun_intermediate_flank,\
         intermediate_planet_normal_force_N,intermediate_planet_flank",
    );
    for (h, _) in &extra {
        s.push(',');
        s.push_str(h);
    }
    s.push('\n');
    for k in 0..r.travel_deg.len() {
        let f = r.frame_force_n[k];
        let _ = write!(
            s,
            "{:.6},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{},{:.9e},{}",
            r.travel_deg[k],
            r.carrier_torque_nm[k],
            r.sun_torque_nm[k],
            r.planet_mesh_torque_nm[k],
            f.x,
            f.y,
            m1.normal_force_n[k],
            m1.flank[k],
            m2.normal_force_n[k],
            m2.flank[k]
        );
        for (_, v) in &extra {
            let _ = write!(s, ",{:.9e}", v[k]);
        }
        s.push('\n');
    }
    s
}

/// `(travel, value)` points of a series.
fn over_turn(travel: &[f64], values: impl IntoIterator<Item = f64>) -> Vec<(f64, f64)> {
    travel.iter().copied().zip(values).collect()
}

/// Vertical marks at the reversals, spanning `[lo, hi]`, NaN-separated into one series.
fn marks(reversals: &[f64], lo: f64, hi: f64) -> Vec<(f64, f64)> {
    reversals
        .iter()
        .flat_map(|&x| [(x, lo), (x, hi), (f64::NAN, f64::NAN)])
        .collect()
}

fn labels(title: &str, y: &str) -> ChartLabels {
    ChartLabels {
        title: title.into(),
        x: "carrier travel (deg)".into(),
        y: y.into(),
        equal_aspect: false,
    }
}

/// The charts of a report: `(file stem, labels, series)`.
fn charts(r: &LoadsReport) -> Vec<(&'static str, ChartLabels, Vec<Series>)> {
    let t = &r.travel_deg;
    let norm = |v: &[Point]| v.iter().map(|p| p.norm()).collect::<Vec<_>>();
    let mut out = vec![
        (
            "torque",
            labels("Torques over the turn", "torque (N·m)"),
            vec![
                Series::line("carrier (drive)", over_turn(t, r.carrier_torque_nm.clone())),
                Series::line(
                    "planet mesh (arm 1)",
                    over_turn(t, r.planet_mesh_torque_nm.clone()),
                ),
                Series::line(
                    "sun (held by the frame)",
                    over_turn(t, r.sun_torque_nm.clone()),
                ),
            ],
        ),
        (
            "forces",
            labels("Forces over the turn", "force (N)"),
            vec![
                Series::line(
                    "sun–intermediate mesh",
                    over_turn(t, r.meshes.sun_intermediate.normal_force_n.clone()),
                ),
                Series::line(
                    "intermediate–planet mesh",
                    over_turn(t, r.meshes.intermediate_planet.normal_force_n.clone()),
                ),
                Series::line("|frame force|", over_turn(t, norm(&r.frame_force_n))),
                Series::line("|bearing D|", over_turn(t, norm(&r.bearings.d_n))),
                Series::line("|bearing A|", over_turn(t, norm(&r.bearings.a_n))),
            ],
        ),
    ];
    if r.rating.is_some() {
        let mut series = Vec::new();
        let mut hi: f64 = 0.0;
        for (name, m) in [
            ("sun–intermediate", &r.meshes.sun_intermediate),
            ("intermediate–planet", &r.meshes.intermediate_planet),
        ] {
            if let Some(c) = &m.contact_stress_mpa {
                hi = c.iter().copied().fold(hi, f64::max);
                series.push(Series::line(
                    format!("contact {name}"),
                    over_turn(t, c.clone()),
                ));
            }
        }
        for (mesh, m) in [
            ("sun–int.", &r.meshes.sun_intermediate),
            ("int.–planet", &r.meshes.intermediate_planet),
        ] {
            for (g, v) in m.root_stress_mpa.iter().flatten() {
                hi = v.iter().copied().fold(hi, f64::max);
                series.push(Series::line(
                    format!("root {g} ({mesh})"),
                    over_turn(t, v.clone()),
                ));
            }
        }
        series.push(Series::line(
            "planet torque reversals",
            marks(&r.summary.reversals_deg, 0.0, hi),
        ));
        out.push((
            "stress",
            labels("Tooth stresses over the turn", "stress (MPa)"),
            series,
        ));
    }
    out
}
