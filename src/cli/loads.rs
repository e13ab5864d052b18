//! `ncgear loads SCENE --out DIR`: the rotor's loads over a turn, the tooth stresses, their
//! safety factors and life ([`ncgear::loads`]).
use super::{CliResult, input_error, print_json, runtime_error, verdict_outcome};
use ncgear::loads::{LoadsError, LoadsReport, run_scene};
use std::path::PathBuf;

/// Arguments of `ncgear loads`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Scene file (.toml or .json): the design it names and how the machine runs it.
    pub scene: PathBuf,
    /// Output directory: loads.json (last), loads.csv, torque.svg, forces.svg, stress.svg.
    #[arg(long, default_value = "out/loads")]
    pub out: PathBuf,
    /// Print the report as JSON on stdout.
    #[arg(long)]
    pub json: bool,
    /// Also write the charts as PNG.
    #[arg(long)]
    pub png: bool,
    /// Exit 0 although a safety factor misses its target (the report says which).
    #[arg(long)]
    pub accept_failed: bool,
}

/// The exit class of a loads error: a mesh that locks is the design's failure at run time;
/// everything else is bad input, refused before any work.
pub fn loads_failure(e: LoadsError) -> super::Failure {
    match e {
        LoadsError::SelfLocking { .. } => runtime_error(miette::miette!("{e}")),
        _ => input_error(miette::miette!("{e}")),
    }
}

/// Runs `ncgear loads`.
pub fn run(args: Args) -> CliResult {
    let report = run_scene(&args.scene).map_err(loads_failure)?;
    let files = ncgear::output::write_loads(&report, &args.out, args.png)
        .map_err(|e| runtime_error(miette::miette!("{e}")))?;
    if args.json {
        print_json(&report)?;
    } else {
        print_summary(&args, &report, files.len());
    }
    verdict_outcome(&report.verdict, args.accept_failed)
}

/// The console summary: torques, power, reversals, peak mesh forces, safety factors and life.
pub fn print_summary(args: &Args, r: &LoadsReport, files: usize) {
    let s = &r.summary;
    let o = &r.operation;
    println!(
        "{}: {} arm(s) at {} r/min over one turn ({} samples)",
        args.scene.display(),
        o.arms,
        o.carrier_rpm,
        o.samples
    );
    println!(
        "  carrier torque: peak {:.3} N·m, rms {:.3} N·m, mean {:.3} N·m → mean power {:.1} W",
        s.carrier_torque_peak_nm, s.carrier_torque_rms_nm, s.carrier_torque_mean_nm, s.mean_power_w
    );
    println!(
        "  planet mesh torque: peak {:.3} N·m; reversals (teeth cross the backlash) at {}",
        s.planet_mesh_torque_peak_nm,
        if s.reversals_deg.is_empty() {
            "none".to_string()
        } else {
            s.reversals_deg
                .iter()
                .map(|x| format!("{x:.1}°"))
                .collect::<Vec<_>>()
                .join(", ")
        }
    );
    let peak = |v: &[f64]| v.iter().copied().fold(0.0, f64::max);
    println!(
        "  mesh normal force: peak {:.1} N (sun–intermediate), {:.1} N (intermediate–planet); frame force peak {:.1} N",
        peak(&r.meshes.sun_intermediate.normal_force_n),
        peak(&r.meshes.intermediate_planet.normal_force_n),
        s.frame_force_peak_n
    );
    if let Some(rt) = &r.rating {
        println!(
            "  {} rating ({}), m = {} mm, b = {} mm:",
            match rt.options.factors.mode {
                ncgear::loads::rating::FactorMode::Iso => "ISO 6336",
                ncgear::loads::rating::FactorMode::Nominal => "nominal",
            },
            rt.options.material.name,
            rt.module_mm,
            rt.face_width_mm
        );
        let (h, f) = (&rt.min_s_h, &rt.min_s_f);
        println!(
            "    S_H min {:.3} (target {}) at {:.1}°, {} ({} tooth {})",
            h.value, rt.options.s_h_min, h.travel_deg, h.mesh, h.gear, h.tooth
        );
        println!(
            "    S_F min {:.3} (target {}) at {:.1}°, {} root, tooth {} ({})",
            f.value, rt.options.s_f_min, f.travel_deg, f.gear, f.tooth, f.mesh
        );
        println!(
            "    life {} ({})",
            if rt.life_h.is_finite() {
                format!("{:.3e} h", rt.life_h)
            } else {
                "unlimited".into()
            },
            rt.life_limited_by
        );
        for n in &rt.notes {
            println!("    note: {n}");
        }
    }
    println!("  wrote {files} files into {}", args.out.display());
}
