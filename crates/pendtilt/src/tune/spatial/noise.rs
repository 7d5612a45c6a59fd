//! The 3-D log's sensor noise, axis by axis, with the planar tune's estimators: the
//! encoder's step and noise ([`crate::tune::encoder`]) on `phi_x` and `phi_y`, the gyro's
//! density and bias ([`crate::tune::gyro`]: still stretches, else the spectrum's top band)
//! on each axis, the accelerometer's noise floor and vibration bands
//! ([`crate::tune::accel`]) on `ax`, `ay`, and the speed's white noise (the second
//! differences of [`crate::tune::encoder::estimate`]: a vehicle's speed is smooth at the
//! sample rate).
//!
//! The gyro's x and y axes are tested for rest against the encoder of the same axis (the
//! pendulum follows roll and pitch); z against both (a yaw turn leaves the pendulum
//! still, but no still stretch is taken where the body tilts).
use crate::tune::accel::{self, AccelNoise};
use crate::tune::encoder::{self, EncoderNoise};
use crate::tune::gyro::{self, GyroNoise};
use pendtilt_core::spatial::SpatialSample;

/// What the log tells of its sensors.
#[derive(Debug, Clone)]
pub struct Noise3d {
    /// The encoders, `[phi_x, phi_y]`.
    pub encoder: [Result<EncoderNoise, String>; 2],
    /// The gyro, `[x, y, z]`.
    pub gyro: [Result<GyroNoise, String>; 3],
    /// The accelerometer (x and y: the axes across the pendulum).
    pub accel: Result<AccelNoise, String>,
    /// The speed's white noise \[m/s\]; `None` when the log has no speed.
    pub speed: Option<Result<f64, String>>,
}

/// One column of the samples.
pub(super) fn column(
    samples: &[SpatialSample<f64>],
    f: impl Fn(&SpatialSample<f64>) -> f64,
) -> Vec<f64> {
    samples.iter().map(f).collect()
}

/// Estimates every sensor's noise on `samples` at `rate` \[Hz\], for a pendulum whose
/// lower natural frequency is `f_n` \[Hz\].
pub fn estimate(samples: &[SpatialSample<f64>], rate: f64, f_n: f64) -> Noise3d {
    let phi = [0, 1].map(|i| column(samples, |s| s.phi[i]));
    let g = [0, 1, 2].map(|i| column(samples, |s| s.gyro[i]));
    // For z: a window is steady only when both encoders are (NaN where either moves is
    // too strict; the sum of the two moves whenever either does).
    let both: Vec<f64> = phi[0].iter().zip(&phi[1]).map(|(a, b)| a + b).collect();
    let gyro = [
        gyro::estimate(&g[0], &phi[0], rate),
        gyro::estimate(&g[1], &phi[1], rate),
        gyro::estimate(&g[2], &both, rate).map(|mut z| {
            // The pendulum's slope says nothing of a yaw bias.
            if z.still_seconds < 2.0 {
                z.bias = None;
                z.method = z.method.replace(
                    "bias: slope of the gyro's integral minus phi",
                    "no bias (the encoders do not see yaw)",
                );
            }
            z
        }),
    ];
    let ax = column(samples, |s| s.accel[0]);
    let ay = column(samples, |s| s.accel[1]);
    let speed = column(samples, |s| s.speed);
    let has_speed = speed.iter().filter(|v| v.is_finite()).count() >= encoder::MIN_READINGS;
    Noise3d {
        encoder: phi.map(|p| encoder::estimate(&p)),
        gyro,
        accel: accel::estimate(&ax, &ay, rate, f_n),
        speed: has_speed.then(|| encoder::estimate(&speed).map(|e| e.white)),
    }
}
