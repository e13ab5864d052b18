//! Seeded, bounded fuzzing of every `ncgear` subcommand.
//!
//! `campaign` (ignored: `cargo test --release --test fuzz -- --ignored`) runs the built binary a
//! few hundred times on valid baselines, mutated option values and mutated copies of the bundled
//! inputs, each run in its own directory under a wall-clock and a memory limit, and holds every
//! run to the invariants of [`violations`], whatever its input:
//! - no panic, abort or other signal, no run over its time or memory limit;
//! - exit code 0 (ok), 1 (runtime error), 2 (bad input) or 3 (files written, verification failed);
//! - exit 0: every JSON file written, and stdout under `--json`, parses (so holds no NaN or
//!   Infinity token), and a top-level `verdict` object says `"passed": true` (unless the run
//!   asks for `--accept-failed`);
//! - exit 1 or 2: stderr says what is wrong (not empty, not a bare `Debug` dump);
//! - an unmutated baseline exits 0;
//! - an input file given a non-finite number (TOML `nan`, `inf`; JSON `NaN`, `Infinity`) is
//!   refused: exit 2 (every number in every file has a range, docs/bounds.md).
//!
//! Environment: `NCGEAR_FUZZ_RUNS` (300), `NCGEAR_FUZZ_SEED` (1), `NCGEAR_FUZZ_LIMIT_S` (10),
//! `NCGEAR_FUZZ_MEM_MB` (2048: the documented memory budget of a run), `NCGEAR_FUZZ_JOBS` (the cores), `NCGEAR_FUZZ_ONLY` (run indices
//! to replay, comma-separated). Run k draws from its own generator seeded by (seed, k): the same
//! seed gives the same command lines and input files, whatever the run count or job count.
//!
//! The regression tests at the end are the known reproducers, held to the same invariants.
use ncgear::math::Point;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use rand::rngs::ChaCha8Rng;
use rand::seq::IndexedRandom;
use rand::{RngExt, SeedableRng};

const BIN: &str = env!("CARGO_BIN_EXE_ncgear");

/// The per-run memory budget, MiB resident (docs/bounds.md): a run above it is killed and counted.
const MEMORY_BUDGET_MB: u64 = 2048;

/// The per-run wall-clock limit: no input may keep the CLI busy longer.
const LIMIT: Duration = Duration::from_secs(10);

/// The limit of a run that shows its progress on a terminal and can be interrupted (a long
/// run is bounded by its progress bar, not by 10 s): a dynamics sweep, a Monte
/// Carlo tolerance analysis, a trade-off table of ten designs.
const PROGRESS_LIMIT: Duration = Duration::from_secs(60);

/// Whether `argv` is a run of [`PROGRESS_LIMIT`].
fn shows_progress(argv: &[String]) -> bool {
    match argv.first().map(String::as_str) {
        Some("tradeoff") => true,
        Some("dynamics") => argv.iter().any(|a| a == "--sweep"),
        Some("tolerance") => option_value(argv, "--samples").is_none_or(|s| s != "0"),
        _ => false,
    }
}

/// A refusal of nonsense input is a check made before any work, so it comes at once.
const REFUSAL_LIMIT: Duration = Duration::from_secs(1);

// ---------------------------------------------------------------------------------------------
// The harness: one run of the binary, watched.

/// What one run of the binary did.
#[derive(Debug)]
struct Outcome {
    code: Option<i32>,
    signal: Option<i32>,
    elapsed: Duration,
    timed_out: bool,
    over_memory: bool,
    peak_rss_mb: u64,
    /// CPU time (user + system) at the last poll: beside `elapsed`, it tells a busy run from one
    /// that other processes on the machine starved.
    cpu_s: f64,
    stdout: Vec<u8>,
    stderr: String,
}

/// Resident memory of a process in MiB (Linux `/proc`; 0 where unavailable).
fn rss_mb(pid: u32) -> u64 {
    std::fs::read_to_string(format!("/proc/{pid}/status"))
        .ok()
        .and_then(|s| {
            s.lines()
                .find_map(|l| l.strip_prefix("VmRSS:"))
                .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<u64>().ok())
        })
        .map_or(0, |kb| kb / 1024)
}

/// CPU time (user + system) of a process in seconds (Linux `/proc`, 100 ticks a second; 0 where
/// unavailable).
fn cpu_s(pid: u32) -> f64 {
    std::fs::read_to_string(format!("/proc/{pid}/stat"))
        .ok()
        .and_then(|s| {
            // Fields after the command name, which is in parentheses and may hold spaces.
            let rest = s.rsplit_once(')')?.1;
            let f: Vec<&str> = rest.split_whitespace().collect();
            Some((f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?) / 100.0)
        })
        .unwrap_or(0.0)
}

/// Runs `ncgear args` in `dir` (its working directory), watched as [`run_watched`] does.
fn execute(
    args: &[String],
    dir: &Path,
    env: &[(&str, &str)],
    limit: Duration,
    mem_mb: u64,
) -> Outcome {
    run_watched(Path::new(BIN), args, dir, env, limit, mem_mb)
}

/// Runs `program args` in `dir` and kills it once it passes `limit` or `mem_mb` of resident
/// memory: a hung or runaway run must not stall the campaign or swap the machine. Output goes to
/// files, not pipes, so a large `--json` report cannot block the child on a full pipe.
fn run_watched(
    program: &Path,
    args: &[String],
    dir: &Path,
    env: &[(&str, &str)],
    limit: Duration,
    mem_mb: u64,
) -> Outcome {
    let (out_path, err_path) = (dir.join(".stdout"), dir.join(".stderr"));
    let mut cmd = Command::new(program);
    cmd.args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(File::create(&out_path).expect("stdout file"))
        .stderr(File::create(&err_path).expect("stderr file"));
    for (k, v) in env {
        cmd.env(k, v);
    }
    let start = Instant::now();
    let mut child = cmd.spawn().expect("the program starts");
    let (mut timed_out, mut over_memory, mut peak_rss_mb, mut cpu) = (false, false, 0, 0.0);
    let status = loop {
        if let Some(s) = child.try_wait().expect("wait for ncgear") {
            break s;
        }
        let rss = rss_mb(child.id());
        peak_rss_mb = peak_rss_mb.max(rss);
        cpu = cpu_s(child.id()).max(cpu);
        timed_out = start.elapsed() > limit;
        over_memory = rss > mem_mb;
        if timed_out || over_memory {
            let _ = child.kill();
            break child.wait().expect("reap ncgear");
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let elapsed = start.elapsed();
    #[cfg(unix)]
    let signal = std::os::unix::process::ExitStatusExt::signal(&status);
    #[cfg(not(unix))]
    let signal = None;
    Outcome {
        code: status.code(),
        signal,
        elapsed,
        timed_out,
        over_memory,
        peak_rss_mb,
        cpu_s: cpu,
        stdout: std::fs::read(&out_path).unwrap_or_default(),
        stderr: String::from_utf8_lossy(&std::fs::read(&err_path).unwrap_or_default()).into(),
    }
}

/// A message that is a Rust `Debug` rendering (`Os { code: … }`, `Error { kind: … }`, `Some(…)`)
/// or holds no word at all: the CLI let an error escape without saying what was wrong.
fn is_debug_dump(stderr: &str) -> bool {
    const MARKERS: [&str; 7] = [
        "Os { code",
        "{ kind:",
        "Error {",
        "Custom {",
        "Some(",
        "Err(",
        "Ok(",
    ];
    let has_word = stderr
        .split(|c: char| !c.is_alphabetic())
        .any(|w| w.chars().count() >= 3);
    !has_word || MARKERS.iter().any(|m| stderr.contains(m))
}

/// The JSON problems of one document: unparsable (a NaN or Infinity token is unparsable JSON), or
/// on a successful run a top-level `verdict` whose `passed` is not `true`.
fn json_problems(name: &str, bytes: &[u8], want_passed: bool) -> Vec<String> {
    match serde_json::from_slice::<serde_json::Value>(bytes) {
        Err(e) => {
            let text = String::from_utf8_lossy(bytes);
            let bad = ["NaN", "Infinity"]
                .iter()
                .filter(|t| text.contains(*t))
                .copied()
                .collect::<Vec<_>>();
            vec![format!(
                "{name}: not JSON ({e}){}",
                if bad.is_empty() {
                    String::new()
                } else {
                    format!(", holds {}", bad.join("/"))
                }
            )]
        }
        Ok(v) => match v.get("verdict") {
            Some(verdict) if want_passed && verdict.get("passed") != Some(&true.into()) => {
                vec![format!(
                    "{name}: exit 0 but verdict {}",
                    short(&verdict.to_string(), 160)
                )]
            }
            _ => Vec::new(),
        },
    }
}

/// Every `.json` file at or under `path`.
fn json_files(path: &Path, found: &mut Vec<PathBuf>) {
    if path.is_dir() {
        let mut entries: Vec<_> = std::fs::read_dir(path)
            .map(|r| r.filter_map(|e| e.ok().map(|e| e.path())).collect())
            .unwrap_or_default();
        entries.sort();
        for e in entries {
            json_files(&e, found);
        }
    } else if path.extension().is_some_and(|e| e == "json") {
        found.push(path.to_path_buf());
    }
}

/// The value of option `name` in an argument list (`--name v` or `--name=v`).
fn option_value<'a>(args: &'a [String], name: &str) -> Option<&'a str> {
    args.iter().enumerate().find_map(|(i, a)| {
        if a == name {
            args.get(i + 1).map(String::as_str)
        } else {
            a.strip_prefix(name).and_then(|r| r.strip_prefix('='))
        }
    })
}

