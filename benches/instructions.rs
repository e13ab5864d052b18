//! Instruction counts of the hot paths under Valgrind's callgrind (gungraun): the speed gate that
//! counts work, not seconds (docs/performance.md, "The instruction gate"). A count moves with the
//! work done, not with the machine's load or where the linker put a loop, so
//! `scripts/check_instructions.sh` compares each against benches/instructions/baseline.toml.
//!
//! Run: `cargo bench --bench instructions` (needs valgrind and `gungraun-runner` of the gungraun
//! version in Cargo.lock; the script installs both). Each benchmark runs its work once, on the
//! benchmark's own thread (a one-thread rayon pool made of it: callgrind counts the function's
//! thread, and a pool's worker threads would escape it), from inputs its setup reads uncounted.
//! The wall-clock benches of the docs stay in the other files of benches/.
#[path = "common/mod.rs"]
mod common;

use gungraun::{
    Callgrind, LibraryBenchmarkConfig, library_benchmark, library_benchmark_group, main,
};
use ncgear::analysis::peak::PeakOptions;
use ncgear::analysis::tolerance::{Analysis, ErrorFile};
use ncgear::config::Format;
use ncgear::design::report::DesignReport;
use ncgear::design::trajectory::Trajectory;
use ncgear::design::{DesignOptions, design, redesign};
use ncgear::loads::{LoadCase, RotorSource, Scene};
use ncgear::math::monte_carlo::McOptions;
use ncgear::pair::{Expr, Law, PairOptions, design_pair};
use std::hint::black_box;
use std::path::{Path, PathBuf};

fn asset(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets")
        .join(rel)
}

/// `work` on this thread alone: a rayon pool of one thread, this one, so that every parallel
/// loop inside runs here, in the order one thread takes it.
fn on_this_thread<T: Send>(work: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .use_current_thread()
        .build()
        .expect("a pool of the current thread")
        .install(work)
}

fn target(name: &str) -> Trajectory {
    Trajectory::from_path(&asset(&format!("trajectories/{name}"))).expect("bundled target")
}

/// `ncgear design T [--module M]` as the command designs (a failed design's alternatives are
/// named, not designed, unless `--alternatives` asks).
fn design_input((name, module): (&str, Option<f64>)) -> (Trajectory, DesignOptions) {
    let opts = DesignOptions::default().with_module_mm(module);
    (target(name), opts)
}

#[library_benchmark]
#[bench::g1(args = (("g1_ellipse.csv", None)), setup = design_input)]
#[bench::g1_m2(args = (("g1_ellipse.csv", Some(2.0))), setup = design_input)]
#[bench::kidney(args = (("designer_kidney.csv", None)), setup = design_input)]
fn design_target((t, opts): (Trajectory, DesignOptions)) -> f64 {
    let d = on_this_thread(|| design(black_box(&t), &opts).expect("designed"));
    d.report.roundtrip.max_deviation_mm
}

/// The designer's edit (`POST /api/design` with `start`): G1 moved by a bump of `amp` mm over
/// ~10 points, re-designed warm from the design before it (`ncgear::design::redesign`).
fn edit_input(amp: f64) -> (Trajectory, DesignOptions, DesignReport) {
    let t = target("g1_ellipse.csv");
    let opts = DesignOptions::default();
    let before = design(&t, &opts).expect("G1").report;
    (common::edit::bumped(&t, amp), opts, before)
}

#[library_benchmark]
#[bench::g1_bump_1mm(args = (1.0), setup = edit_input)]
fn warm_edit((t, opts, before): (Trajectory, DesignOptions, DesignReport)) -> f64 {
    let d = on_this_thread(|| redesign(black_box(&t), &opts, &before).expect("redesigned"));
    d.report.roundtrip.max_deviation_mm
}

/// The Monte Carlo of `ncgear tolerance assets/tolerance/paper_3k.toml`: `samples` random
/// assemblies, seed 1, certified peaks on the default grid.
fn paper(samples: usize) -> (Analysis, McOptions) {
    let text = std::fs::read_to_string(asset("tolerance/paper_3k.toml")).expect("bundled");
    let file = ErrorFile::parse(&text, "paper_3k.toml", Format::Toml).expect("bundled example");
    let opts = McOptions::default().with_samples(samples).with_seed(1);
    (Analysis::new(&file, PeakOptions::default()), opts)
}

#[library_benchmark]
#[bench::paper_50k(args = (50_000), setup = paper)]
fn monte_carlo((a, opts): (Analysis, McOptions)) -> f64 {
    let none = ncgear::progress::Progress::none();
    let (stats, _) = on_this_thread(|| a.monte_carlo(black_box(&opts), &none).expect("finite"));
    stats.mean
}

/// The loads of the bundled rotor (assets/loads/rotor.toml: face width "auto", ISO rating) on
/// the bundled G1 train at m = 2, its teeth made again by the setup.
fn rotor(_: ()) -> (RotorSource, LoadCase) {
    let source = RotorSource::read(&asset("loads/g1_m2_design.json"), true).expect("design");
    let scene = Scene::from_path(&asset("loads/rotor.toml")).expect("scene");
    (source, scene.validate("rotor.toml").expect("valid"))
}

#[library_benchmark]
#[bench::rotor_g1_m2(args = (()), setup = rotor)]
fn loads((source, case): (RotorSource, LoadCase)) -> ncgear::loads::LoadsReport {
    on_this_thread(|| {
        ncgear::loads::analyse(&source.rotor(), black_box(&case), "rotor.toml").expect("loads")
    })
}

/// The bundled rotor in motion (assets/dynamics/rotor_g1.toml: every effect, 300 r/min, settled
/// in two turns).
fn rotor_scene(_: ()) -> ncgear::analysis::dynamics::rotor::Prepared {
    ncgear::analysis::dynamics::rotor::Prepared::from_path(&asset("dynamics/rotor_g1.toml"))
        .expect("the bundled rotor scene")
}

#[library_benchmark]
#[bench::rotor_g1_settled(args = (()), setup = rotor_scene)]
fn dynamics(p: ncgear::analysis::dynamics::rotor::Prepared) -> u32 {
    on_this_thread(|| {
        black_box(&p)
            .run(&ncgear::progress::Progress::none())
            .expect("run")
            .report
            .steady
            .turns
    })
}

/// `ncgear pair "phi - 0.08*sin(2*phi)" --teeth 24 --module 1.5`: the design with its default
/// 90-step mesh verification (benches/pair.rs).
fn pair_input(steps: usize) -> (Law, PairOptions) {
    let mut opts = PairOptions::new(Some(24), 1.5);
    opts.toothing.verify_steps = steps;
    let law = Law::Motion(Expr::parse("phi - 0.08*sin(2*phi)").expect("valid law"));
    (law, opts)
}

#[library_benchmark]
#[bench::law_24_teeth(args = (90), setup = pair_input)]
fn pair((law, opts): (Law, PairOptions)) -> ncgear::pair::PairDesign {
    on_this_thread(|| design_pair(black_box(&law), &opts).expect("pair"))
}

library_benchmark_group!(
    name = hot_paths;
    benchmarks = design_target, warm_edit, monte_carlo, loads, dynamics, pair
);

main!(
    // Instructions only: no cache simulation (half the time under valgrind; the gate compares Ir).
    config = LibraryBenchmarkConfig::default().tool(Callgrind::with_args(["--cache-sim=no"]));
    library_benchmark_groups = hot_paths
);
