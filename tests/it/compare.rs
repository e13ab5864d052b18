//! `ncgear compare`: synthetic tracks filmed from the bundled designs (a known rotation,
//! offset and px/mm scale, 0.3 mm Gaussian noise, 2 % glitch frames, 1–3 turns, ±2 % speed
//! drift) are registered back within 0.1 mm and 0.05°, the scale within 0.1 %; a train built
//! with known errors shows them as deviation; bad input exits 2 naming it.
use crate::cli::ncgear;
use ncgear::compare::{CompareOptions, ReadOptions, Scale, compare, parse_track};
use ncgear::geometry::assembly::{Assembly, Rebuilt};
use ncgear::math::Point;
use ncgear::simulate::DesignFile;
use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};
use std::f64::consts::TAU;
use std::path::PathBuf;

fn asset(path: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(path)
}

fn assembly(path: &str) -> Assembly {
    DesignFile::from_path(&asset(path)).unwrap().1
}

/// The camera: image point `p` (px, y down) of design point `q` (mm): `q = s·R(θ)·(x, −y) + t`.
#[derive(Clone, Copy)]
struct Camera {
    theta_deg: f64,
    t_mm: Point,
    mm_per_px: f64,
}

impl Camera {
    fn to_design(self, p: Point) -> Point {
        Point::new(p.x, -p.y).rotate(self.theta_deg.to_radians()) * self.mm_per_px + self.t_mm
    }
    fn to_image(self, q: Point) -> Point {
        let f = (q - self.t_mm).rotate(-self.theta_deg.to_radians()) / self.mm_per_px;
        Point::new(f.x, -f.y)
    }
}

/// A filmed record: the CSV text, and per frame the true carrier angle, design-frame noise and
/// whether it is a glitch.
struct Record {
    csv: String,
    phi: Vec<f64>,
    noise: Vec<Point>,
    glitch: Vec<bool>,
    tip: Vec<Point>,
}

fn gauss(rng: &mut ChaCha8Rng) -> f64 {
    let (u, v): (f64, f64) = (rng.random::<f64>().max(1e-300), rng.random());
    (-2.0 * u.ln()).sqrt() * (TAU * v).cos()
}

/// `turns` turns (and 3 % more) of `built` at `rpm` filmed at `fps` by `cam`, the speed ramping
/// from −2 % to +2 %; 0.3 mm noise; 2 % of the frames glitch 3–15 mm.
fn film(built: &Rebuilt, cam: Camera, turns: f64, rpm: f64, fps: f64, seed: u64) -> Record {
    film_with(built, cam, turns, rpm, fps, seed, false)
}

/// [`film`], with a second marker at the planet axis when `marker` (0.3 mm noise too).
fn film_with(
    built: &Rebuilt,
    cam: Camera,
    turns: f64,
    rpm: f64,
    fps: f64,
    seed: u64,
    marker: bool,
) -> Record {
    let tip = |phi: f64| built.pose(phi).tip_mm;
    let planet = |phi: f64| built.pose(phi).planet_center_mm;
    let dir = f64::from(built.assembly().direction);
    film_path(
        dir,
        &tip,
        marker.then_some(&planet as &dyn Fn(f64) -> Point),
        cam,
        (turns, rpm, fps),
        seed,
    )
}

