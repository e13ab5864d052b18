//! The gears as geometry: the sun's ratio law as a Fourier series, pitch curves, the mechanism
//! (carrier, sun, intermediate, planet, needle) and its assembly and forward model.

pub mod assembly;
pub mod fourier;
pub mod golden;
pub mod limits;
pub mod mechanism;
pub mod perimeter;
pub mod pitch;
