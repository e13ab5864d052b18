//! The gear blank: what every tooth-generation process reads — the pitch curve by arc length,
//! the basic rack, the tooth count, the module and the outline options.
use super::frame::ArcFrame;
use super::{RackParams, TeethError};
use serde::Serialize;

/// A gear before its teeth are cut: `z` teeth of module `module_mm` on `frame`'s pitch curve,
/// profiled by `rack`, placed, thinned and sampled by `opts`.
///
/// Every generation ([`super::generate`], whatever its [`super::Generation`]) takes one; it
/// borrows the frame (its arc-length table is the costly part) and copies the rest.
///
/// ```
/// use ncgear::geometry::pitch::PitchCurve;
/// use ncgear::teeth::{ArcFrame, GearBlank, Generation, OutlineOptions, RackParams, generate};
/// // A circle of radius 12 mm: perimeter 24π = z·π·m with z = 24 teeth of module 1 mm.
/// let circle = PitchCurve::from_fn(720, |_| 12.0).unwrap();
/// let frame = ArcFrame::new(&circle);
/// let blank = GearBlank::new(&frame, RackParams::default(), 24, 1.0, OutlineOptions::default());
/// assert!((blank.validated_pitch_mm().unwrap() - std::f64::consts::PI).abs() < 1e-9);
/// assert!(generate(&blank, Generation::Rack).is_ok());
/// ```
#[derive(Debug, Clone, Copy)]
pub struct GearBlank<'a> {
    /// The pitch curve by arc length (body frame, mm).
    pub frame: &'a ArcFrame,
    /// The basic rack (profile coefficients per module).
    pub rack: RackParams,
    /// Tooth count.
    pub z: u32,
    /// Module, mm.
    pub module_mm: f64,
    /// Phase, thinning, chord tolerance, open-sector pitch and undercut policy.
    pub opts: OutlineOptions,
}

impl<'a> GearBlank<'a> {
    /// `z` teeth of module `module_mm` (mm) on `frame` with `rack` and `opts`; checked when a
    /// generation starts ([`Self::validated_pitch_mm`]).
    #[must_use]
    pub fn new(
        frame: &'a ArcFrame,
        rack: RackParams,
        z: u32,
        module_mm: f64,
        opts: OutlineOptions,
    ) -> Self {
        Self {
            frame,
            rack,
            z,
            module_mm,
            opts,
        }
    }

    /// The same blank with other outline options (e.g. another chord tolerance, mm).
    #[must_use]
    pub fn with_opts(self, opts: OutlineOptions) -> Self {
        Self { opts, ..self }
    }

    /// Checks the module, chord tolerance, tooth count (`L = zπm`, or `z·p ≤ L` with an open
    /// sector's pitch) and thinnings; returns the pitch `p` (`L/z`, or the open sector's), mm.
    ///
    /// Errors: [`TeethError::InvalidParameter`] naming the first value out of range.
    pub fn validated_pitch_mm(&self) -> Result<f64, TeethError> {
        let (m, z, opts) = (self.module_mm, self.z, &self.opts);
        if !(m.is_finite() && m > 0.0) {
            return Err(TeethError::InvalidParameter {
                name: "module_mm",
                value: m,
                expected: "finite and > 0",
            });
        }
        if !(opts.chord_tol_mm.is_finite() && opts.chord_tol_mm > 0.0) {
            return Err(TeethError::InvalidParameter {
                name: "chord_tol_mm",
                value: opts.chord_tol_mm,
                expected: "finite and > 0",
            });
        }
        let l = self.frame.length_mm();
        let zf = f64::from(z);
        let p = match opts.open_pitch_mm {
            Some(p) if p.is_finite() && p > 0.0 && z >= 1 && zf * p <= l * (1.0 + 1e-12) => p,
            Some(p) => {
                return Err(TeethError::InvalidParameter {
                    name: "open_pitch_mm",
                    value: p,
                    expected: "finite, > 0, with z·p ≤ the perimeter",
                });
            }
            None if z < 3 || ((l / (std::f64::consts::PI * m)) - zf).abs() > 1e-6 * zf => {
                return Err(TeethError::InvalidParameter {
                    name: "z",
                    value: zf,
                    expected: "L/(π·m) (scale the pitch curve to an integer tooth count first)",
                });
            }
            None => l / zf,
        };
        for (name, v) in [
            ("thin_left_mm", opts.thin_left_mm),
            ("thin_right_mm", opts.thin_right_mm),
        ] {
            if !(v.is_finite() && (0.0..0.25 * p).contains(&v)) {
                return Err(TeethError::InvalidParameter {
                    name,
                    value: v,
                    expected: "in [0, p/4)",
                });
            }
        }
        Ok(p)
    }
}

/// Options of a [`GearBlank`]'s outline, whatever its [`super::Generation`]; the defaults are those of [`OutlineOptions::new`]`(0.0, 1e-3)`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct OutlineOptions {
    /// Arc-length position of the centre of tooth 0, mm (the mating phase). Default 0.
    pub phase_mm: f64,
    /// Thinning of the left (smaller-s) flank, mm of arc on the pitch curve. Default 0.
    pub thin_left_mm: f64,
    /// Thinning of the right (larger-s) flank, mm of arc on the pitch curve. Default 0.
    pub thin_right_mm: f64,
    /// Maximum chord sag of the polyline, mm (estimated with a radius of curvature ≥ m on flanks,
    /// root and tip, and ρf on fillets). Default 1e-3 (1e-3·m at m = 1 mm).
    pub chord_tol_mm: f64,
    /// Tooth pitch on the closed carrier of an open sector, mm: `Some(p)` places `z` teeth at
    /// pitch `p` from the phase on (`z·p ≤ L`) and lets the last space absorb `L − z·p` (it is
    /// trimmed away with the sector, see `pair::sector`). Default `None`: `p = L/z`, with
    /// `L = zπm` required.
    pub open_pitch_mm: Option<f64>,
    /// Refuse a flank with undercut ([`TeethError::Undercut`], naming the largest module that
    /// works) instead of cutting it as the rack does. Default `false`: undercut is cut (the
    /// fillet trochoid trims the flank).
    pub refuse_undercut: bool,
}

crate::builder::with_fields!(OutlineOptions {
    with_phase_mm => phase_mm: f64,
    with_thin_left_mm => thin_left_mm: f64,
    with_thin_right_mm => thin_right_mm: f64,
    with_chord_tol_mm => chord_tol_mm: f64,
    with_open_pitch_mm => open_pitch_mm: Option<f64>,
    with_refuse_undercut => refuse_undercut: bool,
});

impl OutlineOptions {
    /// Options with tooth 0 at `phase_mm`, no backlash and chord tolerance `chord_tol_mm`.
    #[must_use]
    pub fn new(phase_mm: f64, chord_tol_mm: f64) -> Self {
        Self {
            phase_mm,
            thin_left_mm: 0.0,
            thin_right_mm: 0.0,
            chord_tol_mm,
            open_pitch_mm: None,
            refuse_undercut: false,
        }
    }
}

impl Default for OutlineOptions {
    /// Tooth 0 at arc length 0, no thinning, chord tolerance 1e-3 mm.
    fn default() -> Self {
        Self::new(0.0, 1e-3)
    }
}
