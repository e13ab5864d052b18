//! `ncgear._ncgear`: the compiled half of the `ncgear` Python package. Thin: every function calls
//! the `ncgear` library; reports come back as [`Report`]s (the JSON text and a tree of dicts whose
//! number arrays are numpy arrays), point sets as float64 (N, 2) numpy arrays in mm; the pure
//! Python half (`ncgear/__init__.py`) turns them into frozen dataclasses. Errors are
//! `ncgear.NcgearError` (a `ValueError`) naming the Python argument at fault.
mod convert;
mod errors;
mod options;

use convert::{points, to_py};
use errors::{NcgearError, design_err, err, loads_err, pair_err, rotor_err};
use ncgear::analysis::dynamics::rotor::rating::{forces_of_scene, run_loads_scene};
use ncgear::analysis::dynamics::rotor::sweep::MAX_SWEEP_SPEEDS;
use ncgear::analysis::dynamics::rotor::{Prepared, RotorError, RotorScene, sweep_rpm};
use ncgear::cad::dxf::{DxfVersion, write_dxf};
use ncgear::cad::step::write_step;
use ncgear::cad::svg::write_svg;
use ncgear::compare::args::CompareArgs;
use ncgear::compare::{CompareError, compare_track};
use ncgear::design::Design;
use ncgear::design::train::{Gear, ToothedTrain, TrainTeethOptions, tooth_train};
use ncgear::design::trajectory::{DrawingOptions, DrawingUnits};
use ncgear::loads::scene::MAX_CARRIER_RPM;
use ncgear::loads::{LoadsError, LoadsReport, Rotor, RotorSource, Scene, analyse_with};
use ncgear::math::polyline::simplify_closed;
use ncgear::output::{SolidOptions, pair_step, train_step_models, write_step_models};
use ncgear::pair::{Expr, Law, PairDesign, PairOptions, design_pair};
use ncgear::simulate::{DesignFile, FeatureOptions, Simulation, deviation_along, features};
use ncgear::{Trajectory, design as run_design};
use numpy::{PyArray1, PyReadonlyArray2};
use options::{DesignArgs, ToothArgs, choice, train_policy};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde_json::Value;
use std::path::{Path, PathBuf};

/// A report: the JSON of the CLI's file, as text or as Python objects.
#[pyclass(frozen, module = "ncgear._ncgear")]
struct Report {
    value: Value,
}

#[pymethods]
impl Report {
    /// The report as dicts, lists and scalars, its number arrays as float64 numpy arrays.
    fn tree<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, &self.value)
    }
    /// The report as JSON text (the CLI's file).
    fn json(&self) -> String {
        self.value.to_string()
    }
}

/// `v` serialised as a [`Report`].
fn report(v: &impl serde::Serialize) -> PyResult<Report> {
    Ok(Report {
        value: serde_json::to_value(v).map_err(err)?,
    })
}

/// Paths as strings.
fn names(paths: Vec<PathBuf>) -> Vec<String> {
    paths.iter().map(|p| p.display().to_string()).collect()
}

/// Face width (mm; `None`: 10·m) and bore diameter (mm; 0: none) of the STEP solids.
fn solids(face_width: Option<f64>, bore: f64) -> SolidOptions {
    SolidOptions::default()
        .with_face_width_mm(face_width)
        .with_bore_mm(bore)
}

/// `(occurrence, part, centre mm, angle rad)` of a STEP assembly.
fn placements_of(m: &ncgear::cad::step::StepModel) -> Vec<(String, String, [f64; 2], f64)> {
    m.instances
        .iter()
        .map(|i| {
            let part = m.parts[i.part].name.clone();
            (i.name.clone(), part, i.center_mm.to_array(), i.angle_rad)
        })
        .collect()
}

/// `{name: (N, 2) array, mm}` of outlines simplified to the export chord tolerance `tol_mm`.
fn outlines_of<'py>(
    py: Python<'py>,
    named: &[(&str, &ncgear::teeth::Outline)],
    tol_mm: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (name, o) in named {
        d.set_item(name, points(py, &simplify_closed(&o.points_mm, tol_mm)))?;
    }
    Ok(d)
}

