//! Dynamics benchmarks (divan): the 16-DOF full scene over 50 mesh periods from rest with DOPRI5
//! (rtol 1e-6, atol 1e-12) with and without breakpoints — the same run as
//! `benches/python/full16_scipy.py` — and the SDOF 6000 rpm scene (120 mesh periods).
//!
//! Run: `cargo bench --bench dynamics`
use ncgear::analysis::dynamics::*;
use ncgear::config::Format;

fn main() {
    divan::main();
}

fn full16() -> model::Model {
    let s = Scene::parse(
        include_str!("../assets/dynamics/full16.toml"),
        "full16.toml",
        Format::Toml,
    )
    .expect("scene");
    s.build("full16.toml").expect("model").0
}

#[divan::bench(args = [false, true])]
fn full16_dopri5_50_mesh_periods(bencher: divan::Bencher, breakpoints: bool) {
    let m = full16();
    let t_end = 50.0 * m.mesh.t0;
    let bps = if breakpoints {
        m.breakpoints(0.0, t_end)
    } else {
        Vec::new()
    };
    let solver = ode::Dopri5::new(1e-6, 1e-12).expect("tolerances");
    bencher.bench_local(|| {
        let mut y = vec![0.0; 2 * m.n()];
        solver
            .integrate(
                &ode::OdeProblem::new(&m, 0.0, t_end).with_breakpoints(&bps),
                &mut y,
                &mut |_| {},
            )
            .expect("integration");
        divan::black_box(y)
    });
}

fn sdof() -> (model::Model, Vec<f64>) {
    let s = Scene::parse(
        include_str!("../assets/dynamics/sdof_6000.toml"),
        "sdof",
        Format::Toml,
    )
    .expect("scene");
    let (m, _) = s.build("sdof").expect("model");
    let y0 = static_state(&m, 1e-9);
    (m, y0)
}

fn bench_run(bencher: divan::Bencher, method: Method, spm: u32) {
    let (m, y0) = sdof();
    let o = RunOptions::window(method, 120, spm);
    bencher
        .bench_local(|| simulate(&m, &y0, &o, &ncgear::progress::Progress::none()).expect("run"));
}

#[divan::bench(args = [20, 80])]
fn sdof_rk4_aligned_120_mesh_periods(bencher: divan::Bencher, steps: u32) {
    bench_run(
        bencher,
        Method::Rk4 {
            steps_per_mesh: steps,
            aligned: true,
        },
        steps,
    );
}

#[divan::bench(args = [1e-6, 1e-9])]
fn sdof_dopri5_breakpoints_120_mesh_periods(bencher: divan::Bencher, rtol: f64) {
    bench_run(
        bencher,
        Method::Dopri5 {
            rtol,
            atol: rtol * 1e-6,
            breakpoints: true,
            events: true,
        },
        64,
    );
}
