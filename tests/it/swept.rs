//! Integration tests: gears made without a cutter (wire EDM, printing) — the outline its
//! mate sweeps — against closed forms: an involute gear swept by an involute mate is the conjugate
//! involute; and the process choice of a pair whose concave gear no cutter fits.
use crate::teeth::rack_cut;
use ncgear::geometry::pitch::PitchCurve;
use ncgear::math::Point;
use ncgear::pair::{Expr, Law, PairOptions, design_pair};
use ncgear::progress::Progress;
use ncgear::teeth::conjugate::{Mate, MatePose};
use ncgear::teeth::mesh::{MeshCheck, verify_mesh};
use ncgear::teeth::process::Process;
use ncgear::teeth::{ArcFrame, GearBlank, Generation, OutlineOptions, RackParams, generate};
use std::f64::consts::{PI, TAU};

fn inv(a: f64) -> f64 {
    a.tan() - a
}

/// Two 24-tooth spur gears (m = 1, r = 12, a = 24): the driven gear is rack-cut, the driver is
/// swept by it over a turn at the law's position less the flank allowance and turned by the
/// backlash (0.04 mm). Every swept flank vertex between the base circle and the tip is on an
/// involute of the base circle (`inv α_r ∓ θ` constant per flank to 3e-5 rad, i.e. 4e-4 mm of
/// arc, from 0.2·m above the base circle to 0.8·m above the pitch circle), and the pair meshes: no interference, transmission error below 1e-3° (the allowance
/// 1e-4·m over r = 12 is 4.8e-4°), backlash between 0.9 and 1.15 times the 0.04 mm asked for
/// (measured 0.037–0.044 mm: the coast flanks are swept from the mate's coast flanks, and the
/// coast contact varies with the position more than the working one).
#[test]
fn a_gear_swept_by_an_involute_mate_is_the_conjugate_involute() {
    let (z, m, r, a) = (24u32, 1.0, 12.0, 24.0);
    let rack = RackParams::default();
    let circle = PitchCurve::from_uniform_radii(vec![r; 512]).unwrap();
    // Driven: a space faces the driver at body angle π (arc π·r from body angle 0).
    let driven = rack_cut(
        &circle,
        &rack,
        z,
        m,
        &OutlineOptions::new(PI * r + 0.5 * PI * m, 1e-6 * m),
    )
    .unwrap();
    let backlash = 0.04;
    // Body → world: driver R(φ); driven R(−(φ + δ)) + (a, 0). Driven body → driver body.
    let pose = |u: f64, set: usize| {
        let phi = TAU * u;
        let delta = if set == 0 {
            -1e-4 / r
        } else {
            (backlash + 1e-4) / r
        };
        MatePose {
            angle_rad: -phi - (phi + delta),
            shift_mm: Point::new(a * phi.cos(), -a * phi.sin()),
        }
    };
    let mate = [Mate {
        outline_mm: &driven.points_mm,
        pitch: &circle,
        pose: &pose,
        offsets: 2,
        positions: z as usize * 96,
    }];
    let frame = ArcFrame::new(&circle);
    let blank = GearBlank::new(&frame, rack, z, m, OutlineOptions::new(0.0, 1e-6 * m));
    let swept = generate(&blank, Generation::Swept(&mate)).unwrap();
    assert_eq!(swept.process.process, Process::WireEdm);
    let min_tip = swept.process.min_tip_width_mm.unwrap();
    assert!(min_tip > 0.5, "{min_tip}");
    let driver = swept.outline;
    // Flank vertices: above the base circle (with a margin) and below the tip land.
    let rb = r * rack.alpha_rad().cos();
    let pitch_angle = TAU / f64::from(z);
    for hand in [1.0, -1.0] {
        // inv(α_r) ∓ θ, reduced per tooth: along a flank whose radius grows counter-clockwise the
        // polar angle grows with inv α_r; each flank of this hand gives one value.
        let mut per_tooth: Vec<Vec<f64>> = vec![Vec::new(); z as usize];
        let pts = &driver.points_mm;
        for (i, p) in pts.iter().enumerate() {
            let rr = p.hypot();
            if !(rr > rb + 0.2 * m && rr < r + 0.8 * m) {
                continue;
            }
            // The flank's hand: the radius grows along the outline on one flank, falls on the other.
            let q = pts[(i + 1) % pts.len()];
            if (q.hypot() - rr) * hand <= 0.0 {
                continue;
            }
            let th = p.atan2().rem_euclid(TAU);
            let tooth = ((th / pitch_angle).round() as usize) % z as usize;
            let v = inv((rb / rr).acos()) - hand * (th - tooth as f64 * pitch_angle);
            per_tooth[tooth].push(v);
        }
        for (k, vals) in per_tooth.iter().enumerate() {
            assert!(
                vals.len() > 20,
                "tooth {k} hand {hand}: {} vertices",
                vals.len()
            );
            let lo = vals.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = vals.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            assert!(hi - lo < 3e-5, "tooth {k} hand {hand}: spread {}", hi - lo);
        }
    }
    let report = verify_mesh(
        &driver.points_mm,
        &driven.points_mm,
        &|phi| phi,
        &{
            let mut c = MeshCheck::new(a, m);
            c.steps = 48;
            c.backlash_mm = backlash;
            c
        },
        &Progress::none(),
    )
    .unwrap();
    assert_eq!(report.interference_steps, 0, "{report:?}");
    assert!(report.max_transmission_error_deg < 1e-3, "{report:?}");
    assert!(
        report.min_backlash_mm > 0.9 * backlash && report.max_backlash_mm < 1.15 * backlash,
        "{report:?}"
    );
}

/// A law whose driver is concave tighter than any standard cutter (ρ = 6.3 mm < 6·m with the
/// 12-tooth cutter invalid) was refused; now the driver is swept by the rack-cut driven gear:
/// wire EDM / printing, 36 teeth each keeping a tip, the rejections kept in the report.
#[test]
fn a_concave_gear_no_cutter_fits_is_swept_by_its_mate() {
    let law = Law::Motion(Expr::parse("phi - 0.12*sin(3*phi)").unwrap());
    let mut opts = PairOptions::new(Some(36), 1.0);
    opts.toothing.verify_steps = 0;
    let d = design_pair(&law, &opts).unwrap();
    assert_eq!(d.driver_process.process, Process::WireEdm);
    assert_eq!(d.driven_process.process, Process::Rack);
    let rho = d.driver_process.min_concave_rho_mm.unwrap();
    assert!(rho > 6.0 && rho < 6.5, "{rho}");
    assert!(d.driver_process.min_tip_width_mm.unwrap() > 0.1);
    assert!(
        d.driver_process.rejected[0].contains("12"),
        "{:?}",
        d.driver_process.rejected
    );
}