/// Writes sheet `s` to `p` as `kind` (`dxf` of `version`, or `svg`); `tol` is the chord
/// tolerance and `module` the module, mm.
fn sheet(
    s: &ncgear::cad::Sheet,
    p: &Path,
    kind: &str,
    version: DxfVersion,
    (tol, module): (f64, f64),
) -> PyResult<String> {
    match kind {
        "dxf" => write_dxf(s, p, version, tol).map_err(err)?,
        _ => write_svg(s, p, 2.0 * module).map_err(err)?,
    }
    Ok(p.display().to_string())
}

/// The DXF version named `version` (`r2010` or `r12`).
fn dxf_version(version: &str) -> PyResult<DxfVersion> {
    choice(
        "version",
        version,
        &[("r2010", DxfVersion::R2010), ("r12", DxfVersion::R12)],
    )
}

/// A designed train (sun, intermediate and planet pitch curves and the report).
#[pyclass(frozen, module = "ncgear._ncgear")]
struct DesignHandle {
    d: Design,
}

#[pymethods]
impl DesignHandle {
    /// The report: `design.json`.
    fn report(&self) -> PyResult<Report> {
        report(&self.d.report)
    }
    /// Distance of each target point to the path the designed gears trace (3600 carrier
    /// positions), mm.
    fn deviations<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let r = self.d.assembly.rebuild();
        let traced: Vec<ncgear::math::Point> = (0..3600)
            .map(|k| r.pose(std::f64::consts::TAU * f64::from(k) / 3600.0).tip_mm)
            .collect();
        PyArray1::from_vec(py, deviation_along(&self.d.report.target_points, &traced))
    }
}

/// The trajectory of an (N, 2) array of points (mm) or of a file.
fn trajectory(
    points: Option<PyReadonlyArray2<'_, f64>>,
    path: Option<&str>,
) -> PyResult<Trajectory> {
    match (points, path) {
        (Some(a), None) => {
            let a = a.as_array();
            if a.ncols() != 2 {
                return Err(err(format!(
                    "points: expected an (N, 2) array of x, y in mm, got shape {:?}",
                    a.shape()
                )));
            }
            Trajectory::from_points(
                a.rows()
                    .into_iter()
                    .map(|r| ncgear::math::Point::new(r[0], r[1]))
                    .collect(),
            )
            .map_err(err)
        }
        (None, Some(p)) => Trajectory::from_path(Path::new(p)).map_err(err),
        _ => Err(err("points: give an (N, 2) array or a file path")),
    }
}

/// `read_trajectory(path, layer, id, units)`: the points (N, 2), mm, that `design` sees in a
/// trajectory file — a DXF or SVG drawing read with its layer, id and units, or CSV/JSON.
#[pyfunction]
#[pyo3(signature = (path, layer, id, units))]
fn read_trajectory<'py>(
    py: Python<'py>,
    path: &str,
    layer: Option<String>,
    id: Option<String>,
    units: Option<&str>,
) -> PyResult<Bound<'py, PyAny>> {
    let units = units
        .map(|u| {
            u.parse::<DrawingUnits>()
                .map_err(|e| errors::arg_err("units", format!("{u:?}"), e))
        })
        .transpose()?;
    let opts = DrawingOptions::default()
        .with_layer(layer)
        .with_id(id)
        .with_units(units);
    let t = Trajectory::from_path_with(Path::new(path), &opts).map_err(err)?;
    Ok(points(py, t.points()))
}

/// `design(points | path, options)`: the options as `DesignArgs`.
#[pyfunction]
#[pyo3(signature = (points, path, options))]
fn design(
    points: Option<PyReadonlyArray2<'_, f64>>,
    path: Option<&str>,
    options: DesignArgs,
) -> PyResult<DesignHandle> {
    let t = trajectory(points, path)?;
    let o = options.options()?;
    let d = run_design(&t, &o).map_err(|e| design_err(&e))?;
    Ok(DesignHandle { d })
}

