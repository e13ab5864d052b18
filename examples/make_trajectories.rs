//! Regenerates the bundled example trajectories under `assets/trajectories/` from the forward
//! model (docs/math/chain.md §2, §11.1):
//!
//! - `g1_ellipse.csv`: the G1 mechanism (focus-pivoted ellipses, a = 45, l3 = 170 mm,
//!   β_init = −70°), 360 points, one per carrier degree — exactly traceable.
//! - `designer_kidney.csv`: G1 with the needle law perturbed by 0.03·sin(3t + 0.5) rad, as a
//!   designer would draw it: no train traces it exactly (best achievable ≈ 3.8 mm, docs/math/chain.md §6.4).
//! - `asymmetric_cw.json`: an asymmetric sun (docs/math/chain.md §11.4 (G4) family), clockwise carrier, carrier axis at
//!   (250, 400) mm, 720 points, JSON format — exactly traceable.
//!
//! Run: `cargo run --release --example make_trajectories`
use ncgear::geometry::mechanism::Mechanism;
use std::f64::consts::TAU;
use std::fmt::Write as _;

fn g1() -> Mechanism {
    ncgear::geometry::golden::g1_mechanism()
}

fn main() -> std::io::Result<()> {
    let dir = std::path::Path::new("assets/trajectories");
    std::fs::create_dir_all(dir)?;
    let m = g1();
    let mut s =
        String::from("x_mm,y_mm (static needle-tip trajectory, carrier angle k deg, CCW)\n");
    for k in 0..360 {
        let p = m.tip((k as f64).to_radians());
        let _ = writeln!(s, "{:.18e},{:.18e}", p.x, p.y);
    }
    std::fs::write(dir.join("g1_ellipse.csv"), s)?;

    let mut s = String::from(
        "# designer-style kidney: G1 with psi3 += 0.03 sin(3t + 0.5); mm\nx_mm,y_mm\n",
    );
    for k in 0..360 {
        let t = (k as f64).to_radians();
        let beta = (-70f64).to_radians() + t - (m.psi3(t) + 0.03 * (3.0 * t + 0.5).sin());
        let _ = writeln!(
            s,
            "{:.12},{:.12}",
            90.0 * t.cos() + 170.0 * beta.cos(),
            90.0 * t.sin() + 170.0 * beta.sin()
        );
    }
    std::fs::write(dir.join("designer_kidney.csv"), s)?;

    // G4-type asymmetric sun, mirrored (clockwise carrier), offset centre.
    let ratio = ncgear::geometry::golden::g4_ratio();
    let m4 = Mechanism {
        a_mm: 42.0,
        l3_mm: 165.0,
        ratio,
        sun_phase_rad: 0.4,
        needle_angle_rad: -1.2,
        idler_offset_rad: 0.0,
    };
    let c = [250.0, 400.0];
    let pts: Vec<String> = (0..720)
        .map(|k| {
            let p = m4.tip(TAU * k as f64 / 720.0);
            format!("[{:.12}, {:.12}]", c[0] + p.x, c[1] - p.y)
        })
        .collect();
    std::fs::write(
        dir.join("asymmetric_cw.json"),
        format!(
            "{{\"units\": \"mm\", \"points\": [\n{}\n]}}\n",
            pts.join(",\n")
        ),
    )?;
    Ok(())
}
