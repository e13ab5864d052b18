//! Accuracy costs time (spec B.11): error against right-hand-side evaluations and run time for
//! DOPRI5 with and without breakpoints and for fixed-step RK4 (aligned / not aligned to the
//! switches), on the SDOF physical model (6000 rpm, rectangular TVMS + backlash + STE), 120 mesh
//! periods from the quasi-static state; error = max |DTE − reference| / DTE peak-to-peak over
//! the last 20 periods, reference = DOPRI5 with breakpoints and events at rtol 1e-12.
//!
//! Run: `cargo run --release --example dynamics_accuracy`
use ncgear::analysis::dynamics::*;
use std::time::Instant;

const SCENE: &str = include_str!("../assets/dynamics/sdof_6000.toml");

fn run(model: &model::Model, y0: &[f64], method: Method, spm: u32) -> (Run, f64) {
    let o = RunOptions::window(method, 120, spm);
    let t = Instant::now();
    let r = simulate(model, y0, &o, &|_| {}).expect("integration");
    (r, t.elapsed().as_secs_f64() * 1e3)
}

fn err(r: &Run, reference: &Run, spm: usize) -> f64 {
    let n = r.dte_m.len();
    let tail = n - 20 * spm..n;
    let (lo, hi) = reference.dte_m[tail.clone()]
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
    tail.map(|i| (r.dte_m[i] - reference.dte_m[i]).abs())
        .fold(0.0, f64::max)
        / (hi - lo)
}

fn main() {
    let scene = Scene::from_str(SCENE, false, "sdof_6000.toml").expect("scene");
    let (m, _) = scene.build("sdof_6000.toml").expect("model");
    let y0 = static_state(&m, 1e-9);
    let dp = |rtol: f64, bp: bool| Method::Dopri5 {
        rtol,
        atol: rtol * 1e-6,
        breakpoints: bp,
        events: bp,
    };
    println!("| method | setting | RHS evals | time [ms] | error |");
    println!("|---|---|---|---|---|");
    let (reference, _) = run(&m, &y0, dp(1e-12, true), 64);
    for (label, bp) in [
        ("DOPRI5 (no breakpoints, no events)", false),
        ("DOPRI5 with breakpoints + events", true),
    ] {
        for rtol in [1e-3, 1e-6, 1e-9] {
            let (r, ms) = run(&m, &y0, dp(rtol, bp), 64);
            println!(
                "| {label} | rtol {rtol:e} | {} | {ms:.1} | {:.1e} |",
                r.stats.rhs_evals,
                err(&r, &reference, 64)
            );
        }
    }
    for (label, aligned) in [
        ("RK4 fixed, not aligned", false),
        ("RK4 fixed, aligned to switches", true),
    ] {
        for steps in [20u32, 40, 80, 160, 320] {
            let (reference, _) = run(&m, &y0, dp(1e-12, true), steps);
            let (r, ms) = run(
                &m,
                &y0,
                Method::Rk4 {
                    steps_per_mesh: steps,
                    aligned,
                },
                steps,
            );
            println!(
                "| {label} | {steps} steps/mesh | {} | {ms:.1} | {:.1e} |",
                r.stats.rhs_evals,
                err(&r, &reference, steps as usize)
            );
        }
    }
}
