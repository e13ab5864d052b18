//! `ncgear design`'s flags, their value types and the design options they ask for; the `X,Y`
//! pair parser the commands share.
use super::teeth_args::RackArgs;
use ncgear::design::hypothesis::segmented::Route;
use ncgear::design::trajectory::{DrawingOptions, DrawingUnits, Trajectory};
use ncgear::design::{DesignOptions, IdlerOffset, RefineMode};
use ncgear::math::Point;
use std::path::PathBuf;

/// Carrier positions of each mesh verification unless `--verify-steps` says otherwise.
pub(super) const DEFAULT_VERIFY_STEPS: usize = 72;

/// `--tooth-policy` values.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum ToothPolicyArg {
    /// Design for the module: the tooth count a constraint of the fit.
    Design,
    /// Scale the centre distance up to z = ⌈L/πm⌉ (tip moves radially by (s − 1)·l1).
    ScaleUp,
    /// Scale the centre distance to z = round(L/πm).
    Nearest,
    /// Scale the centre distance down to z = ⌊L/πm⌋.
    ScaleDown,
    /// Keep the centre distance; rescale the ratio amplitude so that L = zπm.
    RatioAmplitude,
    /// Keep the gears; use the non-standard module L/(zπ), z = round(L/πm).
    AdjustModule,
}

/// `--sense` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SenseArg {
    /// Either; the better-realisable law when both trace the path.
    Auto,
    /// Counter-clockwise.
    Ccw,
    /// Clockwise.
    Cw,
}

/// `--limits` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum LimitsArg {
    /// Design within the gear limits.
    On,
    /// The ratio bounds alone.
    Off,
}

/// `--idler-offset` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum IdlerOffsetArg {
    /// On the carrier line unless a whole number of teeth would move the arm: with --module,
    /// off it by the idler offset that keeps the arm; without, on it (a failed design names
    /// the off-line figure).
    Auto,
    /// Always on the carrier line (the patent's train, l1 = 2a).
    Collinear,
    /// Free in every fit, also without a module.
    Free,
}

/// `--refine` values.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum RefineArg {
    /// When the patent route misses the tolerance.
    Auto,
    /// Always.
    On,
    /// Never.
    Off,
}

/// `--route` values.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum RouteArg {
    /// Front half exact.
    Ac,
    /// Back half exact.
    Bd,
}

/// Parses the point `X,Y` (mm).
pub fn parse_point(s: &str) -> Result<Point, String> {
    parse_pair(s).map(Point::from)
}

/// Parses `X,Y`.
pub fn parse_pair(s: &str) -> Result<[f64; 2], String> {
    let v: Vec<&str> = s.split(',').map(str::trim).collect();
    let num = |t: &str| t.parse::<f64>().ok().filter(|x| x.is_finite());
    match v.as_slice() {
        [a, b] => match (num(a), num(b)) {
            (Some(x), Some(y)) => Ok([x, y]),
            _ => Err(format!("`{s}`: expected two finite numbers `X,Y`")),
        },
        _ => Err(format!(
            "`{s}`: expected two numbers separated by a comma, e.g. `0,0`"
        )),
    }
}

/// How to read a DXF or SVG trajectory drawing (docs/drawings.md); no effect on CSV or JSON.
#[derive(Debug, Clone, clap::Args)]
pub struct DrawingArgs {
    /// DXF drawing: the layer whose closed loop is the target (needed when the drawing has
    /// several loops).
    #[arg(long, value_name = "NAME")]
    pub layer: Option<String>,
    /// SVG drawing: the id of the path (or of a group holding it) that is the target.
    #[arg(long, value_name = "ID")]
    pub id: Option<String>,
    /// Units of the drawing's coordinates, mm|cm|m|in|px (default: the file's own; needed for
    /// a drawing without units, overrides the file's).
    #[arg(long, value_parser = parse_units)]
    pub units: Option<DrawingUnits>,
}

impl DrawingArgs {
    /// The reader's options.
    pub fn options(&self) -> DrawingOptions {
        DrawingOptions::default()
            .with_layer(self.layer.clone())
            .with_id(self.id.clone())
            .with_units(self.units)
    }

