//! Whether a result passed its own verification: the verdict every report carries, and what
//! the command line's exit code follows (3 = written, but the verification failed).
//!
//! A design passes when every check C1–C13 passes and, with teeth, when both meshes roll through
//! their verification positions without interference and with a finite, non-negative backlash;
//! a pair passes on the same mesh rule. A verdict is computed from the report it belongs to, so
//! it cannot disagree with the numbers beside it.
//!
//! ```
//! use ncgear::verdict::Verdict;
//! let v = Verdict::from_failures(vec!["C12: deviation 1.2 mm > 0.05 mm".into()]);
//! assert!(!v.passed);
//! assert!(Verdict::from_failures(Vec::new()).passed);
//! ```

use crate::teeth::mesh::MeshReport;
use serde::{Deserialize, Serialize};

/// The verdict of a report: passed, or the failures that make it fail (one line each).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Verdict {
    /// Every verification passed.
    pub passed: bool,
    /// What failed, one human-readable line per failure (empty when `passed`).
    pub failures: Vec<String>,
}

impl Default for Verdict {
    /// A report nothing has been verified in yet: passed, no failures.
    fn default() -> Self {
        Self::from_failures(Vec::new())
    }
}

impl Verdict {
    /// The verdict of a list of failures: passed when it is empty.
    #[must_use]
    pub fn from_failures(failures: Vec<String>) -> Self {
        Self {
            passed: failures.is_empty(),
            failures,
        }
    }
}

/// The failures of one mesh verification named `name`: interference at any position, or a
/// backlash that is not finite or negative (a pair whose flanks never part or always overlap).
#[must_use]
pub fn mesh_failures(name: &str, m: &MeshReport) -> Vec<String> {
    let mut out = Vec::new();
    if m.interference_steps > 0 {
        out.push(format!(
            "mesh {name}: {} interference steps of {} (max overlap {:.3e} mm²)",
            m.interference_steps, m.steps, m.max_overlap_area_mm2
        ));
    }
    let (lo, hi) = (m.min_backlash_mm, m.max_backlash_mm);
    if m.steps > 0 && !(lo.is_finite() && hi.is_finite() && lo >= 0.0) {
        out.push(format!(
            "mesh {name}: backlash {lo:.4}..{hi:.4} mm (expected finite and ≥ 0)"
        ));
    }
    out
}
