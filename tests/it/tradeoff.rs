//! `ncgear tradeoff` end to end on the designer kidney: the ladder's rows, the limits held, the
//! default row equal to a plain design, and the same `tradeoff.json` for any thread count.
use crate::cli::{ncgear, succeed};
use ncgear::design::trajectory::Trajectory;
use ncgear::design::{DesignOptions, design};
use std::path::{Path, PathBuf};

fn out_dir(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&d);
    d
}

const KIDNEY: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/assets/trajectories/designer_kidney.csv"
);

/// The row's max deviation, mm; panics with the refusal when the row has none.
fn deviation(row: &serde_json::Value) -> f64 {
    row["designed"]["max_deviation_mm"]
        .as_f64()
        .unwrap_or_else(|| panic!("row refused: {row}"))
}

#[test]
fn tradeoff_on_the_designer_kidney() {
    let (a, b) = (out_dir("tradeoff_a"), out_dir("tradeoff_b"));
    let run = |dir: &Path, threads: &str| {
        succeed(
            ncgear()
                .env("RAYON_NUM_THREADS", threads)
                .args(["tradeoff", KIDNEY, "--json", "--out"])
                .arg(dir),
        )
    };
    // Two runs, one on a single thread: the same bytes.
    let out = run(&a, "2");
    run(&b, "1");
    let (ja, jb) = (
        std::fs::read(a.join("tradeoff.json")).unwrap(),
        std::fs::read(b.join("tradeoff.json")).unwrap(),
    );
    assert_eq!(ja, jb, "tradeoff.json differs between 2 threads and 1");
    assert_eq!(
        std::fs::read(a.join("tradeoff.md")).unwrap(),
        std::fs::read(b.join("tradeoff.md")).unwrap()
    );
    let svg = std::fs::read_to_string(a.join("tradeoff.svg")).unwrap();
    assert!(svg.contains("Deviation vs module") && svg.contains("default (45°)"));
    // --json prints the file's table.
    let t: serde_json::Value = serde_json::from_slice(&out.stdout).expect("stdout is JSON");
    assert_eq!(t, serde_json::from_slice::<serde_json::Value>(&ja).unwrap());
    assert!(
        !String::from_utf8_lossy(&ja).contains("time"),
        "no times in the JSON"
    );

    let rows = t["rows"].as_array().unwrap();
    let labels: Vec<&str> = rows.iter().map(|r| r["label"].as_str().unwrap()).collect();
    assert_eq!(
        labels,
        [
            "pressure angle ≤ 35°",
            "pressure angle ≤ 40°",
            "pressure angle ≤ 45°",
            "pressure angle ≤ 50°",
            "no limits",
            "intermediate axis off the line",
            "module 1 mm",
            "module 1.5 mm",
            "module 2 mm",
            "module 2.5 mm",
            "module 3 mm",
        ]
    );
    let defaults: Vec<usize> = (0..rows.len())
        .filter(|&k| rows[k]["is_default"] == true)
        .collect();
    assert_eq!(defaults, [2], "the 45° row, alone, is the default");

    // Every limited row within its pressure-angle limit; the module rows have their teeth.
    for r in rows {
        if let Some(limit) = r["max_pressure_angle_deg"].as_f64() {
            let pa = r["designed"]["pressure_angle_deg"].as_f64().unwrap();
            assert!(pa <= limit, "{}: {pa}° > {limit}°", r["label"]);
        }
        if r["module_mm"].is_number() {
            assert!(r["designed"]["teeth"].as_u64().unwrap() >= 8, "{r}");
        }
    }
    assert!(rows[4]["max_pressure_angle_deg"].is_null());
    let pa_free = rows[4]["designed"]["pressure_angle_deg"].as_f64().unwrap();
    assert!(pa_free > 50.0, "the unlimited kidney needs {pa_free}°");

    // The unlimited row is the closest design of all, or names the limited design that is
    // closer (within its absent limits too: a local optimum of the unlimited fit).
    let free = deviation(&rows[4]);
    let closest = rows[..5]
        .iter()
        .map(deviation)
        .fold(f64::INFINITY, f64::min);
    match rows[4]["closer_tighter_design"].as_str() {
        None => assert!(free <= closest, "no limits: {free} > {closest} unflagged"),
        Some(by) => {
            let j = labels.iter().position(|l| *l == by).unwrap();
            assert!(j < 4 && deviation(&rows[j]) == closest, "no limits: {by}");
        }
    }
    // A module row on the carrier line is one of the collinear trains the limited rows choose
    // from (at a fixed size): never closer than the closest of them. Off the line (an idler
    // offset) the arm is free of the tooth count and the contact shift of the planet law frees
    // the even harmonics a collinear train cannot follow: the kidney is closer at m = 1.5 and 2
    // than any collinear design.
    for r in &rows[6..] {
        let offset = r["designed"]["idler_offset_deg"].as_f64().unwrap();
        if offset == 0.0 {
            assert!(
                closest <= deviation(r),
                "{}: {} < {closest}",
                r["label"],
                deviation(r)
            );
        }
    }
    for r in &rows[7..9] {
        let offset = r["designed"]["idler_offset_deg"].as_f64().unwrap();
        assert!(
            offset.abs() > 1.0 && offset.abs() <= 30.0,
            "{}: ε = {offset}°",
            r["label"]
        );
        // 0.55 and 0.83 mm against 1.57 mm (2026-11-28; 0.47 and 0.49 mm when the module stage
        // started from the collinear free design, which traced the 28 bundled module runs 2.5×
        // farther in geometric mean — docs/design.md, "Gears you can make").
        assert!(
            deviation(r) < 0.6 * closest,
            "{}: {} against {closest} on the line",
            r["label"],
            deviation(r)
        );
    }
    // The off-line row: the default limits held, the intermediate axis off the line (the
    // layout the module rows use), no module — the even harmonics a collinear train cannot
    // follow traced, within the same limits (designer_kidney: 0.08 against 1.57 mm on the line,
    // 2026-11-28); it is another layout, so no limit row is flagged against it.
    let off = &rows[5];
    assert_eq!(off["off_line"], true);
    assert_eq!(off["max_pressure_angle_deg"].as_f64(), Some(45.0));
    assert!(off["module_mm"].is_null());
    let eps = off["designed"]["idler_offset_deg"].as_f64().unwrap();
    assert!(eps.abs() > 1.0 && eps.abs() <= 30.0, "off-line ε = {eps}°");
    assert!(
        deviation(off) < 0.25 * closest,
        "off the line: {} against {closest} on the line",
        deviation(off)
    );
    for r in &rows[..5] {
        assert_ne!(r["closer_tighter_design"].as_str(), Some(labels[5]), "{r}");
    }
    // Loosening the limit from 35° to none: the deviation does not grow, except where a design
    // under a tighter limit (within this row's limits too) is closer — the row names it.
    for k in 1..4 {
        let (prev, cur) = (deviation(&rows[k - 1]), deviation(&rows[k]));
        let closer = rows[k]["closer_tighter_design"].as_str();
        match closer {
            None => assert!(cur <= prev, "{}: {cur} > {prev} unflagged", labels[k]),
            Some(by) => {
                let j = labels.iter().position(|l| *l == by).unwrap();
                assert!(j < k && deviation(&rows[j]) < cur, "{}: {by}", labels[k]);
            }
        }
    }

    // The default row is a plain design with the default options, to the bit.
    let traj = Trajectory::from_path(Path::new(KIDNEY)).unwrap();
    let d = design(&traj, &DesignOptions::default()).unwrap();
    let plain = serde_json::to_string(&d.report.roundtrip.max_deviation_mm).unwrap();
    let row = serde_json::to_string(&rows[2]["designed"]["max_deviation_mm"]).unwrap();
    assert_eq!(row, plain, "the default row is not the plain design");
    assert_eq!(
        rows[2]["designed"]["binding"],
        serde_json::json!(d.report.limits.binding)
    );
}

/// Strict: the deviation never grows as the limit loosens. Fails on the kidney today: the fits at
/// 40° and 45° settle in local optima farther than the 35° design (1.92 and 1.82 mm against
/// 1.73 mm), which is within both limits.
#[test]
#[ignore = "the chain's fit at 40°/45° lands in a local optimum the 35° design beats"]
fn tradeoff_deviation_is_monotone_in_the_limit() {
    let traj = Trajectory::from_path(Path::new(KIDNEY)).unwrap();
    let t = ncgear::design::tradeoff::trade_off(
        &traj,
        &DesignOptions::default(),
        &ncgear::progress::Progress::none(),
    )
    .unwrap();
    let dev: Vec<f64> = t.rows[..5]
        .iter()
        .map(|r| r.numbers().unwrap().max_deviation_mm)
        .collect();
    for k in 1..5 {
        assert!(dev[k] <= dev[k - 1], "{}: {dev:?}", t.rows[k].label);
    }
}