    /// Reads the trajectory file `path` with these options; a bad file is an input error
    /// (exit 2).
    pub fn read(&self, path: &std::path::Path) -> Result<Trajectory, super::Failure> {
        Trajectory::from_path_with(path, &self.options())
            .map_err(|e| super::input_error(miette::miette!("{e}")))
    }
}

fn parse_units(s: &str) -> Result<DrawingUnits, String> {
    s.parse()
}

/// The gear limits and the idler layout a design is made within (`ncgear design` and
/// `ncgear synthesize`).
#[derive(Debug, Clone, clap::Args)]
pub struct GearArgs {
    /// Gear limits as constraints of the design: on (default) keeps every pitch curve within
    /// --max-pressure-angle and --min-concave-radius and the sun ratio within its bounds (`ncgear design --ratio-bounds`); off
    /// keeps only the ratio bounds (research: the closest path whatever the gears; C9 and C10
    /// are still checked).
    #[arg(long, value_enum, default_value = "on")]
    pub limits: LimitsArg,
    /// Largest effective pressure angle α + max|atan(r_θ/r)| of every pitch curve, degrees.
    #[arg(long, default_value_t = 45.0)]
    pub max_pressure_angle: f64,
    /// Smallest concave radius of curvature of a pitch curve, mm (default: 12.5·--module, a
    /// 25-tooth shaper cutter's pitch radius; 10 mm without a module).
    #[arg(long)]
    pub min_concave_radius: Option<f64>,
    /// Smallest convex radius of curvature of a pitch curve, mm: the undercut limit (default:
    /// 7·--module, a 14-tooth gear's pitch radius; none without a module).
    #[arg(long)]
    pub min_convex_radius: Option<f64>,
    /// Convex pitch curves only (cut by a rack): the same as an infinite --min-concave-radius.
    #[arg(long, conflicts_with = "min_concave_radius")]
    pub convexity: bool,
    /// Where the intermediate axis may sit: auto (default) keeps it on the carrier line OA and,
    /// designing for a module, turns it off the line where a whole number of teeth would
    /// otherwise move the tip (l1 = 2a·cos ε keeps the arm at the larger centre distance);
    /// collinear never does; free lets every fit turn it (within 30°).
    #[arg(long, value_enum, default_value = "auto")]
    pub idler_offset: IdlerOffsetArg,
}

impl GearArgs {
    /// `opts` with these limits and this idler layout.
    pub fn apply(&self, opts: DesignOptions) -> DesignOptions {
        opts.with_limits(self.limits == LimitsArg::On)
            .with_max_pressure_angle_rad(self.max_pressure_angle.to_radians())
            .with_min_concave_radius_mm(self.min_concave_radius_mm())
            .with_min_convex_radius_mm(self.min_convex_radius)
            .with_idler_offset(match self.idler_offset {
                IdlerOffsetArg::Auto => IdlerOffset::Auto,
                IdlerOffsetArg::Collinear => IdlerOffset::Collinear,
                IdlerOffsetArg::Free => IdlerOffset::Free,
            })
    }

    /// The concave-radius limit asked for, mm (`--convexity`: infinite).
    pub fn min_concave_radius_mm(&self) -> Option<f64> {
        if self.convexity {
            Some(f64::INFINITY)
        } else {
            self.min_concave_radius
        }
    }
}