/// The invariants every run keeps, whatever its input (see the module doc). `dir` is the run's
/// working directory: the output directories named by `--out` and `--plot-dir` are read there,
/// except the run's `inputs` (an empty `--plot-dir` is the working directory itself).
fn violations(o: &Outcome, args: &[String], dir: &Path, inputs: &[String]) -> Vec<String> {
    let mut v = Vec::new();
    if o.timed_out {
        v.push(format!(
            "timeout: killed after {:.1} s ({:.1} s CPU)",
            o.elapsed.as_secs_f64(),
            o.cpu_s
        ));
    } else if o.over_memory {
        v.push(format!("memory: killed at {} MiB resident", o.peak_rss_mb));
    } else if let Some(s) = o.signal {
        let name = match s {
            6 => " (SIGABRT)",
            9 => " (SIGKILL)",
            11 => " (SIGSEGV)",
            _ => "",
        };
        v.push(format!("signal {s}{name}: {}", first_line(&o.stderr)));
    }
    let panic = o.stderr.lines().find(|l| l.contains("panicked at"));
    if o.code == Some(101) || panic.is_some() {
        let at = panic.unwrap_or_else(|| first_line(&o.stderr));
        let msg = o
            .stderr
            .lines()
            .skip_while(|l| !l.contains("panicked at"))
            .nth(1)
            .unwrap_or("");
        v.push(format!("panic: {} {}", at.trim(), msg.trim()));
    }
    match o.code {
        None | Some(0..=3) | Some(101) => {}
        Some(134) => v.push(format!("abort (exit 134): {}", first_line(&o.stderr))),
        Some(c) => v.push(format!("exit code {c} outside 0..=3")),
    }
    if matches!(o.code, Some(0) | Some(3)) {
        // Files written must be whole, valid JSON; only a successful run must also pass its
        // verdict (`--accept-failed` exits 0 with a failed one).
        let passed = o.code == Some(0) && !args.iter().any(|a| a == "--accept-failed");
        let mut files = Vec::new();
        for opt in ["--out", "--plot-dir", "-o"] {
            if let Some(d) = option_value(args, opt) {
                json_files(&dir.join(d), &mut files);
            }
        }
        files.retain(|f| !inputs.iter().any(|i| *f == dir.join(i)));
        files.sort();
        files.dedup();
        for f in files {
            let name = f.strip_prefix(dir).unwrap_or(&f).display().to_string();
            match std::fs::read(&f) {
                Ok(bytes) => v.extend(json_problems(&name, &bytes, passed)),
                Err(e) => v.push(format!("{name}: unreadable ({e})")),
            }
        }
        if args.iter().any(|a| a == "--json") {
            v.extend(json_problems("stdout (--json)", &o.stdout, passed));
        }
    }
    if matches!(o.code, Some(1) | Some(2)) {
        if o.stderr.trim().is_empty() {
            v.push(format!("exit {} with an empty stderr", o.code.unwrap()));
        } else if is_debug_dump(&o.stderr) {
            v.push(format!(
                "exit {} with a bare debug dump: {}",
                o.code.unwrap(),
                short(o.stderr.trim(), 160)
            ));
        }
    }
    v
}

fn first_line(s: &str) -> &str {
    s.lines()
        .map(|l| l.trim_start_matches(|c: char| c.is_whitespace() || c == '×' || c == '│'))
        .find(|l| !l.trim().is_empty())
        .unwrap_or("")
}

fn short(s: &str, n: usize) -> String {
    let one_line = s.split_whitespace().collect::<Vec<_>>().join(" ");
    match one_line.char_indices().nth(n) {
        Some((i, _)) => format!("{}…", &one_line[..i]),
        None => one_line,
    }
}

/// Quotes an argument for a POSIX shell when it needs it, so a printed command line re-runs as is.
fn quote(a: &str) -> String {
    let plain = !a.is_empty()
        && a.chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_./=,:+@%".contains(c));
    if plain {
        a.to_string()
    } else {
        format!("'{}'", a.replace('\'', r"'\''"))
    }
}

fn command_line(env: &[(&str, &str)], args: &[String]) -> String {
    let mut s = String::new();
    for (k, v) in env {
        let _ = write!(s, "{k}={} ", quote(v));
    }
    s.push_str("ncgear");
    for a in args {
        s.push(' ');
        s.push_str(&quote(a));
    }
    s
}

// ---------------------------------------------------------------------------------------------
// The campaign's inputs: baselines, option pools and file mutations.

fn asset(rel: &str) -> Vec<u8> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets")
        .join(rel);
    std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// One command-line item: a bare word (subcommand, positional) or an option with its value.
#[derive(Clone, Debug, PartialEq)]
enum Arg {
    Word(String),
    Opt(&'static str, Option<String>),
}

/// One campaign run: its command line, the input files it is given and what was mutated.
#[derive(Clone, Debug, PartialEq)]
struct Spec {
    index: usize,
    sub: &'static str,
    args: Vec<Arg>,
    files: Vec<(String, Vec<u8>)>,
    mutations: Vec<String>,
}

impl Spec {
    /// The argument list. A value that starts with `-` (or is empty) is attached with `=`, or clap
    /// would read it as an option and the run would test clap instead of the value.
    fn argv(&self) -> Vec<String> {
        let mut v = Vec::new();
        for a in &self.args {
            match a {
                Arg::Word(w) => v.push(w.clone()),
                Arg::Opt(n, None) => v.push(n.to_string()),
                Arg::Opt(n, Some(x)) if x.is_empty() || x.starts_with('-') => {
                    v.push(format!("{n}={x}"))
                }
                Arg::Opt(n, Some(x)) => {
                    v.push(n.to_string());
                    v.push(x.clone());
                }
            }
        }
        v
    }

    fn has(&self, name: &str) -> bool {
        self.args
            .iter()
            .any(|a| matches!(a, Arg::Opt(n, _) if *n == name))
    }

    /// Sets option `name` (replacing its value if present, else appending it).
    fn set(&mut self, name: &'static str, value: Option<String>) {
        match self
            .args
            .iter_mut()
            .find(|a| matches!(a, Arg::Opt(n, _) if *n == name))
        {
            Some(a) => *a = Arg::Opt(name, value),
            None => self.args.push(Arg::Opt(name, value)),
        }
    }

    fn file(&mut self, name: &str, asset_path: &str) -> Arg {
        self.files.push((name.to_string(), asset(asset_path)));
        Arg::Word(name.to_string())
    }
}

/// How an option's values are drawn.
#[derive(Clone, Copy)]
enum Kind {
    /// A real number: the wild-value pool.
    Float,
    /// A count: the wild-integer pool.
    Int,
    /// A flag without a value.
    Flag,
    /// A choice: mostly its valid values, sometimes an invalid one.
    Choice(&'static [&'static str]),
    /// Option-specific values (plausible ones beside wild ones).
    Values(&'static [&'static str]),
}

/// Real values that parse (clap passes them on to the program: the values worth most runs).
const FLOATS: &[&str] = &[
    "0", "-0", "-1", "1e-9", "1e-12", "1e6", "1e9", "1e300", "-1e300", "nan", "NaN", "inf", "-inf",
    "5e-324",
];
/// Counts that parse as `usize`.
const INTS: &[&str] = &[
    "0",
    "1",
    "2",
    "3",
    "1000000",
    "1000000000",
    "4294967296",
    "18446744073709551615",
];
/// Values no number parser takes: clap's refusals, drawn less often (see [`JUNK_P`]).
const JUNK: &[&str] = &[
    "abc",
    "",
    "1,2",
    "0x10",
    "-1",
    "1.5",
    "1e6",
    "18446744073709551616",
    " 1",
];
/// The chance that a number option gets a value from [`JUNK`].
const JUNK_P: f64 = 0.15;
const PAIRS: &[&str] = &[
    "0,0",
    "nan,0",
    "0,inf",
    "1e9,1e9",
    "-1e300,0",
    "1e-12,1e-12",
    "1",
    "1,2,3",
    "a,b",
    "",
    ",",
];
const MODULES: &[&str] = &[
    "0.5", "1", "2", "3", "10", "0.1", "0.01", "0", "-2", "nan", "inf", "1e-9", "1e6", "x",
];
const TEETH: &[&str] = &[
    "3", "5", "20", "200", "5000", "0", "1", "2", "-20", "1000000", "nan", "x", "",
];
const STEPS: &[&str] = &["0", "1", "2", "10", "1000", "100000", "-1", "1e6", "x"];

const DESIGN_OPTS: &[(&str, Kind)] = &[
    ("--center", Kind::Values(PAIRS)),
    ("--order", Kind::Int),
    ("--tol-mm", Kind::Float),
    ("--refine", Kind::Choice(&["auto", "on", "off"])),
    ("--refine-order", Kind::Int),
    (
        "--harmonic",
        Kind::Values(&["0.1,0", "0.5,90", "nan,0", "1e9,0", "0,inf", "1", "a,b", ""]),
    ),
    ("--route", Kind::Choice(&["ac", "bd"])),
    ("--w1", Kind::Float),
    ("--k-max", Kind::Int),
    (
        "--grid",
        Kind::Values(&["64", "63", "65536", "65537", "0", "1000000", "-1", "x"]),
    ),
    ("--dense", Kind::Int),
    (
        "--samples",
        Kind::Values(&["720", "719", "0", "100000", "1000000", "-1", "x"]),
    ),
    (
        "--ratio-bounds",
        Kind::Values(&[
            "0.3,3.3", "3.3,0.3", "1,1", "0,0", "0.3,1e9", "-1,3", "nan,3", "0.9,1.1", "1",
        ]),
    ),
    ("--no-fit", Kind::Flag),
    ("--limits", Kind::Choice(&["on", "off"])),
    (
        "--max-pressure-angle",
        Kind::Values(&["0", "1", "30", "89.9", "90", "180", "-45", "nan", "inf"]),
    ),
    ("--min-concave-radius", Kind::Float),
    ("--min-convex-radius", Kind::Float),
    ("--convexity", Kind::Flag),
    ("--smooth", Kind::Int),
    ("--png", Kind::Flag),
    ("--json", Kind::Flag),
    ("--module", Kind::Values(MODULES)),
    (
        "--tooth-policy",
        Kind::Choice(&[
            "design",
            "scale-up",
            "nearest",
            "scale-down",
            "ratio-amplitude",
            "adjust-module",
        ]),
    ),
    ("--teeth", Kind::Values(TEETH)),
    ("--wire-edm", Kind::Flag),
    ("--verify-steps", Kind::Values(STEPS)),
    ("--pressure-angle", Kind::Float),
    ("--addendum", Kind::Float),
    ("--clearance", Kind::Float),
    ("--fillet", Kind::Float),
    ("--backlash", Kind::Float),
    ("--chord-tol", Kind::Float),
    ("--dxf-version", Kind::Choice(&["r2010", "r12"])),
    ("--face-width", Kind::Float),
    ("--bore", Kind::Float),
    ("--cutter-teeth", Kind::Int),
    ("--no-undercut", Kind::Flag),
];

