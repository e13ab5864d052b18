//! `ncgear orbit`: floating sun-gear orbit under planet eccentricity (spec A). Thin shell over
//! `ncgear::analysis::orbit`.
use super::{CliResult, input_error, print_json, runtime_error};
use ncgear::analysis::orbit::identify::identify;
use ncgear::analysis::orbit::measure::{
    Comparison, Extractor, Frame, Measurement, Method, Record, full_spectrum,
};
use ncgear::analysis::orbit::model::{
    GearSpeeds, Line, LineKind, ModelParams, PlanetSet, rpm_to_rad_s,
};
use ncgear::analysis::orbit::{C64, Ellipse, Orbit, OrbitError};
use ncgear::output::plot::{ChartLabels, Series, line_chart};
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

/// Arguments of `ncgear orbit`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(subcommand)]
    command: Sub,
}

#[derive(Debug, clap::Subcommand)]
enum Sub {
    /// Kinematic model: planet eccentricities → sun orbit, ellipse, whirl, common mode (A.3–A.6).
    Model {
        /// Parameter file (TOML or JSON), see docs/orbit.md.
        params: PathBuf,
        /// Machine-readable output on stdout.
        #[arg(long)]
        json: bool,
        /// Write the model orbit plot (SVG, or PNG by extension).
        #[arg(long)]
        plot: Option<PathBuf>,
    },
    /// Evaluate a sensor record (t_s, x_um, y_um[, carrier_deg]) at the planet frequency (A.7–A.8).
    Measure {
        /// Sensor CSV.
        signals: PathBuf,
        #[command(flatten)]
        opts: MeasureOpts,
        /// Machine-readable output on stdout.
        #[arg(long)]
        json: bool,
        /// Directory for orbit.svg and spectrum.svg.
        #[arg(long)]
        plot_dir: Option<PathBuf>,
        /// Write the plots as PNG instead of SVG.
        #[arg(long)]
        png: bool,
    },
    /// Planet eccentricity phasors from a measured orbit, up to the unobservable common mode (A.9).
    Identify {
        /// Sensor CSV to evaluate (alternative to --sin-pair).
        #[arg(long, conflicts_with = "sin_pair")]
        signals: Option<PathBuf>,
        /// Measured orbit as A_sx_um,phi_sx_deg,A_sy_um,phi_sy_deg (carrier frame).
        #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
        sin_pair: Option<Vec<f64>>,
        /// Transmission-error (common-mode displacement) channel at ω_p: amplitude µm, phase deg.
        #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
        te: Option<Vec<f64>>,
        #[command(flatten)]
        opts: MeasureOpts,
        /// Machine-readable output on stdout.
        #[arg(long)]
        json: bool,
    },
}

#[derive(Debug, clap::Args)]
struct MeasureOpts {
    /// Model parameter file: gives ω_p (and the expected lines when it has [gears]) and the comparison.
    #[arg(long)]
    model: Option<PathBuf>,
    /// Signed planet speed relative to the carrier, rpm (when no --model).
    #[arg(long, allow_negative_numbers = true)]
    planet_speed_rpm: Option<f64>,
    /// Sensor frame: carrier (or carrier held), derotate (housing sensors + carrier_deg column),
    /// housing (housing sensors, constant --carrier-speed-rpm, full spectrum).
    #[arg(long, default_value = "carrier")]
    frame: FrameArg,
    /// Signed carrier speed, rpm (frame = housing; taken from [gears] of --model if absent).
    #[arg(long, allow_negative_numbers = true)]
    carrier_speed_rpm: Option<f64>,
    /// Estimator.
    #[arg(long, default_value = "ls")]
    method: MethodArg,
    /// Extra nuisance line, signed Hz in the analysis frame (repeatable).
    #[arg(long = "line-hz", allow_negative_numbers = true)]
    line_hz: Vec<f64>,
    /// Mesh harmonics added as nuisance lines when --model has [gears].
    #[arg(long, default_value_t = 2)]
    mesh_harmonics: u32,
    /// Remove only the mean, not a linear drift.
    #[arg(long)]
    no_drift: bool,
    /// Treat ω_p as approximate: estimate it from the record (interpolated Hann spectrum within
    /// ±10 %, then least-squares refinement) and extract there.
    #[arg(long)]
    estimate_frequency: bool,
    /// Refuse the least-squares fit above this condition number.
    #[arg(long, default_value_t = 1e6)]
    max_condition: f64,
}

#[derive(Debug, Clone, Copy, clap::ValueEnum)]
enum FrameArg {
    Carrier,
    Derotate,
    Housing,
}

