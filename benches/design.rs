//! Benchmarks of the design chain (divan). Run: `cargo bench --bench design`.
//! The accuracy-vs-time table of docs/accuracy.md comes from `cargo run --release --example accuracy -- design`.
#[path = "common/mod.rs"]
mod common;

use ncgear::design::trajectory::Trajectory;
use ncgear::design::{DesignOptions, RefineMode, design};
use ncgear::math::Point;

fn main() {
    divan::main();
}

fn load(name: &str) -> Trajectory {
    let p = format!("{}/assets/trajectories/{name}", env!("CARGO_MANIFEST_DIR"));
    Trajectory::from_path(std::path::Path::new(&p)).expect("bundled example")
}

/// The full chain on the 360-point G1 trajectory with default options (adaptive K).
#[divan::bench(sample_count = 20)]
fn full_chain_g1_360(b: divan::Bencher) {
    let t = load("g1_ellipse.csv");
    let opts = DesignOptions::default();
    b.bench(|| design(divan::black_box(&t), &opts).expect("G1"));
}

/// The full chain at fixed order K (patent route only).
#[divan::bench(args = [4, 8, 16, 32], sample_count = 10)]
fn patent_route_order(b: divan::Bencher, k: usize) {
    let t = load("g1_ellipse.csv");
    let opts = DesignOptions::default()
        .with_order(Some(k))
        .with_refine(RefineMode::Off);
    b.bench(|| design(divan::black_box(&t), &opts).expect("G1"));
}

/// Designer-style target: the patent route misses, so the LM refinement runs (K = 12).
#[divan::bench(sample_count = 10)]
fn designer_with_refinement(b: divan::Bencher) {
    let t = load("designer_kidney.csv");
    let opts = DesignOptions::default();
    b.bench(|| design(divan::black_box(&t), &opts).expect("designer"));
}

/// What the gear limits cost in time: the full chain on G1 and on the designer kidney with the
/// limits as constraints (default) and without (`limits = false`).
#[divan::bench(args = [("g1_ellipse.csv", true), ("g1_ellipse.csv", false), ("designer_kidney.csv", true), ("designer_kidney.csv", false)], sample_count = 5)]
fn limits_cost(b: divan::Bencher, (name, limits): (&str, bool)) {
    let t = load(name);
    let opts = DesignOptions::default().with_limits(limits);
    b.bench(|| design(divan::black_box(&t), &opts).expect("design"));
}

/// Designed for a module (the perimeter zπm a constraint of the fit at both neighbouring z).
#[divan::bench(args = [1.5, 2.0], sample_count = 5)]
fn designed_for_module_g1(b: divan::Bencher, module_mm: f64) {
    let t = load("g1_ellipse.csv");
    let opts = DesignOptions::default().with_module_mm(Some(module_mm));
    b.bench(|| design(divan::black_box(&t), &opts).expect("G1"));
}

/// Teeth on the designed G1 train at m = 2 (z = 23): outlines of the three gears at the export
/// chord tolerance 1e-3·m, with `steps` verified carrier positions per mesh (0 = none).
#[divan::bench(args = [0, 12], sample_count = 5)]
fn teeth_g1_module_2(b: divan::Bencher, steps: usize) {
    use ncgear::design::train::{TrainSource, TrainTeethOptions, tooth_train};
    let d = design(&load("g1_ellipse.csv"), &DesignOptions::default()).expect("G1");
    let mut opts = TrainTeethOptions::new(2.0);
    opts.toothing.verify_steps = steps;
    b.bench(|| {
        let on = TrainSource::Assembly {
            assembly: divan::black_box(&d.assembly),
            target_mm: &d.report.target_points,
        };
        tooth_train(on, &opts).expect("G1 teeth")
    });
}

/// One case per family (`assets/cases/`, made by an independent forward model): the
/// whole chain with default options, the fit to the points included. `exact_cw_offset` is CW
/// with its carrier axis at the centre named in the file's `# center:` line.
#[divan::bench(
    args = [
        "exact_two_harmonic", "exact_three_harmonic", "exact_concave_sun", "exact_sparse_200",
        "exact_cw_offset", "noisy_020um", "noisy_050um", "noisy_030um_400", "designer_even2",
        "designer_odd3", "designer_odd2",
    ],
    sample_count = 5
)]
fn family_case(b: divan::Bencher, name: &str) {
    let p = format!("{}/assets/cases/{name}.csv", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&p).expect("bundled case");
    let center = text
        .lines()
        .find_map(|l| l.strip_prefix("# center:"))
        .map_or(Point::ZERO, |c| {
            let v: Vec<f64> = c.split(',').map(|x| x.trim().parse().unwrap()).collect();
            Point::new(v[0], v[1])
        });
    let t = Trajectory::parse_csv(&text, name).expect("bundled case");
    let opts = DesignOptions::default().with_center_mm(center);
    b.bench(|| design(divan::black_box(&t), &opts).expect("designed"));
}

/// One edit of the interactive designer: the target moved by a bump of `amp` mm (Gaussian over
/// ~10 points) and re-designed warm from the design before the edit
/// (`ncgear::design::redesign`, what `ncgear serve` runs on each drag).
#[divan::bench(args = [0.2, 1.0, 3.0], sample_count = 20)]
fn redesign_after_edit_g1(b: divan::Bencher, amp: f64) {
    let t = load("g1_ellipse.csv");
    let opts = DesignOptions::default();
    let before = design(&t, &opts).expect("G1");
    let moved = common::edit::bumped(&t, amp);
    b.bench(|| {
        ncgear::design::redesign(divan::black_box(&moved), &opts, &before.report)
            .expect("redesigned")
    });
}
