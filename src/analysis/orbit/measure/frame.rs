//! The sensor frame (docs/math/companion.md §A.7) and the sample-wise conversions to the analysis frame: mean/drift
//! removal and rotation by the carrier angle.

/// Frame of the sensors and how to get to the carrier frame (docs/math/companion.md §A.7).
#[derive(
    Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Frame {
    /// Sensors fixed to the carrier, or carrier held (star arrangement / test rig).
    Carrier,
    /// Housing-fixed sensors, de-rotated with the recorded carrier angle (option a).
    HousingDerotate,
    /// Housing-fixed sensors, carrier at constant signed speed `carrier_rad_s`; Z± read in the
    /// complex spectrum at `ω_c ± ω_p` (option b).
    HousingFullSpectrum {
        /// Signed carrier speed ω_c, rad/s.
        carrier_rad_s: f64,
    },
}

/// Rotates `(x, y)` by `sign·θ_k` sample by sample (`sign = −1`: housing → carrier).
pub(super) fn rotate(x: &[f64], y: &[f64], theta: &[f64], sign: f64) -> (Vec<f64>, Vec<f64>) {
    let mut ox = Vec::with_capacity(x.len());
    let mut oy = Vec::with_capacity(x.len());
    for k in 0..x.len() {
        let (s, c) = (sign * theta[k]).sin_cos();
        ox.push(c * x[k] - s * y[k]);
        oy.push(s * x[k] + c * y[k]);
    }
    (ox, oy)
}

/// Removes the mean, and a least-squares line when `drift`.
pub(super) fn detrend(t: &[f64], x: &[f64], y: &[f64], drift: bool) -> (Vec<f64>, Vec<f64>) {
    let n = t.len() as f64;
    let tm = t.iter().sum::<f64>() / n;
    let stt: f64 = t.iter().map(|v| (v - tm).powi(2)).sum();
    let one = |v: &[f64]| -> Vec<f64> {
        let m = v.iter().sum::<f64>() / n;
        let slope = if drift {
            t.iter()
                .zip(v)
                .map(|(a, b)| (a - tm) * (b - m))
                .sum::<f64>()
                / stt
        } else {
            0.0
        };
        t.iter()
            .zip(v)
            .map(|(a, b)| b - m - slope * (a - tm))
            .collect()
    };
    (one(x), one(y))
}
