//! `ncgear orbit`: floating sun-gear orbit under planet eccentricity (docs/math/companion.md §A). Thin shell over
//! `ncgear::analysis::orbit`.
use super::{CliResult, input_error, print_json, runtime_error};
use ncgear::analysis::orbit::evaluate::{Evaluation, MeasureOptions, SensorFrame};
use ncgear::analysis::orbit::measure::{Measurement, Method, Record};
use ncgear::analysis::orbit::model::ModelParams;
use ncgear::analysis::orbit::report::{IdentifyReport, MeasureReport, ModelReport, OrbitSummary};
use ncgear::analysis::orbit::{C64, Orbit, OrbitError, SinPair};
use ncgear::output::{OutputError, PlotFormat};
use std::path::{Path, PathBuf};

/// Arguments of `ncgear orbit`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(subcommand)]
    command: Sub,
}

#[derive(Debug, clap::Subcommand)]
enum Sub {
    /// Kinematic model: planet eccentricities → sun orbit, ellipse, whirl, common mode (docs/math/companion.md §A.3–§A.6).
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
    /// Evaluate a sensor record (t_s, x_um, y_um[, carrier_deg]) at the planet frequency (docs/math/companion.md §A.7–§A.8).
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
    /// Planet eccentricity phasors from a measured orbit, up to the unobservable common mode (docs/math/companion.md §A.9).
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

/// Reads a model parameter file and checks that it gives a valid planet set.
fn load_params(path: &Path) -> Result<ModelParams, super::Failure> {
    let p = ModelParams::from_path(path).map_err(input_error)?;
    p.planet_set().map_err(|e| input_error(located(path, e)))?;
    Ok(p)
}

fn located(path: &Path, e: OrbitError) -> miette::Report {
    miette::miette!("{}: {e}", path.display())
}

/// The library names fields; this adds, as help, the flag that sets the field.
fn with_flag_help(e: OrbitError) -> miette::Report {
    let help = match &e {
        OrbitError::Invalid { key, .. } => match key.as_str() {
            "planet_speed_rpm" => "give --model PARAMS or --planet-speed-rpm RPM, not both",
            "carrier_speed_rpm" => {
                "--frame housing needs --carrier-speed-rpm or [gears] in --model"
            }
            "planet_speed" => "check --planet-speed-rpm or the speeds in --model",
            "carrier_speed" => "check --carrier-speed-rpm or [gears] in --model",
            "method" => "--method sync needs --frame carrier or --frame derotate",
            "max_condition" => "check --max-condition",
            k if k.starts_with("line ") => "check --line-hz",
            _ => return miette::Report::new(e),
        },
        _ => return miette::Report::new(e),
    };
    miette::miette!(help = help, "{e}")
}

/// Prints a report as JSON. Through `serde_json::Value`, whose objects keep their keys sorted:
/// the layout `--json` has always printed.
fn print_report(report: &impl serde::Serialize) -> CliResult {
    let v = serde_json::to_value(report).map_err(|e| runtime_error(miette::miette!("{e}")))?;
    print_json(&v)
}

fn print_orbit(o: &OrbitSummary) {
    let e = &o.ellipse;
    println!(
        "  x_s = {:.6} µm · sin(ω_p t {:+.6} rad)",
        o.a_sx_um, o.phi_sx_rad
    );
    println!(
        "  y_s = {:.6} µm · sin(ω_p t {:+.6} rad)",
        o.a_sy_um, o.phi_sy_rad
    );
    println!(
        "  |Z+| = {:.6} µm, |Z-| = {:.6} µm",
        o.z_plus_um.abs, o.z_minus_um.abs
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
    let p = load_params(path)?;
    let r = ModelReport::new(&p).map_err(|e| input_error(located(path, e)))?;
    if let Some(plot) = plot {
        ncgear::output::write_orbit_model_plot(&r, plot).map_err(output_failure)?;
    }
    if json {
        return print_report(&r);
    }
    println!(
        "Sun orbit (carrier frame, planet frequency ω_p = {:.6} rad/s):",
        r.orbit.omega_p_rad_s
    );
    print_orbit(&r.orbit);
    let common = r.common_mode_um;
    println!(
        "  common mode (transmission error along the lines of action): c = {:.6} µm · sin(ω_p t {:+.6} rad)",
        common.amplitude_um, common.phase_rad
    );
    if !r.load_independent {
        println!(
            "  note: planets not equally spaced — the kinematic (least-squares) solution is not load independent; use a stiffness model"
        );
    }
    if let Some(g) = r.gear_speeds {
        println!(
            "  speeds [rad/s]: sun {:.6}, carrier {:.6}, planet rel. carrier {:.6}, sun rel. carrier {:.6}, mesh {:.6}",
            g.sun_rad_s, g.carrier_rad_s, g.planet_rad_s, g.sun_relative_rad_s, g.mesh_rad_s
        );
    }
    Ok(())
}

/// The evaluation the flags describe.
fn evaluation(o: &MeasureOpts) -> Result<Evaluation, super::Failure> {
    let model = o.model.as_deref().map(load_params).transpose()?;
    let frame = match o.frame {
        FrameArg::Carrier => SensorFrame::Carrier,
        FrameArg::Derotate => SensorFrame::Derotate,
        FrameArg::Housing => SensorFrame::Housing,
    };
    let method = match o.method {
        MethodArg::Ls => Method::LeastSquares,
        MethodArg::Hann => Method::HannDtft,
        MethodArg::Sync => Method::Synchronous,
        MethodArg::Fft => Method::PlainFft,
    };
    let opts = MeasureOptions::default()
        .with_planet_speed_rpm(o.planet_speed_rpm)
        .with_frame(frame)
        .with_carrier_speed_rpm(o.carrier_speed_rpm)
        .with_method(method)
        .with_line_hz(o.line_hz.clone())
        .with_mesh_harmonics(o.mesh_harmonics)
        .with_drift(!o.no_drift)
        .with_estimate_frequency(o.estimate_frequency)
        .with_max_condition(o.max_condition);
    Evaluation::new(model.as_ref(), &opts).map_err(|e| input_error(with_flag_help(e)))
}

fn run_measure(path: &Path, ev: &mut Evaluation) -> Result<(Record, Measurement), super::Failure> {
    let rec = Record::from_path(path).map_err(input_error)?;
    if ev.estimates_frequency() {
        let pb = super::progress_bar(ev.refine_iterations(&rec), "ω_p refine");
        ev.refine_frequency(&rec, &super::bar_sink(&pb))
            .map_err(input_error)?;
        pb.finish_and_clear();
    }
    let m = ev.extract(&rec).map_err(|e| match e {
        OrbitError::Collision { .. } | OrbitError::Record(_) => input_error(located(path, e)),
        other => runtime_error(other),
    })?;
    Ok((rec, m))
}

fn measure(
    path: &Path,
    o: &MeasureOpts,
    json: bool,
    plot_dir: Option<&Path>,
    png: bool,
) -> CliResult {
    let mut ev = evaluation(o)?;
    let (rec, m) = run_measure(path, &mut ev)?;
    if let Some(dir) = plot_dir {
        let format = if png {
            PlotFormat::Png
        } else {
            PlotFormat::Svg
        };
        ncgear::output::write_orbit_measure_plots(dir, &rec, &m, &ev, format)
            .map_err(output_failure)?;
    }
    let r: MeasureReport = ev.report(&m);
    if json {
        return print_report(&r);
    }
    println!(
        "Record: {} samples over {:.6} s; method {:?}, frame {:?}",
        r.samples, r.record_length_s, r.method, r.frame
    );
    print_orbit(&r.orbit);
    if let Some(u) = r.uncertainty_1sigma {
        println!(
            "  1-σ: A_sx ±{:.4} µm, φ_sx ±{:.5} rad, A_sy ±{:.4} µm, φ_sy ±{:.5} rad, |Z+| ±{:.4} µm, |Z-| ±{:.4} µm",
            u.a_x_um, u.phi_x_rad, u.a_y_um, u.phi_y_rad, u.z_plus_um, u.z_minus_um
        );
    }
    if let Some(c) = r.condition_number {
        println!("  condition number {c:.3e}");
    }
    if let Some(rms) = r.residual_rms_um {
        println!("  residual RMS x {:.4} µm, y {:.4} µm", rms.x, rms.y);
    }
    for w in &r.warnings {
        println!("  warning: {w}");
    }
    if let Some(c) = r.comparison_with_model {
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

/// The CLI failure of an output error: the record's own (an input error), or a file that could
/// not be written.
fn output_failure(e: OutputError) -> super::Failure {
    match e {
        OutputError::Orbit(e) => input_error(e),
        e => runtime_error(miette::miette!("{e}")),
    }
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
    let mut ev = evaluation(o)?;
    let Some(set) = ev.model().cloned() else {
        return Err(input_error(miette::miette!(
            "identify needs --model PARAMS (planet positions, α, sense, ω_p)"
        )));
    };
    let orbit = match (signals, sin_pair) {
        // With --estimate-frequency the phasors are taken at the estimated ω_p; the report
        // identifies them against the model's.
        (Some(path), _) => run_measure(path, &mut ev)?.1.orbit,
        (None, Some(v)) => {
            let sp = SinPair {
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
    let r = IdentifyReport::new(&set, &orbit, te).map_err(input_error)?;
    if json {
        return print_report(&r);
    }
    println!("Identified planet eccentricity phasors E_i = e_i·exp(i(θp0+θp_i)):");
    for (k, p) in r.planets.iter().enumerate() {
        println!(
            "  planet {}: e = {:.6} µm, phase = {:+.4}°",
            k + 1,
            p.eccentricity_um,
            p.phase_deg
        );
    }
    println!("{}", r.statement);
    Ok(())
}
