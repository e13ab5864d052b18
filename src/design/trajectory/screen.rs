//! What the points say about themselves before any design: outliers (typos) and the noise level.

use super::dist;

/// The first point that jumps far off the curve and back: both its steps exceed 50× the median
/// spacing (and 1000× the distance between its two neighbours plus one spacing). Returns
/// `(index, nearer step, neighbour distance, median spacing)`, mm.
pub(super) fn outlier(points: &[[f64; 2]]) -> Option<(usize, f64, f64, f64)> {
    let n = points.len();
    if n < 3 {
        return None;
    }
    let steps: Vec<f64> = (0..n)
        .map(|k| dist(points[k], points[(k + 1) % n]))
        .collect();
    let mut sorted = steps.clone();
    sorted.sort_by(f64::total_cmp);
    let spacing = sorted[n / 2];
    (0..n).find_map(|k| {
        let (before, after) = (steps[(k + n - 1) % n], steps[k]);
        let jump = before.min(after);
        let between = dist(points[(k + n - 1) % n], points[(k + 1) % n]);
        (jump > 50.0 * spacing && jump > 1000.0 * (between + spacing))
            .then_some((k, jump, between, spacing))
    })
}

/// Median over the points of the local cubic-fit residual (9-point windows, chord-length
/// parameter, both coordinates, 10 degrees of freedom), corrected to a standard deviation: an
/// estimate of the measurement noise σ (mm) that needs no model of the curve. On exact samples of a
/// smooth curve it is the cubic's truncation error (µm for 200+ points on a transplanter loop).
pub(super) fn local_cubic_noise_mm(points: &[[f64; 2]]) -> f64 {
    let n = points.len();
    if n < 9 {
        return 0.0;
    }
    let mut rss: Vec<f64> = (0..n)
        .map(|k| {
            // Window k−4..k+4, parameter u = chord length from the centre, scaled to O(1).
            let idx: Vec<usize> = (0..9).map(|j| (k + n + j - 4) % n).collect();
            let mut u = [0.0; 9];
            for j in 5..9 {
                u[j] = u[j - 1] + dist(points[idx[j - 1]], points[idx[j]]);
            }
            for j in (0..4).rev() {
                u[j] = u[j + 1] - dist(points[idx[j + 1]], points[idx[j]]);
            }
            let scale = (u[8] - u[0]).max(1e-300) / 2.0;
            let mut a = nalgebra::Matrix4::<f64>::zeros();
            let mut bx = nalgebra::Vector4::<f64>::zeros();
            let mut by = nalgebra::Vector4::<f64>::zeros();
            for j in 0..9 {
                let t = u[j] / scale;
                let v = nalgebra::Vector4::new(1.0, t, t * t, t * t * t);
                a += v * v.transpose();
                bx += v * points[idx[j]][0];
                by += v * points[idx[j]][1];
            }
            let Some(ch) = a.cholesky() else { return 0.0 };
            let (cx, cy) = (ch.solve(&bx), ch.solve(&by));
            (0..9)
                .map(|j| {
                    let t = u[j] / scale;
                    let v = nalgebra::Vector4::new(1.0, t, t * t, t * t * t);
                    (points[idx[j]][0] - v.dot(&cx)).powi(2)
                        + (points[idx[j]][1] - v.dot(&cy)).powi(2)
                })
                .sum::<f64>()
        })
        .collect();
    rss.sort_by(f64::total_cmp);
    // Median of χ²₁₀/10 is 0.9342.
    (rss[n / 2] / 10.0 / 0.9342).sqrt()
}
