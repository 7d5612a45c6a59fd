//! The angle + bias Kalman filter's q_angle, q_bias and R by maximum likelihood of its own
//! innovations.
//!
//! For a linear Gaussian model the innovations `y_k = z_k - theta_k^-` are independent
//! with variances `S_k = P_k^-[0,0] + R`, so the negative log-likelihood of the
//! measurements is, up to a constant, `sum_k ln S_k + y_k^2 / S_k`. It needs no true
//! angle: a `Q` too small makes the innovations larger than `S` says, one too large makes
//! `S` larger than they are. [`innovation_pass`] is the filter of MODEL.md section 4
//! written out with its innovations (the same arithmetic as
//! [`pendtilt_core::kalman::TiltKalman`]; a test checks they agree sample by sample); the
//! first [`BURN_IN`] seconds, while the bias settles from its start at 0, are not scored.
use super::search::{coordinate_log, Budget};
use pendtilt_core::kalman::KalmanSettings;

/// Seconds at the start of a log left out of the likelihood.
pub const BURN_IN: f64 = 2.0;

/// Passes of the coordinate search.
pub const ROUNDS: usize = 4;

/// The inputs of the filter: per row, the step \[s\], the gyro \[rad/s\] and the measured
/// angle \[rad\] (NaN where unusable).
#[derive(Debug, Clone, Copy)]
pub struct KalmanData<'a> {
    /// [`pendtilt_core::Sample::dt`] of each row.
    pub dt: &'a [f64],
    /// Gyro readings.
    pub gyro: &'a [f64],
    /// Angle measurements (an estimator's output).
    pub z: &'a [f64],
}

/// Runs the filter with `q_angle`, `q_bias` from `s`, measurement variance `r`; calls
/// `each(k, theta, y, s_k)` after each row's update (`y`, `s_k` NaN without a measurement;
/// before the start `theta` is NaN). Rows with a bad step are skipped, as the filter does.
pub fn innovation_pass(
    s: &KalmanSettings<f64>,
    r: f64,
    d: &KalmanData,
    each: impl FnMut(usize, f64, f64, f64),
) {
    pass(s, d.dt, d.gyro, &[(d.z, r)], each);
}

/// [`innovation_pass`] with several measurements per row, each `(z, r)` used in turn as
/// `kf_fused` uses them; the filter starts on the usable one with the least `r` (the first
/// of equals), as [`pendtilt_core::kalman::TiltKalman`] does. `y`, `s_k` are the last
/// update's of the row.
pub fn pass(
    s: &KalmanSettings<f64>,
    dt: &[f64],
    gyro: &[f64],
    zs: &[(&[f64], f64)],
    mut each: impl FnMut(usize, f64, f64, f64),
) {
    let (mut th, mut b) = (f64::NAN, 0.0);
    let (mut p00, mut p01, mut p11) = (s.p0_angle, 0.0, s.p0_bias);
    let mut u_last = 0.0;
    let n = zs
        .iter()
        .map(|(z, _)| z.len())
        .fold(dt.len().min(gyro.len()), usize::min);
    for k in 0..n {
        let u = if gyro[k].is_finite() {
            u_last = gyro[k];
            gyro[k]
        } else {
            u_last
        };
        if th.is_nan() {
            let mut least = f64::INFINITY;
            for &(z, r) in zs {
                if z[k].is_finite() && r < least {
                    (th, least) = (z[k], r);
                }
            }
            each(k, th, f64::NAN, f64::NAN);
            continue;
        }
        let h = dt[k];
        if !(h.is_finite() && h >= 0.0) {
            each(k, th, f64::NAN, f64::NAN);
            continue;
        }
        // Predict: A = [[1, -dt], [0, 1]], B = [dt, 0], Q = diag(q_angle, q_bias) dt.
        th += h * (u - b);
        let a00 = p00 - h * (2.0 * p01 - h * p11) + s.q_angle * h;
        let a01 = p01 - h * p11;
        p00 = a00;
        p01 = a01;
        p11 += s.q_bias * h;
        let (mut y_last, mut s_last) = (f64::NAN, f64::NAN);
        for &(z, r) in zs {
            let z = z[k];
            if !z.is_finite() {
                continue;
            }
            let y = z - th;
            let sk = p00 + r;
            let (k0, k1) = (p00 / sk, p01 / sk);
            th += k0 * y;
            b += k1 * y;
            // P - v v^T / s with v = P h = (p00, p01).
            let (v0, v1) = (p00, p01);
            p00 -= v0 * v0 / sk;
            p01 -= v0 * v1 / sk;
            p11 -= v1 * v1 / sk;
            (y_last, s_last) = (y, sk);
        }
        each(k, th, y_last, s_last);
    }
}

/// Mean negative log-likelihood per scored innovation, `mean(ln S + y^2 / S)`, after
/// `skip` rows; infinite when nothing is scored.
pub fn nll(s: &KalmanSettings<f64>, r: f64, d: &KalmanData, skip: usize) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    innovation_pass(s, r, d, |k, _, y, sk| {
        if k >= skip && y.is_finite() && sk > 0.0 {
            sum += sk.ln() + y * y / sk;
            n += 1;
        }
    });
    if n == 0 {
        f64::INFINITY
    } else {
        sum / n as f64
    }
}

