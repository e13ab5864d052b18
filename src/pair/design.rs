//! Designing the toothed pair: options, scaled pitch curves with mating phases, rack-generated
//! outlines, the mesh verification, and the assembly sheet.
use super::PairError;
use crate::cad::{Contour, Marker, Sheet};
use crate::geometry::pitch::PitchCurve;
use crate::math::Point;
use crate::math::periodic::uniform_angles;
use crate::progress::Progress;
use crate::teeth::conjugate::Mate;
use crate::teeth::mate_motion::MeshMotion;
use crate::teeth::mesh::{MeshCheck, MeshReport, verify_mesh};
use crate::teeth::process::{GearProcess, swept_process};
use crate::teeth::{
    ArcFrame, GearBlank, Generated, Generation, Outline, OutlineOptions, TeethError,
    ToothingOptions, UndercutReport, generate,
};
use serde::Serialize;
use std::f64::consts::{PI, TAU};

/// Options of [`super::design_pair`]; [`PairOptions::new`] and [`Default`] fill the defaults named on
/// each field.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize, schemars::JsonSchema)]
#[non_exhaustive]
pub struct PairOptions {
    /// Driver tooth count; the driven gear gets `z·2π/Δ` (Δ the cycle advance; equal counts for a
    /// 1:1 law). `None`: from the centrode's own size rounded up to a count that the driven gear
    /// can share (centrode only). Default `None`.
    pub teeth: Option<u32>,
    /// Cycle advance Δ that a centrode's centre distance is solved for, rad (driven rotation per
    /// driver turn: 2π for equal gears, π for 1:2). Motion laws bring their own. Default 2π.
    pub centrode_advance_rad: f64,
    /// Module, basic rack, backlash, chord tolerances and verified positions (driver positions
    /// over one turn; 0 skips the verification). Default [`ToothingOptions::new`] at the module:
    /// 20° rack, backlash 0.04·m, chord 1e-3·m, verification at chord 1e-6·m over 90 steps.
    #[serde(flatten)]
    pub toothing: ToothingOptions,
    /// Samples per turn of the law and of the pitch curves. Default 4096.
    pub samples: usize,
    /// An open (incomplete) pair over the driver interval `[start, end]`, rad, with `teeth` on
    /// that interval (motion laws only; see [`SectorReport`]). Default `None`: closed gears.
    pub open_sector_rad: Option<[f64; 2]>,
}

crate::builder::with_fields!(PairOptions {
    with_teeth => teeth: Option<u32>,
    with_centrode_advance_rad => centrode_advance_rad: f64,
    with_toothing => toothing: ToothingOptions,
    with_samples => samples: usize,
    with_open_sector_rad => open_sector_rad: Option<[f64; 2]>,
});

impl PairOptions {
    /// The defaults for `teeth` and `module_mm`: 20° rack, backlash 0.04·m, 4096 samples,
    /// chord 1e-3·m, verification at chord 1e-6·m over 90 steps (every 4°).
    #[must_use]
    pub fn new(teeth: Option<u32>, module_mm: f64) -> Self {
        Self {
            teeth,
            centrode_advance_rad: TAU,
            toothing: ToothingOptions::new(module_mm),
            samples: 4096,
            open_sector_rad: None,
        }
    }
}

impl Default for PairOptions {
    /// [`PairOptions::new`]`(None, 1.0)` (a centrode law sized by its own perimeter).
    fn default() -> Self {
        Self::new(None, 1.0)
    }
}

/// The open sector of an incomplete pair.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct SectorReport {
    /// Active driver interval `[φs, φe]`, degrees (as given).
    pub drive_deg: [f64; 2],
    /// Driven rotation over the active interval, ψ(φe) − ψ(φs), degrees.
    pub driven_advance_deg: f64,
    /// Pitches on the active driver arc (arc / πm; within 0.5 of the requested teeth).
    pub active_teeth: f64,
    /// Whole teeth kept on each sector `[driver, driven]` (active teeth and padding).
    pub kept_teeth: [u32; 2],
    /// Hub radius of each gear's body beyond the sector, mm.
    pub hub_radius_mm: [f64; 2],
    /// Driver angle of the outlines' φ = 0 and of the assembly sheet (the padded start), degrees.
    pub assembly_at_deg: f64,
}

