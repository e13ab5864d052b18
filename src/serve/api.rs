//! The JSON API of the designer: requests, the design options by their CLI names, errors.
//!
//! `POST /api/design` takes `{"points": [[x, y], …], "options": {…}, "start": <design.json>,
//! "view": true}` and answers the `design.json` object (with a `view` member, the drawing data of
//! [`super::view`], when asked). `options` are the `ncgear design` flags by their JSON names
//! (`--tol-mm` → `tol_mm`); every field is optional and takes the CLI's default. Errors are
//! HTTP 400 `{"error": "…", "field": "…"}`.
//!
//! `POST /api/loads` takes `{"design": <design.json>, "scene": {…}}` (or `"points"` and
//! `"options"` in place of `"design"`) and answers the `loads.json` object ([`super::loads`]).

use ncgear::design::trajectory::{DrawingOptions, DrawingUnits, Trajectory};
use ncgear::design::{DesignError, DesignOptions, IdlerOffset, RefineMode};
use ncgear::math::Point;
use serde::Deserialize;

/// An error answered as JSON: HTTP status, message, and the request field it concerns.
#[derive(Debug, Clone)]
pub struct ApiError {
    /// HTTP status code.
    pub status: u16,
    /// What went wrong and what to do.
    pub error: String,
    /// The request field at fault (`points`, `options.module`, `body`, …), if one.
    pub field: Option<String>,
}

impl ApiError {
    /// A 400 naming `field`.
    pub fn bad(field: &str, error: impl Into<String>) -> Self {
        Self {
            status: 400,
            error: error.into(),
            field: Some(field.to_string()),
        }
    }

    /// The JSON body `{"error": …, "field": …}`.
    pub fn body(&self) -> String {
        serde_json::json!({"error": self.error, "field": self.field}).to_string()
    }
}

/// The design options a request may set: `ncgear design`'s flags by their JSON names.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Options {
    /// Carrier axis O `[x, y]`, mm (`--center`).
    pub center: Option<Point>,
    /// Fixed Fourier order (`--order`).
    pub order: Option<usize>,
    /// Target max tip deviation, mm (`--tol-mm`).
    pub tol_mm: Option<f64>,
    /// `"auto"`, `"on"` or `"off"` (`--refine`).
    pub refine: Option<String>,
    /// `"on"` or `"off"` (`--limits`).
    pub limits: Option<String>,
    /// Largest effective pressure angle, degrees (`--max-pressure-angle`).
    pub max_pressure_angle: Option<f64>,
    /// Smallest concave radius of curvature, mm (`--min-concave-radius`).
    pub min_concave_radius: Option<f64>,
    /// Smallest convex radius of curvature, mm (`--min-convex-radius`).
    pub min_convex_radius: Option<f64>,
    /// Admissible sun ratio range `[min, max]` (`--ratio-bounds`).
    pub ratio_bounds: Option<[f64; 2]>,
    /// Smoothing harmonics (`--smooth`).
    pub smooth: Option<usize>,
    /// Module, mm (`--module`): the design is made for it and gets teeth.
    pub module: Option<f64>,
    /// Carrier sense `"auto"`, `"ccw"` or `"cw"` (`--sense`).
    pub sense: Option<String>,
    /// Where the intermediate axis sits: `"auto"`, `"collinear"` or `"free"` (`--idler-offset`).
    pub idler_offset: Option<String>,
}

