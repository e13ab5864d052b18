//! `ncgear dynamics`: thin shell over `ncgear::analysis::dynamics`.
use super::{CliResult, input_error, print_json, progress_bar, runtime_error};
use ncgear::analysis::dynamics::{self as dy, DynamicsError, RunOptions, Scene};
use ncgear::output::plot::{ChartLabels, Series, line_chart};
use std::path::{Path, PathBuf};

/// Arguments of `ncgear dynamics`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Scene file (.toml or .json).
    pub scene: PathBuf,
    /// Output directory for CSV files and plots.
    #[arg(long, default_value = "dynamics_out")]
    pub out: PathBuf,
    /// Frequency sweep over Ω = ωe/ωn as START:END:STEP, run up and then down.
    #[arg(long)]
    pub sweep: Option<String>,
    /// Plot format: svg or png.
    #[arg(long, default_value = "svg")]
    pub format: String,
    /// Print a machine-readable summary to stdout.
    #[arg(long)]
    pub json: bool,
}

fn dyn_err(e: DynamicsError) -> super::Failure {
    match e {
        DynamicsError::Scene(_) | DynamicsError::BadOption { .. } | DynamicsError::NotLinear(_) => {
            input_error(miette::miette!("{e}"))
        }
        _ => runtime_error(miette::miette!("{e}")),
    }
}

fn chart(
    path: &Path,
    title: &str,
    x: &str,
    y: &str,
    series: Vec<Series>,
    equal: bool,
) -> CliResult {
    let labels = ChartLabels {
        title: title.into(),
        x: x.into(),
        y: y.into(),
        equal_aspect: equal,
    };
    line_chart(path, &labels, &series, (900, 600))
        .map_err(|e| runtime_error(miette::miette!("{e}")))
}

fn write_csv(path: &Path, header: &[String], rows: impl Iterator<Item = Vec<f64>>) -> CliResult {
    let err =
        |e: csv::Error| runtime_error(miette::miette!("cannot write {}: {e}", path.display()));
    let mut w = csv::Writer::from_path(path).map_err(err)?;
    w.write_record(header).map_err(err)?;
    for r in rows {
        w.write_record(r.iter().map(|x| format!("{x:.9e}")))
            .map_err(err)?;
    }
    w.flush()
        .map_err(|e| runtime_error(miette::miette!("cannot write {}: {e}", path.display())))
}

fn parse_sweep(s: &str) -> Result<Vec<f64>, super::Failure> {
    let bad = || {
        input_error(miette::miette!(
            "--sweep `{s}`: expected START:END:STEP with 0 < START < END and STEP > 0, e.g. 0.6:1.0:0.02"
        ))
    };
    let p: Vec<f64> = s
        .split(':')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| bad())?;
    let [a, b, h] = p[..] else { return Err(bad()) };
    if !(a > 0.0 && b > a && h > 0.0) || (b - a) / h > 10_000.0 {
        return Err(bad());
    }
    let n = ((b - a) / h + 1e-9).floor() as usize;
    Ok((0..=n).map(|i| a + h * i as f64).collect())
}