/// [`film`] of the tip path `tip(φ)` (carrier angle φ advancing in the sense `dir`), with a
/// second marker at `planet(φ)` when given; `(turns, rpm, fps)` as [`film`]'s.
fn film_path(
    dir: f64,
    tip: &dyn Fn(f64) -> Point,
    planet: Option<&dyn Fn(f64) -> Point>,
    cam: Camera,
    (turns, rpm, fps): (f64, f64, f64),
    seed: u64,
) -> Record {
    let marker = planet.is_some();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let w0 = dir * TAU * rpm / 60.0;
    let span = turns * 1.03 * 60.0 / rpm;
    let n = (span * fps) as usize;
    let phi0 = rng.random_range(0.0..TAU);
    let header = if marker {
        "time (s),x (px),y (px),x2 (px),y2 (px)\n"
    } else {
        "time (s),x (px),y (px)\n"
    };
    let mut r = Record {
        csv: header.into(),
        phi: vec![],
        noise: vec![],
        glitch: vec![],
        tip: vec![],
    };
    for i in 0..n {
        let t = i as f64 / fps;
        // ω(t) = ω₀·(1 + 0.02·(2t/T − 1)): ±2 % over the record.
        let phi = phi0 + w0 * (t + 0.02 * (t * t / span - t));
        let tip = tip(phi);
        let noise = Point::new(gauss(&mut rng), gauss(&mut rng)) * 0.3;
        let glitch = rng.random::<f64>() < 0.02;
        let jump = if glitch {
            Point::unit(rng.random_range(0.0..TAU)) * rng.random_range(3.0..15.0)
        } else {
            Point::default()
        };
        let p = cam.to_image(tip + noise + jump);
        r.csv.push_str(&format!("{t:.6},{:.5},{:.5}", p.x, p.y));
        if let Some(planet) = planet {
            let a = cam.to_image(planet(phi) + Point::new(gauss(&mut rng), gauss(&mut rng)) * 0.3);
            r.csv.push_str(&format!(",{:.5},{:.5}", a.x, a.y));
        }
        r.csv.push('\n');
        r.phi.push(phi);
        r.noise.push(noise);
        r.glitch.push(glitch);
        r.tip.push(tip);
    }
    r
}

fn cam() -> Camera {
    Camera {
        theta_deg: 17.3,
        t_mm: Point::new(-412.0, 233.0),
        mm_per_px: 0.3127,
    }
}