/// `design(points | path, options, module="auto", loads=scene)`: the module sized by strength
/// under the scene `scene` (a file path, or the name of the dict whose JSON is `text`), as
/// `ncgear design --module auto --loads` sizes it ([`ncgear::loads::Sized::into_kept`], the default
/// rack at each module); the design kept carries the table (`report.sizing`). Without the GIL.
#[pyfunction]
#[pyo3(signature = (points, path, options, scene, text))]
fn design_sized(
    py: Python<'_>,
    points: Option<PyReadonlyArray2<'_, f64>>,
    path: Option<&str>,
    options: DesignArgs,
    scene: &str,
    text: Option<&str>,
) -> PyResult<DesignHandle> {
    let t = trajectory(points, path)?;
    let o = options.options()?;
    let run = || -> Result<Result<Design, String>, LoadsError> {
        let spec = scene_of(scene, text)?;
        let case = spec.validate(scene)?;
        let dynamics = forces_of_scene(&spec, scene)?;
        let opts = ncgear::loads::SizingOptions::default();
        let sized = ncgear::loads::size_module(
            &t,
            &o,
            &case,
            &opts,
            &ncgear::loads::rating_teeth,
            dynamics.as_deref(),
            scene,
        )?;
        Ok(sized
            .into_kept()
            .map(|k| k.design)
            .map_err(|table| table.markdown()))
    };
    let sized = py
        .detach(run)
        .map_err(|e| loads_err(&e, text.is_some(), true))?;
    let d = sized.map_err(|table| {
        err(format!(
            "module=\"auto\": no standard module could be designed and rated:\n{table}"
        ))
    })?;
    Ok(DesignHandle { d })
}

/// A toothed train.
#[pyclass(frozen, module = "ncgear._ncgear")]
struct TrainHandle {
    t: ToothedTrain,
    /// Both meshes and the tooth-count policy against the design's C12 (`teeth_verdict`).
    verdict: ncgear::verdict::Verdict,
}

#[pymethods]
impl TrainHandle {
    /// The `teeth` block of `design.json`.
    fn report(&self) -> PyResult<Report> {
        report(&self.t.report)
    }
    /// The toothed train's verdict `{"passed", "failures"}`: both meshes, and a scaling tooth
    /// policy whose tip shift exceeds the design's C12 limit.
    fn verdict(&self) -> PyResult<Report> {
        report(&self.verdict)
    }
    /// Gear outlines `{name: (N, 2) array, mm}` in body frames, as exported.
    fn outlines<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let t = &self.t;
        let named = [
            ("sun", &t.sun),
            ("intermediate", &t.intermediate),
            ("planet", &t.planet),
        ];
        outlines_of(py, &named, t.report.options.toothing.chord_tol_mm)
    }
    /// Placements at φH = 0 `(occurrence, part, centre mm, angle rad)`, as in `train.step`.
    fn placements(&self) -> Vec<(String, String, [f64; 2], f64)> {
        placements_of(&ncgear::output::train_step(
            &self.t,
            &SolidOptions::default(),
        ))
    }
    /// Writes `<gear>.step` and `train.step` into `dir`.
    #[pyo3(signature = (dir, face_width, bore))]
    fn write_step(&self, dir: &str, face_width: Option<f64>, bore: f64) -> PyResult<Vec<String>> {
        let models = train_step_models(&self.t, &solids(face_width, bore));
        let written = write_step_models(&models, Path::new(dir)).map_err(err)?;
        Ok(names(written))
    }
    /// Writes `<gear>.dxf`/`.svg` (body frames) and `train.dxf`/`.svg` (φH = 0) into `dir`.
    fn write_sheets(&self, dir: &str, kind: &str, version: &str) -> PyResult<Vec<String>> {
        let version = dxf_version(version)?;
        std::fs::create_dir_all(dir).map_err(err)?;
        let mut sheets = vec![("train".to_string(), self.t.sheet(0.0))];
        sheets.extend(Gear::ALL.map(|g| (g.name().to_string(), self.t.gear_sheet(g))));
        let r = &self.t.report;
        let sizes = (r.options.toothing.chord_tol_mm, r.module_mm);
        sheets
            .iter()
            .map(|(n, s)| {
                let p = Path::new(dir).join(format!("{n}.{kind}"));
                sheet(s, &p, kind, version, sizes)
            })
            .collect()
    }
}

/// `teeth(design, module, tooth_policy, teeth, wire_edm, tooth)`: `tooth` as `ToothArgs`.
#[pyfunction]
#[pyo3(signature = (design, module, tooth_policy, teeth, wire_edm, tooth))]
fn teeth(
    design: &DesignHandle,
    module: f64,
    tooth_policy: &str,
    teeth: Option<u32>,
    wire_edm: bool,
    tooth: ToothArgs,
) -> PyResult<TrainHandle> {
    let mut o = TrainTeethOptions::new(module)
        .with_wire_edm(wire_edm)
        .with_policy(train_policy(tooth_policy, teeth)?);
    tooth.apply_to(&mut o.toothing)?;
    let t = tooth_train(&design.d, &o).map_err(|e| errors::arg_err("module", module, e))?;
    let verdict = design.d.report.teeth_verdict(&t.report);
    Ok(TrainHandle { t, verdict })
}

