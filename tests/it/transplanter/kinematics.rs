//! The exact model against closed forms (circular train, radial pin errors, clocking, mirror) and
//! the linear model against the exact one.
use super::*;
use ncgear::progress::Progress;

#[test]
fn zero_errors_reproduce_the_rebuilt_train_and_give_zero_deviation() {
    for dir in [1, -1] {
        let asm = g1(dir);
        let m = ExactModel::new(&asm, 20f64.to_radians(), 1).unwrap();
        let rb = asm.rebuild();
        let mut worst: f64 = 0.0;
        for p in m.grid(360) {
            let s = m.state(p, &ZERO).unwrap();
            worst = worst.max(dist(s.tip_mm, rb.pose(p).tip_mm));
        }
        // The flank-line solve with zero errors is the rolling of the design tables.
        assert!(worst < 1e-7, "direction {dir}: {worst} mm");
    }
    // Whole pipeline with an empty inventory: every deviation is zero.
    let inv = Inventory::zero(20f64.to_radians(), 1, 360);
    let opts = TransplanterOptions::default()
        .with_mc(
            McOptions::default()
                .with_samples(1000)
                .with_seed(3)
                .with_bins(10),
        )
        .with_validation_samples(10)
        .with_feature_samples(0);
    let r = analyse(&g1(1), &inv, &opts, &Progress::none()).unwrap();
    assert!(
        r.max_deviation_um.max < 1e-9 * 1e3,
        "{}",
        r.max_deviation_um.max
    );
    assert!(r.nominal_errors_exact_um < 1e-6 && r.envelope_max_um < 1e-6);
    assert!(r.assembly.is_none());
}

/// Pure radial pin error δ of A on the circular train: A moves by δ along OA, the centre distance
/// of the intermediate–planet mesh grows by δ and the flank condition gives the planet rotation
/// `σ₂Δ = asin((1 + δ/r)·sin α) − α` (σ₂ = −load_side), exactly; the tip is
/// `B + δ·e(φH) + l3·(e(β + Δ) − e(β))`.
#[test]
fn radial_pin_error_of_a_matches_the_closed_form() {
    let asm = circular();
    let r = asm.a_mm / 2.0;
    let l3 = asm.l3_mm;
    for (side, alpha_deg, delta) in [(1i8, 20.0f64, 0.05), (-1, 20.0, 0.05), (1, 25.0, -0.03)] {
        let alpha = alpha_deg.to_radians();
        let m = ExactModel::new(&asm, alpha, side).unwrap();
        let mut x = ZERO;
        x[PIN_A[0]] = delta;
        let s2 = -f64::from(side);
        let big = s2 * (((1.0 + delta / r) * alpha.sin()).asin() - alpha);
        let mut worst: f64 = 0.0;
        let mut moved: f64 = 0.0;
        for p in m.grid(360) {
            let nom = m.state(p, &ZERO).unwrap();
            let per = m.state(p, &x).unwrap();
            let b = nom.needle_angle_rad;
            let expect = Point::new(
                nom.tip_mm.x + delta * p.cos() + l3 * ((b + big).cos() - b.cos()),
                nom.tip_mm.y + delta * p.sin() + l3 * ((b + big).sin() - b.sin()),
            );
            worst = worst.max(dist(per.tip_mm, expect));
            moved = moved.max(dist(per.tip_mm, nom.tip_mm));
            // The planet centre moves by δ along OA.
            let a0 = nom.planet_center_mm;
            let a1 = per.planet_center_mm;
            assert!((a1.x - a0.x - delta * p.cos()).abs() < 1e-12);
            assert!((a1.y - a0.y - delta * p.sin()).abs() < 1e-12);
        }
        println!(
            "radial pin closed form, side {side}, α {alpha_deg}°, δ {delta} mm: {worst:.2e} mm"
        );
        assert!(worst < 1e-9, "side {side}: {worst} mm");
        // Not a rigid translation: the rotation adds l3·Δ ≈ l3·δ·tan α / r.
        let rigid_plus_rotation = (delta.abs() + l3 * big.abs()) * 1.0001;
        assert!(
            moved > delta.abs() * 1.5 && moved < rigid_plus_rotation,
            "{moved}"
        );
    }
}

