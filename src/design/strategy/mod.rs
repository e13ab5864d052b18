//! The fit strategies that turn a route's train into the design (docs/math/chain.md §8): the free
//! fit of every parameter to the points (`free`), a module's tooth count as a constraint
//! (`module`), the warm start of a re-design ([`warm`]), a start off the carrier line
//! (`offset_start`) and restarts from the classical elliptic sun (`ellipse`), all over the
//! trains built on step 1's arms (`arms`).

pub(in crate::design) mod arms;
pub(in crate::design) mod ellipse;
pub(in crate::design) mod free;
pub(in crate::design) mod module;
pub(in crate::design) mod offset_start;
pub mod warm;