/// The registration of one synthetic record, asserted against its truth.
fn recovers(design: &str, turns: f64, seed: u64, scale: Scale) {
    let asm = assembly(design);
    let rebuilt = asm.rebuild();
    let cam = cam();
    let rec = film(&rebuilt, cam, turns, 100.0, 1000.0, seed);
    let track = parse_track(&rec.csv, "synthetic.csv", &ReadOptions::default()).unwrap();
    assert!(track.y_down, "pixels are image coordinates");
    let opts = CompareOptions {
        scale,
        spacing_mm: Some(140.0),
        ..CompareOptions::default()
    };
    let c = compare(&track, &rebuilt, &opts).unwrap();
    let r = &c.report;
    let g = &r.registration;
    let s = g.scale_mm_per_unit.value;
    let est = |p: Point| {
        Point::new(p.x, -p.y).rotate(g.rotation_deg.value.to_radians()) * s
            + Point::new(g.translation_mm[0].value, g.translation_mm[1].value)
    };
    let img: Vec<Point> = track.tip.clone();
    let worst = img
        .iter()
        .map(|p| est(*p).distance(cam.to_design(*p)))
        .fold(0.0, f64::max);
    let dtheta = g.rotation_deg.value - cam.theta_deg;
    let dscale = s / cam.mm_per_px - 1.0;
    println!(
        "{design} {turns} turns seed {seed}: transform {worst:.4} mm, rotation {dtheta:.5}° (se {:.5}°), scale {:.5} % (se {:.5} %), noise {:.4} mm, {} iterations",
        g.rotation_deg.se,
        100.0 * dscale,
        100.0 * g.scale_mm_per_unit.se / s,
        g.noise_mm,
        g.iterations
    );
    assert!(worst <= 0.1, "transform off by {worst} mm");
    assert!(dtheta.abs() <= 0.05, "rotation off by {dtheta}°");
    assert!(dscale.abs() <= 1e-3, "scale off by {} %", 100.0 * dscale);
    assert!((g.noise_mm - 0.3).abs() < 0.03, "noise {}", g.noise_mm);
    // Every glitch flagged, few good frames.
    let flagged: Vec<bool> = c.frames.iter().map(|f| f.outlier).collect();
    let missed = rec
        .glitch
        .iter()
        .zip(&flagged)
        .filter(|(g, f)| **g && !**f)
        .count();
    let false_flags = rec
        .glitch
        .iter()
        .zip(&flagged)
        .filter(|(g, f)| !**g && **f)
        .count();
    println!(
        "  glitches {} missed {missed} false {false_flags}",
        rec.glitch.iter().filter(|g| **g).count()
    );
    assert_eq!(missed, 0);
    assert!(
        false_flags * 500 <= rec.glitch.len(),
        "{false_flags} good frames flagged"
    );
    // The frames' deviation figures, against their truth (the noise of the good frames).
    let truth: Vec<f64> = rec
        .noise
        .iter()
        .zip(&flagged)
        .filter(|(_, f)| !**f)
        .map(|(n, _)| n.norm())
        .collect();
    let rms = (truth.iter().map(|d| d * d).sum::<f64>() / truth.len() as f64).sqrt();
    let mx = truth.iter().copied().fold(0.0, f64::max);
    let d = &r.deviation;
    println!(
        "  frame rms {:.4} (truth {rms:.4}), max {:.4} (truth {mx:.4}), smooth rms {:.4} max {:.4} hausdorff {:.4} floor {:.4}",
        d.frame_rms_mm, d.frame_max_mm, d.rms_mm, d.max_mm, d.hausdorff_mm, d.noise_floor_mm
    );
    assert!((d.frame_rms_mm - rms).abs() <= 0.05 && (d.frame_max_mm - mx).abs() <= 0.05);
    // The design itself: no deviation beyond the noise floor of the smooth fit (per axis; |d|
    // has RMS √2 of it), and within 0.05 mm from two turns at 1000 frames/s, 100 rpm on.
    let floor = d.noise_floor_mm;
    assert!(
        d.rms_mm <= 1.5 * 2f64.sqrt() * floor && d.max_mm <= 4.0 * floor,
        "rms {} max {} floor {floor}",
        d.rms_mm,
        d.max_mm
    );
    if turns >= 2.0 {
        assert!(d.rms_mm <= 0.05, "rms {}", d.rms_mm);
    }
    // The agronomic angles measured on the track.
    let f = &r.features;
    let (dt, dp) = (
        f.track.take_angle_deg - f.design.take_angle_deg,
        f.track.push_angle_deg - f.design.push_angle_deg,
    );
    println!(
        "  take {dt:.4}° push {dp:.4}° hole {:.4} mm, turns {}",
        f.track.hole_width_mm - f.design.hole_width_mm,
        r.turns.len()
    );
    assert!(dt.abs() <= 0.2 && dp.abs() <= 0.2);
    assert_eq!(r.turns.len(), turns.floor() as usize);
    // The speed: the record's mean.
    let mean = (rec.phi[rec.phi.len() - 1] - rec.phi[0]).abs()
        / (track.time_s[track.time_s.len() - 1])
        * 60.0
        / TAU;
    assert!(
        (g.mean_rpm - mean).abs() < 1e-3 * mean,
        "{} vs {mean}",
        g.mean_rpm
    );
}

#[test]
fn compare_one_turn_of_g1_is_registered_at_a_given_scale() {
    recovers(
        "assets/transplanter/g1_design.json",
        1.0,
        1,
        Scale::PxPerMm(1.0 / 0.3127),
    );
}

#[test]
fn compare_two_turns_of_g1_with_the_scale_fitted() {
    recovers("assets/transplanter/g1_design.json", 2.0, 2, Scale::Fit);
}

#[test]
fn compare_three_turns_of_the_offset_train_with_the_scale_fitted() {
    recovers("assets/loads/g1_m2_design.json", 3.0, 3, Scale::Fit);
}

