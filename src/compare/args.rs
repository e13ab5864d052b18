//! A comparison's options as the shells take them, written once: the CLI's flags (clap derives
//! on this type, behind the `cli` feature), the Python keywords (their JSON deserialised into
//! it; the defaults are this type's), both turned into [`ReadOptions`] and [`CompareOptions`]
//! by [`CompareArgs::resolve`], which checks what the two option types cannot say alone.
//! Lengths mm (or track units where said), angles degrees.

use super::{CompareError, CompareOptions, LengthUnit, ReadOptions, Scale, bad};
use crate::math::Point;
use crate::simulate::FeatureOptions;

/// The timing drift's highest power unless given.
pub const DEFAULT_DRIFT_ORDER: usize = 3;

/// The planting depth for the hole width unless given, mm.
pub const DEFAULT_DEPTH_MM: f64 = 30.0;

/// `ncgear compare`'s options (the flags of the same names; `ncgear.compare`'s keywords).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct CompareArgs {
    /// Carrier speed, rpm (default: found from the record's period).
    #[cfg_attr(feature = "cli", arg(long))]
    pub rpm: Option<f64>,
    /// Frames per second: for a frame-number time column (or none).
    #[cfg_attr(feature = "cli", arg(long))]
    pub fps: Option<f64>,
    /// Columns time,x,y or time,x,y,x2,y2 (x2, y2: a second marker on the needle's axis), names or
    /// 1-based positions; time `-` for none.
    #[cfg_attr(
        feature = "cli",
        arg(long, value_delimiter = ',', allow_hyphen_values = true)
    )]
    pub columns: Vec<String>,
    /// The encoder column (name or 1-based position): each frame's carrier angle, deg, in the
    /// direction of travel (default: a column named `encoder` or `carrier_deg`).
    #[cfg_attr(feature = "cli", arg(long))]
    pub encoder: Option<String>,
    /// The track's length unit (mm, cm, m, px), overriding the header's.
    #[cfg_attr(feature = "cli", arg(long))]
    pub units: Option<String>,
    /// Pixels per mm.
    #[cfg_attr(feature = "cli", arg(long, conflicts_with_all = ["calibration", "fit_scale"]))]
    pub px_per_mm: Option<f64>,
    /// Two-point calibration x1,y1,x2,y2,dist_mm: two image points (track units) and their distance.
    #[cfg_attr(
        feature = "cli",
        arg(
            long,
            value_delimiter = ',',
            allow_hyphen_values = true,
            conflicts_with = "fit_scale"
        )
    )]
    pub calibration: Vec<f64>,
    /// Fit the scale to the design (it then absorbs any size error of the built mechanism).
    #[cfg_attr(feature = "cli", arg(long))]
    pub fit_scale: bool,
    /// The carrier axis as filmed, x,y (track units): pins the translation.
    #[cfg_attr(
        feature = "cli",
        arg(long, value_delimiter = ',', allow_hyphen_values = true)
    )]
    pub carrier_axis: Vec<f64>,
    /// The rotation from the track's axes (y flipped, mirrored) to the design's, deg, when known
    /// (a levelled camera: 0): pins the rotation.
    #[cfg_attr(feature = "cli", arg(long, allow_hyphen_values = true))]
    pub rotation: Option<f64>,
    /// Mirror the track (filmed from the other side).
    #[cfg_attr(feature = "cli", arg(long))]
    pub mirror: bool,
    /// y points down (image coordinates; the default for pixels).
    #[cfg_attr(feature = "cli", arg(long, conflicts_with = "y_up"))]
    pub y_down: bool,
    /// y points up (the default for mm, cm, m).
    #[cfg_attr(feature = "cli", arg(long))]
    pub y_up: bool,
    /// Highest power of the timing drift (1: constant speed).
    #[cfg_attr(feature = "cli", arg(long, default_value_t = DEFAULT_DRIFT_ORDER))]
    pub drift_order: usize,
    /// Order of the smooth deviation by carrier angle (Fourier harmonics, 2..=40; default:
    /// chosen from the frames, at most 8, by the Bayesian information criterion).
    #[cfg_attr(feature = "cli", arg(long))]
    pub smooth_order: Option<usize>,
    /// Planting depth, mm (for the hole width).
    #[cfg_attr(feature = "cli", arg(long, default_value_t = DEFAULT_DEPTH_MM))]
    pub depth: f64,
    /// Plant spacing, mm (sets the forward speed for the hole width; default 1 m/s).
    #[cfg_attr(feature = "cli", arg(long))]
    pub spacing: Option<f64>,
}

