//! The one way to cut a gear's teeth: [`generate`] makes the outline of a [`GearBlank`] by the
//! [`Generation`] asked for — the rack, the process the pitch curve allows, a given shaper
//! cutter, the process a gear was cut by (with or without a tip relief), or its mates' sweep —
//! and reports the process with it.
use super::conjugate::{Mate, generate_swept};
use super::outline::{Outline, generate_on};
use super::process::{
    CutterChoice, GearProcess, generate_as_relieved, generate_by_process, generate_with_cutter,
};
use super::{GearBlank, TeethError};

/// How the teeth of a [`GearBlank`] are made.
#[derive(Clone, Copy)]
#[non_exhaustive]
pub enum Generation<'a> {
    /// The envelope of the basic rack (hobbing, docs/math/teeth.md §12.3): the pitch curve must
    /// be convex along every generating range ([`TeethError::Concave`] otherwise); an undercut
    /// flank is cut as the rack cuts it, or refused naming the largest module that works
    /// ([`TeethError::Undercut`]) with [`super::OutlineOptions::refuse_undercut`].
    Rack,
    /// The process the curve allows ([`super::process`]): [`Self::Rack`] on a convex curve, a
    /// shaper cutter chosen by the [`CutterChoice`] on one with concave stretches —
    /// [`TeethError::NoCutter`] when none fits, listing why each one tried failed.
    Process(CutterChoice),
    /// The pinion-type shaper cutter with this many teeth, whatever the curve's convexity (on a
    /// circle it cuts the involute); the outline is not checked for self-intersection or
    /// secondary cutting here.
    Shaper(u32),
    /// Cut again by the process a gear was cut by (the rack, or the same shaper cutter, without
    /// choosing again and without the choice's checks: they hold for the same cutter on the same
    /// curve), e.g. at the mesh check's chord tolerance. A swept gear has no cutter:
    /// [`TeethError::Swept`].
    AsCut(&'a GearProcess),
    /// [`Self::AsCut`] with tooth `k`'s tip lowered by `tip_relief_mm[k]` along the pitch
    /// curve's normal (mm; none where the slice is shorter): the relief that keeps each tip off
    /// its mates' fillets ([`super::tip_relief`]).
    Relieved {
        /// The process the gear was cut by.
        as_cut: &'a GearProcess,
        /// Tip relief of each tooth, mm.
        tip_relief_mm: &'a [f64],
    },
    /// Without a cutter (wire EDM, printing): the blank less everything its mates (one, or two
    /// for the intermediate gear of a train) sweep through in the mesh ([`super::conjugate`]);
    /// the blank's phase and thinning are unused (the mates' positions place and thin the
    /// teeth). [`TeethError::Swept`] when the sweep consumes a tooth's tip or leaves other than
    /// `z` teeth.
    Swept(&'a [Mate<'a>]),
}

/// A generated gear: its outline and the process that made it.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Generated {
    /// One simple closed CCW outline, body frame, mm, with its undercut report.
    pub outline: Outline,
    /// The process: the rack (with its undercut flanks), the shaper cutter chosen or given (with
    /// the cutters tried), the recorded one ([`Generation::AsCut`]; with the tip relief and the
    /// narrowest tip it leaves for [`Generation::Relieved`]), or wire EDM with the narrowest tip
    /// ([`Generation::Swept`]; the cutters' rejections are the caller's to record).
    pub process: GearProcess,
}

/// The outline of `blank`'s `z` teeth of module `module_mm` made `how`, with its process.
///
/// Errors: [`TeethError::InvalidParameter`] naming the first blank value out of range
/// ([`GearBlank::validated_pitch_mm`]), then those of the [`Generation`].
///
/// ```
/// use ncgear::geometry::pitch::PitchCurve;
/// use ncgear::teeth::process::{CutterChoice, Process};
/// use ncgear::teeth::{ArcFrame, GearBlank, Generation, OutlineOptions, RackParams, generate};
/// // A circle of radius 12 mm: perimeter 24π = z·π·m with z = 24 teeth of module 1 mm.
/// let circle = PitchCurve::from_fn(720, |_| 12.0).unwrap();
/// let frame = ArcFrame::new(&circle);
/// let blank = GearBlank::new(&frame, RackParams::default(), 24, 1.0, OutlineOptions::default());
/// let rack = generate(&blank, Generation::Rack).unwrap();
/// assert_eq!(rack.process.process, Process::Rack);
/// // A convex curve takes the rack whatever the cutter choice.
/// let chosen = generate(&blank, Generation::Process(CutterChoice::Auto)).unwrap();
/// assert_eq!(chosen, rack);
/// // A shaper cutter on a circle cuts the same involute.
/// let shaped = generate(&blank, Generation::Shaper(50)).unwrap();
/// assert_eq!(shaped.process.cutter_teeth, Some(50));
/// ```
pub fn generate(blank: &GearBlank<'_>, how: Generation<'_>) -> Result<Generated, TeethError> {
    match how {
        Generation::Rack => {
            let outline = generate_on(blank)?;
            let process = GearProcess::rack(outline.undercut.undercut_count);
            Ok(Generated { outline, process })
        }
        Generation::Process(choice) => {
            let (outline, process) = generate_by_process(blank, choice)?;
            Ok(Generated { outline, process })
        }
        Generation::Shaper(cutter_teeth) => {
            let (outline, process) = generate_with_cutter(blank, cutter_teeth)?;
            Ok(Generated { outline, process })
        }
        Generation::AsCut(as_cut) => Ok(Generated {
            outline: generate_as_relieved(blank, as_cut, &[])?.0,
            process: as_cut.clone(),
        }),
        Generation::Relieved {
            as_cut,
            tip_relief_mm,
        } => {
            let (outline, min_tip_width_mm) = generate_as_relieved(blank, as_cut, tip_relief_mm)?;
            let mut process = as_cut.clone();
            process.set_relief(tip_relief_mm, min_tip_width_mm);
            Ok(Generated { outline, process })
        }
        Generation::Swept(mates) => {
            let (outline, checks) = generate_swept(blank, mates)?;
            let process = GearProcess::swept(&outline.undercut, checks.min_tip_width_mm);
            Ok(Generated { outline, process })
        }
    }
}
