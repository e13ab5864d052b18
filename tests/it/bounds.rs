//! Bounded inputs and honest exit codes: options outside their admissible range are refused
//! before any work (exit 2, naming the flag), a result that fails its own verification is
//! written and exits 3 (0 with `--accept-failed`), `--out` always gets a report.
use crate::cli::ncgear;
use std::path::{Path, PathBuf};

const LAW: &str = "phi - 0.08*sin(2*phi)";

fn out_dir(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("bounds_{name}"));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn asset(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets")
        .join(rel)
}

/// Runs `args`, returns (exit code, stderr with the message box's wrapping undone: single
/// spaces, no frame characters).
fn run(args: &[&str]) -> (Option<i32>, String) {
    let o = ncgear().args(args).output().expect("ncgear runs");
    (o.status.code(), super::cli::message(&o))
}

/// Each reproducer of an unbounded run is refused with exit 2, naming the value, the range and
/// the flag that sets it, and writes nothing.
#[test]
fn options_outside_their_range_are_refused_before_any_work() {
    let out = out_dir("refused");
    let o = out.to_str().unwrap();
    let g1 = asset("trajectories/g1_ellipse.csv");
    let g1 = g1.to_str().unwrap();
    let cases: [(&[&str], &str); 10] = [
        (
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
            ],
            "widen the interval",
        ),
        (&["pair", LAW, "--teeth", "1000000"], "3..=1000"),
        (
            &["pair", LAW, "--teeth", "20", "--chord-tol", "1e-12"],
            "--chord-tol",
        ),
        (
            &["pair", LAW, "--teeth", "20", "--verify-steps", "100000"],
            "--verify-steps",
        ),
        (
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
            ],
            "--bore",
        ),
        (
            &[
                "design",
                g1,
                "--module",
                "0.5",
                "--teeth",
                "3",
                "--verify-steps",
                "100000",
            ],
            "0..=3600",
        ),
        (&["design", g1, "--bore", "3"], "--module"),
        (&["design", g1, "--k-max", "100000000"], "--k-max"),
        (&["design", g1, "--samples", "1000000000"], "--samples"),
        (
            &["pair", LAW, "--teeth", "20", "--pressure-angle", "1"],
            "[10°, 45°]: below 10° a rack undercuts every gear of fewer than 2/sin²α ≈ 66 teeth so deeply that whole flanks vanish (standard racks: 14.5°–25°) help: set by --pressure-angle",
        ),
    ];
    for (args, names) in cases {
        let mut full = args.to_vec();
        full.extend(["--out", o]);
        let (code, err) = run(&full);
        assert_eq!(code, Some(2), "{args:?}: {err}");
        assert!(err.contains(names), "{args:?} should name `{names}`: {err}");
        assert!(!out.exists(), "{args:?} wrote {}", out.display());
    }
    let (code, err) = run(&[
        "orbit",
        "measure",
        asset("orbit/signals.csv").to_str().unwrap(),
        "--model",
        asset("orbit/model.toml").to_str().unwrap(),
        "--mesh-harmonics",
        "1000",
    ]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("mesh_harmonics"), "{err}");
}

