//! Command-line interface: parsing, exit codes, progress bars. Each subcommand is a thin shell
//! over the library, in its own file.
use clap::{Parser, Subcommand};
use std::io::IsTerminal;
use std::process::ExitCode;

mod design;
mod dynamics;
mod orbit;
mod pair;
mod simulate;
mod teeth_args;
mod tolerance;
mod tradeoff;

/// Non-circular gear design for rice-transplanter planting arms, and gear-train analyses.
#[derive(Debug, Parser)]
#[command(name = "ncgear", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
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
}

/// How a command failed; decides the exit code.
#[derive(Debug)]
pub enum Failure {
    /// Bad input (file, field, value): exit code 2.
    Input(miette::Report),
    /// Runtime failure (non-convergence, cannot write output): exit code 1.
    Runtime(miette::Report),
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
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Design(a) => design::run(a),
        Command::Tradeoff(a) => tradeoff::run(a),
        Command::Pair(a) => pair::run(a),
        Command::Simulate(a) => simulate::run(a),
        Command::Tolerance(a) => tolerance::run(a),
        Command::Orbit(a) => orbit::run(a),
        Command::Dynamics(a) => dynamics::run(a),
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
    }
}
