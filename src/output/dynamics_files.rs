//! Files written by `ncgear dynamics`: `dynamics.json` (the report, last, whatever the path),
//! and of a time-domain run `timeseries.csv` and the plots of the DTE, the mesh force and the
//! phase plane with its Poincaré section, `spectrum.csv` and its plot, an orbit plot per gear
//! centre that has one; of a sweep `sweep.csv` (up, then down) and the jump diagram. Plots are
//! SVG or PNG.

use super::error::{OutputError, create_dir, remove_stale, write_json};
use super::plot::{ChartLabels, PlotFormat, Series, line_chart};
use crate::analysis::dynamics::{self as dy, DynamicsReport};
use std::path::{Path, PathBuf};

/// Writes the files of `report` (of the scene `prepared`) into `dir` (created if needed), the
/// report last; returns the paths written.
///
/// # Errors
/// [`OutputError`] when a file cannot be written or drawn.
pub fn write_dynamics(
    report: &DynamicsReport,
    prepared: &dy::Prepared,
    dir: &Path,
    format: PlotFormat,
) -> Result<Vec<PathBuf>, OutputError> {
    create_dir(dir)?;
    let json_path = dir.join("dynamics.json");
    remove_stale(&json_path)?;
    let mut out = Files {
        dir,
        ext: format.ext(),
        written: Vec::new(),
    };
    if let (Some(up), Some(down)) = (&report.sweep_up, &report.sweep_down) {
        sweep_files(&mut out, prepared, up, down)?;
    }
    if let (Some(summary), Some(rec)) = (&report.run, &report.recording) {
        time_domain_files(&mut out, summary, rec)?;
        if let Some(spectrum) = &rec.spectrum {
            spectrum_files(&mut out, prepared, spectrum)?;
        }
        orbit_files(&mut out, rec)?;
    }
    write_json(&json_path, report)?;
    out.written.push(json_path);
    Ok(out.written)
}

/// Where the files go, the plot format, and what was written.
struct Files<'a> {
    dir: &'a Path,
    ext: &'a str,
    written: Vec<PathBuf>,
}

impl Files<'_> {
    fn file(&mut self, name: &str) -> PathBuf {
        let p = self.dir.join(name);
        self.written.push(p.clone());
        p
    }

    fn plot(&mut self, stem: &str) -> PathBuf {
        let p = self.dir.join(format!("{stem}.{}", self.ext));
        self.written.push(p.clone());
        p
    }
}

/// A 900 × 600 line chart.
fn chart(
    path: &Path,
    title: &str,
    x: &str,
    y: &str,
    series: Vec<Series>,
    equal: bool,
) -> Result<(), OutputError> {
    let labels = ChartLabels {
        title: title.into(),
        x: x.into(),
        y: y.into(),
        equal_aspect: equal,
    };
    Ok(line_chart(path, &labels, &series, (900, 600))?)
}

/// A CSV file: `header`, then each row's numbers as `{:.9e}`.
fn write_csv(
    path: &Path,
    header: &[String],
    rows: impl Iterator<Item = Vec<f64>>,
) -> Result<(), OutputError> {
    let err = |e: csv::Error| OutputError::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    };
    let mut w = csv::Writer::from_path(path).map_err(err)?;
    w.write_record(header).map_err(err)?;
    for r in rows {
        w.write_record(r.iter().map(|x| format!("{x:.9e}")))
            .map_err(err)?;
    }
    w.flush().map_err(|e| OutputError::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    })
}

