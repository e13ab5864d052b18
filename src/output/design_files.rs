//! Files written by `ncgear design`: `design.json`, the pitch tables (CSV, mm and degrees), the
//! traced path, the mechanism preview and the ratio plot.

use super::error::{OutputError, create_dir, remove_stale, write};
use super::fixed::Fixed;
use super::mechanism_preview::{mechanism_chart, mechanism_svg};
use super::plot::{ChartLabels, Series, line_chart};
use crate::design::Design;
use crate::geometry::pitch::PitchCurve;
use crate::math::Point;
use rayon::prelude::*;
use std::f64::consts::TAU;
use std::path::{Path, PathBuf};

/// A pitch table as CSV: header `theta_deg,r_mm,x_mm,y_mm`, body frame, `n` uniform samples.
#[must_use]
pub fn pitch_csv(curve: &PitchCurve, n: usize) -> String {
    let mut s = String::with_capacity(52 * n + 32);
    s.push_str("theta_deg,r_mm,x_mm,y_mm\n");
    for (k, &r) in curve.radii_at_uniform_mm(n).iter().enumerate() {
        let th = TAU * k as f64 / n as f64;
        let (sn, cs) = th.sin_cos();
        Fixed(th.to_degrees(), 6).push_to(&mut s);
        for v in [r, r * cs, r * sn] {
            s.push(',');
            Fixed(v, 9).push_to(&mut s);
        }
        s.push('\n');
    }
    s
}

/// Which optional design files to write ([`write_design_with`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub struct DesignFiles {
    /// Also write `design.png`, a raster copy of the `design.svg` preview. Default false: the
    /// SVG is the preview; the PNG takes longer to draw and encode than the rest of the files
    /// together.
    pub png: bool,
}

/// Writes the design outputs into `dir` (created if needed): `design.json`, the three pitch
/// tables, `traced.csv`, `design.svg` and `ratio.svg`; returns the paths written. Each file is
/// written whole, `design.json` last (an earlier one removed first): an interrupted run leaves
/// no report ([`crate::files`]).
pub fn write_design(design: &Design, dir: &Path) -> Result<Vec<PathBuf>, OutputError> {
    write_design_with(design, dir, DesignFiles::default())
}

/// [`write_design`] with the optional files of `files`.
pub fn write_design_with(
    design: &Design,
    dir: &Path,
    files: DesignFiles,
) -> Result<Vec<PathBuf>, OutputError> {
    create_dir(dir)?;
    let n = design.report.gears.sun.pitch.len();
    let asm = &design.assembly;
    let target: Vec<Point> = design
        .inversion
        .points
        .iter()
        .map(|q| {
            Point::new(
                asm.center_mm.x + q.x,
                asm.center_mm.y + f64::from(asm.direction) * q.y,
            )
        })
        .collect();
    type Job<'a> = Box<dyn Fn(&Path) -> Result<(), OutputError> + Sync + 'a>;
    // The report vouches for the files beside it: an earlier run's goes first, the new one is
    // written last ([`crate::files`]).
    let report = dir.join("design.json");
    remove_stale(&report)?;
    let mut jobs: Vec<(&str, Job<'_>)> = vec![
        ("sun.csv", Box::new(|p| write(p, &pitch_csv(&asm.sun, n)))),
        (
            "intermediate.csv",
            Box::new(|p| write(p, &pitch_csv(&asm.intermediate, n))),
        ),
        (
            "planet.csv",
            Box::new(|p| write(p, &pitch_csv(&asm.planet, n))),
        ),
        (
            "traced.csv",
            Box::new(|p| {
                let mut traced = String::with_capacity(28 * design.traced_mm.len() + 16);
                traced.push_str("x_mm,y_mm\n");
                for q in &design.traced_mm {
                    Fixed(q.x, 9).push_to(&mut traced);
                    traced.push(',');
                    Fixed(q.y, 9).push_to(&mut traced);
                    traced.push('\n');
                }
                write(p, &traced)
            }),
        ),
        (
            "design.svg",
            Box::new(|p| {
                write(
                    p,
                    &mechanism_svg(&design.rebuilt, &target, &design.traced_mm, 0.0),
                )
            }),
        ),
        ("ratio.svg", Box::new(|p| ratio_plot(design, p))),
    ];
    if files.png {
        jobs.push((
            "design.png",
            Box::new(|p| mechanism_chart(&design.rebuilt, &target, &design.traced_mm, 0.0, p)),
        ));
    }
    // The files are independent: formatted and written side by side (rayon); the list keeps
    // this order, and the first error in it is returned.
    let written: Result<Vec<PathBuf>, OutputError> = jobs
        .par_iter()
        .map(|(name, job)| {
            let p = dir.join(name);
            job(&p).map(|()| p)
        })
        .collect::<Vec<_>>()
        .into_iter()
        .collect();
    let written = written?;
    let json = super::json::to_string(&design.report).map_err(|e| OutputError::Io {
        path: "design.json".into(),
        message: e.to_string(),
    })?;
    write(&report, &json)?;
    Ok(std::iter::once(report).chain(written).collect())
}

/// Plot of i21 and i31 against the sun angle / carrier angle (degrees after the reference ray).
pub fn ratio_plot(design: &Design, path: &Path) -> Result<(), OutputError> {
    let m = &design.mechanism;
    let n = 720;
    let i21: Vec<(f64, f64)> = (0..=n)
        .map(|k| {
            let t = TAU * k as f64 / n as f64;
            (t.to_degrees(), m.ratio.value(t))
        })
        .collect();
    // S(t) along the turn, each solve started from its neighbours' (i21 is periodic, so the
    // closing point takes S(0)).
    let s = m.ratio.contact_map_uniform(
        0.0,
        m.contact_shift_rad(),
        n,
        crate::geometry::mechanism::INVERSE_TOL_RAD,
    );
    let i31: Vec<(f64, f64)> = (0..=n)
        .map(|k| {
            let t = TAU * k as f64 / n as f64;
            (t.to_degrees(), m.ratio.value(t) / m.ratio.value(s[k % n]))
        })
        .collect();
    let target: Vec<(f64, f64)> = {
        let law = &design.inversion.law;
        // The sun angle t meets the intermediate gear at carrier angle t + φ_ref − ε.
        let tau = m.sun_phase_rad - m.idler_offset_rad - design.inversion.phi_h0_rad;
        (0..=n)
            .map(|k| {
                let t = TAU * k as f64 / n as f64;
                (t.to_degrees(), law.i31(t + tau))
            })
            .collect()
    };
    line_chart(
        path,
        &ChartLabels {
            title: "Gear ratios over one turn".into(),
            x: "sun angle from the design reference ray (deg)".into(),
            y: "ratio (-)".into(),
            equal_aspect: false,
        },
        &[
            Series::line("i21 (sun → intermediate)", i21),
            Series::line("i31 (design)", i31),
            Series::line("i31 (target)", target),
        ],
        (900, 500),
    )?;
    Ok(())
}
