//! Line plots (SVG or PNG) via plotters with an embedded font, so plots work on a bare machine.
//!
//! Every module that plots calls [`line_chart`]; the font (DejaVu Sans, `assets/fonts/`) is
//! registered once per process.

use plotters::prelude::*;
use std::path::Path;
use std::sync::Once;

static FONT: Once = Once::new();

fn register_font() {
    FONT.call_once(|| {
        // The embedded font is a valid TTF, so registration cannot fail.
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            include_bytes!("../../assets/fonts/DejaVuSans.ttf"),
        );
    });
}

/// How a [`Series`] is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Style {
    /// A line through the points.
    Line,
    /// A marker (filled circle) at each point.
    Markers,
    /// Each point `(x_from, x_to)` is an interval of x, shaded over the panel's whole height
    /// (it widens the x range only).
    Bands,
}

/// One named line of a chart.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend label.
    pub name: String,
    /// `(x, y)` points in data units (a band's `(x_from, x_to)`).
    pub points: Vec<(f64, f64)>,
    /// How the points are drawn.
    pub style: Style,
}

impl Series {
    /// A line series.
    #[must_use]
    pub fn line(name: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self {
            name: name.into(),
            points,
            style: Style::Line,
        }
    }
    /// A marker (scatter) series.
    #[must_use]
    pub fn markers(name: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self {
            name: name.into(),
            points,
            style: Style::Markers,
        }
    }
    /// Shaded intervals of x, `(x_from, x_to)` in data units (either order), over the panel's
    /// whole height.
    #[must_use]
    pub fn bands(name: impl Into<String>, intervals: Vec<(f64, f64)>) -> Self {
        Self {
            name: name.into(),
            points: intervals,
            style: Style::Bands,
        }
    }
}

/// Axis labels and title of a chart.
#[derive(Debug, Clone, Default)]
pub struct ChartLabels {
    /// Chart caption.
    pub title: String,
    /// x-axis label (with unit).
    pub x: String,
    /// y-axis label (with unit).
    pub y: String,
    /// Draw x and y with the same scale (for trajectories and orbits in mm).
    pub equal_aspect: bool,
}

/// The format of a run's charts, where a command lets the user choose it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum PlotFormat {
    /// Scalable vector graphics (the default).
    Svg,
    /// Raster images.
    Png,
}

impl PlotFormat {
    /// The file extension of the format (`svg`, `png`).
    #[must_use]
    pub fn ext(self) -> &'static str {
        match self {
            Self::Svg => "svg",
            Self::Png => "png",
        }
    }
}

/// Why a plot could not be written.
#[derive(Debug, thiserror::Error)]
#[error("cannot draw plot {path}: {message}")]
pub struct PlotError {
    /// Output path.
    pub path: String,
    /// What went wrong.
    pub message: String,
}

const PALETTE: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
];

/// Writes a line chart to `path`; the format follows the extension (`.png` → PNG, else SVG).
/// Size in pixels. A non-finite point breaks a line (a gap); markers skip it.
pub fn line_chart(
    path: &Path,
    labels: &ChartLabels,
    series: &[Series],
    size_px: (u32, u32),
) -> Result<(), PlotError> {
    panels_chart(path, &[(labels.clone(), series.to_vec())], size_px)
}

/// Writes charts side by side (one panel each, left to right) to one file at `path`; the format
/// follows the extension (`.png` → PNG, else SVG). Size in pixels of the whole figure. A
/// non-finite point breaks a line (a gap); markers skip it.
pub fn panels_chart(
    path: &Path,
    panels: &[(ChartLabels, Vec<Series>)],
    size_px: (u32, u32),
) -> Result<(), PlotError> {
    register_font();
    let is_png = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    crate::files::write_whole_with(
        path,
        |tmp| {
            if is_png {
                draw(BitMapBackend::new(tmp, size_px).into_drawing_area(), panels)
            } else {
                draw(SVGBackend::new(tmp, size_px).into_drawing_area(), panels)
            }
        },
        |e| e.to_string(),
    )
    .map_err(|message| PlotError {
        path: path.display().to_string(),
        message,
    })
}

