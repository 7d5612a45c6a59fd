//! What drives the simulated Cardan pendulum of a 3-D fit: the body rate w, its derivative
//! wd and the specific force at the pivot f, at every RK4 node (each sample and each
//! interval's middle), computed once from the log and kept.
//!
//! Both targets go through the replay's drive ([`crate::replay::Drive`]: w smoothed by a
//! zero-phase low-pass and splined, wd the spline's derivative, the specific force
//! interpolated linearly); they differ in what they hand it:
//! - [`Target::Gyro`]: the gyro (less its mean over an initial rest, when the log has one)
//!   and the accelerometer, as recorded.
//! - [`Target::Truth`]: w from the true roll and pitch (MODEL.md 7.1, the yaw rate from the
//!   gyro), and the specific force `g u(roll, pitch)` plus the accelerometer's part above
//!   [`super::Fit3dSettings::truth_accel_hz`] (its bias and slow errors replaced by the
//!   true gravity direction).
//!
//! The force is moved from the accelerometer to the pivot by MODEL.md 7.1's transport
//! over `r = r12 - accel_at`, which is linear in r: each node keeps the force for the held
//! part of r and the force per metre of r12_z, so that a fitted c_z costs no extra pass.
use crate::replay::drive::{fill_gaps, filtfilt, Drive, Rest, GYRO_CUTOFF_HZ};
use crate::sim::spatial::{specific_force_at, LogRow3d};

use super::super::{FitError, Target};
use super::Fit3dSettings;

/// One RK4 node: body rate, its derivative, the force at the pivot for c_z = 0 and the
/// force per metre of pivot offset along body z (all body axes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Node {
    pub w: [f64; 3],
    pub wd: [f64; 3],
    pub f0: [f64; 3],
    pub fz: [f64; 3],
}

/// The log's columns a 3-D fit reads, SI units, one entry per row.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Log3dColumns {
    /// t \[s\].
    pub t: Vec<f64>,
    /// Encoders (phi_x, phi_y) \[rad\].
    pub phi: Vec<[f64; 2]>,
    /// Gyro, body axes \[rad/s\].
    pub gyro: Vec<[f64; 3]>,
    /// Accelerometer, body axes \[m/s^2\].
    pub accel: Vec<[f64; 3]>,
    /// True (roll, pitch) \[rad\]; NaN where missing or without truth columns.
    pub truth: Vec<[f64; 2]>,
}

impl Log3dColumns {
    /// The columns of simulated or replayed log rows ([`LogRow3d`]).
    pub fn from_rows(rows: &[LogRow3d]) -> Self {
        Self {
            t: rows.iter().map(|r| r.t).collect(),
            phi: rows.iter().map(|r| r.phi).collect(),
            gyro: rows.iter().map(|r| r.gyro).collect(),
            accel: rows.iter().map(|r| r.accel).collect(),
            truth: rows.iter().map(|r| [r.roll, r.pitch]).collect(),
        }
    }

    /// Whether every row has a finite roll and pitch.
    pub fn has_truth(&self) -> bool {
        !self.truth.is_empty()
            && self
                .truth
                .iter()
                .all(|r| r[0].is_finite() && r[1].is_finite())
    }

    /// The leading run of rows with a finite, increasing time.
    pub(super) fn usable_rows(&self) -> usize {
        let mut n = 0;
        while n < self.t.len() && self.t[n].is_finite() && (n == 0 || self.t[n] > self.t[n - 1]) {
            n += 1;
        }
        n
    }
}

/// The world's up direction in body axes from roll and pitch, times `g` (MODEL.md 7.1).
fn gravity_force(roll: f64, pitch: f64, g: f64) -> [f64; 3] {
    let (sr, cr) = roll.sin_cos();
    let (sp, cp) = pitch.sin_cos();
    [-sp * g, cp * sr * g, cp * cr * g]
}

/// Central differences of `x` at times `t` (one-sided at the ends).
fn derivative(t: &[f64], x: &[f64]) -> Vec<f64> {
    let n = x.len();
    (0..n)
        .map(|k| {
            let (i, j) = (k.saturating_sub(1), (k + 1).min(n - 1));
            (x[j] - x[i]) / (t[j] - t[i])
        })
        .collect()
}

/// The centred moving average of `x` over `width` seconds (the window shrinks at the
/// ends): a low-pass without a start-up transient, which a recursive filter started on a
/// vibrating first sample would carry for several time constants.
fn moving_average(t: &[f64], x: &[f64], width: f64) -> Vec<f64> {
    let n = x.len();
    let mut prefix = Vec::with_capacity(n + 1);
    prefix.push(0.0);
    for v in x {
        prefix.push(prefix[prefix.len() - 1] + v);
    }
    let (mut lo, mut hi) = (0, 0);
    (0..n)
        .map(|k| {
            while t[k] - t[lo] > 0.5 * width {
                lo += 1;
            }
            while hi < n && t[hi] - t[k] <= 0.5 * width {
                hi += 1;
            }
            (prefix[hi] - prefix[lo]) / (hi - lo) as f64
        })
        .collect()
}

