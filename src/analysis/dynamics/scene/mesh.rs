//! The mesh effects of a scene turned into model parts: the stiffness law (docs/math/companion.md §B.2), the static
//! transmission error, backlash (docs/math/companion.md §B.3 eq. B-5) and tip relief (docs/math/companion.md §B.3 eq. B-4), converted from file units (µm, mm,
//! degrees) to SI.

use super::{BacklashSpec, MeshSpec, ReliefKind, ReliefSpec, SceneError, SteSpec};
use super::{ERROR_UM, PHASE_DEG, invalid, pos, ranged};
use crate::analysis::dynamics::model::{Backlash, Relief, Ste, StiffnessLaw};
use crate::analysis::dynamics::tvms::{PairGeometry, RectangularTvms};
use crate::bounds::Span;

/// The stiffness law of `effects.mesh_stiffness`; `eps` is the contact ratio ε.
pub(super) fn stiffness_law(
    file: &str,
    ms: &MeshSpec,
    eps: f64,
) -> Result<StiffnessLaw, SceneError> {
    let key = "effects.mesh_stiffness";
    let rect = |kmax: f64, kmin: f64| -> Result<RectangularTvms, SceneError> {
        pos(file, &format!("{key}.kmax"), kmax)?;
        pos(file, &format!("{key}.kmin"), kmin)?;
        if kmin > kmax {
            return Err(invalid(
                file,
                &format!("{key}.kmin"),
                kmin.to_string(),
                &format!("kmin ≤ kmax = {kmax}"),
            ));
        }
        Ok(RectangularTvms { kmax, kmin, eps })
    };
    Ok(match *ms {
        MeshSpec::Constant { k, .. } => {
            pos(file, &format!("{key}.k"), k)?;
            StiffnessLaw::Constant(k)
        }
        MeshSpec::Fourier { kmax, kmin, n, .. } => {
            StiffnessLaw::Fourier(rect(kmax, kmin)?, n.unwrap_or(9))
        }
        MeshSpec::Rectangular { kmax, kmin, .. } => StiffnessLaw::Rectangular(rect(kmax, kmin)?),
        MeshSpec::Pairs { kmax, kmin, .. } => StiffnessLaw::Pairs(rect(kmax, kmin)?),
    })
}

/// `effects.static_te`: `e(t) = e0 + er sin(ωe t + φ)`, µm and degrees → m and rad.
pub(super) fn static_te(file: &str, s: &SteSpec) -> Result<Ste, SceneError> {
    let um = "a transmission error in µm (10 mm at most)";
    ranged(
        file,
        "effects.static_te.er_um",
        s.er_um,
        Span::closed(0.0, ERROR_UM.hi),
        um,
    )?;
    ranged(file, "effects.static_te.e0_um", s.e0_um, ERROR_UM, um)?;
    ranged(
        file,
        "effects.static_te.phase_deg",
        s.phase_deg,
        PHASE_DEG,
        "a phase in degrees",
    )?;
    Ok(Ste {
        e0: s.e0_um * 1e-6,
        er: s.er_um * 1e-6,
        phase: s.phase_deg.to_radians(),
    })
}

/// `effects.backlash`: half gap b, µm → m.
pub(super) fn backlash(file: &str, b: &BacklashSpec) -> Result<Backlash, SceneError> {
    ranged(
        file,
        "effects.backlash.half_gap_um",
        b.half_gap_um,
        Span::positive(ERROR_UM.hi),
        "a positive half gap in µm (10 mm at most)",
    )?;
    Ok(Backlash {
        b: b.half_gap_um * 1e-6,
        damping_in_gap: b.damping_in_gap,
        no_tension: b.no_tension,
    })
}

/// `effects.tip_relief`: Δmax (µm → m) over a length L (mm → m) along the line of action,
/// 0 < L ≤ (ε−1)·pb.
pub(super) fn tip_relief(
    file: &str,
    r: &ReliefSpec,
    geom: &PairGeometry,
) -> Result<Relief, SceneError> {
    match r.kind {
        ReliefKind::Linear => {}
    }
    ranged(
        file,
        "effects.tip_relief.delta_max_um",
        r.delta_max_um,
        Span::closed(0.0, ERROR_UM.hi),
        "a relief depth in µm (10 mm at most)",
    )?;
    let lmax = (geom.contact_ratio - 1.0) * geom.base_pitch_m * 1e3;
    if !(r.length_mm > 0.0 && r.length_mm <= lmax + 1e-12) {
        return Err(invalid(
            file,
            "effects.tip_relief.length_mm",
            r.length_mm.to_string(),
            &format!(
                "a relief length along the line of action in mm, 0 < L ≤ (ε−1)·pb = {lmax:.4}"
            ),
        ));
    }
    Ok(Relief {
        delta_max: r.delta_max_um * 1e-6,
        length: r.length_mm * 1e-3,
    })
}
