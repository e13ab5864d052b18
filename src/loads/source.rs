//! Where the rotor comes from: a design file (`design.json`, with or without its `teeth` block)
//! read back into its train, the teeth made again from the file's own tooth count and options
//! when the stresses are asked for; or a design in memory.

use super::{LoadsError, Rotor};
use crate::design::train::{
    ToothedTrain, TrainPolicy, TrainSource, TrainTeethOptions, tooth_train,
};
use crate::geometry::assembly::Assembly;
use crate::math::Point;
use crate::simulate::DesignFile;
use crate::teeth::ToothPolicy;
use std::path::Path;

/// A designed train ready for its loads: the assembly, its teeth when made, and the teeth's
/// pressure angle when the design has teeth.
#[derive(Debug, Clone)]
pub struct RotorSource {
    /// The train as the design file gives it.
    pub assembly: Assembly,
    /// The teeth, made again from the file (when asked for and the file has them).
    pub teeth: Option<ToothedTrain>,
    /// The teeth's rack pressure angle, rad (the file's teeth, made or not).
    pub pressure_angle_rad: Option<f64>,
    /// The file's `teeth` block: tooth count and options.
    pub teeth_options: Option<TrainTeethOptions>,
    /// The teeth's `phase_mm` (tooth 0's centre on each gear's arc, mm), when known.
    pub teeth_phase_mm: Option<[f64; 3]>,
    /// The target points, mm, world frame.
    pub target_mm: Vec<Point>,
}

impl RotorSource {
    /// Reads a design file; with `make_teeth`, makes its teeth again (its `z` at its module,
    /// its rack, backlash and cutters; no mesh check).
    ///
    /// # Errors
    /// [`LoadsError::Design`] for a file that is not a design, [`LoadsError::NoTeeth`] when
    /// teeth are asked of a design without them, [`LoadsError::Teeth`] when they cannot be made.
    pub fn read(path: &Path, make_teeth: bool) -> Result<Self, LoadsError> {
        let (file, assembly) =
            DesignFile::from_path(path).map_err(|e| LoadsError::Design(e.to_string()))?;
        let mut source = Self::from_design_file(file, assembly);
        if make_teeth {
            source.make_teeth()?;
        }
        Ok(source)
    }

    /// A design file already read ([`DesignFile::parse`]) and its assembly; the teeth not made
    /// yet ([`Self::make_teeth`]).
    #[must_use]
    pub fn from_design_file(file: DesignFile, assembly: Assembly) -> Self {
        let teeth_options = file.teeth.as_ref().map(|t| {
            let opts = t
                .options
                .clone()
                .unwrap_or_else(|| TrainTeethOptions::new(t.module_mm));
            opts.with_policy(TrainPolicy::ScaleCenterDistance(ToothPolicy::Exact(t.z)))
        });
        Self {
            pressure_angle_rad: teeth_options.as_ref().map(|o| o.toothing.rack.alpha_rad()),
            teeth_phase_mm: file.teeth.as_ref().and_then(|t| t.phase_mm),
            assembly,
            teeth: None,
            teeth_options,
            target_mm: file.target_points,
        }
    }

    /// A design in memory and its teeth, if any.
    #[must_use]
    pub fn from_train(
        assembly: Assembly,
        teeth: Option<ToothedTrain>,
        target_mm: Vec<Point>,
    ) -> Self {
        Self {
            pressure_angle_rad: teeth
                .as_ref()
                .map(|t| t.report.options.toothing.rack.alpha_rad()),
            teeth_options: teeth.as_ref().map(|t| t.report.options.clone()),
            teeth_phase_mm: teeth.as_ref().map(|t| t.report.phase_mm),
            assembly,
            teeth,
            target_mm,
        }
    }

    /// Makes the teeth of the file's `teeth` block (no mesh check).
    ///
    /// # Errors
    /// [`LoadsError::NoTeeth`], [`LoadsError::Teeth`].
    pub fn make_teeth(&mut self) -> Result<(), LoadsError> {
        if self.teeth.is_some() {
            return Ok(());
        }
        let mut opts = self.teeth_options.clone().ok_or(LoadsError::NoTeeth)?;
        opts.toothing.verify_steps = 0;
        let on = TrainSource::Assembly {
            assembly: &self.assembly,
            target_mm: &self.target_mm,
        };
        let train = tooth_train(on, &opts).map_err(|e| {
            LoadsError::Teeth(format!("the design's teeth cannot be made again: {e}"))
        })?;
        self.teeth = Some(train);
        Ok(())
    }

    /// The rotor: the toothed train when its teeth are made, else the pitch curves (with the
    /// teeth's pressure angle, if the file has teeth).
    #[must_use]
    pub fn rotor(&self) -> Rotor<'_> {
        match &self.teeth {
            Some(t) => Rotor::toothed(t),
            None => {
                let r = Rotor::pitch(&self.assembly);
                match self.pressure_angle_rad {
                    Some(a) => r.with_pressure_angle_rad(a),
                    None => r,
                }
            }
        }
    }
}
