//! Every number of every input file has a range, checked before any work (docs/bounds.md,
//! "Ranges inside input files"): a bundled file with one number made absurd (1e308, a negative
//! σ, a NaN) is refused at once, exit code 2, with the file and the key named.
use crate::cli::{message, ncgear};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// The longest a refusal may take: it comes before any work (the 1e308 amplitude of
/// `paper_3k.toml` ran past 2 minutes).
const AT_ONCE: Duration = Duration::from_secs(5);

fn asset(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets")
        .join(rel)
}

/// A fresh scratch folder under the target directory.
fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("input_ranges_{name}"));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A copy of the bundled `asset` in `dir` (under its own name) with the first `from` replaced by
/// `to` (which must be there: the test fails if the asset changes under it).
fn mutated(dir: &Path, asset_rel: &str, from: &str, to: &str) -> PathBuf {
    let text = std::fs::read_to_string(asset(asset_rel)).unwrap();
    assert!(text.contains(from), "{asset_rel} no longer holds {from:?}");
    let path = dir.join(Path::new(asset_rel).file_name().unwrap());
    std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    path
}

/// Runs `ncgear args…` and asserts exit code 2 within [`AT_ONCE`], with `file` and every one
/// of `keys` named on stderr.
fn refused(args: &[&std::ffi::OsStr], file: &Path, keys: &[&str]) -> String {
    let started = Instant::now();
    let out = ncgear().args(args).output().unwrap();
    let took = started.elapsed();
    let err = message(&out);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
    assert!(took < AT_ONCE, "{args:?} took {took:?}: {err}");
    let name = file.file_name().unwrap().to_string_lossy();
    assert!(
        err.contains(&*name),
        "{args:?}: the file is not named: {err}"
    );
    for key in keys {
        assert!(err.contains(key), "{args:?}: `{key}` is not named: {err}");
    }
    err
}

fn os<S: AsRef<std::ffi::OsStr> + ?Sized>(s: &S) -> &std::ffi::OsStr {
    s.as_ref()
}

#[test]
fn error_file_numbers_out_of_range_are_refused_at_once() {
    let dir = scratch("tolerance");
    let out = dir.join("out");
    for (from, to, key, range) in [
        // The reproducer: one amplitude of 1e308 ran past 2 minutes.
        (
            "amplitude_um = -0.699",
            "amplitude_um = 1e308",
            "terms[0].amplitude_um",
            "[-1e6, 1e6]",
        ),
        (
            "amplitude_um = -13.0",
            "amplitude_um = -13.0\namplitude_dist = { rayleigh_sigma_um = -2.0 }",
            "terms[1].amplitude_dist.rayleigh_sigma_um",
            "(0, 1e6]",
        ),
        (
            "phase_deg = 90",
            "phase_deg = nan",
            "terms[2].phase_deg",
            "[-3600, 3600]",
        ),
        (
            "omega_rad_s = 63",
            "omega_rad_s = 1e300",
            "terms[3].omega_rad_s",
            "[0, 1e6]",
        ),
        (
            "teeth = 50",
            "teeth = inf",
            "base_circle.teeth",
            "[3, 1000]",
        ),
    ] {
        let f = mutated(&dir, "tolerance/paper_3k.toml", from, to);
        let err = refused(
            &[os("tolerance"), f.as_os_str(), os("--out"), out.as_os_str()],
            &f,
            &[key, range],
        );
        // The summary never printed: the refusal is all there is.
        assert!(!err.contains("sum of amplitudes"), "{err}");
    }
}