/// Circular gears: the planet's angle error is the line-of-action sum of the eccentricities and
/// backlashes over the base radius r_b = r·cos α (the non-circular ρ_b), and — every term having
/// order 1 in φH — a single phasor (docs/math/companion.md §C.2 eq. C-1) plus the accumulated lost motion.
#[test]
fn circular_train_reduces_to_the_phasor_model() {
    let asm = circular();
    let r = asm.a_mm / 2.0;
    let alpha = 20f64.to_radians();
    let rb = r * alpha.cos();
    let (e1, g1_, e2, g2, e3, g3): (f64, f64, f64, f64, f64, f64) =
        (0.010, 0.4, 0.008, 2.0, 0.006, -1.1);
    let (j1, j2) = (0.004, 0.003);
    let mut x = ZERO;
    x[ecc_index(0)] = e1 * g1_.cos();
    x[ecc_index(0) + 1] = e1 * g1_.sin();
    x[ecc_index(1)] = e2 * g2.cos();
    x[ecc_index(1) + 1] = e2 * g2.sin();
    x[ecc_index(2)] = e3 * g3.cos();
    x[ecc_index(2) + 1] = e3 * g3.sin();
    x[BACKLASH[0]] = j1;
    x[BACKLASH[1]] = j2;
    for side in [1i8, -1] {
        let s = f64::from(side);
        let m = ExactModel::new(&asm, alpha, side).unwrap();
        let grid = m.grid(720);
        let mut exact = Vec::new();
        let mut worst: f64 = 0.0;
        let mut th0 = (0.0, 0.0);
        for (k, &p) in grid.iter().enumerate() {
            let nom = m.state(p, &ZERO).unwrap();
            let per = m.state(p, &x).unwrap();
            // Angles are reported modulo 2π.
            let d3 = (per.planet_angle_rad - nom.planet_angle_rad + PI).rem_euclid(2.0 * PI) - PI;
            exact.push(d3);
            let (t2, t3) = (nom.intermediate_angle_rad, nom.planet_angle_rad);
            if k == 0 {
                th0 = (t2, t3);
            }
            let n = |sig: f64| {
                let a = e(p + FRAC_PI_2);
                let b = e(p);
                Point::new(
                    sig * alpha.cos() * a.x + alpha.sin() * b.x,
                    sig * alpha.cos() * a.y + alpha.sin() * b.y,
                )
            };
            let (n1, n2) = (n(s), n(-s));
            let v1 = e(g1_);
            let v2 = e(t2 + g2);
            let v3 = e(t3 + g3);
            let d2 = ((e2 * dot(v2, n1) - e1 * dot(v1, n1)) - j1 / 2.0) / (s * rb);
            let model = -d2 + ((e3 * dot(v3, n2) - e2 * dot(v2, n2)) - j2 / 2.0) / (-s * rb);
            worst = worst.max((d3 - model).abs());
        }
        let amp = exact.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        println!("circular LOA sum, side {side}: residual {worst:.2e} rad of {amp:.2e} rad");
        assert!(
            worst < 1e-3 * amp,
            "side {side}: {worst} vs amplitude {amp}"
        );
        if side == 1 {
            // Phasor form: Δθ3 = (j1 + j2)/(2 r_b) + B·sin(φH + ξ)/r_b with (B, ξ) = Σ A_k e^{iφ_k}.
            let (t20, t30) = th0;
            let terms = [
                (e1, PI - g1_ - alpha),
                (-e2, t20 + g2 + alpha),
                (-e3, alpha - t30 - g3),
                (e2, PI + t20 + g2 - alpha),
            ];
            let (b, xi) = phasor_sum(&terms);
            let lost = (j1 + j2) / (2.0 * rb);
            let mut w: f64 = 0.0;
            for (&p, d) in grid.iter().zip(&exact) {
                w = w.max((d - lost - b * (p + xi).sin() / rb).abs());
            }
            println!(
                "phasor docs/math/companion.md §C.2 eq. C-1: residual {w:.2e} rad of B/r_b = {:.2e} rad",
                b / rb
            );
            assert!(w < 1e-3 * b / rb, "phasor: {w} vs {}", b / rb);
            let (lo, hi) = exact
                .iter()
                .fold((f64::MAX, f64::MIN), |(l, h), v| (l.min(*v), h.max(*v)));
            assert!(((hi - lo) / 2.0 - b / rb).abs() < 1e-3 * b / rb);
            assert!(((hi + lo) / 2.0 - lost).abs() < 1e-3 * b / rb);
            // The linear model's planet transmission error: max |Δθ3| = lost motion + B/r_b.
            let lin = LinearModel::build(&m, 720, FdSteps::default()).unwrap();
            let te = lin.max_planet_angle_error_rad(&x);
            assert!((te - (lost + b / rb)).abs() < 1e-3 * b / rb, "{te}");
        }
    }
}