fn bounds(series: &[Series], equal: bool) -> ((f64, f64), (f64, f64)) {
    let mut xr = (f64::INFINITY, f64::NEG_INFINITY);
    let mut yr = (f64::INFINITY, f64::NEG_INFINITY);
    for s in series {
        for &(x, y) in &s.points {
            if !(x.is_finite() && y.is_finite()) {
                continue;
            }
            if s.style == Style::Bands {
                xr = (xr.0.min(x.min(y)), xr.1.max(x.max(y)));
            } else {
                xr = (xr.0.min(x), xr.1.max(x));
                yr = (yr.0.min(y), yr.1.max(y));
            }
        }
    }
    if !xr.0.is_finite() {
        return ((0.0, 1.0), (0.0, 1.0));
    }
    if !yr.0.is_finite() {
        yr = (0.0, 1.0);
    }
    let pad = |r: (f64, f64)| {
        let w = (r.1 - r.0).max(1e-12 * (1.0 + r.0.abs()));
        (r.0 - 0.05 * w, r.1 + 0.05 * w)
    };
    let (mut xr, mut yr) = (pad(xr), pad(yr));
    if equal {
        let (cx, cy) = (0.5 * (xr.0 + xr.1), 0.5 * (yr.0 + yr.1));
        let half = 0.5 * (xr.1 - xr.0).max(yr.1 - yr.0);
        xr = (cx - half, cx + half);
        yr = (cy - half, cy + half);
    }
    (xr, yr)
}

/// Fills `root` white, draws the panels side by side and presents the figure.
fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    panels: &[(ChartLabels, Vec<Series>)],
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    root.fill(&WHITE).map_err(e)?;
    let areas = root.split_evenly((1, panels.len().max(1)));
    for (area, (labels, series)) in areas.into_iter().zip(panels) {
        draw_panel(&area, labels, series)?;
    }
    root.present().map_err(e)?;
    Ok(())
}

/// One chart in `root`.
fn draw_panel<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    labels: &ChartLabels,
    series: &[Series],
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    let (xr, yr) = bounds(series, labels.equal_aspect);
    let mut chart = ChartBuilder::on(root)
        .caption(&labels.title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc(&labels.x)
        .y_desc(&labels.y)
        .label_style(("sans-serif", 13))
        .draw()
        .map_err(e)?;
    for (k, s) in series.iter().enumerate() {
        let color = PALETTE[k % PALETTE.len()];
        let pts: Vec<(f64, f64)> = s
            .points
            .iter()
            .copied()
            .filter(|(x, y)| x.is_finite() && y.is_finite())
            .collect();
        let anno = if s.style == Style::Markers {
            chart
                .draw_series(pts.iter().map(|p| Circle::new(*p, 2, color.filled())))
                .map_err(e)?
        } else if s.style == Style::Bands {
            let fill = color.mix(0.2).filled();
            let anno = chart
                .draw_series(
                    pts.iter()
                        .map(|&(a, b)| Rectangle::new([(a, yr.0), (b, yr.1)], fill)),
                )
                .map_err(e)?;
            if !s.name.is_empty() {
                anno.label(s.name.clone())
                    .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 18, y + 5)], fill));
            }
            continue;
        } else {
            // A non-finite point ends a run: each run is its own line, one legend entry.
            let runs: Vec<Vec<(f64, f64)>> = s
                .points
                .split(|(x, y)| !(x.is_finite() && y.is_finite()))
                .filter(|r| !r.is_empty())
                .map(<[(f64, f64)]>::to_vec)
                .collect();
            chart
                .draw_series(
                    runs.into_iter()
                        .map(|r| PathElement::new(r, color.stroke_width(2))),
                )
                .map_err(e)?
        };
        if !s.name.is_empty() {
            anno.label(s.name.clone()).legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2))
            });
        }
    }
    if series.iter().any(|s| !s.name.is_empty()) {
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 13))
            .draw()
            .map_err(e)?;
    }
    Ok(())
}