/// A train built 0.5 mm long in the needle and with its intermediate 0.3° off its phase, filmed
/// with the carrier axis marked: the registration stays that of the camera, the difference
/// shows in the deviation by carrier angle where it is.
#[test]
fn compare_a_train_built_with_known_errors_shows_them_as_deviation() {
    let asm = assembly("assets/transplanter/g1_design.json");
    let design = asm.rebuild();
    let mut built = asm.clone();
    built.l3_mm += 0.5;
    built.intermediate_angle_at_zero_rad += 0.3f64.to_radians();
    let built = built.rebuild();
    let cam = cam();
    let rec = film(&built, cam, 2.0, 100.0, 1000.0, 7);
    let track = parse_track(&rec.csv, "built.csv", &ReadOptions::default()).unwrap();
    let axis = cam.to_image(asm.center_mm);
    // Free: the rotation and the carrier phase absorb part of the errors (a rotation of the
    // whole train about O at a shifted phase is a sun mounted turned).
    let free = CompareOptions {
        scale: Scale::PxPerMm(1.0 / cam.mm_per_px),
        carrier_axis: Some(axis),
        ..CompareOptions::default()
    };
    let f = compare(&track, &design, &free).unwrap().report;
    println!(
        "  axis only: rotation {:.4}°, deviation rms {:.4} mm",
        f.registration.rotation_deg.value - cam.theta_deg,
        f.deviation.rms_mm
    );
    // The camera levelled (its rotation known) and the axis marked: only the timing is fitted.
    let opts = CompareOptions {
        rotation_rad: Some(cam.theta_deg.to_radians()),
        ..free
    };
    let c = compare(&track, &design, &opts).unwrap();
    let r = &c.report;
    // Without an encoder the carrier phase is fitted, and it takes up the errors' component along
    // the path (`d = δ − B′·Δφ₀`); their component normal to the path, which no timing can
    // take, shows where it is.
    let (mut worst, mut truth2, mut normal2, mut err2) = (0.0f64, 0.0, 0.0, 0.0);
    for a in &r.deviation.by_angle {
        let phi = a.carrier_deg.to_radians();
        let delta = built.pose(phi).tip_mm - design.pose(phi).tip_mm;
        let along = design.pose(phi + 1e-6).tip_mm - design.pose(phi - 1e-6).tip_mm;
        let normal = along.perp() / along.norm();
        truth2 += delta.norm_squared();
        normal2 += delta.dot(normal).powi(2);
        worst = worst.max((a.normal_mm - delta.dot(normal)).abs());
        err2 += (a.normal_mm - delta.dot(normal)).powi(2);
    }
    let m = r.deviation.by_angle.len() as f64;
    let (truth_rms, normal_rms, err_rms) =
        ((truth2 / m).sqrt(), (normal2 / m).sqrt(), (err2 / m).sqrt());
    let floor = r.deviation.noise_floor_mm;
    println!(
        "built with errors: deviation rms {:.4} mm (truth {truth_rms:.4}, normal part {normal_rms:.4}), error of its normal part rms {err_rms:.4} max {worst:.4} mm (noise floor {floor:.4}), push angle {:.3}° vs design {:.3}°",
        r.deviation.rms_mm, r.features.track.push_angle_deg, r.features.design.push_angle_deg
    );
    assert!(
        normal_rms > 0.2,
        "the errors move the tip off the path: {normal_rms} mm"
    );
    assert!(
        err_rms <= 0.05 && worst <= 4.0 * floor,
        "normal part of d(φ) off the built train's by {err_rms} (rms), {worst} mm"
    );
    assert!(r.deviation.rms_mm >= normal_rms - 0.05 && r.deviation.rms_mm <= truth_rms + 0.05);
}

