//! Seeded robustness suite: 200 generated trajectories from an independent forward model
//! ([`forward`], no code shared with the chain), fed to `design()`, the traced path measured
//! against the truth with our own symmetric point-to-segment Hausdorff distance.
//!
//! Families (fixed seeds):
//! - exact (90): harmonic suns up to the ratio bounds, M in 200..3600, arc/time sampling, random
//!   start, CCW/CW, offset centre, any γ. Must design; Hausdorff ≤ 0.05 mm and the tool's own
//!   round-trip max deviation ≤ 0.05 mm.
//! - sparse (40): the same with M in 200..300.
//! - noisy (40): M in 300..1200, Gaussian noise σ in [0.005, 0.05] mm; Hausdorff to the clean
//!   truth ≤ 0.1 mm.
//! - designer (30): G1 focus-ellipse law with the needle direction perturbed by c·sin(n t + φp):
//!   not traceable; Hausdorff ≤ 1.05 × the best achievable found independently
//!   ([`designer_reference`]).
//!
//! A per-family summary goes to stderr and to `target/robust_summary.md`; all failures are
//! collected and reported together.
//!
//! Run: `cargo test --release --test it robust -- --nocapture`
use ncgear::math::Point;
pub mod forward;

use forward::{Case, Family, SunLaw, Train, generate};
use ncgear::design::trajectory::{Origin, Trajectory};
use ncgear::design::{DesignOptions, design};
use rayon::prelude::*;
use std::f64::consts::TAU;
use std::fmt::Write as _;
use std::time::Instant;

/// (family, first seed, number of cases).
const FAMILIES: [(Family, u64, usize); 4] = [
    (Family::Exact, 1000, 90),
    (Family::Sparse, 2000, 40),
    (Family::Noisy, 3000, 40),
    (Family::Designer, 4000, 30),
];

/// Acceptance bounds.
const EXACT_TOL_MM: f64 = 0.05;
const NOISY_TOL_MM: f64 = 0.1;
const DESIGNER_FACTOR: f64 = 1.05;

/// Random perturbed starts of the multi-start reference (plus the unperturbed generating one).
const FIT_RANDOM_STARTS: usize = 3;
/// Fourier order of the multi-start's starting ratio (the focus-ellipse series, truncated).
const FIT_START_ORDER: usize = 6;
/// Carrier angles sampled on a fitted mechanism's path.
const FIT_PATH_SAMPLES: usize = 2048;

// ---------------------------------------------------------------------------------------------
// Hausdorff distance between closed polylines (point-to-segment, both directions)
// ---------------------------------------------------------------------------------------------

fn seg_dist(p: Point, a: Point, b: Point) -> f64 {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (((p.x - a.x) * dx + (p.y - a.y) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p.x - a.x - t * dx).hypot(p.y - a.y - t * dy)
}

/// Segments of a closed polyline bucketed in a uniform grid.
struct SegGrid<'a> {
    pts: &'a [Point],
    cell: f64,
    x0: f64,
    y0: f64,
    nx: i64,
    ny: i64,
    cells: Vec<Vec<u32>>,
}

