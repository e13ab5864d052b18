//! `ncgear`: the command-line shell over the `ncgear` library.
mod cli;
mod serve;

fn main() -> std::process::ExitCode {
    cli::main()
}
