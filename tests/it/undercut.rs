//! Undercut as cut, not refused: the outline is what the rack really cuts —
//! on an undercut flank the rack tip's fillet trochoid trims the flank — checked against the
//! closed forms of the rack-generated spur gear below the minimum tooth count, and on a pair
//! that the peer ncgears makes and ncgear used to refuse.
use crate::teeth::rack_cut;
use ncgear::cad::dxf::{DxfVersion, write_dxf};
use ncgear::cad::points::write_points;
use ncgear::geometry::pitch::PitchCurve;
use ncgear::math::Point;
use ncgear::pair::{Expr, Law, PairOptions, design_pair};
use ncgear::teeth::overlap::first_self_intersection;
use ncgear::teeth::{OutlineOptions, RackParams, TeethError};

/// inv α = tan α − α.
fn inv(a: f64) -> f64 {
    a.tan() - a
}

/// Closed form of a rack-cut spur gear with z teeth of module m (ISO 53 A rack, α = 20°):
/// the rolling rack's tip-rounding centre traces the trochoid
/// `C(s) = P(s) + (x_c − s)·T(s) + e_c·N(s)` (P, T, N the pitch circle's point, tangent and
/// outward normal at arc s; `x_c = s_l − h_s·tan α − ρf·cos α`, `e_c = −(h_f − ρf)`), the root
/// fillet is its offset by ρf, and the flank above it is the involute of the base circle
/// `r·cos α`: `θ − inv α_R = const` with `cos α_R = r cos α / R`. For z = 10…16 (< 2/sin²α =
/// 17.1) the fillet cuts the flank: every vertex of tooth 0's left side lies on the offset
/// trochoid or on the involute, and the reported form depth is the two curves' crossing.
#[test]
fn undercut_spur_gear_has_the_trochoidal_root_and_the_involute_flank() {
    let rack = RackParams::default();
    let (m, tol) = (1.0, 1e-4);
    let alpha = rack.alpha_rad();
    let (sa, ca) = alpha.sin_cos();
    let (ha, hf, rho, hs) = (
        rack.addendum() * m,
        (rack.addendum() + rack.clearance()) * m,
        rack.fillet() * m,
        rack.straight_depth() * m,
    );
    for z in [10u32, 12, 14, 16] {
        let r = f64::from(z) * m / 2.0;
        let curve = PitchCurve::from_fn(4096, |_| r).unwrap();
        let o = rack_cut(&curve, &rack, z, m, &OutlineOptions::new(0.0, tol)).unwrap();
        assert_eq!(
            first_self_intersection(&o.points_mm).unwrap(),
            None,
            "z = {z}"
        );
        let f0 = &o.undercut.flanks[0];
        assert!(f0.undercut && f0.side == "left", "z = {z}: {f0:?}");
        // The rack's tip-rounding centre for tooth 0's left flank, in the gear frame.
        let p = std::f64::consts::PI * m;
        let sl = -0.25 * p;
        let xc = sl - hs * alpha.tan() - rho * ca;
        let ec = -(hf - rho);
        let centre = |s: f64| {
            let t = s / r;
            let (st, ct) = t.sin_cos();
            let (pp, tt, nn) = ([r * ct, r * st], [-st, ct], [ct, st]);
            [
                pp[0] + (xc - s) * tt[0] + ec * nn[0],
                pp[1] + (xc - s) * tt[1] + ec * nn[1],
            ]
        };
        // Distance to the trochoid: dense scan, then golden-section refinement.
        let dist = |v: Point| {
            let d = |s: f64| {
                let c = centre(s);
                (v.x - c[0]).hypot(v.y - c[1])
            };
            let (lo, hi) = (xc - 3.0 * p, xc + p);
            let k = (0..=4000)
                .min_by(|&a, &b| {
                    let sa_ = lo + (hi - lo) * f64::from(a) / 4000.0;
                    let sb = lo + (hi - lo) * f64::from(b) / 4000.0;
                    d(sa_).total_cmp(&d(sb))
                })
                .unwrap();
            let h = (hi - lo) / 4000.0;
            let (mut a, mut b) = (lo + h * (f64::from(k) - 1.0), lo + h * (f64::from(k) + 1.0));
            for _ in 0..100 {
                let (x1, x2) = (b - 0.618 * (b - a), a + 0.618 * (b - a));
                if d(x1) < d(x2) { b = x2 } else { a = x1 }
            }
            d(0.5 * (a + b))
        };
        // The involute of tooth 0's left flank: θ − inv α_R equals its value at the pitch point.
        let rb = r * ca;
        let c_inv = sl / r - inv(alpha);
        let inv_err = |v: Point| {
            let big_r = v.hypot();
            if big_r <= rb {
                return f64::INFINITY;
            }
            let a_r = (rb / big_r).acos();
            (v.atan2() - inv(a_r) - c_inv).abs() * big_r
        };
        // Tooth 0's left side: from the outline's start (its left fillet) up to the tip circle.
        let mut on_fillet = 0;
        let mut on_involute = 0;
        let mut deepest_involute = f64::INFINITY;
        for v in o.points_mm.iter().take_while(|v| v.hypot() < r + ha - 1e-9) {
            let (e_f, e_i) = ((dist(*v) - rho).abs(), inv_err(*v));
            // Vertices are exact curve points; the cut point lies on a chord of each piece.
            assert!(
                e_f.min(e_i) <= tol,
                "z = {z}: vertex {v:?} off both: {e_f:e} {e_i:e}"
            );
            if e_i <= 1e-9 {
                on_involute += 1;
                deepest_involute = deepest_involute.min(v.hypot());
                // Trimmed where the cutter passes: no kept flank vertex inside the region the
                // tip rounding sweeps.
                assert!(dist(*v) >= rho - tol, "z = {z}: {v:?} was cut away");
            } else if e_f <= 1e-9 {
                on_fillet += 1;
            }
        }
        assert!(
            on_fillet > 5 && on_involute > 5,
            "z = {z}: {on_fillet} {on_involute}"
        );
        // The form depth: the involute point of the crossing, closed form. The flank generated
        // at rolling arc s lies at rack depth (sl − s)·sin α·cos α; bisect the depth where the
        // involute point is ρf from the trochoid (the highest crossing on the flank).
        let flank_at = |depth: f64| {
            let s = sl - depth / (sa * ca);
            let dd = depth / sa; // distance along the rack flank from the pitch line
            let t = s / r;
            let (st, ct) = t.sin_cos();
            let (xi, eta) = (dd * ca, -dd * sa);
            Point::new(r * ct + xi * -st + eta * ct, r * st + xi * ct + eta * st)
        };
        let g = |depth: f64| dist(flank_at(depth)) - rho;
        let (mut lo, mut hi) = (0.0, hs);
        // Highest crossing: scan down from the pitch line for the first sign change.
        let steps = 2000;
        let mut prev = g(0.0);
        for k in 1..=steps {
            let dpt = hs * f64::from(k) / f64::from(steps);
            let v = g(dpt);
            if v < 0.0 && prev >= 0.0 {
                (lo, hi) = (hs * f64::from(k - 1) / f64::from(steps), dpt);
                break;
            }
            prev = v;
        }
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if g(mid) >= 0.0 { lo = mid } else { hi = mid }
        }
        let want = 0.5 * (lo + hi);
        assert!(
            want < hs - 1e-6,
            "z = {z}: the closed form is undercut ({want} < {hs})"
        );
        // The crossing of two polylines that are each within `tol` of their curves lies within
        // the rhombus where their tol-bands overlap: ≤ 2·tol/sin(θ/2) from the true crossing
        // along either curve (θ the crossing angle; depth changes at most 1:1 with arc).
        let theta = {
            let h = 1e-6;
            let (a, b) = (flank_at(want - h), flank_at(want + h));
            let t1 = (b - a).atan2();
            // The trochoid's tangent at the point nearest the crossing (its offset is parallel).
            let v = flank_at(want);
            let s_near = (0..=20000)
                .map(|k| xc - 3.0 * p + 4.0 * p * f64::from(k) / 20000.0)
                .min_by(|&x, &y| {
                    let (c, d) = (centre(x), centre(y));
                    (v.x - c[0])
                        .hypot(v.y - c[1])
                        .total_cmp(&(v.x - d[0]).hypot(v.y - d[1]))
                })
                .unwrap();
            let (c, d) = (centre(s_near - h), centre(s_near + h));
            let t2 = (d[1] - c[1]).atan2(d[0] - c[0]);
            let x = (t1 - t2).rem_euclid(std::f64::consts::PI);
            x.min(std::f64::consts::PI - x)
        };
        let bound = 2.0 * tol / (0.5 * theta).sin();
        // A near-tangent crossing (z = 16: 2°) is ill-conditioned along the curves while the
        // outline stays within tol of them (checked above): its depth is compared from 10° up.
        if theta < 10f64.to_radians() {
            continue;
        }
        assert!(
            (f0.form_depth_mm - want).abs() <= bound,
            "z = {z}: form depth {} vs closed form {want} (crossing at {:.2}°, bound {bound:e})",
            f0.form_depth_mm,
            theta.to_degrees()
        );
        // The involute ends at the form point: no involute vertex deeper than it.
        let r_form = {
            let v = flank_at(want);
            v.hypot()
        };
        assert!(deepest_involute >= r_form - bound, "z = {z}");
        // Loss of contact ratio against the rack, closed form.
        let loss = (hs - want) / (p * sa * ca);
        assert!(
            (f0.contact_ratio_loss - loss).abs() <= bound / (p * sa * ca),
            "z = {z}"
        );
        assert!(o.undercut.min_root_thickness_mm.unwrap() > 0.0);
    }
}

