//! `ncgear compare TRACK.csv --design design.json`: a filmed needle-tip track registered to the
//! design's static path and compared with it.
use super::{CliResult, input_error, print_json, runtime_error};
use ncgear::analysis::dynamics::rotor::Prepared;
use ncgear::compare::args::CompareArgs;
use ncgear::compare::{CompareError, compare_track};
use ncgear::simulate::DesignFile;
use std::path::PathBuf;

/// Arguments of `ncgear compare`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The track: CSV of time (s, ms, or frame numbers with --fps), x, y (mm, cm, m or px);
    /// plain, Tracker's or Kinovea's export.
    pub track: PathBuf,
    /// The design file the mechanism was built from (design.json).
    #[arg(long)]
    pub design: PathBuf,
    /// Output directory.
    #[arg(long, default_value = "out/compare")]
    pub out: PathBuf,
    /// The comparison's options.
    #[command(flatten)]
    pub opts: CompareArgs,
    /// A rotor dynamics scene (`[scene] model = "rotor"`) of the same design: its settled turn
    /// at the track's mean speed becomes a second reference path (backlash, elastic teeth).
    #[arg(long)]
    pub dynamics: Option<PathBuf>,
    /// Also write compare.png.
    #[arg(long)]
    pub png: bool,
    /// Print the report as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

fn input(e: impl std::fmt::Display) -> super::Failure {
    input_error(miette::miette!("{e}"))
}

/// Runs `ncgear compare`.
pub fn run(args: Args) -> CliResult {
    let (_, asm) = DesignFile::from_path(&args.design).map_err(input)?;
    let scene = args
        .dynamics
        .as_deref()
        .map(|p| Prepared::from_path(p).map_err(input))
        .transpose()?;
    let turns = scene.as_ref().map_or(0, |p| p.case.settings.max_turns);
    let pb = super::progress_bar(u64::from(turns), "turns");
    let c = compare_track(
        &args.track,
        &asm.rebuild(),
        &args.opts,
        scene.as_ref(),
        &super::bar_sink(&pb),
    )
    .map_err(|e| match e {
        CompareError::NoFit { .. } => runtime_error(miette::miette!("{e}")),
        _ => input(e),
    })?;
    pb.finish_and_clear();
    let report = ncgear::output::write_compare(&c, &args.out, args.png)
        .map_err(|e| runtime_error(miette::miette!("{e}")))?;
    if args.json {
        return print_json(&report);
    }
    let r = &report.registration;
    let d = &report.deviation;
    let f = &report.features;
    println!(
        "{}: {} frames ({} outliers) registered to {}",
        args.track.display(),
        report.track.frames,
        r.outliers,
        args.design.display()
    );
    println!(
        "  rotation {:.4}° ± {:.4}°, translation ({:.3}, {:.3}) mm, scale {:.6} mm/unit{}",
        r.rotation_deg.value,
        r.rotation_deg.se,
        r.translation_mm[0].value,
        r.translation_mm[1].value,
        r.scale_mm_per_unit.value,
        if r.scale_fitted { " (fitted)" } else { "" }
    );
    println!(
        "  carrier {:.2} rpm (mean {:.2}), frame noise σ {:.3} mm",
        r.rpm.value, r.mean_rpm, r.noise_mm
    );
    println!(
        "  deviation by carrier angle: RMS {:.3} mm, max {:.3} mm at {:.0}°, Hausdorff {:.3} mm (noise floor {:.3} mm)",
        d.rms_mm, d.max_mm, d.max_at_carrier_deg, d.hausdorff_mm, d.noise_floor_mm
    );
    println!(
        "  taking angle {:.2}° (design {:.2}°), pushing angle {:.2}° (design {:.2}°), hole width {:.2} mm (design {:.2} mm)",
        f.track.take_angle_deg,
        f.design.take_angle_deg,
        f.track.push_angle_deg,
        f.design.push_angle_deg,
        f.track.hole_width_mm,
        f.design.hole_width_mm
    );
    if let Some(d) = &report.dynamics {
        println!(
            "  against the dynamics of `{}` at {:.2} r/min ({} turns{}): deviation RMS {:.3} mm, max {:.3} mm at {:.0}° (static RMS {:.3} mm; the dynamic tip leaves the static path by up to {:.3} mm): the dynamics explain {:.0} % of the mean square",
            d.scene,
            d.carrier_rpm,
            d.turns,
            if d.settled { "" } else { ", not settled" },
            d.rms_mm,
            d.max_mm,
            d.max_at_carrier_deg,
            d.static_rms_mm,
            d.max_tip_departure_mm,
            100.0 * d.explained
        );
    }
    if let Some(s) = &report.spread {
        println!(
            "  {} turns: spread of the pushing angle {:.3}°, of the hole width {:.3} mm",
            report.turns.len(),
            s.push_angle_deg,
            s.hole_width_mm
        );
    }
    println!(
        "  wrote {} files into {}",
        report.files.len() + 1,
        args.out.display()
    );
    Ok(())
}
