//! Tooth and CAD-export options shared by `ncgear design --module` and `ncgear pair`.
use ncgear::cad::ExportError;
use ncgear::cad::dxf::DxfVersion;
use ncgear::output::SolidOptions;
use ncgear::teeth::{RackParams, TeethError, ToothingOptions};

/// DXF flavour on the command line.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum DxfFlavour {
    /// AutoCAD 2010, closed LWPOLYLINE (default).
    R2010,
    /// AutoCAD R12, POLYLINE/VERTEX, for old programs.
    R12,
}

impl From<DxfFlavour> for DxfVersion {
    fn from(f: DxfFlavour) -> Self {
        match f {
            DxfFlavour::R2010 => DxfVersion::R2010,
            DxfFlavour::R12 => DxfVersion::R12,
        }
    }
}

/// Basic rack, backlash and export options.
#[derive(Debug, Clone, clap::Args)]
pub struct RackArgs {
    /// Rack pressure angle, degrees.
    #[arg(long, default_value_t = 20.0)]
    pub pressure_angle: f64,
    /// Addendum factor ha*.
    #[arg(long, default_value_t = 1.0)]
    pub addendum: f64,
    /// Clearance factor c*.
    #[arg(long, default_value_t = 0.25)]
    pub clearance: f64,
    /// Rack tip-fillet radius factor ρf*.
    #[arg(long, default_value_t = 0.38)]
    pub fillet: f64,
    /// Circumferential backlash of each mesh on the pitch curve, mm (default 0.04·m).
    #[arg(long)]
    pub backlash: Option<f64>,
    /// Chord tolerance of the exported contours, mm (default 1e-3·m).
    #[arg(long)]
    pub chord_tol: Option<f64>,
    /// DXF version.
    #[arg(long, value_enum, default_value = "r2010")]
    pub dxf_version: DxfFlavour,
    /// Face width of the STEP solids, mm (default 10·m).
    #[arg(long)]
    pub face_width: Option<f64>,
    /// Bore diameter of the STEP solids about each rotation centre, mm (0 = none).
    #[arg(long, default_value_t = 0.0)]
    pub bore: f64,
    /// Shaper-cutter tooth count for gears whose pitch curve has concave stretches (default: the
    /// largest standard cutter that fits, 100 … 12 teeth; convex gears are rack-cut).
    #[arg(long)]
    pub cutter_teeth: Option<u32>,
    /// Refuse a gear that the rack undercuts (naming the largest module that works) instead of
    /// cutting it as the rack does and reporting the undercut.
    #[arg(long)]
    pub no_undercut: bool,
}

impl RackArgs {
    /// Face width and bore of the STEP solids.
    pub fn solids(&self) -> SolidOptions {
        SolidOptions::default()
            .with_face_width_mm(self.face_width)
            .with_bore_mm(self.bore)
    }

    /// The validated basic rack.
    /// Checks the export options before any work (face width, bore), naming the flag.
    pub fn check_exports(&self) -> Result<(), super::Failure> {
        self.solids().validate().map_err(|e| match &e {
            ExportError::InvalidOption { name, .. } => super::option_error(Some(name), &e),
            _ => super::input_error(miette::miette!("{e}")),
        })
    }

    /// The first flag given that differs from its default (`None`: all at their defaults), for
    /// refusing tooth options where no teeth are made.
    pub fn first_given(&self) -> Option<&'static str> {
        let d = <Self as clap::FromArgMatches>::from_arg_matches(
            &<Self as clap::Args>::augment_args(clap::Command::new("x")).get_matches_from(["x"]),
        )
        .ok()?;
        [
            (self.pressure_angle != d.pressure_angle, "--pressure-angle"),
            (self.addendum != d.addendum, "--addendum"),
            (self.clearance != d.clearance, "--clearance"),
            (self.fillet != d.fillet, "--fillet"),
            (self.backlash.is_some(), "--backlash"),
            (self.chord_tol.is_some(), "--chord-tol"),
            (
                !matches!(self.dxf_version, DxfFlavour::R2010),
                "--dxf-version",
            ),
            (self.face_width.is_some(), "--face-width"),
            (self.bore.to_bits() != d.bore.to_bits(), "--bore"),
            (self.cutter_teeth.is_some(), "--cutter-teeth"),
            (self.no_undercut, "--no-undercut"),
        ]
        .into_iter()
        .find_map(|(given, flag)| given.then_some(flag))
    }

    pub fn rack(&self) -> Result<RackParams, TeethError> {
        RackParams::new(
            self.pressure_angle.to_radians(),
            self.addendum,
            self.clearance,
            self.fillet,
        )
    }

    /// Writes the validated rack and the given overrides (backlash, chord tolerance, mm) into
    /// the toothing options of a toothed design.
    pub fn apply_to(&self, toothing: &mut ToothingOptions) -> Result<(), TeethError> {
        toothing.rack = self.rack()?;
        if let Some(b) = self.backlash {
            toothing.backlash_mm = b;
        }
        if let Some(c) = self.chord_tol {
            toothing.chord_tol_mm = c;
        }
        toothing.cutter_teeth = self.cutter_teeth;
        toothing.refuse_undercut = self.no_undercut;
        Ok(())
    }
}

