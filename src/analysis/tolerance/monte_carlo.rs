//! Monte Carlo of random assembly: uniform assembly angles and the amplitude distributions of the
//! error file, the certified peak of every sample.

use super::Analysis;
use super::error_file::AmplitudeDist;
use crate::math::monte_carlo::{self, McError, McOptions, McStats};
use crate::progress::Progress;
use rand::RngExt;
use std::f64::consts::TAU;

impl Analysis {
    /// Monte Carlo over random assembly angles (uniform) and amplitude distributions: certified
    /// peak per sample, µm. Sample `i` draws the free angles first, then the amplitudes, from
    /// its own stream ([`monte_carlo::run`]).
    ///
    /// # Errors
    /// [`McError`] for bad options or a non-finite sample.
    pub fn monte_carlo(
        &self,
        opts: &McOptions,
        progress: &Progress,
    ) -> Result<(McStats, Vec<f64>), McError> {
        let d = self.free_count();
        monte_carlo::run(
            opts,
            |rng, _| {
                let betas: Vec<f64> = (0..d).map(|_| rng.random::<f64>() * TAU).collect();
                let ph = self.phases(&betas);
                let amps: Vec<f64> = self
                    .terms
                    .iter()
                    .map(|t| match t.amplitude_dist {
                        None => t.amplitude_um,
                        Some(AmplitudeDist::UniformUm([lo, hi])) => {
                            lo + (hi - lo) * rng.random::<f64>()
                        }
                        Some(AmplitudeDist::RayleighSigmaUm(s)) => {
                            let u: f64 = rng.random::<f64>();
                            s * (-2.0 * (1.0 - u).ln()).sqrt()
                        }
                    })
                    .collect();
                self.grid.peak(&amps, &ph).value
            },
            progress,
        )
    }
}
