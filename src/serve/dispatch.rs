//! The endpoints: the page, the bundled examples, parsing an upload, designing, the loads,
//! exporting.

use super::api::{ApiError, DesignRequest, LoadsRequest, ParseRequest, design_error};
use super::{Reply, loads, page, view};
use ncgear::design::train::{ToothedTrain, TrainPolicy, TrainTeethOptions, tooth_train};
use ncgear::design::trajectory::Trajectory;
use ncgear::design::{Design, design, redesign};
use serde_json::Value;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Answers one request; `gone` tells whether its client has closed the connection (a design is
/// then not drawn nor written: nobody would read it).
pub fn route(method: &str, url: &str, body: &str, gone: &dyn Fn() -> bool) -> Reply {
    let path = url.split('?').next().unwrap_or("");
    let result = match (method, path) {
        ("GET", "/" | "/index.html") => Ok(page::asset("index.html")),
        ("GET", p) if p.starts_with("/assets/") => page::asset_reply(&p["/assets/".len()..]),
        ("GET", "/api/examples") => Ok(Reply::json(page::examples_json())),
        ("GET", p) if p.starts_with("/api/examples/") => {
            page::example(&p["/api/examples/".len()..])
        }
        ("POST", "/api/parse") => parse(body),
        ("POST", "/api/design") => design_endpoint(body, gone),
        ("GET", "/api/loads/scene") => page::loads_scene(),
        ("POST", "/api/loads") => loads_endpoint(body),
        ("POST", "/api/export") => export(body),
        ("POST", "/api/synthesize") => synthesize_endpoint(body),
        (_, p) if p.starts_with("/api/") => Err(ApiError {
            status: 404,
            error: format!("no endpoint {method} {p}"),
            field: None,
        }),
        _ => Err(ApiError {
            status: 404,
            error: format!("nothing at {path}"),
            field: None,
        }),
    };
    result.unwrap_or_else(|e| Reply::error(&e))
}

/// `POST /api/parse`: the points of an uploaded file, read as `ncgear design` reads that file.
fn parse(body: &str) -> Result<Reply, ApiError> {
    let (label, req) = ParseRequest::parse(body)?;
    let opts = req.drawing_options()?;
    // The drawing's choices are the page's fields here, not the command line's flags.
    let traj = Trajectory::from_bytes(req.text.as_bytes(), &label, &opts).map_err(|e| {
        let m = e
            .to_string()
            .replace("--layer NAME", "the \"layer or id\" field")
            .replace("--id ID", "the \"layer or id\" field")
            .replace("--units mm|cm|m|in|px", "the \"units\" field");
        ApiError::bad("file", m)
    })?;
    Ok(Reply::json(
        serde_json::json!({"name": label, "points": traj.points()}).to_string(),
    ))
}

/// A design and, with a module, its toothed train (mesh verified as by `ncgear design`).
fn designed(req: &DesignRequest) -> Result<(Design, Option<ToothedTrain>), ApiError> {
    let traj = req.trajectory()?;
    let opts = req.options.design_options()?;
    let d = match &req.start {
        Some(start) => redesign(&traj, &opts, start),
        None => design(&traj, &opts),
    }
    .map_err(|e| design_error(&e))?;
    let Some(m) = opts.module_mm else {
        return Ok((d, None));
    };
    let t = TrainTeethOptions::new(m).with_policy(TrainPolicy::Designed);
    let train = tooth_train(&d, &t)
        .map_err(|e| ApiError::bad("options.module", format!("module {m} mm: {e}")))?;
    let mut d = d;
    train.record(&mut d);
    Ok((d, Some(train)))
}

/// `POST /api/design`: the `design.json` object (with `view` when asked); nothing more once the
/// client is gone.
fn design_endpoint(body: &str, gone: &dyn Fn() -> bool) -> Result<Reply, ApiError> {
    let started = std::time::Instant::now();
    let req = DesignRequest::parse(body)?;
    let spacing = req.spacing()?;
    let (d, train) = designed(&req)?;
    if gone() {
        return Err(super::gone_error());
    }
    let mut value = serde_json::to_value(&d.report).map_err(internal)?;
    if req.view {
        let v = view::view(&d, train.as_ref(), spacing);
        value["view"] = serde_json::to_value(v).map_err(internal)?;
    }
    value["server_ms"] = Value::from(1e3 * started.elapsed().as_secs_f64());
    Ok(Reply::json(value.to_string()))
}

/// `POST /api/loads`: the `loads.json` object of the design sent (the page sends the design on
/// screen: no second design per edit), or of the points designed as `POST /api/export` designs
/// them; its per-sample arrays slimmed to those the page draws unless `full`; `left_out` lists
/// what of the scene was not computed, and why; plus `server_ms`.
fn loads_endpoint(body: &str) -> Result<Reply, ApiError> {
    let started = std::time::Instant::now();
    let req = LoadsRequest::parse(body)?;
    let design = match (req.design, req.points) {
        (Some(_), Some(_)) => {
            return Err(ApiError::bad(
                "points",
                "give the design or the points to design, not both",
            ));
        }
        (Some(_), None) if req.options.is_some() => {
            return Err(ApiError::bad(
                "options",
                "the design carries its own options: send `options` with `points` only",
            ));
        }
        (Some(d), None) => d,
        (None, Some(points)) => {
            let cold = DesignRequest {
                points,
                options: req.options.unwrap_or_default(),
                start: None,
                view: false,
                spacing_mm: None,
                format: None,
            };
            let (d, _) = designed(&cold)?;
            // Read back as a design file is: the loads of `ncgear design` + `ncgear loads`.
            serde_json::to_value(&d.report).map_err(internal)?
        }
        (None, None) => {
            return Err(ApiError::bad(
                "design",
                "send the design (the design.json object) or the points to design",
            ));
        }
    };
    let mut answer = loads::loads(&design, &req.scene)?;
    if !req.full {
        loads::slim(&mut answer.report);
    }
    let mut value = serde_json::to_value(&answer.report).map_err(internal)?;
    if !answer.left_out.is_empty() {
        value["left_out"] = Value::from(answer.left_out);
    }
    value["server_ms"] = Value::from(1e3 * started.elapsed().as_secs_f64());
    Ok(Reply::json(value.to_string()))
}

/// `POST /api/synthesize`: a synthesis spec as uploaded (`{"name", "text"}`, TOML or JSON as
/// `ncgear synthesize` reads it) → `{"synthesis": synthesis.json, "design": design.json with its
/// view, "spec": the spec as read, in JSON}`.
fn synthesize_endpoint(body: &str) -> Result<Reply, ApiError> {
    let started = std::time::Instant::now();
    let (label, req) = ParseRequest::parse(body)?;
    let format = ncgear::config::Format::detect(std::path::Path::new(&label), &req.text);
    let spec: ncgear::synthesis::Spec = ncgear::config::parse(&req.text, &label, format)
        .map_err(|e| ApiError::bad("file", e.to_string()))?;
    let s = ncgear::synthesis::synthesize(&spec, &ncgear::design::DesignOptions::default())
        .map_err(|e| ApiError::bad("file", format!("{label}: {e}")))?;
    let mut design = serde_json::to_value(&s.design.report).map_err(internal)?;
    design["view"] = serde_json::to_value(view::view(&s.design, None, spec.machine.spacing_mm))
        .map_err(internal)?;
    design["server_ms"] = Value::from(1e3 * started.elapsed().as_secs_f64());
    let synthesis = serde_json::to_value(&s.report).map_err(internal)?;
    // The spec as read, so that the page can move a pose and send it back (as JSON).
    let spec = serde_json::to_value(&spec).map_err(internal)?;
    Ok(Reply::json(
        serde_json::json!({"name": label, "synthesis": synthesis, "design": design, "spec": spec})
            .to_string(),
    ))
}

/// `POST /api/export`: the file `ncgear design` writes for these points and options, its bytes
/// (written by the same library calls into a private temporary folder, then read back).
fn export(body: &str) -> Result<Reply, ApiError> {
    let req = DesignRequest::parse(body)?;
    let format = req.format.clone().unwrap_or_else(|| "json".into());
    let module = req.options.module;
    let file = match (format.as_str(), module) {
        ("json", _) => "design.json",
        ("svg", None) => "design.svg",
        ("svg", Some(_)) => "teeth/train.svg",
        ("dxf", Some(_)) => "teeth/train.dxf",
        ("step", Some(_)) => "teeth/train.step",
        ("dxf" | "step", None) => {
            return Err(ApiError::bad(
                "options.module",
                format!("{format} files hold the toothed gears: set a module"),
            ));
        }
        _ => {
            return Err(ApiError::bad(
                "format",
                format!("`{format}`: expected \"json\", \"svg\", \"dxf\" or \"step\""),
            ));
        }
    };
    // The export is the CLI's design of these points: never a warm start.
    let cold = DesignRequest { start: None, ..req };
    let (mut d, train) = designed(&cold)?;
    let dir = TempDir::new()?;
    if let Some(mut t) = train {
        ncgear::output::write_teeth(&mut t, &dir.0, ncgear::cad::dxf::DxfVersion::R2010)
            .map_err(internal)?;
        let step =
            ncgear::output::write_teeth_step(&t, &dir.0, &Default::default()).map_err(internal)?;
        t.report
            .files
            .extend(step.iter().map(|p| p.display().to_string()));
        t.record(&mut d);
    }
    ncgear::output::write_design_with(&d, &dir.0, Default::default()).map_err(internal)?;
    let bytes = std::fs::read(dir.0.join(file)).map_err(internal)?;
    let content_type = match format.as_str() {
        "json" => "application/json",
        "svg" => "image/svg+xml",
        "dxf" => "application/dxf",
        _ => "application/step",
    };
    Ok(Reply {
        status: 200,
        content_type,
        body: bytes,
        download: Some(file.rsplit('/').next().unwrap_or(file).to_string()),
    })
}

fn internal(e: impl std::fmt::Display) -> ApiError {
    ApiError {
        status: 500,
        error: e.to_string(),
        field: None,
    }
}

/// A private folder under the system's temporary directory, removed when dropped.
struct TempDir(std::path::PathBuf);

impl TempDir {
    fn new() -> Result<Self, ApiError> {
        static NEXT: AtomicUsize = AtomicUsize::new(0);
        let dir = std::env::temp_dir().join(format!(
            "ncgear-serve-{}-{}",
            std::process::id(),
            NEXT.fetch_add(1, Ordering::SeqCst)
        ));
        std::fs::create_dir_all(&dir).map_err(internal)?;
        Ok(Self(dir))
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}
