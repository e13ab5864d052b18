//! `ncgear dynamics`: thin shell over `ncgear::analysis::dynamics`.
use super::{CliResult, input_error, print_json, progress_bar, runtime_error};
use ncgear::analysis::dynamics::{self as dy, AnalysisOptions, DynamicsError, Scene};
use ncgear::output::PlotFormat;
use std::path::PathBuf;

/// Arguments of `ncgear dynamics`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Scene file (.toml or .json).
    pub scene: PathBuf,
    /// Output directory: dynamics.json (always), CSV files and plots of a time-domain run.
    #[arg(long, default_value = "dynamics_out")]
    pub out: PathBuf,
    /// Frequency sweep over Ω = ωe/ωn as START:END:STEP, run up and then down (time-domain
    /// solvers only: a `method = "linear"` scene is solved in closed form).
    #[arg(long)]
    pub sweep: Option<String>,
    /// Carrier-speed sweep of a rotor scene as START:END:STEP, r/min (within (0, 3000], at
    /// most 200 speeds), each steady state warm-started from the previous.
    #[arg(long)]
    pub sweep_rpm: Option<String>,
    /// Plot format of a time-domain run: svg (default) or png.
    #[arg(long)]
    pub format: Option<String>,
    /// A rotor scene's charts also as PNG (SVG always).
    #[arg(long)]
    pub png: bool,
    /// Print a machine-readable summary to stdout.
    #[arg(long)]
    pub json: bool,
}

fn dyn_err(e: DynamicsError) -> super::Failure {
    match e {
        DynamicsError::Scene(_)
        | DynamicsError::BadOption { .. }
        | DynamicsError::NotLinear(_)
        | DynamicsError::Output { .. } => input_error(miette::miette!("{e}")),
        _ => runtime_error(miette::miette!("{e}")),
    }
}

/// Most steps a `--sweep` may take, so at most this + 1 frequencies (each a steady-state run,
/// up and down: the 21-point sweep of `full16.toml` takes about 20 s; a response curve needs
/// far fewer than this).
const MAX_SWEEP_STEPS: f64 = 1000.0;

fn parse_sweep(s: &str) -> Result<Vec<f64>, super::Failure> {
    let bad = |why: &str| {
        input_error(miette::miette!(
            "--sweep `{s}`: {why}; expected START:END:STEP, e.g. 0.6:1.0:0.02"
        ))
    };
    let p: Vec<f64> = s
        .split(':')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| bad("three numbers separated by `:`"))?;
    let [a, b, h] = p[..] else {
        return Err(bad("three numbers separated by `:`"));
    };
    if !(a > 0.0 && b > a && h > 0.0 && b.is_finite()) {
        return Err(bad(
            "the frequency ratios need 0 < START < END (finite) and STEP > 0",
        ));
    }
    let count = (b - a) / h + 1.0;
    if count > MAX_SWEEP_STEPS + 1.0 {
        return Err(bad(&format!(
            "{count:.0} frequencies, more than a sweep may run ({MAX_SWEEP_STEPS:.0} steps, \
             {:.0} frequencies, each a steady-state run up and down): take a larger STEP",
            MAX_SWEEP_STEPS + 1.0
        )));
    }
    let n = ((b - a) / h + 1e-9).floor() as usize;
    Ok((0..=n).map(|i| a + h * i as f64).collect())
}

