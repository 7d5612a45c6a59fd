//! The drive of a replay (MODEL.md 7.10): the recorded gyro and specific force turned into
//! the body rate w(t), its derivative wd(t) and the specific force at the pivot f(t) that
//! the joint equations of 7.3 take, at any time inside the recording.
//!
//! - The gyro's bias over the initial rest is removed, the rate smoothed by a zero-phase
//!   2nd-order Butterworth low-pass and interpolated by a natural cubic spline; wd is the
//!   spline's derivative, so that w and wd are consistent (integrating wd gives w back).
//! - The specific force is interpolated linearly and moved from the IMU (P1) to the pivot
//!   with 7.1's rigid-body transport.
use pendtilt_core::filters::biquad::LowPass2;

use crate::sim::spatial::specific_force_at;

/// Cutoff of the gyro's zero-phase low-pass \[Hz\] (MODEL.md 7.10): 40 Hz, or 0.4 of the
/// sampling rate when that is lower. Above 40 Hz a hand-held or vehicle body's rate is
/// noise and vibration that a spline would turn into large, spurious wd.
pub const GYRO_CUTOFF_HZ: f64 = 40.0;

/// A natural cubic spline through (t_k, y_k): its value and derivative anywhere inside.
#[derive(Debug, Clone)]
pub struct Spline {
    /// Second derivatives at the knots.
    m: Vec<f64>,
}

impl Spline {
    /// The natural spline (zero second derivative at both ends) through `y` at times `t`
    /// (strictly increasing, as long as `y`). Fewer than 3 knots give the straight line.
    pub fn natural(t: &[f64], y: &[f64]) -> Self {
        let n = t.len();
        let mut m = vec![0.0; n];
        if n < 3 {
            return Self { m };
        }
        // Tridiagonal system for the inner second derivatives (Thomas algorithm).
        let mut c = vec![0.0; n];
        let mut d = vec![0.0; n];
        for i in 1..n - 1 {
            let h0 = t[i] - t[i - 1];
            let h1 = t[i + 1] - t[i];
            let a = h0 / 6.0;
            let b = (h0 + h1) / 3.0;
            let cc = h1 / 6.0;
            let r = (y[i + 1] - y[i]) / h1 - (y[i] - y[i - 1]) / h0;
            let den = b - a * c[i - 1];
            c[i] = cc / den;
            d[i] = (r - a * d[i - 1]) / den;
        }
        for i in (1..n - 1).rev() {
            m[i] = d[i] - c[i] * m[i + 1];
        }
        Self { m }
    }

    /// Value and derivative on the interval [t_k, t_k+1] at `tau` seconds after t_k.
    #[inline]
    pub fn eval(&self, t: &[f64], y: &[f64], k: usize, tau: f64) -> (f64, f64) {
        let h = t[k + 1] - t[k];
        let (m0, m1) = (self.m[k], self.m[k + 1]);
        let a = (h - tau) / h;
        let b = tau / h;
        let v =
            a * y[k] + b * y[k + 1] + ((a * a * a - a) * m0 + (b * b * b - b) * m1) * h * h / 6.0;
        let dv = (y[k + 1] - y[k]) / h
            + (-(3.0 * a * a - 1.0) * m0 + (3.0 * b * b - 1.0) * m1) * h / 6.0;
        (v, dv)
    }
}

/// Zero-phase low-pass of `y` sampled at `t`: the 2nd-order Butterworth run forward, then
/// backward over the result (the squared magnitude response, no delay).
pub fn filtfilt(t: &[f64], y: &[f64], cutoff_hz: f64) -> Vec<f64> {
    let n = y.len();
    let mut out = vec![0.0; n];
    if n == 0 {
        return out;
    }
    let mut lp = LowPass2::new(cutoff_hz);
    for k in 0..n {
        let dt = if k == 0 {
            t.get(1).map_or(1.0, |t1| t1 - t[0])
        } else {
            t[k] - t[k - 1]
        };
        out[k] = lp.update(y[k], dt);
    }
    let mut lp = LowPass2::new(cutoff_hz);
    for k in (0..n).rev() {
        let dt = if k + 1 == n {
            if n > 1 {
                t[n - 1] - t[n - 2]
            } else {
                1.0
            }
        } else {
            t[k + 1] - t[k]
        };
        out[k] = lp.update(out[k], dt);
    }
    out
}