impl<'a> SegGrid<'a> {
    fn new(pts: &'a [Point]) -> Self {
        let n = pts.len();
        let (mut x0, mut y0, mut x1, mut y1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
        let mut len = 0.0;
        for i in 0..n {
            let (p, q) = (pts[i], pts[(i + 1) % n]);
            x0 = x0.min(p.x);
            y0 = y0.min(p.y);
            x1 = x1.max(p.x);
            y1 = y1.max(p.y);
            len += q.distance(p);
        }
        let span = (x1 - x0).max(y1 - y0).max(1e-9);
        let cell = (4.0 * len / n as f64).max(span / 512.0).max(1e-9);
        let nx = ((x1 - x0) / cell) as i64 + 1;
        let ny = ((y1 - y0) / cell) as i64 + 1;
        let mut cells = vec![Vec::new(); (nx * ny) as usize];
        for i in 0..n {
            let (p, q) = (pts[i], pts[(i + 1) % n]);
            let cx = |x: f64| (((x - x0) / cell) as i64).clamp(0, nx - 1);
            let cy = |y: f64| (((y - y0) / cell) as i64).clamp(0, ny - 1);
            for ix in cx(p.x.min(q.x))..=cx(p.x.max(q.x)) {
                for iy in cy(p.y.min(q.y))..=cy(p.y.max(q.y)) {
                    cells[(iy * nx + ix) as usize].push(i as u32);
                }
            }
        }
        Self {
            pts,
            cell,
            x0,
            y0,
            nx,
            ny,
            cells,
        }
    }

    /// Exact distance from p to the polyline.
    fn dist(&self, p: Point) -> f64 {
        let n = self.pts.len();
        let ix = ((p.x - self.x0) / self.cell).floor() as i64;
        let iy = ((p.y - self.y0) / self.cell).floor() as i64;
        let mut best = f64::INFINITY;
        let rmax = self.nx.max(self.ny) + ix.abs().max(iy.abs()) + 2;
        for r in 0..=rmax {
            for jx in (ix - r)..=(ix + r) {
                if jx < 0 || jx >= self.nx {
                    continue;
                }
                for jy in (iy - r)..=(iy + r) {
                    if jy < 0 || jy >= self.ny {
                        continue;
                    }
                    if (jx - ix).abs() != r && (jy - iy).abs() != r {
                        continue; // interior: seen in an earlier ring
                    }
                    for &s in &self.cells[(jy * self.nx + jx) as usize] {
                        let s = s as usize;
                        best = best.min(seg_dist(p, self.pts[s], self.pts[(s + 1) % n]));
                    }
                }
            }
            // every unseen segment lies in cells at ring ≥ r + 1: at least r·cell away
            if best <= r as f64 * self.cell {
                break;
            }
        }
        best
    }
}

/// Max over the vertices of `a` of the distance to the closed polyline `b`.
fn directed(a: &[Point], b: &[Point]) -> f64 {
    let g = SegGrid::new(b);
    a.iter().map(|&p| g.dist(p)).fold(0.0, f64::max)
}

/// Symmetric Hausdorff distance between two closed polylines (point-to-segment), mm.
pub fn hausdorff(a: &[Point], b: &[Point]) -> f64 {
    directed(a, b).max(directed(b, a))
}

// ---------------------------------------------------------------------------------------------
// Designer reference: the best achievable Hausdorff
// ---------------------------------------------------------------------------------------------

/// The best achievable Hausdorff of a designer case and how it was found.
#[derive(Debug, Clone)]
struct Reference {
    hausdorff_mm: f64,
    how: &'static str,
    starts_ok: usize,
    /// Wall time of the reference search, ms.
    ms: f64,
}

/// The unperturbed generating train (a realisable mechanism), traced by our model at
/// [`FIT_PATH_SAMPLES`] carrier angles: an upper bound of the best achievable.
fn generating_reference(case: &Case) -> Reference {
    let mut train: Train = case.train.clone();
    train.wobble = None;
    let trace = train.trace(4 * FIT_PATH_SAMPLES);
    let path: Vec<Point> = trace.tips()[..4 * FIT_PATH_SAMPLES]
        .iter()
        .step_by(4)
        .map(|&p| Point::from(p))
        .collect();
    Reference {
        hausdorff_mm: hausdorff(&path, &case.truth),
        how: "generating mechanism",
        starts_ok: 1,
        ms: 0.0,
    }
}

/// Multi-start reference through `ncgear::design::fit::fit_points`: the generating ellipse mechanism
/// plus [`FIT_RANDOM_STARTS`] random perturbations of it; best = min over starts of the Hausdorff
/// between the fitted mechanism's path (2048 carrier angles) and the truth. Kept in a macro so it
/// is only type-checked once invoked (the `fit` module is being written concurrently).
#[allow(unused_macros)]
macro_rules! fit_multistart_reference {
    ($case:expr) => {{
        use ncgear::design::fit::{FitOptions, fit_points};
        use ncgear::geometry::fourier::SunRatio;
        use ncgear::geometry::mechanism::Mechanism;
        use rand::rngs::ChaCha8Rng;
        use rand::{RngExt, SeedableRng};
        let case: &Case = $case;
        let SunLaw::FocusEllipse { e } = case.train.law else {
            unreachable!("designer cases use the focus ellipse")
        };
        let fo = FitOptions::default(); // order climbs 6 → 40 from the start's order
        let k = FIT_START_ORDER;
        let base = Mechanism {
            a_mm: case.train.a,
            l3_mm: case.train.l3,
            ratio: SunRatio::new(
                (1..=k).map(|j| 2.0 * e.powi(j as i32)).collect(),
                vec![0.0; k],
            )
            .unwrap(),
            sun_phase_rad: case.train.sun_phase,
            needle_angle_rad: case.train.gamma,
            idler_offset_rad: 0.0,
        };
        let mut rng = ChaCha8Rng::seed_from_u64(case.seed ^ 0xf17_5eed);
        let mut starts = vec![base.clone()];
        for _ in 0..FIT_RANDOM_STARTS {
            let ca: Vec<f64> = base
                .ratio
                .cos_coefficients()
                .iter()
                .enumerate()
                .map(|(j, c)| {
                    c + if j < 3 {
                        rng.random_range(-0.03..0.03)
                    } else {
                        0.0
                    }
                })
                .collect();
            let sb: Vec<f64> = (0..k)
                .map(|j| {
                    if j < 3 {
                        rng.random_range(-0.03..0.03)
                    } else {
                        0.0
                    }
                })
                .collect();
            let Ok(ratio) = SunRatio::new(ca, sb) else {
                continue;
            };
            starts.push(Mechanism {
                a_mm: base.a_mm * (1.0 + rng.random_range(-0.005..0.005)),
                l3_mm: base.l3_mm * (1.0 + rng.random_range(-0.005..0.005)),
                ratio,
                sun_phase_rad: base.sun_phase_rad + rng.random_range(-0.05..0.05),
                needle_angle_rad: base.needle_angle_rad + rng.random_range(-0.05..0.05),
                idler_offset_rad: 0.0,
            });
        }
        let mut best = generating_reference(case).hausdorff_mm;
        let mut ok = 0;
        for s in &starts {
            match fit_points(&case.points, s, &fo) {
                Ok(f) => {
                    let path: Vec<Point> = (0..FIT_PATH_SAMPLES)
                        .map(|j| f.mechanism.tip(TAU * j as f64 / FIT_PATH_SAMPLES as f64))
                        .collect();
                    best = best.min(hausdorff(&path, &case.truth));
                    ok += 1;
                }
                Err(err) => eprintln!("designer seed {}: fit start failed: {err}", case.seed),
            }
        }
        Reference {
            hausdorff_mm: best,
            how: "multi-start ncgear::design::fit::fit_points",
            starts_ok: ok,
            ms: 0.0,
        }
    }};
}

/// The best achievable Hausdorff of a designer case.
///
/// ONE-LINE SWITCH: without `ncgear::design::fit`, replace the body by `generating_reference(case)`
/// (an upper bound of the best achievable: the unperturbed generating train).
fn designer_reference(case: &Case) -> Reference {
    fit_multistart_reference!(case)
}

// ---------------------------------------------------------------------------------------------
// Running the cases
// ---------------------------------------------------------------------------------------------

struct Outcome {
    family: Family,
    seed: u64,
    describe: String,
    design_ms: f64,
    /// Err(message) when design() refused.
    result: Result<Measured, String>,
    reference: Option<Reference>,
    failure: Option<String>,
}

struct Measured {
    hausdorff_mm: f64,
    claimed_max_dev_mm: f64,
    claimed_hausdorff_mm: f64,
    /// Checks C6, C9 and C10 pass.
    within_limits: bool,
}

fn run_case(case: &Case) -> Outcome {
    let origins: Vec<Origin> = (0..case.points.len()).map(Origin::Index).collect();
    let traj = Trajectory::new(case.points.clone(), &origins, "generated");
    let opts = DesignOptions::default().with_center_mm(case.opts.center.into());
    let t0 = Instant::now();
    let d = traj
        .map_err(|e| format!("trajectory rejected: {e}"))
        .and_then(|t| design(&t, &opts).map_err(|e| format!("design refused: {e}")));
    let design_ms = t0.elapsed().as_secs_f64() * 1e3;
    let result = d.map(|d| Measured {
        hausdorff_mm: hausdorff(&d.traced_mm, &case.truth),
        claimed_max_dev_mm: d.report.roundtrip.max_deviation_mm,
        claimed_hausdorff_mm: d.report.roundtrip.hausdorff_mm,
        within_limits: d
            .report
            .checks
            .iter()
            .filter(|c| ["C6", "C9", "C10"].contains(&c.id.as_str()))
            .all(|c| c.pass),
    });
    let reference = (case.family == Family::Designer).then(|| {
        let t0 = Instant::now();
        let mut r = designer_reference(case);
        r.ms = t0.elapsed().as_secs_f64() * 1e3;
        r
    });
    let failure = match (&result, case.family) {
        (Err(e), _) => Some(e.clone()),
        // True gears beyond the gear limits (or within 1 % of them): the design is the closest
        // within the limits, which its C9/C10 and the quality suite judge; no exact reproduction.
        (Ok(m), Family::Exact | Family::Sparse) if case.train.limit_margin() < 0.01 => {
            (!m.within_limits).then(|| {
                "true gears beyond the limits: the design must be within them (C6, C9, C10)"
                    .to_string()
            })
        }
        (Ok(m), Family::Exact | Family::Sparse) => {
            let mut v = Vec::new();
            if !(m.hausdorff_mm <= EXACT_TOL_MM) {
                v.push(format!(
                    "Hausdorff(traced, truth) = {:.4} mm > {EXACT_TOL_MM}",
                    m.hausdorff_mm
                ));
            }
            if !(m.claimed_max_dev_mm <= EXACT_TOL_MM) {
                v.push(format!(
                    "report.roundtrip.max_deviation_mm = {:.4} > {EXACT_TOL_MM}",
                    m.claimed_max_dev_mm
                ));
            }
            (!v.is_empty()).then(|| v.join("; "))
        }
        (Ok(m), Family::Noisy) if case.train.limit_margin() < 0.01 => {
            (!m.within_limits).then(|| {
                "true gears beyond the limits: the design must be within them (C6, C9, C10)"
                    .to_string()
            })
        }
        (Ok(m), Family::Noisy) => (!(m.hausdorff_mm <= NOISY_TOL_MM)).then(|| {
            format!(
                "Hausdorff(traced, clean truth) = {:.4} mm > {NOISY_TOL_MM}",
                m.hausdorff_mm
            )
        }),
        (Ok(m), Family::Designer) => {
            let r = reference.as_ref().unwrap();
            (!(m.hausdorff_mm <= DESIGNER_FACTOR * r.hausdorff_mm)).then(|| {
                format!(
                    "Hausdorff(traced, truth) = {:.4} mm > {DESIGNER_FACTOR} × best achievable {:.4} mm ({})",
                    m.hausdorff_mm, r.hausdorff_mm, r.how
                )
            })
        }
    };
    Outcome {
        family: case.family,
        seed: case.seed,
        describe: case.describe(),
        design_ms,
        result,
        reference,
        failure,
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

fn summary(outcomes: &[Outcome], gen_s: f64, total_s: f64, worst_sag: f64) -> String {
    let mut s = String::from(
        "| family | cases | passed | pass rate | refused | worst Hausdorff (mm) | median Hausdorff (mm) | worst claimed max dev (mm) | worst H / reference | median design (ms) | worst design (ms) |\n|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for (fam, _, _) in FAMILIES {
        let o: Vec<&Outcome> = outcomes.iter().filter(|o| o.family == fam).collect();
        let n = o.len();
        let passed = o.iter().filter(|o| o.failure.is_none()).count();
        let refused = o.iter().filter(|o| o.result.is_err()).count();
        let hs: Vec<f64> = o
            .iter()
            .filter_map(|o| o.result.as_ref().ok().map(|m| m.hausdorff_mm))
            .collect();
        let worst_h = hs.iter().copied().fold(f64::NAN, f64::max);
        let worst_claim = o
            .iter()
            .filter_map(|o| o.result.as_ref().ok().map(|m| m.claimed_max_dev_mm))
            .fold(f64::NAN, f64::max);
        let worst_ratio = o
            .iter()
            .filter_map(|o| {
                let m = o.result.as_ref().ok()?;
                Some(m.hausdorff_mm / o.reference.as_ref()?.hausdorff_mm)
            })
            .fold(f64::NAN, f64::max);
        let times: Vec<f64> = o.iter().map(|o| o.design_ms).collect();
        let worst_t = times.iter().copied().fold(f64::NAN, f64::max);
        let _ = writeln!(
            s,
            "| {} | {n} | {passed} | {:.1} % | {refused} | {worst_h:.4} | {:.4} | {worst_claim:.4} | {} | {:.0} | {worst_t:.0} |",
            fam.name(),
            100.0 * passed as f64 / n.max(1) as f64,
            median(hs),
            if worst_ratio.is_nan() {
                "—".to_string()
            } else {
                format!("{worst_ratio:.3}")
            },
            median(times),
        );
    }
    let _ = writeln!(
        s,
        "\nGeneration {gen_s:.1} s, total {total_s:.1} s. Truth polylines: 3600 points, discretisation ≤ {worst_sag:.1e} mm. Designer reference: {}.",
        outcomes
            .iter()
            .find_map(|o| o.reference.as_ref().map(|r| r.how))
            .unwrap_or("—")
    );
    s
}

#[test]
fn robust_generated_trajectories_meet_the_quality_targets() {
    let t_all = Instant::now();
    // `NCGEAR_ROBUST_SEEDS=4009,4022` runs only those seeds (a debugging aid; the suite runs all).
    let only: Option<Vec<u64>> = std::env::var("NCGEAR_ROBUST_SEEDS")
        .ok()
        .map(|v| v.split(',').filter_map(|s| s.trim().parse().ok()).collect());
    let jobs: Vec<(Family, u64)> = FAMILIES
        .iter()
        .flat_map(|&(f, s0, n)| (0..n as u64).map(move |k| (f, s0 + k)))
        .filter(|(_, s)| only.as_ref().is_none_or(|o| o.contains(s)))
        .collect();
    assert!(jobs.len() >= 200 || only.is_some());
    let cases: Vec<Case> = jobs.par_iter().map(|&(f, s)| generate(f, s)).collect();
    let gen_s = t_all.elapsed().as_secs_f64();
    for c in &cases {
        assert!(
            c.closure_error.abs() < 1e-7,
            "model closure error {:e} for seed {}",
            c.closure_error,
            c.seed
        );
    }
    let worst_sag = cases.iter().map(|c| c.truth_sag_mm).fold(0.0, f64::max);
    eprintln!(
        "generated {} cases in {gen_s:.1} s; truth-polyline discretisation ≤ {worst_sag:.2e} mm",
        cases.len()
    );
    assert!(
        worst_sag < 0.005,
        "truth polyline too coarse: {worst_sag} mm"
    );

    let mut outcomes = Vec::with_capacity(cases.len());
    for c in &cases {
        let o = run_case(c);
        let status = match (&o.result, &o.failure) {
            (Err(e), _) => format!("REFUSED {e}"),
            (Ok(m), f) => format!(
                "H = {:.4} mm (claims max dev {:.4}, H {:.4}){}{}",
                m.hausdorff_mm,
                m.claimed_max_dev_mm,
                m.claimed_hausdorff_mm,
                o.reference.as_ref().map_or(String::new(), |r| format!(
                    ", reference {:.4} mm ({} start(s), {:.0} ms)",
                    r.hausdorff_mm, r.starts_ok, r.ms
                )),
                if f.is_some() { "  FAIL" } else { "" }
            ),
        };
        eprintln!(
            "[{} {}] {:.0} ms  {status}",
            o.family.name(),
            o.seed,
            o.design_ms
        );
        outcomes.push(o);
    }

    let total_s = t_all.elapsed().as_secs_f64();
    let table = summary(&outcomes, gen_s, total_s, worst_sag);
    eprintln!("\n{table}");
    let failures: Vec<String> = outcomes
        .iter()
        .filter_map(|o| {
            o.failure.as_ref().map(|f| {
                format!(
                    "  seed {} [{}] {}\n      params: {}",
                    o.seed,
                    o.family.name(),
                    f,
                    o.describe
                )
            })
        })
        .collect();
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target");
    let _ = std::fs::create_dir_all(&dir);
    let mut md = format!(
        "# ncgear robust suite\n\n{} generated cases (independent forward model, fixed seeds).\n\n{table}",
        outcomes.len()
    );
    if !failures.is_empty() {
        let _ = write!(
            md,
            "\n## Failures ({})\n\n```text\n{}\n```\n",
            failures.len(),
            failures.join("\n")
        );
    }
    if let Err(e) = std::fs::write(dir.join("robust_summary.md"), md) {
        eprintln!("could not write target/robust_summary.md: {e}");
    }

    // Every case is held to the quality targets: any failure fails the suite.
    let unexpected: Vec<&String> = outcomes
        .iter()
        .filter(|o| o.failure.is_some() && !KNOWN_MISSES.contains(&o.seed))
        .filter_map(|o| {
            failures
                .iter()
                .find(|f| f.contains(&format!("seed {} ", o.seed)))
        })
        .collect();
    assert!(
        unexpected.is_empty(),
        "{} of {} generated cases failed ({} known misses):\n{}",
        unexpected.len(),
        outcomes.len(),
        KNOWN_MISSES.len(),
        unexpected
            .iter()
            .map(|s| s.as_str())
            .collect::<Vec<_>>()
            .join("\n")
    );
}

/// Seeds that miss the quality targets of `robust_generated_trajectories_meet_the_quality_targets`:
/// none since the perturbed restarts (designer 4009 and 4022 were at 1.08× the multi-start
/// reference before).
const KNOWN_MISSES: [u64; 0] = [];

/// Our model against the crate's closed-form mechanism (used here only as a cross-check, never in
/// the generator): focus ellipse and harmonic suns with random phases and needle angles.
#[test]
fn robust_forward_model_agrees_with_the_crate_mechanism() {
    use ncgear::geometry::fourier::SunRatio;
    use ncgear::geometry::mechanism::Mechanism;
    use rand::rngs::ChaCha8Rng;
    use rand::{RngExt, SeedableRng};
    let mut worst: f64 = 0.0;
    for seed in 0..4u64 {
        let mut rng = ChaCha8Rng::seed_from_u64(77 + seed);
        let train = if seed % 2 == 0 {
            Train::ellipse(
                rng.random_range(0.1..0.2),
                45.0,
                170.0,
                rng.random_range(0.0..TAU),
                rng.random_range(-3.0..3.0),
            )
        } else {
            generate(Family::Exact, 1000 + seed).train
        };
        // Fourier series of our i21 (DFT on 2048 points), order 96
        let n = 2048;
        let k_max = 96;
        let vals: Vec<f64> = (0..n)
            .map(|j| train.i21(TAU * j as f64 / n as f64))
            .collect();
        let mut ca = vec![0.0; k_max];
        let mut sb = vec![0.0; k_max];
        for k in 1..=k_max {
            for (j, v) in vals.iter().enumerate() {
                let th = TAU * (k * j) as f64 / n as f64;
                ca[k - 1] += 2.0 / n as f64 * v * th.cos();
                sb[k - 1] += 2.0 / n as f64 * v * th.sin();
            }
        }
        let m = Mechanism {
            a_mm: train.a,
            l3_mm: train.l3,
            ratio: SunRatio::new(ca, sb).unwrap(),
            sun_phase_rad: train.sun_phase,
            needle_angle_rad: train.gamma,
            idler_offset_rad: 0.0,
        };
        let trace = train.trace(forward::DENSE_STEPS);
        for j in 0..72 {
            let t = TAU * j as f64 / 72.0;
            let (p, q) = (trace.tip_at(t), m.tip(t));
            let d = (p[0] - q.x).hypot(p[1] - q.y);
            worst = worst.max(d);
            assert!(
                d < 1e-5,
                "seed {seed}, t = {t:.3}: model {p:?} vs crate {q:?} ({d:e} mm); law {:?}",
                train.law
            );
        }
        if let SunLaw::Harmonic { .. } = train.law {
            assert!((train.psi_period() - TAU).abs() < 1e-10);
        }
    }
    eprintln!("forward model vs crate Mechanism: worst tip difference {worst:.2e} mm");
}

/// Writes generated targets as CSV files (`x_mm,y_mm`) for measuring the CLI on them: with
/// `NCGEAR_DUMP_DIR=dir NCGEAR_DUMP_SEEDS=designer:7101-7123,noisy:5000-5003` it writes
/// `dir/<family>_<seed>.csv`. Ignored: a tool, not a test.
#[test]
#[ignore = "a tool: writes generated targets for measurement"]
fn dump_generated_targets() {
    let (Ok(dir), Ok(spec)) = (
        std::env::var("NCGEAR_DUMP_DIR"),
        std::env::var("NCGEAR_DUMP_SEEDS"),
    ) else {
        return;
    };
    std::fs::create_dir_all(&dir).unwrap();
    for part in spec.split(',') {
        let (fam, range) = part.split_once(':').expect("family:a-b");
        let family = [
            Family::Exact,
            Family::Sparse,
            Family::Noisy,
            Family::Designer,
        ]
        .into_iter()
        .find(|f| f.name() == fam)
        .expect("exact, sparse, noisy or designer");
        let (a, b) = range.split_once('-').unwrap_or((range, range));
        for seed in a.parse::<u64>().unwrap()..=b.parse::<u64>().unwrap() {
            let c = generate(family, seed);
            let mut s = String::from("x_mm,y_mm\n");
            for p in &c.points {
                s.push_str(&format!("{},{}\n", p.x, p.y));
            }
            std::fs::write(format!("{dir}/{fam}_{seed}.csv"), s).unwrap();
        }
    }
}
