//! `ncgear tolerance ERRORS` (error harmonics, phase compensation, Monte Carlo) and
//! `ncgear tolerance DESIGN.json --errors ERRORS` (transplanter tolerance analysis, docs/math/companion.md §C.6).
use super::{CliResult, input_error, print_json, progress_bar, runtime_error};
use ncgear::analysis::tolerance::{ErrorFile, ToleranceOptions, analyse};
use ncgear::analysis::transplanter::{
    self, ErrorInventory, TransplanterError, TransplanterOptions, TransplanterReport,
};
use ncgear::math::monte_carlo::{McOptions, McStats};
use ncgear::simulate::DesignFile;
use std::path::{Path, PathBuf};

/// Arguments of `ncgear tolerance`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Error file (TOML or JSON): terms A·sin(ωt + φ) in µm, rad/s, degrees; or, with `--errors`,
    /// the design.json of a transplanter (see docs/transplanter.md).
    pub errors: PathBuf,
    /// Transplanter error inventory (TOML or JSON, µm and degrees): analyse the design file given
    /// as the positional argument (docs/math/companion.md §C.6).
    #[arg(long = "errors", value_name = "ERRORS")]
    pub inventory: Option<PathBuf>,
    /// Monte Carlo samples over random assemblies (0: no Monte Carlo; the transplanter analysis
    /// needs at least 2).
    #[arg(long, default_value_t = 50_000)]
    pub samples: usize,
    /// Seed of the Monte Carlo.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Starts of the joint phase / assembly optimizer (1..=1000).
    #[arg(long, default_value_t = 24, value_parser = super::count_in(1, 1000))]
    pub starts: usize,
    /// Transplanter: exact-model samples for the agronomic-feature distributions (0: skip;
    /// at most 2000: 10 000 took 15 s).
    #[arg(long, default_value_t = 200, value_parser = super::count_in(0, 2000))]
    pub feature_samples: usize,
    /// Transplanter: samples at 3σ validating the linear model against the exact one (at most
    /// 1000: 10 000 took 10 s).
    #[arg(long, default_value_t = 100, value_parser = super::count_in(0, 1000))]
    pub validation_samples: usize,
    /// Output directory for the plots and tolerance.json / transplanter.json.
    #[arg(long, default_value = "out/tolerance")]
    pub out: PathBuf,
    /// Print the report as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Runs `ncgear tolerance`.
