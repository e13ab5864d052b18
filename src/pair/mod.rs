//! A single non-circular gear pair from a law (the job of the Python `ncgears` package):
//! a motion law `ψ(φ)`, a drive centrode `r(φ)` (centre distance solved for closure), or a CSV
//! table of `(φ, ψ)` in degrees; then teeth, mesh verification and exports.
//!
//! Conventions (docs/math/chain.md §5): driver centre at the origin, rotating CCW by φ; driven centre at
//! `(a, 0)`, rotating CW by ψ; ratio `i = dψ/dφ > 0`. Contact on the centre line:
//! `r1 = a·i/(1+i)` at driver body angle `−φ`, `r2 = a/(1+i)` at driven body angle `π + ψ`.
//! A closed law advances the driven gear by a constant `Δ = ψ(φ+2π) − ψ(φ)` per driver turn
//! (`2π`: equal tooth counts; `π`: 1:2); an open law is used over a driver interval only
//! (an incomplete pair, [`SectorReport`]).
mod closed;
mod design;
mod entry;
pub mod expr;
mod law;
mod motion;
mod report;
mod sector;
mod shaper_relief;

pub use design::{PairDesign, PairOptions, PendingMesh, SectorReport};
pub use entry::{design_pair, design_pair_staged};
pub use expr::{Expr, ExprError};
pub use law::Law;
pub use motion::Motion;
pub use report::{PairReport, PairTimings, UndercutSummary};

use crate::teeth::TeethError;

/// Errors of the pair designer.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PairError {
    /// Expression syntax.
    #[error(transparent)]
    Expr(#[from] ExprError),
    /// The law is not usable.
    #[error("law: {0}")]
    Law(String),
    /// CSV law file problem.
    #[error("{path}:{line}: {message}")]
    Csv {
        /// File.
        path: String,
        /// 1-based line.
        line: usize,
        /// What was expected.
        message: String,
    },
    /// Teeth.
    #[error(transparent)]
    Teeth(#[from] TeethError),
    /// A size of the work outside its admissible range ([`crate::bounds`]).
    #[error(transparent)]
    Bounds(#[from] crate::bounds::OutOfBounds),
    /// Mesh check.
    #[error(transparent)]
    Mesh(#[from] crate::teeth::mesh::MeshError),
    /// Bad parameter.
    #[error("invalid parameter `{name}` = {value}: {expected}")]
    InvalidParameter {
        /// Name.
        name: &'static str,
        /// Value.
        value: f64,
        /// Expectation.
        expected: &'static str,
    },
}
