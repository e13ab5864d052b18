//! What a design run writes: the design's files, charts and the animation.

pub mod animate;
pub mod files;
pub mod plot;
