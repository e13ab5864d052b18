//! SVG writer: `width`/`height` in mm and a viewBox in mm (1 user unit = 1 mm), one `<g>` per
//! layer (contours, centre markers, a `TEXT` layer with labels), y flipped (SVG y points down).
use super::{ExportError, Sheet, io_err};
use std::fmt::Write as _;
use std::path::Path;

/// Renders `sheet` to an SVG string with `margin_mm` around the bounding box.
#[must_use]
pub fn to_svg_string(sheet: &Sheet, margin_mm: f64) -> String {
    let b = sheet.bbox_mm();
    let (x0, y0) = (b[0] - margin_mm, -(b[3] + margin_mm));
    let (w, h) = (b[2] - b[0] + 2.0 * margin_mm, b[3] - b[1] + 2.0 * margin_mm);
    let mut s = String::new();
    let _ = writeln!(s, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape" width="{w:.4}mm" height="{h:.4}mm" viewBox="{x0:.4} {y0:.4} {w:.4} {h:.4}" data-units="millimetres">"#
    );
    let stroke = (0.002 * w.max(h)).clamp(0.05, 0.5);
    for layer in sheet.layers() {
        let _ = writeln!(
            s,
            r#"<g id="{layer}" inkscape:groupmode="layer" inkscape:label="{layer}" fill="none" stroke="black" stroke-width="{stroke:.3}">"#
        );
        for c in sheet.contours.iter().filter(|c| c.layer == layer) {
            let tag = if c.closed { "polygon" } else { "polyline" };
            let _ = write!(s, r#"<{tag} id="{}" points=""#, c.name);
            for p in &c.points_mm {
                let _ = write!(s, "{:.5},{:.5} ", p[0], -p[1]);
            }
            let _ = writeln!(s, r#""/>"#);
        }
        for m in sheet.markers.iter().filter(|m| m.layer == layer) {
            let _ = writeln!(
                s,
                r#"<circle id="{}" cx="{:.5}" cy="{:.5}" r="{:.3}"/>"#,
                m.name,
                m.at_mm[0],
                -m.at_mm[1],
                2.0 * stroke
            );
        }
        let _ = writeln!(s, "</g>");
    }
    let _ = writeln!(
        s,
        r#"<g id="TEXT" inkscape:groupmode="layer" inkscape:label="TEXT" font-family="sans-serif" font-size="{:.2}">"#,
        4.0 * stroke.max(0.5)
    );
    for m in &sheet.markers {
        let _ = writeln!(
            s,
            r#"<text x="{:.4}" y="{:.4}">{}</text>"#,
            m.at_mm[0] + 3.0 * stroke,
            -m.at_mm[1] - 3.0 * stroke,
            m.name
        );
    }
    let _ = writeln!(s, "</g>\n</svg>");
    s
}

/// Writes the SVG file.
pub fn write_svg(sheet: &Sheet, path: &Path, margin_mm: f64) -> Result<(), ExportError> {
    sheet.validate()?;
    std::fs::write(path, to_svg_string(sheet, margin_mm)).map_err(|e| io_err(path, e))
}