/// Runs `ncgear dynamics`: loads the scene, prints the run log, runs it through the library
/// ([`dy::Prepared::run`]) and writes the CSV files and plots of the result.
pub fn run(args: Args) -> CliResult {
    let file = args.scene.display().to_string();
    let text = std::fs::read_to_string(&args.scene).unwrap_or_default();
    if ncgear::analysis::dynamics::rotor::RotorScene::names_rotor(&text) {
        return super::dynamics_rotor::run(&args);
    }
    if args.sweep_rpm.is_some() {
        return Err(input_error(miette::miette!(
            "--sweep-rpm sweeps a rotor scene's carrier speed ([scene] model = \"rotor\"); a \
             spur scene sweeps the frequency ratio with --sweep"
        )));
    }
    if args.png {
        return Err(input_error(miette::miette!(
            "--png adds PNG copies of a rotor scene's charts ([scene] model = \"rotor\"); a \
             spur scene's plots are PNG with --format png"
        )));
    }
    let scene = Scene::from_path(&args.scene).map_err(|e| input_error(miette::miette!("{e}")))?;
    let prepared = dy::Prepared::new(scene, &file).map_err(dyn_err)?;
    let format = args.format.as_deref().unwrap_or("svg");
    if !matches!(format, "svg" | "png") {
        return Err(input_error(miette::miette!(
            "--format `{format}`: expected svg or png"
        )));
    }
    // The linear path has no time history: a sweep or a plot format would do nothing.
    let ignored = [
        (args.sweep.is_some(), "--sweep"),
        (args.format.is_some(), "--format"),
    ]
    .into_iter()
    .find_map(|(given, flag)| given.then_some(flag));
    if let (true, Some(flag)) = (prepared.takes_linear_path(), ignored) {
        return Err(input_error(miette::miette!(
            help = "set [solver] method to a time-domain solver (e.g. \"dopri5\") to run it",
            "{flag} applies to a time-domain run, and this scene's `method = \"linear\"` is \
             solved in closed form at the mesh frequency (dynamics.json holds the result)"
        )));
    }
    std::fs::create_dir_all(&args.out)
        .map_err(|e| runtime_error(miette::miette!("cannot create {}: {e}", args.out.display())))?;
    print_header(&prepared, &file);
    let linear = prepared.takes_linear_path();
    let sweep = match (&args.sweep, linear) {
        (Some(sw), false) => Some(parse_sweep(sw)?),
        _ => None,
    };
    let options = AnalysisOptions::default().with_sweep(sweep);
    let pb = match &options.sweep {
        _ if linear => None,
        Some(up) => Some(progress_bar(2 * up.len() as u64, "sweep")),
        None => Some(progress_bar(
            u64::from(prepared.options.max_periods),
            "transient",
        )),
    };
    let sink = pb
        .as_ref()
        .map_or_else(ncgear::progress::Progress::none, super::bar_sink);
    let report = prepared.run(&options, &sink).map_err(dyn_err)?;
    if let Some(pb) = &pb {
        pb.finish_and_clear();
    }
    if let Some(amp) = report.linear_dte_amplitude_m {
        eprintln!(
            "linear fast path: DTE amplitude at the mesh frequency {:.6} µm",
            amp * 1e6
        );
    }
    // The report, whatever the path (--out always gets it), written last by the library.
    let format = if format == "png" {
        PlotFormat::Png
    } else {
        PlotFormat::Svg
    };
    ncgear::output::write_dynamics(&report, &prepared, &args.out, format)
        .map_err(|e| runtime_error(miette::miette!("{e}")))?;
    if report.sweep_up.is_some() {
        eprintln!("sweep written to {}", args.out.join("sweep.csv").display());
    }
    if let Some(summary) = &report.run {
        log_run(summary);
        eprintln!("outputs written to {}", args.out.display());
    }
    if args.json {
        print_json(&report)?;
    }
    Ok(())
}

/// The run log's header on stderr: scene, DOFs, terms, solver, natural frequencies.
fn print_header(p: &dy::Prepared, file: &str) {
    let h = &p.header;
    eprintln!("scene `{}` ({file})", h.scene);
    eprintln!("DOFs ({}): {}", h.dofs.len(), h.dofs.join(", "));
    for t in &h.terms {
        eprintln!("term: {t}");
    }
    eprintln!(
        "solver: {}{}",
        h.solver,
        if p.model.is_linear() {
            " (linear model: eigen-solution and FRF available)"
        } else {
            ""
        }
    );
    if let Some(f) = &h.natural_frequencies_hz {
        eprintln!(
            "natural frequencies (mean stiffness) [Hz]: {}",
            f.iter()
                .map(|x| format!("{x:.2}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
}

/// The run's log lines: the transient, the DTE's mean and harmonics.
fn log_run(s: &dy::RunReport) {
    log_transient(s);
    eprintln!(
        "DTE mean {:.4} µm, harmonics at k·f_mesh [µm]: {}",
        s.dte_mean_m * 1e6,
        s.dte_harmonics_m
            .iter()
            .map(|x| format!("{:.4}", x * 1e6))
            .collect::<Vec<_>>()
            .join(", ")
    );
}

/// Logs the transient: Poincaré periods, whether it settled, the integrator's counters.
fn log_transient(s: &dy::RunReport) {
    eprintln!(
        "transient {} Poincaré periods ({}), {} RHS evaluations, {} accepted / {} rejected steps, {} events",
        s.transient_periods,
        if s.steady {
            "steady".to_string()
        } else {
            format!("NOT steady, change {:.2e}", s.poincare_change)
        },
        s.stats.rhs_evals,
        s.stats.accepted,
        s.stats.rejected,
        s.stats.events
    );
}

#[cfg(test)]
mod tests {
    use super::parse_sweep;
    use crate::cli::Failure;

    fn message(s: &str) -> String {
        match parse_sweep(s) {
            Err(Failure::Input(r)) => r.to_string(),
            other => panic!("{s}: expected an input error, got {:?}", other.ok()),
        }
    }

    #[test]
    fn a_sweep_is_parsed_and_each_refusal_names_its_cause() {
        let v = parse_sweep("0.6:1.0:0.1").unwrap();
        assert_eq!(v.len(), 5);
        assert!((v[4] - 1.0).abs() < 1e-12);
        // 99 991 frequencies: refused by count, not by the order of its bounds.
        let m = message("0.01:100:0.001");
        assert!(m.contains("99991 frequencies") && m.contains("1000"), "{m}");
        assert!(message("1.0:0.6:0.02").contains("0 < START < END"));
        assert!(message("0.6:inf:0.1").contains("finite"));
        assert!(message("a:b:c").contains("three numbers"));
        // At the limit exactly: 1001 frequencies (0..=1000 steps) are run.
        assert_eq!(parse_sweep("1:2:0.001").unwrap().len(), 1001);
    }
}