#[derive(Debug, Clone, Copy, clap::ValueEnum)]
enum MethodArg {
    Ls,
    Hann,
    Sync,
    Fft,
}

/// Runs `ncgear orbit`.
pub fn run(args: Args) -> CliResult {
    match args.command {
        Sub::Model { params, json, plot } => model(&params, json, plot.as_deref()),
        Sub::Measure {
            signals,
            opts,
            json,
            plot_dir,
            png,
        } => measure(&signals, &opts, json, plot_dir.as_deref(), png),
        Sub::Identify {
            signals,
            sin_pair,
            te,
            opts,
            json,
        } => identify_cmd(
            signals.as_deref(),
            sin_pair.as_deref(),
            te.as_deref(),
            &opts,
            json,
        ),
    }
}

fn load_model(path: &Path) -> Result<(ModelParams, PlanetSet), super::Failure> {
    let p = ModelParams::from_path(path).map_err(input_error)?;
    let set = p.planet_set().map_err(|e| input_error(located(path, e)))?;
    Ok((p, set))
}

fn located(path: &Path, e: OrbitError) -> miette::Report {
    miette::miette!("{}: {e}", path.display())
}

fn c_json(z: C64) -> Value {
    json!({"re": z.re, "im": z.im, "abs": z.norm(), "arg_rad": z.arg()})
}

fn orbit_json(o: &Orbit) -> Value {
    let s = o.sin_pair();
    let e = o.ellipse();
    json!({
        "omega_p_rad_s": o.omega_p_rad_s,
        "a_sx_um": s.a_x_um, "phi_sx_rad": s.phi_x_rad, "a_sy_um": s.a_y_um, "phi_sy_rad": s.phi_y_rad,
        "z_plus_um": c_json(o.z_plus_um), "z_minus_um": c_json(o.z_minus_um),
        "ellipse": ellipse_json(&e),
    })
}

fn ellipse_json(e: &Ellipse) -> Value {
    json!({
        "r_long_um": e.r_long_um, "r_short_um": e.r_short_um,
        "alpha_long_rad": e.alpha_long_rad, "alpha_long_deg": e.alpha_long_rad.map(f64::to_degrees),
        "whirl": e.whirl, "counter_clockwise": e.counter_clockwise,
    })
}

fn print_orbit(o: &Orbit) {
    let s = o.sin_pair();
    let e = o.ellipse();
    println!(
        "  x_s = {:.6} µm · sin(ω_p t {:+.6} rad)",
        s.a_x_um, s.phi_x_rad
    );
    println!(
        "  y_s = {:.6} µm · sin(ω_p t {:+.6} rad)",
        s.a_y_um, s.phi_y_rad
    );
    println!(
        "  |Z+| = {:.6} µm, |Z-| = {:.6} µm",
        o.z_plus_um.norm(),
        o.z_minus_um.norm()
    );
    println!(
        "  ellipse: R_L = {:.6} µm, R_S = {:.6} µm, α_L = {}",
        e.r_long_um,
        e.r_short_um,
        e.alpha_long_rad
            .map_or("undefined (circle)".into(), |a| format!(
                "{:.6} rad ({:.4}°)",
                a,
                a.to_degrees()
            ))
    );
    let sense = match e.counter_clockwise {
        Some(true) => "counter-clockwise",
        Some(false) => "clockwise",
        None => "none (straight line)",
    };
    println!(
        "  whirl: {:?} relative to ω_p; physical sense in the carrier frame: {sense}",
        e.whirl
    );
}

fn model(path: &Path, json: bool, plot: Option<&Path>) -> CliResult {
    let (p, set) = load_model(path)?;
    let sol = set.solve();
    let speeds = p.gear_speeds().map_err(input_error)?;
    if let Some(plot) = plot {
        let o = sol.orbit;
        let trace = o.trace_um(720);
        let mut series = vec![Series::line("sun orbit (carrier frame)", trace)];
        series.push(Series::line("major axis", axis_points(&o)));
        line_chart(
            plot,
            &ChartLabels {
                title: "Sun orbit, kinematic model".into(),
                x: "x_s [µm]".into(),
                y: "y_s [µm]".into(),
                equal_aspect: true,
            },
            &series,
            (800, 800),
        )
        .map_err(|e| runtime_error(miette::miette!("{e}")))?;
    }
    let common = sol.common_mode_um;
    if json {
        return print_json(&json!({
            "orbit": orbit_json(&sol.orbit),
            "common_mode_um": {"amplitude_um": common.norm(), "phase_rad": common.arg()},
            "load_independent": sol.load_independent,
            "gear_speeds": speeds,
            "line_of_action_angles_rad": set.line_of_action_angles_rad(),
        }));
    }
    println!(
        "Sun orbit (carrier frame, planet frequency ω_p = {:.6} rad/s):",
        set.omega_p_rad_s()
    );
    print_orbit(&sol.orbit);
    println!(
        "  common mode (transmission error along the lines of action): c = {:.6} µm · sin(ω_p t {:+.6} rad)",
        common.norm(),
        common.arg()
    );
    if !sol.load_independent {
        println!(
            "  note: planets not equally spaced — the kinematic (least-squares) solution is not load independent; use a stiffness model"
        );
    }
    if let Some(g) = speeds {
        println!(
            "  speeds [rad/s]: sun {:.6}, carrier {:.6}, planet rel. carrier {:.6}, sun rel. carrier {:.6}, mesh {:.6}",
            g.sun_rad_s, g.carrier_rad_s, g.planet_rad_s, g.sun_relative_rad_s, g.mesh_rad_s
        );
    }
    Ok(())
}

