//! Design chain: every knob of docs/math/chain.md §13 that trades accuracy for time, measured against references
//! (closed forms of the G1 mechanism, the best achievable deviation of the designer-style target).
use super::{Row, timed};
use ncgear::design::hypothesis::refine::RefineOptions;
use ncgear::design::inverse::{InverseOptions, invert};
use ncgear::design::trajectory::{Origin, Trajectory};
use ncgear::design::{DesignOptions, RefineMode, design};
use ncgear::geometry::mechanism::Mechanism;
use ncgear::math::Point;
use std::f64::consts::TAU;

fn g1() -> Mechanism {
    ncgear::geometry::golden::g1_mechanism()
}

fn traj(points: Vec<Point>) -> Trajectory {
    let o: Vec<Origin> = (0..points.len()).map(Origin::Index).collect();
    Trajectory::new(points, &o, "generated").expect("valid")
}

fn g1_traj(m: usize) -> Trajectory {
    let g = g1();
    traj((0..m).map(|k| g.tip(TAU * k as f64 / m as f64)).collect())
}

fn designer() -> Trajectory {
    let g = g1();
    traj(
        (0..360)
            .map(|k| {
                let t = (k as f64).to_radians();
                let beta = (-70f64).to_radians() + t - (g.psi3(t) + 0.03 * (3.0 * t + 0.5).sin());
                Point::new(
                    90.0 * t.cos() + 170.0 * beta.cos(),
                    90.0 * t.sin() + 170.0 * beta.sin(),
                )
            })
            .collect(),
    )
}

/// The design-chain rows.
pub fn rows() -> Vec<Row> {
    let g = g1();
    let mut rows = Vec::new();
    // 1. Trajectory points M: ψ3 error of step 1 against the closed form, and l1 error.
    for m in [72, 180, 360, 720, 1440] {
        let t = g1_traj(m);
        let (ms, inv) = timed(5, || {
            invert(&t, Point::new(0.0, 0.0), &InverseOptions::default()).expect("G1")
        });
        let t0 = inv.phi_h0_rad;
        let err = (0..720)
            .map(|j| {
                let x = TAU * j as f64 / 720.0;
                (inv.law.psi3(x) - (g.psi3(x + t0) - g.psi3(t0))).abs()
            })
            .fold(0.0, f64::max);
        rows.push(Row::new(
            "trajectory points M (step 1)",
            m.to_string(),
            "max |ψ3 error| × l3, mm",
            err * 170.0,
            ms,
        ));
    }
    // 2. FFT grid N: the whole chain's round trip at K = 16 (patent route).
    let t360 = g1_traj(360);
    for n in [128, 256, 512, 1024, 2048, 4096] {
        let opts = DesignOptions::default()
            .with_order(Some(16))
            .with_refine(RefineMode::Off)
            .with_inverse({
                let mut o = InverseOptions::default();
                o.grid = n;
                o
            });
        let (ms, d) = timed(3, || design(&t360, &opts).expect("G1"));
        rows.push(Row::new(
            "ψ3 grid N (full chain, K = 16)",
            n.to_string(),
            "round-trip max deviation, mm",
            d.report.roundtrip.max_deviation_mm,
            ms,
        ));
    }
    // 3. Fourier order K, patent route, G1 360 points.
    for k in [4, 6, 8, 12, 16, 24, 32, 40] {
        let opts = DesignOptions::default()
            .with_order(Some(k))
            .with_refine(RefineMode::Off);
        let (ms, d) = timed(3, || design(&t360, &opts).expect("G1"));
        rows.push(Row::new(
            "Fourier order K (patent route, G1)",
            k.to_string(),
            "round-trip max deviation, mm",
            d.report.roundtrip.max_deviation_mm,
            ms,
        ));
    }
    // 4. Refinement on G1 (compatible) at low order.
    for k in [4, 8] {
        let opts = DesignOptions::default()
            .with_order(Some(k))
            .with_refine(RefineMode::On);
        let (ms, d) = timed(3, || design(&t360, &opts).expect("G1"));
        rows.push(Row::new(
            "LM refinement (G1, compatible)",
            format!("K = {k}"),
            "round-trip max deviation, mm",
            d.report.roundtrip.max_deviation_mm,
            ms,
        ));
    }
    // 5. Designer-style target: patent route vs refinement order and iteration budget.
    let dz = designer();
    {
        let opts = DesignOptions::default()
            .with_order(Some(12))
            .with_refine(RefineMode::Off);
        let (ms, d) = timed(3, || design(&dz, &opts).expect("designer"));
        rows.push(Row::new(
            "designer target, patent route",
            "K = 12",
            "excess over best 3.82 mm, mm",
            d.report.roundtrip.max_deviation_mm - 3.82,
            ms,
        ));
    }
    for (k, patience) in [(4, 60), (8, 60), (12, 5), (12, 15), (12, 60), (16, 60)] {
        let opts = DesignOptions::default()
            .with_order(Some(k))
            .with_refine(RefineMode::On)
            .with_refine_options({
                let mut o = RefineOptions::default();
                o.patience = patience;
                o
            });
        let (ms, d) = timed(3, || design(&dz, &opts).expect("designer"));
        rows.push(Row::new(
            "designer target, LM refinement",
            format!("K = {k}, patience {patience}"),
            "excess over best 3.82 mm, mm",
            d.report.roundtrip.max_deviation_mm - 3.82,
            ms,
        ));
    }
    rows
}
