//! `ncgear serve`: the interactive designer in the browser ([`crate::serve`]).
use super::{CliResult, input_error};

/// Arguments of `ncgear serve`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// TCP port (0: any free port; the URL is printed).
    #[arg(long, default_value_t = 8080)]
    pub port: u16,
    /// Interface to listen on. The default is loopback: only this machine can connect; another
    /// address exposes the designer to the network on purpose.
    #[arg(long, default_value = "127.0.0.1")]
    pub host: String,
    /// Requests computed at once (default: the number of cores); the others wait their turn in
    /// arrival order. A design already runs on every core for part of its time: fewer leave
    /// cores to other work on a shared machine.
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..=256))]
    pub workers: Option<u16>,
    /// Open the page in the default browser once the server listens.
    #[arg(long)]
    pub open: bool,
}

/// Runs `ncgear serve` until interrupted.
pub fn run(args: Args) -> CliResult {
    let loopback = matches!(args.host.as_str(), "127.0.0.1" | "localhost" | "::1");
    let opts = crate::serve::ServeOptions {
        host: args.host.clone(),
        port: args.port,
        workers: args.workers.map(usize::from),
    };
    crate::serve::run(&opts, |url| {
        println!("ncgear designer: {url} (Ctrl-C stops it)");
        if !loopback {
            eprintln!(
                "warning: listening on {}: any machine that reaches it can use the designer",
                args.host
            );
        }
        if args.open {
            open_browser(url);
        }
    })
    .map_err(|e| {
        input_error(miette::miette!(
            help = "choose another --port (0 picks a free one) or --host",
            "{e}"
        ))
    })
}

/// Asks the desktop to open `url`; a failure is only reported.
fn open_browser(url: &str) {
    let program = if cfg!(target_os = "macos") {
        "open"
    } else if cfg!(windows) {
        "explorer"
    } else {
        "xdg-open"
    };
    if let Err(e) = std::process::Command::new(program).arg(url).spawn() {
        eprintln!("warning: could not open the browser ({program}: {e}); open {url} by hand");
    }
}
