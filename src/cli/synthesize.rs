//! `ncgear synthesize SPEC.toml --out DIR`: key poses or target bands → mechanism and gears
//! ([`ncgear::synthesis`]).
use super::design_args::GearArgs;
use super::{CliResult, input_error, print_json, runtime_error};
use ncgear::design::DesignOptions;
use ncgear::synthesis::{Spec, Synthesis, SynthesisError, SynthesisReport, synthesize};
use std::path::PathBuf;

/// Arguments of `ncgear synthesize`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Spec file (TOML or JSON): `[machine]`, `[[pose]]` (x_mm, y_mm, needle_deg, kind), `[targets]`.
    pub spec: PathBuf,
    /// Output directory: the design's files (design.json, pitch curves, previews) and synthesis.json.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Print synthesis.json to stdout instead of the summary.
    #[arg(long)]
    pub json: bool,
    /// Exit 0 even when a pose is missed (an exact one by more than 0.05 mm / 0.05°, an
    /// approximate one by more than its tolerances), a target band is not met or the design fails
    /// a check.
    #[arg(long)]
    pub accept_failed: bool,
    /// Design each candidate's gears for this module, mm, as `ncgear design --module` does (the
    /// tooth count a constraint of the fit; the teeth are then `ncgear teeth` of the design).
    #[arg(long)]
    pub module: Option<f64>,
    /// Gear limits and the idler layout of each candidate's gears.
    #[command(flatten)]
    pub gears: GearArgs,
}

/// Largest pose error that counts as passed, mm and degrees.
const POSE_PASS: (f64, f64) = (0.05, 0.05);

/// Runs `ncgear synthesize`.
pub fn run(args: Args) -> CliResult {
    let started = std::time::Instant::now();
    let file = args.spec.display().to_string();
    let spec: Spec =
        ncgear::config::load(&args.spec).map_err(|e| input_error(miette::miette!("{e}")))?;
    let opts = args
        .gears
        .apply(DesignOptions::default())
        .with_module_mm(args.module);
    opts.validate()
        .map_err(|e| input_error(miette::miette!("{e}")))?;
    let pb = super::spinner("synthesising");
    let s = synthesize(&spec, &opts);
    pb.finish_and_clear();
    let s = s.map_err(|e| match e {
        SynthesisError::NoDesign(_) => runtime_error(miette::miette!("{file}: {e}")),
        _ => input_error(miette::miette!("{file}: {e}")),
    })?;
    let written = ncgear::output::write_synthesis(&s, &args.out)
        .map_err(|e| runtime_error(miette::miette!("{e}")))?;
    let r = &s.report;
    let missed = missed_poses(r, &spec);
    if args.json {
        print_json(r)?;
    } else {
        print_summary(&file, &s);
        println!(
            "  {:.1} ms; wrote {}",
            super::ms_since(started),
            written
                .iter()
                .map(|p| p.display().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    if !args.accept_failed {
        check_met(r, &missed)?;
    }
    super::verdict_outcome(&s.design.report.verdict, args.accept_failed, &[])
}

/// The poses missed: an exact pose passes within [`POSE_PASS`], an approximate one within its
/// own tolerances.
fn missed_poses(r: &SynthesisReport, spec: &Spec) -> Vec<usize> {
    r.poses
        .iter()
        .zip(&spec.poses)
        .enumerate()
        .filter(|(_, (p, s))| {
            let (mm, deg) = if s.approximate() {
                (s.position_tolerance_mm(), s.direction_tolerance_deg())
            } else {
                POSE_PASS
            };
            p.error_mm > mm || p.error_deg.abs() > deg
        })
        .map(|(k, _)| k)
        .collect()
}

/// The summary on stdout: the chosen train, each pose's error, each target band, the binding
/// search-box limits and the gears' checks.
fn print_summary(file: &str, s: &Synthesis) {
    let r = &s.report;
    let c = &r.candidates[r.chosen];
    if r.dyad_kind == "targets" {
        println!(
            "{file}: target bands only, {} candidate train(s), carrier {}",
            r.candidates.len(),
            r.carrier.to_uppercase()
        );
    } else {
        println!(
            "{file}: {} poses, {} arm(s) ({}), carrier {}",
            r.poses.len(),
            r.dyads.len(),
            r.dyad_kind,
            r.carrier.to_uppercase()
        );
    }
    println!(
        "  chosen: O = ({:.6}, {:.6}) mm, l1 = {:.6} mm, l3 = {:.6} mm (candidate {} of {})",
        c.dyad.center_mm.x,
        c.dyad.center_mm.y,
        c.dyad.l1_mm,
        c.dyad.l3_mm,
        r.chosen + 1,
        r.candidates.len()
    );
    for (k, p) in r.poses.iter().enumerate() {
        println!(
            "  pose {k}: at carrier {:.3}°, {:.6} mm and {:.6}° from the designed gears' tip and needle",
            p.carrier_deg, p.error_mm, p.error_deg
        );
    }
    for t in &r.targets {
        println!(
            "  {}: {:.3} in [{}, {}]: {}",
            t.index,
            t.value,
            t.band[0],
            t.band[1],
            if t.margin >= 0.0 {
                format!("met, margin {:.3}", t.margin)
            } else {
                format!("MISSED by {:.3}", -t.margin)
            }
        );
    }
    for b in r.binding.iter().filter(|b| b.starts_with("search box")) {
        println!("  {b}");
    }
    let d = &s.design.report;
    println!(
        "  gears: pressure angle {:.2}°, round trip {:.4} mm, checks {}",
        d.limits.pressure_angle_deg,
        d.roundtrip.max_deviation_mm,
        if d.verdict.passed { "pass" } else { "FAILED" }
    );
}

/// Fails when a target band is not met or a pose (`missed`) is missed.
fn check_met(r: &SynthesisReport, missed: &[usize]) -> CliResult {
    let bands_missed: Vec<&str> = r
        .targets
        .iter()
        .filter(|t| t.margin < 0.0)
        .map(|t| t.index.as_str())
        .collect();
    if !bands_missed.is_empty() {
        return Err(super::Failure::Verification(miette::miette!(
            help = "the files are written (the nearest design found); synthesis.json lists each band's margin; --accept-failed exits 0 with them",
            "target band(s) {bands_missed:?} not met"
        )));
    }
    if !missed.is_empty() {
        return Err(super::Failure::Verification(miette::miette!(
            help = "the files are written; --accept-failed exits 0 with them",
            "pose(s) {missed:?} missed by more than their tolerance ({} mm, {}° for an exact pose)",
            POSE_PASS.0,
            POSE_PASS.1
        )));
    }
    Ok(())
}
