//! The charts of a rotor scene (`ncgear dynamics` on assets/dynamics/rotor_g1.toml, about 1 s):
//! `forces.svg` shades every contact loss and marks every impact of `dynamics.json`, its force
//! axis reaches the largest dynamic force, `tip.svg` is written beside it, PNG copies only with
//! `--png`; a speed sweep writes `sweep.csv` and `sweep.svg`.
use super::cli::{message, ncgear};
use std::path::{Path, PathBuf};

fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn scene() -> String {
    format!(
        "{}/assets/dynamics/rotor_g1.toml",
        env!("CARGO_MANIFEST_DIR")
    )
}

/// The opening tags `<name …>` of `svg`.
fn tags<'a>(svg: &'a str, name: &str) -> Vec<&'a str> {
    let open = format!("<{name} ");
    svg.match_indices(&open)
        .map(|(i, _)| {
            let rest = &svg[i..];
            &rest[..rest.find('>').map_or(rest.len(), |e| e + 1)]
        })
        .collect()
}

/// The numeric attribute `key` of the tag `tag`.
fn attr(tag: &str, key: &str) -> f64 {
    let k = format!(" {key}=\"");
    let from = tag.find(&k).unwrap_or_else(|| panic!("{key} in {tag}")) + k.len();
    let len = tag[from..].find('"').unwrap();
    tag[from..from + len].parse().unwrap()
}

/// The y-axis tick labels `(pixel y, value)` of `svg` (right-aligned texts), left of `x_split`
/// px or right of it.
fn y_ticks(svg: &str, left: bool, x_split: f64) -> Vec<(f64, f64)> {
    svg.match_indices("<text ")
        .filter_map(|(i, _)| {
            let rest = &svg[i..];
            let end = rest.find('>')?;
            let tag = &rest[..end];
            let body = rest[end + 1..rest.find("</text>")?].trim();
            let on_side = (attr(tag, "x") < x_split) == left;
            (tag.contains("text-anchor=\"end\"") && on_side)
                .then(|| body.parse().ok().map(|v| (attr(tag, "y"), v)))
                .flatten()
        })
        .collect()
}

/// The bands of contact-loss intervals as the chart draws them: one each, two across φ = 0.
fn bands(intervals: &serde_json::Value) -> usize {
    intervals
        .as_array()
        .unwrap()
        .iter()
        .map(|p| if p[1].as_f64() < p[0].as_f64() { 2 } else { 1 })
        .sum()
}

#[test]
fn the_force_chart_shows_every_contact_loss_and_impact_on_an_axis_that_holds_the_peak() {
    let out = scratch("rotor_charts");
    let o = ncgear()
        .args(["dynamics", &scene(), "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", message(&o));
    for f in ["forces.svg", "tip.svg", "dynamics.json"] {
        assert!(out.join(f).is_file(), "{f} not written");
    }
    assert!(!out.join("forces.png").exists(), "a PNG without --png");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("dynamics.json")).unwrap()).unwrap();
    let svg = std::fs::read_to_string(out.join("forces.svg")).unwrap();
    let width = attr(tags(&svg, "svg")[0], "width");
    // The bands span the plotting area's height (the legend's swatch is 10 px tall).
    let shaded: Vec<&str> = tags(&svg, "rect")
        .into_iter()
        .filter(|r| r.contains("opacity=\"0.2\"") && attr(r, "height") > 20.0)
        .collect();
    let circles = tags(&svg, "circle");
    let mut want_bands = 0;
    let mut want_impacts = 0;
    for (k, mesh) in ["sun_intermediate", "intermediate_planet"]
        .into_iter()
        .enumerate()
    {
        let s = &report["summary"]["meshes"][mesh];
        let left = k == 0;
        let side = |x: f64| (x < 0.5 * width) == left;
        let n_bands = bands(&s["contact_loss_deg"]);
        let impacts = s["impacts"].as_array().unwrap();
        assert!(
            n_bands > 0 && !impacts.is_empty(),
            "{mesh}: no knock to draw"
        );
        let mine: Vec<&&str> = shaded.iter().filter(|r| side(attr(r, "x"))).collect();
        assert_eq!(mine.len(), n_bands, "{mesh}: shaded intervals");
        let marks = circles.iter().filter(|c| side(attr(c, "cx"))).count();
        assert_eq!(marks, impacts.len(), "{mesh}: impact markers");
        want_bands += n_bands;
        want_impacts += impacts.len();
        // The axis: the bands run from its bottom to its top; the tick labels map px to N.
        let top_px = attr(mine[0], "y");
        let ticks = y_ticks(&svg, left, 0.5 * width);
        assert!(ticks.len() >= 2, "{mesh}: tick labels {ticks:?}");
        let ((p0, v0), (p1, v1)) = (ticks[0], ticks[ticks.len() - 1]);
        let top_n = v0 + (top_px - p0) * (v1 - v0) / (p1 - p0);
        let peak = s["peak_dynamic_n"].as_f64().unwrap();
        let hardest = impacts
            .iter()
            .map(|i| i["peak_force_n"].as_f64().unwrap())
            .fold(peak, f64::max);
        assert!(
            top_n >= hardest && top_n < 1.2 * hardest,
            "{mesh}: the axis reaches {top_n} N, the largest force is {hardest} N"
        );
    }
    assert_eq!(shaded.len(), want_bands);
    assert_eq!(circles.len(), want_impacts);
    let tip = std::fs::read_to_string(out.join("tip.svg")).unwrap();
    assert!(tags(&tip, "polyline").len() > 2 && tip.contains("tip deviation (mm)"));
}

#[test]
fn a_speed_sweep_writes_its_table_and_chart_and_png_on_request() {
    let out = scratch("rotor_sweep_charts");
    let o = ncgear()
        .args([
            "dynamics",
            &scene(),
            "--sweep-rpm",
            "250:300:50",
            "--png",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", message(&o));
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(
        lines[0],
        "carrier_rpm,dynamic_factor_sun,dynamic_factor_planet,impacts_per_turn,\
         max_impact_speed_m_s,max_tip_deviation_mm,turns,settled"
    );
    assert_eq!(lines.len(), 3, "{csv}");
    assert!(lines[1].starts_with("250,") && lines[2].starts_with("300,"));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("K_dyn sun") && err.contains("   250.0  "),
        "{err}"
    );
    let svg = std::fs::read_to_string(out.join("sweep.svg")).unwrap();
    for title in [
        "Dynamic factor",
        "Impacts per turn",
        "Largest impact speed",
        "Largest tip deviation",
    ] {
        assert!(svg.contains(title), "{title} missing");
    }
    assert!(out.join("sweep.png").is_file());
    assert!(!out.join("dynamics.json").exists());
}

#[test]
fn each_models_plot_flag_is_refused_on_the_other() {
    let out = scratch("rotor_chart_flags");
    let o = ncgear()
        .args(["dynamics", &scene(), "--format", "png", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(message(&o).contains("--png"), "{}", message(&o));
    let spur = format!(
        "{}/assets/dynamics/backlash_oscillator.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let o = ncgear()
        .args(["dynamics", &spur, "--png", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(message(&o).contains("--format png"), "{}", message(&o));
}
