//! Gear speeds of a fixed-ring planetary set and the spectral lines they put into the
//! sun-displacement signal (docs/math/companion.md §A.2, §A.7).

use crate::analysis::orbit::{OrbitError, invalid};
use std::f64::consts::TAU;

/// Angular speeds of a planetary set with a fixed ring (docs/math/companion.md §A.2, §A.7), rad/s, all signed
/// (CCW positive, sun speed given).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, schemars::JsonSchema)]
pub struct GearSpeeds {
    /// Sun ω_s.
    pub sun_rad_s: f64,
    /// Carrier `ω_c = ω_s z_s/(z_s+z_r)`.
    pub carrier_rad_s: f64,
    /// Planet relative to the carrier `ω_p = −ω_c z_r/z_p`.
    pub planet_rad_s: f64,
    /// Sun relative to the carrier `ω_s − ω_c = −(z_p/z_s) ω_p`.
    pub sun_relative_rad_s: f64,
    /// Mesh frequency `ω_m = z_r |ω_c|`.
    pub mesh_rad_s: f64,
}

impl GearSpeeds {
    /// Fixed ring, given tooth numbers and sun speed.
    ///
    /// # Errors
    /// [`OrbitError::Invalid`] for tooth numbers < 1 or a non-finite / zero sun speed.
    pub fn fixed_ring(
        z_sun: u32,
        z_planet: u32,
        z_ring: u32,
        sun_rad_s: f64,
    ) -> Result<Self, OrbitError> {
        for (k, z) in [
            ("gears.sun_teeth", z_sun),
            ("gears.planet_teeth", z_planet),
            ("gears.ring_teeth", z_ring),
        ] {
            if z == 0 {
                return Err(invalid(k, "must be ≥ 1"));
            }
        }
        if !(sun_rad_s.is_finite() && sun_rad_s != 0.0) {
            return Err(invalid(
                "gears.sun_speed_rpm",
                "must be finite and non-zero",
            ));
        }
        let (zs, zp, zr) = (f64::from(z_sun), f64::from(z_planet), f64::from(z_ring));
        let wc = sun_rad_s * zs / (zs + zr);
        let wp = -wc * zr / zp;
        Ok(Self {
            sun_rad_s,
            carrier_rad_s: wc,
            planet_rad_s: wp,
            sun_relative_rad_s: sun_rad_s - wc,
            mesh_rad_s: zr * wc.abs(),
        })
    }

    /// Expected lines of the sun-displacement signal (docs/math/companion.md §A.7) in the chosen frame, signed rad/s:
    /// planet Z₊/Z₋, sun runout, twice the planet frequency, the carrier (housing frame only) and
    /// `mesh_harmonics` mesh harmonics. Housing frame: a carrier-frame line at ω appears at ω + ω_c.
    #[must_use]
    pub fn expected_lines(&self, housing_frame: bool, mesh_harmonics: u32) -> Vec<Line> {
        let wc = if housing_frame {
            self.carrier_rad_s
        } else {
            0.0
        };
        let wp = self.planet_rad_s;
        let mut v = vec![
            Line::new("planet Z+", wc + wp, LineKind::Planet),
            Line::new("planet Z-", wc - wp, LineKind::Planet),
            Line::new(
                "sun runout",
                wc + self.sun_relative_rad_s,
                LineKind::Nuisance,
            ),
            Line::new("2x planet +", wc + 2.0 * wp, LineKind::Nuisance),
            Line::new("2x planet -", wc - 2.0 * wp, LineKind::Nuisance),
        ];
        if housing_frame {
            v.push(Line::new("carrier", wc, LineKind::Nuisance));
        }
        for k in 1..=mesh_harmonics {
            let w = f64::from(k) * self.mesh_rad_s;
            v.push(Line::new(
                format!("mesh x{k} +"),
                wc + w,
                LineKind::Nuisance,
            ));
            v.push(Line::new(
                format!("mesh x{k} -"),
                wc - w,
                LineKind::Nuisance,
            ));
        }
        v
    }
}

/// Role of a spectral line.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum LineKind {
    /// A planet-eccentricity component (to be extracted).
    Planet,
    /// A known interfering component (fitted and discarded).
    Nuisance,
}

/// A spectral line at a signed angular frequency of the analysis frame.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Line {
    /// Label for reports.
    pub label: String,
    /// Signed angular frequency, rad/s (complex spectrum of z = x + iy).
    pub omega_rad_s: f64,
    /// Role.
    pub kind: LineKind,
}

impl Line {
    /// A line.
    #[must_use]
    pub fn new(label: impl Into<String>, omega_rad_s: f64, kind: LineKind) -> Self {
        Self {
            label: label.into(),
            omega_rad_s,
            kind,
        }
    }
}

/// rpm → rad/s.
#[must_use]
pub fn rpm_to_rad_s(rpm: f64) -> f64 {
    rpm * TAU / 60.0
}