#[test]
fn idler_clocking_is_invisible_and_planet_clocking_is_an_arm_error() {
    let asm = g1(1);
    let m = ExactModel::new(&asm, 20f64.to_radians(), 1).unwrap();
    let k = 0.1f64.to_radians();
    let mut idler = ZERO;
    idler[clock_index(1)] = k;
    let mut planet = ZERO;
    planet[clock_index(2)] = k;
    let mut arm = ZERO;
    arm[ARM] = -k;
    let mut sun = ZERO;
    sun[clock_index(0)] = k;
    let (mut w_idler, mut w_pa, mut sun_dev): (f64, f64, f64) = (0.0, 0.0, 0.0);
    for p in m.grid(180) {
        let n = m.state(p, &ZERO).unwrap().tip_mm;
        w_idler = w_idler.max(dist(m.state(p, &idler).unwrap().tip_mm, n));
        w_pa = w_pa.max(dist(
            m.state(p, &planet).unwrap().tip_mm,
            m.state(p, &arm).unwrap().tip_mm,
        ));
        sun_dev = sun_dev.max(dist(m.state(p, &sun).unwrap().tip_mm, n));
    }
    assert!(w_idler < 1e-9, "{w_idler}");
    assert!(w_pa < 1e-9, "{w_pa}");
    // The sun's clocking shifts the ratio phase: a real error (≈ l3·κ·|i31 − 1| scale).
    assert!(sun_dev > 0.05, "{sun_dev}");
}

#[test]
fn clockwise_design_mirrors_the_deviations() {
    let (ccw, cw) = (g1(1), g1(-1));
    let (mc, mw) = (
        ExactModel::new(&ccw, 20f64.to_radians(), 1).unwrap(),
        ExactModel::new(&cw, 20f64.to_radians(), 1).unwrap(),
    );
    let inv = inventory();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let x = inv.draw_three_sigma(&mut rng);
    let grid = mc.grid(90);
    let dc = mc.deviations(&grid, &x).unwrap();
    let mirrored: Vec<f64> = grid.iter().map(|p| -p).collect();
    let dw = mw.deviations(&mirrored, &x).unwrap();
    for (a, b) in dc.iter().zip(&dw) {
        assert!((a.x - b.x).abs() < 1e-9 && (a.y + b.y).abs() < 1e-9);
    }
}