/// A STEP export failure: a bad `--face-width`/`--bore` (or outline) is an input error (exit 2),
/// a file that cannot be written a runtime one.
pub fn step_failure(e: &ExportError) -> super::Failure {
    match e {
        ExportError::Io { .. } => super::runtime_error(miette::miette!("{e}")),
        _ => super::input_error(miette::miette!("{e}")),
    }
}

/// The undercut warning of one gear for the console (`None` without undercut): the tool that
/// cuts it (the rack's numbers from its report; a shaper cutter's flank count from `process`),
/// and what it costs. A swept gear has no cutter to undercut it.
pub fn undercut_line(
    name: &str,
    u: &ncgear::teeth::UndercutReport,
    process: Option<&ncgear::teeth::process::GearProcess>,
) -> Option<String> {
    use ncgear::teeth::process::Process;
    match process.map(|p| (p.process, p)) {
        Some((Process::Shaper, p)) => (p.undercut_flanks > 0).then(|| {
            format!(
                "warning: {name}: the shaper cutter (z_c = {}) undercuts {} flank(s), cut as it \
                 cuts them (--no-undercut refuses instead)",
                p.cutter_teeth.unwrap_or(0),
                p.undercut_flanks
            )
        }),
        Some((Process::WireEdm, _)) => None,
        _ => (u.undercut_count > 0).then(|| {
            let root = u.min_root_thickness_mm.map_or(String::new(), |r| {
                format!(", thinnest tooth root {r:.3} mm")
            });
            format!(
                "warning: {name}: the rack undercuts {} flank(s), cut as the rack cuts them: \
                 deepest {:.4} mm below the cusp, contact ratio lost up to {:.3}{root} \
                 (--no-undercut refuses instead)",
                u.undercut_count, u.max_undercut_mm, u.max_contact_ratio_loss,
            )
        }),
    }
}

/// The tip changes of a cut gear for its console line: teeth lowered where a small cutter does
/// not reach, and the tip relief against the mates' fillets.
fn tip_notes(p: &ncgear::teeth::process::GearProcess) -> String {
    let mut s = String::new();
    if p.reach_topped_teeth > 0 {
        s += &format!(
            ", {} tips lowered to where the cutter's involute reaches",
            p.reach_topped_teeth
        );
    }
    if p.relieved_teeth > 0 {
        s += &format!(
            ", tip relief on {} teeth (up to {:.4} mm) to clear the mates' fillets",
            p.relieved_teeth, p.max_tip_relief_mm
        );
    }
    s
}

/// One line on how a gear is cut, for the console summaries.
pub fn process_line(p: &ncgear::teeth::process::GearProcess) -> String {
    match (p.cutter_teeth, p.cutter_pitch_radius_mm) {
        (Some(zc), Some(r0)) => format!(
            "shaper cutter z_c = {zc} (pitch radius {r0:.2} mm < tightest concave radius {:.2} mm; \
             tried {:?}), undercut flanks {}, narrowest tip {:.3} mm{}",
            p.min_concave_rho_mm.unwrap_or(f64::NAN),
            p.tried_cutter_teeth,
            p.undercut_flanks,
            p.min_tip_width_mm.unwrap_or(f64::NAN),
            tip_notes(p)
        ),
        _ if p.process == ncgear::teeth::process::Process::WireEdm => format!(
            "wire EDM / printing: no cutter fits the tightest concave radius {:.2} mm; flanks swept \
             by the mating gear (experimental: not yet conjugate on strongly non-circular pairs, \
             see the mesh line), narrowest tip {:.3} mm",
            p.min_concave_rho_mm.unwrap_or(f64::NAN),
            p.min_tip_width_mm.unwrap_or(f64::NAN)
        ),
        _ => format!(
            "rack/hob (convex), undercut flanks {}{}",
            p.undercut_flanks,
            tip_notes(p)
        ),
    }
}

/// The bad-input failure of a tooth option the library refused: the error, and the flag that
/// sets the option when there is one (exit 2).
pub fn option_failure(e: ncgear::teeth::TeethError) -> super::Failure {
    match &e {
        ncgear::teeth::TeethError::Bounds(b) => super::option_error(Some(&b.quantity), &e),
        ncgear::teeth::TeethError::InvalidParameter { name, .. } => {
            super::option_error(Some(name), &e)
        }
        _ => super::input_error(miette::miette!("{e}")),
    }
}
