//! Integration tests: shaper-cutter generation against closed forms — involutes on a
//! circle (external gear) and on a concave circular arc (internal gear), the basic-rack profile
//! on a straight stretch — and the process choice.
use crate::teeth::rack_cut;
use ncgear::geometry::pitch::PitchCurve;
use ncgear::math::Point;
use ncgear::teeth::overlap::first_self_intersection;
use ncgear::teeth::process::{CutterChoice, Process};
use ncgear::teeth::{
    ArcFrame, GearBlank, Generation, Outline, OutlineOptions, RackParams, TeethError, ToothPolicy,
    generate, scale_curve, tooth_count,
};

/// The outline of `blank` cut by the shaper cutter with `cutter_teeth` teeth.
fn shaper_cut(blank: &GearBlank<'_>, cutter_teeth: u32) -> Result<Outline, TeethError> {
    generate(blank, Generation::Shaper(cutter_teeth)).map(|g| g.outline)
}

fn inv(a: f64) -> f64 {
    a.tan() - a
}

/// Range `[min, max]` of `inv(α_r) + sign·polar angle` about `centre` over the outline vertices
/// selected by `keep(radius, polar angle)`: a single value for an exact involute of the base
/// circle `rb` (the sign chooses the flank's hand). Returns (min, max, count).
fn involute_range(
    pts: &[Point],
    centre: Point,
    rb: f64,
    sign: f64,
    keep: impl Fn(f64, f64) -> bool,
) -> (f64, f64, usize) {
    let vals: Vec<f64> = pts
        .iter()
        .filter_map(|p| {
            let (x, y) = (p.x - centre.x, p.y - centre.y);
            let (r, t) = (x.hypot(y), y.atan2(x));
            keep(r, t).then(|| inv((rb / r).acos()) + sign * t)
        })
        .collect();
    let lo = vals.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = vals.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    (lo, hi, vals.len())
}

/// Runs `ncgear design assets/cases/<case> <args> --out <out>`, asserts it succeeds, and returns
/// its `design.json` and console output.
fn design_case(case: &str, args: &[&str], out: &std::path::Path) -> (serde_json::Value, String) {
    let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("assets/cases")
        .join(case);
    let _ = std::fs::remove_dir_all(out);
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_ncgear"))
        .arg("design")
        .arg(&path)
        .args(args)
        // The cases' own (exact) gears, unconstrained, scaled to the tooth count: the processes
        // are tested on fixed geometry, not on the design made for each module (with sparse
        // points several exact trains exist; the limits pick a smoother one).
        .args(["--tooth-policy", "scale-up", "--limits", "off"])
        // Off limits, such gears may fail C8 (undercut) or C10: the teeth are what is tested here.
        .arg("--accept-failed")
        .arg("--out")
        .arg(out)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{case} {args:?}: {}",
        String::from_utf8_lossy(&run.stderr)
    );
    let json =
        serde_json::from_str(&std::fs::read_to_string(out.join("design.json")).unwrap()).unwrap();
    (json, String::from_utf8_lossy(&run.stdout).into_owned())
}

#[test]
fn shaper_on_a_circle_cuts_the_involute() {
    // Any involute cutter generates the involute of the gear's base circle r·cos α: the right
    // flank of tooth 0 crosses the pitch circle at θp = p/4/r = π/48, so its vertices satisfy
    // inv(α_r) + θ = θp + inv α (docs/math/chain.md §11.5 (G5), the rack's closed form) — for every cutter size.
    let (r0, m, z) = (24.0, 2.0, 24);
    let c = PitchCurve::from_fn(256, |_| r0).unwrap();
    let frame = ArcFrame::new(&c);
    let alpha = 20f64.to_radians();
    let rb = r0 * alpha.cos();
    let want = std::f64::consts::PI / 48.0 + inv(alpha);
    // 25 teeth: a cutter made taller so that its involute still reaches the rack's flank depth.
    for zc in [25, 34, 50, 100] {
        let o = shaper_cut(
            &GearBlank::new(
                &frame,
                RackParams::default(),
                z,
                m,
                OutlineOptions::new(0.0, 1e-6),
            ),
            zc,
        )
        .unwrap();
        assert_eq!(first_self_intersection(&o.points_mm).unwrap(), None);
        let (lo, hi, n) = involute_range(&o.points_mm, Point::new(0.0, 0.0), rb, 1.0, |r, t| {
            t > 0.0 && t < 0.13 && r > rb * 1.01 && r > r0 - m && r < r0 + 0.99 * m
        });
        assert!(n > 50, "z_c {zc}: {n}");
        assert!(
            (lo - want).abs() < 1e-9 && (hi - want).abs() < 1e-9,
            "z_c {zc}: [{lo}, {hi}] vs {want}"
        );
    }
    // A 12-tooth cutter made tall enough for its involute to reach the rack's flank depth keeps
    // no tip flat in the gear's space: refused, naming why.
    let err = shaper_cut(
        &GearBlank::new(
            &frame,
            RackParams::default(),
            z,
            m,
            OutlineOptions::new(0.0, 1e-3),
        ),
        12,
    )
    .unwrap_err();
    assert!(
        matches!(
            err,
            TeethError::Shaper {
                cutter_teeth: 12,
                what
            } if what.contains("tip flat")
        ),
        "{err}"
    );
}