/// A single gear pair.
#[pyclass(frozen, module = "ncgear._ncgear")]
struct PairHandle {
    p: PairDesign,
    chord_tol_mm: f64,
    report: Value,
}

#[pymethods]
impl PairHandle {
    /// `pair.json` without files and timings ([`ncgear::pair::PairReport`]).
    fn report(&self) -> Report {
        Report {
            value: self.report.clone(),
        }
    }
    /// `{name: (N, 2) array, mm}`: driver and driven outlines in their body frames, as exported.
    fn outlines<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let named = [("driver", &self.p.driver), ("driven", &self.p.driven)];
        outlines_of(py, &named, self.chord_tol_mm)
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
    #[pyo3(signature = (dir, face_width, bore))]
    fn write_step(&self, dir: &str, face_width: Option<f64>, bore: f64) -> PyResult<Vec<String>> {
        std::fs::create_dir_all(dir).map_err(err)?;
        let p = Path::new(dir).join("pair.step");
        let m = pair_step(&self.p, self.chord_tol_mm, &solids(face_width, bore));
        write_step(&m, &p).map_err(err)?;
        Ok(vec![p.display().to_string()])
    }
    /// Writes `pair.dxf` or `pair.svg` (both gears at the start) into `dir`.
    fn write_sheets(&self, dir: &str, kind: &str, version: &str) -> PyResult<Vec<String>> {
        let version = dxf_version(version)?;
        std::fs::create_dir_all(dir).map_err(err)?;
        let p = Path::new(dir).join(format!("pair.{kind}"));
        let s = self.p.assembly_sheet();
        let sizes = (self.chord_tol_mm, self.p.module_mm);
        Ok(vec![sheet(&s, &p, kind, version, sizes)?])
    }
}

/// The law of `kind` (`motion`, `centrode` or `csv`: `law` is then a path).
fn law_of(law: &str, kind: &str) -> PyResult<Law> {
    #[derive(Clone, Copy)]
    enum Kind {
        Motion,
        Centrode,
        Csv,
    }
    let table = [
        ("motion", Kind::Motion),
        ("centrode", Kind::Centrode),
        ("csv", Kind::Csv),
    ];
    match choice("kind", kind, &table)? {
        Kind::Motion => Ok(Law::Motion(Expr::parse(law).map_err(err)?)),
        Kind::Centrode => Ok(Law::Centrode(Expr::parse(law).map_err(err)?)),
        Kind::Csv => Law::from_csv(Path::new(law)).map_err(err),
    }
}

/// `pair(law, kind, teeth, module, cycle_advance_deg, drive_deg, tooth)`: `drive_deg` an open
/// sector's driver interval, degrees; `tooth` as `ToothArgs`.
#[pyfunction]
#[pyo3(signature = (law, kind, teeth, module, cycle_advance_deg, drive_deg, tooth))]
fn pair(
    law: &str,
    kind: &str,
    teeth: Option<u32>,
    module: f64,
    cycle_advance_deg: f64,
    drive_deg: Option<(f64, f64)>,
    tooth: ToothArgs,
) -> PyResult<PairHandle> {
    let law = law_of(law, kind)?;
    let mut o = PairOptions::new(teeth, module)
        .with_centrode_advance_rad(cycle_advance_deg.to_radians())
        .with_open_sector_rad(drive_deg.map(|(a, b)| [a.to_radians(), b.to_radians()]));
    tooth.apply_to(&mut o.toothing)?;
    let p = design_pair(&law, &o).map_err(|e| pair_err(&e))?;
    Ok(PairHandle {
        report: report(&p.report(&o))?.value,
        chord_tol_mm: o.toothing.chord_tol_mm,
        p,
    })
}

