//! `ncgear._ncgear`: the compiled half of the `ncgear` Python package. Thin: every function calls
//! the `ncgear` library and hands back plain lists, tuples and JSON text; `ncgear/__init__.py`
//! turns them into numpy arrays and dicts. Errors are `ncgear.NcgearError` (a `ValueError`)
//! carrying the library error's message, as the CLI prints it.
use ncgear::design::train::{Gear, ToothedTrain, TrainPolicy, TrainTeethOptions, tooth_design};
use ncgear::design::{Design, DesignOptions, RefineMode};
use ncgear::export::dxf::{DxfVersion, write_dxf};
use ncgear::export::step::write_step;
use ncgear::export::svg::write_svg;
use ncgear::math::polyline::simplify_closed;
use ncgear::output::{SolidOptions, pair_step, train_step_models, write_step_models};
use ncgear::pair::{Expr, Law, PairDesign, PairOptions, design_pair};
use ncgear::simulate::{FeatureOptions, Simulation, deviation_along, features};
use ncgear::teeth::ToothPolicy;
use ncgear::{Trajectory, design as run_design};
use pyo3::create_exception;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use serde_json::Value;
use std::path::{Path, PathBuf};

create_exception!(
    _ncgear,
    NcgearError,
    PyValueError,
    "An ncgear input or design error."
);

fn err(e: impl std::fmt::Display) -> PyErr {
    NcgearError::new_err(e.to_string())
}

fn json(v: &impl serde::Serialize) -> PyResult<String> {
    serde_json::to_string(v).map_err(err)
}

/// Paths as strings.
fn names(paths: Vec<PathBuf>) -> Vec<String> {
    paths.iter().map(|p| p.display().to_string()).collect()
}

fn solids(face_width: Option<f64>, bore: f64) -> SolidOptions {
    let mut s = SolidOptions::default();
    s.face_width_mm = face_width;
    s.bore_mm = bore;
    s
}

/// `(occurrence, part, centre mm, angle rad)` of a STEP assembly.
fn placements_of(m: &ncgear::export::step::StepModel) -> Vec<(String, String, [f64; 2], f64)> {
    m.instances
        .iter()
        .map(|i| {
            (
                i.name.clone(),
                m.parts[i.part].name.clone(),
                i.centre_mm,
                i.angle_rad,
            )
        })
        .collect()
}

/// Outlines `(name, points mm)` simplified to the export chord tolerance `tol_mm`.
fn outlines_of(
    named: &[(&str, &ncgear::teeth::Outline)],
    tol_mm: f64,
) -> Vec<(String, Vec<[f64; 2]>)> {
    named
        .iter()
        .map(|(n, o)| (n.to_string(), simplify_closed(&o.points_mm, tol_mm)))
        .collect()
}

/// Design options from a JSON object of the Python keyword arguments.
fn design_options(center: [f64; 2], options: &str) -> PyResult<DesignOptions> {
    let mut o = DesignOptions::default();
    o.center_mm = center;
    let map: serde_json::Map<String, Value> = serde_json::from_str(options).map_err(err)?;
    for (k, v) in map {
        let bad = || err(format!("option `{k}` = {v}: wrong type"));
        let count = || v.as_u64().map(|n| n as usize).ok_or_else(bad);
        match k.as_str() {
            "order" => o.order = if v.is_null() { None } else { Some(count()?) },
            "tol_mm" => o.tol_tip_mm = v.as_f64().ok_or_else(bad)?,
            "smoothing" => o.smoothing = if v.is_null() { None } else { Some(count()?) },
            "fit" => o.fit_to_points = v.as_bool().ok_or_else(bad)?,
            "samples" => o.curve_samples = count()?,
            "refine" => {
                o.refine = match v.as_str() {
                    Some("auto") => RefineMode::Auto,
                    Some("on") => RefineMode::On,
                    Some("off") => RefineMode::Off,
                    _ => return Err(err(format!("option `refine` = {v}: auto, on or off"))),
                }
            }
            "limits" => o.gear_limits = v.as_bool().ok_or_else(bad)?,
            "max_pressure_angle" => {
                o.pressure_angle_limit_rad = v.as_f64().ok_or_else(bad)?.to_radians()
            }
            "min_concave_radius" => o.min_concave_radius_mm = Some(v.as_f64().ok_or_else(bad)?),
            "min_convex_radius" => o.min_convex_radius_mm = Some(v.as_f64().ok_or_else(bad)?),
            "module" => {
                o.module_mm = if v.is_null() {
                    None
                } else {
                    Some(v.as_f64().ok_or_else(bad)?)
                }
            }
            _ => {
                return Err(err(format!(
                    "unknown option `{k}` (order, tol_mm, smoothing, fit, samples, refine, limits, max_pressure_angle, min_concave_radius, min_convex_radius, module)"
                )));
            }
        }
    }
    Ok(o)
}