/// Major-axis segment of an orbit (empty for a circle).
fn axis_points(o: &Orbit) -> Vec<(f64, f64)> {
    let e = o.ellipse();
    e.alpha_long_rad.map_or_else(Vec::new, |a| {
        let (s, c) = a.sin_cos();
        vec![
            (-e.r_long_um * c, -e.r_long_um * s),
            (e.r_long_um * c, e.r_long_um * s),
        ]
    })
}

struct Setup {
    extractor: Extractor,
    estimate: bool,
    model: Option<(ModelParams, PlanetSet)>,
}

fn setup(o: &MeasureOpts) -> Result<Setup, super::Failure> {
    let model = o.model.as_deref().map(load_model).transpose()?;
    let speeds: Option<GearSpeeds> = match &model {
        Some((p, _)) => p.gear_speeds().map_err(input_error)?,
        None => None,
    };
    let omega_p = match (&model, o.planet_speed_rpm) {
        (Some(_), Some(_)) => {
            return Err(input_error(miette::miette!(
                "give --model or --planet-speed-rpm, not both"
            )));
        }
        (Some((_, set)), None) => set.omega_p_rad_s(),
        (None, Some(rpm)) => rpm_to_rad_s(rpm),
        (None, None) => {
            return Err(input_error(miette::miette!(
                "need --model PARAMS or --planet-speed-rpm RPM"
            )));
        }
    };
    let frame = match o.frame {
        FrameArg::Carrier => Frame::Carrier,
        FrameArg::Derotate => Frame::HousingDerotate,
        FrameArg::Housing => {
            let wc = match (o.carrier_speed_rpm, speeds) {
                (Some(rpm), _) => rpm_to_rad_s(rpm),
                (None, Some(g)) => g.carrier_rad_s,
                (None, None) => {
                    return Err(input_error(miette::miette!(
                        "--frame housing needs --carrier-speed-rpm or [gears] in --model"
                    )));
                }
            };
            Frame::HousingFullSpectrum { carrier_rad_s: wc }
        }
    };
    let mut lines: Vec<Line> = speeds
        .map(|g| {
            g.expected_lines(
                matches!(frame, Frame::HousingFullSpectrum { .. }),
                o.mesh_harmonics,
            )
        })
        .unwrap_or_default();
    lines.extend(o.line_hz.iter().map(|f| {
        Line::new(
            format!("user {f} Hz"),
            f * std::f64::consts::TAU,
            LineKind::Nuisance,
        )
    }));
    let method = match o.method {
        MethodArg::Ls => Method::LeastSquares,
        MethodArg::Hann => Method::HannDtft,
        MethodArg::Sync => Method::Synchronous,
        MethodArg::Fft => Method::PlainFft,
    };
    let extractor = Extractor::builder(omega_p)
        .frame(frame)
        .method(method)
        .drift(!o.no_drift)
        .nuisance(lines)
        .max_condition(o.max_condition)
        .build()
        .map_err(input_error)?;
    Ok(Setup {
        extractor,
        estimate: o.estimate_frequency,
        model,
    })
}