pub fn run(args: Args) -> CliResult {
    if let Some(inv) = args.inventory.clone() {
        return run_transplanter(&args, &inv);
    }
    let file =
        ErrorFile::from_path(&args.errors).map_err(|e| input_error(miette::miette!("{e}")))?;
    let opts = ToleranceOptions::default()
        .with_monte_carlo((args.samples > 0).then(|| mc_options(&args)))
        .with_joint_starts(args.starts);
    let pb = progress_bar(args.samples as u64, "Monte Carlo");
    // Every error of the analysis is the input's (a value of the file, or --samples).
    let report = analyse(&file, &opts, &super::bar_sink(&pb)).map_err(|e| {
        input_error(miette::miette!(
            help = "--samples sets the Monte Carlo sample count",
            "{e}"
        ))
    })?;
    pb.finish_and_clear();
    ncgear::output::write_tolerance(&report, &args.out)
        .map_err(|e| runtime_error(miette::miette!("{e}")))?;
    if args.json {
        return print_json(&report);
    }
    let asec = |v: f64| report.arcsec(v);
    println!(
        "{}: base radius {:.4} mm, common period {:.6} s{}",
        args.errors.display(),
        report.base_radius_mm,
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

/// The Monte Carlo options of the arguments (60 histogram bins).
fn mc_options(args: &Args) -> McOptions {
    McOptions::default()
        .with_samples(args.samples)
        .with_seed(args.seed)
        .with_bins(60)
}

/// The command-line flag that sets a field of [`TransplanterOptions`], for error hints.
fn flag_of(option: &str) -> Option<&'static str> {
    match option {
        "mc.samples" => Some("--samples"),
        "mc.seed" => Some("--seed"),
        _ => None,
    }
}

fn run_transplanter(args: &Args, inventory: &Path) -> CliResult {
    let (_, asm) =
        DesignFile::from_path(&args.errors).map_err(|e| input_error(miette::miette!("{e}")))?;
    let inv =
        ErrorInventory::from_path(inventory).map_err(|e| input_error(miette::miette!("{e}")))?;
    let opts = TransplanterOptions::default()
        .with_mc(mc_options(args))
        .with_validation_samples(args.validation_samples)
        .with_feature_samples(args.feature_samples)
        .with_starts(args.starts);
    // The tip-deviation samples, then as many random assemblies when a direction is free.
    let passes = if inv.free_gears().is_empty() { 1 } else { 2 };
    let pb = progress_bar(passes * args.samples as u64, "Monte Carlo");
    let report =
        transplanter::analyse(&asm, &inv, &opts, &super::bar_sink(&pb)).map_err(|e| match &e {
            TransplanterError::BadOption { option, .. } => match flag_of(option) {
                Some(flag) => input_error(miette::miette!(help = format!("set by {flag}"), "{e}")),
                None => input_error(miette::miette!("{e}")),
            },
            _ => runtime_error(miette::miette!("{e}")),
        })?;
    pb.finish_and_clear();
    ncgear::output::write_transplanter(&report, &args.out)
        .map_err(|e| runtime_error(miette::miette!("{e}")))?;
    if args.json {
        return print_json(&report);
    }
    print_transplanter(&report, args, inventory);
    Ok(())
}

fn print_transplanter(r: &TransplanterReport, args: &Args, inventory: &Path) {
    let s = &r.max_deviation_um;
    println!(
        "{} with {}: α = {:.1}°, load side {}, {} carrier angles",
        args.errors.display(),
        inventory.display(),
        r.pressure_angle_deg,
        r.load_side,
        r.samples_per_turn
    );
    println!(
        "  errors as given: max |ΔB| = {:.3} µm (exact), {:.3} µm (linear)",
        r.nominal_errors_exact_um, r.nominal_errors_linear_um
    );
    let v = &r.validation;
    println!(
        "  linear vs exact on {} samples at 3σ: max relative error {:.3} % (mean {:.3} %, max {:.3} µm) → {} model",
        v.samples,
        100.0 * v.max_relative_error,
        100.0 * v.mean_relative_error,
        v.max_absolute_error_um,
        v.model_used
    );
    println!(
        "  Monte Carlo ({} samples, seed {}): max |ΔB| µm: mean {:.3} std {:.3} P50 {:.3} P95 {:.3} P99.73 {:.3} max {:.3}",
        s.n, r.seed, s.mean, s.std, s.p50, s.p95, s.p9973, s.max
    );
    let t = &r.planet_angle_error_arcsec;
    println!(
        "  planet transmission error max |Δθ3| (arcsec): mean {:.2} std {:.2} P95 {:.2} P99.73 {:.2}",
        t.mean, t.std, t.p95, t.p9973
    );
    println!(
        "  3σ envelope along the trajectory: max {:.3} µm",
        r.envelope_max_um
    );
    if let Some(f) = &r.features {
        let line = |name: &str, st: &McStats, unit: &str| {
            println!(
                "    {name:<28} mean {:+.5} std {:.5} P99.73 {:+.5} {unit}",
                st.mean, st.std, st.p9973
            );
        };
        println!(
            "  agronomic-feature deviations over {} exact samples:",
            f.samples
        );
        line("trajectory height", &f.height_mm, "mm");
        line("hole width", &f.hole_width_mm, "mm");
        line("static width at depth", &f.static_width_at_depth_mm, "mm");
        line("lowest point", &f.lowest_point_mm, "mm");
        line("needle angle at taking", &f.needle_angle_take_deg, "deg");
        line("needle angle at planting", &f.needle_angle_plant_deg, "deg");
    }
    println!("  worst contributors (at 3σ):");
    for c in r.ranking.iter().take(8) {
        println!(
            "    {:<30} {:>9.3} {:<3} → {:>9.3} µm ({:>5.1} %)",
            c.error, c.three_sigma, c.unit, c.max_deviation_um, c.share_percent
        );
    }
    if let Some(a) = &r.assembly {
        println!(
            "  best assembly of {:?}: as given {:.3} µm, greedy {:.3} µm, joint ({}) {:.3} µm at {:?}° (exact {:.3} µm)",
            a.free,
            a.as_given_um,
            a.greedy_um,
            a.joint_method,
            a.joint_um,
            a.joint_directions_deg
                .iter()
                .map(|d| (d * 10.0).round() / 10.0)
                .collect::<Vec<_>>(),
            a.joint_exact_um
        );
        println!(
            "    random orientation: mean {:.3} µm, P95 {:.3} µm; gain vs mean {:.1} %; P(random ≤ best) = {:.2} %",
            a.random.mean,
            a.random.p95,
            a.gain_vs_random_mean_percent,
            100.0 * a.p_random_beats_joint
        );
    }
}