/// A designed train (sun, intermediate and planet pitch curves and the report).
#[pyclass(frozen, module = "ncgear._ncgear")]
struct DesignHandle {
    d: Design,
}

#[pymethods]
impl DesignHandle {
    /// The report: the keys and numbers of `design.json`.
    fn report_json(&self) -> PyResult<String> {
        json(&self.d.report)
    }
    /// Pitch curves `(name, points mm)`, body frames, 1440 points each.
    fn pitch_curves(&self) -> Vec<(String, Vec<[f64; 2]>)> {
        let a = &self.d.assembly;
        let n = 1440;
        [
            ("sun", &a.sun),
            ("intermediate", &a.intermediate),
            ("planet", &a.planet),
        ]
        .into_iter()
        .map(|(name, c)| {
            let pts = (0..n)
                .map(|k| c.point_mm(std::f64::consts::TAU * k as f64 / n as f64))
                .collect();
            (name.to_string(), pts)
        })
        .collect()
    }
    /// Distance of each target point to the path the designed gears trace (3600 carrier
    /// positions), mm.
    fn deviations(&self) -> Vec<f64> {
        let r = self.d.assembly.rebuild();
        let traced: Vec<[f64; 2]> = (0..3600)
            .map(|k| r.pose(std::f64::consts::TAU * f64::from(k) / 3600.0).tip_mm)
            .collect();
        deviation_along(&self.d.report.target_points, &traced)
    }
}

/// `design(points | path, center, options_json)`.
#[pyfunction]
#[pyo3(signature = (points, path, center, options))]
fn design(
    points: Option<Vec<[f64; 2]>>,
    path: Option<String>,
    center: [f64; 2],
    options: &str,
) -> PyResult<DesignHandle> {
    let t = match (points, path) {
        (Some(p), None) => Trajectory::from_points(p).map_err(err)?,
        (None, Some(p)) => Trajectory::from_path(Path::new(&p)).map_err(err)?,
        _ => return Err(err("give the trajectory as points or as a file path")),
    };
    let o = design_options(center, options)?;
    let d = run_design(&t, &o).map_err(err)?;
    Ok(DesignHandle { d })
}

/// A toothed train.
#[pyclass(frozen, module = "ncgear._ncgear")]
struct TrainHandle {
    t: ToothedTrain,
}

#[pymethods]
impl TrainHandle {
    /// The `teeth` block of `design.json`.
    fn report_json(&self) -> PyResult<String> {
        json(&self.t.report)
    }
    /// The toothed train's verdict `{"passed", "failures"}` (both meshes), as JSON.
    fn verdict_json(&self) -> PyResult<String> {
        json(&self.t.report.verdict())
    }
    /// Gear outlines `(name, points mm)` in body frames, as exported (export chord tolerance).
    fn outlines(&self) -> Vec<(String, Vec<[f64; 2]>)> {
        let t = &self.t;
        let named = [
            ("sun", &t.sun),
            ("intermediate", &t.intermediate),
            ("planet", &t.planet),
        ];
        outlines_of(&named, t.report.options.toothing.chord_tol_mm)
    }
    /// Placements at φH = 0 `(occurrence, part, centre mm, angle rad)`, as in `train.step`.
    fn placements(&self) -> Vec<(String, String, [f64; 2], f64)> {
        placements_of(&ncgear::output::train_step(
            &self.t,
            &SolidOptions::default(),
        ))
    }
    /// Writes `<gear>.step` and `train.step` into `dir`.
    #[pyo3(signature = (dir, face_width=None, bore=0.0))]
    fn write_step(&self, dir: &str, face_width: Option<f64>, bore: f64) -> PyResult<Vec<String>> {
        let models = train_step_models(&self.t, &solids(face_width, bore));
        Ok(names(
            write_step_models(&models, Path::new(dir)).map_err(err)?,
        ))
    }
    /// Writes `<gear>.dxf`/`.svg` (body frames) and `train.dxf`/`.svg` (φH = 0) into `dir`.
    fn write_sheets(&self, dir: &str, kind: &str) -> PyResult<Vec<String>> {
        std::fs::create_dir_all(dir).map_err(err)?;
        let mut sheets = vec![("train".to_string(), self.t.sheet(0.0))];
        sheets.extend(Gear::ALL.map(|g| (g.name().to_string(), self.t.gear_sheet(g))));
        let r = &self.t.report;
        sheets
            .iter()
            .map(|(n, s)| {
                let p = Path::new(dir).join(format!("{n}.{kind}"));
                sheet(s, &p, kind, r.options.toothing.chord_tol_mm, r.module_mm)
            })
            .collect()
    }
}