/// Design options that act only on a toothed design: a mutation of one also asks for teeth.
const DESIGN_TEETH_OPTS: &[&str] = &[
    "--tooth-policy",
    "--teeth",
    "--wire-edm",
    "--verify-steps",
    "--pressure-angle",
    "--addendum",
    "--clearance",
    "--fillet",
    "--backlash",
    "--chord-tol",
    "--dxf-version",
    "--face-width",
    "--bore",
    "--cutter-teeth",
    "--no-undercut",
];

const TRADEOFF_OPTS: &[(&str, Kind)] = &[("--center", Kind::Values(PAIRS)), ("--json", Kind::Flag)];

const PAIR_OPTS: &[(&str, Kind)] = &[
    (
        "--cycle-advance",
        Kind::Values(&[
            "360", "180", "720", "120", "0", "-360", "1e-9", "nan", "inf", "x",
        ]),
    ),
    (
        "--drive-start",
        Kind::Values(&["0", "10", "350", "-10", "360", "1e9", "nan", "inf", "x"]),
    ),
    (
        "--drive-end",
        Kind::Values(&[
            "120", "360", "370", "0", "1e-9", "720", "1e9", "nan", "-inf",
        ]),
    ),
    ("--open", Kind::Flag),
    ("--teeth", Kind::Values(TEETH)),
    ("--module", Kind::Values(MODULES)),
    ("--pressure-angle", Kind::Float),
    ("--addendum", Kind::Float),
    ("--clearance", Kind::Float),
    ("--fillet", Kind::Float),
    ("--backlash", Kind::Float),
    ("--chord-tol", Kind::Float),
    ("--dxf-version", Kind::Choice(&["r2010", "r12"])),
    ("--face-width", Kind::Float),
    ("--bore", Kind::Float),
    ("--cutter-teeth", Kind::Int),
    ("--no-undercut", Kind::Flag),
    ("--verify-steps", Kind::Values(STEPS)),
    ("--json", Kind::Flag),
];

/// Motion laws ψ(φ): valid ones, degenerate ones and syntax errors. None starts with `-`, which
/// clap would take for an option.
const LAWS: &[&str] = &[
    "phi - 0.08*sin(2*phi)",
    "phi + 0.3*sin(phi)",
    "2*phi",
    "phi/2",
    "phi",
    "0",
    "phi*pi",
    "phi - 0.99*sin(phi)",
    "phi - 1.5*sin(phi)",
    "phi/0",
    "sqrt(phi - 3)",
    "tan(phi)",
    "exp(phi)",
    "phi*1e9",
    "phi + 1e-12*sin(phi)",
    "phi^phi",
    "abs(phi - pi)",
    "phi +",
    "sin(",
    "",
    "x",
];

const CENTRODES: &[&str] = &[
    "1 + 0.08*cos(2*phi)",
    "1 + 0.3*cos(phi)",
    "1",
    "0",
    "1 - 2*cos(phi)",
    "1 + 0.99*cos(3*phi)",
    "1/0",
    "phi",
    "1e-12",
    "1e12 + cos(phi)",
    "cos(",
    "",
];

const SYNTHESIZE_OPTS: &[(&str, Kind)] = &[("--json", Kind::Flag), ("--accept-failed", Kind::Flag)];

const SIMULATE_OPTS: &[(&str, Kind)] = &[
    ("--rpm", Kind::Float),
    ("--speed", Kind::Float),
    ("--spacing", Kind::Float),
    ("--depth", Kind::Float),
    ("--take-level", Kind::Float),
    ("--plant-level", Kind::Float),
    ("--frames", Kind::Values(STEPS)),
    ("--duration", Kind::Float),
    ("--json", Kind::Flag),
    ("--module", Kind::Values(MODULES)),
];

const LOADS_OPTS: &[(&str, Kind)] = &[
    ("--json", Kind::Flag),
    ("--png", Kind::Flag),
    ("--accept-failed", Kind::Flag),
];

const TOLERANCE_OPTS: &[(&str, Kind)] = &[
    (
        "--samples",
        Kind::Values(&["0", "1", "2", "100", "1000000", "-1", "1e6", "x"]),
    ),
    ("--seed", Kind::Int),
    (
        "--starts",
        Kind::Values(&["0", "1", "100", "100000", "-1", "x"]),
    ),
    ("--feature-samples", Kind::Values(STEPS)),
    ("--validation-samples", Kind::Values(STEPS)),
    ("--json", Kind::Flag),
];

const ORBIT_MODEL_OPTS: &[(&str, Kind)] = &[
    ("--json", Kind::Flag),
    (
        "--plot",
        Kind::Values(&["orbit.svg", "orbit.png", "orbit.txt", "", "nodir/orbit.svg"]),
    ),
];

const ORBIT_SIGNAL_OPTS: &[(&str, Kind)] = &[
    ("--planet-speed-rpm", Kind::Float),
    ("--frame", Kind::Choice(&["carrier", "derotate", "housing"])),
    ("--carrier-speed-rpm", Kind::Float),
    ("--method", Kind::Choice(&["ls", "hann", "sync", "fft"])),
    ("--line-hz", Kind::Float),
    (
        "--mesh-harmonics",
        Kind::Values(&["0", "1", "5", "50", "1000", "-1", "1000000", "x"]),
    ),
    ("--no-drift", Kind::Flag),
    ("--estimate-frequency", Kind::Flag),
    ("--max-condition", Kind::Float),
    ("--json", Kind::Flag),
];

const ORBIT_MEASURE_OPTS: &[(&str, Kind)] = &[
    ("--plot-dir", Kind::Values(&["plots", "", "plots/deeper"])),
    ("--png", Kind::Flag),
];

const ORBIT_IDENTIFY_OPTS: &[(&str, Kind)] = &[
    (
        "--sin-pair",
        Kind::Values(&[
            "10,0,10,90",
            "0,0,0,0",
            "nan,0,10,90",
            "1e300,0,1e300,0",
            "10,0,10",
            "-10,0,10,90",
            "a,b,c,d",
            "",
        ]),
    ),
    (
        "--te",
        Kind::Values(&["1,0", "0,0", "nan,0", "1e300,inf", "1", "a,b", ""]),
    ),
];

const DYNAMICS_OPTS: &[(&str, Kind)] = &[
    (
        "--sweep",
        Kind::Values(&[
            "0.6:1.0:0.02",
            "0.6:1.0:0",
            "1.0:0.6:0.02",
            "0.6:1.0:-0.02",
            "0.6:1.0:1e-9",
            "0:0:0",
            "0:1e9:1",
            "nan:1:0.1",
            "0.6:inf:0.1",
            "0.6:1.0",
            "a:b:c",
            "",
        ]),
    ),
    ("--format", Kind::Choice(&["svg", "png"])),
    ("--json", Kind::Flag),
];

/// Design targets whose toothed design (m = 2) takes 3.5–5.3 s of CPU: the campaign does not add
/// teeth to them itself, so that a run killed at the limit is a finding, not a slow baseline.
const SLOW_TEETH: &[&str] = &["exact_concave_sun.csv", "designer_kidney.csv"];

/// G1's trajectory in the JSON trajectory format (`{"units": "mm", "points": [[x, y], ...]}`):
/// the JSON reader and its mutations on a target that designs in milliseconds.
fn g1_json() -> Vec<u8> {
    let csv = String::from_utf8(asset("trajectories/g1_ellipse.csv")).unwrap();
    let points: Vec<Point> = csv
        .lines()
        .filter_map(|l| {
            let (x, y) = l.split_once(',')?;
            Some(Point::new(x.trim().parse().ok()?, y.trim().parse().ok()?))
        })
        .collect();
    assert_eq!(points.len(), 360, "G1 has one point per carrier degree");
    serde_json::json!({"units": "mm", "points": points})
        .to_string()
        .into_bytes()
}

/// Which subcommand run k exercises: a fixed cycle of 20, so any 20 consecutive runs cover every
/// subcommand, weighted toward the cheap and option-rich ones (`tradeoff` costs seconds a run).
const SCHEDULE: [&str; 20] = [
    "pair",
    "design",
    "orbit",
    "dynamics",
    "simulate",
    "tolerance",
    "pair",
    "design",
    "tradeoff",
    "orbit",
    "dynamics",
    "simulate",
    "tolerance",
    "loads",
    "design",
    "orbit",
    "synthesize",
    "simulate",
    "tolerance",
    "dynamics",
];

fn pick<T: Copy>(rng: &mut ChaCha8Rng, items: &[T]) -> T {
    *items.choose(rng).expect("a non-empty pool")
}