/// The law that ncgears 0.3.1 makes 24:24 (centre distance 23.814, TE 1.7e-5°) and ncgear
/// refused for undercut: now made, cut as the rack cuts it, 0 interference and a smaller TE;
/// the strict option keeps the refusal with its advice.
#[test]
fn undercut_pair_is_made_and_the_strict_option_refuses_it() {
    let law = Law::Motion(Expr::parse("phi - 0.12*sin(2*phi)").unwrap());
    let d = design_pair(&law, &PairOptions::new(Some(24), 1.0)).unwrap();
    assert!(
        (d.center_distance_mm - 23.814).abs() < 5e-4,
        "{}",
        d.center_distance_mm
    );
    let u = &d.driven_undercut;
    assert!(u.undercut_count > 0 && u.max_undercut_mm > 0.0, "{u:?}");
    assert!(u.max_contact_ratio_loss > 0.0 && u.min_root_thickness_mm.unwrap() > 0.0);
    for o in [&d.driver, &d.driven] {
        assert_eq!(first_self_intersection(&o.points_mm).unwrap(), None);
    }
    // The cut outlines' DXF and point lists for the ezdxf read-back in `.ci/run`.
    let dir = crate::teeth::out_dir("test-dxf");
    let sheet = d.assembly_sheet();
    write_dxf(
        &sheet,
        &dir.join("pair_undercut_r2010.dxf"),
        DxfVersion::R2010,
        1e-3,
    )
    .unwrap();
    write_points(&sheet, &dir.join("pair_undercut_points"), "pair_undercut").unwrap();
    let mesh = d.mesh.unwrap();
    assert_eq!(mesh.interference_steps, 0, "{mesh:?}");
    assert!(mesh.max_overlap_area_mm2 <= 1e-9, "{mesh:?}");
    assert!(mesh.max_transmission_error_deg <= 1.7e-5, "{mesh:?}");
    let mut strict = PairOptions::new(Some(24), 1.0);
    strict.toothing.refuse_undercut = true;
    let e = design_pair(&law, &strict).unwrap_err().to_string();
    assert!(
        e.contains("undercut") && e.contains("at least 30 teeth"),
        "{e}"
    );
    // The refusal is the strict option's, not a generation failure.
    assert!(matches!(
        design_pair(&law, &strict),
        Err(ncgear::pair::PairError::Teeth(TeethError::Undercut { .. }))
    ));
}