/// Agronomic features of one carrier turn of a design (or its toothed train): forward speed
/// mm/s, planting depth and the taking / planting levels (`None`: the highest / lowest point) mm.
#[pyfunction]
#[pyo3(signature = (design, train, rpm, forward_mm_s, depth_mm, levels_mm))]
fn simulate(
    design: &DesignHandle,
    train: Option<&TrainHandle>,
    rpm: f64,
    forward_mm_s: f64,
    depth_mm: f64,
    levels_mm: (Option<f64>, Option<f64>),
) -> PyResult<Report> {
    let sim = match train {
        Some(t) => Simulation::toothed(&t.t),
        None => Simulation::new(design.d.assembly.clone()),
    };
    let (take_level_mm, plant_level_mm) = levels_mm;
    let o = FeatureOptions::default()
        .with_rpm(rpm)
        .with_forward_mm_s(forward_mm_s)
        .with_planting_depth_mm(depth_mm)
        .with_take_level_mm(take_level_mm)
        .with_plant_level_mm(plant_level_mm);
    report(&features(&sim, &o).map_err(err)?)
}

/// Plant spacing → forward speed (mm/s) at `rpm`, two arms.
#[pyfunction]
fn forward_for_spacing(spacing_mm: f64, rpm: f64) -> f64 {
    FeatureOptions::forward_for_spacing(spacing_mm, rpm)
}

/// `ncgear tolerance` on an error file: `tolerance.json`. `samples` 0: no Monte Carlo; `seed`
/// its seed; `starts` the joint optimizer's starts.
#[pyfunction]
#[pyo3(signature = (path, samples, seed, starts))]
fn tolerance(path: &str, samples: usize, seed: u64, starts: usize) -> PyResult<Report> {
    use ncgear::analysis::tolerance::{ErrorFile, ToleranceOptions, analyse};
    use ncgear::math::monte_carlo::McOptions;
    let file = ErrorFile::from_path(Path::new(path)).map_err(err)?;
    let mc = McOptions::default().with_samples(samples).with_seed(seed);
    let o = ToleranceOptions::default()
        .with_joint_starts(starts)
        .with_monte_carlo((samples > 0).then_some(mc));
    report(&analyse(&file, &o, &ncgear::progress::Progress::none()).map_err(err)?)
}

/// The scene named `name`, as type `T` (a loads or a rotor scene): the JSON `text` of a dict
/// when given (messages name it `name`), else the file at `name` (TOML or JSON). The error is
/// the message naming the scene, line and key.
fn read_scene<T: serde::de::DeserializeOwned>(name: &str, text: Option<&str>) -> Result<T, String> {
    match text {
        Some(t) => ncgear::config::parse(t, name, ncgear::config::Format::Json),
        None => ncgear::config::load(Path::new(name)),
    }
    .map_err(|e| e.to_string())
}

/// The loads scene named `name` ([`read_scene`]).
fn scene_of(name: &str, text: Option<&str>) -> Result<Scene, LoadsError> {
    read_scene(name, text).map_err(LoadsError::Scene)
}

/// The loads of a design's pitch curves, or of its toothed `train`, over one carrier turn under
/// the scene `scene` (a file path, or the name of the dict whose JSON is `text`); the scene's
/// `design` key is not read. Without the GIL.
#[pyfunction]
#[pyo3(signature = (design, train, scene, text))]
fn loads(
    py: Python<'_>,
    design: &DesignHandle,
    train: Option<&TrainHandle>,
    scene: &str,
    text: Option<&str>,
) -> PyResult<Report> {
    let run = || -> Result<LoadsReport, LoadsError> {
        let spec = scene_of(scene, text)?;
        let case = spec.validate(scene)?;
        let dynamics = forces_of_scene(&spec, scene)?;
        let rotor = match train {
            Some(t) => Rotor::toothed(&t.t),
            None => Rotor::pitch(&design.d.assembly),
        };
        analyse_with(&rotor, &case, scene, dynamics.as_deref())
    };
    let r = py
        .detach(run)
        .map_err(|e| loads_err(&e, text.is_some(), true))?;
    report(&r)
}

/// `ncgear loads SCENE` in-process: the scene file and the design file it names (`loads.json`).
/// Without the GIL.
#[pyfunction]
fn loads_file(py: Python<'_>, path: &str) -> PyResult<Report> {
    let r = py
        .detach(|| run_loads_scene(Path::new(path)))
        .map_err(|e| loads_err(&e, false, false))?;
    report(&r)
}