/// Concave stretches cut by a shaper: `exact_concave_sun.csv` (an exactly traceable target whose intermediate
/// has concave stretches) gets teeth on all three gears at m = 1 and up to the largest module
/// that meshes within the convex examples' 1e-5°, 2.4 mm (2.6 mm: 1.1e-5°). The intermediate is
/// shaper-cut with the largest standard cutter whose pitch radius is below the tightest concave
/// radius ≈ 100 mm (100 teeth up to 2 mm, then 80), sun and planet stay rack-cut; both meshes roll
/// through a carrier turn without an interference step. At 1.2 mm the standard rack's tips would
/// graze the planet's fillet (next test); at 2.4 mm every cutter that fits undercuts the
/// intermediate (cut and reported, as the rack cuts the sun's undercut). The DXF files are read
/// back by ezdxf in `.ci/run`.
#[test]
fn concave_case_gets_teeth_on_all_three_gears() {
    let case = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("assets/cases/exact_concave_sun.csv");
    // (module, addendum ha*, cutter teeth, undercut intermediate): measured TE 8.8e-7°/6.9e-7°
    // at 1, 8.5e-7°/1.0e-6° at 1.2 with ha* = 0.9, 1.4e-6°/8.7e-7° at 1.2, 5.9e-6°/5.8e-6° at 2.4.
    for (m, ha, zc, undercut) in [
        ("1", "1", 100, false),
        ("1.2", "0.9", 100, false),
        ("1.2", "1", 100, false),
        ("2.4", "1", 80, true),
    ] {
        let out = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("target/test-dxf")
            .join(format!("concave_sun_m{m}_ha{ha}"));
        let (json, _) = design_case(
            "exact_concave_sun.csv",
            &["--module", m, "--addendum", ha],
            &out,
        );
        let t = &json["teeth"];
        let p = &t["process"];
        assert_eq!(p["sun"]["process"], "rack", "m = {m}");
        assert_eq!(p["planet"]["process"], "rack", "m = {m}");
        let i = &p["intermediate"];
        assert_eq!(i["process"], "shaper", "m = {m}");
        assert_eq!(i["cutter_teeth"], zc, "m = {m}");
        assert_eq!(i["tried_cutter_teeth"][0], zc, "m = {m}");
        assert_eq!(
            i["undercut_flanks"].as_u64().unwrap() > 0,
            undercut,
            "m = {m}"
        );
        let rho = i["min_concave_rho_mm"].as_f64().unwrap();
        let r0 = f64::from(zc) * m.parse::<f64>().unwrap() / 2.0;
        // z_c·m/2 to rounding.
        assert!(
            (i["cutter_pitch_radius_mm"].as_f64().unwrap() - r0).abs() < 1e-12,
            "m = {m}"
        );
        assert!(
            r0 < rho && (90.0..110.0).contains(&rho),
            "m = {m}: {r0} {rho}"
        );
        assert!(t["undercut"]["intermediate"]["concave_flanks"].is_null());
        assert!(
            t["undercut"]["intermediate"]["concave_count"]
                .as_u64()
                .unwrap()
                > 0,
            "m = {m}"
        );
        for mesh in ["sun_intermediate", "intermediate_planet"] {
            let r = &t["mesh"][mesh];
            assert_eq!(r["interference_steps"], 0, "m = {m} {mesh}: {r}");
            assert!(r["min_backlash_mm"].as_f64().unwrap() > 0.0, "{r}");
            let te = r["max_transmission_error_deg"].as_f64().unwrap();
            assert!(te <= 1e-5, "m = {m} {mesh}: TE {te}°");
        }
        for f in ["train.dxf", "intermediate.dxf", "intermediate.svg"] {
            assert!(out.join("teeth").join(f).exists(), "{f}");
        }
    }
    // At 1.25 mm the convex sun undercuts (rack): with --no-undercut refused, naming the gear.
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_ncgear"))
        .args([
            "design",
            case.to_str().unwrap(),
            "--module",
            "1.25",
            "--no-undercut",
            "--tooth-policy",
            "scale-up",
            "--limits",
            "off",
            "--out",
        ])
        .arg(std::env::temp_dir().join("ncgear_concave_m125"))
        .output()
        .unwrap();
    assert_eq!(run.status.code(), Some(2));
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(err.contains("sun") && err.contains("undercut"), "{err}");
}

