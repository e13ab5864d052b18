//! Hard cases of the teeth (issue 8, item 3): random pitch curves from convex to concave, modules
//! from fine to undercut, random pair laws. Rack generation gives a finite simple outline whose
//! vertices stay within an addendum/dedendum band of the pitch curve, or a typed error
//! (`Concave`, `Undercut`, …) — never a panic or a NaN vertex.
use ncgear::geometry::pitch::PitchCurve;
use ncgear::pair::{Expr, Law, PairOptions, design_pair};
use ncgear::teeth::{
    OutlineOptions, RackParams, TeethError, ToothPolicy, generate_outline, scale_curve, tooth_count,
};
use proptest::prelude::*;
use proptest::test_runner::RngSeed;
use std::f64::consts::TAU;

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 32,
        failure_persistence: None,
        rng_seed: RngSeed::Fixed(0x8_0004),
        ..ProptestConfig::default()
    })]

    /// r(θ) = R(1 + ε cos(kθ + φ) + ε₂ cos(k₂θ)): convex for small k²ε, concave beyond
    /// (`k²ε > 1` makes the curvature change sign). Concave curves must be refused as `Concave`;
    /// convex ones give an outline inside the band [r − 1.25m − ε, r + m + ε] of the pitch radius
    /// at the same polar angle, or a typed undercut/tip error.
    #[test]
    fn random_pitch_curves_give_outlines_or_typed_errors(
        radius in 15.0f64..40.0,
        eps in 0.0f64..0.35,
        k in 1u32..5,
        phase in 0.0f64..TAU,
        eps2 in 0.0f64..0.05,
        k2 in 2u32..7,
        module in 0.5f64..3.0,
    ) {
        let f = |t: f64| {
            radius * (1.0 + eps * (f64::from(k) * t + phase).cos() + eps2 * (f64::from(k2) * t).cos())
        };
        let c = PitchCurve::from_fn(1024, f).unwrap();
        let concave = c.curvature_extremes(4096).min_convexity_mm2 < 0.0;
        let Ok(tc) = tooth_count(&c, module, ToothPolicy::Nearest, 1e-9) else {
            // Fewer than 3 teeth at this module: a typed refusal is the expected outcome.
            return Ok(());
        };
        let c = scale_curve(&c, tc.scale).unwrap();
        let opts = OutlineOptions::new(0.0, 1e-3 * module);
        match generate_outline(&c, &RackParams::default(), tc.z, module, &opts) {
            Ok(o) => {
                prop_assert!(!concave, "a concave curve was cut (k = {k}, ε = {eps})");
                let m = module;
                for p in &o.points_mm {
                    prop_assert!(p[0].is_finite() && p[1].is_finite());
                    let th = p[1].atan2(p[0]);
                    let r = p[0].hypot(p[1]);
                    let rp = c.radius_mm(th);
                    // Radial band: addendum m, dedendum 1.25 m, plus the slant of the normal.
                    let slack = 0.5 * m + 0.05 * rp;
                    prop_assert!(
                        r <= rp + m + slack && r >= rp - 1.25 * m - slack,
                        "vertex at r = {r} vs pitch {rp} (m = {m})"
                    );
                }
            }
            Err(TeethError::Concave { min_rho_mm, .. }) => {
                prop_assert!(min_rho_mm < 0.0 && min_rho_mm.is_finite());
            }
            Err(TeethError::Undercut { max_module_mm, min_teeth, .. }) => {
                prop_assert!(max_module_mm.is_finite() && max_module_mm < module);
                prop_assert!(min_teeth > tc.z);
            }
            Err(TeethError::NoRackTipFlat { .. } | TeethError::Trim { .. }) => {}
            Err(e) => prop_assert!(false, "unexpected error: {e}"),
        }
    }
}

/// Pair laws from mild to extreme: each gives the outcome its geometry dictates — a meshed pair
/// with finite ratios, `Concave` where the driven or driver centrode turns concave, `Undercut`
/// for a circle with too few teeth (classical limit z ≥ 2h*/sin²α = 17.1 → 18 at α = 20°), or a
/// `Law` error where the ratio would reverse.
#[test]
fn extreme_pair_laws_give_a_pair_or_the_typed_error_their_geometry_dictates() {
    use ncgear::pair::PairError;
    enum Want {
        Pair,
        Concave,
        Undercut(u32),
        Law,
    }
    for (law, teeth, want) in [
        ("phi - 0.08*sin(2*phi)", 24, Want::Pair),
        ("phi - 0.45*sin(phi)", 30, Want::Pair),
        ("phi - 0.3*sin(2*phi)", 30, Want::Concave),
        ("phi - 0.95*sin(phi)", 30, Want::Concave),
        ("phi + 0.2*sin(phi)^3", 24, Want::Concave),
        ("phi - 0.1*sin(8*phi)", 40, Want::Concave),
        ("phi + 0.0*phi", 12, Want::Undercut(18)),
        ("phi - 1.2*sin(phi)", 30, Want::Law),
    ] {
        let e = Expr::parse(law).unwrap();
        // A short mesh verification (12 driver positions): the full one is in tests/it/teeth.rs.
        let mut opts = PairOptions::new(Some(teeth), 1.0);
        opts.toothing.verify_steps = 12;
        let got = design_pair(&Law::Motion(e), &opts);
        match (want, got) {
            (Want::Pair, Ok(d)) => {
                let [lo, hi] = d.ratio_range;
                assert!(
                    lo.is_finite() && hi.is_finite() && lo > 0.0 && hi >= lo,
                    "{law}"
                );
                assert!(
                    (d.perimeter_mm - f64::from(teeth) * std::f64::consts::PI).abs() < 1e-6,
                    "{law}"
                );
                let mesh = d.mesh.expect("verified");
                assert_eq!(mesh.interference_steps, 0, "{law}: {mesh:?}");
            }
            (Want::Concave, Err(PairError::Teeth(TeethError::Concave { min_rho_mm, .. }))) => {
                assert!(min_rho_mm < 0.0, "{law}");
            }
            (Want::Undercut(z), Err(PairError::Teeth(TeethError::Undercut { min_teeth, .. }))) => {
                assert_eq!(min_teeth, z, "{law}")
            }
            (Want::Law, Err(PairError::Law(msg))) => assert!(msg.contains("> 0"), "{law}: {msg}"),
            (_, Ok(_)) => panic!("{law}: designed, expected a refusal"),
            (_, Err(e)) => panic!("{law}: unexpected outcome {e}"),
        }
    }
}