/// Carrier speeds of a sweep checked: 1 to [`MAX_SWEEP_SPEEDS`] speeds, each in
/// (0, [`MAX_CARRIER_RPM`]] r/min.
fn sweep_speeds(rpm: Option<Vec<f64>>) -> PyResult<Option<Vec<f64>>> {
    let Some(rpm) = rpm else { return Ok(None) };
    let ok = |v: &f64| v.is_finite() && *v > 0.0 && *v <= MAX_CARRIER_RPM;
    if rpm.is_empty() || rpm.len() > MAX_SWEEP_SPEEDS || !rpm.iter().all(ok) {
        return Err(errors::arg_err(
            "sweep_rpm",
            format!("{rpm:?}"),
            format!(
                "1 to {MAX_SWEEP_SPEEDS} carrier speeds (each a steady state), each in \
                 (0, {MAX_CARRIER_RPM}] r/min"
            ),
        ));
    }
    Ok(Some(rpm))
}

/// The steady state of `prepared` as its [`ncgear::analysis::dynamics::rotor::RotorReport`], or
/// with `rpm` (r/min) the sweep's rows.
fn rotor_run(prepared: &Prepared, rpm: Option<&[f64]>) -> Result<Value, RotorError> {
    let none = ncgear::progress::Progress::none();
    let v = match rpm {
        Some(rpm) => serde_json::to_value(sweep_rpm(prepared, rpm, &none)?),
        None => serde_json::to_value(prepared.run(&none)?.report),
    };
    v.map_err(|e| RotorError::Scene(e.to_string()))
}

/// The planting rotor's dynamics (elastic teeth, damping, backlash, impacts) of a design's
/// pitch curves, or of its toothed `train`, under the rotor scene `scene` (a file path, or the
/// name of the dict whose JSON is `text`), to the periodic steady state; with `sweep_rpm`
/// (r/min) the sweep's rows. The scene's `design` key is not read (only echoed in the report).
/// Without the GIL.
#[pyfunction]
#[pyo3(signature = (design, train, scene, text, sweep_rpm))]
fn dynamics(
    py: Python<'_>,
    design: &DesignHandle,
    train: Option<&TrainHandle>,
    scene: &str,
    text: Option<&str>,
    sweep_rpm: Option<Vec<f64>>,
) -> PyResult<Report> {
    let rpm = sweep_speeds(sweep_rpm)?;
    let run = || -> Result<Value, RotorError> {
        let spec: RotorScene = read_scene(scene, text).map_err(RotorError::Scene)?;
        let case = spec.validate(scene)?;
        let source = match train {
            Some(t) => RotorSource::from_train(t.t.assembly.clone(), Some(t.t.clone()), vec![]),
            None => RotorSource::from_train(design.d.assembly.clone(), None, vec![]),
        };
        rotor_run(&Prepared::new(&spec, case, source, scene)?, rpm.as_deref())
    };
    let value = py
        .detach(run)
        .map_err(|e| rotor_err(&e, text.is_some(), true))?;
    Ok(Report { value })
}

/// `ncgear dynamics SCENE` in-process: the rotor scene file and the design file it names
/// (`dynamics.json`), or with `sweep_rpm` (r/min) the sweep's rows. Without the GIL.
#[pyfunction]
#[pyo3(signature = (path, sweep_rpm))]
fn dynamics_file(py: Python<'_>, path: &str, sweep_rpm: Option<Vec<f64>>) -> PyResult<Report> {
    let rpm = sweep_speeds(sweep_rpm)?;
    let value = py
        .detach(|| rotor_run(&Prepared::from_path(Path::new(path))?, rpm.as_deref()))
        .map_err(|e| rotor_err(&e, false, false))?;
    Ok(Report { value })
}