/// A track of the bundled G1 rotor as it moves (assets/dynamics/rotor_g1.toml: its teeth's
/// backlash, elastic teeth, the settled turn at 300 r/min), filmed as [`film`] films (±2 % speed
/// drift, 0.3 mm noise, 2 % glitches): against the static path it shows the lean across the
/// backlash; against the scene's dynamic path at the track's speed (`--dynamics`) the deviation
/// falls to the noise, and the dynamics explain nearly all of the static deviation's mean square.
/// The CLI says so and writes it into compare.json.
#[test]
fn compare_against_the_dynamics_explains_a_track_of_the_rotor_in_motion() {
    use ncgear::analysis::dynamics::rotor::Prepared;
    use ncgear::compare::dynamic::against_dynamics;
    use ncgear::progress::Progress;
    let scene = asset("assets/dynamics/rotor_g1.toml");
    let p = Prepared::from_path(&scene).unwrap();
    let run = p.run_at_rpm(300.0, None, &Progress::none()).unwrap();
    let asm = assembly("assets/loads/g1_m2_design.json");
    let design = asm.rebuild();
    let dir = f64::from(design.assembly().direction);
    // The dynamic tip by carrier angle: linear between the run's samples of travel (0.5°, so
    // within a micrometre of the path), travel sample k at carrier angle dir·2πk/n.
    let tips = &run.report.tip_mm;
    let n = tips.len();
    let tip_at = |phi: f64| {
        let u = (dir * phi / TAU).rem_euclid(1.0) * n as f64;
        let (k, f) = (u.floor() as usize % n, u - u.floor());
        tips[k] * (1.0 - f) + tips[(k + 1) % n] * f
    };
    let lean = (0..n)
        .map(|k| tips[k].distance(design.pose(dir * TAU * k as f64 / n as f64).tip_mm))
        .fold(0.0, f64::max);
    assert!(lean > 0.3, "the rotor leans across its backlash: {lean} mm");
    let cam = cam();
    let rec = film_path(dir, &tip_at, None, cam, (2.0, 300.0, 1000.0), 23);
    let track = parse_track(&rec.csv, "rotor.csv", &ReadOptions::default()).unwrap();
    let opts = CompareOptions {
        scale: Scale::PxPerMm(1.0 / cam.mm_per_px),
        ..CompareOptions::default()
    };
    let c = compare(&track, &design, &opts).unwrap();
    let (dc, d) = against_dynamics(&track, &design, &c, &p, &opts, &Progress::none()).unwrap();
    println!(
        "rotor track: static rms {:.4} max {:.4} mm; dynamic rms {:.4} max {:.4} mm (floor {:.4}); explained {:.4}; departure {:.4} mm at {:.2} r/min",
        c.report.deviation.rms_mm,
        c.report.deviation.max_mm,
        d.rms_mm,
        d.max_mm,
        dc.report.deviation.noise_floor_mm,
        d.explained,
        d.max_tip_departure_mm,
        d.carrier_rpm
    );
    assert!(d.settled && (d.carrier_rpm - 300.0).abs() < 1.0, "{d:?}");
    assert!((d.max_tip_departure_mm - lean).abs() < 0.02 * lean, "{d:?}");
    assert!(
        c.report.deviation.rms_mm > 0.15,
        "the lean shows against the static path"
    );
    assert!(
        d.rms_mm < 2.0 * dc.report.deviation.noise_floor_mm,
        "against the dynamic path only the noise is left: {d:?}"
    );
    assert!(d.explained > 0.9, "{d:?}");
    assert!((d.static_rms_mm - c.report.deviation.rms_mm).abs() < 1e-12);
    // The registration to the dynamic path finds the camera as well.
    let r = &dc.report.registration;
    assert!((r.rotation_deg.value - cam.theta_deg).abs() < 0.05, "{r:?}");
    // The CLI: the same figures, said and written.
    let (code, err, dir_out) = run_cli_on(
        "dynamics",
        &rec.csv,
        "assets/loads/g1_m2_design.json",
        &[
            "--px-per-mm",
            &format!("{}", 1.0 / cam.mm_per_px),
            "--dynamics",
            scene.to_str().unwrap(),
        ],
    );
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir_out.join("compare.json")).unwrap())
            .unwrap();
    let e = j["dynamics"]["explained"].as_f64().unwrap();
    assert!((e - d.explained).abs() < 1e-9, "{e} vs {}", d.explained);
}

/// `--dynamics` with a scene of another train is refused, naming the option.
#[test]
fn compare_against_the_dynamics_of_another_train_is_refused() {
    let rec = g1_record(1.2);
    let (code, err, _) = run_cli(
        "dynamics_other",
        &rec.csv,
        &[
            "--px-per-mm",
            &format!("{}", 1.0 / cam().mm_per_px),
            "--dynamics",
            asset("assets/dynamics/rotor_g1.toml").to_str().unwrap(),
        ],
    );
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("dynamics") && err.contains("another train"),
        "{err}"
    );
}

