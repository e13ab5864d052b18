//! The picture of a comparison: the design path, the registered frames coloured by the smooth
//! deviation `|d(φ_i)|` at their carrier angle — where the mechanism departs from its design,
//! the frames' noise averaged out (four bands: below 0.1, 0.3 and 1 mm, and above) — and the
//! outlier frames marked; SVG or PNG by the file's extension ([`crate::output::plot`]), mm.

use super::plot::{ChartLabels, PlotError, Series, line_chart};
use crate::compare::Comparison;

/// The deviation bands of the frames, mm (upper bounds; the last band is open).
pub const BANDS_MM: [f64; 3] = [0.1, 0.3, 1.0];

/// Writes the chart of `c` to `path` (`.svg` or `.png`).
///
/// # Errors
/// [`PlotError`] when it cannot be drawn or written.
pub fn compare_chart(c: &Comparison, path: &std::path::Path) -> Result<(), PlotError> {
    let mut design: Vec<(f64, f64)> = c.design_mm.iter().map(|p| (p.x, p.y)).collect();
    if let Some(&first) = design.first() {
        design.push(first);
    }
    let names = [
        format!("frames, |d(φ)| < {} mm", BANDS_MM[0]),
        format!("{}–{} mm", BANDS_MM[0], BANDS_MM[1]),
        format!("{}–{} mm", BANDS_MM[1], BANDS_MM[2]),
        format!("> {} mm", BANDS_MM[2]),
    ];
    let mut bands: [Vec<(f64, f64)>; 4] = Default::default();
    let mut outliers = Vec::new();
    for f in &c.frames {
        let p = (f.q_mm.x, f.q_mm.y);
        if f.outlier {
            outliers.push(p);
            continue;
        }
        let d = f.smooth_mm.norm();
        let k = BANDS_MM.iter().position(|b| d < *b).unwrap_or(3);
        bands[k].push(p);
    }
    let mut series = vec![Series::line("design path", design)];
    for (name, pts) in names.into_iter().zip(bands) {
        if !pts.is_empty() {
            series.push(Series::markers(name, pts));
        }
    }
    if !outliers.is_empty() {
        series.push(Series::markers(
            format!("{} outlier frames", outliers.len()),
            outliers,
        ));
    }
    let r = &c.report;
    let labels = ChartLabels {
        title: format!(
            "{}: deviation RMS {:.3} mm, max {:.3} mm at {:.0}°",
            r.track.file, r.deviation.rms_mm, r.deviation.max_mm, r.deviation.max_at_carrier_deg
        ),
        x: "x, mm".into(),
        y: "y, mm".into(),
        equal_aspect: true,
    };
    line_chart(path, &labels, &series, (900, 800))
}
