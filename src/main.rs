//! `ncgear`: the command-line shell over the `ncgear` library.
mod cli;

fn main() -> std::process::ExitCode {
    cli::main()
}
