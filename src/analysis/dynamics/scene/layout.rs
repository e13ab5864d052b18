//! The kept degrees of freedom and the shaft speeds: what the term builders read of the model.

use crate::analysis::dynamics::model::DOF_NAMES;

/// The kept DOFs and the shaft speeds, shared by the term builders.
pub(super) struct Layout {
    /// Kept DOFs, as indices into [`DOF_NAMES`].
    pub dofs: Vec<usize>,
    /// The single relative coordinate `u` only.
    pub sdof: bool,
    /// Pinion and gear speeds ω1 = ωe/z1, ω2 = ωe/z2, rad/s.
    pub omega: [f64; 2],
}

impl Layout {
    /// Position of DOF `name` in the model, if kept.
    pub fn idx(&self, name: &str) -> Option<usize> {
        self.dofs.iter().position(|&k| DOF_NAMES[k] == name)
    }

    /// Names of the kept DOFs, in model order.
    pub fn names(&self) -> impl Iterator<Item = &'static str> + '_ {
        self.dofs.iter().map(|&k| DOF_NAMES[k])
    }
}