/// An unmutated, valid run of subcommand `sub`; returns it with the option pool its mutations
/// draw from.
fn baseline(sub: &str, rng: &mut ChaCha8Rng) -> (Spec, &'static [(&'static str, Kind)]) {
    let mut s = Spec {
        index: 0,
        sub: "",
        args: Vec::new(),
        files: Vec::new(),
        mutations: Vec::new(),
    };
    let w = |x: &str| Arg::Word(x.to_string());
    let out = || Arg::Opt("--out", Some("out".to_string()));
    let pool: &'static [(&'static str, Kind)] = match sub {
        "design" => {
            // Fast targets (≤ 0.1 s untoothed, ≤ 2.2 s CPU at m = 2): G1 as CSV and as JSON, the
            // exact and noisy cases; the kidney (2.2 s) and the concave sun only untoothed (see
            // SLOW_TEETH). asymmetric_cw.json takes 5 s untoothed: too close to the limit.
            let traj = pick(
                rng,
                &[
                    "trajectories/g1_ellipse.csv",
                    "trajectories/g1_ellipse.csv",
                    "trajectories/g1_ellipse.json",
                    "trajectories/g1_ellipse.json",
                    "cases/exact_two_harmonic.csv",
                    "cases/exact_sparse_200.csv",
                    "cases/exact_concave_sun.csv",
                    "cases/noisy_020um.csv",
                    "cases/noisy_050um.csv",
                    "trajectories/designer_kidney.csv",
                ],
            );
            let name = Path::new(traj).file_name().unwrap().to_str().unwrap();
            let f = if name == "g1_ellipse.json" {
                s.files.push((name.to_string(), g1_json()));
                w(name)
            } else {
                s.file(name, traj)
            };
            s.sub = "design";
            s.args = vec![w("design"), f, out()];
            if !SLOW_TEETH.contains(&name) && rng.random_bool(0.3) {
                s.set("--module", Some("2".into()));
            }
            if rng.random_bool(0.3) {
                s.set("--json", None);
            }
            DESIGN_OPTS
        }
        "tradeoff" => {
            // Targets whose tradeoff takes ≈ 4 s on one thread; the exact cases take 6–27 s, too
            // close to or over the limit for a baseline.
            let traj = pick(
                rng,
                &["trajectories/g1_ellipse.csv", "cases/noisy_020um.csv"],
            );
            let name = Path::new(traj).file_name().unwrap().to_str().unwrap();
            let f = s.file(name, traj);
            s.sub = "tradeoff";
            s.args = vec![w("tradeoff"), f, out()];
            if rng.random_bool(0.3) {
                s.set("--json", None);
            }
            TRADEOFF_OPTS
        }
        "pair" => {
            s.sub = "pair";
            s.args = match rng.random_range(0..5) {
                0 | 1 => vec![w("pair"), w(LAWS[0])],
                2 => vec![w("pair"), Arg::Opt("--centrode", Some(CENTRODES[0].into()))],
                3 => {
                    let f = s.file("law.csv", "pair/law.csv");
                    vec![w("pair"), Arg::Opt("--csv", None), f]
                }
                _ => vec![
                    w("pair"),
                    w(LAWS[0]),
                    Arg::Opt("--open", None),
                    Arg::Opt("--drive-start", Some("0".into())),
                    Arg::Opt("--drive-end", Some("120".into())),
                ],
            };
            s.args.push(Arg::Opt(
                "--teeth",
                Some(if s.has("--open") { "10" } else { "20" }.into()),
            ));
            s.args.push(out());
            if rng.random_bool(0.3) {
                s.set("--json", None);
            }
            PAIR_OPTS
        }
        "synthesize" => {
            // Poses (0.1 s) or target bands alone (2 s).
            let (name, asset) = pick(
                rng,
                &[
                    ("g1_five_poses.toml", "synthesis/g1_five_poses.toml"),
                    ("rice_targets.toml", "synthesis/rice_targets.toml"),
                ],
            );
            let f = s.file(name, asset);
            s.sub = "synthesize";
            s.args = vec![w("synthesize"), f, out()];
            if rng.random_bool(0.3) {
                s.set("--json", None);
            }
            SYNTHESIZE_OPTS
        }
        "simulate" => {
            let f = s.file("g1_design.json", "transplanter/g1_design.json");
            s.sub = "simulate";
            s.args = vec![w("simulate"), f, out()];
            if rng.random_bool(0.3) {
                let t = s.file("g1_ellipse.csv", "trajectories/g1_ellipse.csv");
                s.args.push(Arg::Opt("--target", None));
                s.args.push(t);
            }
            if rng.random_bool(0.2) {
                s.set("--spacing", Some("140".into()));
            }
            if rng.random_bool(0.3) {
                s.set("--json", None);
            }
            SIMULATE_OPTS
        }
        "tolerance" => {
            s.sub = "tolerance";
            if rng.random_bool(0.5) {
                let f = s.file("paper_3k.toml", "tolerance/paper_3k.toml");
                s.args = vec![w("tolerance"), f, out()];
            } else {
                let d = s.file("g1_design.json", "transplanter/g1_design.json");
                let e = s.file("g1_errors.toml", "transplanter/g1_errors.toml");
                s.args = vec![w("tolerance"), d, Arg::Opt("--errors", None), e, out()];
            }
            if rng.random_bool(0.3) {
                s.set("--json", None);
            }
            TOLERANCE_OPTS
        }
        "orbit" => {
            let (model_name, model_asset) = if rng.random_bool(0.7) {
                ("model.toml", "orbit/model.toml")
            } else {
                ("model.json", "orbit/model.json")
            };
            let json = rng.random_bool(0.5);
            let pool = match rng.random_range(0..3) {
                0 => {
                    let m = s.file(model_name, model_asset);
                    s.sub = "orbit model";
                    s.args = vec![w("orbit"), w("model"), m];
                    if rng.random_bool(0.3) {
                        s.set("--plot", Some("orbit.svg".into()));
                    }
                    ORBIT_MODEL_OPTS
                }
                1 => {
                    let sig = s.file("signals.csv", "orbit/signals.csv");
                    s.sub = "orbit measure";
                    s.args = vec![w("orbit"), w("measure"), sig];
                    if rng.random_bool(0.8) {
                        let m = s.file("model.toml", "orbit/model.toml");
                        s.args.push(Arg::Opt("--model", None));
                        s.args.push(m);
                        s.set("--frame", Some("derotate".into()));
                    } else {
                        s.set("--planet-speed-rpm", Some("100".into()));
                    }
                    if rng.random_bool(0.3) {
                        s.set("--plot-dir", Some("plots".into()));
                    }
                    ORBIT_MEASURE_OPTS
                }
                _ => {
                    let m = s.file(model_name, model_asset);
                    s.sub = "orbit identify";
                    s.args = vec![w("orbit"), w("identify"), Arg::Opt("--model", None), m];
                    if model_name == "model.toml" && rng.random_bool(0.5) {
                        let sig = s.file("signals.csv", "orbit/signals.csv");
                        s.args.push(Arg::Opt("--signals", None));
                        s.args.push(sig);
                        s.set("--frame", Some("derotate".into()));
                    } else {
                        s.set("--sin-pair", Some("10,0,10,90".into()));
                    }
                    ORBIT_IDENTIFY_OPTS
                }
            };
            if json {
                s.set("--json", None);
            }
            pool
        }
        "loads" => {
            // The bundled rotor on the bundled G1 train at module 2 (its design file beside the
            // scene): the teeth made again and rated, 0.1 s; or the loads alone.
            let scene = s.file("g1_rotor.toml", "loads/g1_rotor.toml");
            s.file("g1_m2_design.json", "loads/g1_m2_design.json");
            if rng.random_bool(0.3) {
                let text = String::from_utf8(s.files[0].1.clone()).unwrap();
                let cut = text.find("[material]").unwrap_or(text.len());
                s.files[0].1 = text.as_bytes()[..cut].to_vec();
            }
            s.sub = "loads";
            s.args = vec![w("loads"), scene, out()];
            if rng.random_bool(0.3) {
                s.set("--json", None);
            }
            LOADS_OPTS
        }
        "dynamics" => {
            let scene = pick(
                rng,
                &[
                    "backlash_oscillator.toml",
                    "full16.toml",
                    "full16_hertz.toml",
                    "sdof_6000.toml",
                    "torsional4.toml",
                ],
            );
            let f = s.file(scene, &format!("dynamics/{scene}"));
            s.sub = "dynamics";
            s.args = vec![w("dynamics"), f, out()];
            if scene == "backlash_oscillator.toml" && rng.random_bool(0.4) {
                s.set("--sweep", Some("0.6:1.0:0.02".into()));
            }
            if rng.random_bool(0.5) {
                s.set("--json", None);
            }
            DYNAMICS_OPTS
        }
        _ => unreachable!("unknown subcommand {sub}"),
    };
    (s, pool)
}

/// The orbit subcommands share the signal-analysis options; the others have one pool each.
fn option_pool(s: &Spec, own: &'static [(&'static str, Kind)]) -> Vec<(&'static str, Kind)> {
    let mut v = own.to_vec();
    if s.sub == "orbit measure" || s.sub == "orbit identify" {
        v.extend_from_slice(ORBIT_SIGNAL_OPTS);
    }
    v
}

