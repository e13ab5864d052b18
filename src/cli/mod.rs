//! Command-line interface: parsing, exit codes, progress bars. Each subcommand is a thin shell
//! over the library, in its own file.
use clap::{Parser, Subcommand};
use std::io::IsTerminal;
use std::process::ExitCode;

mod compare;
mod design;
mod design_args;
mod dynamics;
mod dynamics_rotor;
mod loads;
mod orbit;
mod pair;
mod serve;
mod simulate;
mod synthesize;
mod teeth_args;
mod tolerance;
mod tradeoff;

/// Non-circular gear design for rice-transplanter planting arms, and gear-train analyses.
#[derive(Debug, Parser)]
#[command(name = "ncgear", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Memory a single computation may estimate for itself before it is refused, GB (default 4).
    #[arg(long, global = true)]
    max_memory_gb: Option<f64>,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Design the sun and intermediate pitch curves from a needle-tip trajectory file.
    Design(design::Args),
    /// What accuracy costs: the target designed under pressure-angle limits and modules, tabulated.
    Tradeoff(tradeoff::Args),
    /// Design a single non-circular gear pair from a motion law or centrode, with teeth.
    Pair(pair::Args),
    /// Simulate a designed mechanism: traced trajectories, animation, agronomic features.
    Simulate(simulate::Args),
    /// Transmission-error harmonics, phase compensation and Monte Carlo tolerance analysis.
    Tolerance(tolerance::Args),
    /// Floating sun-gear orbit under planet eccentricity: model, measurement, identification.
    Orbit(orbit::Args),
    /// Scene-driven nonlinear spur-gear dynamics.
    Dynamics(dynamics::Args),
    /// The planting rotor's loads over a turn, tooth stresses, safety factors and life.
    Loads(loads::Args),
    /// The interactive designer in the browser: drag the trajectory, watch the gears follow.
    Serve(serve::Args),
    /// Key poses of the needle (and target bands) → the mechanism and its gears.
    Synthesize(synthesize::Args),
    /// A filmed needle-tip track registered to its design's path and compared with it.
    Compare(compare::Args),
}

/// How a command failed; decides the exit code.
#[derive(Debug)]
pub enum Failure {
    /// Bad input (file, field, value): exit code 2.
    Input(miette::Report),
    /// Runtime failure (non-convergence, cannot write output): exit code 1.
    Runtime(miette::Report),
    /// The files are written, but the result failed its own verification (a check, a mesh):
    /// exit code 3, unless `--accept-failed`.
    Verification(miette::Report),
}

/// Result of a subcommand.
pub type CliResult = Result<(), Failure>;

/// Wraps a bad-input error (exit code 2).
pub fn input_error(e: impl Into<miette::Report>) -> Failure {
    Failure::Input(e.into())
}

/// Wraps a runtime error (exit code 1).
pub fn runtime_error(e: impl Into<miette::Report>) -> Failure {
    Failure::Runtime(e.into())
}

/// The flag that sets an option field named in a library error (design, teeth, export).
pub fn flag_of(option: &str) -> Option<&'static str> {
    Some(match option {
        "order" => "--order",
        "smooth" => "--smooth",
        "tol_mm" => "--tol-mm",
        "inverse.grid" => "--grid",
        "inverse.sense" => "--sense",
        "inverse.dense_samples" => "--dense",
        "samples" => "--samples",
        "refine_options.ratio_bounds" => "--ratio-bounds",
        "center_mm" => "--center",
        "segmented.w1" => "--w1",
        "segmented.k_max" => "--k-max",
        "max_pressure_angle_rad" => "--max-pressure-angle",
        "min_concave_radius_mm" => "--min-concave-radius",
        "min_convex_radius_mm" => "--min-convex-radius",
        "module_mm" => "--module",
        "pressure_angle_deg" => "--pressure-angle",
        "addendum" => "--addendum",
        "clearance" => "--clearance",
        "fillet" => "--fillet",
        "refine_order" => "--refine-order",
        "chord_tol_mm" => "--chord-tol",
        "verify_steps" | "verify_steps × driver turns per cycle" => "--verify-steps",
        "teeth" | "teeth of the driven gear (z·q/p)" => "--teeth",
        "backlash_mm" => "--backlash",
        "cutter_teeth" => "--cutter-teeth",
        "bore" => "--bore",
        "face_width" => "--face-width",
        _ => return None,
    })
}

/// Removes an earlier run's report at `path` before the first file of this run: the report is
/// written last, so files of two runs never sit beside a report that vouches for them
/// ([`ncgear::files`]).
pub fn remove_stale_report(path: &std::path::Path) -> CliResult {
    ncgear::files::remove_stale(path)
        .map_err(|e| runtime_error(miette::miette!("cannot remove {}: {e}", path.display())))
}

/// The bad-input failure of a library error naming the option `field`: the error, and the flag
/// that sets the field when there is one.
pub fn option_error(field: Option<&str>, e: impl std::fmt::Display) -> Failure {
    match field.and_then(flag_of) {
        Some(flag) => input_error(miette::miette!(help = format!("set by {flag}"), "{e}")),
        None => input_error(miette::miette!("{e}")),
    }
}