/// Interference is a failed verification: the files are written, pair.json says so, the exit
/// code is 3; `--accept-failed` exits 0 with the same files.
#[test]
fn a_mesh_with_interference_is_written_and_exits_3() {
    let out = out_dir("clearance0");
    let o = out.to_str().unwrap();
    let (code, err) = run(&["pair", LAW, "--teeth", "20", "--clearance", "0", "--out", o]);
    assert_eq!(code, Some(3), "{err}");
    assert!(err.contains("interference"), "{err}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("pair.json")).unwrap()).unwrap();
    assert_eq!(report["verdict"]["passed"], false);
    let failures = report["verdict"]["failures"].as_array().unwrap();
    assert!(
        failures
            .iter()
            .any(|f| f.as_str().unwrap().contains("interference steps"))
    );
    assert!(out.join("pair.step").exists() && out.join("pair.dxf").exists());
    let (code, _) = run(&[
        "pair",
        LAW,
        "--teeth",
        "20",
        "--clearance",
        "0",
        "--out",
        o,
        "--accept-failed",
    ]);
    assert_eq!(code, Some(0));
    // The default clearance meshes cleanly: passed, exit 0.
    let (code, err) = run(&["pair", LAW, "--teeth", "20", "--out", o]);
    assert_eq!(code, Some(0), "{err}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("pair.json")).unwrap()).unwrap();
    assert_eq!(report["verdict"]["passed"], true);
}

/// A design that misses its tolerance fails C12: design.json's verdict names it, exit 3; the
/// reported times add up to the whole command.
#[test]
fn a_design_that_fails_a_check_exits_3_with_its_verdict() {
    let out = out_dir("kidney");
    let o = out.to_str().unwrap();
    let kidney = asset("trajectories/designer_kidney.csv");
    let (code, err) = run(&["design", kidney.to_str().unwrap(), "--out", o]);
    assert_eq!(code, Some(3), "{err}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("design.json")).unwrap()).unwrap();
    let v = &report["verdict"];
    assert_eq!(v["passed"], false);
    let failed: Vec<&str> = v["failures"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap().split(':').next().unwrap())
        .collect();
    // Exactly the checks design.json marks as failed.
    let marked: Vec<&str> = report["checks"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|c| c["pass"] == false)
        .map(|c| c["id"].as_str().unwrap())
        .collect();
    assert_eq!(failed, marked);
    assert_eq!(failed, ["C12"]);
    let t = &report["timings_ms"];
    let (total, command) = (t["total"].as_f64().unwrap(), t["command"].as_f64().unwrap());
    assert!(command >= total && total > 0.0, "{t}");
    // Unasked, the alternatives that apply are named and not designed: no second design.
    assert!(report.get("alternatives").is_none(), "{report}");
    assert_eq!(t["alternatives"].as_f64().unwrap(), 0.0, "{t}");
    let untried = "what may pass, not designed: off the carrier line, the same limits (--idler-offset free); a pressure-angle limit of 50° (--max-pressure-angle 50); --alternatives designs the first";
    let failure = &err[err.find("verification failed").expect(&err)..];
    assert!(failure.contains(untried), "{err}");
    assert!(
        report["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .any(|w| w.as_str().unwrap().starts_with(untried)),
        "{report}"
    );
    // Asked (--alternatives), what would come closer is named with its figure, in design.json
    // and in the failure, and the figure is what that design's own command makes.
    let asked = out_dir("kidney_alternatives");
    let (code, err) = run(&[
        "design",
        kidney.to_str().unwrap(),
        "--alternatives",
        "--out",
        asked.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(3), "{err}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(asked.join("design.json")).unwrap()).unwrap();
    assert!(report["timings_ms"]["alternatives"].as_f64().unwrap() > 0.0);
    let alt = &report["alternatives"][0];
    assert_eq!(alt["flags"], "--idler-offset free", "{alt}");
    let figure = alt["max_deviation_mm"].as_f64().unwrap();
    assert!(
        figure < 0.1 && alt["idler_offset_deg"].as_f64().unwrap().abs() > 5.0,
        "{alt}"
    );
    let named = format!("(--idler-offset free): traced within {figure:.4} mm");
    let failure = &err[err.find("verification failed").expect(&err)..];
    assert!(failure.contains(&named), "{err}");
    let off = out_dir("kidney_off_line");
    let (code, err) = run(&[
        "design",
        kidney.to_str().unwrap(),
        "--idler-offset",
        "free",
        "--out",
        off.to_str().unwrap(),
    ]);
    assert!(code == Some(0) || code == Some(3), "{err}");
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(off.join("design.json")).unwrap()).unwrap();
    assert_eq!(r["roundtrip"]["max_deviation_mm"].as_f64().unwrap(), figure);
    assert_eq!(r["verdict"]["passed"], alt["passed"]);
}

/// A linear dynamics scene writes its report into --out and refuses the options of a
/// time-domain run.
#[test]
fn a_linear_dynamics_scene_writes_its_report_and_refuses_what_it_ignores() {
    let out = out_dir("linear");
    let o = out.to_str().unwrap();
    let scene = asset("dynamics/torsional4.toml");
    let scene = scene.to_str().unwrap();
    let (code, err) = run(&["dynamics", scene, "--out", o]);
    assert_eq!(code, Some(0), "{err}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("dynamics.json")).unwrap()).unwrap();
    assert!(report["linear_dte_amplitude_m"].as_f64().unwrap() > 0.0);
    for flag in [["--sweep", "0.5:1.5:0.1"], ["--format", "png"]] {
        let (code, err) = run(&["dynamics", scene, "--out", o, flag[0], flag[1]]);
        assert_eq!(code, Some(2), "{err}");
        assert!(err.contains(flag[0]) && err.contains("linear"), "{err}");
    }
}

/// A law that begins with a minus sign is a law, not a flag.
#[test]
fn a_law_beginning_with_a_minus_sign_is_read_as_the_law() {
    let out = out_dir("minus");
    let o = out.to_str().unwrap();
    let (code, err) = run(&[
        "pair",
        "-0.08*sin(2*phi) + phi",
        "--teeth",
        "20",
        "--verify-steps",
        "0",
        "--out",
        o,
    ]);
    assert_eq!(code, Some(0), "{err}");
    assert!(out.join("pair.json").exists());
}

/// Every file is written whole under its name and the report last: a run leaves no temporary
/// (`.partial-*`) file, and a report of an earlier run in the same directory is replaced by this
/// run's, never left beside the new files.
#[test]
fn files_are_written_whole_and_the_report_replaces_an_earlier_one() {
    let out = out_dir("whole");
    std::fs::create_dir_all(&out).unwrap();
    let report = out.join("pair.json");
    std::fs::write(&report, "{\"from\": \"an earlier run\"}").unwrap();
    let (code, err) = run(&["pair", LAW, "--teeth", "20", "--out", out.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{err}");
    let text = std::fs::read_to_string(&report).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(
        v["verdict"]["passed"],
        serde_json::Value::Bool(true),
        "{text}"
    );
    let mut left = Vec::new();
    let mut dirs = vec![out.clone()];
    while let Some(d) = dirs.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                dirs.push(p);
            } else if p
                .file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with(".partial-")
            {
                left.push(p);
            }
        }
    }
    assert!(left.is_empty(), "temporary files left: {left:?}");
    assert!(out.join("pair.step").exists() && out.join("pair.dxf").exists());
}
