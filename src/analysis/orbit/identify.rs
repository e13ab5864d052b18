//! Inverse problem (docs/math/companion.md §A.9): planet eccentricity phasors from a measured sun orbit.
//!
//! The model is complex-linear, `[P_x, P_y, P_c]ᵀ = G E` with a real 3×N matrix `G`
//! ([`KinematicMap`]). The sun orbit gives only the first two rows; for three equally spaced
//! planets their null space is `(1, 1, 1)` (`Σ e^{±iβ_i} = 0`): a **common eccentricity E₀ on all
//! planets moves no sun** and is visible only in the torsional channel (transmission error, row 3).
//! Without it the min-norm solution `E − mean(E)` is returned and the null space is reported.
//! With a transmission-error phasor the 3×N system is solved (full identification for N = 3).

use super::model::KinematicMap;
use super::{C64, Orbit, OrbitError};
use nalgebra::DMatrix;

/// Singular values below this fraction of the largest count as zero (rank decisions).
pub const RANK_TOL_REL: f64 = 1e-10;

/// Result of [`identify`].
#[derive(Debug, Clone, PartialEq)]
pub struct Identification {
    /// Minimum-norm planet phasors `E_i = e_pi e^{i(θ_p0+θ_pi)}`, µm.
    pub phasors_um: Vec<C64>,
    /// Orthonormal real basis of the unobservable directions (each a vector over planets);
    /// empty when fully identified. For 3 equally spaced planets without TE: `(1,1,1)/√3`.
    pub null_space: Vec<Vec<f64>>,
    /// Whether a transmission-error channel was used.
    pub used_transmission_error: bool,
    /// Human-readable statement of what is and is not observable.
    pub statement: String,
}

/// Identifies planet phasors from a carrier-frame orbit and, optionally, the sine phasor of the
/// common-mode (transmission-error) displacement at ω_p, `c(t) = Im(P_c e^{iω_p t})`, µm.
///
/// # Errors
/// [`OrbitError::Invalid`] if the orbit's ω_p differs from the map's (relative 1e-9) or data are
/// not finite.
pub fn identify(
    map: &KinematicMap,
    orbit: &Orbit,
    transmission_error_um: Option<C64>,
) -> Result<Identification, OrbitError> {
    let w = map.omega_p_rad_s();
    if (orbit.omega_p_rad_s - w).abs() > 1e-9 * w.abs() {
        return Err(super::invalid(
            "omega_p",
            format!(
                "orbit at ω_p = {} rad/s, model at {w} rad/s",
                orbit.omega_p_rad_s
            ),
        ));
    }
    let (px, py) = orbit.sin_phasors();
    let mut rhs = vec![px, py];
    if let Some(te) = transmission_error_um {
        rhs.push(te);
    }
    if rhs.iter().any(|z| !(z.re.is_finite() && z.im.is_finite())) {
        return Err(super::invalid("orbit", "non-finite phasor"));
    }
    let m = rhs.len();
    let g = map.matrix();
    let n = g.ncols();
    let gm = DMatrix::from_fn(m, n, |i, j| g[(i, j)]);
    // SVD of the (m×n) real map; complex right-hand side handled part by part.
    let svd = gm.transpose().svd(true, true); // n×m: U (n×m) spans the row space of gm
    let smax = svd.singular_values.max();
    let u = svd
        .u
        .as_ref()
        .map_or_else(|| DMatrix::zeros(n, 0), Clone::clone);
    let vt = svd
        .v_t
        .as_ref()
        .map_or_else(|| DMatrix::zeros(0, m), Clone::clone);
    let mut e = vec![C64::new(0.0, 0.0); n];
    let mut rank = 0;
    let mut row_space: Vec<nalgebra::DVector<f64>> = Vec::new();
    for k in 0..svd.singular_values.len() {
        let s = svd.singular_values[k];
        if s <= RANK_TOL_REL * smax {
            continue;
        }
        rank += 1;
        // gmᵀ = U S Vᵀ ⇒ gm = V S Uᵀ ⇒ pinv(gm) = U S⁻¹ Vᵀ.
        let coef: C64 = (0..m).map(|i| rhs[i] * vt[(k, i)]).sum::<C64>() / s;
        for (j, ej) in e.iter_mut().enumerate() {
            *ej += coef * u[(j, k)];
        }
        row_space.push(u.column(k).into_owned());
    }
    // Null space: complement of the row space (Gram–Schmidt on the unit vectors).
    let mut null_space: Vec<Vec<f64>> = Vec::new();
    let mut basis = row_space;
    for j in 0..n {
        let mut v = nalgebra::DVector::from_fn(n, |i, _| if i == j { 1.0 } else { 0.0 });
        for _ in 0..2 {
            for b in &basis {
                let d = b.dot(&v);
                v -= b * d;
            }
        }
        let nv = v.norm();
        if nv > 1e-8 && basis.len() < n {
            v /= nv;
            null_space.push(v.iter().copied().collect());
            basis.push(v);
        }
    }
    let used = transmission_error_um.is_some();
    let statement = if null_space.is_empty() {
        "fully identified: all planet eccentricity phasors determined".to_string()
    } else if !used {
        format!(
            "common-mode component unobservable: the sun orbit determines the planet eccentricities only up to \
             {} unobservable direction(s) (for equally spaced planets the common eccentricity E0, equal on all planets, \
             which moves no sun and appears only as transmission error); shown is the minimum-norm solution \
             (E - mean(E) for 3 planets); |E0| is not bounded by the orbit data; supply a transmission-error phasor \
             to identify it",
            null_space.len()
        )
    } else {
        format!(
            "rank {rank} < {n} planets even with transmission error: {} direction(s) unobservable",
            null_space.len()
        )
    };
    Ok(Identification {
        phasors_um: e,
        null_space,
        used_transmission_error: used,
        statement,
    })
}