/// A designed pair.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct PairDesign {
    /// Centre distance, mm.
    pub center_distance_mm: f64,
    /// Driver tooth count.
    pub z: u32,
    /// Driven tooth count (`z` for a 1:1 law, `2z` for 1:2).
    pub z_driven: u32,
    /// Cycle advance Δ = ψ(φ + 2π) − ψ(φ), rad.
    pub advance_rad: f64,
    /// Module, mm.
    pub module_mm: f64,
    /// Driver pitch-curve perimeter, mm (= zπm; the driven one is `z_driven·π·m`).
    pub perimeter_mm: f64,
    /// Driven pitch-curve perimeter, mm (= z_driven·π·m when the driven gear closes).
    pub driven_perimeter_mm: f64,
    /// Ratio range `[min, max]` of i = dψ/dφ.
    pub ratio_range: [f64; 2],
    /// Driver outline (export tolerance).
    pub driver: Outline,
    /// Driven outline (export tolerance).
    pub driven: Outline,
    /// Undercut report of the driver.
    pub driver_undercut: UndercutReport,
    /// Undercut report of the driven gear.
    pub driven_undercut: UndercutReport,
    /// How the driver is cut (rack, or shaper with the chosen cutter).
    pub driver_process: GearProcess,
    /// How the driven gear is cut.
    pub driven_process: GearProcess,
    /// Mesh verification (if run).
    pub mesh: Option<MeshReport>,
    /// Driven rotation at φ = 0, ψ(0), rad.
    pub psi0_rad: f64,
    /// Driver pitch polyline (body frame), mm.
    pub driver_pitch_mm: Vec<Point>,
    /// Driven pitch polyline (body frame), mm.
    pub driven_pitch_mm: Vec<Point>,
    /// The open sector, when the pair is incomplete; `None` for closed gears.
    pub sector: Option<SectorReport>,
}

/// Most samples of the law per driver turn (memory and time grow linearly; 4096 is the default).
const MAX_SAMPLES: usize = 1 << 20;

/// Checks the options every pair needs before any work: the toothing
/// ([`crate::teeth::ToothingOptions::validate`]: module, backlash, chord tolerance, verification
/// steps), the tooth count ([`crate::bounds`]), the samples.
pub(super) fn validate_options(opts: &PairOptions) -> Result<(), PairError> {
    opts.toothing.validate()?;
    if let Some(z) = opts.teeth {
        crate::bounds::check_teeth("teeth", z)?;
    }
    if !(64..=MAX_SAMPLES).contains(&opts.samples) {
        return Err(PairError::InvalidParameter {
            name: "samples",
            value: opts.samples as f64,
            expected: "in 64..=1048576",
        });
    }
    Ok(())
}

/// A designed pair's mesh check, ready to run ([`super::design_pair_staged`]): the outlines at
/// the verification's chord tolerance, the motion law and the check's parameters. Running it
/// while the design's files are written hides the writing's time.
pub struct PendingMesh {
    pub(super) outlines: [Vec<Point>; 2],
    pub(super) psi: Box<dyn Fn(f64) -> f64 + Send + Sync>,
    pub(super) check: MeshCheck,
    /// Added to the report's `max_overlap_at_deg` (an open sector is checked in `t = φ − u0`),
    /// degrees.
    pub(super) at_offset_deg: f64,
}

impl PendingMesh {
    /// The check's parameters: positions, span, backlash, centre distance and module.
    #[must_use]
    pub fn check(&self) -> &MeshCheck {
        &self.check
    }

    /// Rolls the pair through the check ([`verify_mesh`]); `progress` told of each driver
    /// position.
    ///
    /// # Errors
    /// [`PairError::Mesh`]: an outline the check cannot index.
    pub fn run(&self, progress: &Progress) -> Result<MeshReport, PairError> {
        let [v1, v2] = &self.outlines;
        let mut r = verify_mesh(v1, v2, &*self.psi, &self.check, progress)?;
        r.max_overlap_at_deg += self.at_offset_deg;
        Ok(r)
    }
}

/// A closed pair's mesh cycle, for sweeping a gear no cutter makes: its motion and the number of
/// whole-outline mate positions.
pub(super) struct Cycle<'a> {
    pub(super) motion: &'a MeshMotion<'a>,
    pub(super) positions: usize,
}

impl Cycle<'_> {
    /// Gear `k` (0 driver, 1 driven), cut from `blank`, swept by its mate's `mate_outline` (body
    /// frame, mm) over this cycle, with its process (wire EDM).
    fn sweep(
        &self,
        k: usize,
        blank: &GearBlank<'_>,
        mate_outline: &[Point],
        mate_pitch: &PitchCurve,
    ) -> Result<Generated, TeethError> {
        let pose = |u: f64, set: usize| self.motion.mate_pose(k, u, set);
        let mate = [Mate {
            outline_mm: mate_outline,
            pitch: mate_pitch,
            pose: &pose,
            offsets: 2,
            positions: self.positions,
        }];
        generate(blank, Generation::Swept(&mate))
    }
}