fn run_measure(path: &Path, s: &mut Setup) -> Result<(Record, Measurement), super::Failure> {
    let rec = Record::from_csv_path(path).map_err(input_error)?;
    if s.estimate {
        let w = s.extractor.omega_p_rad_s();
        let tol = 1e-10 * w.abs();
        let pb = super::progress_bar(
            Extractor::frequency_iterations(rec.duration_s(), tol),
            "ω_p refine",
        );
        let est = s
            .extractor
            .estimate_frequency(&rec, 0.1, tol, &|k| pb.set_position(k))
            .map_err(input_error)?;
        pb.finish_and_clear();
        s.extractor = s
            .extractor
            .with_omega_p(est.refined_rad_s)
            .map_err(input_error)?;
    }
    let m = s.extractor.extract(&rec).map_err(|e| match e {
        OrbitError::Collision { .. } | OrbitError::Record(_) => input_error(located(path, e)),
        other => runtime_error(other),
    })?;
    Ok((rec, m))
}

fn measurement_json(m: &Measurement, s: &Setup) -> Value {
    let cmp = s
        .model
        .as_ref()
        .map(|(_, set)| Comparison::new(&m.orbit, &set.solve().orbit));
    json!({
        "method": s.extractor.method(),
        "frame": s.extractor.frame(),
        "orbit": orbit_json(&m.orbit),
        "uncertainty_1sigma": m.uncertainty,
        "condition_number": m.condition_number,
        "residual_rms_um": m.residual_rms_um.map(|(x, y)| json!({"x": x, "y": y})),
        "lines": m.lines,
        "warnings": m.warnings,
        "omega_p_rad_s": s.extractor.omega_p_rad_s(),
        "frequency_estimated": s.estimate,
        "record_length_s": m.record_length_s,
        "samples": m.samples,
        "comparison_with_model": cmp,
    })
}

fn measure(
    path: &Path,
    o: &MeasureOpts,
    json: bool,
    plot_dir: Option<&Path>,
    png: bool,
) -> CliResult {
    let mut s = setup(o)?;
    let (rec, m) = run_measure(path, &mut s)?;
    if let Some(dir) = plot_dir {
        plots(dir, &rec, &m, &s, if png { "png" } else { "svg" })?;
    }
    if json {
        return print_json(&measurement_json(&m, &s));
    }
    println!(
        "Record: {} samples over {:.6} s; method {:?}, frame {:?}",
        m.samples,
        m.record_length_s,
        s.extractor.method(),
        s.extractor.frame()
    );
    print_orbit(&m.orbit);
    if let Some(u) = m.uncertainty {
        println!(
            "  1-σ: A_sx ±{:.4} µm, φ_sx ±{:.5} rad, A_sy ±{:.4} µm, φ_sy ±{:.5} rad, |Z+| ±{:.4} µm, |Z-| ±{:.4} µm",
            u.a_x_um, u.phi_x_rad, u.a_y_um, u.phi_y_rad, u.z_plus_um, u.z_minus_um
        );
    }
    if let Some(c) = m.condition_number {
        println!("  condition number {c:.3e}");
    }
    if let Some((x, y)) = m.residual_rms_um {
        println!("  residual RMS x {x:.4} µm, y {y:.4} µm");
    }
    for w in &m.warnings {
        println!("  warning: {w}");
    }
    if let Some((_, set)) = &s.model {
        let c = Comparison::new(&m.orbit, &set.solve().orbit);
        println!(
            "  vs model: ΔR_L {:+.4} µm, ΔR_S {:+.4} µm, Δα_L {}, |ΔZ+| {:.4} µm, |ΔZ-| {:.4} µm",
            c.d_r_long_um,
            c.d_r_short_um,
            c.d_alpha_long_rad
                .map_or("n/a".into(), |a| format!("{:+.5} rad", a)),
            c.d_z_plus_um,
            c.d_z_minus_um
        );
    }
    Ok(())
}