fn sheet(
    s: &ncgear::export::Sheet,
    p: &Path,
    kind: &str,
    tol: f64,
    module: f64,
) -> PyResult<String> {
    match kind {
        "dxf" => write_dxf(s, p, DxfVersion::R2010, tol).map_err(err)?,
        _ => write_svg(s, p, 2.0 * module).map_err(err)?,
    }
    Ok(p.display().to_string())
}

/// `teeth(design, module, policy, teeth, backlash, chord_tol, verify_steps)`.
#[pyfunction]
#[pyo3(signature = (design, module, policy, teeth, backlash, chord_tol, verify_steps))]
fn teeth(
    design: &DesignHandle,
    module: f64,
    policy: &str,
    teeth: Option<u32>,
    backlash: Option<f64>,
    chord_tol: Option<f64>,
    verify_steps: usize,
) -> PyResult<TrainHandle> {
    let mut o = TrainTeethOptions::new(module);
    o.toothing.verify_steps = verify_steps;
    o.toothing.backlash_mm = backlash.unwrap_or(o.toothing.backlash_mm);
    o.toothing.chord_tol_mm = chord_tol.unwrap_or(o.toothing.chord_tol_mm);
    o.policy = match (teeth, policy) {
        (Some(z), _) => TrainPolicy::ScaleCenterDistance(ToothPolicy::Exact(z)),
        (None, "scale-up") => TrainPolicy::ScaleCenterDistance(ToothPolicy::ScaleUp),
        (None, "nearest") => TrainPolicy::ScaleCenterDistance(ToothPolicy::Nearest),
        (None, "scale-down") => TrainPolicy::ScaleCenterDistance(ToothPolicy::ScaleDown),
        (None, "ratio-amplitude") => TrainPolicy::RatioAmplitude,
        (None, "adjust-module") => TrainPolicy::AdjustModule,
        (None, "design") => TrainPolicy::Designed,
        (None, p) => {
            return Err(err(format!(
                "policy `{p}`: design, scale-up, nearest, scale-down, ratio-amplitude or adjust-module"
            )));
        }
    };
    // The CLI's accuracy: 1e-9 of the centre distance.
    let acc = 1e-9 * design.d.assembly.a_mm;
    let t = tooth_design(&design.d, &o, acc, &|_| {})
        .map_err(|e| err(format!("--module {module}: {e}")))?;
    Ok(TrainHandle { t })
}

/// A single gear pair.
#[pyclass(frozen, module = "ncgear._ncgear")]
struct PairHandle {
    p: PairDesign,
    chord_tol_mm: f64,
    report: String,
}

#[pymethods]
impl PairHandle {
    /// z, module, centre distance, perimeter, ratio range and the mesh report.
    fn report_json(&self) -> String {
        self.report.clone()
    }
    /// `(name, points mm)`: driver and driven outlines in their body frames (export tolerance).
    fn outlines(&self) -> Vec<(String, Vec<[f64; 2]>)> {
        outlines_of(
            &[("driver", &self.p.driver), ("driven", &self.p.driven)],
            self.chord_tol_mm,
        )
    }
    /// Placements at the start `(occurrence, part, centre mm, angle rad)`, as in `pair.step`.
    fn placements(&self) -> Vec<(String, String, [f64; 2], f64)> {
        placements_of(&pair_step(
            &self.p,
            self.chord_tol_mm,
            &SolidOptions::default(),
        ))
    }
    /// Writes `pair.step` into `dir`.
    #[pyo3(signature = (dir, face_width=None, bore=0.0))]
    fn write_step(&self, dir: &str, face_width: Option<f64>, bore: f64) -> PyResult<Vec<String>> {
        std::fs::create_dir_all(dir).map_err(err)?;
        let p = Path::new(dir).join("pair.step");
        let m = pair_step(&self.p, self.chord_tol_mm, &solids(face_width, bore));
        write_step(&m, &p).map_err(err)?;
        Ok(vec![p.display().to_string()])
    }
    /// Writes `pair.dxf` or `pair.svg` (both gears at the start) into `dir`.
    fn write_sheets(&self, dir: &str, kind: &str) -> PyResult<Vec<String>> {
        std::fs::create_dir_all(dir).map_err(err)?;
        let p = Path::new(dir).join(format!("pair.{kind}"));
        let s = self.p.assembly_sheet();
        Ok(vec![sheet(
            &s,
            &p,
            kind,
            self.chord_tol_mm,
            self.p.module_mm,
        )?])
    }
}