/// Runs `ncgear dynamics`.
pub fn run(args: Args) -> CliResult {
    let file = args.scene.display().to_string();
    let scene = Scene::from_path(&args.scene).map_err(|e| input_error(miette::miette!("{e}")))?;
    let (model, derived) = scene
        .build(&file)
        .map_err(|e| input_error(miette::miette!("{e}")))?;
    let opts = RunOptions::from_scene(&scene).map_err(dyn_err)?;
    if !matches!(args.format.as_str(), "svg" | "png") {
        return Err(input_error(miette::miette!(
            "--format `{}`: expected svg or png",
            args.format
        )));
    }
    std::fs::create_dir_all(&args.out)
        .map_err(|e| runtime_error(miette::miette!("cannot create {}: {e}", args.out.display())))?;
    let ext = &args.format;
    let out = |name: &str| args.out.join(name);
    // run log
    let terms: Vec<String> = model.terms.iter().map(|t| t.name()).collect();
    let solver = format!("{:?}", opts.method);
    eprintln!("scene `{}` ({file})", scene.scene.name);
    eprintln!("DOFs ({}): {}", model.n(), model.dof_names().join(", "));
    for t in &terms {
        eprintln!("term: {t}");
    }
    eprintln!(
        "solver: {solver}{}",
        if model.is_linear() {
            " (linear model: eigen-solution and FRF available)"
        } else {
            ""
        }
    );
    let eig = dy::natural_frequencies_hz(&model).ok();
    let mut summary = serde_json::json!({
        "scene": scene.scene.name, "dofs": model.dof_names(), "terms": terms, "solver": solver,
        "derived": derived, "natural_frequencies_hz": eig,
    });
    if let Some(f) = &eig {
        eprintln!(
            "natural frequencies (mean stiffness) [Hz]: {}",
            f.iter()
                .map(|x| format!("{x:.2}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    if scene.solver.method == "linear" || (scene.solver.method == "auto" && model.is_linear()) {
        let amp = dy::linear_dte_amplitude(&model).map_err(dyn_err)?;
        eprintln!(
            "linear fast path: DTE amplitude at the mesh frequency {:.6} µm",
            amp * 1e6
        );
        summary["linear_dte_amplitude_m"] = amp.into();
        if args.json {
            print_json(&summary)?;
        }
        return Ok(());
    }
    if let Some(sw) = &args.sweep {
        let up = parse_sweep(sw)?;
        let down: Vec<f64> = up.iter().rev().copied().collect();
        let pb = progress_bar(2 * up.len() as u64, "sweep");
        let res_up =
            dy::sweep(&scene, &file, &up, &opts, None, &|k| pb.set_position(k)).map_err(dyn_err)?;
        let start = res_up.len() as u64;
        let res_down = dy::sweep(&scene, &file, &down, &opts, None, &|k| {
            pb.set_position(start + k)
        })
        .map_err(dyn_err)?;
        pb.finish_and_clear();
        let b = model.mesh.backlash.map_or(1.0, |b| b.b);
        let pts = |r: &[dy::SweepPoint]| {
            r.iter()
                .map(|p| (p.omega_ratio, p.dte_half_pp_m / b))
                .collect::<Vec<_>>()
        };
        let ylab = if model.mesh.backlash.is_some() {
            "DTE half peak-to-peak / b"
        } else {
            "DTE half peak-to-peak [m]"
        };
        chart(
            &out(&format!("sweep.{ext}")),
            "Frequency sweep (jump phenomenon)",
            "Ω = ωe/ωn",
            ylab,
            vec![
                Series::line("sweep up", pts(&res_up)),
                Series::line("sweep down", pts(&res_down)),
            ],
            false,
        )?;
        let rows = res_up
            .iter()
            .map(|p| (1.0, p))
            .chain(res_down.iter().map(|p| (-1.0, p)));
        write_csv(
            &out("sweep.csv"),
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
        summary["sweep_up"] = serde_json::to_value(&res_up).unwrap_or_default();
        summary["sweep_down"] = serde_json::to_value(&res_down).unwrap_or_default();
        eprintln!("sweep written to {}", out("sweep.csv").display());
        if args.json {
            print_json(&summary)?;
        }
        return Ok(());
    }
    let y0 = dy::static_state(&model, 1e-6);
    let pb = progress_bar(u64::from(opts.max_periods), "transient");
    let run = dy::simulate(&model, &y0, &opts, &|k| pb.set_position(k)).map_err(dyn_err)?;
    pb.finish_and_clear();
    eprintln!(
        "transient {} Poincaré periods ({}), {} RHS evaluations, {} accepted / {} rejected steps, {} events",
        run.transient_periods,
        if run.steady {
            "steady".to_string()
        } else {
            format!("NOT steady, change {:.2e}", run.poincare_change)
        },
        run.stats.rhs_evals,
        run.stats.accepted,
        run.stats.rejected,
        run.stats.events
    );
    // time series
    let mut header = vec!["t_s".to_string(), "dte_m".into(), "mesh_force_n".into()];
    let mut cols = Vec::new();
    for s in &scene.output.signals {
        if s == "dte" || s == "mesh_force" {
            continue;
        }
        let i = model.index_of(s).ok_or_else(|| {
            input_error(miette::miette!(
                "output.signals: `{s}` is not a DOF of this scene; DOFs: {}",
                model.dof_names().join(", ")
            ))
        })?;
        header.push(s.clone());
        cols.push(i);
    }
    write_csv(
        &out("timeseries.csv"),
        &header,
        (0..run.t_s.len()).map(|k| {
            let mut r = vec![run.t_s[k], run.dte_m[k], run.mesh_force_n[k]];
            r.extend(cols.iter().map(|&i| run.states[k][i]));
            r
        }),
    )?;
    let spm = run.samples_per_mesh as usize;
    let show = run.t_s.len().min(10 * spm);
    let t0 = run.t_s[0];
    chart(
        &out(&format!("dte.{ext}")),
        "Dynamic transmission error",
        "t − t_rec [ms]",
        "DTE [µm]",
        vec![Series::line(
            "DTE",
            (0..show)
                .map(|k| ((run.t_s[k] - t0) * 1e3, run.dte_m[k] * 1e6))
                .collect(),
        )],
        false,
    )?;
    chart(
        &out(&format!("mesh_force.{ext}")),
        "Mesh force",
        "t − t_rec [ms]",
        "F_m [N]",
        vec![Series::line(
            "F_m",
            (0..show)
                .map(|k| ((run.t_s[k] - t0) * 1e3, run.mesh_force_n[k]))
                .collect(),
        )],
        false,
    )?;
    // phase plane (spectral derivative over the integer-period record) and Poincaré section
    let t_rec = model.mesh.t0 * f64::from(opts.record_mesh_periods);
    let rate: Vec<f64> = ncgear::math::periodic::spectral_derivative(&run.dte_m)
        .iter()
        .map(|d| d * 2.0 * std::f64::consts::PI / t_rec)
        .collect();
    let phase: Vec<(f64, f64)> = run
        .dte_m
        .iter()
        .zip(&rate)
        .map(|(d, v)| (d * 1e6, v * 1e3))
        .collect();
    let poincare: Vec<(f64, f64)> = phase.iter().step_by(spm).copied().collect();
    chart(
        &out(&format!("phase.{ext}")),
        "Phase plane and Poincaré section (once per mesh period)",
        "DTE [µm]",
        "dDTE/dt [mm/s]",
        vec![
            Series::line("trajectory", phase),
            Series::markers("Poincaré", poincare.clone()),
        ],
        false,
    )?;
    // spectrum
    if scene.output.spectrum {
        let c = ncgear::math::periodic::fft_coefficients(&run.dte_m);
        let df = 1.0 / t_rec;
        let spectrum = c
            .iter()
            .enumerate()
            .skip(1)
            .map(|(k, z)| (k as f64 * df, 2.0 * z.norm()))
            .collect::<Vec<_>>();
        write_csv(
            &out("spectrum.csv"),
            &["f_hz".into(), "amplitude_m".into()],
            spectrum.iter().map(|&(f, a)| vec![f, a]),
        )?;
        let fmax = 10.0 / model.mesh.t0;
        chart(
            &out(&format!("spectrum.{ext}")),
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
    }
    for which in &scene.output.orbit {
        let g = match which.as_str() {
            "pinion" => 1,
            "gear" => 2,
            o => {
                return Err(input_error(miette::miette!(
                    "output.orbit: `{o}`: expected \"pinion\" or \"gear\""
                )));
            }
        };
        let (Some(ix), Some(iy)) = (
            model.index_of(&format!("x{g}")),
            model.index_of(&format!("y{g}")),
        ) else {
            return Err(input_error(miette::miette!(
                "output.orbit: the {which} centre has no lateral DOFs (x{g}, y{g}) in this scene"
            )));
        };
        let pts = run
            .states
            .iter()
            .map(|s| (s[ix] * 1e6, s[iy] * 1e6))
            .collect();
        chart(
            &out(&format!("orbit_{which}.{ext}")),
            &format!("Orbit of the {which} centre"),
            "x [µm]",
            "y [µm]",
            vec![Series::line(which.clone(), pts)],
            true,
        )?;
    }
    let h = run.dte_harmonics(6);
    eprintln!(
        "DTE mean {:.4} µm, harmonics at k·f_mesh [µm]: {}",
        h[0] * 1e6,
        h[1..]
            .iter()
            .map(|x| format!("{:.4}", x * 1e6))
            .collect::<Vec<_>>()
            .join(", ")
    );
    eprintln!("outputs written to {}", args.out.display());
    summary["run"] = serde_json::json!({
        "stats": run.stats, "transient_periods": run.transient_periods, "steady": run.steady,
        "poincare_change": run.poincare_change, "dte_mean_m": h[0], "dte_harmonics_m": &h[1..],
        "dte_half_pp_m": run.dte_half_pp(), "dte_non_harmonic_max_m": run.dte_non_harmonic(),
        "poincare_section": poincare,
    });
    if args.json {
        print_json(&summary)?;
    }
    Ok(())
}