impl Options {
    /// The library options, as `ncgear design` builds them from the same flags.
    pub fn design_options(&self) -> Result<DesignOptions, ApiError> {
        let d = DesignOptions::default();
        let refine = match self.refine.as_deref() {
            None | Some("auto") => RefineMode::Auto,
            Some("on") => RefineMode::On,
            Some("off") => RefineMode::Off,
            Some(v) => {
                return Err(ApiError::bad(
                    "options.refine",
                    format!("`{v}`: expected \"auto\", \"on\" or \"off\""),
                ));
            }
        };
        let limits_on = match self.limits.as_deref() {
            None | Some("on") => true,
            Some("off") => false,
            Some(v) => {
                return Err(ApiError::bad(
                    "options.limits",
                    format!("`{v}`: expected \"on\" or \"off\""),
                ));
            }
        };
        let sense = match self.sense.as_deref() {
            None | Some("auto") => None,
            Some("ccw") => Some(1),
            Some("cw") => Some(-1),
            Some(v) => {
                return Err(ApiError::bad(
                    "options.sense",
                    format!("`{v}`: expected \"auto\", \"ccw\" or \"cw\""),
                ));
            }
        };
        let idler_offset = match self.idler_offset.as_deref() {
            None | Some("auto") => IdlerOffset::Auto,
            Some("collinear") => IdlerOffset::Collinear,
            Some("free") => IdlerOffset::Free,
            Some(v) => {
                return Err(ApiError::bad(
                    "options.idler_offset",
                    format!("`{v}`: expected \"auto\", \"collinear\" or \"free\""),
                ));
            }
        };
        let ratio_bounds = self.ratio_bounds.unwrap_or(d.refine_options.ratio_bounds);
        Ok(DesignOptions::default()
            .with_center_mm(self.center.unwrap_or(d.center_mm))
            .with_order(self.order)
            .with_tol_mm(self.tol_mm.unwrap_or(d.tol_mm))
            .with_refine(refine)
            .with_limits(limits_on)
            .with_max_pressure_angle_rad(
                self.max_pressure_angle
                    .map_or(d.max_pressure_angle_rad, f64::to_radians),
            )
            .with_min_concave_radius_mm(self.min_concave_radius)
            .with_min_convex_radius_mm(self.min_convex_radius)
            .with_refine_options(d.refine_options.with_ratio_bounds(ratio_bounds))
            .with_smooth(self.smooth)
            .with_inverse(d.inverse.with_sense(sense))
            .with_module_mm(self.module)
            .with_idler_offset(idler_offset))
    }
}

/// `POST /api/design` and `POST /api/export`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DesignRequest {
    /// Target points `[x, y]` in travel order, mm.
    pub points: Vec<Point>,
    /// Design options (CLI names).
    #[serde(default)]
    pub options: Options,
    /// An earlier `design.json` to re-design from ([`ncgear::design::redesign`]).
    #[serde(default)]
    pub start: Option<Box<ncgear::design::DesignReport>>,
    /// Answer the drawing data too (`view`).
    #[serde(default)]
    pub view: bool,
    /// Plant spacing of the agronomic figures in `view`, mm (two plants per carrier turn).
    #[serde(default)]
    pub spacing_mm: Option<f64>,
    /// `POST /api/export` only: `"json"`, `"svg"`, `"dxf"` or `"step"`.
    #[serde(default)]
    pub format: Option<String>,
}

impl DesignRequest {
    /// Parses a request body, naming the field at fault.
    pub fn parse(body: &str) -> Result<Self, ApiError> {
        serde_json::from_str(body).map_err(|e| {
            let msg = e.to_string();
            let field = ["points", "options", "start", "format", "view", "spacing_mm"]
                .into_iter()
                .find(|f| msg.contains(&format!("`{f}`")))
                .unwrap_or("body");
            ApiError::bad(field, format!("the request is not a design request: {msg}"))
        })
    }

    /// The plant spacing, checked (positive and finite, mm).
    pub fn spacing(&self) -> Result<Option<f64>, ApiError> {
        match self.spacing_mm {
            Some(s) if !(s > 0.0 && s.is_finite()) => Err(ApiError::bad(
                "spacing_mm",
                format!("{s}: the plant spacing must be a positive length in mm"),
            )),
            s => Ok(s),
        }
    }

    /// The target, checked as the CLI checks a trajectory file.
    pub fn trajectory(&self) -> Result<Trajectory, ApiError> {
        Trajectory::from_points(self.points.clone())
            .map_err(|e| ApiError::bad("points", e.to_string()))
    }
}

/// `POST /api/loads`: the loads of a design under a scene ([`super::loads`]).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadsRequest {
    /// The design: the `design.json` object `POST /api/design` answered (its `view` and
    /// `server_ms` are not read), or a design file's contents.
    #[serde(default)]
    pub design: Option<serde_json::Value>,
    /// Or the target points `[x, y]`, mm, designed as `POST /api/export` designs them (the full
    /// search, `ncgear design`'s design) with `options`.
    #[serde(default)]
    pub points: Option<Vec<Point>>,
    /// Design options of `points` (CLI names).
    #[serde(default)]
    pub options: Option<Options>,
    /// The scene's tables by the keys of a scene file (`operation`, `arm`, `gears`, `needle`,
    /// `material`, `rating`; docs/loads.md), without `design`.
    pub scene: serde_json::Value,
    /// Answer every per-sample array of `loads.json` (default: those the page draws).
    #[serde(default)]
    pub full: bool,
}

