//! `ncgear loads SCENE --out DIR`: the rotor's loads over a turn, the tooth stresses, their
//! safety factors and life ([`ncgear::loads`]); and the loads of `ncgear design --loads`: the
//! scene checked, the module sized by strength (`--module auto`), the table printed.
use super::design_args::{ModuleArg, ToothPolicyArg};
use super::{CliResult, input_error, print_json, runtime_error, verdict_outcome};
use ncgear::analysis::dynamics::rotor::rating::{forces_of_scene, run_loads_scene};
use ncgear::design::trajectory::Trajectory;
use ncgear::loads::{LoadCase, LoadsError, LoadsReport, MeshForceSource};
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
    let help = match &e {
        LoadsError::NoTeeth => Some("design with --module M: the teeth are part of design.json"),
        LoadsError::SelfLocking { .. } => Some("--max-pressure-angle sets the limit"),
        LoadsError::Field { key, .. } if key == "gears.face_width_mm" => {
            Some("\"auto\" needs the module: design with --module M")
        }
        _ => None,
    };
    let report = match help {
        Some(h) => miette::miette!(help = h, "{e}"),
        None => miette::miette!("{e}"),
    };
    match e {
        LoadsError::SelfLocking { .. } | LoadsError::Dynamics(_) => runtime_error(report),
        _ => input_error(report),
    }
}

/// Runs `ncgear loads`.
pub fn run(args: Args) -> CliResult {
    let report = run_loads_scene(&args.scene).map_err(loads_failure)?;
    let files = ncgear::output::write_loads(&report, &args.out, args.png)
        .map_err(|e| runtime_error(miette::miette!("{e}")))?;
    if args.json {
        print_json(&report)?;
    } else {
        print_summary(&args, &report, files.len());
    }
    verdict_outcome(&report.verdict, args.accept_failed, &[])
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
            if rt.life_h < 1e9 {
                format!("{:.3e} h", rt.life_h)
            } else {
                "over 10⁹ h".into()
            },
            rt.life_limited_by
        );
        for n in &rt.notes {
            println!("    note: {n}");
        }
    }
    println!("  wrote {files} files into {}", args.out.display());
}

/// A loads scene read for rating teeth: the case, the file's name, and the dynamic forces when
/// it rates on them (`rating.K_v = "dynamic"`).
pub type SizingScene = (LoadCase, String, Option<Box<MeshForceSource<'static>>>);

/// The loads scene of `--loads`, read and checked before any work: `--module auto` needs it,
/// and it needs a `[material]` to rate the teeth against.
pub fn design_scene(args: &super::design::Args) -> Result<Option<SizingScene>, super::Failure> {
    let Some(path) = &args.loads else {
        if args.module == Some(ModuleArg::Auto) {
            return Err(input_error(miette::miette!(
                help = "give the loads the gears must carry: --loads SCENE.toml (docs/loads.md)",
                "--module auto sizes the module by strength, and no --loads scene is given"
            )));
        }
        return Ok(None);
    };
    if args.module.is_none() {
        return Err(input_error(miette::miette!(
            help = "--module auto sizes the module for the scene; --module M rates module M",
            "--loads rates the teeth, and no teeth are made without --module"
        )));
    }
    if args.module == Some(ModuleArg::Auto)
        && (args.teeth.is_some() || !matches!(args.tooth_policy, ToothPolicyArg::Design))
    {
        return Err(input_error(miette::miette!(
            "--module auto designs each module for its own tooth count: leave out --teeth and \
             --tooth-policy"
        )));
    }
    sizing_scene(path).map(Some)
}

/// A loads scene read and checked for rating teeth (`--loads`): it needs a `[material]`; a
/// `design` it names is not read (the command makes its own).
pub fn sizing_scene(path: &std::path::Path) -> Result<SizingScene, super::Failure> {
    let file = path.display().to_string();
    let scene = ncgear::loads::Scene::from_path(path).map_err(loads_failure)?;
    let case = scene.validate(&file).map_err(loads_failure)?;
    if case.rating.is_none() {
        return Err(input_error(miette::miette!(
            help = "add [material] (preset = \"steel\", …) and [gears] with face_width_mm (a width \
                    or \"auto\") to the scene",
            "{file}: --loads rates the teeth, and the scene names no material"
        )));
    }
    if scene.design.is_some() {
        eprintln!(
            "note: {file}: its `design` is not read here (the design is the one this command makes)"
        );
    }
    let dynamics = forces_of_scene(&scene, &file).map_err(loads_failure)?;
    Ok((case, file, dynamics))
}

/// `--module auto`: the target designed and rated at each standard module in turn, its teeth
/// cut with `teeth` at each module (the command's tooth options); the design of the smallest
/// module that carries the loads (or the best one, its verdict failing), with the sizing table in
/// its report, and its teeth and loads as rated.
pub fn sized_design(
    traj: &Trajectory,
    opts: &ncgear::design::DesignOptions,
    (case, scene_file, dynamics): &SizingScene,
    teeth: &dyn Fn(
        f64,
    )
        -> Result<ncgear::design::train::TrainTeethOptions, ncgear::teeth::TeethError>,
    file: &str,
) -> Result<ncgear::loads::Kept, super::Failure> {
    let pb = super::spinner(if dynamics.is_some() {
        "sizing the module on the rotor dynamics"
    } else {
        "sizing the module"
    });
    let sized = ncgear::loads::size_module(
        traj,
        opts,
        case,
        &ncgear::loads::SizingOptions::default(),
        teeth,
        dynamics.as_deref(),
        scene_file,
    );
    pb.finish_and_clear();
    sized.map_err(loads_failure)?.into_kept().map_err(|table| {
        runtime_error(miette::miette!(
            "{file}: no standard module could be designed and rated:\n{}",
            table.markdown()
        ))
    })
}

/// The console lines of the sizing table and the loads of the design kept.
pub fn print_sizing(r: &ncgear::design::DesignReport, l: &ncgear::loads::LoadsReport) {
    if let Some(s) = &r.sizing {
        match s.chosen_module_mm {
            Some(m) => println!(
                "  module sized by strength: m = {m} mm (S_H ≥ {}, S_F ≥ {}, face width {}):",
                s.s_h_min, s.s_f_min, s.face_width
            ),
            None => println!(
                "  module sized by strength: no module meets S_H ≥ {}, S_F ≥ {}; the best is kept:",
                s.s_h_min, s.s_f_min
            ),
        }
        for line in s.markdown().lines() {
            println!("    {line}");
        }
    }
    let sm = &l.summary;
    if let (Some(h), Some(f)) = (&sm.min_s_h, &sm.min_s_f) {
        println!(
            "  loads: carrier torque peak {:.3} N·m, mean power {:.1} W; S_H {:.3} ({}), S_F {:.3} ({} root); files in loads/",
            sm.carrier_torque_peak_nm, sm.mean_power_w, h.value, h.mesh, f.value, f.gear
        );
    }
}