/// The initial rest of a recording: where it ends, the gyro's mean over it (its bias) and
/// the mean magnitude of the specific force over it (the g that drives the pendulum).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rest {
    /// Index of the first row after the rest (the first movement).
    pub end: usize,
    /// The gyro's mean over the rest \[rad/s\] (zero when there was no rest).
    pub gyro_bias: [f64; 3],
    /// The mean |a| over the rest \[m/s^2\].
    pub gravity: f64,
}

/// Shortest stretch that counts as an initial rest \[s\]: long enough for the bias's mean
/// to beat a MEMS gyro's white noise by 20x at 100 Hz.
pub const MIN_REST_S: f64 = 0.5;

/// A row belongs to the rest while its gyro stays within this of the rest's mean so far
/// \[rad/s\] (3 deg/s: a hand holding still moves by less, a deliberate motion by more).
pub const REST_GYRO: f64 = 0.05;

/// ... and its |a| within this of the rest's mean |a| so far \[m/s^2\].
pub const REST_ACCEL: f64 = 0.5;

impl Rest {
    /// The rest found from the start of the recording, or, when `movement` is given (the
    /// index of the first movement sample, as BROAD marks it), the rows before it.
    /// `None` when the recording does not start at rest for at least [`MIN_REST_S`].
    pub fn find(
        t: &[f64],
        gyro: &[[f64; 3]],
        accel: &[[f64; 3]],
        movement: Option<usize>,
    ) -> Option<Rest> {
        let n = t.len();
        let norm = |a: &[f64; 3]| (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        let (mut sg, mut sa, mut count) = ([0.0; 3], 0.0, 0usize);
        let mut end = 0;
        while end < n && movement.is_none_or(|m| end < m) {
            let (g, a) = (gyro[end], accel[end]);
            if !(g.iter().all(|x| x.is_finite()) && a.iter().all(|x| x.is_finite())) {
                end += 1;
                continue;
            }
            if movement.is_none() && count > 0 {
                let c = count as f64;
                let moved = (0..3).any(|i| (g[i] - sg[i] / c).abs() > REST_GYRO);
                if moved || (norm(&a) - sa / c).abs() > REST_ACCEL {
                    break;
                }
            }
            for i in 0..3 {
                sg[i] += g[i];
            }
            sa += norm(&a);
            count += 1;
            end += 1;
        }
        if count == 0 || end == 0 || t[end - 1] - t[0] < MIN_REST_S - 1e-9 {
            return None;
        }
        let c = count as f64;
        Some(Rest {
            end,
            gyro_bias: sg.map(|x| x / c),
            gravity: sa / c,
        })
    }
}

/// The body's motion between the recorded samples: w, wd and f at the pivot.
#[derive(Debug, Clone)]
pub struct Drive {
    t: Vec<f64>,
    w: [Vec<f64>; 3],
    spline: [Spline; 3],
    f: Vec<[f64; 3]>,
    pivot_offset: [f64; 3],
}

/// The body's kinematics at one instant, body axes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DriveAt {
    /// Body rate w \[rad/s\].
    pub w: [f64; 3],
    /// Its derivative wd \[rad/s^2\].
    pub wd: [f64; 3],
    /// Specific force at the pivot P2 \[m/s^2\].
    pub f: [f64; 3],
}

