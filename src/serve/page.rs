//! The page's files, the bundled example trajectories and the bundled loads scene, embedded in
//! the binary.

use super::Reply;
use super::api::ApiError;
use ncgear::design::trajectory::Trajectory;

/// `(name, content type, bytes)` of the page's files.
const ASSETS: [(&str, &str, &str); 3] = [
    (
        "index.html",
        "text/html; charset=utf-8",
        include_str!("page/index.html"),
    ),
    (
        "app.js",
        "text/javascript; charset=utf-8",
        include_str!("page/app.js"),
    ),
    (
        "app.css",
        "text/css; charset=utf-8",
        include_str!("page/app.css"),
    ),
];

/// `(name, file name, text)` of the bundled trajectories (the first opens with the page).
const EXAMPLES: [(&str, &str, &str); 3] = [
    (
        "g1_ellipse",
        "g1_ellipse.csv",
        include_str!("../../assets/trajectories/g1_ellipse.csv"),
    ),
    (
        "designer_kidney",
        "designer_kidney.csv",
        include_str!("../../assets/trajectories/designer_kidney.csv"),
    ),
    (
        "asymmetric_cw",
        "asymmetric_cw.json",
        include_str!("../../assets/trajectories/asymmetric_cw.json"),
    ),
];

/// The bundled loads scene (`ncgear design --module auto --loads` sizes by it): the defaults of
/// the page's loads panel, which reads them from [`loads_scene`] (their one source).
const LOADS_SCENE: (&str, &str) = (
    "assets/loads/rotor.toml",
    include_str!("../../assets/loads/rotor.toml"),
);

/// One of the page's files.
pub fn asset(name: &str) -> Reply {
    asset_reply(name).unwrap_or_else(|e| Reply::error(&e))
}

/// One of the page's files, or 404.
pub fn asset_reply(name: &str) -> Result<Reply, ApiError> {
    let (_, content_type, text) =
        ASSETS
            .iter()
            .find(|(n, ..)| *n == name)
            .ok_or_else(|| ApiError {
                status: 404,
                error: format!("no page file {name}"),
                field: None,
            })?;
    Ok(Reply {
        status: 200,
        content_type,
        body: text.as_bytes().to_vec(),
        download: None,
    })
}

/// `GET /api/examples`: `[{"name": …, "file": …}, …]`.
pub fn examples_json() -> String {
    let list: Vec<_> = EXAMPLES
        .iter()
        .map(|(name, file, _)| serde_json::json!({"name": name, "file": file}))
        .collect();
    serde_json::Value::from(list).to_string()
}

/// `GET /api/examples/NAME`: `{"name": …, "points": […]}`.
pub fn example(name: &str) -> Result<Reply, ApiError> {
    let (_, file, text) = EXAMPLES
        .iter()
        .find(|(n, ..)| *n == name)
        .ok_or_else(|| ApiError {
            status: 404,
            error: format!("no bundled example `{name}`"),
            field: None,
        })?;
    let traj = Trajectory::parse(text, file).map_err(|e| ApiError::bad("file", e.to_string()))?;
    Ok(Reply::json(
        serde_json::json!({"name": name, "file": file, "points": traj.points()}).to_string(),
    ))
}

/// `GET /api/loads/scene`: `{"file", "scene": the bundled scene's tables as JSON (read by the
/// library's config loader), "materials": the material presets}`.
pub fn loads_scene() -> Result<Reply, ApiError> {
    let (file, text) = LOADS_SCENE;
    let scene: ncgear::loads::Scene =
        ncgear::config::parse(text, file, ncgear::config::Format::Toml).map_err(|e| ApiError {
            status: 500,
            error: e.to_string(),
            field: None,
        })?;
    Ok(Reply::json(
        serde_json::json!({
            "file": file,
            "scene": scene,
            "materials": ncgear::loads::rating::material::PRESETS,
        })
        .to_string(),
    ))
}
