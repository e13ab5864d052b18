//! Spec §12.1 option 2: an integer tooth count by rescaling the ratio amplitude of the designed
//! mechanism at a fixed centre distance.
use super::TrainError;
use crate::geometry::fourier::SunRatio;
use crate::geometry::mechanism::Mechanism;
use crate::math::periodic::bracketed_root;
use std::f64::consts::PI;

/// Result of [`rescale_ratio_amplitude`].
#[derive(Debug, Clone, PartialEq)]
pub struct AmplitudeFit {
    /// The mechanism with the rescaled ratio (same `a`, `l3`, γ, sun phase).
    pub mechanism: Mechanism,
    /// Tooth count.
    pub z: u32,
    /// Amplitude factor λ.
    pub lambda: f64,
    /// Sun perimeter `L(λ)` (= zπm to `accuracy_mm`), mm.
    pub perimeter_mm: f64,
}

pub(super) fn with_amplitude(mech: &Mechanism, lambda: f64) -> Mechanism {
    let k = |v: &[f64]| v.iter().map(|x| x * lambda).collect::<Vec<_>>();
    Mechanism {
        ratio: SunRatio::new_unchecked(
            k(mech.ratio.cos_coefficients()),
            k(mech.ratio.sin_coefficients()),
        ),
        ..mech.clone()
    }
}

/// Spec §12.1 option 2: the amplitude λ of `i_λ = 1 + λ(i21 − 1)` with `a` held fixed such that
/// the sun perimeter `L(λ) = zπm`, z the achievable integer nearest to `L(1)/(πm)`.
///
/// `L(λ)` is sampled on `λ ∈ [0, λmax]` (`λmax` keeps `i_λ ≥ 0.05` and ≤ 4); the bracket
/// nearest to λ = 1 is refined by bisection to `accuracy_mm` in L. `L(0) = πa` (circle).
/// Errors: no integer z is achievable in that range (module too large for the curve).
pub fn rescale_ratio_amplitude(
    mech: &Mechanism,
    module_mm: f64,
    samples: usize,
    accuracy_mm: f64,
) -> Result<AmplitudeFit, TrainError> {
    let perimeter = |lambda: f64| -> Result<f64, TrainError> {
        Ok(with_amplitude(mech, lambda)
            .sun_curve(samples)?
            .perimeter_mm(0.1 * accuracy_mm))
    };
    let grid = 64;
    let (i_min, _) = mech
        .ratio
        .sampled_extreme(64 * mech.ratio.order() + 256, false);
    let lambda_max = if i_min < 1.0 {
        (0.95 / (1.0 - i_min)).min(4.0)
    } else {
        4.0
    };
    let lambdas: Vec<f64> = (0..=grid)
        .map(|k| lambda_max * k as f64 / f64::from(grid))
        .collect();
    let ls: Vec<f64> = lambdas
        .iter()
        .map(|&l| perimeter(l))
        .collect::<Result<_, _>>()?;
    let pm = PI * module_mm;
    let z_raw = perimeter(1.0)? / pm;
    // Candidate z values, nearest first; take the first with a bracket, nearest to λ = 1.
    let mut candidates: Vec<f64> = (0..40)
        .flat_map(|k| {
            [
                z_raw.round() + f64::from(k),
                z_raw.round() - f64::from(k + 1),
            ]
        })
        .filter(|z| *z >= 3.0)
        .collect();
    candidates.sort_by(|x, y| (x - z_raw).abs().total_cmp(&(y - z_raw).abs()));
    for z in candidates {
        let target = z * pm;
        let best = lambdas
            .windows(2)
            .zip(ls.windows(2))
            .filter(|(_, l)| (l[0] - target) * (l[1] - target) <= 0.0)
            .min_by(|(x, _), (y, _)| {
                (0.5 * (x[0] + x[1]) - 1.0)
                    .abs()
                    .total_cmp(&(0.5 * (y[0] + y[1]) - 1.0).abs())
            });
        if let Some((lam, _)) = best {
            // A failing sample (cannot happen for i_λ ≥ 0.05) reads as NaN and is caught below.
            let lambda = bracketed_root(
                |l| perimeter(l).map_or(f64::NAN, |v| v - target),
                lam[0],
                lam[1],
                1e-14,
            );
            let mechanism = with_amplitude(mech, lambda);
            let perimeter_mm = mechanism
                .sun_curve(samples)?
                .perimeter_mm(0.1 * accuracy_mm);
            return Ok(AmplitudeFit {
                mechanism,
                z: z as u32,
                lambda,
                perimeter_mm,
            });
        }
    }
    Err(TrainError::InvalidOption {
        name: "module_mm",
        value: module_mm,
        expected: "a module for which some integer tooth count is reachable by rescaling the \
                   ratio amplitude (L(λ) ranges between the circle πa and the largest amplitude)",
    })
}
