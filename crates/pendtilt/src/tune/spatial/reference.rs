//! The gyro as a reference for ekf3d's up direction where no true attitude exists (the
//! 3-D form of [`crate::tune::reference`]).
//!
//! The world's up direction seen from the body turns with the body: `u' = u x w`, `w` the
//! gyro less its bias. Started from the filter's own `u` at the start of a window of
//! [`WINDOW_SECONDS`], the gyro carries it through the window; the difference from the
//! filter's `u`, its straight-line trend removed per component (the start's error and the
//! bias error's drift, both slow), is the filter's own error faster than the window: its
//! delay, its noise, and what vibration or an unpredicted force makes it follow. The
//! slow part (what the pendulum is there for) is not seen: a filter that trusts the gyro
//! more always scores better here, so this alone does not choose the process noise.
use nalgebra::Vector3;
use pendtilt_core::spatial::ekf::{Ekf, Settings};
use pendtilt_core::spatial::SpatialSample;
use pendtilt_core::Estimator;

/// Length of the windows \[s\].
pub const WINDOW_SECONDS: f64 = 5.0;

/// ekf3d with `settings` on `samples`: its up direction and gyro bias per row (NaN before
/// it starts).
pub fn run(
    settings: &Settings<f64>,
    samples: &[SpatialSample<f64>],
) -> Vec<(Vector3<f64>, Vector3<f64>)> {
    let mut ekf = Ekf::new(*settings);
    samples
        .iter()
        .map(|s| {
            let a = ekf.update(s);
            let u = a.up();
            let b = ekf.state().map_or(Vector3::repeat(f64::NAN), |x| x.bias);
            (Vector3::new(u[0], u[1], u[2]), b)
        })
        .collect()
}

/// RMS \[rad\] of the filter's detrended difference from the gyro's up direction (module
/// documentation), rows before `skip` left out; infinite when no window could be scored.
pub fn band_error(
    est: &[(Vector3<f64>, Vector3<f64>)],
    samples: &[SpatialSample<f64>],
    rate: f64,
    skip: usize,
) -> f64 {
    let w = ((WINDOW_SECONDS * rate).round() as usize).max(16);
    let (mut sum, mut n) = (0.0, 0usize);
    let mut k0 = skip;
    while k0 + w <= est.len().min(samples.len()) {
        if let Some((s, m)) = window(&est[k0..k0 + w], &samples[k0..k0 + w]) {
            sum += s;
            n += m;
        }
        k0 += w;
    }
    if n == 0 {
        f64::INFINITY
    } else {
        (sum / n as f64).sqrt()
    }
}

/// One window's sum of squared detrended differences and its row count.
fn window(
    est: &[(Vector3<f64>, Vector3<f64>)],
    samples: &[SpatialSample<f64>],
) -> Option<(f64, usize)> {
    let (u0, bias) = est[0];
    if !(u0.iter().all(|v| v.is_finite()) && bias.iter().all(|v| v.is_finite())) {
        return None;
    }
    let mut u = u0;
    let mut d = Vec::with_capacity(est.len());
    for (k, ((ue, _), s)) in est.iter().zip(samples).enumerate() {
        if k > 0 {
            let g = Vector3::new(s.gyro[0], s.gyro[1], s.gyro[2]) - bias;
            if g.iter().all(|v| v.is_finite()) && s.dt.is_finite() && s.dt > 0.0 {
                // The exact rotation of u by -g dt (u turns opposite to the body).
                let angle = g.norm() * s.dt;
                if angle > 0.0 {
                    let axis = g / g.norm();
                    let r = nalgebra::Rotation3::from_axis_angle(
                        &nalgebra::Unit::new_unchecked(axis),
                        -angle,
                    );
                    u = r * u;
                }
            }
        }
        if !ue.iter().all(|v| v.is_finite()) {
            return None;
        }
        d.push(ue - u);
    }
    let n = d.len() as f64;
    let mt = (n - 1.0) / 2.0;
    let stt: f64 = (0..d.len()).map(|k| (k as f64 - mt).powi(2)).sum();
    let mut total = 0.0;
    for c in 0..3 {
        let m = d.iter().map(|x| x[c]).sum::<f64>() / n;
        let slope = d
            .iter()
            .enumerate()
            .map(|(k, x)| (k as f64 - mt) * (x[c] - m))
            .sum::<f64>()
            / stt;
        total += d
            .iter()
            .enumerate()
            .map(|(k, x)| (x[c] - m - slope * (k as f64 - mt)).powi(2))
            .sum::<f64>();
    }
    Some((total, d.len()))
}
