//! Shared helpers for the end-to-end tests of the `ncgear` binary.
use std::process::{Command, Output};

/// The `ncgear` binary built for this test run.
pub fn ncgear() -> Command {
    Command::new(env!("CARGO_BIN_EXE_ncgear"))
}

/// Runs `cmd`, asserts it succeeded (showing its stderr otherwise) and returns its output.
pub fn succeed(cmd: &mut Command) -> Output {
    let out = cmd.output().expect("ncgear runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// Runs `cmd` (a `--json` command), asserts it succeeded and parses its stdout.
pub fn succeed_json(cmd: &mut Command) -> serde_json::Value {
    serde_json::from_slice(&succeed(cmd).stdout).expect("stdout is JSON")
}

/// The stderr of `out` with the message box's wrapping undone: single spaces, no frame
/// characters.
pub fn message(out: &Output) -> String {
    let err = String::from_utf8_lossy(&out.stderr).replace(['│', '×'], " ");
    err.split_whitespace().collect::<Vec<_>>().join(" ")
}