#[test]
fn linear_model_agrees_with_the_exact_model_at_three_sigma() {
    let asm = g1(1);
    let inv = inventory();
    let m = ExactModel::new(&asm, inv.pressure_angle_rad, inv.load_side).unwrap();
    let lin = LinearModel::build(&m, 360, FdSteps::default()).unwrap();
    let mut max_rel: f64 = 0.0;
    for i in 0..100 {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        rng.set_stream(i);
        let x = inv.draw_three_sigma(&mut rng);
        let ex = m.deviations(&lin.phis_rad, &x).unwrap();
        let li = lin.deviations(&x);
        let peak = ex.iter().fold(0.0f64, |a, d| a.max(d.hypot()));
        let err = ex
            .iter()
            .zip(&li)
            .fold(0.0f64, |a, (d, l)| a.max(dist(*d, *l)));
        assert!(peak > 0.01, "3σ errors move the tip by tens of µm: {peak}");
        max_rel = max_rel.max(err / peak);
    }
    println!("linear vs exact at 3σ: max relative error {max_rel:.3e}");
    assert!(max_rel < 0.05, "{max_rel}");
}

/// Non-circular G1: a radial pin error δ of A changes the intermediate–planet centre distance;
/// to first order (docs/math/companion.md §C.6 item 2) the planet turns by `Δθ3 = −δ·(u·N)/ρ_b`, with u the line of
/// centres, N the line of action through the contact (pitch tangent t and normal n of the
/// intermediate, `N = σ cos α t + sin α n`, σ = −load_side) and `ρ_b = (R⁺(W − A))·N` the moment
/// arm about A; the tip moves by `δ·u + l3·Δθ3·e(β + π/2)`. Computed here from the pitch tables.
#[test]
fn radial_pin_error_on_g1_follows_the_first_order_line_of_action_formula() {
    let asm = g1(1);
    let alpha = 20f64.to_radians();
    let m = ExactModel::new(&asm, alpha, 1).unwrap();
    let rb = asm.rebuild();
    let [_, mid, _] = rb.ccw_curves();
    let (a, l3) = (asm.a_mm, asm.l3_mm);
    let delta = 1e-3;
    let mut x = ZERO;
    x[PIN_A[0]] = delta;
    let (mut worst, mut peak): (f64, f64) = (0.0, 0.0);
    for p in m.grid(240) {
        let th2 = rb.ccw_intermediate_angle(p);
        let c2 = p - th2; // intermediate body angle facing A
        let g = mid.geometry(c2);
        let u = e(p);
        let t = {
            let (r, dr) = (g.r_mm, g.dr_mm);
            let v = Point::new(dr * u.x - r * u.y, dr * u.y + r * u.x);
            let l = v.hypot();
            Point::new(v.x / l, v.y / l)
        };
        let mut n = Point::new(-t.y, t.x);
        if dot(n, u) < 0.0 {
            n = Point::new(-n.x, -n.y);
        }
        let sigma = -1.0;
        let nl = Point::new(
            sigma * alpha.cos() * t.x + alpha.sin() * n.x,
            sigma * alpha.cos() * t.y + alpha.sin() * n.y,
        );
        // Contact W = D + ρ2 u; lever of the planet about A: W − A = (ρ2 − a) u.
        let w_a = Point::new((g.r_mm - a) * u.x, (g.r_mm - a) * u.y);
        let arm = dot(Point::new(-w_a.y, w_a.x), nl);
        let dth3 = -delta * dot(u, nl) / arm;
        let nom = m.state(p, &ZERO).unwrap();
        let per = m.state(p, &x).unwrap();
        let b = nom.needle_angle_rad;
        let pred = Point::new(
            delta * u.x - l3 * dth3 * b.sin(),
            delta * u.y + l3 * dth3 * b.cos(),
        );
        let got = per.tip_mm - nom.tip_mm;
        worst = worst.max(dist(got, pred));
        peak = peak.max(got.hypot());
    }
    println!(
        "G1 radial pin δ = 1 µm: first-order formula residual {worst:.2e} mm of {peak:.2e} mm"
    );
    assert!(
        peak > 2.0 * delta,
        "the planet rotation amplifies the pin error: {peak}"
    );
    assert!(worst < 1e-3 * peak, "{worst} vs {peak}");
}
