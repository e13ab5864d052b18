//! SVG writer: `width`/`height` in mm and a viewBox in mm (1 user unit = 1 mm), one `<g>` per
//! layer (contours, centre markers, a `TEXT` layer with labels), y flipped (SVG y points down).
//! Built with the `svg` crate; coordinates are formatted here (5 decimals, mm) to keep precision.
use super::{ExportError, Sheet, io_err};
use std::fmt::Write as _;
use std::path::Path;
use svg::Document;
use svg::node::element::{Circle, Group, Polygon, Polyline, Text};

/// Inkscape namespace (layers open as Inkscape layers).
const INKSCAPE: &str = "http://www.inkscape.org/namespaces/inkscape";

/// Renders `sheet` to an SVG string with `margin_mm` around the bounding box.
#[must_use]
pub fn to_svg_string(sheet: &Sheet, margin_mm: f64) -> String {
    let b = sheet.bbox_mm();
    let (x0, y0) = (b[0] - margin_mm, -(b[3] + margin_mm));
    let (w, h) = (b[2] - b[0] + 2.0 * margin_mm, b[3] - b[1] + 2.0 * margin_mm);
    let mut doc = Document::new()
        .set("xmlns:inkscape", INKSCAPE)
        .set("width", format!("{w:.4}mm"))
        .set("height", format!("{h:.4}mm"))
        .set("viewBox", format!("{x0:.4} {y0:.4} {w:.4} {h:.4}"))
        .set("data-units", "millimetres");
    // Stroke width, mm: 0.2 % of the sheet, within [0.05, 0.5].
    let stroke = (0.002 * w.max(h)).clamp(0.05, 0.5);
    for layer in sheet.layers() {
        let mut g = Group::new()
            .set("id", layer.as_str())
            .set("inkscape:groupmode", "layer")
            .set("inkscape:label", layer.as_str())
            .set("fill", "none")
            .set("stroke", "black")
            .set("stroke-width", format!("{stroke:.3}"));
        for c in sheet.contours.iter().filter(|c| c.layer == layer) {
            let mut points = String::new();
            for p in &c.points_mm {
                let _ = write!(points, "{:.5},{:.5} ", p.x, -p.y);
            }
            g = if c.closed {
                g.add(
                    Polygon::new()
                        .set("id", c.name.as_str())
                        .set("points", points),
                )
            } else {
                g.add(
                    Polyline::new()
                        .set("id", c.name.as_str())
                        .set("points", points),
                )
            };
        }
        for m in sheet.markers.iter().filter(|m| m.layer == layer) {
            g = g.add(
                Circle::new()
                    .set("id", m.name.as_str())
                    .set("cx", format!("{:.5}", m.at_mm.x))
                    .set("cy", format!("{:.5}", -m.at_mm.y))
                    .set("r", format!("{:.3}", 2.0 * stroke)),
            );
        }
        doc = doc.add(g);
    }
    let mut text = Group::new()
        .set("id", "TEXT")
        .set("inkscape:groupmode", "layer")
        .set("inkscape:label", "TEXT")
        .set("font-family", "sans-serif")
        .set("font-size", format!("{:.2}", 4.0 * stroke.max(0.5)));
    for m in &sheet.markers {
        text = text.add(
            Text::new(m.name.as_str())
                .set("x", format!("{:.4}", m.at_mm.x + 3.0 * stroke))
                .set("y", format!("{:.4}", -m.at_mm.y - 3.0 * stroke)),
        );
    }
    doc = doc.add(text);
    format!("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n{doc}\n")
}

/// Writes the SVG file.
pub fn write_svg(sheet: &Sheet, path: &Path, margin_mm: f64) -> Result<(), ExportError> {
    sheet.validate()?;
    crate::files::write_whole(path, to_svg_string(sheet, margin_mm)).map_err(|e| io_err(path, e))
}
