//! Gear-quality limits of the design chain on designer targets (no train traces them exactly).
//!
//! Limits (α = 20°): α + max|atan(r_θ/r)| ≤ 45° on sun, intermediate and planet; every concave
//! arc |ρ| ≥ 10 mm; i21 ∈ [0.3, 3.3]. For each target, `design()` with default options must
//! (i) stay within the limits by the independent table check of [`limits_check`], and
//! (ii) reach a deviation (the Hausdorff distance between the target polyline and `d.traced_mm`,
//! both ways, as the design reports it) within 1.05× of the independent constrained optimum of
//! [`reference`].
//!
//! Run: `cargo test --release --test it quality -- --nocapture`; with
//! `NCGEAR_QUALITY_SEEDS=7104,7105` it measures those generated targets instead of the fixed set.
use ncgear::math::Point;
pub mod limits_check;
pub mod model;
pub mod reference;
pub mod search;

use crate::robust::forward::{Family, generate};
use limits_check::{GEAR_NAMES, Limits, Quality, assert_within, evaluate, violations};
use ncgear::design::trajectory::Trajectory;
use ncgear::design::{DesignOptions, design};
use std::path::Path;
use std::time::Instant;

/// The chain's deviation may exceed the reference's by this factor.
const FACTOR: f64 = 1.05;
/// Seeds of the generated designer targets (the robustness suite uses 4000..4030); 7108 and
/// 7113 were 13 % and 17 % behind the reference before the minimax weighed both sides.
const SEEDS: [u64; 5] = [7101, 7102, 7103, 7108, 7113];
/// Target files in the repository.
const FILES: [&str; 4] = [
    "assets/trajectories/designer_kidney.csv",
    "assets/cases/designer_even2.csv",
    "assets/cases/designer_odd2.csv",
    "assets/cases/designer_odd3.csv",
];

fn targets() -> Vec<(String, Vec<Point>, u64)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut v: Vec<(String, Vec<Point>, u64)> = FILES
        .iter()
        .enumerate()
        .map(|(k, f)| {
            let t = Trajectory::from_path(&root.join(f)).expect("target file reads");
            let name = Path::new(f).file_stem().unwrap().to_string_lossy().into();
            (name, t.points().to_vec(), k as u64)
        })
        .collect();
    // `NCGEAR_QUALITY_SEEDS=1,2,3` measures other generated targets (the files are then skipped).
    let seeds: Vec<u64> = match std::env::var("NCGEAR_QUALITY_SEEDS") {
        Ok(list) => {
            v.clear();
            list.split(',')
                .filter_map(|x| x.trim().parse().ok())
                .collect()
        }
        Err(_) => SEEDS.to_vec(),
    };
    for s in seeds {
        let mut c = generate(Family::Designer, s);
        // The reference takes counter-clockwise targets: a clockwise one is mirrored (x → −x),
        // which changes neither the best deviation nor the gears' limits.
        let area: f64 = (0..c.points.len())
            .map(|k| {
                let (p, q) = (c.points[k], c.points[(k + 1) % c.points.len()]);
                p.x * q.y - q.x * p.y
            })
            .sum();
        let mut name = format!("designer seed {s}");
        if area < 0.0 {
            c.points.iter_mut().for_each(|p| p.x = -p.x);
            name.push_str(" (mirrored)");
        }
        v.push((name, c.points, s));
    }
    v
}

fn show(q: &Quality, lim: &Limits) -> (String, String) {
    let tight = q
        .gears
        .iter()
        .zip(GEAR_NAMES)
        .filter_map(|(g, n)| g.tightest_concave_mm.map(|r| (r, n)))
        .min_by(|a, b| a.0.total_cmp(&b.0));
    (
        format!("{:.2}", q.pressure_deg(lim)),
        tight.map_or("convex".into(), |(r, n)| format!("{r:.1} ({n})")),
    )
}

/// Targets on which the chain is known to miss the reference by more than [`FACTOR`], with
/// the deviation measured when recorded (mm; it may not get worse) and why. Within the limits
/// they must still be. None at present: seed 7101, recorded at 1.18× while the reference was
/// one-sided, is at 1.02× of the two-sided reference since the minimax weighs the traced
/// curve's distance from the target (2026-11-27).
const KNOWN_MISSES: [(&str, f64, &str); 0] = [];