impl LoadsRequest {
    /// Parses a request body, naming the field at fault.
    pub fn parse(body: &str) -> Result<Self, ApiError> {
        serde_json::from_str(body).map_err(|e| {
            let msg = e.to_string();
            let field = ["design", "points", "options", "scene", "full"]
                .into_iter()
                .find(|f| msg.contains(&format!("`{f}`")))
                .unwrap_or("body");
            ApiError::bad(field, format!("the request is not a loads request: {msg}"))
        })
    }
}

/// `POST /api/parse`: a file's text as uploaded, parsed exactly as the CLI reads that file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParseRequest {
    /// File name (its extension chooses the format, as on the command line).
    pub name: String,
    /// File contents.
    pub text: String,
    /// A DXF drawing's layer holding the loop (`--layer`).
    #[serde(default)]
    pub layer: Option<String>,
    /// An SVG drawing's element id, or a group's, holding the loop (`--id`).
    #[serde(default)]
    pub id: Option<String>,
    /// A drawing's units when the file does not say them: `mm`, `cm`, `m`, `in`, `px` (`--units`).
    #[serde(default)]
    pub units: Option<String>,
}

impl ParseRequest {
    /// Parses an upload body; returns the file name made a safe label (no control characters, at
    /// most 200 characters: only a label and a format hint, nothing is read from or written to
    /// disk) and the request.
    pub fn parse(body: &str) -> Result<(String, Self), ApiError> {
        let req: Self = serde_json::from_str(body).map_err(|e| {
            ApiError::bad(
                "body",
                format!("expected {{\"name\": …, \"text\": …}}: {e}"),
            )
        })?;
        let label = req
            .name
            .chars()
            .filter(|c| !c.is_control())
            .take(200)
            .collect();
        Ok((label, req))
    }

    /// How to read the loop when the file is a drawing (blank fields: the file's own choice).
    pub fn drawing_options(&self) -> Result<DrawingOptions, ApiError> {
        let given = |s: &Option<String>| s.as_ref().filter(|s| !s.trim().is_empty()).cloned();
        let units = given(&self.units)
            .map(|u| u.parse::<DrawingUnits>())
            .transpose()
            .map_err(|e| ApiError::bad("units", e))?;
        Ok(DrawingOptions::default()
            .with_layer(given(&self.layer))
            .with_id(given(&self.id))
            .with_units(units))
    }
}

/// The HTTP answer for a design error: 400 naming the option, or 500 for an internal failure.
pub fn design_error(e: &DesignError) -> ApiError {
    match e {
        DesignError::Internal(_) => ApiError {
            status: 500,
            error: e.to_string(),
            field: None,
        },
        DesignError::BadOption { option, .. } => {
            ApiError::bad(&format!("options.{option}"), e.to_string())
        }
        DesignError::Bounds(b) => ApiError::bad(&format!("options.{}", b.quantity), e.to_string()),
        _ => ApiError::bad("points", e.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The page's three layouts reach the library's; anything else is refused naming the field.
    #[test]
    fn idler_offset_maps_to_the_librarys_layouts() {
        let with = |v: &str| Options {
            idler_offset: Some(v.into()),
            ..Options::default()
        };
        assert_eq!(
            Options::default().design_options().unwrap().idler_offset,
            IdlerOffset::Auto
        );
        assert_eq!(
            with("collinear").design_options().unwrap().idler_offset,
            IdlerOffset::Collinear
        );
        assert_eq!(
            with("free").design_options().unwrap().idler_offset,
            IdlerOffset::Free
        );
        let e = with("beside").design_options().unwrap_err();
        assert_eq!(e.field.as_deref(), Some("options.idler_offset"));
    }

    /// The page states the one rule of `auto` in the library's words (the trade-off table
    /// prints the same constant).
    #[test]
    fn the_page_states_the_auto_rule() {
        let page = include_str!("page/index.html");
        assert!(
            page.contains(IdlerOffset::AUTO_RULE),
            "the page lost the rule"
        );
        assert!(page.contains(r#"data-testid="idler-offset""#));
    }
}