/// Arguments of `ncgear design`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Trajectory file: CSV (x,y in mm, optional header, `#` comments) or JSON
    /// (`{"units": "mm", "points": [[x, y], ...]}`), points in travel order; or a DXF or SVG
    /// drawing of the loop (docs/drawings.md).
    pub trajectory: PathBuf,
    /// How to read a DXF or SVG drawing.
    #[command(flatten)]
    pub drawing: DrawingArgs,
    /// Output directory (design.json, sun/intermediate/planet.csv, design.svg, ratio.svg, traced.csv;
    /// design.png with --png).
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Carrier axis O as `X,Y` in mm.
    #[arg(long, value_parser = parse_point, default_value = "0,0", allow_hyphen_values = true)]
    pub center: Point,
    /// Fixed Fourier order K (default: adaptive 4…40 until --tol-mm is met).
    #[arg(long)]
    pub order: Option<usize>,
    /// Carrier sense: auto (the sense whose law the train realises best when both trace the
    /// path), ccw or cw.
    #[arg(long, value_enum, default_value = "auto")]
    pub sense: SenseArg,
    /// Target max tip deviation, mm.
    #[arg(long, default_value_t = DesignOptions::default().tol_mm)]
    pub tol_mm: f64,
    /// Refinement: auto (the fit to the points when the chain's result misses 0.2·--tol-mm, leaves the ratio bounds or comes from noisy points), on (docs/math/chain.md §8.3 tip-motion fit, then the fit to the points), off (the patent route only).
    #[arg(long, value_enum, default_value = "auto")]
    pub refine: RefineArg,
    /// Fourier order of the refinement when --order is not given.
    #[arg(long, default_value_t = DesignOptions::default().refine_order)]
    pub refine_order: usize,
    /// Hypothesis harmonic `A,PHI_DEG` of F′₀ = 1 + Σ A_n sin(2n·u + φ_n); repeat for n = 1, 2, …
    #[arg(long = "harmonic", value_parser = parse_pair, allow_hyphen_values = true)]
    pub harmonics: Vec<[f64; 2]>,
    /// Patent route: ac (front exact) or bd (back exact).
    #[arg(long, value_enum, default_value = "ac")]
    pub route: RouteArg,
    /// Mirror weight w1 of the patent iteration.
    #[arg(long, default_value_t = 0.5)]
    pub w1: f64,
    /// Iteration cap of the patent iteration.
    #[arg(long, default_value_t = 20)]
    pub k_max: usize,
    /// Uniform carrier-angle grid N for ψ3 (FFT size).
    #[arg(long, default_value_t = 1024)]
    pub grid: usize,
    /// Dense samples of the trajectory interpolant.
    #[arg(long, default_value_t = 20_000)]
    pub dense: usize,
    /// Samples per pitch curve in the outputs (≥ 720).
    #[arg(long, default_value_t = DesignOptions::default().samples)]
    pub samples: usize,
    /// Admissible sun ratio range `MIN,MAX`.
    #[arg(long, value_parser = parse_pair, default_value = "0.3,3.3")]
    pub ratio_bounds: [f64; 2],
    /// Keep the chain's result: skip the final fit of every parameter to the points.
    #[arg(long)]
    pub no_fit: bool,
    /// Gear limits and the idler layout.
    #[command(flatten)]
    pub gears: GearArgs,
    /// Smooth a measured or noisy trajectory to this many Fourier harmonics before the inversion.
    #[arg(long)]
    pub smooth: Option<usize>,
    /// Also write design.png, a raster copy of the design.svg preview.
    #[arg(long)]
    pub png: bool,
    /// Print the report (design.json) to stdout instead of the summary.
    #[arg(long)]
    pub json: bool,
    /// Exit 0 even when a check or a mesh verification fails (its report still says so, in
    /// `verdict`); without it such a run writes its files and exits with code 3.
    #[arg(long)]
    pub accept_failed: bool,
    /// When the design fails its verification, design its nearest alternative too (the other
    /// idler layout, else a pressure-angle limit 5° looser, else the next smaller module) and
    /// name it with its figure: one more design, about as long as this one. Without it a failed
    /// design names the alternatives that apply, not designed.
    #[arg(long)]
    pub alternatives: bool,
    /// Module in mm: put rack-generated teeth on the three gears, verify both meshes and write
    /// the CAD files under OUT/teeth/ (the `teeth` block of design.json). `auto` with --loads:
    /// the smallest standard module whose teeth carry the scene's loads (the `sizing` table).
    #[arg(long, help_heading = "Teeth", value_parser = parse_module)]
    pub module: Option<ModuleArg>,
    /// Loads scene for --module auto (a `ncgear loads` scene without `design`): the speed, arms,
    /// masses, needle load, material and safety targets the module is sized for.
    #[arg(long, help_heading = "Teeth")]
    pub loads: Option<std::path::PathBuf>,
    /// How the tooth count is made an integer: design (default) fits the train at the tooth
    /// counts nearest its size, the perimeter zπm a constraint of the fit (the toothed train
    /// traces what the report states); the others scale a design made without the module.
    #[arg(long, value_enum, default_value = "design", help_heading = "Teeth")]
    pub tooth_policy: ToothPolicyArg,
    /// A given tooth count (scales the centre distance to fit; overrides --tooth-policy).
    #[arg(long, requires = "module", help_heading = "Teeth")]
    pub teeth: Option<u32>,
    /// Sweep a gear no shaper cutter fits by its cut neighbours (wire EDM or printing) instead
    /// of refusing it.
    #[arg(long, requires = "module", help_heading = "Teeth")]
    pub wire_edm: bool,
    /// Carrier positions of the mesh verification per mesh (0 = skip).
    #[arg(long, default_value_t = DEFAULT_VERIFY_STEPS, help_heading = "Teeth")]
    pub verify_steps: usize,
    /// Rack, backlash and export options.
    #[command(flatten, next_help_heading = "Teeth")]
    pub rack: RackArgs,
}