#[test]
fn designer_targets_meet_the_limits_near_the_constrained_optimum() {
    let lim = Limits::default();
    let mut rows = vec![
        "| case | points | reference dev (mm) | ref pressure (deg) | ref tightest concave (mm) | ref i21 | ref time (s) | chain dev (mm) | chain / ref | chain pressure (deg) | chain tightest concave (mm) | chain i21 |".to_string(),
        "|---|---|---|---|---|---|---|---|---|---|---|---|".to_string(),
    ];
    let mut failures = Vec::new();
    let t_all = Instant::now();
    for (name, points, seed) in targets() {
        let r = reference::reference(&points, seed);
        let rq = Quality {
            gears: r.gears,
            ratio_range: r.ratio_range,
        };
        // The reference is only a bound if it is itself within the limits.
        assert_within(&format!("{name} (reference)"), &rq, &lim);
        // The reference train traced by the library's kinematics gives the same deviation.
        let lib_path: Vec<Point> = (0..8192)
            .map(|k| r.mechanism.tip(std::f64::consts::TAU * k as f64 / 8192.0))
            .collect();
        let lib_dev = search::hausdorff_closed(&points, &lib_path);
        assert!(
            (lib_dev - r.deviation_mm).abs() <= 0.01,
            "{name}: reference deviation {:.4} mm, its train traced by Mechanism::tip {lib_dev:.4} mm",
            r.deviation_mm
        );
        let (rp, rc) = show(&rq, &lim);
        let traj = Trajectory::from_points(points.clone()).expect("target is a trajectory");
        let chain = match design(&traj, &DesignOptions::default()) {
            Ok(d) => {
                let q = evaluate(&d.report);
                let dev = search::hausdorff_closed(traj.points(), &d.traced_mm);
                let v = violations(&q, &lim);
                if !v.is_empty() {
                    failures.push(format!(
                        "{name}: chain outside the limits: {}",
                        v.join("; ")
                    ));
                }
                let known = KNOWN_MISSES.iter().find(|k| k.0 == name);
                if let Some((_, bound, why)) = known {
                    // A known miss still may not get worse than measured when it was recorded.
                    if !(dev <= *bound) {
                        failures.push(format!(
                            "{name} (known miss: {why}): chain deviation {dev:.4} mm > recorded {bound} mm"
                        ));
                    }
                } else if !(dev <= FACTOR * r.deviation_mm) {
                    failures.push(format!(
                        "{name}: chain deviation {dev:.4} mm > {FACTOR} × reference {:.4} mm",
                        r.deviation_mm
                    ));
                }
                let (p, c) = show(&q, &lim);
                let [lo, hi] = q.ratio_range;
                format!(
                    "{dev:.4} | {:.3} | {p} | {c} | [{lo:.3}, {hi:.3}]",
                    dev / r.deviation_mm
                )
            }
            Err(e) => {
                failures.push(format!("{name}: design refused: {e}"));
                "refused | – | – | – | –".into()
            }
        };
        let [lo, hi] = r.ratio_range;
        rows.push(format!(
            "| {name} | {} | {:.4} | {rp} | {rc} | [{lo:.3}, {hi:.3}] | {:.1} | {chain} |",
            points.len(),
            r.deviation_mm,
            r.seconds
        ));
        eprintln!(
            "{name}: reference {} evaluations in {:.1} s, per start (mm) {:?}",
            r.evaluations,
            r.seconds,
            r.per_start_mm
                .iter()
                .map(|v| format!("{v:.4}"))
                .collect::<Vec<_>>()
        );
    }
    eprintln!("{}", rows.join("\n"));
    eprintln!("total {:.1} s", t_all.elapsed().as_secs_f64());
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The reference's forward model reproduces the library's `Mechanism::tip` for a Fourier ratio
/// (same conventions, independent kinematics) to 1e-6 mm, and its grid limits match the table check.
#[test]
fn reference_model_matches_the_mechanism() {
    use ncgear::geometry::{fourier::SunRatio, mechanism::Mechanism};
    let ratio = SunRatio::new(vec![0.2, 0.0, 0.03, 0.08], vec![0.05, -0.03, 0.0, 0.02]).unwrap();
    let m = Mechanism {
        a_mm: 44.0,
        l3_mm: 172.0,
        ratio: ratio.clone(),
        sun_phase_rad: 0.7,
        needle_angle_rad: -1.1,
        idler_offset_rad: 0.0,
    };
    let n = reference::GRID;
    let t = model::Train {
        a: 44.0,
        l3: 172.0,
        gamma: -1.1,
        phi_ref: 0.7,
        ratio: model::Ratio::from_fn(n, |u| ratio.eval3(u)),
    };
    let tips = t.tips();
    let worst = (0..n)
        .map(|j| {
            let b = m.tip(std::f64::consts::TAU * j as f64 / n as f64 + 0.7);
            tips[j].distance(b)
        })
        .fold(0.0, f64::max);
    assert!(worst < 1e-6, "model vs Mechanism::tip: {worst:e} mm");
    let e = t.extremes();
    let tables = t.tables();
    let q = tables.map(|r| limits_check::gear_quality(&r));
    let slope = q.iter().map(|g| g.slope_deg).fold(0.0, f64::max);
    assert!(
        (slope - e.slope_tan.atan().to_degrees()).abs() < 1e-3,
        "{slope} vs {}",
        e.slope_tan.atan().to_degrees()
    );
    let kappa = q
        .iter()
        .filter_map(|g| g.tightest_concave_mm)
        .map(|r| 1.0 / r)
        .fold(0.0, f64::max);
    assert!(e.concave_curvature > 0.0, "the test ratio has concave arcs");
    assert!(
        (kappa - e.concave_curvature).abs() < 1e-4 * e.concave_curvature,
        "{kappa} vs {}",
        e.concave_curvature
    );
}