fn scratch(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("compare_{name}"));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn g1_record(turns: f64) -> Record {
    let asm = assembly("assets/transplanter/g1_design.json");
    film(&asm.rebuild(), cam(), turns, 100.0, 1000.0, 11)
}

/// `ncgear compare` on `csv` with `args`: exit code and stderr.
fn run_cli(name: &str, csv: &str, args: &[&str]) -> (i32, String, PathBuf) {
    run_cli_on(name, csv, "assets/transplanter/g1_design.json", args)
}

/// [`run_cli`] against the design file `design`.
fn run_cli_on(name: &str, csv: &str, design: &str, args: &[&str]) -> (i32, String, PathBuf) {
    let d = scratch(name);
    let track = d.join("track.csv");
    std::fs::write(&track, csv).unwrap();
    let out = ncgear()
        .arg("compare")
        .arg(&track)
        .arg("--design")
        .arg(asset(design))
        .arg("--out")
        .arg(d.join("out"))
        .args(args)
        .output()
        .unwrap();
    // miette's wrapped box, as one line.
    let err = String::from_utf8_lossy(&out.stderr).replace(['│', '×'], " ");
    let err = err.split_whitespace().collect::<Vec<_>>().join(" ");
    (out.status.code().unwrap_or(-1), err, d.join("out"))
}

