//! `ncgear tolerance ERRORS`: error harmonics, phase compensation and Monte Carlo.
use super::{CliResult, input_error, print_json, progress_bar, runtime_error};
use ncgear::analysis::montecarlo::McOptions;
use ncgear::analysis::tolerance::{ErrorFile, analyse};
use ncgear::plot::{ChartLabels, Series, line_chart};
use std::path::PathBuf;

/// Arguments of `ncgear tolerance`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Error file (TOML or JSON): terms A·sin(ωt + φ) in µm, rad/s, degrees; see the README.
    pub errors: PathBuf,
    /// Monte Carlo samples over random assembly phases (0: no Monte Carlo).
    #[arg(long, default_value_t = 50_000)]
    pub samples: usize,
    /// Seed of the Monte Carlo.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Starts of the joint phase optimiser.
    #[arg(long, default_value_t = 24)]
    pub starts: usize,
    /// Output directory for the histogram plot and tolerance.json.
    #[arg(long, default_value = "out/tolerance")]
    pub out: PathBuf,
    /// Print the report as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Runs `ncgear tolerance`.
pub fn run(args: Args) -> CliResult {
    let file = ErrorFile::read(&args.errors).map_err(|e| input_error(miette::miette!("{e}")))?;
    let mc = (args.samples > 0).then_some(McOptions {
        samples: args.samples,
        seed: args.seed,
        bins: 60,
    });
    let pb = progress_bar(args.samples as u64, "Monte Carlo");
    let report = analyse(&file, mc.as_ref(), args.starts, &|d| pb.set_position(d))
        .map_err(|e| runtime_error(miette::miette!("{e}")))?;
    pb.finish_and_clear();
    std::fs::create_dir_all(&args.out)
        .map_err(|e| runtime_error(miette::miette!("cannot create {}: {e}", args.out.display())))?;
    let json =
        serde_json::to_string_pretty(&report).map_err(|e| runtime_error(miette::miette!("{e}")))?;
    std::fs::write(args.out.join("tolerance.json"), json)
        .map_err(|e| runtime_error(miette::miette!("cannot write tolerance.json: {e}")))?;
    if let Some(s) = &report.monte_carlo_arcsec {
        let pts: Vec<(f64, f64)> = s
            .histogram
            .iter()
            .flat_map(|h| [(h[0], h[2]), (h[1], h[2])])
            .collect();
        line_chart(
            &args.out.join("histogram.png"),
            &ChartLabels {
                title: format!("Peak transmission error over {} random assemblies", s.n),
                x: "peak transmission error (arc seconds)".into(),
                y: "samples per bin".into(),
                equal_aspect: false,
            },
            &[
                Series::line("random assembly", pts),
                Series::markers(
                    "greedy compensation",
                    vec![(report.greedy_peak_arcsec, 0.0)],
                ),
            ],
            (900, 500),
        )
        .map_err(|e| runtime_error(miette::miette!("{e}")))?;
    }
    if args.json {
        return print_json(&report);
    }
    let rb = report.base_radius_mm;
    let asec = |v: f64| ncgear::analysis::tolerance::arcsec(v, rb);
    println!(
        "{}: base radius {rb:.4} mm, common period {:.6} s{}",
        args.errors.display(),
        report.period_s,
        if report.commensurate {
            ""
        } else {
            " (incommensurate: peak = Σ|A| for any phases)"
        }
    );
    println!(
        "  sum of amplitudes {:.4} µm ({:.2}″), phase-independent floor {:.4} µm ({:.2}″)",
        report.amplitude_sum_um,
        asec(report.amplitude_sum_um),
        report.floor_um,
        asec(report.floor_um)
    );
    for s in &report.greedy {
        println!(
            "  greedy: {:<24} i = {:>4} (β = {:.4} rad), peak {:.6} µm, {} tie(s)",
            s.term,
            s.index,
            s.beta_rad,
            s.peak_um,
            s.ties.len()
        );
    }
    println!(
        "  greedy assembly: {:.6} µm = {:.2}″; joint optimum {:.6} µm (gap {:.4} µm)",
        report.greedy_peak_um,
        report.greedy_peak_arcsec,
        report.joint.peak_um,
        report.greedy_gap_um
    );
    if let (Some(s), Some(p)) = (&report.monte_carlo_arcsec, report.p_random_beats_greedy) {
        println!(
            "  Monte Carlo ({} samples, seed {}): min {:.2}″ max {:.2}″ mean {:.2}″ std {:.2}″ P50 {:.2}″ P95 {:.2}″ P99.73 {:.2}″",
            s.n, args.seed, s.min, s.max, s.mean, s.std, s.p50, s.p95, s.p9973
        );
        println!(
            "  probability that a random assembly beats greedy compensation: {:.2} %",
            100.0 * p
        );
    }
    Ok(())
}
