//! Benchmarks of the rotor's loads (divan). Run: `cargo bench --bench loads`.
//!
//! The loads of a design (the kinetostatics over 720 samples, the teeth made again from the
//! design file and rated), and the module sized by strength, beside the design's own time: the
//! design of G1 for a module, the unit the sizing repeats.
use ncgear::design::trajectory::Trajectory;
use ncgear::design::{DesignOptions, design};
use ncgear::loads::{RotorSource, Scene, SizingOptions, analyse, run_scene, size_module};
use std::path::Path;

fn main() {
    divan::main();
}

fn asset(rel: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets")
        .join(rel)
}

/// The whole `ncgear loads` of the bundled scene: the design file read, its teeth made again,
/// the turn solved and both meshes rated.
#[divan::bench(sample_count = 20)]
fn loads_g1_m2_rated() -> ncgear::loads::LoadsReport {
    run_scene(&asset("loads/g1_rotor.toml")).expect("bundled scene")
}

/// The loads alone (no rating): the turn solved on the design file's pitch curves.
#[divan::bench(sample_count = 50)]
fn loads_g1_m2_kinetostatics(b: divan::Bencher) {
    let source = RotorSource::read(&asset("loads/g1_m2_design.json"), false).expect("design");
    let text = std::fs::read_to_string(asset("loads/g1_rotor.toml")).expect("scene");
    let text = &text[..text.find("[material]").expect("a material table")];
    let scene: Scene = toml::from_str(text).expect("scene");
    let case = scene.validate("g1_rotor.toml").expect("valid");
    b.bench(|| analyse(&source.rotor(), &case, "g1_rotor.toml").expect("loads"));
}

/// The design of G1 for module 2, the unit `--module auto` repeats per module.
#[divan::bench(sample_count = 5)]
fn design_g1_for_module_2(b: divan::Bencher) {
    let t = Trajectory::from_path(&asset("trajectories/g1_ellipse.csv")).expect("G1");
    let opts = DesignOptions::default().with_module_mm(Some(2.0));
    b.bench(|| design(&t, &opts).expect("G1"));
}

/// `--module auto` with the bundled rotor: G1 (four modules designed, toothed, rated) and the
/// designer kidney (three).
#[divan::bench(args = ["g1_ellipse.csv", "designer_kidney.csv"], sample_count = 2)]
fn sizing(b: divan::Bencher, target: &str) {
    let t = Trajectory::from_path(&asset(&format!("trajectories/{target}"))).expect("target");
    let scene = Scene::from_path(&asset("loads/rotor.toml")).expect("scene");
    let case = scene.validate("rotor.toml").expect("valid");
    b.bench(|| {
        size_module(
            &t,
            &DesignOptions::default(),
            &case,
            &SizingOptions::default(),
            &ncgear::loads::rating_teeth,
            None,
            "rotor.toml",
        )
        .expect("sized")
    });
}