/// `ncgear compare TRACK --design …` in-process: `compare.json` of the track file `track`
/// against the design `design` (a handle) or the design file `design_path`, with `args` the
/// JSON of `ncgear.compare`'s keywords (the library's [`CompareArgs`]: its keys, defaults and
/// checks), and with the rotor scene file `dynamics` against its dynamic path too; and the
/// frames: carrier angle (rad), registered tip (mm), residual (mm), outlier flag. Without the
/// GIL.
#[pyfunction]
#[pyo3(signature = (track, design, design_path, args, dynamics))]
fn compare<'py>(
    py: Python<'py>,
    track: &str,
    design: Option<&DesignHandle>,
    design_path: Option<&str>,
    args: &str,
    dynamics: Option<&str>,
) -> PyResult<CompareOut<'py>> {
    let args: CompareArgs = serde_json::from_str(args).map_err(|e| err(format!("options: {e}")))?;
    let asm = match (design, design_path) {
        (Some(d), _) => d.d.assembly.clone(),
        (None, Some(p)) => {
            DesignFile::from_path(Path::new(p))
                .map_err(|e| errors::arg_err("design", p, e))?
                .1
        }
        (None, None) => return Err(err("design: expected a Design, a Train or a design file")),
    };
    let scene = dynamics
        .map(|p| Prepared::from_path(Path::new(p)).map_err(|e| rotor_err(&e, false, false)))
        .transpose()?;
    let c = py
        .detach(|| {
            compare_track(
                Path::new(track),
                &asm.rebuild(),
                &args,
                scene.as_ref(),
                &ncgear::progress::Progress::none(),
            )
        })
        .map_err(|e| match e {
            // An option's error on its keyword (`px_per_mm`), the rest on the track.
            CompareError::BadOption { option, message } => {
                err(format!("{}: {message}", option.replace('-', "_")))
            }
            e => errors::arg_err("track", track, e),
        })?;
    let f = &c.frames;
    Ok((
        report(&c.report)?,
        PyArray1::from_vec(py, f.iter().map(|x| x.phi_rad).collect()).into_any(),
        points(py, &f.iter().map(|x| x.q_mm).collect::<Vec<_>>()),
        points(py, &f.iter().map(|x| x.residual_mm).collect::<Vec<_>>()),
        f.iter().map(|x| x.outlier).collect(),
    ))
}

/// What [`compare`] returns: the report and the frames' arrays.
type CompareOut<'py> = (
    Report,
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
    Vec<bool>,
);

/// The synthesis spec named `name`: the JSON `text` of a dict when given (messages name it
/// `name`), else the file at `name` (TOML or JSON), as `ncgear synthesize` reads it.
fn spec_of(name: &str, text: Option<&str>) -> PyResult<ncgear::synthesis::Spec> {
    match text {
        Some(t) => ncgear::config::parse(t, name, ncgear::config::Format::Json),
        None => ncgear::config::load(Path::new(name)),
    }
    .map_err(|e| errors::arg_err("spec", name, e))
}

/// `ncgear synthesize SPEC` in-process: `synthesis.json` and the chosen design, from the spec
/// file `spec` (or the dict whose JSON is `text`), each candidate's gears designed with `options`
/// (`ncgear.design`'s; its `center` is the arm's); `l1_mm`, `l3_mm` (`[min, max]`, mm) replace
/// the spec's arm search box `machine.l1_mm`, `machine.l3_mm` when given. Without the GIL.
#[pyfunction]
#[pyo3(signature = (spec, text, options, l1_mm, l3_mm))]
fn synthesize(
    py: Python<'_>,
    spec: &str,
    text: Option<&str>,
    options: DesignArgs,
    l1_mm: Option<[f64; 2]>,
    l3_mm: Option<[f64; 2]>,
) -> PyResult<(Report, DesignHandle)> {
    let mut s = spec_of(spec, text)?;
    s.machine.l1_mm = l1_mm.or(s.machine.l1_mm);
    s.machine.l3_mm = l3_mm.or(s.machine.l3_mm);
    let o = options.options()?;
    let r = py
        .detach(|| ncgear::synthesis::synthesize(&s, &o))
        .map_err(|e| errors::arg_err("spec", spec, e))?;
    Ok((report(&r.report)?, DesignHandle { d: r.design }))
}

/// The arm search box `(l1_mm, l3_mm)`, each `[min, max]` mm, of the spec file `spec` (or the
/// dict whose JSON is `text`): its `machine.l1_mm`, `machine.l3_mm`, else the defaults (a study
/// moves the upper edges).
#[pyfunction]
#[pyo3(signature = (spec, text))]
fn spec_box(spec: &str, text: Option<&str>) -> PyResult<([f64; 2], [f64; 2])> {
    use ncgear::synthesis::targets::{DEFAULT_L1_MM, DEFAULT_L3_MM};
    let m = spec_of(spec, text)?.machine;
    Ok((
        m.l1_mm.unwrap_or(DEFAULT_L1_MM),
        m.l3_mm.unwrap_or(DEFAULT_L3_MM),
    ))
}