/// Mutates one option of `s`: a new or replaced value drawn for its kind, a flag toggled, or the
/// positional law / centrode of `pair` replaced.
fn mutate_option(s: &mut Spec, pool: &[(&'static str, Kind)], rng: &mut ChaCha8Rng) {
    if s.sub == "pair" && rng.random_bool(0.2) {
        // The law or centrode itself.
        if let Some(i) = s.args.iter().position(|a| *a == Arg::Word(LAWS[0].into())) {
            let law = pick(rng, LAWS);
            s.args[i] = Arg::Word(law.into());
            s.mutations.push(format!("law {law:?}"));
            return;
        }
        if s.has("--centrode") {
            let c = pick(rng, CENTRODES);
            s.set("--centrode", Some(c.into()));
            s.mutations.push(format!("--centrode {c:?}"));
            return;
        }
    }
    let (name, kind) = pick(rng, pool);
    let value = match kind {
        Kind::Flag => {
            if s.has(name) {
                s.args
                    .retain(|a| !matches!(a, Arg::Opt(n, _) if *n == name));
                s.mutations.push(format!("{name} removed"));
                return;
            }
            None
        }
        Kind::Float | Kind::Int if rng.random_bool(JUNK_P) => Some(pick(rng, JUNK)),
        Kind::Float => Some(pick(rng, FLOATS)),
        Kind::Int => Some(pick(rng, INTS)),
        Kind::Values(v) => Some(pick(rng, v)),
        Kind::Choice(v) => Some(if rng.random_bool(0.85) {
            pick(rng, v)
        } else {
            pick(rng, &["bogus", "", "ON"])
        }),
    };
    s.set(name, value.map(String::from));
    s.mutations.push(match value {
        Some(v) => format!("{name} {v:?}"),
        None => format!("{name} added"),
    });
    // A teeth option of `design` acts only with a module (not added where teeth take seconds).
    if s.sub == "design"
        && DESIGN_TEETH_OPTS.contains(&name)
        && !s.has("--module")
        && !s.files.iter().any(|f| SLOW_TEETH.contains(&f.0.as_str()))
        && rng.random_bool(0.7)
    {
        s.set("--module", Some("2".into()));
    }
}

const WILD_CELLS: &[&str] = &[
    "nan", "NaN", "inf", "-inf", "abc", "", "1e300", "-1e300", "1e9", "0", "1e-12",
];

/// Line-level mutations of a CSV file (header kept when the first line is not numeric).
fn mutate_csv(text: &str, rng: &mut ChaCha8Rng) -> (String, String) {
    let lines: Vec<&str> = text.lines().collect();
    let numeric = |l: &str| {
        l.split(',')
            .next()
            .is_some_and(|c| c.trim().parse::<f64>().is_ok())
    };
    let head = lines.iter().take_while(|l| !numeric(l)).count();
    let (header, rows) = lines.split_at(head);
    let mut rows: Vec<String> = rows.iter().map(|r| r.to_string()).collect();
    let n = rows.len().max(1);
    let what = match rng.random_range(0..10) {
        0 => {
            let a = rng.random_range(0..n);
            let k = rng.random_range(1..=n.div_ceil(2));
            let b = (a + k).min(rows.len());
            rows.drain(a.min(rows.len())..b);
            format!("rows {a}..{b} dropped")
        }
        1 => {
            let k = rng.random_range(0..4usize);
            rows.truncate(k);
            format!("only {k} rows kept")
        }
        2 => {
            let i = rng.random_range(0..n).min(rows.len().saturating_sub(1));
            let times = pick(rng, &[1usize, 5, 500]);
            if let Some(r) = rows.get(i).cloned() {
                for _ in 0..times {
                    rows.insert(i, r.clone());
                }
            }
            format!("row {i} duplicated ×{times}")
        }
        3 | 4 => {
            let i = rng.random_range(0..n).min(rows.len().saturating_sub(1));
            let cell = pick(rng, WILD_CELLS);
            let mut col = 0;
            if let Some(r) = rows.get_mut(i) {
                let mut cells: Vec<String> = r.split(',').map(String::from).collect();
                col = rng.random_range(0..cells.len());
                cells[col] = cell.to_string();
                *r = cells.join(",");
            }
            format!("row {i} column {col} = {cell:?}")
        }
        5 => {
            for r in rows.iter_mut() {
                let mut cells: Vec<&str> = r.split(',').collect();
                if cells.len() >= 2 {
                    cells.swap(0, 1);
                }
                *r = cells.join(",");
            }
            "columns 0 and 1 swapped".to_string()
        }
        6 => {
            let i = rng.random_range(0..n).min(rows.len().saturating_sub(1));
            if let Some(r) = rows.get(i).cloned() {
                rows.iter_mut().for_each(|x| *x = r.clone());
            }
            format!("every row = row {i}")
        }
        7 => {
            let f = pick(rng, &[1e9, 1e-9, -1.0, 0.0]);
            for r in rows.iter_mut() {
                *r = r
                    .split(',')
                    .map(|c| {
                        c.trim()
                            .parse::<f64>()
                            .map_or(c.to_string(), |x| (x * f).to_string())
                    })
                    .collect::<Vec<_>>()
                    .join(",");
            }
            format!("every number ×{f}")
        }
        8 => {
            for r in rows.iter_mut() {
                *r = r.split(',').next().unwrap_or("").to_string();
            }
            "only the first column kept".to_string()
        }
        _ => {
            rows.reverse();
            "rows reversed".to_string()
        }
    };
    let mut out: Vec<String> = header.iter().map(|h| h.to_string()).collect();
    out.extend(rows);
    (out.join("\n") + "\n", what)
}

/// Replacement values for a JSON leaf; the `__NaN__`-style strings become bare tokens afterwards,
/// since serde_json cannot write a non-finite number.
fn wild_json(rng: &mut ChaCha8Rng) -> serde_json::Value {
    use serde_json::json;
    match rng.random_range(0..14) {
        0 => json!(0),
        1 => json!(-1),
        2 => json!(1e-12),
        3 => json!(1e300),
        4 => json!(-1e300),
        5 => json!("text"),
        6 => json!(null),
        7 => json!(true),
        8 => json!([]),
        9 => json!({}),
        10 => json!("__NaN__"),
        11 => json!(1e308),
        12 => json!(-0.5),
        _ => json!("__Infinity__"),
    }
}

/// Mutates one node of a JSON document: removed, replaced by a wild value, or (an array)
/// truncated or reversed. Descends into a random child with probability 0.7 at each level.
fn mutate_json_node(v: &mut serde_json::Value, rng: &mut ChaCha8Rng, path: String) -> String {
    use serde_json::Value;
    let keys: Vec<String> = match v {
        Value::Object(m) => m.keys().cloned().collect(),
        Value::Array(a) => (0..a.len()).map(|i| i.to_string()).collect(),
        _ => Vec::new(),
    };
    let Some(key) = keys.choose(rng).cloned() else {
        *v = wild_json(rng);
        return format!("{path} = {v}");
    };
    let child_path = format!("{path}/{key}");
    let child = match v {
        Value::Object(m) => m.get_mut(&key).unwrap(),
        Value::Array(a) => &mut a[key.parse::<usize>().unwrap()],
        _ => unreachable!(),
    };
    let container_len = match child {
        Value::Object(m) => m.len(),
        Value::Array(a) => a.len(),
        _ => 0,
    };
    if container_len > 0 && rng.random_bool(0.7) {
        return mutate_json_node(child, rng, child_path);
    }
    match rng.random_range(0..4) {
        0 => {
            match v {
                Value::Object(m) => {
                    m.remove(&key);
                }
                Value::Array(a) => {
                    a.remove(key.parse::<usize>().unwrap());
                }
                _ => {}
            }
            format!("{child_path} removed")
        }
        1 if matches!(child, Value::Array(_)) => {
            let a = child.as_array_mut().unwrap();
            let k = pick(rng, &[0, 1, 2, a.len() / 2]);
            a.truncate(k);
            format!("{child_path} truncated to {k}")
        }
        2 if matches!(child, Value::Array(_)) => {
            child.as_array_mut().unwrap().reverse();
            format!("{child_path} reversed")
        }
        _ => {
            *child = wild_json(rng);
            format!("{child_path} = {child}")
        }
    }
}

fn wild_toml(rng: &mut ChaCha8Rng) -> toml::Value {
    use toml::Value;
    match rng.random_range(0..15) {
        0 => Value::Integer(0),
        1 => Value::Integer(-1),
        2 => Value::Integer(i64::MAX),
        3 => Value::Float(f64::NAN),
        4 => Value::Float(f64::INFINITY),
        5 => Value::Float(f64::NEG_INFINITY),
        6 => Value::Float(1e-12),
        7 => Value::Float(1e12),
        8 => Value::Float(1e300),
        9 => Value::String("text".into()),
        10 => Value::Boolean(true),
        11 => Value::Float(1e308),
        12 => Value::Float(-1e308),
        13 => Value::Float(-0.5),
        _ => Value::Array(Vec::new()),
    }
}

/// As [`mutate_json_node`], for a TOML table: keys removed or set to wild values, arrays cut.
fn mutate_toml_table(t: &mut toml::Table, rng: &mut ChaCha8Rng, path: String) -> String {
    let keys: Vec<String> = t.keys().cloned().collect();
    let Some(key) = keys.choose(rng).cloned() else {
        t.insert("unknown_key".into(), wild_toml(rng));
        return format!("{path}/unknown_key added");
    };
    let child_path = format!("{path}/{key}");
    let child = t.get_mut(&key).unwrap();
    match child {
        toml::Value::Table(sub) if !sub.is_empty() && rng.random_bool(0.7) => {
            return mutate_toml_table(sub, rng, child_path);
        }
        toml::Value::Array(a) if !a.is_empty() && rng.random_bool(0.6) => {
            let i = rng.random_range(0..a.len());
            if let toml::Value::Table(sub) = &mut a[i]
                && rng.random_bool(0.7)
            {
                return mutate_toml_table(sub, rng, format!("{child_path}/{i}"));
            }
            let k = pick(rng, &[0, 1, a.len() / 2]);
            a.truncate(k);
            return format!("{child_path} truncated to {k}");
        }
        _ => {}
    }
    if rng.random_bool(0.3) {
        t.remove(&key);
        format!("{child_path} removed")
    } else {
        let w = wild_toml(rng);
        let shown = w.to_string();
        t.insert(key, w);
        format!("{child_path} = {shown}")
    }
}

/// Mutates file `i` of `s`: whole-file damage (empty, truncated, missing, a line duplicated) or a
/// format-aware change (CSV rows and cells, JSON and TOML keys and values).
fn mutate_file(s: &mut Spec, rng: &mut ChaCha8Rng) {
    let i = rng.random_range(0..s.files.len());
    let name = s.files[i].0.clone();
    let text = String::from_utf8_lossy(&s.files[i].1).into_owned();
    let what = match rng.random_range(0..12) {
        0 => {
            s.files[i].1.clear();
            "emptied".to_string()
        }
        1 => {
            let k = rng.random_range(0..s.files[i].1.len().max(1));
            s.files[i].1.truncate(k);
            format!("truncated at byte {k}")
        }
        2 => {
            s.files.remove(i);
            s.mutations.push(format!("{name} missing"));
            return;
        }
        3 => {
            let lines: Vec<&str> = text.lines().collect();
            let j = rng.random_range(0..lines.len().max(1));
            let mut out = lines.clone();
            if let Some(l) = lines.get(j) {
                out.insert(j, l);
            }
            s.files[i].1 = (out.join("\n") + "\n").into_bytes();
            format!("line {j} duplicated")
        }
        _ => {
            // Format-aware; a file an earlier mutation already broke gets a line duplicated.
            let structured = if name.ends_with(".csv") {
                Some(mutate_csv(&text, rng))
            } else if name.ends_with(".json") {
                serde_json::from_str::<serde_json::Value>(&text)
                    .ok()
                    .map(|mut v| {
                        let w = mutate_json_node(&mut v, rng, String::new());
                        let t = v
                            .to_string()
                            .replace("\"__NaN__\"", "NaN")
                            .replace("\"__Infinity__\"", "Infinity");
                        (t, w)
                    })
            } else {
                toml::from_str::<toml::Table>(&text).ok().map(|mut t| {
                    let w = mutate_toml_table(&mut t, rng, String::new());
                    (t.to_string(), w)
                })
            };
            let (t, w) = structured.unwrap_or_else(|| {
                let mut lines: Vec<&str> = text.lines().collect();
                if let Some(l) = lines.first().copied() {
                    lines.push(l);
                }
                (
                    lines.join("\n"),
                    "first line repeated at the end".to_string(),
                )
            });
            s.files[i].1 = t.into_bytes();
            w
        }
    };
    s.mutations.push(format!("{name}: {what}"));
}

/// Run `index` of the campaign for `seed`: a pure function of both, so a run can be replayed alone.
fn spec(seed: u64, index: usize) -> Spec {
    let mut key = [0u8; 32];
    key[..8].copy_from_slice(&seed.to_le_bytes());
    key[8..16].copy_from_slice(&(index as u64).to_le_bytes());
    let mut rng = ChaCha8Rng::from_seed(key);
    let sub = SCHEDULE[index % SCHEDULE.len()];
    let (mut s, own) = baseline(sub, &mut rng);
    s.index = index;
    let pool = option_pool(&s, own);
    // One run in seven is a valid baseline; the others take one to three mutations.
    let n = if rng.random_bool(1.0 / 7.0) {
        0
    } else {
        pick(&mut rng, &[1, 1, 1, 2, 2, 3])
    };
    for _ in 0..n {
        if !s.files.is_empty() && rng.random_bool(0.45) {
            mutate_file(&mut s, &mut rng);
        } else {
            mutate_option(&mut s, &pool, &mut rng);
        }
    }
    s
}

// ---------------------------------------------------------------------------------------------
// The campaign.

fn env_or<T: std::str::FromStr>(name: &str, default: T) -> T {
    match std::env::var(name) {
        Ok(v) => v
            .trim()
            .parse()
            .unwrap_or_else(|_| panic!("{name}={v:?} is not a valid value")),
        Err(_) => default,
    }
}

/// One finished campaign run.
struct Record {
    spec: Spec,
    argv: Vec<String>,
    outcome: Outcome,
    violations: Vec<String>,
    dir: PathBuf,
}

#[test]
#[ignore = "a campaign of minutes: cargo test --release --test fuzz -- --ignored"]
fn campaign() {
    let runs: usize = env_or("NCGEAR_FUZZ_RUNS", 300);
    let seed: u64 = env_or("NCGEAR_FUZZ_SEED", 1);
    let limit = Duration::from_secs_f64(env_or("NCGEAR_FUZZ_LIMIT_S", LIMIT.as_secs_f64()));
    let mem_mb: u64 = env_or("NCGEAR_FUZZ_MEM_MB", MEMORY_BUDGET_MB);
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let jobs: usize = env_or("NCGEAR_FUZZ_JOBS", cores).max(1);
    let indices: Vec<usize> = match std::env::var("NCGEAR_FUZZ_ONLY") {
        Ok(v) => v
            .split(',')
            .map(|x| x.trim().parse().expect("NCGEAR_FUZZ_ONLY: run indices"))
            .collect(),
        Err(_) => (0..runs).collect(),
    };
    // Parallel runs each get one rayon thread, so that they do not fight over the cores and a
    // run's time does not depend on its neighbour (the time limit is an invariant).
    let env: Vec<(&str, &str)> = if jobs > 1 {
        vec![("RAYON_NUM_THREADS", "1")]
    } else {
        Vec::new()
    };
    let root = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("fuzz")
        .join(format!("seed-{seed}"));
    let _ = std::fs::remove_dir_all(&root);

    let start = Instant::now();
    let next = AtomicUsize::new(0);
    let records: Mutex<Vec<Record>> = Mutex::new(Vec::new());
    std::thread::scope(|scope| {
        for _ in 0..jobs {
            scope.spawn(|| {
                loop {
                    let k = next.fetch_add(1, Ordering::SeqCst);
                    let Some(&index) = indices.get(k) else { break };
                    let spec = spec(seed, index);
                    let dir = root.join(format!("run-{index:04}"));
                    std::fs::create_dir_all(&dir).expect("run directory");
                    for (name, bytes) in &spec.files {
                        std::fs::write(dir.join(name), bytes).expect("input file");
                    }
                    let argv = spec.argv();
                    let limit = if shows_progress(&argv) {
                        limit.max(PROGRESS_LIMIT)
                    } else {
                        limit
                    };
                    let outcome = execute(&argv, &dir, &env, limit, mem_mb);
                    let inputs: Vec<String> = spec.files.iter().map(|f| f.0.clone()).collect();
                    let mut violations = violations(&outcome, &argv, &dir, &inputs);
                    // A valid input is designed and written: exit 0, or 3 when its result fails
                    // its own verification (a drawn or noisy target misses --tol-mm: C12).
                    if nonfinite_in_a_file(&spec.mutations) && outcome.code != Some(2) {
                        violations.push(format!(
                            "a non-finite number in an input file was not refused (exit {:?}): {}",
                            outcome.code,
                            first_line(&outcome.stderr)
                        ));
                    }
                    if spec.mutations.is_empty() && !matches!(outcome.code, Some(0 | 3)) {
                        violations.push(format!(
                            "valid baseline exited {:?}: {}",
                            outcome.code,
                            first_line(&outcome.stderr)
                        ));
                    }
                    // Keep a failing run's directory (its mutated inputs reproduce it).
                    if violations.is_empty() {
                        let _ = std::fs::remove_dir_all(&dir);
                    }
                    records.lock().unwrap().push(Record {
                        spec,
                        argv,
                        outcome,
                        violations,
                        dir,
                    });
                }
            });
        }
    });
    let mut records = records.into_inner().unwrap();
    records.sort_by_key(|r| r.spec.index);
    let report = summary(&records, seed, limit, jobs, &env, start.elapsed());
    println!("{report}");
    let _ = std::fs::create_dir_all(&root);
    let _ = std::fs::write(root.join("summary.txt"), &report);
    // Every run, one line each, for what the summary leaves out (which refusals, how long).
    let mut log =
        String::from("index\tsubcommand\texit\tseconds\tcpu_s\tcommand\tmutations\tstderr\n");
    for r in &records {
        let _ = writeln!(
            log,
            "{}\t{}\t{:?}\t{:.3}\t{:.2}\t{}\t{}\t{}",
            r.spec.index,
            r.spec.sub,
            r.outcome.code,
            r.outcome.elapsed.as_secs_f64(),
            r.outcome.cpu_s,
            command_line(&[], &r.argv),
            r.spec.mutations.join("; "),
            short(first_line(&r.outcome.stderr), 200)
        );
    }
    let _ = std::fs::write(root.join("runs.tsv"), log);
    let bad = records.iter().filter(|r| !r.violations.is_empty()).count();
    assert!(
        bad == 0,
        "{bad} of {} runs broke an invariant (summary above, also in {})",
        records.len(),
        root.join("summary.txt").display()
    );
}

/// Whether a mutation set a number in an input file to a non-finite value (as [`mutate_file`]
/// describes it: `name: /key = nan`, `= inf`, `= -inf`, `= "__NaN__"`, `= "__Infinity__"`).
fn nonfinite_in_a_file(mutations: &[String]) -> bool {
    mutations.iter().any(|m| {
        m.split_once(": ").is_some_and(|(_, what)| {
            [
                "= nan",
                "= inf",
                "= -inf",
                "= \"__NaN__\"",
                "= \"__Infinity__\"",
            ]
            .iter()
            .any(|t| what.ends_with(t))
        })
    })
}

/// Runs per subcommand, the exit-code histogram, the slowest runs and every violation with the
/// command line that reproduces it, grouped by subcommand and first violation.
fn summary(
    records: &[Record],
    seed: u64,
    limit: Duration,
    jobs: usize,
    env: &[(&str, &str)],
    wall: Duration,
) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "ncgear fuzz campaign: seed {seed}, {} runs, limit {:.0} s, {jobs} jobs, {:.1} s wall\n\
         ncgear = {BIN}",
        records.len(),
        limit.as_secs_f64(),
        wall.as_secs_f64()
    );
    let exit_class = |o: &Outcome| -> String {
        if o.timed_out {
            "killed:time".into()
        } else if o.over_memory {
            "killed:memory".into()
        } else if let Some(sig) = o.signal {
            format!("signal {sig}")
        } else {
            format!("{}", o.code.unwrap_or(-1))
        }
    };
    let mut per_sub: BTreeMap<&str, (usize, usize, usize, f64)> = BTreeMap::new();
    let mut hist: BTreeMap<String, usize> = BTreeMap::new();
    for r in records {
        let e = per_sub.entry(r.spec.sub).or_default();
        e.0 += 1;
        e.1 += usize::from(r.spec.mutations.is_empty());
        e.2 += usize::from(!r.violations.is_empty());
        e.3 += r.outcome.elapsed.as_secs_f64();
        *hist.entry(exit_class(&r.outcome)).or_default() += 1;
    }
    let _ = writeln!(
        s,
        "\n{:<16}{:>6}{:>10}{:>12}{:>10}",
        "subcommand", "runs", "baseline", "violations", "time s"
    );
    for (sub, (n, base, bad, t)) in &per_sub {
        let _ = writeln!(s, "{sub:<16}{n:>6}{base:>10}{bad:>12}{t:>10.1}");
    }
    let _ = write!(s, "\nexit codes:");
    for (k, n) in &hist {
        let _ = write!(s, "  {k}: {n}");
    }
    if let Some(r) = records.iter().max_by_key(|r| r.outcome.peak_rss_mb) {
        let _ = write!(
            s,
            "\n\nlargest resident memory: {} MiB (run #{}, budget {} MiB)",
            r.outcome.peak_rss_mb, r.spec.index, MEMORY_BUDGET_MB
        );
    }
    let mut slow: Vec<&Record> = records.iter().collect();
    slow.sort_by_key(|r| std::cmp::Reverse(r.outcome.elapsed));
    let _ = writeln!(s, "\n\nslowest runs:");
    for r in slow.iter().take(5) {
        let _ = writeln!(
            s,
            "  #{} {:.2} s exit {}  {}",
            r.spec.index,
            r.outcome.elapsed.as_secs_f64(),
            exit_class(&r.outcome),
            command_line(&[], &r.argv)
        );
    }
    let bad: Vec<&Record> = records
        .iter()
        .filter(|r| !r.violations.is_empty())
        .collect();
    let _ = writeln!(s, "\nviolations: {} runs", bad.len());
    // Group by subcommand and the violation's kind (its text up to the first ':').
    let mut groups: BTreeMap<(&str, String), Vec<&Record>> = BTreeMap::new();
    for r in &bad {
        let kind = r.violations[0].split(':').next().unwrap_or("").to_string();
        groups.entry((r.spec.sub, kind)).or_default().push(r);
    }
    for ((sub, kind), rs) in &groups {
        let _ = writeln!(s, "\n[{sub}] {kind} ({} runs)", rs.len());
        for r in rs {
            let _ = writeln!(
                s,
                "  #{} {:.2} s exit {}: {}\n    (cd {} && {})\n    mutations: {}\n    stderr: {}",
                r.spec.index,
                r.outcome.elapsed.as_secs_f64(),
                exit_class(&r.outcome),
                r.violations.join("; "),
                r.dir.display(),
                command_line(env, &r.argv),
                if r.spec.mutations.is_empty() {
                    "none (baseline)".to_string()
                } else {
                    r.spec.mutations.join("; ")
                },
                short(first_line(&r.outcome.stderr), 200)
            );
        }
    }
    s
}

