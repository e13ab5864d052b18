//! The pair designer's entry point: check the options, then design the closed pair (equal or
//! unequal tooth counts, [`super::design`]) or the open sector ([`super::sector`]).
use super::closed::design_closed;
use super::design::{PairDesign, PairOptions, PendingMesh, validate_options};
use super::{Law, PairError};

/// Designs the toothed pair: pitch curves scaled so that `L = zπm` (an open sector: z pitches on
/// its active arc), outlines with the mating phase (driver tooth 0 centred at the contact of
/// φ = 0, a driven space facing it), and the mesh verification over a full cycle (the q driver
/// turns of a p/q ratio) or over the sector's interval. To watch the check, run the two stages:
/// [`design_pair_staged`], then [`PendingMesh::run`] with a [`Progress`](crate::progress::Progress).
///
/// # Errors
/// [`PairError`]: bad options, a law without a closed (or open) pair, teeth that cannot be cut.
pub fn design_pair(law: &Law, opts: &PairOptions) -> Result<PairDesign, PairError> {
    let (mut design, pending) = design_pair_staged(law, opts)?;
    if let Some(p) = pending {
        design.mesh = Some(p.run(&crate::progress::Progress::none())?);
    }
    Ok(design)
}

/// [`design_pair`] in its two stages, for a caller that runs the mesh check beside other work
/// (writing the design's files): the design (its `mesh` is `None`) and the check ready to run
/// ([`PendingMesh::run`]; `None` when `verify_steps` is 0).
///
/// # Errors
/// As [`design_pair`], except the check's own.
pub fn design_pair_staged(
    law: &Law,
    opts: &PairOptions,
) -> Result<(PairDesign, Option<PendingMesh>), PairError> {
    validate_options(opts)?;
    match (opts.open_sector_rad, law) {
        (None, _) => design_closed(law, opts),
        (Some(range), Law::Motion(e)) => super::sector::design_open(e, range, opts),
        (Some(_), _) => Err(PairError::Law(
            "an open sector takes a motion law ψ(φ) (not a centrode or a table)".into(),
        )),
    }
}
