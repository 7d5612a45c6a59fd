//! The gyro's integral as a reference for the tilt in a band, where no true angle exists.
//!
//! The gyro reads theta' exactly but for its bias and noise, so its running integral is
//! the tilt up to a slow drift (the bias error integrated, and the unknown start). Above
//! a corner `f_hp` the drift is gone: `HP(theta_est - int gyro)` is the estimator's own
//! error in that band, measured without a true angle. The high-pass is the complement of
//! a 2nd-order low-pass (`x - LP(x)`, which removes constants and slow drift); 0.2 Hz
//! keeps the delay and vibration errors of Algorithms 1-2 (the tilt's fast part and the
//! vibration) and leaves out only the slowest tilt, where their errors are small (a delay
//! error grows with frequency).
use pendtilt_core::filters::biquad::LowPass2;
use pendtilt_core::Sample;

/// Corner of the high-pass \[Hz\].
pub const CORNER_HZ: f64 = 0.2;

/// The gyro's running integral minus `bias` \[rad\] (a missing reading takes the last
/// good one).
pub fn integral(samples: &[Sample<f64>], bias: f64) -> Vec<f64> {
    let (mut acc, mut last) = (0.0, 0.0);
    samples
        .iter()
        .map(|s| {
            if s.gyro.is_finite() {
                last = s.gyro;
            }
            if s.dt.is_finite() && s.dt > 0.0 {
                acc += s.dt * (last - bias);
            }
            acc
        })
        .collect()
}

/// RMS \[rad\] of `HP(est - reference)` from row `skip` on, rows with a non-finite
/// estimate left out (the filter holds its state across them); infinite if none.
pub fn band_error(est: &[f64], reference: &[f64], samples: &[Sample<f64>], skip: usize) -> f64 {
    let mut lp = LowPass2::new(CORNER_HZ);
    let (mut sum, mut sum2, mut n) = (0.0, 0.0, 0usize);
    let mut started = false;
    for (k, ((e, r), s)) in est.iter().zip(reference).zip(samples).enumerate() {
        let d = e - r;
        if !d.is_finite() {
            continue;
        }
        let dt = if started { s.dt.max(0.0) } else { 0.0 };
        started = true;
        let hp = d - lp.update(d, dt);
        if k >= skip {
            sum += hp;
            sum2 += hp * hp;
            n += 1;
        }
    }
    if n == 0 {
        return f64::INFINITY;
    }
    let m = sum / n as f64;
    (sum2 / n as f64 - m * m).max(0.0).sqrt()
}

/// RMS \[rad\] of the gyro's integral (less `bias`) above [`CORNER_HZ`] from row `skip` on:
/// how much the tilt moves in the band where a differentiator's delay shows.
pub fn band_motion(samples: &[Sample<f64>], bias: f64, skip: usize) -> f64 {
    let reference = integral(samples, bias);
    band_error(&vec![0.0; samples.len()], &reference, samples, skip)
}
