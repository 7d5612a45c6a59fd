//! Accelerometer noise and the vibration level per band, from the spectrum of the
//! specific force (`ax`, `ay`).
//!
//! - Noise floor: the median of each axis' spectrum over 0.3-0.45 of the sample rate
//!   (`d = sqrt(P / 2)`, as for the gyro). With floor vibration reaching that band it is
//!   the vibration's level there, an upper bound on the sensor's own noise; the bands
//!   below tell which.
//! - Vibration: the RMS of each axis in bands above the pendulum's band (twice its
//!   natural frequency, at least 1 Hz: below it the body's tilt moves the reading), and in
//!   all of them together, which is what the EKF's accelerometer model adds to its noise.
//! - The density across the pendulum near its natural frequency: the spectrum of `ax`
//!   within a third of an octave of f_n, the start the EKF's pendulum process noise is
//!   derived from ([`pendtilt_core::ekf::Environment::vibration_density`]).
use super::spectrum::{segment_for, welch, Psd};

/// One band's vibration level.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BandLevel {
    /// Band edges \[Hz\].
    pub band: [f64; 2],
    /// RMS on body x and y \[m/s^2\].
    pub rms: [f64; 2],
}

/// What the log tells of its accelerometer and the vibration it reads.
#[derive(Debug, Clone, PartialEq)]
pub struct AccelNoise {
    /// Noise floor density, the mean of the two axes \[m/s^2/sqrt(Hz)\].
    pub density: f64,
    /// The bands above the pendulum's band.
    pub bands: Vec<BandLevel>,
    /// RMS above the pendulum's band, the larger axis \[m/s^2\].
    pub vibration_rms: f64,
    /// Density of `ax` near the pendulum's natural frequency \[m/s^2/sqrt(Hz)\].
    pub density_near_natural: f64,
    /// Lower edge of the bands \[Hz\].
    pub pendulum_band: f64,
}

/// Estimates the accelerometer's noise and the vibration from `ax`, `ay` at `rate` for a
/// pendulum of natural frequency `f_n` \[Hz\].
pub fn estimate(ax: &[f64], ay: &[f64], rate: f64, f_n: f64) -> Result<AccelNoise, String> {
    let seg = segment_for(rate);
    let px = welch(ax, rate, seg);
    let py = welch(ay, rate, seg);
    let (Some(px), Some(py)) = (px, py) else {
        return Err("too short for an accelerometer spectrum (2 s needed)".to_string());
    };
    let nyq = 0.5 * rate;
    let floor = |p: &Psd| {
        p.band_median(0.3 * rate, 0.45 * rate)
            .map(|m| (m / 2.0).sqrt())
    };
    let (Some(dx), Some(dy)) = (floor(&px), floor(&py)) else {
        return Err("no high band in the accelerometer spectrum".to_string());
    };
    let lo = (2.0 * f_n).max(1.0);
    let mut edges = vec![lo];
    for e in [10.0, 30.0, 100.0, 300.0] {
        if e > lo && e < nyq {
            edges.push(e);
        }
    }
    edges.push(nyq);
    let bands = edges
        .windows(2)
        .map(|w| BandLevel {
            band: [w[0], w[1]],
            rms: [
                px.band_power(w[0], w[1]).sqrt(),
                py.band_power(w[0], w[1]).sqrt(),
            ],
        })
        .collect();
    let vibration_rms = px
        .band_power(lo, nyq + 1.0)
        .max(py.band_power(lo, nyq + 1.0))
        .sqrt();
    let third = 2f64.powf(1.0 / 6.0);
    let near = px
        .band_median(f_n / third, (f_n * third).max(f_n / third + 2.0 * px.df))
        .unwrap_or(0.0)
        .sqrt();
    Ok(AccelNoise {
        density: 0.5 * (dx + dy),
        bands,
        vibration_rms,
        density_near_natural: near,
        pendulum_band: lo,
    })
}