// ---------------------------------------------------------------------------------------------
// Tests of the harness itself (fast): a campaign that cannot fail proves nothing.

#[test]
fn same_seed_same_runs_and_every_subcommand_in_each_schedule_cycle() {
    let a: Vec<Spec> = (0..40).map(|i| spec(7, i)).collect();
    let b: Vec<Spec> = (0..40).map(|i| spec(7, i)).collect();
    assert!(a == b, "a seed must give the same command lines and files");
    let other: Vec<Vec<String>> = (0..40).map(|i| spec(8, i).argv()).collect();
    assert!(
        a.iter().map(Spec::argv).collect::<Vec<_>>() != other,
        "another seed must give other runs"
    );
    let subs: std::collections::BTreeSet<&str> = a[..20]
        .iter()
        .map(|s| s.sub.split(' ').next().unwrap())
        .collect();
    for sub in [
        "design",
        "tradeoff",
        "pair",
        "simulate",
        "tolerance",
        "orbit",
        "dynamics",
        "synthesize",
        "loads",
    ] {
        assert!(subs.contains(sub), "{sub} missing from the first 20 runs");
    }
    // Most runs are mutated, and both option and file mutations occur.
    let runs: Vec<Spec> = (0..300).map(|i| spec(1, i)).collect();
    let mutated = runs.iter().filter(|s| !s.mutations.is_empty()).count();
    assert!((200..300).contains(&mutated), "{mutated} of 300 mutated");
    let file_mutations = runs
        .iter()
        .flat_map(|s| &s.mutations)
        .filter(|m| m.contains(": ") || m.ends_with(" missing"))
        .count();
    assert!(file_mutations > 50, "{file_mutations} file mutations");
}