/// `ncgear tradeoff TRAJ` in-process: `tradeoff.json` of the target (`points` or `path`) about
/// the carrier axis `center` (mm). Without the GIL.
#[pyfunction]
#[pyo3(signature = (points, path, center))]
fn tradeoff(
    py: Python<'_>,
    points: Option<PyReadonlyArray2<'_, f64>>,
    path: Option<&str>,
    center: (f64, f64),
) -> PyResult<Report> {
    let t = trajectory(points, path)?;
    let o = ncgear::design::DesignOptions::default().with_center_mm(center.into());
    o.validate().map_err(|e| design_err(&e))?;
    let progress = ncgear::progress::Progress::none();
    let r = py
        .detach(|| ncgear::design::tradeoff::trade_off(&t, &o, &progress))
        .map_err(|e| design_err(&e))?;
    report(&r)
}

/// The design of a target (`points` or `path`) re-designed from an earlier design: the handle
/// `start`, or the `design.json` text `start_json` (the warm start of the edit loop,
/// [`ncgear::design::redesign`]). Without the GIL.
#[pyfunction]
#[pyo3(signature = (points, path, start, start_json, options))]
fn redesign(
    py: Python<'_>,
    points: Option<PyReadonlyArray2<'_, f64>>,
    path: Option<&str>,
    start: Option<&DesignHandle>,
    start_json: Option<&str>,
    options: DesignArgs,
) -> PyResult<DesignHandle> {
    let t = trajectory(points, path)?;
    let o = options.options()?;
    let parsed;
    let start = match (start, start_json) {
        (Some(h), _) => &h.d.report,
        (None, Some(text)) => {
            parsed = serde_json::from_str::<ncgear::design::DesignReport>(text).map_err(|e| {
                errors::arg_err("start", "design.json", format!("not a design report: {e}"))
            })?;
            &parsed
        }
        (None, None) => {
            return Err(err(
                "start: give an ncgear.Design or the path of a design.json",
            ));
        }
    };
    let d = py
        .detach(|| ncgear::design::redesign(&t, &o, start))
        .map_err(|e| design_err(&e))?;
    Ok(DesignHandle { d })
}

/// Memory a single computation may estimate for itself before it is refused, GB (the CLI's
/// `--max-memory-gb`; default 4).
#[pyfunction]
fn set_max_memory_gb(gb: f64) -> PyResult<()> {
    if !(gb.is_finite() && gb > 0.0) {
        return Err(errors::arg_err("gb", gb, "a positive number of GB"));
    }
    ncgear::bounds::set_memory_ceiling_bytes((gb * 1e9) as u64);
    Ok(())
}

#[pymodule]
fn _ncgear(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("NcgearError", m.py().get_type::<NcgearError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    // The arm box a targets-only synthesis searches when its spec gives none, mm.
    let [a, b] = ncgear::synthesis::targets::DEFAULT_L1_MM;
    m.add("DEFAULT_L1_MM", (a, b))?;
    let [a, b] = ncgear::synthesis::targets::DEFAULT_L3_MM;
    m.add("DEFAULT_L3_MM", (a, b))?;
    m.add_class::<Report>()?;
    m.add_class::<DesignHandle>()?;
    m.add_class::<TrainHandle>()?;
    m.add_class::<PairHandle>()?;
    for f in [
        wrap_pyfunction!(read_trajectory, m)?,
        wrap_pyfunction!(design, m)?,
        wrap_pyfunction!(design_sized, m)?,
        wrap_pyfunction!(teeth, m)?,
        wrap_pyfunction!(pair, m)?,
        wrap_pyfunction!(simulate, m)?,
        wrap_pyfunction!(forward_for_spacing, m)?,
        wrap_pyfunction!(tolerance, m)?,
        wrap_pyfunction!(loads, m)?,
        wrap_pyfunction!(loads_file, m)?,
        wrap_pyfunction!(dynamics, m)?,
        wrap_pyfunction!(dynamics_file, m)?,
        wrap_pyfunction!(compare, m)?,
        wrap_pyfunction!(synthesize, m)?,
        wrap_pyfunction!(spec_box, m)?,
        wrap_pyfunction!(tradeoff, m)?,
        wrap_pyfunction!(redesign, m)?,
        wrap_pyfunction!(set_max_memory_gb, m)?,
    ] {
        m.add_function(f)?;
    }
    Ok(())
}