#[test]
fn transplanter_inventory_numbers_out_of_range_are_refused_at_once() {
    let dir = scratch("transplanter");
    let out = dir.join("out");
    let design = asset("transplanter/g1_design.json");
    for (from, to, key) in [
        (
            "sigma_um = 3.0",
            "sigma_um = -3.0",
            "sun.eccentricity.sigma_um",
        ),
        (
            "magnitude_um = 15.0",
            "magnitude_um = 1e308",
            "sun.eccentricity.magnitude_um",
        ),
        (
            "direction_deg = 30.0",
            "direction_deg = nan",
            "planet.eccentricity.direction_deg",
        ),
        (
            "nominal_um = 40.0, half_width_um = 20.0",
            "nominal_um = 40.0, half_width_um = 1e308",
            "backlash.sun_intermediate.half_width_um",
        ),
        (
            "radial = { sigma_um = 5.0 }",
            "radial = { nominal_um = inf }",
            "pin_d.radial.nominal_um",
        ),
    ] {
        let f = mutated(&dir, "transplanter/g1_errors.toml", from, to);
        refused(
            &[
                os("tolerance"),
                design.as_os_str(),
                os("--errors"),
                f.as_os_str(),
                os("--out"),
                out.as_os_str(),
            ],
            &f,
            &[key],
        );
    }
}

#[test]
fn dynamics_scene_numbers_out_of_range_are_refused_at_once() {
    let dir = scratch("dynamics");
    let out = dir.join("out");
    for (from, to, key) in [
        ("er_um = 10.0", "er_um = 1e308", "effects.static_te.er_um"),
        (
            "half_gap_um = 50.0",
            "half_gap_um = -50.0",
            "effects.backlash.half_gap_um",
        ),
        (
            "input_torque_Nm = 50.0",
            "input_torque_Nm = 1e300",
            "operating.input_torque_Nm",
        ),
        (
            "kmax = 4.5e8",
            "kmax = 1e300",
            "effects.mesh_stiffness.kmax",
        ),
        ("zeta = 0.05", "zeta = nan", "effects.mesh_stiffness.zeta"),
        (
            "face_width_mm = 20.0",
            "face_width_mm = 1e308",
            "gears.face_width_mm",
        ),
    ] {
        let f = mutated(&dir, "dynamics/sdof_6000.toml", from, to);
        refused(
            &[os("dynamics"), f.as_os_str(), os("--out"), out.as_os_str()],
            &f,
            &[key],
        );
    }
}

#[test]
fn synthesis_spec_numbers_out_of_range_are_refused_at_once() {
    let dir = scratch("synthesis");
    let out = dir.join("out");
    for (from, to, key) in [
        ("rpm = 300.0", "rpm = nan", "machine.rpm"),
        ("depth_mm = 30.0", "depth_mm = 1e308", "machine.depth_mm"),
        (
            "height_mm = [284.76, 294.76]",
            "height_mm = [284.76, 1e308]",
            "targets.height_mm[1]",
        ),
    ] {
        let f = mutated(&dir, "synthesis/rice_targets.toml", from, to);
        refused(
            &[
                os("synthesize"),
                f.as_os_str(),
                os("--out"),
                out.as_os_str(),
            ],
            &f,
            &[key],
        );
    }
    let f = mutated(
        &dir,
        "synthesis/g1_five_poses.toml",
        "x_mm = ",
        "x_mm = 1e308 #",
    );
    refused(
        &[
            os("synthesize"),
            f.as_os_str(),
            os("--out"),
            out.as_os_str(),
        ],
        &f,
        &["pose[0].x_mm"],
    );
}

#[test]
fn orbit_model_numbers_out_of_range_are_refused_at_once() {
    let dir = scratch("orbit");
    for (from, to, key) in [
        (
            "eccentricity_um = 10.0",
            "eccentricity_um = 1e308",
            "planet[0].eccentricity_um",
        ),
        ("phase_deg = 0.0", "phase_deg = nan", "planet[0].phase_deg"),
        (
            "sun_speed_rpm = 300.0",
            "sun_speed_rpm = 1e300",
            "gears.sun_speed_rpm",
        ),
    ] {
        let f = mutated(&dir, "orbit/model.toml", from, to);
        refused(&[os("orbit"), os("model"), f.as_os_str()], &f, &[key]);
    }
}