#[test]
fn harness_flags_a_hang_a_bad_exit_and_unclean_json() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fuzz-harness");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("out")).unwrap();
    let args = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    // A run over its limit is killed and reported (`sleep` stands for a hung run).
    #[cfg(unix)]
    {
        let o = run_watched(
            Path::new("sleep"),
            &args(&["5"]),
            &dir,
            &[],
            Duration::from_millis(200),
            4096,
        );
        assert!(o.timed_out && o.elapsed < Duration::from_secs(2), "{o:?}");
        let v = violations(&o, &[], &dir, &[]);
        assert!(v.len() == 1 && v[0].starts_with("timeout"), "{v:?}");
    }
    // Unknown subcommand: clap's exit 2 with a message is within the invariants.
    let a = args(&["no-such-subcommand"]);
    let o = execute(&a, &dir, &[], LIMIT, 4096);
    assert_eq!(o.code, Some(2));
    assert!(violations(&o, &a, &dir, &[]).is_empty());
    // A NaN token or a failed verdict in a written report is a violation of a successful run.
    let ok = Outcome {
        code: Some(0),
        signal: None,
        elapsed: Duration::ZERO,
        timed_out: false,
        over_memory: false,
        peak_rss_mb: 0,
        cpu_s: 0.0,
        stdout: b"{\"x\": NaN}".to_vec(),
        stderr: String::new(),
    };
    std::fs::write(
        dir.join("out/r.json"),
        r#"{"verdict": {"passed": false, "failures": ["C9"]}}"#,
    )
    .unwrap();
    let a = args(&["x", "--out", "out", "--json"]);
    let v = violations(&ok, &a, &dir, &[]);
    assert!(
        v.iter()
            .any(|m| m.contains("out/r.json") && m.contains("verdict")),
        "{v:?}"
    );
    assert!(
        v.iter().any(|m| m.contains("stdout") && m.contains("NaN")),
        "{v:?}"
    );
    // A refusal must say what is wrong.
    let dump = Outcome {
        code: Some(2),
        stdout: Vec::new(),
        stderr: "Error: Os { code: 2, kind: NotFound }".into(),
        ..ok
    };
    assert!(violations(&dump, &[], &dir, &[])[0].contains("debug dump"));
}

// ---------------------------------------------------------------------------------------------
// The regression corpus: the known reproducers of unbounded runs, each held to the invariants.

/// Runs one reproducer in a fresh directory (`--out out` there) under the per-run limit and
/// asserts the invariants, showing the command on failure; returns the outcome and directory.
fn reproduce(name: &str, args: &[&str], setup: impl FnOnce(&Path)) -> (Outcome, PathBuf) {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("fuzz-regress")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    setup(&dir);
    let argv: Vec<String> = args.iter().map(|a| a.to_string()).collect();
    let o = execute(&argv, &dir, &[], LIMIT, 4096);
    let v = violations(&o, &argv, &dir, &[]);
    assert!(
        v.is_empty(),
        "(cd {} && {}) after {:.2} s, exit {:?}: {}\nstderr: {}",
        dir.display(),
        command_line(&[], &argv),
        o.elapsed.as_secs_f64(),
        o.code,
        v.join("; "),
        short(&o.stderr, 400)
    );
    (o, dir)
}

/// A refusal: exit 2 (bad input), and, in a release build, within [`REFUSAL_LIMIT`].
fn assert_refused(o: &Outcome) {
    assert_eq!(
        o.code,
        Some(2),
        "must be refused: {}",
        short(&o.stderr, 300)
    );
    if !cfg!(debug_assertions) {
        assert!(
            o.elapsed <= REFUSAL_LIMIT,
            "refused after {:.2} s (≤ 1 s: a check before any work)",
            o.elapsed.as_secs_f64()
        );
    }
}

fn asset_path(rel: &str) -> String {
    format!("{}/assets/{rel}", env!("CARGO_MANIFEST_DIR"))
}

const LAW: &str = "phi - 0.08*sin(2*phi)";

#[test]
fn pair_sector_of_a_nanodegree_is_refused() {
    let (o, _) = reproduce(
        "pair_tiny_sector",
        &[
            "pair",
            "phi*pi",
            "--open",
            "--drive-start",
            "0",
            "--drive-end",
            "1e-9",
            "--teeth",
            "24",
            "--out",
            "out",
        ],
        |_| {},
    );
    assert_refused(&o);
}

#[test]
fn pair_a_million_teeth() {
    reproduce(
        "pair_million_teeth",
        &["pair", LAW, "--teeth", "1000000", "--out", "out"],
        |_| {},
    );
}

#[test]
fn pair_picometre_chord_tolerance() {
    reproduce(
        "pair_chord_tol",
        &[
            "pair",
            LAW,
            "--teeth",
            "20",
            "--chord-tol",
            "1e-12",
            "--out",
            "out",
        ],
        |_| {},
    );
}

#[test]
fn pair_hundred_thousand_verify_steps() {
    reproduce(
        "pair_verify_steps",
        &[
            "pair",
            LAW,
            "--teeth",
            "20",
            "--verify-steps",
            "100000",
            "--out",
            "out",
        ],
        |_| {},
    );
}

