//! The analytic reference cases of docs/math/chain.md §11, as ready-made values (for tests, benchmarks,
//! examples and users who want a known-good mechanism to start from).
//!
//! ```
//! let m = ncgear::geometry::golden::g1_mechanism();
//! // ψ3 at t = 30° (docs/math/chain.md §11.1: 52.252904°).
//! assert!((m.psi3(30f64.to_radians()).to_degrees() - 52.252904).abs() < 1e-6);
//! ```

use crate::geometry::fourier::SunRatio;
use crate::geometry::mechanism::Mechanism;

/// G1 sun ratio: focus-pivoted ellipse pair, `i = (1−e²)/(1 − 2e cos θ + e²) = 1 + 2Σ eᵏ cos kθ`,
/// truncated where `eᵏ` falls below machine precision (`e` < 0.5).
#[must_use]
pub fn ellipse_ratio(e: f64) -> SunRatio {
    let k = ((f64::EPSILON.ln() / e.abs().max(1e-3).ln()).ceil() as usize).clamp(1, 200);
    SunRatio::new_unchecked(
        (1..=k).map(|j| 2.0 * e.powi(j as i32)).collect(),
        vec![0.0; k],
    )
}

/// The G1 mechanism (docs/math/chain.md §11.1): A = 22.5 mm, e = 0.15, a = 45 mm, l3 = 170 mm, β_init = −70°,
/// CCW carrier, the sun's far vertex facing D at φH = 0.
#[must_use]
pub fn g1_mechanism() -> Mechanism {
    Mechanism {
        a_mm: 45.0,
        l3_mm: 170.0,
        ratio: ellipse_ratio(0.15),
        sun_phase_rad: 0.0,
        needle_angle_rad: (-70f64).to_radians(),
        idler_offset_rad: 0.0,
    }
}

/// G4 generic asymmetric sun (docs/math/chain.md §11.4): `1 + 0.25 cos(t + 0.3) + 0.08 sin(2t + 1.1) + 0.05 cos(3t − 0.4)`.
#[must_use]
pub fn g4_ratio() -> SunRatio {
    SunRatio::new_unchecked(
        vec![
            0.25 * 0.3f64.cos(),
            0.08 * 1.1f64.sin(),
            0.05 * (-0.4f64).cos(),
        ],
        vec![
            -0.25 * 0.3f64.sin(),
            0.08 * 1.1f64.cos(),
            -0.05 * (-0.4f64).sin(),
        ],
    )
}