fn plots(dir: &Path, rec: &Record, m: &Measurement, s: &Setup, ext: &str) -> CliResult {
    std::fs::create_dir_all(dir)
        .map_err(|e| runtime_error(miette::miette!("{}: {e}", dir.display())))?;
    let (x, y) = s.extractor.analysis_signal(rec).map_err(input_error)?;
    let step = (x.len() / 4000).max(1);
    let raw: Vec<(f64, f64)> = x
        .iter()
        .zip(&y)
        .step_by(step)
        .map(|(a, b)| (*a, *b))
        .collect();
    let mut series = vec![
        Series::markers("raw (detrended)", raw),
        Series::line("filtered orbit / ellipse", m.orbit.trace_um(720)),
    ];
    let axis = axis_points(&m.orbit);
    if !axis.is_empty() {
        series.push(Series::line("major axis", axis));
    }
    if let Some((_, set)) = &s.model {
        series.push(Series::line("model", set.solve().orbit.trace_um(720)));
    }
    let labels = ChartLabels {
        title: "Sun orbit".into(),
        x: "x [µm]".into(),
        y: "y [µm]".into(),
        equal_aspect: true,
    };
    line_chart(
        &dir.join(format!("orbit.{ext}")),
        &labels,
        &series,
        (800, 800),
    )
    .map_err(|e| runtime_error(miette::miette!("{e}")))?;
    if rec.is_uniform(1e-6) {
        let fmax = 1.5
            * m.lines
                .iter()
                .map(|l| l.omega_rad_s.abs())
                .fold(0.0, f64::max)
            / std::f64::consts::TAU;
        let spec: Vec<(f64, f64)> = full_spectrum(rec.mean_step_s(), &x, &y)
            .into_iter()
            .filter(|p| p.0.abs() <= fmax)
            .collect();
        let mut series = vec![Series::line("|Z(f)| (Hann, analysis frame)", spec)];
        for l in m.lines.iter().filter(|l| l.kind == LineKind::Planet) {
            let f = l.omega_rad_s / std::f64::consts::TAU;
            let a = if l.label.ends_with('+') {
                m.orbit.z_plus_um.norm()
            } else {
                m.orbit.z_minus_um.norm()
            };
            series.push(Series::markers(format!("{} (fit)", l.label), vec![(f, a)]));
        }
        let labels = ChartLabels {
            title: "Full spectrum of x + iy (forward f > 0, backward f < 0)".into(),
            x: "signed frequency [Hz]".into(),
            y: "amplitude [µm]".into(),
            equal_aspect: false,
        };
        line_chart(
            &dir.join(format!("spectrum.{ext}")),
            &labels,
            &series,
            (1000, 600),
        )
        .map_err(|e| runtime_error(miette::miette!("{e}")))?;
    }
    Ok(())
}

fn identify_cmd(
    signals: Option<&Path>,
    sin_pair: Option<&[f64]>,
    te: Option<&[f64]>,
    o: &MeasureOpts,
    json: bool,
) -> CliResult {
    if sin_pair.is_some_and(|v| v.len() != 4) {
        return Err(input_error(miette::miette!(
            "--sin-pair expects 4 comma-separated numbers: A_sx_um,phi_sx_deg,A_sy_um,phi_sy_deg"
        )));
    }
    if te.is_some_and(|v| v.len() != 2) {
        return Err(input_error(miette::miette!(
            "--te expects 2 comma-separated numbers: amplitude_um,phase_deg"
        )));
    }
    let mut s = setup(o)?;
    let Some((_, set)) = s.model.clone() else {
        return Err(input_error(miette::miette!(
            "identify needs --model PARAMS (planet positions, α, sense, ω_p)"
        )));
    };
    let orbit = match (signals, sin_pair) {
        (Some(path), _) => {
            // With --estimate-frequency the phasors were taken at the estimated ω_p; the model's
            // map is linear in them, so identify them against the nominal ω_p.
            let o = run_measure(path, &mut s)?.1.orbit;
            Orbit {
                omega_p_rad_s: set.omega_p_rad_s(),
                ..o
            }
        }
        (None, Some(v)) => {
            let sp = ncgear::analysis::orbit::SinPair {
                a_x_um: v[0],
                phi_x_rad: v[1].to_radians(),
                a_y_um: v[2],
                phi_y_rad: v[3].to_radians(),
            };
            Orbit::from_sin_pair(set.omega_p_rad_s(), &sp)
        }
        (None, None) => {
            return Err(input_error(miette::miette!(
                "give --signals CSV or --sin-pair A_x,phi_x_deg,A_y,phi_y_deg"
            )));
        }
    };
    let te = te.map(|v| C64::from_polar(v[0], v[1].to_radians()));
    let id = identify(&set.kinematic_map(), &orbit, te).map_err(input_error)?;
    if json {
        let planets: Vec<Value> = id
            .phasors_um
            .iter()
            .map(|e| json!({"eccentricity_um": e.norm(), "phase_rad": e.arg(), "phase_deg": e.arg().to_degrees()}))
            .collect();
        return print_json(&json!({
            "planets": planets,
            "null_space": id.null_space,
            "common_mode_observable": id.null_space.is_empty(),
            "used_transmission_error": id.used_transmission_error,
            "statement": id.statement,
            "orbit": orbit_json(&orbit),
        }));
    }
    println!("Identified planet eccentricity phasors E_i = e_i·exp(i(θp0+θp_i)):");
    for (k, e) in id.phasors_um.iter().enumerate() {
        println!(
            "  planet {}: e = {:.6} µm, phase = {:+.4}°",
            k + 1,
            e.norm(),
            e.arg().to_degrees()
        );
    }
    println!("{}", id.statement);
    Ok(())
}
