//! `pair.json`: the report of a designed pair, one type for the CLI, the Python binding and a
//! CAD pipeline (docs/schemas.md).
use super::design::{PairDesign, PairOptions, SectorReport};
use crate::teeth::UndercutReport;
use crate::teeth::mesh::MeshReport;
use crate::teeth::process::GearProcess;
use crate::verdict::Verdict;
use serde::Serialize;

/// `pair.json`: the options, the pair's numbers, the written files, the verdict and the timings.
/// Lengths in mm, angles in degrees, as the field names say.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
#[non_exhaustive]
pub struct PairReport {
    /// Layout version, [`crate::design::SCHEMA_VERSION`].
    pub schema_version: u32,
    /// `ncgear` and its version.
    pub tool: &'static str,
    /// The options the pair was designed with.
    pub options: PairOptions,
    /// Driver tooth count.
    pub z: u32,
    /// Driven tooth count.
    pub z_driven: u32,
    /// Driven rotation per driver turn Δ, degrees.
    pub cycle_advance_deg: f64,
    /// Module, mm.
    pub module_mm: f64,
    /// Centre distance, mm.
    pub center_distance_mm: f64,
    /// Driver pitch perimeter, mm (= zπm).
    pub perimeter_mm: f64,
    /// Ratio range `[min, max]` of i = dψ/dφ.
    pub ratio_range: [f64; 2],
    /// Undercut of the driver's flanks.
    pub driver_undercut: UndercutSummary,
    /// Undercut of the driven gear's flanks.
    pub driven_undercut: UndercutSummary,
    /// How the driver is cut.
    pub driver_process: GearProcess,
    /// How the driven gear is cut.
    pub driven_process: GearProcess,
    /// The mesh verification, when run.
    pub mesh: Option<MeshReport>,
    /// The open sector of an incomplete pair.
    pub sector: Option<SectorReport>,
    /// Files written (set by the caller that writes them).
    pub files: Vec<String>,
    /// Whether the pair passed its verification.
    pub verdict: Verdict,
    /// Wall times, ms (set by the caller that measures them).
    pub timings_ms: PairTimings,
}

/// A gear's undercut in `pair.json`.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct UndercutSummary {
    /// Flanks the rack's tip cuts into.
    pub undercut_flanks: usize,
    /// Flanks on concave pitch arcs.
    pub concave_flanks: usize,
    /// Smallest pitch radius of curvature over convex arcs, mm.
    pub min_rho_mm: f64,
    /// Radius of curvature the module needs to avoid undercut, mm.
    pub required_rho_mm: f64,
    /// Largest module without undercut, mm.
    pub max_module_mm: f64,
    /// Deepest undercut, mm.
    pub max_undercut_mm: f64,
    /// Largest loss of contact ratio from undercut.
    pub max_contact_ratio_loss: f64,
    /// Thinnest tooth root, mm (`None` without undercut).
    pub min_root_thickness_mm: Option<f64>,
}

impl From<&UndercutReport> for UndercutSummary {
    fn from(u: &UndercutReport) -> Self {
        Self {
            undercut_flanks: u.undercut_count,
            concave_flanks: u.concave_count,
            min_rho_mm: u.min_rho_mm,
            required_rho_mm: u.required_rho_mm,
            max_module_mm: u.max_module_mm,
            max_undercut_mm: u.max_undercut_mm,
            max_contact_ratio_loss: u.max_contact_ratio_loss,
            min_root_thickness_mm: u.min_root_thickness_mm,
        }
    }
}

/// Wall times of a pair command, ms.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, schemars::JsonSchema)]
pub struct PairTimings {
    /// Design (law, pitch curves, teeth).
    pub design: f64,
    /// Mesh verification.
    pub verification: f64,
    /// Mesh verification and file writing, side by side.
    pub verification_and_files: f64,
    /// The whole command.
    pub command: f64,
}

impl PairDesign {
    /// The report of this pair designed with `opts`: no files, zero timings (a caller that
    /// writes files and measures time fills [`PairReport::files`] and [`PairReport::timings_ms`]).
    #[must_use]
    pub fn report(&self, opts: &PairOptions) -> PairReport {
        PairReport {
            schema_version: crate::design::SCHEMA_VERSION,
            tool: concat!("ncgear ", env!("CARGO_PKG_VERSION")),
            options: opts.clone(),
            z: self.z,
            z_driven: self.z_driven,
            cycle_advance_deg: self.advance_rad.to_degrees(),
            module_mm: self.module_mm,
            center_distance_mm: self.center_distance_mm,
            perimeter_mm: self.perimeter_mm,
            ratio_range: self.ratio_range,
            driver_undercut: (&self.driver_undercut).into(),
            driven_undercut: (&self.driven_undercut).into(),
            driver_process: self.driver_process.clone(),
            driven_process: self.driven_process.clone(),
            mesh: self.mesh.clone(),
            sector: self.sector.clone(),
            files: Vec::new(),
            verdict: self.verdict(),
            timings_ms: PairTimings::default(),
        }
    }
}
