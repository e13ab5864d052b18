//! The patent route's ratio: the segmented-ratio Fourier hypothesis with its mirror and weight
//! iteration (docs/math/chain.md §7), and the refinement that fits the tip motion directly when it
//! misses the tolerance (docs/math/chain.md §8.3).

pub mod refine;
pub mod segmented;