impl Drive {
    /// The drive of a recording at times `t` (strictly increasing, at least 2 rows): the
    /// gyro less `gyro_bias`, smoothed at `cutoff_hz` and splined; the specific force at
    /// P1 moved to the pivot at `pivot_offset` (r12, body axes \[m\]). Every value must be
    /// finite (fill gaps first: [`fill_gaps`]).
    pub fn new(
        t: &[f64],
        gyro: &[[f64; 3]],
        accel: &[[f64; 3]],
        gyro_bias: [f64; 3],
        cutoff_hz: f64,
        pivot_offset: [f64; 3],
    ) -> Self {
        let w: [Vec<f64>; 3] = core::array::from_fn(|i| {
            let raw: Vec<f64> = gyro.iter().map(|g| g[i] - gyro_bias[i]).collect();
            filtfilt(t, &raw, cutoff_hz)
        });
        let spline = core::array::from_fn(|i| Spline::natural(t, &w[i]));
        Self {
            t: t.to_vec(),
            w,
            spline,
            f: accel.to_vec(),
            pivot_offset,
        }
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// True when there is no sample.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// The sample times \[s\].
    pub fn times(&self) -> &[f64] {
        &self.t
    }

    /// The smoothed body rate at sample `k` \[rad/s\].
    pub fn rate(&self, k: usize) -> [f64; 3] {
        core::array::from_fn(|i| self.w[i][k])
    }

    /// w, wd and f at `tau` seconds into the interval that starts at sample `k`
    /// (0 <= tau <= t_k+1 - t_k).
    #[inline]
    pub fn at(&self, k: usize, tau: f64) -> DriveAt {
        let mut w = [0.0; 3];
        let mut wd = [0.0; 3];
        for i in 0..3 {
            (w[i], wd[i]) = self.spline[i].eval(&self.t, &self.w[i], k, tau);
        }
        let s = tau / (self.t[k + 1] - self.t[k]);
        let f1: [f64; 3] =
            core::array::from_fn(|i| self.f[k][i] + s * (self.f[k + 1][i] - self.f[k][i]));
        DriveAt {
            w,
            wd,
            f: specific_force_at(f1, w, wd, self.pivot_offset),
        }
    }
}

/// Fills the non-finite values of `x` (per component) by linear interpolation between the
/// nearest finite neighbours (held at the ends); returns how many values were filled, or
/// `None` when a component has no finite value at all.
pub fn fill_gaps(t: &[f64], x: &mut [[f64; 3]]) -> Option<usize> {
    let mut filled = 0;
    for i in 0..3 {
        let good: Vec<usize> = (0..x.len()).filter(|&k| x[k][i].is_finite()).collect();
        let (&first, &last) = (good.first()?, good.last()?);
        let mut g = 0;
        for k in 0..x.len() {
            if x[k][i].is_finite() {
                continue;
            }
            filled += 1;
            if k < first {
                x[k][i] = x[first][i];
            } else if k > last {
                x[k][i] = x[last][i];
            } else {
                while good[g + 1] < k {
                    g += 1;
                }
                let (k0, k1) = (good[g], good[g + 1]);
                let s = (t[k] - t[k0]) / (t[k1] - t[k0]);
                x[k][i] = x[k0][i] + s * (x[k1][i] - x[k0][i]);
            }
        }
    }
    Some(filled)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A spline through a cubic's samples at uneven times is close to it, and its
    /// derivative to the cubic's; a natural spline is exact on a straight line.
    #[test]
    fn the_spline_follows_a_smooth_signal_and_its_derivative() {
        let t: Vec<f64> = (0..400)
            .map(|k| k as f64 * 0.01 + 0.002 * (k % 3) as f64)
            .collect();
        let y: Vec<f64> = t.iter().map(|&t| (2.0 * t).sin()).collect();
        let s = Spline::natural(&t, &y);
        for k in [50, 200, 350] {
            let tau = 0.4 * (t[k + 1] - t[k]);
            let (v, dv) = s.eval(&t, &y, k, tau);
            let tt = t[k] + tau;
            assert!((v - (2.0 * tt).sin()).abs() < 1e-7, "{v}");
            assert!((dv - 2.0 * (2.0 * tt).cos()).abs() < 1e-4, "{dv}");
        }
        let line: Vec<f64> = t.iter().map(|&t| 3.0 - 0.5 * t).collect();
        let s = Spline::natural(&t, &line);
        let (v, dv) = s.eval(&t, &line, 10, 0.003);
        assert!((v - (3.0 - 0.5 * (t[10] + 0.003))).abs() < 1e-12);
        assert!((dv + 0.5).abs() < 1e-12);
    }

    /// The zero-phase low-pass has no delay: a 1 Hz sine at 286 Hz comes back in phase
    /// and at full amplitude (40 Hz cutoff), while a 100 Hz tone is cut below 20 %.
    #[test]
    fn filtfilt_keeps_the_phase_and_cuts_vibration() {
        let fs = 285.714;
        let t: Vec<f64> = (0..2000).map(|k| k as f64 / fs).collect();
        let slow: Vec<f64> = t
            .iter()
            .map(|&t| (std::f64::consts::TAU * t).sin())
            .collect();
        let out = filtfilt(&t, &slow, GYRO_CUTOFF_HZ);
        let worst = (200..1800)
            .map(|k| (out[k] - slow[k]).abs())
            .fold(0.0, f64::max);
        assert!(worst < 2e-3, "{worst}");
        let fast: Vec<f64> = t
            .iter()
            .map(|&t| (std::f64::consts::TAU * 100.0 * t).sin())
            .collect();
        let out = filtfilt(&t, &fast, GYRO_CUTOFF_HZ);
        let peak = (200..1800).map(|k| out[k].abs()).fold(0.0, f64::max);
        assert!(peak < 0.2, "{peak}");
    }

    /// The rest ends where the gyro moves; its mean is the bias; gravity is the mean |a|.
    #[test]
    fn the_initial_rest_gives_bias_and_gravity() {
        let t: Vec<f64> = (0..300).map(|k| k as f64 * 0.01).collect();
        let gyro: Vec<[f64; 3]> = t
            .iter()
            .map(|&t| {
                if t < 1.5 {
                    [0.01, -0.02, 0.005]
                } else {
                    [0.5, 0.0, 0.0]
                }
            })
            .collect();
        let accel = vec![[0.0, 0.0, 9.79]; 300];
        let r = Rest::find(&t, &gyro, &accel, None).unwrap();
        assert_eq!(r.end, 150);
        assert!((r.gyro_bias[1] + 0.02).abs() < 1e-15 && (r.gravity - 9.79).abs() < 1e-12);
        assert_eq!(Rest::find(&t, &gyro, &accel, Some(80)).unwrap().end, 80);
        // Moving from the start: no rest.
        let moving = vec![[0.5, 0.0, 0.0]; 300];
        let spin: Vec<[f64; 3]> = (0..300)
            .map(|k| [0.3 * (k as f64 * 0.2).sin(), 0.0, 0.0])
            .collect();
        assert!(Rest::find(&t, &spin, &accel, None).is_none());
        assert!(
            Rest::find(&t, &moving, &accel, Some(10)).is_none(),
            "0.1 s is no rest"
        );
    }

    #[test]
    fn gaps_are_filled_between_neighbours() {
        let t = [0.0, 1.0, 2.0, 3.0, 4.0];
        let mut x = [
            [f64::NAN, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [f64::NAN, 0.0, 0.0],
            [3.0, 0.0, 0.0],
            [f64::NAN; 3],
        ];
        assert_eq!(fill_gaps(&t, &mut x), Some(5));
        assert_eq!(x.map(|r| r[0]), [1.0, 1.0, 2.0, 3.0, 3.0]);
        let mut none = [[f64::NAN; 3]; 2];
        assert_eq!(fill_gaps(&t[..2], &mut none), None);
    }
}