#[test]
fn loads_scene_numbers_out_of_range_are_refused_at_once() {
    let dir = scratch("loads");
    let out = dir.join("out");
    std::fs::copy(
        asset("loads/g1_m2_design.json"),
        dir.join("g1_m2_design.json"),
    )
    .unwrap();
    for (from, to, key) in [
        (
            "carrier_rpm = 300.0",
            "carrier_rpm = nan",
            "operation.carrier_rpm",
        ),
        ("mass_kg = 0.55", "mass_kg = -0.55", "arm.mass_kg"),
        (
            "face_width_mm = 25.0",
            "face_width_mm = 1e308",
            "gears.face_width_mm",
        ),
    ] {
        let f = mutated(&dir, "loads/g1_rotor.toml", from, to);
        refused(
            &[os("loads"), f.as_os_str(), os("--out"), out.as_os_str()],
            &f,
            &[key],
        );
    }
}

/// The bundled design file as JSON, edited by `edit`, written to `dir/name`.
fn edited_design(dir: &Path, name: &str, edit: impl Fn(&mut serde_json::Value)) -> PathBuf {
    let text = std::fs::read_to_string(asset("transplanter/g1_design.json")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    edit(&mut v);
    let path = dir.join(name);
    std::fs::write(&path, v.to_string()).unwrap();
    path
}

#[test]
fn hand_edited_design_files_are_refused_by_simulate_at_once() {
    let dir = scratch("simulate");
    let out = dir.join("out");
    let cases: Vec<(PathBuf, &str)> = vec![
        (
            edited_design(&dir, "l3.json", |v| v["l3"] = serde_json::json!(1e308)),
            "l3_mm",
        ),
        (
            edited_design(&dir, "negative.json", |v| {
                v["gears"]["planet"]["pitch"][7][1] = serde_json::json!(-20.0);
            }),
            "gears.planet.pitch[7][1]",
        ),
        (
            edited_design(&dir, "needle.json", |v| {
                v["needle_angle_deg"] = serde_json::json!(1e300);
            }),
            "needle_angle_deg",
        ),
        (
            // One radius of the sun 0.5 mm larger: the intermediate no longer returns after a
            // turn of the sun (the table is not closed).
            edited_design(&dir, "open.json", |v| {
                let r = v["gears"]["sun"]["pitch"][100][1].as_f64().unwrap();
                v["gears"]["sun"]["pitch"][100][1] = serde_json::json!(r + 0.5);
            }),
            "gears.sun.pitch",
        ),
        (
            edited_design(&dir, "center.json", |v| {
                v["carrier"]["center"] = serde_json::json!([1e300, 0.0]);
            }),
            "carrier.center_mm.x",
        ),
    ];
    for (f, key) in &cases {
        let err = refused(
            &[os("simulate"), f.as_os_str(), os("--out"), out.as_os_str()],
            f,
            &[key],
        );
        if f.ends_with("open.json") {
            assert!(err.contains("does not close"), "{err}");
        }
    }
    // A number JSON cannot hold as a double: refused by the parser, naming the line and column.
    let text = std::fs::read_to_string(asset("transplanter/g1_design.json")).unwrap();
    let huge = dir.join("huge.json");
    let at = text.find("\"l3\":").unwrap();
    let end = at + text[at..].find([',', '\n']).unwrap();
    std::fs::write(
        &huge,
        format!("{}\"l3\": 1e400{}", &text[..at], &text[end..]),
    )
    .unwrap();
    refused(
        &[
            os("simulate"),
            huge.as_os_str(),
            os("--out"),
            out.as_os_str(),
        ],
        &huge,
        &["line"],
    );
    // And the bundled file itself is accepted by the same checks (each case above can fail).
    let (_, asm) =
        ncgear::simulate::DesignFile::from_path(&asset("transplanter/g1_design.json")).unwrap();
    assert!(asm.a_mm > 0.0);
}