impl Args {
    /// The design options the flags ask for.
    pub(super) fn options(&self) -> DesignOptions {
        let args = self;
        let refine = match args.refine {
            RefineArg::Auto => RefineMode::Auto,
            RefineArg::On => RefineMode::On,
            RefineArg::Off => RefineMode::Off,
        };
        let hypothesis = args
            .harmonics
            .iter()
            .map(|h| (h[0], h[1].to_radians()))
            .collect();
        let route = match args.route {
            RouteArg::Ac => Route::Ac,
            RouteArg::Bd => Route::Bd,
        };
        let sense = match args.sense {
            SenseArg::Auto => None,
            SenseArg::Ccw => Some(1),
            SenseArg::Cw => Some(-1),
        };
        let defaults = DesignOptions::default();
        let min_concave = args.gears.min_concave_radius_mm();
        let opts = DesignOptions::default()
            .with_center_mm(args.center)
            .with_order(args.order)
            .with_tol_mm(args.tol_mm)
            .with_refine(refine)
            .with_refine_order(args.refine_order)
            .with_fit(!args.no_fit)
            .with_smooth(args.smooth)
            .with_segmented(
                defaults
                    .segmented
                    .with_hypothesis(hypothesis)
                    .with_route(route)
                    .with_w1(args.w1)
                    .with_k_max(args.k_max),
            )
            .with_inverse(
                defaults
                    .inverse
                    .with_grid(args.grid)
                    .with_sense(sense)
                    .with_dense_samples(args.dense),
            )
            .with_samples(args.samples)
            .with_refine_options(defaults.refine_options.with_ratio_bounds(args.ratio_bounds))
            .with_alternatives(self.alternatives);
        let opts = args.gears.apply(opts);
        // --teeth or a scaling policy: the design is made without the module and scaled after;
        // the concave- and convex-radius limits still follow the module.
        match args.module.and_then(ModuleArg::mm) {
            Some(m)
                if args.teeth.is_none() && matches!(args.tooth_policy, ToothPolicyArg::Design) =>
            {
                opts.with_module_mm(Some(m))
            }
            Some(m) => {
                let concave =
                    min_concave.or(Some(ncgear::design::SMALLEST_CUTTER_RADIUS_MODULES * m));
                let convex = args
                    .gears
                    .min_convex_radius
                    .or(Some(ncgear::design::UNDERCUT_RADIUS_MODULES * m));
                opts.with_min_concave_radius_mm(concave)
                    .with_min_convex_radius_mm(convex)
            }
            None => opts,
        }
    }
}

/// `--module`: a module in mm, or `auto` (sized by strength, with `--loads`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ModuleArg {
    /// The module, mm.
    Mm(f64),
    /// The smallest standard module that carries the loads of `--loads`.
    Auto,
}

impl ModuleArg {
    /// The module in mm, `None` for `auto`.
    pub fn mm(self) -> Option<f64> {
        match self {
            Self::Mm(m) => Some(m),
            Self::Auto => None,
        }
    }
}

/// Parses `--module`: a number (mm) or `auto`.
fn parse_module(s: &str) -> Result<ModuleArg, String> {
    if s.trim().eq_ignore_ascii_case("auto") {
        return Ok(ModuleArg::Auto);
    }
    s.trim()
        .parse::<f64>()
        .map(ModuleArg::Mm)
        .map_err(|_| format!("`{s}`: expected a module in mm (e.g. 1.5) or `auto` (with --loads)"))
}