/// `pair(law, kind, teeth, module, verify_steps, cycle_advance_deg, drive_deg)`; kind: motion,
/// centrode or csv (law = path); `drive_deg`: an open sector's driver interval, degrees.
#[pyfunction]
#[pyo3(signature = (law, kind, teeth, module, verify_steps, cycle_advance_deg, drive_deg))]
fn pair(
    law: &str,
    kind: &str,
    teeth: Option<u32>,
    module: f64,
    verify_steps: usize,
    cycle_advance_deg: f64,
    drive_deg: Option<(f64, f64)>,
) -> PyResult<PairHandle> {
    let law = match kind {
        "motion" => Law::Motion(Expr::parse(law).map_err(err)?),
        "centrode" => Law::Centrode(Expr::parse(law).map_err(err)?),
        "csv" => Law::from_csv(Path::new(law)).map_err(err)?,
        k => return Err(err(format!("kind `{k}`: motion, centrode or csv"))),
    };
    let mut o = PairOptions::new(teeth, module);
    o.toothing.verify_steps = verify_steps;
    o.centrode_advance_rad = cycle_advance_deg.to_radians();
    o.open_sector_rad = drive_deg.map(|(a, b)| [a.to_radians(), b.to_radians()]);
    let p = design_pair(&law, &o).map_err(err)?;
    let report = serde_json::json!({
        "z": p.z,
        "z_driven": p.z_driven,
        "cycle_advance_deg": p.advance_rad.to_degrees(),
        "module_mm": p.module_mm,
        "centre_distance_mm": p.centre_distance_mm,
        "perimeter_mm": p.perimeter_mm,
        "ratio_range": p.ratio_range,
        "mesh": p.mesh,
        "sector": p.sector,
        "verdict": p.verdict(),
    })
    .to_string();
    Ok(PairHandle {
        p,
        chord_tol_mm: o.toothing.chord_tol_mm,
        report,
    })
}

/// Agronomic features of one carrier turn of a design (or its toothed train), as JSON.
#[pyfunction]
#[pyo3(signature = (design, train, rpm, forward_mm_s, depth_mm))]
fn simulate(
    design: &DesignHandle,
    train: Option<&TrainHandle>,
    rpm: f64,
    forward_mm_s: f64,
    depth_mm: f64,
) -> PyResult<String> {
    let sim = match train {
        Some(t) => Simulation::toothed(&t.t),
        None => Simulation::new(design.d.assembly.clone()),
    };
    let mut o = FeatureOptions::default();
    o.rpm = rpm;
    o.forward_mm_s = forward_mm_s;
    o.planting_depth_mm = depth_mm;
    json(&features(&sim, &o).map_err(err)?)
}

/// Plant spacing → forward speed (mm/s) at `rpm`, two arms.
#[pyfunction]
fn forward_for_spacing(spacing_mm: f64, rpm: f64) -> f64 {
    FeatureOptions::forward_for_spacing(spacing_mm, rpm)
}

/// `ncgear tolerance` on an error file: the report (`tolerance.json`) as JSON.
#[pyfunction]
#[pyo3(signature = (path, samples))]
fn tolerance(path: &str, samples: usize) -> PyResult<String> {
    use ncgear::analysis::tolerance::{ErrorFile, ToleranceOptions, analyse};
    let file = ErrorFile::from_path(Path::new(path)).map_err(err)?;
    let mut o = ToleranceOptions::default();
    if samples > 0 {
        let mut mc = ncgear::analysis::montecarlo::McOptions::default();
        mc.samples = samples;
        o.monte_carlo = Some(mc);
    }
    json(&analyse(&file, &o, &|_| {}).map_err(err)?)
}

#[pymodule]
fn _ncgear(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("NcgearError", m.py().get_type::<NcgearError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<DesignHandle>()?;
    m.add_class::<TrainHandle>()?;
    m.add_class::<PairHandle>()?;
    for f in [
        wrap_pyfunction!(design, m)?,
        wrap_pyfunction!(teeth, m)?,
        wrap_pyfunction!(pair, m)?,
        wrap_pyfunction!(simulate, m)?,
        wrap_pyfunction!(forward_for_spacing, m)?,
        wrap_pyfunction!(tolerance, m)?,
    ] {
        m.add_function(f)?;
    }
    Ok(())
}