impl Default for CompareArgs {
    fn default() -> Self {
        Self {
            rpm: None,
            fps: None,
            columns: Vec::new(),
            encoder: None,
            units: None,
            px_per_mm: None,
            calibration: Vec::new(),
            fit_scale: false,
            carrier_axis: Vec::new(),
            rotation: None,
            mirror: false,
            y_down: false,
            y_up: false,
            drift_order: DEFAULT_DRIFT_ORDER,
            smooth_order: None,
            depth: DEFAULT_DEPTH_MM,
            spacing: None,
        }
    }
}

impl CompareArgs {
    /// The reading and comparison options these say.
    ///
    /// # Errors
    /// [`CompareError::BadOption`] naming the option: an unknown unit, a calibration or carrier
    /// axis of the wrong count, both `y_down` and `y_up`, a scale given two ways, a spacing that
    /// is not positive. The ranges of the rest are checked by [`super::compare`].
    pub fn resolve(&self) -> Result<(ReadOptions, CompareOptions), CompareError> {
        let units = match &self.units {
            Some(u) => Some(
                LengthUnit::parse(u)
                    .ok_or_else(|| bad("units", format!("{u}: expected mm, cm, m or px")))?,
            ),
            None => None,
        };
        let y_down = match (self.y_down, self.y_up) {
            (true, true) => {
                return Err(bad(
                    "y-down",
                    "y-down and y-up both given: expected one".into(),
                ));
            }
            (true, false) => Some(true),
            (false, true) => Some(false),
            (false, false) => None,
        };
        let read = ReadOptions {
            columns: self.columns.clone(),
            fps: self.fps,
            units,
            y_down,
            encoder: self.encoder.clone(),
        };
        let scale = match (self.px_per_mm, self.calibration.as_slice(), self.fit_scale) {
            (Some(_), [_, ..], _) | (Some(_), _, true) | (None, [_, ..], true) => {
                return Err(bad(
                    "px-per-mm",
                    "the scale is given more than one way (px-per-mm, calibration, fit-scale): \
                     expected one"
                        .into(),
                ));
            }
            (Some(s), [], false) => Scale::PxPerMm(s),
            (None, [x1, y1, x2, y2, d], false) => Scale::Calibration {
                p1: Point::new(*x1, *y1),
                p2: Point::new(*x2, *y2),
                distance_mm: *d,
            },
            (None, [], true) => Scale::Fit,
            (None, [], false) => Scale::Units,
            (None, c, false) => {
                return Err(bad(
                    "calibration",
                    format!("{} numbers given; expected x1,y1,x2,y2,dist_mm", c.len()),
                ));
            }
        };
        let carrier_axis = match self.carrier_axis.as_slice() {
            [] => None,
            [x, y] => Some(Point::new(*x, *y)),
            c => {
                return Err(bad(
                    "carrier-axis",
                    format!("{} numbers given; expected x,y", c.len()),
                ));
            }
        };
        if let Some(s) = self.spacing
            && !(s.is_finite() && s > 0.0)
        {
            return Err(bad(
                "spacing",
                format!("{s}: expected a positive plant spacing in mm"),
            ));
        }
        let opts = CompareOptions {
            scale,
            mirror: self.mirror,
            rpm: self.rpm,
            carrier_axis,
            rotation_rad: self.rotation.map(f64::to_radians),
            drift_order: self.drift_order,
            smooth_order: self.smooth_order,
            features: FeatureOptions::default().with_planting_depth_mm(self.depth),
            spacing_mm: self.spacing,
            ..CompareOptions::default()
        };
        Ok((read, opts))
    }
}