/// The tip relief at work: at m = 1.2 with the standard rack (ISO 53 A: the straight flank ends
/// exactly at the addendum depth) the intermediate's tips would reach the planet's fillet, which
/// sits near its undercut limit — measured before the relief: overlap 3.9e-6 mm² at the law's
/// position and a transmission error of 9.4e-4°, two orders above the numeric level. The relief
/// lowers the one tooth tip that grazes it (by 0.024 mm, one step of the ladder) and both meshes
/// run within 1e-5° without overlap.
#[test]
fn standard_rack_at_1_2_relieves_the_tip_that_grazes_the_fillet() {
    let out = std::env::temp_dir().join("ncgear_concave_m12_standard");
    let (json, stdout) = design_case("exact_concave_sun.csv", &["--module", "1.2"], &out);
    assert!(stdout.contains("tip relief on 1 teeth"), "{stdout}");
    let i = &json["teeth"]["process"]["intermediate"];
    assert_eq!(i["relieved_teeth"], 1, "{i}");
    // A step of the ladder (0.02·m): 0.024 mm.
    assert!(
        (i["max_tip_relief_mm"].as_f64().unwrap() - 0.02 * 1.2).abs() < 1e-12,
        "{i}"
    );
    for g in ["sun", "planet"] {
        assert_eq!(json["teeth"]["process"][g]["relieved_teeth"], 0);
    }
    for mesh in ["sun_intermediate", "intermediate_planet"] {
        let r = &json["teeth"]["mesh"][mesh];
        let te = r["max_transmission_error_deg"].as_f64().unwrap();
        let overlap = r["max_overlap_area_mm2"].as_f64().unwrap();
        assert!(te <= 1e-5, "{mesh}: TE {te}°");
        assert!(overlap < 1e-9, "{mesh}: overlap {overlap} mm²");
    }
}

