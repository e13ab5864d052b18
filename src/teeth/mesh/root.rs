//! The root search of the mesh check on per-vertex clearances: the minimum over the vertices,
//! and Illinois regula falsi pruning the vertices that cannot be the minimiser.

/// Minimum of all per-vertex clearances, mm.
pub(super) fn min_of(v: &PerVertex) -> f64 {
    v.0.iter()
        .chain(v.1.iter())
        .copied()
        .fold(f64::INFINITY, f64::min)
}

pub(super) type PerVertex = (Vec<f64>, Vec<f64>);

/// Vertex sets of both gears (polar indices).
pub(super) type VertexSets = (Vec<usize>, Vec<usize>);

/// The entries of `set` whose clearance `c` (same order, mm) is at most `thresh`: the Lipschitz
/// pruning of the root searches.
pub(super) fn keep(set: &[usize], c: &[f64], thresh: f64) -> Vec<usize> {
    set.iter()
        .zip(c)
        .filter(|(_, c)| **c <= thresh)
        .map(|(i, _)| *i)
        .collect()
}

/// Per-vertex clearances at a driven offset δ (rad) for two vertex sets.
type ClearanceFn<'a> = dyn Fn(f64, &[usize], &[usize]) -> PerVertex + 'a;

/// A driven offset whose minimum clearance is within this of 0 (mm) is a contact root: far below
/// the backlash and clearances reported (µm); about 2e-12 rad of transmission error at a clearance
/// slope of 6 mm/rad.
pub(super) const ROOT_VALUE_MM: f64 = 1e-11;

/// Root of the minimum clearance over the vertex sets `[k1, k2]` of the two gears on the bracket
/// `[lo, hi]` (driven offsets, rad) (Illinois regula falsi), to `tol` (rad), pruning after each
/// evaluation the vertices that cannot be the minimiser anywhere in the bracket: a vertex's
/// clearance changes by at most `lip·|Δδ|` (mm/rad), so it is dropped when
/// `c_i(x) > min c(x) + 2·lip·(hi − lo)`.
/// Returns the root and the secant slope (mm/rad) of the last two evaluations.
pub(super) fn root_pruned(
    f: &ClearanceFn<'_>,
    [k1, k2]: [&[usize]; 2],
    [mut lo, mut hi]: [f64; 2],
    lip: f64,
    tol: f64,
) -> Option<(f64, f64)> {
    let mut s1 = k1.to_vec();
    let mut s2 = k2.to_vec();
    let (mut flo, mut fhi) = (min_of(&f(lo, &s1, &s2)), min_of(&f(hi, &s1, &s2)));
    if flo * fhi > 0.0 {
        return None;
    }
    // The last two evaluations (Illinois scales the bracket's values; these are the true ones).
    let mut last = [(lo, flo), (hi, fhi)];
    let slope = |l: &[(f64, f64); 2]| (l[1].1 - l[0].1) / (l[1].0 - l[0].0);
    let mut side = 0i8;
    for _ in 0..100 {
        let x = (lo * fhi - hi * flo) / (fhi - flo);
        let x = if x.is_finite() && x > lo && x < hi {
            x
        } else {
            0.5 * (lo + hi)
        };
        let v = f(x, &s1, &s2);
        let fx = min_of(&v);
        last = [last[1], (x, fx)];
        if fx * fhi > 0.0 {
            hi = x;
            fhi = fx;
            if side == 1 {
                flo *= 0.5;
            }
            side = 1;
        } else {
            lo = x;
            flo = fx;
            if side == -1 {
                fhi *= 0.5;
            }
            side = -1;
        }
        if hi - lo <= tol || fx.abs() <= ROOT_VALUE_MM {
            return Some((x, slope(&last)));
        }
        let thresh = fx + 2.0 * lip * (hi - lo);
        (s1, s2) = (keep(&s1, &v.0, thresh), keep(&s2, &v.1, thresh));
    }
    Some((0.5 * (lo + hi), slope(&last)))
}