#[test]
fn design_three_teeth_hundred_thousand_verify_steps() {
    reproduce(
        "design_verify_steps",
        &[
            "design",
            &asset_path("trajectories/g1_ellipse.csv"),
            "--module",
            "0.5",
            "--teeth",
            "3",
            "--verify-steps",
            "100000",
            "--out",
            "out",
        ],
        |_| {},
    );
}

#[test]
fn simulate_hundredth_module_on_the_kidney() {
    // G1's design draws m = 0.01 in under a second; the designer kidney's (≈ 2000 teeth on more
    // complex gears) is what runs past the limit, so the design is made first.
    let design = |dir: &Path| {
        let argv: Vec<String> = [
            "design",
            &asset_path("trajectories/designer_kidney.csv"),
            "--out",
            "design",
            // The kidney misses the 0.05 mm tolerance (C12): written, exit 3 without this.
            "--accept-failed",
        ]
        .iter()
        .map(|a| a.to_string())
        .collect();
        let o = execute(&argv, dir, &[], Duration::from_secs(120), 4096);
        assert_eq!(o.code, Some(0), "setup design: {}", short(&o.stderr, 300));
    };
    reproduce(
        "simulate_module_001",
        &[
            "simulate",
            "design/design.json",
            "--module",
            "0.01",
            "--out",
            "out",
        ],
        design,
    );
}

#[test]
fn orbit_measure_thousand_mesh_harmonics() {
    reproduce(
        "orbit_mesh_harmonics",
        &[
            "orbit",
            "measure",
            &asset_path("orbit/signals.csv"),
            "--model",
            &asset_path("orbit/model.toml"),
            "--mesh-harmonics",
            "1000",
            "--json",
        ],
        |_| {},
    );
}

// Found by the campaign (seeds 1, 2, 7, 100), beyond those reproducers: one per cause.

#[test]
fn dynamics_astronomic_speed_is_refused_at_once() {
    let (o, _) = reproduce(
        "dynamics_speed_1e299",
        &["dynamics", "full16.toml", "--out", "out"],
        |dir| {
            let scene = std::fs::read_to_string(asset_path("dynamics/full16.toml")).unwrap();
            let scene = scene.replace("n1_rpm = 6000.0", "n1_rpm = 1e299");
            assert!(scene.contains("1e299"), "the scene's speed line moved");
            std::fs::write(dir.join("full16.toml"), scene).unwrap();
        },
    );
    assert_refused(&o);
    assert!(o.stderr.contains("operating.n1_rpm"), "{}", o.stderr);
}

#[test]
fn transplanter_astronomic_angle_spread_is_refused_at_once() {
    // Seed 7 (2026-11-28): an arm-mounting σ of 2⁶³ degrees ran past 60 s.
    let (o, _) = reproduce(
        "transplanter_sigma_deg_2e63",
        &[
            "tolerance",
            "g1_design.json",
            "--errors",
            "g1_errors.toml",
            "--out",
            "out",
        ],
        |dir| {
            let errors =
                std::fs::read_to_string(asset_path("transplanter/g1_errors.toml")).unwrap();
            let errors = errors.replace(
                "[arm_mounting]\nsigma_deg = 0.03",
                "[arm_mounting]\nsigma_deg = 9223372036854775807",
            );
            assert!(
                errors.contains("9223372036854775807"),
                "the arm's line moved"
            );
            std::fs::write(dir.join("g1_errors.toml"), errors).unwrap();
            std::fs::copy(
                asset_path("transplanter/g1_design.json"),
                dir.join("g1_design.json"),
            )
            .unwrap();
        },
    );
    assert_refused(&o);
    assert!(o.stderr.contains("arm_mounting.sigma_deg"), "{}", o.stderr);
}

#[test]
fn design_far_carrier_axis_does_not_panic() {
    reproduce(
        "design_center_1e300",
        &[
            "design",
            &asset_path("trajectories/g1_ellipse.csv"),
            "--center=-1e300,0",
            "--out",
            "out",
        ],
        |_| {},
    );
}

#[test]
fn design_dense_count_of_usize_max_does_not_panic() {
    reproduce(
        "design_dense_max",
        &[
            "design",
            &asset_path("trajectories/g1_ellipse.csv"),
            "--dense",
            "18446744073709551615",
            "--out",
            "out",
        ],
        |_| {},
    );
}

#[test]
fn pair_micrometre_tip_fillet() {
    reproduce(
        "pair_fillet_1e-6",
        &[
            "pair", LAW, "--teeth", "20", "--fillet", "1e-6", "--out", "out",
        ],
        |_| {},
    );
}

#[test]
fn pair_nan_bore_is_refused_at_once() {
    let (o, _) = reproduce(
        "pair_bore_nan",
        &[
            "pair",
            LAW,
            "--open",
            "--drive-start",
            "350",
            "--drive-end",
            "370",
            "--teeth",
            "5000",
            "--bore",
            "nan",
            "--out",
            "out",
        ],
        |_| {},
    );
    assert_refused(&o);
}

#[test]
fn pair_without_clearance_interferes_and_says_so() {
    let (o, _) = reproduce(
        "pair_clearance_0",
        &[
            "pair",
            LAW,
            "--teeth",
            "20",
            "--clearance",
            "0",
            "--out",
            "out",
        ],
        |_| {},
    );
    // c* = 0 puts each tip on the mating root: the verification sees the overlap, so the run
    // must not report success.
    assert_eq!(
        o.code,
        Some(3),
        "interference must exit 3: {}",
        short(&o.stderr, 300)
    );
}

#[test]
fn dynamics_linear_scene_writes_its_report() {
    let (o, dir) = reproduce(
        "dynamics_linear",
        &["dynamics", "scene.toml", "--out", "out"],
        |dir| {
            let text = std::fs::read_to_string(asset_path("dynamics/torsional4.toml")).unwrap();
            let mut scene: toml::Table = toml::from_str(&text).unwrap();
            scene
                .entry("solver")
                .or_insert_with(|| toml::Table::new().into())
                .as_table_mut()
                .unwrap()
                .insert("method".into(), "linear".into());
            std::fs::write(dir.join("scene.toml"), scene.to_string()).unwrap();
        },
    );
    assert_eq!(o.code, Some(0), "{}", short(&o.stderr, 300));
    // The report is JSON (what --json prints); `violations` has already parsed every JSON file.
    let mut reports = Vec::new();
    json_files(&dir.join("out"), &mut reports);
    assert!(
        !reports.is_empty(),
        "no report under --out: {:?}",
        std::fs::read_dir(dir.join("out")).map(|r| r.count())
    );
}

/// A fresh campaign's finding: at module 0.5 on the sparse exact target with a sharp rack
/// (`--fillet 0`, the nearest tooth count) the shaper cutters' corner radius comes out near zero,
/// and their corner trochoid was sampled at the chord step of that radius (nanometres): a million
/// points a piece, 7 minutes and 24 GB before it was stopped. The corner is sampled at the
/// radius it really has (a quarter of the tightest measured, `teeth::outline::fillet_step_mm`):
/// 1.5 s, 250 MB, the same outlines as before for every cutter with a real corner radius.
#[test]
fn design_sharp_rack_half_module_on_the_sparse_target() {
    let (o, _) = reproduce(
        "design_sharp_rack_half_module",
        &[
            "design",
            &asset_path("cases/exact_sparse_200.csv"),
            "--out",
            "out",
            "--module",
            "0.5",
            "--tooth-policy",
            "nearest",
            "--fillet",
            "0",
        ],
        |_| {},
    );
    assert!(matches!(o.code, Some(0 | 3)), "{}", short(&o.stderr, 300));
    assert!(o.peak_rss_mb < 2048, "{} MiB", o.peak_rss_mb);
}

/// Campaign seed 1659486911, run #359: `atol = nan` in a scene's `[solver]` reached the
/// integrator, which refused it as a runtime failure (exit 1); it is the scene's input, refused
/// with its key before any work (exit 2).
#[test]
fn dynamics_nan_tolerance_is_bad_input() {
    for (key, value) in [("atol", "nan"), ("rtol", "-1.0"), ("atol", "inf")] {
        let (o, _) = reproduce(
            &format!("dynamics_{key}_{value}"),
            &["dynamics", "scene.toml", "--out", "out"],
            |dir| {
                let text = std::fs::read_to_string(asset_path("dynamics/sdof_6000.toml")).unwrap();
                let line = |l: &str| {
                    if l.starts_with(&format!("{key} = ")) {
                        format!("{key} = {value}")
                    } else {
                        l.to_string()
                    }
                };
                let text: Vec<String> = text.lines().map(line).collect();
                assert!(
                    text.contains(&format!("{key} = {value}")),
                    "no {key} in the scene"
                );
                let text = text.join("\n");
                std::fs::write(dir.join("scene.toml"), text).unwrap();
            },
        );
        assert_eq!(o.code, Some(2), "{}", short(&o.stderr, 300));
        assert!(
            o.stderr.contains(&format!("solver.{key}")),
            "{}",
            short(&o.stderr, 300)
        );
    }
}

/// CI campaign seed 1, run #587: `--min-convex-radius 1e6` on G1 shrank every ratio to a circle
/// (radius a/2, still tighter than the limit) and spent 10 s fitting a train 68 mm off the
/// target; no train for the target can have so flat an arc, and the design says so at once
/// (exit 2, the bound and the flag named).
#[test]
fn design_unreachable_convex_radius_is_refused_at_once() {
    for value in ["1e6", "1e300"] {
        let (o, _) = reproduce(
            &format!("design_convex_{value}"),
            &[
                "design",
                &asset_path("trajectories/g1_ellipse.csv"),
                "--min-convex-radius",
                value,
                "--out",
                "out",
            ],
            |_| {},
        );
        assert_eq!(o.code, Some(2), "{}", short(&o.stderr, 300));
        let err = o.stderr.replace('│', " ");
        let err = err.split_whitespace().collect::<Vec<_>>().join(" ");
        for s in ["48.5 mm", "--min-convex-radius"] {
            assert!(err.contains(s), "{}", short(&o.stderr, 400));
        }
    }
}
