//! The cost each filter fit minimises: the likelihood of its innovations
//! ([`Target::Likelihood`]) or, on a calibration ride, the RMS error against the true
//! angle ([`Target::Truth`], the paper's Eq 23). Both run the same search
//! ([`super::search::coordinate_log`]) over the same parameters.
use super::ekf::{self, EkfFitted};
use super::kalman::{self, Fitted, KalmanData, ROUNDS};
use super::search::{coordinate_log, Budget};
use super::{Options, Target};
use crate::peers::tune::{rms_error, Log};
use pendtilt_core::ekf::{Ekf, ModelSettings};
use pendtilt_core::kalman::KalmanSettings;
use pendtilt_core::Sample;

/// RMS error \[rad\] against `truth` of the angle + bias filter fed the measurements
/// `zs` (each with its R) with the steps and gyro of `d`, rows from `skip` on.
fn kalman_rms(
    s: &KalmanSettings<f64>,
    d: &KalmanData,
    zs: &[(&[f64], f64)],
    truth: &[f64],
    skip: usize,
) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    kalman::pass(s, d.dt, d.gyro, zs, |k, th, _, _| {
        if k >= skip && k < truth.len() && th.is_finite() && truth[k].is_finite() {
            sum += (th - truth[k]).powi(2);
            n += 1;
        }
    });
    if n == 0 {
        f64::INFINITY
    } else {
        (sum / n as f64).sqrt()
    }
}

/// The cost of the angle + bias filter with `x = [q_angle, q_bias, r]`.
fn kalman_cost(s: &KalmanSettings<f64>, x: &[f64], d: &KalmanData, skip: usize, t: &Target) -> f64 {
    let at = KalmanSettings {
        q_angle: x[0],
        q_bias: x[1],
        ..*s
    };
    match t {
        Target::Likelihood => kalman::nll(&at, x[2], d, skip),
        Target::Truth(th) => kalman_rms(&at, d, &[(d.z, x[2])], th, skip),
    }
}

/// Fits q_angle, q_bias and R of `s` (R starting at `r0`) on `d`.
pub(super) fn kalman(
    s: &KalmanSettings<f64>,
    r0: f64,
    d: &KalmanData,
    skip: usize,
    opts: &Options,
    budget: &mut Budget,
) -> Fitted {
    let x0 = [s.q_angle, s.q_bias, r0];
    let before = kalman_cost(s, &x0, d, skip, &opts.target);
    let (x, after) = coordinate_log(
        |x| kalman_cost(s, x, d, skip, &opts.target),
        &x0,
        6.0,
        ROUNDS,
        budget,
    );
    let x = if after < before { x } else { x0.to_vec() };
    Fitted {
        q_angle: x[0],
        q_bias: x[1],
        r: x[2],
        nll_before: before,
        nll_after: after.min(before),
    }
}

/// Fits R alone (q_angle, q_bias of `s` kept): `(R, cost before, cost after)`.
pub(super) fn kalman_r(
    s: &KalmanSettings<f64>,
    r0: f64,
    d: &KalmanData,
    skip: usize,
    opts: &Options,
    budget: &mut Budget,
) -> (f64, f64, f64) {
    let cost = |r: f64| kalman_cost(s, &[s.q_angle, s.q_bias, r], d, skip, &opts.target);
    search_r(r0, cost, budget)
}

/// Fits kf_fused's accelerometer R against `truth`: the R of the first of `zs` (from its
/// value), the others' R and `s`'s Q kept. `(R, RMS before, RMS after)` \[rad^2, rad, rad\].
pub(super) fn kalman_fused_r(
    s: &KalmanSettings<f64>,
    zs: &[(&[f64], f64)],
    d: &KalmanData,
    truth: &[f64],
    skip: usize,
    budget: &mut Budget,
) -> (f64, f64, f64) {
    let cost = |r: f64| {
        let mut with: Vec<(&[f64], f64)> = zs.to_vec();
        with[0].1 = r;
        kalman_rms(s, d, &with, truth, skip)
    };
    search_r(zs[0].1, cost, budget)
}

/// One R by the search from `r0` on `cost`: `(R, cost before, cost after)`, `r0` if
/// nothing lowered it.
fn search_r(r0: f64, cost: impl Fn(f64) -> f64, budget: &mut Budget) -> (f64, f64, f64) {
    let before = cost(r0);
    let (x, after) = coordinate_log(|x| cost(x[0]), &[r0], 4.0, 1, budget);
    if after < before {
        (x[0], before, after)
    } else {
        (r0, before, before)
    }
}

/// Fits the EKF's densities ([`ekf::fit`] or, against the truth, the same parameters by
/// RMS error).
pub(super) fn ekf(
    start: &ModelSettings<f64>,
    samples: &[Sample<f64>],
    skip: usize,
    opts: &Options,
    budget: &mut Budget,
) -> EkfFitted {
    let Target::Truth(truth) = opts.target else {
        return ekf::fit(start, samples, skip, budget);
    };
    let log = Log {
        samples,
        truth: &truth[..samples.len().min(truth.len())],
        skip,
    };
    let at = |x: &[f64]| ekf::with_parameters(start, x);
    let x0 = ekf::parameters(start);
    let before = rms_error(&mut Ekf::new(*start), &log);
    let (x, after) = coordinate_log(
        |x| rms_error(&mut Ekf::new(at(x)), &log),
        &x0,
        4.0,
        ekf::ROUNDS,
        budget,
    );
    EkfFitted::better_of(start, at(&x), before, after)
}
