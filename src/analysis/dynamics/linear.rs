//! The linear analyses (docs/math/companion.md §B.10 fast path): natural frequencies of the mean-stiffness linearisation
//! and the steady-state DTE amplitude of an LTI scene from its complex frequency response.

use super::DynamicsError;
use super::model::Model;
use nalgebra::{Complex, DMatrix};

/// Undamped natural frequencies of the mean-stiffness linearisation, Hz (ascending; rigid-body
/// modes give 0): generalized symmetric eigenproblem `K φ = ω² M φ` via `M^{-1/2} K M^{-1/2}`.
pub fn natural_frequencies_hz(model: &Model) -> Result<Vec<f64>, DynamicsError> {
    let (k, _) = linear_or_err(model)?;
    let n = model.n();
    let s = DMatrix::from_fn(n, n, |i, j| {
        k[(i, j)] / (model.mass[i] * model.mass[j]).sqrt()
    });
    let s = (&s + s.transpose()) * 0.5;
    let ev = s.symmetric_eigen().eigenvalues;
    let mut f: Vec<f64> = ev
        .iter()
        .map(|&l| l.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
        .collect();
    f.sort_by(f64::total_cmp);
    Ok(f)
}

fn linear_or_err(model: &Model) -> Result<(DMatrix<f64>, DMatrix<f64>), DynamicsError> {
    model.linear_matrices().ok_or_else(|| {
        let name = model.terms.iter().find(|t| {
            t.is_nonlinear()
                && !t.linear_matrices(
                    &mut DMatrix::zeros(model.n(), model.n()),
                    &mut DMatrix::zeros(model.n(), model.n()),
                )
        });
        DynamicsError::NotLinear(name.map_or_else(|| "?".into(), |t| t.name()))
    })
}

/// Linear fast path (docs/math/companion.md §B.10): steady-state DTE amplitude (m) of an LTI scene under its static-TE
/// harmonic at the mesh frequency, from the complex frequency response
/// `(K − ω²M + iωC) q̂ = (k + iωc_m) ê · c`, DTE = cᵀq̂ − ê.
pub fn linear_dte_amplitude(model: &Model) -> Result<f64, DynamicsError> {
    let (k, c) = linear_or_err(model)?;
    if !model.is_linear() {
        return Err(DynamicsError::NotLinear(
            "time-varying or nonlinear mesh".into(),
        ));
    }
    let Some(ste) = model.mesh.ste else {
        return Ok(0.0);
    };
    let n = model.n();
    let w = model.mesh.omega_e;
    let a = DMatrix::from_fn(n, n, |i, j| {
        let m = if i == j { model.mass[i] } else { 0.0 };
        Complex::new(k[(i, j)] - w * w * m, w * c[(i, j)])
    });
    let e_hat = Complex::from_polar(ste.er, ste.phase - std::f64::consts::FRAC_PI_2);
    let km = Complex::new(model.mesh.mean_k(), w * model.mesh.c_m) * e_hat;
    let mut f = nalgebra::DVector::from_element(n, Complex::new(0.0, 0.0));
    for &(i, cc) in &model.mesh.coeffs {
        f[i] += km * cc;
    }
    let q = a.lu().solve(&f).ok_or(DynamicsError::NotLinear(
        "singular dynamic stiffness (undamped rigid-body mode)".into(),
    ))?;
    let g: Complex<f64> = model.mesh.coeffs.iter().map(|&(i, cc)| q[i] * cc).sum();
    Ok((g - e_hat).norm())
}
