//! The SVG exports render in an independent SVG engine (resvg): the document size is the
//! sheet's size in mm, and the drawn pixels lie on the outlines (1 SVG unit = 1 mm, y up in the
//! sheet, y down in SVG), not elsewhere.
use crate::assembled;
use ncgear::cad::Sheet;
use ncgear::cad::svg::to_svg_string;
use ncgear::design::train::{TrainTeethOptions, tooth_train};
use ncgear::design::trajectory::Trajectory;
use ncgear::design::{DesignOptions, design};

/// CSS pixels per mm (usvg resolves `mm` at 96 dpi).
const PX_PER_MM: f64 = 96.0 / 25.4;

/// Renders `sheet` at `scale` device pixels per CSS pixel and checks it; returns the fraction of
/// outline vertices that land on a drawn pixel.
fn render_and_check(sheet: &Sheet, margin_mm: f64, scale: f32, tag: &str) -> f64 {
    let svg = to_svg_string(sheet, margin_mm);
    let tree = resvg::usvg::Tree::from_str(&svg, &resvg::usvg::Options::default())
        .unwrap_or_else(|e| panic!("{tag}: usvg cannot parse our SVG: {e}"));
    let b = sheet.bbox_mm();
    let (w_mm, h_mm) = (b[2] - b[0] + 2.0 * margin_mm, b[3] - b[1] + 2.0 * margin_mm);
    let size = tree.size();
    // The document size is the sheet in mm (4-decimal rounding in the file).
    assert!(
        (f64::from(size.width()) - w_mm * PX_PER_MM).abs() < 1e-3 * PX_PER_MM + 1e-3,
        "{tag}: width {} px vs {w_mm} mm",
        size.width()
    );
    assert!(
        (f64::from(size.height()) - h_mm * PX_PER_MM).abs() < 1e-3 * PX_PER_MM + 1e-3,
        "{tag}: height {} px vs {h_mm} mm",
        size.height()
    );
    let (pw, ph) = (
        (size.width() * scale).ceil() as u32,
        (size.height() * scale).ceil() as u32,
    );
    let mut pix = resvg::tiny_skia::Pixmap::new(pw, ph).unwrap();
    resvg::render(
        &tree,
        resvg::tiny_skia::Transform::from_scale(scale, scale),
        &mut pix.as_mut(),
    );
    let alpha = |x: i64, y: i64| -> u8 {
        if x < 0 || y < 0 || x >= i64::from(pw) || y >= i64::from(ph) {
            return 0;
        }
        pix.pixel(x as u32, y as u32).map_or(0, |p| p.alpha())
    };
    let inked = pix.pixels().iter().filter(|p| p.alpha() > 64).count();
    let total = (pw * ph) as usize;
    assert!(
        inked > total / 1000 && inked < total / 2,
        "{tag}: {inked} of {total} pixels drawn"
    );
    // The margin band is empty (nothing is drawn outside the bounding box).
    let m = (margin_mm * PX_PER_MM * f64::from(scale) * 0.5) as i64;
    for x in 0..i64::from(pw) {
        assert_eq!(
            alpha(x, m / 2),
            0,
            "{tag}: ink in the top margin at x = {x}"
        );
    }
    // Map sheet mm → device pixels: x' = (x − x0)·k, y' = (−y − y0)·k, with the viewBox origin
    // (x0, y0) = (b[0] − margin, −(b[3] + margin)).
    let k = PX_PER_MM * f64::from(scale);
    let (x0, y0) = (b[0] - margin_mm, -(b[3] + margin_mm));
    let (mut hit, mut n) = (0usize, 0usize);
    for c in sheet
        .contours
        .iter()
        .filter(|c| c.layer.ends_with("OUTLINE"))
    {
        for p in c.points_mm.iter().step_by(7) {
            let (x, y) = ((p.x - x0) * k, (-p.y - y0) * k);
            let (xi, yi) = (x.floor() as i64, y.floor() as i64);
            let near = (-1..=1).any(|dx| (-1..=1).any(|dy| alpha(xi + dx, yi + dy) > 64));
            hit += usize::from(near);
            n += 1;
        }
    }
    assert!(n > 100, "{tag}: only {n} outline points");
    hit as f64 / n as f64
}

#[test]
fn pair_sheet_renders_at_its_size_in_mm_with_ink_on_the_outlines() {
    let d = crate::teeth::oracle_pair_unverified();
    let sheet = d.assembly_sheet();
    let f = render_and_check(&sheet, 5.0, 4.0, "pair");
    assert!(
        f > 0.99,
        "pair: only {:.1} % of outline points inked",
        100.0 * f
    );
    // A sheet rendered with the y axis NOT flipped would miss the outlines: mirror the sheet's
    // contours about a horizontal line and check that the test above would have failed.
    let mut mirrored = sheet.clone();
    let b = sheet.bbox_mm();
    for c in &mut mirrored.contours {
        for p in &mut c.points_mm {
            p.y = b[1] + b[3] - p.y + 7.3;
        }
    }
    let svg = to_svg_string(&sheet, 5.0);
    let tree = resvg::usvg::Tree::from_str(&svg, &resvg::usvg::Options::default()).unwrap();
    let scale = 4.0f32;
    let s = tree.size();
    let mut pix = resvg::tiny_skia::Pixmap::new(
        (s.width() * scale).ceil() as u32,
        (s.height() * scale).ceil() as u32,
    )
    .unwrap();
    resvg::render(
        &tree,
        resvg::tiny_skia::Transform::from_scale(scale, scale),
        &mut pix.as_mut(),
    );
    let k = PX_PER_MM * f64::from(scale);
    let (x0, y0) = (b[0] - 5.0, -(b[3] + 5.0));
    let c = mirrored
        .contours
        .iter()
        .find(|c| c.layer == "DRIVER_OUTLINE")
        .unwrap();
    let wrong = c
        .points_mm
        .iter()
        .step_by(7)
        .filter(|p| {
            let (x, y) = ((p.x - x0) * k, (-p.y - y0) * k);
            pix.pixel(x as u32, y as u32)
                .is_some_and(|q| q.alpha() > 64)
        })
        .count();
    assert!(
        (wrong as f64) < 0.2 * (c.points_mm.len() / 7) as f64,
        "the pixel test cannot tell a mirrored outline: {wrong}"
    );
}

#[test]
fn train_sheet_renders_at_its_size_in_mm_with_ink_on_the_outlines() {
    let t = Trajectory::parse_csv(
        include_str!("../data/G1_trajectory_360.csv"),
        "G1_trajectory_360.csv",
    )
    .unwrap();
    let d = design(&t, &DesignOptions::default()).unwrap();
    let train = tooth_train(assembled(&d), &{
        let mut o = TrainTeethOptions::new(2.0);
        o.toothing.verify_steps = 0;
        o
    })
    .unwrap();
    let sheet = train.sheet(0.0);
    let f = render_and_check(&sheet, 10.0, 2.0, "train");
    assert!(
        f > 0.99,
        "train: only {:.1} % of outline points inked",
        100.0 * f
    );
}