/// The toothed gears of a pair at centre distance `a`: scaled pitch curves with their arc frames,
/// the mating phases, and the export outlines with their processes.
pub(super) struct Toothed {
    pub(super) c: [PitchCurve; 2],
    pub(super) f: [ArcFrame; 2],
    pub(super) o: [OutlineOptions; 2],
    pub(super) z: [u32; 2],
    pub(super) driver: Outline,
    pub(super) driven: Outline,
    pub(super) driver_process: GearProcess,
    pub(super) driven_process: GearProcess,
    /// The gear no cutter makes (0: driver, 1: driven), swept by its mate.
    swept: Option<usize>,
}

impl Toothed {
    /// Gear `k`'s blank (0 driver, 1 driven) with `toothing`'s rack and module.
    pub(super) fn blank(&self, k: usize, toothing: &ToothingOptions) -> GearBlank<'_> {
        GearBlank::new(
            &self.f[k],
            toothing.rack,
            self.z[k],
            toothing.module_mm,
            self.o[k],
        )
    }

    /// The pitch curves `(driver, driven)` (mm) with `z = [driver, driven]` teeth; driver tooth 0
    /// centred at the contact of φ = 0 (body angle 0), a driven space facing it (body angle
    /// π + ψ(0), `psi0_rad`); both gears generated by their process. `open_pitch_mm`: an open
    /// sector's carriers, teeth at that pitch ([`OutlineOptions::open_pitch_mm`]); `None`:
    /// `p = L/z`.
    pub(super) fn new(
        (c1, c2): (PitchCurve, PitchCurve),
        psi0_rad: f64,
        z: [u32; 2],
        open_pitch_mm: Option<f64>,
        cycle: Option<&Cycle<'_>>,
        opts: &PairOptions,
    ) -> Result<Self, PairError> {
        let t = &opts.toothing;
        let m = t.module_mm;
        let f = rayon::join(|| ArcFrame::new(&c1), || ArcFrame::new(&c2));
        let f = [f.0, f.1];
        let p = open_pitch_mm.unwrap_or(f[0].length_mm() / f64::from(z[0]));
        let th2 = (PI + psi0_rad).rem_euclid(TAU);
        let s2 = c2.arc_length_between_mm(0.0, th2, 1e-12 * f[1].length_mm());
        let mk = |phase: f64| OutlineOptions {
            phase_mm: phase,
            thin_left_mm: 0.5 * t.backlash_mm,
            thin_right_mm: 0.0,
            chord_tol_mm: t.chord_tol_mm,
            open_pitch_mm,
            refuse_undercut: t.refuse_undercut,
        };
        // An open carrier's driver teeth run back from s = 0 (its sector lies at s ≤ 0) so that
        // the remainder space falls on the closing stretch.
        let driver_phase = open_pitch_mm.map_or(0.0, |p| -f64::from(z[0] - 1) * p);
        let o = [mk(driver_phase), mk(s2 + 0.5 * p)];
        let choice = t.cutter_choice();
        let blank = |k: usize| GearBlank::new(&f[k], t.rack, z[k], m, o[k]);
        let cut = |k: usize| generate(&blank(k), Generation::Process(choice));
        let (r1, r2) = rayon::join(|| cut(0), || cut(1));
        // A gear no cutter can make is swept by its mate when the mate is cut (closed pairs).
        let no_cutter = |r: &Result<_, TeethError>| matches!(r, Err(TeethError::NoCutter { .. }));
        let sweep_gear = match cycle {
            Some(_) if no_cutter(&r1) && r2.is_ok() => Some(0),
            Some(_) if no_cutter(&r2) && r1.is_ok() => Some(1),
            _ => None,
        };
        let (r1, r2, swept) = match (sweep_gear, cycle) {
            (Some(k), Some(mm)) => {
                let (mine, other) = if k == 0 { (r1, r2) } else { (r2, r1) };
                let other = other?;
                let c = [&c1, &c2];
                let swept = match mine {
                    Err(e) => {
                        let g = mm.sweep(k, &blank(k), &other.outline.points_mm, c[1 - k])?;
                        let process = swept_process(e, g.process)?;
                        Generated { process, ..g }
                    }
                    Ok(g) => g,
                };
                let pair = if k == 0 {
                    (swept, other)
                } else {
                    (other, swept)
                };
                (pair.0, pair.1, Some(k))
            }
            _ => (r1?, r2?, None),
        };
        Ok(Self {
            c: [c1, c2],
            f,
            o,
            z,
            driver: r1.outline,
            driven: r2.outline,
            driver_process: r1.process,
            driven_process: r2.process,
            swept,
        })
    }

    /// The fine outlines of the mesh check (verification chord tolerance), built side by side,
    /// each with its gear's cutter.
    pub(super) fn fine_outlines(
        &self,
        opts: &PairOptions,
        cycle: Option<&Cycle<'_>>,
    ) -> Result<[Vec<Point>; 2], PairError> {
        let t = &opts.toothing;
        let fine_blank = |k: usize| {
            self.blank(k, t).with_opts(OutlineOptions {
                chord_tol_mm: t.verify_chord_tol_mm,
                ..self.o[k]
            })
        };
        let fine = |k: usize, p: &GearProcess| {
            generate(&fine_blank(k), Generation::AsCut(p)).map(|g| g.outline.points_mm)
        };
        if let (Some(k), Some(mm)) = (self.swept, cycle) {
            // The cut gear first, then the swept one from it.
            let procs = [&self.driver_process, &self.driven_process];
            let other = fine(1 - k, procs[1 - k])?;
            let mine = mm
                .sweep(k, &fine_blank(k), &other, &self.c[1 - k])?
                .outline
                .points_mm;
            return Ok(if k == 0 { [mine, other] } else { [other, mine] });
        }
        let (v1, v2) = rayon::join(
            || fine(0, &self.driver_process),
            || fine(1, &self.driven_process),
        );
        Ok([v1?, v2?])
    }

    /// The design report; `[ψ(0), Δ]` in rad; `ratios` are the samples of i whose range is
    /// reported.
    pub(super) fn into_design(
        self,
        [psi0_rad, advance_rad]: [f64; 2],
        a_mm: f64,
        mesh: Option<MeshReport>,
        ratios: &[f64],
        sector: Option<SectorReport>,
    ) -> PairDesign {
        let pitch_poly = |c: &PitchCurve| {
            uniform_angles(720)
                .iter()
                .map(|&t| c.point_mm(t))
                .collect::<Vec<_>>()
        };
        PairDesign {
            center_distance_mm: a_mm,
            z: self.z[0],
            z_driven: self.z[1],
            advance_rad,
            module_mm: self.driver.module_mm,
            perimeter_mm: self.f[0].length_mm(),
            driven_perimeter_mm: self.f[1].length_mm(),
            ratio_range: [
                ratios.iter().copied().fold(f64::INFINITY, f64::min),
                ratios.iter().copied().fold(0.0, f64::max),
            ],
            driver_undercut: self.driver.undercut.clone(),
            driven_undercut: self.driven.undercut.clone(),
            driver: self.driver,
            driven: self.driven,
            driver_process: self.driver_process,
            driven_process: self.driven_process,
            mesh,
            psi0_rad,
            driver_pitch_mm: pitch_poly(&self.c[0]),
            driven_pitch_mm: pitch_poly(&self.c[1]),
            sector,
        }
    }
}