/// The truth target's rate and force at the samples: w from the smoothed true roll and
/// pitch and their rates (MODEL.md 7.1), the yaw rate from the gyro's inverse Euler relation
/// yaw' = (w_y sin r + w_z cos r) / cos p; the force g u plus the accelerometer's
/// high-frequency part (`hz` = 0: the whole accelerometer; infinite: gravity alone).
fn truth_inputs(
    log: &Log3dColumns,
    n: usize,
    gyro: &[[f64; 3]],
    accel: &[[f64; 3]],
    s: &Fit3dSettings,
    gravity: f64,
) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let t = &log.t[..n];
    let smooth = |i: usize| {
        let raw: Vec<f64> = log.truth[..n].iter().map(|r| r[i]).collect();
        filtfilt(t, &raw, s.smoothing_hz)
    };
    let (roll, pitch) = (smooth(0), smooth(1));
    let (droll, dpitch) = (derivative(t, &roll), derivative(t, &pitch));
    let w: Vec<[f64; 3]> = (0..n)
        .map(|k| {
            let (sr, cr) = roll[k].sin_cos();
            let (sp, cp) = pitch[k].sin_cos();
            let yaw_rate = (gyro[k][1] * sr + gyro[k][2] * cr) / cp;
            [
                droll[k] - yaw_rate * sp,
                dpitch[k] * cr + yaw_rate * cp * sr,
                -dpitch[k] * sr + yaw_rate * cp * cr,
            ]
        })
        .collect();
    let up: Vec<[f64; 3]> = (0..n)
        .map(|k| gravity_force(roll[k], pitch[k], gravity))
        .collect();
    let hz = s.truth_accel_hz;
    let f = if hz.is_infinite() {
        up
    } else {
        // The accelerometer's departure from g u, its slow part taken out.
        let rest: [Vec<f64>; 3] = core::array::from_fn(|i| {
            let d: Vec<f64> = (0..n).map(|k| accel[k][i] - up[k][i]).collect();
            if hz > 0.0 {
                let slow = moving_average(t, &d, 1.0 / hz);
                d.iter().zip(&slow).map(|(x, y)| x - y).collect()
            } else {
                d
            }
        });
        (0..n)
            .map(|k| core::array::from_fn(|i| up[k][i] + rest[i][k]))
            .collect()
    };
    (w, f)
}

/// The nodes of the first `n` rows: 2n - 1 of them (sample k at 2k, the middle of the
/// interval after it at 2k + 1), the force moved to the pivot for the held offset
/// `r_held` (r12 with its z part zero, less `accel_at`), and per metre of r12_z.
pub(super) fn nodes(
    log: &Log3dColumns,
    n: usize,
    s: &Fit3dSettings,
    r_held: [f64; 3],
    gravity: f64,
) -> Result<Vec<Node>, FitError> {
    let t = &log.t[..n];
    let (mut gyro, mut accel) = (log.gyro[..n].to_vec(), log.accel[..n].to_vec());
    fill_gaps(t, &mut gyro).ok_or(FitError::MissingColumn("gyro_x`, `gyro_y`, `gyro_z"))?;
    fill_gaps(t, &mut accel).ok_or(FitError::MissingColumn("ax`, `ay`, `az"))?;
    let fs = (n - 1) as f64 / (t[n - 1] - t[0]);
    let cutoff = GYRO_CUTOFF_HZ.min(0.4 * fs);
    let drive = match s.target {
        Target::Gyro => {
            let bias = Rest::find(t, &gyro, &accel, None).map_or([0.0; 3], |r| r.gyro_bias);
            Drive::new(t, &gyro, &accel, bias, cutoff, [0.0; 3])
        }
        Target::Truth => {
            let (w, f) = truth_inputs(log, n, &gyro, &accel, s, gravity);
            Drive::new(t, &w, &f, [0.0; 3], cutoff, [0.0; 3])
        }
    };
    let node = |k: usize, tau: f64| {
        let d = drive.at(k, tau);
        let f0 = specific_force_at(d.f, d.w, d.wd, r_held);
        let fz = specific_force_at([0.0; 3], d.w, d.wd, [0.0, 0.0, 1.0]);
        Node {
            w: d.w,
            wd: d.wd,
            f0,
            fz,
        }
    };
    let mut out = Vec::with_capacity(2 * n);
    for k in 0..n - 1 {
        out.push(node(k, 0.0));
        out.push(node(k, 0.5 * (t[k + 1] - t[k])));
    }
    out.push(node(n - 2, t[n - 1] - t[n - 2]));
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// At rest the force of g u is the accelerometer's reading (MODEL.md 7.1's roll and
    /// pitch from f invert it).
    #[test]
    fn gravity_force_inverts_the_tilt_formulas() {
        let (r, p) = (0.3, -0.2);
        let f = gravity_force(r, p, 9.8);
        assert!((f[1].atan2(f[2]) - r).abs() < 1e-12);
        assert!(((-f[0]).atan2(f[1].hypot(f[2])) - p).abs() < 1e-12);
        let n = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
        assert!((n - 9.8).abs() < 1e-12);
    }
}
