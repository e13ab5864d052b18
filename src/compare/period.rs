//! The carrier period of a track from its own frames: the lag `L` that brings the path back onto
//! itself, the minimum of the mean squared difference `d(L) = mean_i |p(t_i + L) − p(t_i)|²`
//! (the YIN difference function, de Cheveigné & Kawahara, JASA 111(4), 2002), computed for all
//! lags at once with an FFT: `d(L)·(n − L) = Σ|p_i|² + Σ|p_{i+L}|² − 2·Σ p_i·p_{i+L}`.

use crate::math::Point;
use realfft::RealFftPlanner;

/// Fewest overlapping samples at the period's lag: the record must run this much past a turn.
pub const MIN_OVERLAP: usize = 8;

/// The positions resampled on a uniform time grid of the median frame interval (linear
/// interpolation; the track has dropped frames or jitter), centred on their mean, and the step, s.
fn uniform(time_s: &[f64], pts: &[Point]) -> (Vec<Point>, f64) {
    let mut dt: Vec<f64> = time_s.windows(2).map(|w| w[1] - w[0]).collect();
    dt.sort_by(f64::total_cmp);
    let h = dt[dt.len() / 2];
    let n = ((time_s[time_s.len() - 1] - time_s[0]) / h).floor() as usize + 1;
    let mut out = Vec::with_capacity(n);
    let mut j = 0;
    for k in 0..n {
        let t = time_s[0] + k as f64 * h;
        while j + 2 < time_s.len() && time_s[j + 1] < t {
            j += 1;
        }
        let f = ((t - time_s[j]) / (time_s[j + 1] - time_s[j])).clamp(0.0, 1.0);
        out.push(pts[j].lerp(pts[j + 1], f));
    }
    let mean = out.iter().fold(Point::default(), |a, p| a + *p) / n as f64;
    (out.into_iter().map(|p| p - mean).collect(), h)
}

/// `Σ_i p_i·p_{i+L}` for every lag `L < n` (zero-padded real FFTs of x and y).
fn autocorrelation(p: &[Point]) -> Vec<f64> {
    let n = p.len();
    let m = (2 * n).next_power_of_two();
    let mut planner = RealFftPlanner::<f64>::new();
    let (fwd, inv) = (planner.plan_fft_forward(m), planner.plan_fft_inverse(m));
    let mut r = vec![0.0; n];
    for coord in [0, 1] {
        let mut buf = vec![0.0; m];
        for (b, q) in buf.iter_mut().zip(p) {
            *b = if coord == 0 { q.x } else { q.y };
        }
        let mut spec = fwd.make_output_vec();
        fwd.process(&mut buf, &mut spec)
            .expect("sizes from the plan");
        for c in &mut spec {
            *c *= c.conj();
        }
        inv.process(&mut spec, &mut buf)
            .expect("sizes from the plan");
        for (ri, b) in r.iter_mut().zip(&buf) {
            *ri += b / m as f64;
        }
    }
    r
}

/// The period (s) of the track `pts` at times `time_s`, or `None` when it never comes back onto
/// itself (less than a turn, a few [`MIN_OVERLAP`] samples more, of frames).
#[must_use]
pub fn period_s(time_s: &[f64], pts: &[Point]) -> Option<f64> {
    if pts.len() < 4 * MIN_OVERLAP {
        return None;
    }
    // A grid of the median interval longer than 8 frames a frame: the frames are not evenly
    // timed (a burst, then a gap), and no period is found in them.
    let mut dt: Vec<f64> = time_s.windows(2).map(|w| w[1] - w[0]).collect();
    dt.sort_by(f64::total_cmp);
    if (time_s[time_s.len() - 1] - time_s[0]) / dt[dt.len() / 2] > 8.0 * pts.len() as f64 {
        return None;
    }
    let (p, h) = uniform(time_s, pts);
    let n = p.len();
    let r = autocorrelation(&p);
    let mut prefix = vec![0.0; n + 1];
    for (k, q) in p.iter().enumerate() {
        prefix[k + 1] = prefix[k] + q.norm_squared();
    }
    let last = n.checked_sub(MIN_OVERLAP)?;
    let d: Vec<f64> = (0..=last)
        .map(|l| {
            let e = prefix[n - l] + (prefix[n] - prefix[l]);
            ((e - 2.0 * r[l]) / (n - l) as f64).max(0.0)
        })
        .collect();
    let dmax = d.iter().copied().fold(0.0, f64::max);
    // Past the lag where the track has moved far from itself, the first deep minimum.
    let l0 = d.iter().position(|&v| v >= 0.5 * dmax)?;
    let tail = &d[l0..];
    let lo = tail.iter().copied().fold(f64::INFINITY, f64::min);
    let mut sorted = tail.to_vec();
    sorted.sort_by(f64::total_cmp);
    let median = sorted[sorted.len() / 2];
    let mut l = l0 + tail.iter().position(|&v| v <= lo + 0.1 * (median - lo))?;
    while l + 1 < d.len() && d[l + 1] < d[l] {
        l += 1;
    }
    // Back onto itself: within a tenth of the track's size.
    let size2 = prefix[n] / n as f64;
    if d[l] > 0.01 * size2 || l == 0 || l + 1 >= d.len() {
        return None;
    }
    let (a, b, c) = (d[l - 1], d[l], d[l + 1]);
    let den = a - 2.0 * b + c;
    let shift = if den > 0.0 { 0.5 * (a - c) / den } else { 0.0 };
    Some((l as f64 + shift.clamp(-0.5, 0.5)) * h)
}
