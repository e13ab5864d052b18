//! The 16-DOF full scene (`assets/dynamics/full16.toml`) from rest (y = 0) over 50 mesh periods
//! at rtol 1e-6 / atol 1e-12, with and without breakpoints; prints RHS evaluations, wall time and
//! the final DTE so that `benches/python/full16_scipy.py` (the same model in scipy's solve_ivp)
//! can be checked against it.
//!
//! Run: `cargo run --release --example dynamics_speed`
use ncgear::analysis::dynamics::*;
use ncgear::config::Format;
use std::time::Instant;

fn main() {
    let scene = Scene::parse(
        include_str!("../assets/dynamics/full16.toml"),
        "full16.toml",
        Format::Toml,
    )
    .expect("scene");
    let (m, _) = scene.build("full16.toml").expect("model");
    let t_end = 50.0 * m.mesh.t0;
    for bp in [false, true] {
        let mut best = f64::MAX;
        let mut out = (0, 0.0);
        for _ in 0..5 {
            let mut y = vec![0.0; 2 * m.n()];
            let solver = ode::Dopri5::new(1e-6, 1e-12).expect("tolerances");
            let bps = if bp {
                m.breakpoints(0.0, t_end)
            } else {
                Vec::new()
            };
            let t = Instant::now();
            let st = solver
                .integrate(
                    &ode::OdeProblem::new(&m, 0.0, t_end).with_breakpoints(&bps),
                    &mut y,
                    &mut |_| {},
                )
                .expect("integration");
            best = best.min(t.elapsed().as_secs_f64());
            out = (st.rhs_evals, m.mesh.dte(t_end, &y[..m.n()]));
        }
        println!(
            "rust DOPRI5 breakpoints={bp}: {} RHS evals, best of 5: {:.2} ms, final DTE {:.6} µm",
            out.0,
            best * 1e3,
            out.1 * 1e6
        );
    }
}
