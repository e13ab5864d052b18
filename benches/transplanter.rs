//! Transplanter tolerance analysis on G1 (docs/math/companion.md §C.6): one exact state (both meshes solved), the
//! linear model build (720 carrier angles × 16 coordinates × central differences), one exact
//! turn, and the linear Monte Carlo per 1000 samples. Run: `cargo bench --bench transplanter`.
use ncgear::analysis::transplanter::{ErrorInventory, ExactModel, FdSteps, Inventory, LinearModel};
use ncgear::config::Format;
use ncgear::geometry::assembly::Assembly;
use ncgear::geometry::golden::g1_mechanism;
use ncgear::math::Point;
use ncgear::math::monte_carlo::McOptions;

fn main() {
    divan::main();
}

fn setup() -> (Assembly, Inventory, ExactModel) {
    let asm = Assembly::from_mechanism(&g1_mechanism(), Point::new(0.0, 0.0), 1, 720).expect("G1");
    let inv = ErrorInventory::parse(
        include_str!("../assets/transplanter/g1_errors.toml"),
        "g1_errors.toml",
        Format::Toml,
    )
    .expect("bundled example");
    let m = ExactModel::new(&asm, inv.pressure_angle_rad, inv.load_side).expect("model");
    (asm, inv, m)
}

/// One exact state (per carrier angle).
#[divan::bench]
fn exact_state(b: divan::Bencher) {
    let (_, inv, m) = setup();
    let x = inv.nominal_vector();
    b.bench(|| m.state(divan::black_box(0.7), &x).expect("contact"));
}

/// One exact turn of 720 carrier angles.
#[divan::bench(sample_count = 20)]
fn exact_turn_720(b: divan::Bencher) {
    let (_, inv, m) = setup();
    let x = inv.nominal_vector();
    let grid = m.grid(720);
    b.bench(|| m.trace(&grid, &x).expect("contact"));
}

/// Linear model: 720 carrier angles × 16 coordinates, central differences.
#[divan::bench(sample_count = 5)]
fn linear_build_720(b: divan::Bencher) {
    let (_, _, m) = setup();
    b.bench(|| LinearModel::build(&m, 720, FdSteps::default()).expect("build"));
}

/// Linear Monte Carlo, 1000 samples of max_φ |ΔB| over 720 carrier angles.
#[divan::bench(sample_count = 10)]
fn linear_mc_1000(b: divan::Bencher) {
    let (_, inv, m) = setup();
    let lin = LinearModel::build(&m, 720, FdSteps::default()).expect("build");
    let opts = McOptions::default()
        .with_samples(1000)
        .with_seed(1)
        .with_bins(20);
    b.bench(|| {
        ncgear::math::monte_carlo::run(
            &opts,
            |r, _| lin.max_deviation_mm(&inv.draw(r)),
            &ncgear::progress::Progress::none(),
        )
        .expect("finite")
    });
}