/// On any pitch curve the shaper touches each flank at the point where the rack touches it — the
/// same line of action through `P(s)`, the same distance `|s − s_f|·cos α` — so on a concave
/// stretch (which no rack can cut) the shaper-cut flank is the rack-envelope closed form of
/// docs/math/teeth.md §12.3, `P(s) + (s_f − s)·cos α·(cos α·T ± sin α·N)`: on a straight stretch the basic rack
/// profile itself, on a concave circular arc the internal involute.
#[test]
fn shaper_flanks_on_a_concave_stretch_are_the_rack_envelope() {
    // r = 20(1 + 0.12 cos 3θ): Δ = r² + 2r′² − r·r″ < 0 near θ = π/3 (ρ ≈ −78 mm).
    let c = PitchCurve::from_fn(4096, |t| 20.0 * (1.0 + 0.12 * (3.0 * t).cos())).unwrap();
    let m = 1.0;
    let tc = tooth_count(&c, m, ToothPolicy::Nearest, 1e-10).unwrap();
    let c = scale_curve(&c, tc.scale).unwrap();
    let frame = ArcFrame::new(&c);
    let rack = RackParams::default();
    // A rack refuses it.
    let err = rack_cut(&c, &rack, tc.z, m, &OutlineOptions::new(0.0, 1e-3)).unwrap_err();
    assert!(matches!(err, TeethError::Concave { .. }), "{err}");
    let opts = OutlineOptions::new(0.0, 1e-6);
    let cut = generate(
        &GearBlank::new(&frame, rack, tc.z, m, opts),
        Generation::Process(CutterChoice::Auto),
    )
    .unwrap();
    let (o, proc_) = (cut.outline, cut.process);
    assert_eq!(proc_.process, Process::Shaper);
    assert_eq!(proc_.cutter_teeth, Some(100));
    assert_eq!(proc_.tried_cutter_teeth, vec![100]);
    let rho = proc_.min_concave_rho_mm.unwrap();
    assert!((60.0..100.0).contains(&rho), "{rho}");
    assert_eq!(first_self_intersection(&o.points_mm).unwrap(), None);
    // Closed-form flank points on every concave flank, from 0.8·ha above to 0.9·h_straight below
    // the pitch curve (the tip trim on a concave stretch sits below ha in the rack's η), lie on the
    // outline polyline within the chord tolerance.
    let (sa, ca) = 20f64.to_radians().sin_cos();
    let p = frame.length_mm() / f64::from(tc.z);
    let hs = rack.straight_depth() * m;
    let mut want = Vec::new();
    for (k, f) in o.undercut.flanks.iter().enumerate() {
        if !f.concave {
            continue;
        }
        let sign = if f.side == "right" { 1.0 } else { -1.0 };
        let sf = opts.phase_mm + (k / 2) as f64 * p + sign * 0.25 * p;
        assert!((sf - f.s_mm).abs() < 1e-12);
        for j in 0..=20 {
            let eta = 0.8 * m - (0.8 * m + 0.9 * hs) * f64::from(j) / 20.0;
            let s = sf - sign * eta / (sa * ca);
            let fp = frame.at(s);
            let d = (sf - s) * ca;
            want.push(Point::new(
                fp.p.x + d * ca * fp.t.x + sign * d * sa * fp.n.x,
                fp.p.y + d * ca * fp.t.y + sign * d * sa * fp.n.y,
            ));
        }
    }
    assert!(want.len() > 100, "{}", want.len());
    let mut closed = o.points_mm.clone();
    closed.push(closed[0]);
    let dist = ncgear::math::polyline::distances_to_polyline(&want, &closed);
    let worst = dist.iter().copied().fold(0.0, f64::max);
    assert!(worst < 1e-6, "worst {worst} mm");
}

/// Internal gear closed form: over an exactly circular concave arc (radius ρ about a centre C
/// outside the body) the teeth point towards C and each flank is an involute of the base circle
/// `ρ·cos α` about C: polar angle about C `φ = φ_f ± (inv α_r − inv α)` with `φ_f` where the flank
/// crosses the pitch arc. Checked on the outline vertices of the flanks generated wholly on the arc.
#[test]
fn shaper_on_a_concave_circular_arc_cuts_the_internal_involute() {
    // r(θ): the near side of the circle |X − (60, 0)| = 40 for |θ| ≤ 0.15, blended (quintic
    // smoothstep over 0.15 … 0.45 rad) into a circle of radius 21 elsewhere; m = 0.3 (the blend is tightly curved).
    let (d, rho) = (60.0f64, 40.0f64);
    let arc = |t: f64| d * t.cos() - (rho * rho - (d * t.sin()).powi(2)).sqrt();
    let f = |t: f64| {
        let a = t.rem_euclid(std::f64::consts::TAU);
        let a = a.min(std::f64::consts::TAU - a);
        let x = ((a - 0.15) / 0.3).clamp(0.0, 1.0);
        let w = 1.0 - x * x * x * (10.0 - 15.0 * x + 6.0 * x * x);
        if w > 0.0 {
            w * arc(a) + (1.0 - w) * 21.0
        } else {
            21.0
        }
    };
    let c = PitchCurve::from_fn(8192, f).unwrap();
    let m = 0.3;
    let tc = tooth_count(&c, m, ToothPolicy::Nearest, 1e-10).unwrap();
    let s = tc.scale;
    let c = scale_curve(&c, s).unwrap();
    let frame = ArcFrame::new(&c);
    let opts = OutlineOptions::new(0.0, 1e-6);
    let blank = GearBlank::new(&frame, RackParams::default(), tc.z, m, opts);
    let o = shaper_cut(&blank, 50).unwrap();
    let (centre, rho) = ([d * s, 0.0], rho * s);
    let alpha = 20f64.to_radians();
    let rb = rho * alpha.cos();
    let about = |q: Point| (q.y - centre[1]).atan2(q.x - centre[0]);
    // Flanks crossing the pitch curve within 0.04 rad of θ = 0 (their generation, ±3 m of arc,
    // stays on the exact arc): pitch-crossing angle about C.
    let p = frame.length_mm() / f64::from(tc.z);
    let flanks: Vec<f64> = (0..tc.z)
        .flat_map(|k| {
            let sk = f64::from(k) * p;
            [sk - 0.25 * p, sk + 0.25 * p]
        })
        .map(|sf| frame.at(sf).p)
        .filter(|q| q.atan2().abs() < 0.04)
        .map(about)
        .collect();
    assert!(flanks.len() >= 2, "{}", flanks.len());
    let mut n = 0;
    for q in &o.points_mm {
        let r = (q.x - centre[0]).hypot(q.y - centre[1]);
        // Involute part: from 0.7·ha inside the pitch arc (tips point to C, topped to ≈ 0.8·ha
        // here) to 0.9·h_s outside.
        if q.atan2().abs() > 0.035 || r < rho - 0.7 * m || r > rho + 0.9 * m {
            continue;
        }
        let e = inv((rb / r).acos()) - inv(alpha);
        let phi = about(*q);
        let best = flanks
            .iter()
            .flat_map(|&pf| [(phi - pf - e).abs(), (phi - pf + e).abs()])
            .fold(f64::INFINITY, f64::min);
        // Vertices of the tip and root arcs match no involute; flank vertices match to 1e-9 rad.
        if best < 1e-3 {
            assert!(
                best * rho < 1e-6,
                "r = {r}: off the involute by {} mm",
                best * rho
            );
            n += 1;
        }
    }
    assert!(n > 50, "{n}");
}