/// `sweep.csv` and the sweep plot (amplitude over b with backlash).
fn sweep_files(
    out: &mut Files,
    p: &dy::Prepared,
    up: &[dy::SweepPoint],
    down: &[dy::SweepPoint],
) -> Result<(), OutputError> {
    let backlash = p.model.mesh.backlash;
    let b = backlash.map_or(1.0, |b| b.b);
    let pts = |r: &[dy::SweepPoint]| {
        r.iter()
            .map(|p| (p.omega_ratio, p.dte_half_pp_m / b))
            .collect::<Vec<_>>()
    };
    let ylab = if backlash.is_some() {
        "DTE half peak-to-peak / b"
    } else {
        "DTE half peak-to-peak [m]"
    };
    chart(
        &out.plot("sweep"),
        "Frequency sweep (jump phenomenon)",
        "Ω = ωe/ωn",
        ylab,
        vec![
            Series::line("sweep up", pts(up)),
            Series::line("sweep down", pts(down)),
        ],
        false,
    )?;
    let rows = up
        .iter()
        .map(|p| (1.0, p))
        .chain(down.iter().map(|p| (-1.0, p)));
    write_csv(
        &out.file("sweep.csv"),
        &[
            "direction",
            "omega_ratio",
            "n1_rpm",
            "dte_half_pp_m",
            "dte_mean_m",
            "dte_first_harmonic_m",
            "contact_loss_fraction",
        ]
        .map(String::from),
        rows.map(|(d, p)| {
            vec![
                d,
                p.omega_ratio,
                p.n1_rpm,
                p.dte_half_pp_m,
                p.dte_mean_m,
                p.dte_first_harmonic_m,
                p.contact_loss_fraction,
            ]
        }),
    )?;
    Ok(())
}

/// `timeseries.csv` and the plots of the first 10 mesh periods of the record (DTE in µm, mesh
/// force in N, against time in ms) and of the phase plane with its Poincaré section.
fn time_domain_files(
    out: &mut Files,
    s: &dy::RunReport,
    rec: &dy::Recording,
) -> Result<(), OutputError> {
    let run = &rec.run;
    write_csv(
        &out.file("timeseries.csv"),
        &rec.timeseries_header(),
        rec.timeseries_rows(),
    )?;
    let spm = run.samples_per_mesh as usize;
    let show = run.t_s.len().min(10 * spm);
    let t0 = run.t_s[0];
    // The DTE (µm) and the mesh force (N) over the first 10 mesh periods, against time (ms).
    let dte_um: Vec<f64> = run.dte_m.iter().map(|x| x * 1e6).collect();
    for (stem, title, y, name, values) in [
        (
            "dte",
            "Dynamic transmission error",
            "DTE [µm]",
            "DTE",
            &dte_um,
        ),
        (
            "mesh_force",
            "Mesh force",
            "F_m [N]",
            "F_m",
            &run.mesh_force_n,
        ),
    ] {
        let points = (0..show)
            .map(|k| ((run.t_s[k] - t0) * 1e3, values[k]))
            .collect();
        chart(
            &out.plot(stem),
            title,
            "t − t_rec [ms]",
            y,
            vec![Series::line(name, points)],
            false,
        )?;
    }
    chart(
        &out.plot("phase"),
        "Phase plane and Poincaré section (once per mesh period)",
        "DTE [µm]",
        "dDTE/dt [mm/s]",
        vec![
            Series::line("trajectory", rec.phase.clone()),
            Series::markers("Poincaré", s.poincare_section.clone()),
        ],
        false,
    )?;
    Ok(())
}

/// `spectrum.csv` (Hz, m) and its plot up to 10 mesh frequencies (µm).
fn spectrum_files(
    out: &mut Files,
    p: &dy::Prepared,
    spectrum: &[(f64, f64)],
) -> Result<(), OutputError> {
    write_csv(
        &out.file("spectrum.csv"),
        &["f_hz".into(), "amplitude_m".into()],
        spectrum.iter().map(|&(f, a)| vec![f, a]),
    )?;
    let fmax = 10.0 / p.model.mesh.t0;
    chart(
        &out.plot("spectrum"),
        "DTE spectrum",
        "f [Hz]",
        "amplitude [µm]",
        vec![Series::line(
            "DTE",
            spectrum
                .iter()
                .filter(|p| p.0 <= fmax)
                .map(|&(f, a)| (f, a * 1e6))
                .collect(),
        )],
        false,
    )?;
    Ok(())
}

/// The orbit plot of each gear centre that has one (µm).
fn orbit_files(out: &mut Files, rec: &dy::Recording) -> Result<(), OutputError> {
    for (gear, pts) in &rec.orbits {
        let which = gear.as_str();
        chart(
            &out.plot(&format!("orbit_{which}")),
            &format!("Orbit of the {which} centre"),
            "x [µm]",
            "y [µm]",
            vec![Series::line(which, pts.clone())],
            true,
        )?;
    }
    Ok(())
}