/// The result of a likelihood fit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fitted {
    /// The fitted q_angle \[rad^2/s\], q_bias \[(rad/s)^2/s\] and R \[rad^2\].
    pub q_angle: f64,
    /// See [`Self::q_angle`].
    pub q_bias: f64,
    /// See [`Self::q_angle`].
    pub r: f64,
    /// Mean negative log-likelihood at the start.
    pub nll_before: f64,
    /// ... and at the fit.
    pub nll_after: f64,
}

/// Fits q_angle, q_bias and R (starting from `s` and `r0`) by maximum likelihood, each
/// within 6 decades of its start, [`ROUNDS`] passes (fewer left q_angle 30 % off on a
/// linear model: R and q_angle trade against each other). `skip` rows are not scored.
pub fn fit(
    s: &KalmanSettings<f64>,
    r0: f64,
    d: &KalmanData,
    skip: usize,
    budget: &mut Budget,
) -> Fitted {
    let at = |x: &[f64]| KalmanSettings {
        q_angle: x[0],
        q_bias: x[1],
        ..*s
    };
    let before = nll(s, r0, d, skip);
    let (x, after) = coordinate_log(
        |x| nll(&at(x), x[2], d, skip),
        &[s.q_angle, s.q_bias, r0],
        6.0,
        ROUNDS,
        budget,
    );
    Fitted {
        q_angle: x[0],
        q_bias: x[1],
        r: x[2],
        nll_before: before,
        nll_after: after.min(before),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pendtilt_core::kalman::TiltKalman;

    #[test]
    fn innovation_pass_is_the_core_filter() {
        let s = KalmanSettings {
            q_angle: 2e-3,
            q_bias: 5e-4,
            ..KalmanSettings::default()
        };
        let n = 400;
        let dt: Vec<f64> = (0..n).map(|k| if k == 0 { 0.0 } else { 0.002 }).collect();
        let gyro: Vec<f64> = (0..n).map(|k| (k as f64 * 0.03).sin() + 0.01).collect();
        let z: Vec<f64> = (0..n)
            .map(|k| {
                if k % 7 == 3 {
                    f64::NAN
                } else {
                    (k as f64 * 0.011).cos() * 0.2
                }
            })
            .collect();
        let d = KalmanData {
            dt: &dt,
            gyro: &gyro,
            z: &z,
        };
        let mut mine = Vec::new();
        innovation_pass(&s, 3e-3, &d, |_, th, _, _| mine.push(th));
        let mut kf = TiltKalman::new(s);
        for k in 0..n {
            let e = kf.step(dt[k], gyro[k], &[(z[k], 3e-3)]);
            assert!((e.theta - mine[k]).abs() < 1e-12, "row {k}");
        }
    }

    /// kf_fused's two measurements: the pass starts where the core filter starts (on the
    /// accelerometer while Algorithm 2 has no angle yet, else on the one of least R) and
    /// follows it sample by sample, whichever is listed first.
    #[test]
    fn pass_with_two_measurements_is_the_core_filter() {
        let s = KalmanSettings {
            q_angle: 1e-3,
            q_bias: 2e-4,
            ..KalmanSettings::default()
        };
        let n = 300;
        let dt: Vec<f64> = (0..n).map(|k| if k == 0 { 0.0 } else { 0.002 }).collect();
        let gyro: Vec<f64> = (0..n).map(|k| (k as f64 * 0.05).cos() - 0.02).collect();
        let za: Vec<f64> = (0..n)
            .map(|k| 0.3 + (k as f64 * 0.7).sin() * 0.05)
            .collect();
        for late in [0, 5] {
            let zp: Vec<f64> = (0..n)
                .map(|k| {
                    if k < late || k % 11 == 4 {
                        f64::NAN
                    } else {
                        0.25 + (k as f64 * 0.013).sin() * 0.1
                    }
                })
                .collect();
            for (first, second) in [((&za, 0.03), (&zp, 1e-3)), ((&zp, 1e-3), (&za, 0.03))] {
                let zs = [
                    (first.0.as_slice(), first.1),
                    (second.0.as_slice(), second.1),
                ];
                let mut mine = Vec::new();
                pass(&s, &dt, &gyro, &zs, |_, th, _, _| mine.push(th));
                let start = if late == 0 { zp[0] } else { za[0] };
                assert_eq!(mine[0], start, "start, Alg 2 from row {late}");
                let mut kf = TiltKalman::new(s);
                for k in 0..n {
                    let e = kf.step(
                        dt[k],
                        gyro[k],
                        &[(first.0[k], first.1), (second.0[k], second.1)],
                    );
                    assert!(
                        (e.theta - mine[k]).abs() < 1e-12,
                        "row {k}, Alg 2 from row {late}"
                    );
                }
            }
        }
    }
}
