//! Dynamics (docs/math/companion.md §B.11): ODE tolerance and breakpoints. DOPRI5 with and without breakpoints and
//! events, and fixed-step RK4 aligned / not aligned to the switches, on the SDOF physical model
//! (6000 rpm, rectangular TVMS + backlash + STE), 120 mesh periods from the quasi-static state.
//! Error = max |DTE − reference| / DTE peak-to-peak over the last 20 periods; reference = DOPRI5
//! with breakpoints and events at rtol 1e-12 (a converged run: its own change from rtol 1e-11 is
//! reported as the first row).
use super::{Row, timed};
use ncgear::analysis::dynamics::*;
use ncgear::config::Format;

const SCENE: &str = include_str!("../../assets/dynamics/sdof_6000.toml");

fn run(model: &model::Model, y0: &[f64], method: Method, spm: u32) -> Run {
    let o = RunOptions::window(method, 120, spm);
    simulate(model, y0, &o, &ncgear::progress::Progress::none()).expect("integration")
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

fn dp(rtol: f64, bp: bool) -> Method {
    Method::Dopri5 {
        rtol,
        atol: rtol * 1e-6,
        breakpoints: bp,
        events: bp,
    }
}

/// The dynamics rows.
pub fn rows() -> Vec<Row> {
    let scene = Scene::parse(SCENE, "sdof_6000.toml", Format::Toml).expect("scene");
    let (m, _) = scene.build("sdof_6000.toml").expect("model");
    let y0 = static_state(&m, 1e-9);
    let measure = "max |DTE error| / DTE p-p (last 20 of 120 mesh periods)";
    let mut rows = Vec::new();
    let reference = run(&m, &y0, dp(1e-12, true), 64);
    let (ms, check) = timed(1, || run(&m, &y0, dp(1e-11, true), 64));
    rows.push(Row::new(
        "reference check: DOPRI5 + breakpoints",
        "rtol 1e-11 vs 1e-12",
        measure,
        err(&check, &reference, 64),
        ms,
    ));
    for (label, bp) in [
        ("DOPRI5 rtol (no breakpoints/events)", false),
        ("DOPRI5 rtol (breakpoints + events)", true),
    ] {
        for rtol in [1e-3, 1e-4, 1e-6, 1e-8, 1e-9] {
            let (ms, r) = timed(3, || run(&m, &y0, dp(rtol, bp), 64));
            rows.push(Row::new(
                label,
                format!("rtol {rtol:e} ({} RHS)", r.stats.rhs_evals),
                measure,
                err(&r, &reference, 64),
                ms,
            ));
        }
    }
    for (label, aligned) in [
        ("RK4 steps per mesh (not aligned)", false),
        ("RK4 steps per mesh (aligned to switches)", true),
    ] {
        for steps in [20u32, 40, 80, 160, 320] {
            let reference = run(&m, &y0, dp(1e-12, true), steps);
            let (ms, r) = timed(3, || {
                run(
                    &m,
                    &y0,
                    Method::Rk4 {
                        steps_per_mesh: steps,
                        aligned,
                    },
                    steps,
                )
            });
            rows.push(Row::new(
                label,
                steps,
                measure,
                err(&r, &reference, steps as usize),
                ms,
            ));
        }
    }
    rows
}
