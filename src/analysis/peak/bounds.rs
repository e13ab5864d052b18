//! Upper bounds of |f| on one grid interval from its end values (and slopes), which decide the
//! intervals the certified peak must refine.

/// A coarse bound of |f| on a grid interval from its end values `y0`, `y1`, with `c = M2·h²/2`
/// (= 4 × the grid loss `M2·h²/8`).
///
/// With |f″| ≤ M2, f lies within (M2/2)(t − t_j)(t_j+1 − t) of its chord, so
/// |f| ≤ max_s ±(y0 + d s) + c s(1 − s) — at most, and mostly well below, max(|y0|, |y1|) + loss.
pub(super) fn chord_bound(y0: f64, y1: f64, c: f64) -> f64 {
    let g = |y0: f64, d: f64| {
        let s = (d + c) / (2.0 * c);
        if s > 0.0 && s < 1.0 {
            y0 + (d + c) * (d + c) / (4.0 * c)
        } else {
            y0.max(y0 + d)
        }
    };
    g(y0, y1 - y0).max(g(-y0, y0 - y1))
}

/// The maximum `(value, s)` of |p| over `s ∈ [0, 1]`, `p` the cubic Hermite interpolant of the
/// end values `(y0, y1)` (same sign) and scaled slopes `(m0, m1) = h·(f′_0, f′_1)`, capped at
/// `max(|y0|, |y1|) + loss`; the interpolation error bound `M4·h⁴/384` is the caller's to add.
pub(super) fn hermite_bound((y0, y1): (f64, f64), (m0, m1): (f64, f64), loss: f64) -> (f64, f64) {
    let sg = y0.signum();
    let (y0, y1, m0, m1) = (sg * y0, sg * y1, sg * m0, sg * m1);
    let (c2, c3) = (
        -3.0 * y0 - 2.0 * m0 + 3.0 * y1 - m1,
        2.0 * y0 + m0 - 2.0 * y1 + m1,
    );
    let p = |s: f64| y0 + s * (m0 + s * (c2 + s * c3));
    let (mut mx, mut at) = if y0 >= y1 { (y0, 0.0) } else { (y1, 1.0) };
    // p′(s) = m0 + 2c2 s + 3c3 s² = 0 in (0, 1).
    let (qa, qb, qc) = (3.0 * c3, 2.0 * c2, m0);
    let roots: [f64; 2] = if qa.abs() < 1e-300 {
        [if qb != 0.0 { -qc / qb } else { -1.0 }, -1.0]
    } else {
        let disc = qb * qb - 4.0 * qa * qc;
        if disc < 0.0 {
            [-1.0, -1.0]
        } else {
            [
                (-qb + disc.sqrt()) / (2.0 * qa),
                (-qb - disc.sqrt()) / (2.0 * qa),
            ]
        }
    };
    for r in roots {
        if r > 0.0 && r < 1.0 && p(r) > mx {
            (mx, at) = (p(r), r);
        }
    }
    (mx.min(y0.max(y1) + loss), at)
}