#[test]
fn compare_cli_writes_the_report_chart_and_frames() {
    let rec = g1_record(1.5);
    let (code, err, out) = run_cli(
        "cli",
        &rec.csv,
        &["--px-per-mm", &format!("{}", 1.0 / 0.3127), "--png"],
    );
    assert_eq!(code, 0, "{err}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("compare.json")).unwrap()).unwrap();
    assert!(
        (report["registration"]["rotation_deg"]["value"]
            .as_f64()
            .unwrap()
            - 17.3)
            .abs()
            < 0.05
    );
    assert_eq!(report["files"].as_array().unwrap().len(), 3);
    let svg = std::fs::read_to_string(out.join("compare.svg")).unwrap();
    assert!(svg.contains("outlier frames"));
    assert!(std::fs::metadata(out.join("compare.png")).unwrap().len() > 1000);
    let frames = std::fs::read_to_string(out.join("compare_frames.csv")).unwrap();
    assert_eq!(frames.lines().count(), rec.phi.len() + 1);
}

#[test]
fn compare_bad_input_exits_2_naming_it() {
    let rec = g1_record(1.5);
    let px = format!("{}", 1.0 / 0.3127);
    // Less than a turn.
    let short: String = rec
        .csv
        .lines()
        .take(rec.phi.len() / 2)
        .map(|l| format!("{l}\n"))
        .collect();
    let (code, err, _) = run_cli("short", &short, &["--px-per-mm", &px]);
    assert_eq!(code, 2);
    assert!(err.contains("carrier turn"), "{err}");
    // Time not increasing: line 6 goes back.
    let mut lines: Vec<String> = rec.csv.lines().map(String::from).collect();
    lines.swap(4, 5);
    let (code, err, _) = run_cli("time", &(lines.join("\n") + "\n"), &["--px-per-mm", &px]);
    assert_eq!(code, 2);
    assert!(
        err.contains(":6: time") && err.contains("not after"),
        "{err}"
    );
    // A non-finite value on line 9.
    let mut lines: Vec<String> = rec.csv.lines().map(String::from).collect();
    lines[8] = "0.007000,nan,12.0".into();
    let (code, err, _) = run_cli("nan", &(lines.join("\n") + "\n"), &["--px-per-mm", &px]);
    assert_eq!(code, 2);
    assert!(
        err.contains(":9: column `x`") && err.contains("finite"),
        "{err}"
    );
    // Pixels without a scale.
    let (code, err, _) = run_cli("px", &rec.csv, &[]);
    assert_eq!(code, 2);
    assert!(
        err.contains("pixels") && err.contains("--px-per-mm"),
        "{err}"
    );
    // An unknown column.
    let (code, err, _) = run_cli(
        "column",
        &rec.csv,
        &["--px-per-mm", &px, "--columns", "time,x,z"],
    );
    assert_eq!(code, 2);
    assert!(
        err.contains("no column `z`") && err.contains("time, x, y"),
        "{err}"
    );
    // Filmed from the other side.
    let mirrored: String = rec
        .csv
        .lines()
        .enumerate()
        .map(|(k, l)| {
            if k == 0 {
                return format!("{l}\n");
            }
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            format!("{},{},{}\n", v[0], -v[1], v[2])
        })
        .collect();
    let (code, err, _) = run_cli("mirror", &mirrored, &["--px-per-mm", &px]);
    assert_eq!(code, 2);
    assert!(err.contains("--mirror"), "{err}");
    let (code, err, _) = run_cli("mirrored", &mirrored, &["--px-per-mm", &px, "--mirror"]);
    assert_eq!(code, 0, "{err}");
}

/// Tracker's export (a title line, then t,x,y in its calibrated unit) and Kinovea's
/// (`;`-separated, ms, decimal commas), and frame numbers with --fps.
#[test]
fn compare_reads_tracker_kinovea_and_frame_numbers() {
    let t = parse_track(
        "mass A\nt,x,y\n0.0,1.5,2.5\n0.001,1.6,2.4\n,,\n0.003,1.7,2.3\n0.004,,\n",
        "t.csv",
        &ReadOptions::default(),
    )
    .unwrap();
    assert_eq!((t.format, t.tip.len(), t.skipped), ("tracker", 3, 2));
    assert_eq!(t.line, vec![3, 4, 6]);
    assert!(!t.y_down);
    let k = parse_track(
        "# Kinovea trajectory export\nTime (ms);X (px);Y (px)\n0;10,5;20,25\n40;11,5;21,25\n",
        "k.csv",
        &ReadOptions::default(),
    )
    .unwrap();
    assert_eq!(k.format, "kinovea");
    assert_eq!(k.time_s, vec![0.0, 0.04]);
    assert_eq!(k.tip[1], Point::new(11.5, 21.25));
    assert!(k.y_down);
    let f = parse_track(
        "frame,x,y\n10,1,2\n11,1,2\n",
        "f.csv",
        &ReadOptions {
            fps: Some(500.0),
            ..ReadOptions::default()
        },
    )
    .unwrap();
    assert!((f.time_s[1] - 11.0 / 500.0).abs() < 1e-15);
    let e = parse_track(
        "frame,x,y\n10,1,2\n11,1,2\n",
        "f.csv",
        &ReadOptions::default(),
    )
    .unwrap_err();
    assert!(e.to_string().contains("--fps"), "{e}");
    let p = parse_track("1 2 3\n2 2 3\n", "h.txt", &ReadOptions::default()).unwrap();
    assert_eq!(
        (p.format, p.time_s[1], p.tip[0]),
        ("headerless", 2.0, Point::new(2.0, 3.0))
    );
}

/// A second marker at the planet axis measures the needle's angle: the intermediate 0.3° off its
/// phase turns the needle at planting, and the track's pushing angle is the built train's, not
/// the design's.
#[test]
fn compare_a_marker_on_the_needle_axis_measures_the_built_needle_angle() {
    use ncgear::simulate::{FeatureOptions, Simulation, features};
    let asm = assembly("assets/transplanter/g1_design.json");
    let design = asm.rebuild();
    let mut built_asm = asm.clone();
    built_asm.intermediate_angle_at_zero_rad += 0.3f64.to_radians();
    let built = built_asm.rebuild();
    let cam = cam();
    let rec = film_with(&built, cam, 2.0, 100.0, 1000.0, 13, true);
    let track = parse_track(&rec.csv, "marker.csv", &ReadOptions::default()).unwrap();
    assert!(track.marker.is_some());
    let opts = CompareOptions {
        scale: Scale::PxPerMm(1.0 / cam.mm_per_px),
        carrier_axis: Some(cam.to_image(asm.center_mm)),
        rotation_rad: Some(cam.theta_deg.to_radians()),
        ..CompareOptions::default()
    };
    let r = compare(&track, &design, &opts).unwrap().report;
    let o = FeatureOptions::default();
    let truth = features(&Simulation::new(built_asm), &o).unwrap();
    let nominal = features(&Simulation::new(asm), &o).unwrap();
    let f = &r.features;
    println!(
        "marker: push {:.4}° (built {:.4}°, design {:.4}°), take {:.4}° (built {:.4}°, design {:.4}°)",
        f.track.push_angle_deg,
        truth.push_angle_deg,
        nominal.push_angle_deg,
        f.track.take_angle_deg,
        truth.take_angle_deg,
        nominal.take_angle_deg
    );
    assert_eq!(f.needle_from, "marker");
    // The 0.3° error turns the needle by 0.14° at planting, 0.11° at taking.
    for (a, b) in [
        (truth.push_angle_deg, nominal.push_angle_deg),
        (truth.take_angle_deg, nominal.take_angle_deg),
    ] {
        assert!(
            (a - b).abs() > 0.1,
            "the error turns the needle: {a} vs {b}"
        );
    }
    assert!((f.track.push_angle_deg - truth.push_angle_deg).abs() <= 0.05);
    assert!((f.track.take_angle_deg - truth.take_angle_deg).abs() <= 0.05);
}

/// A carrier whose speed swings ±8 % once a turn (the load varies over the turn): a constant
/// speed with a slow drift cannot time it, and the timing error shows as deviation; an encoder
/// column (0.01° counts) times every frame and the deviation is the noise floor again.
#[test]
fn compare_an_encoder_column_times_an_uneven_carrier() {
    let asm = assembly("assets/transplanter/g1_design.json");
    let rebuilt = asm.rebuild();
    let cam = cam();
    let mut rng = ChaCha8Rng::seed_from_u64(17);
    let (fps, w0) = (1000.0, TAU * 100.0 / 60.0);
    let (mut phi, mut with, mut without) = (
        0.4,
        String::from("time (s),x (px),y (px),encoder\n"),
        String::from("time (s),x (px),y (px)\n"),
    );
    let start = phi;
    for i in 0..1300 {
        let t = i as f64 / fps;
        let q = rebuilt.pose(phi).tip_mm + Point::new(gauss(&mut rng), gauss(&mut rng)) * 0.3;
        let p = cam.to_image(q);
        let enc = ((phi - start).to_degrees() * 100.0).round() / 100.0;
        with.push_str(&format!("{t:.6},{:.5},{:.5},{enc:.2}\n", p.x, p.y));
        without.push_str(&format!("{t:.6},{:.5},{:.5}\n", p.x, p.y));
        phi += w0 * (1.0 + 0.08 * phi.sin()) / fps;
    }
    let opts = CompareOptions {
        scale: Scale::PxPerMm(1.0 / cam.mm_per_px),
        ..CompareOptions::default()
    };
    let run = |csv: &str| {
        let track = parse_track(csv, "uneven.csv", &ReadOptions::default()).unwrap();
        compare(&track, &rebuilt, &opts).unwrap().report
    };
    let (e, f) = (run(&with), run(&without));
    println!(
        "uneven carrier: encoder: rotation {:.5}°, d rms {:.4} mm (floor {:.4}); fitted timing: rotation {:.5}°, d rms {:.4} mm",
        e.registration.rotation_deg.value - cam.theta_deg,
        e.deviation.rms_mm,
        e.deviation.noise_floor_mm,
        f.registration.rotation_deg.value - cam.theta_deg,
        f.deviation.rms_mm
    );
    assert!(e.track.encoder && !f.track.encoder);
    assert!((e.registration.rotation_deg.value - cam.theta_deg).abs() <= 0.05);
    assert!(e.deviation.rms_mm <= 2.0 * e.deviation.noise_floor_mm);
    assert!(
        f.deviation.rms_mm > 5.0 * e.deviation.rms_mm,
        "the fitted timing cannot follow the swing"
    );
}