/// The shaper's closed form on a literally straight pitch line: over the flat side of a
/// D-shaped pitch curve (`r = d/cos θ` for |θ| ≤ 0.3, the line x = d) a shaper cutter of any
/// size (forced: 40 and 100 teeth) cuts the rack's own straight flanks — every flank point of the
/// basic rack profile, `P(s_f) + t·(sin α·T ∓ cos α·N)` from 0.8·ha above to 0.9·h_straight below
/// the line, lies on the shaper-cut outline within the chord tolerance. (The blend into the circle
/// is slightly concave, so only a shaper cuts this gear.)
#[test]
fn shaper_on_a_straight_pitch_line_cuts_the_rack_profile() {
    let d = 20.0;
    let smooth = |u: f64| {
        let u = u.clamp(0.0, 1.0);
        u * u * u * (10.0 - 15.0 * u + 6.0 * u * u)
    };
    // The flat side, blended (quintic smoothstep over 0.3 … 1.0 rad) into a circle of 25 mm
    // (|ρ| ≥ 6 mm elsewhere: no undercut at this module).
    let r = |t: f64| {
        let t = (t + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
        let w = smooth((t.abs() - 0.3) / 0.7);
        (1.0 - w) * d / t.cos().max(0.5) + w * 25.0
    };
    let c = PitchCurve::from_fn(8192, r).unwrap();
    let m = 0.25;
    let tc = tooth_count(&c, m, ToothPolicy::Nearest, 1e-10).unwrap();
    let c = scale_curve(&c, tc.scale).unwrap();
    let frame = ArcFrame::new(&c);
    let rack = RackParams::default();
    let opts = OutlineOptions::new(0.0, 1e-6);
    let (sa, ca) = rack.alpha_rad().sin_cos();
    let p = frame.length_mm() / f64::from(tc.z);
    let hs = rack.straight_depth() * m;
    let ha = rack.addendum() * m;
    // The straight stretch in arc length: |θ| ≤ 0.3 on the line x = d·scale, tan θ·d·scale.
    let half = (0.3f64).tan() * d * tc.scale;
    for zc in [40u32, 100] {
        let o = shaper_cut(&GearBlank::new(&frame, rack, tc.z, m, opts), zc).unwrap();
        let mut want = Vec::new();
        for k in 0..tc.z as usize {
            for sign in [-1.0, 1.0] {
                let sf = (k as f64 * p + sign * 0.25 * p + 0.5 * frame.length_mm())
                    .rem_euclid(frame.length_mm())
                    - 0.5 * frame.length_mm();
                // The whole generating range (the cutter's reach, ±(ha + hs)/(sin α cos α)) on
                // the line.
                if sf.abs() + (ha + hs) / (sa * ca) + 2.0 * m > half {
                    continue;
                }
                let f = frame.at(sf);
                for j in 0..=20 {
                    let eta = 0.8 * ha - (0.8 * ha + 0.9 * hs) * f64::from(j) / 20.0;
                    // Depth η along the normal, tangential offset −sign·η·tan α.
                    let t_off = -sign * eta * sa / ca;
                    want.push(Point::new(
                        f.p.x + t_off * f.t.x + eta * f.n.x,
                        f.p.y + t_off * f.t.y + eta * f.n.y,
                    ));
                }
            }
        }
        assert!(want.len() >= 4 * 21, "z_c = {zc}: {} points", want.len());
        let mut closed = o.points_mm.clone();
        closed.push(closed[0]);
        let dist = ncgear::math::polyline::distances_to_polyline(&want, &closed);
        let worst = dist.iter().copied().fold(0.0, f64::max);
        assert!(worst < 1e-6, "z_c = {zc}: worst {worst} mm");
    }
}

/// A hollow tighter than the 30-tooth cutter (|ρ| = 13.2 mm at m = 1) is cut by a 25-tooth one,
/// made taller so that its involute still reaches the rack's flank depth (it was swept before,
/// wire EDM, with a transmission error of 0.13°): the 24-tooth pair of `phi − 0.2·sin 2φ`
/// meshes without interference within 1e-5°, the cutter's other teeth clear of the gear
/// (secondary cutting is checked for every cutter).
#[test]
fn a_tight_hollow_is_cut_by_a_taller_small_cutter() {
    use ncgear::pair::{Expr, Law, PairOptions, design_pair};
    let d = design_pair(
        &Law::Motion(Expr::parse("phi - 0.2*sin(2*phi)").unwrap()),
        &PairOptions::new(Some(24), 1.0),
    )
    .unwrap();
    let p = &d.driver_process;
    assert_eq!(p.process, Process::Shaper, "{p:?}");
    assert_eq!(p.cutter_teeth, Some(25), "{p:?}");
    let rho = p.min_concave_rho_mm.unwrap();
    assert!(12.5 < rho && rho < 15.0, "{p:?}");
    assert_eq!(p.undercut_flanks, 0, "{p:?}");
    let mesh = d.mesh.unwrap();
    assert_eq!(mesh.interference_steps, 0, "{mesh:?}");
    assert!(mesh.max_transmission_error_deg <= 1e-5, "{mesh:?}");
    assert!(mesh.max_overlap_area_mm2 < 1e-9, "{mesh:?}");
}

/// A small cutter does not reach every tip: `exact_sparse_200.csv` at m = 1 has a sun whose
/// tightest hollow (|ρ| ≈ 12 mm) only a 20-tooth cutter fits; on its tightly convex stretches
/// that cutter's involute would have to reach below its base circle to generate the full tips,
/// so those tips are lowered to where it reaches (reported) — and both meshes still run without
/// interference within 1e-5° (the gear was swept before, wire EDM, with 0.05°–0.08°).
#[test]
fn small_cutter_tips_are_lowered_to_its_reach_and_the_train_meshes() {
    let out = std::env::temp_dir().join("ncgear_sparse_m1_teeth");
    let (json, _) = design_case("exact_sparse_200.csv", &["--module", "1"], &out);
    let t = &json["teeth"];
    for g in ["sun", "planet"] {
        let p = &t["process"][g];
        assert_eq!(p["process"], "shaper", "{p}");
        assert_eq!(p["cutter_teeth"], 20, "{p}");
        assert!(p["reach_topped_teeth"].as_u64().unwrap() > 0, "{p}");
        assert!(p["min_tip_width_mm"].as_f64().unwrap() > 0.3, "{p}");
    }
    for mesh in ["sun_intermediate", "intermediate_planet"] {
        let r = &t["mesh"][mesh];
        assert_eq!(r["interference_steps"], 0, "{mesh}: {r}");
        let te = r["max_transmission_error_deg"].as_f64().unwrap();
        assert!(te <= 1e-5, "{mesh}: TE {te}°");
    }
}