/// A parser of a count option in `lo..=hi` (refused by the argument parser, exit 2, before any
/// work): the range keeps the work of the option within seconds.
pub fn count_in(
    lo: usize,
    hi: usize,
) -> impl Fn(&str) -> Result<usize, String> + Clone + Send + Sync + 'static {
    move |s| {
        let v: usize = s
            .trim()
            .parse()
            .map_err(|_| format!("`{s}`: expected a whole number in {lo}..={hi}"))?;
        if (lo..=hi).contains(&v) {
            Ok(v)
        } else {
            Err(format!("{v} is outside the admissible range {lo}..={hi}"))
        }
    }
}

/// Exit code of [`Failure::Verification`]: written, but the verification failed.
pub const EXIT_VERIFICATION_FAILED: u8 = 3;

/// The outcome of a written result: exit 0 when its verdict passed or the user accepts a failed
/// one (`--accept-failed`), otherwise [`Failure::Verification`] listing what failed, then
/// `notes` (what would pass, say).
pub fn verdict_outcome(
    v: &ncgear::verdict::Verdict,
    accept_failed: bool,
    notes: &[String],
) -> CliResult {
    if v.passed || accept_failed {
        return Ok(());
    }
    let notes: String = notes.iter().map(|n| format!("\n  {n}")).collect();
    Err(Failure::Verification(miette::miette!(
        help = "the files are written and their report says `\"verdict\": {\"passed\": false}`; \
                --accept-failed exits 0 with them as they are",
        "verification failed:\n  {}{notes}",
        v.failures.join("\n  ")
    )))
}

/// A progress bar on stderr when stderr is a terminal; hidden (a no-op) when piped.
pub fn progress_bar(len: u64, what: &str) -> indicatif::ProgressBar {
    if !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let pb = indicatif::ProgressBar::new(len);
    let style = indicatif::ProgressStyle::with_template("{msg:>12} [{bar:40}] {pos}/{len} ({eta})")
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar())
        .progress_chars("=> ");
    pb.set_style(style);
    pb.set_message(what.to_string());
    pb
}

/// A progress sink that advances `pb`.
pub fn bar_sink(pb: &indicatif::ProgressBar) -> ncgear::progress::Progress {
    let pb = pb.clone();
    ncgear::progress::Progress::new(move |n| pb.inc(n))
}

/// A spinner on stderr naming the stage that runs (a stage with no measure of its progress),
/// ticking by itself when stderr is a terminal; hidden (a no-op) when piped.
pub fn spinner(what: &str) -> indicatif::ProgressBar {
    if !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let pb = indicatif::ProgressBar::new_spinner();
    pb.set_message(what.to_string());
    pb.enable_steady_tick(std::time::Duration::from_millis(120));
    pb
}

/// Milliseconds since `t0`.
pub fn ms_since(t0: std::time::Instant) -> f64 {
    t0.elapsed().as_secs_f64() * 1e3
}

/// Writes `value` as pretty JSON to stdout.
pub fn print_json(value: &impl serde::Serialize) -> CliResult {
    let s = ncgear::output::json::to_string(value)
        .map_err(|e| runtime_error(miette::miette!("{e}")))?;
    println!("{s}");
    Ok(())
}

/// Entry point: parse, dispatch, map failures to exit codes.
pub fn main() -> ExitCode {
    // A closed pipe (`ncgear … | head`) ends the process quietly, as for any Unix tool, instead
    // of panicking inside `println!`.
    #[cfg(unix)]
    // SAFETY: called once at start-up, before any thread exists; SIG_DFL is a valid handler.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    // glibc serves blocks above 128 KiB by fresh mmap, freed by munmap: the chain's arrays of
    // tens of thousands of points then fault their pages in again at every stage. Kept on the
    // heap instead, freed blocks are reused.
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: mallopt only sets allocator parameters; called before any thread exists.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 256 << 20);
        libc::mallopt(libc::M_TRIM_THRESHOLD, 512 << 20);
    }
    // Messages wrap at the terminal's width, but never inside a word: a flag such as
    // `--idler-offset` split at its hyphen could not be copied back.
    let _ = miette::set_hook(Box::new(|_| {
        Box::new(
            miette::MietteHandlerOpts::new()
                .word_splitter(textwrap::WordSplitter::NoHyphenation)
                .build(),
        )
    }));
    let cli = Cli::parse();
    if let Some(gb) = cli.max_memory_gb {
        if !(gb.is_finite() && gb > 0.0 && gb <= 1e6) {
            eprintln!(
                "{:?}",
                miette::miette!("--max-memory-gb {gb}: expected a memory size in (0, 1e6] GB")
            );
            return ExitCode::from(2);
        }
        ncgear::bounds::set_memory_ceiling_bytes((gb * 1e9) as u64);
    }
    let result = match cli.command {
        Command::Design(a) => design::run(a),
        Command::Tradeoff(a) => tradeoff::run(a),
        Command::Pair(a) => pair::run(a),
        Command::Simulate(a) => simulate::run(a),
        Command::Tolerance(a) => tolerance::run(a),
        Command::Orbit(a) => orbit::run(a),
        Command::Dynamics(a) => dynamics::run(a),
        Command::Loads(a) => loads::run(a),
        Command::Serve(a) => serve::run(a),
        Command::Synthesize(a) => synthesize::run(a),
        Command::Compare(a) => compare::run(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Input(report)) => {
            eprintln!("{report:?}");
            ExitCode::from(2)
        }
        Err(Failure::Runtime(report)) => {
            eprintln!("{report:?}");
            ExitCode::from(1)
        }
        Err(Failure::Verification(report)) => {
            eprintln!("{report:?}");
            ExitCode::from(EXIT_VERIFICATION_FAILED)
        }
    }
}
