//! ncgear inside a CAD pipeline, no CLI involved: needle-tip points in memory → the design chain →
//! teeth on the three gears → DXF (R2010, mm) and SVG files of each gear, and the numbers a CAD
//! script needs (arm lengths, centre distance, tooth counts, the round trip).
//!
//! ```sh
//! cargo run --release --example cad_pipeline -- out/cad
//! ```
//!
//! The points here come from the classic elliptical (G1) train; in a pipeline they would come
//! from a drawing's polyline, in mm, in travel order.

use ncgear::math::Point;
use std::error::Error;
use std::path::PathBuf;

use ncgear::cad::dxf::{DxfVersion, write_dxf};
use ncgear::cad::svg::write_svg;
use ncgear::design::train::{Gear, TrainPolicy, TrainTeethOptions};
use ncgear::geometry::golden::g1_mechanism;
use ncgear::{DesignOptions, Trajectory, design, tooth_train};

fn main() -> Result<(), Box<dyn Error>> {
    let out: PathBuf = std::env::args_os()
        .nth(1)
        .map_or_else(|| PathBuf::from("out/cad_pipeline"), PathBuf::from);
    std::fs::create_dir_all(&out)?;

    // 1. The target: 720 needle-tip points, mm, in travel order.
    let g1 = g1_mechanism();
    let points: Vec<Point> = (0..720)
        .map(|k| g1.tip(std::f64::consts::TAU * k as f64 / 720.0))
        .collect();

    // 2. The design chain: arm lengths, sun and intermediate pitch curves, checks, round trip.
    let d = design(&Trajectory::from_points(points)?, &DesignOptions::default())?;
    let r = &d.report;
    println!(
        "l1 = {:.3} mm, l3 = {:.3} mm, a = {:.3} mm, round trip {:.4} mm ({})",
        r.l1_mm, r.l3_mm, r.center_distance_mm, r.roundtrip.max_deviation_mm, r.chosen
    );

    // 3. Teeth: about module 2 mm, a 20° rack; the tooth count is made an integer by adjusting
    //    the module, so the gears and the traced path stay exactly as designed.
    let opts = TrainTeethOptions::new(2.0).with_policy(TrainPolicy::AdjustModule);
    let teeth = tooth_train(&d, &opts)?;
    let t = &teeth.report;
    println!(
        "teeth: z = {} on every gear, module {:.4} mm, centre distance {:.3} mm, round trip {:.4} mm",
        t.z, t.module_mm, t.center_distance_mm, t.roundtrip.max_deviation_mm
    );

    // 4. One DXF and one SVG per gear, in its body frame (rotation centre at the origin), mm.
    for g in Gear::ALL {
        let sheet = teeth.gear_sheet(g);
        let dxf = out.join(format!("{}.dxf", g.name()));
        let svg = out.join(format!("{}.svg", g.name()));
        write_dxf(
            &sheet,
            &dxf,
            DxfVersion::R2010,
            t.options.toothing.chord_tol_mm,
        )?;
        write_svg(&sheet, &svg, 2.0 * t.module_mm)?;
        println!("wrote {} and {}", dxf.display(), svg.display());
    }
    Ok(())
}