impl PairDesign {
    /// The verdict of the pair's mesh verification: no interference, a finite, non-negative
    /// backlash ([`crate::verdict::mesh_failures`]; passed when not verified).
    #[must_use]
    pub fn verdict(&self) -> crate::verdict::Verdict {
        crate::verdict::Verdict::from_failures(
            self.mesh
                .as_ref()
                .map(|m| crate::verdict::mesh_failures("driver-driven", m))
                .unwrap_or_default(),
        )
    }

    /// The assembly sheet at φ = 0 (an open sector: at its padded start,
    /// [`SectorReport::assembly_at_deg`]): driver at the origin, driven at `(a, 0)` rotated by ψ(0)
    /// (driven body angle π + ψ(0) faces the driver), layers `DRIVER_OUTLINE`, `DRIVER_PITCH`,
    /// `DRIVEN_OUTLINE`, `DRIVEN_PITCH`, `CENTRES`.
    #[must_use]
    pub fn assembly_sheet(&self) -> Sheet {
        let a = self.center_distance_mm;
        let (s, c) = self.psi0_rad.sin_cos();
        let place = |v: &[Point]| {
            v.iter()
                .map(|p| Point::new(c * p.x + s * p.y + a, -s * p.x + c * p.y))
                .collect::<Vec<_>>()
        };
        let contour = |name: &str, layer: &str, pts: Vec<Point>| Contour {
            name: name.into(),
            layer: layer.into(),
            points_mm: pts,
            // An open sector's pitch curve is an arc.
            closed: self.sector.is_none() || !layer.ends_with("PITCH"),
        };
        Sheet {
            contours: vec![
                contour(
                    "driver_outline",
                    "DRIVER_OUTLINE",
                    self.driver.points_mm.clone(),
                ),
                contour("driver_pitch", "DRIVER_PITCH", self.driver_pitch_mm.clone()),
                contour(
                    "driven_outline",
                    "DRIVEN_OUTLINE",
                    place(&self.driven.points_mm),
                ),
                contour("driven_pitch", "DRIVEN_PITCH", place(&self.driven_pitch_mm)),
            ],
            markers: vec![
                Marker {
                    name: "driver_center".into(),
                    layer: "CENTRES".into(),
                    at_mm: Point::new(0.0, 0.0),
                },
                Marker {
                    name: "driven_center".into(),
                    layer: "CENTRES".into(),
                    at_mm: Point::new(a, 0.0),
                },
            ],
        }
    }
}
