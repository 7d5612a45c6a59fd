//! A small simulated ride shared by the examples, so that each runs with no input file.
//!
//! The body rocks about a fixed axis (a slow tilt motion) while the pivot shakes sideways
//! at 30 Hz, like a vehicle's floor with its engine running. The pendulum obeys MODEL.md
//! section 2 with l12 = 0, integrated with RK4; the sensors are ideal except for a
//! constant gyro bias. The `pendtilt` crate has the full simulator (vibration spectra,
//! noise, quantisation, scenarios); this is only what the examples need.
use pendtilt_core::prelude::*;

/// Sample interval of the ride [s] (1 kHz, as on the paper's rig).
pub const DT: f64 = 1e-3;
/// The gyro's constant bias [rad/s] (a Kalman filter estimates it).
pub const GYRO_BIAS: f64 = 0.02;

/// One sample of the ride: what the sensors read, and the true tilt.
pub struct Row {
    /// Time stamp [s], as a data logger would write it.
    pub t: f64,
    /// Encoder angle phi [rad].
    pub phi: f64,
    /// Gyro rate [rad/s], bias included.
    pub gyro: f64,
    /// Accelerometer, body x and y [m/s^2].
    pub ax: f64,
    /// See `ax`.
    pub ay: f64,
    /// The true body tilt theta [rad]: what an estimator should return.
    pub theta: f64,
}

/// The body's tilt theta(t) and its first two derivatives: two slow sines (0.25 and
/// 0.6 Hz, 15 and 5 deg).
fn tilt(t: f64) -> [f64; 3] {
    let mut out = [0.0; 3];
    for (amp, hz) in [(0.26, 0.25), (0.09, 0.6)] {
        let w = core::f64::consts::TAU * hz;
        out[0] += amp * (w * t).sin();
        out[1] += amp * w * (w * t).cos();
        out[2] -= amp * w * w * (w * t).sin();
    }
    out
}

/// Sideways acceleration of the pivot [m/s^2]: 30 Hz, 3 m/s^2 amplitude.
fn shake(t: f64) -> f64 {
    3.0 * (core::f64::consts::TAU * 30.0 * t).sin()
}

/// phi'' for the pendulum state (phi, phi') at time t, from MODEL.md section 2 divided
/// by m g l: b beta'' = -(f_x / g) cos beta - sin beta + a phi', beta = theta - phi.
fn phi_dd(p: &PendulumParams<f64>, g: f64, t: f64, phi: f64, phi_d: f64) -> f64 {
    let [theta, _, theta_dd] = tilt(t);
    let beta = theta - phi;
    let beta_dd = (-(shake(t) / g) * beta.cos() - beta.sin() + p.a * phi_d) / p.b;
    theta_dd - beta_dd
}

/// `seconds` of the ride at 1 kHz on the default rig ([`PhysicalParams::default`]),
/// starting with the pendulum at rest.
pub fn ride(seconds: f64) -> Vec<Row> {
    let rig = PhysicalParams::<f64>::default();
    let (p, g) = (rig.normalised(), rig.gravity);
    let (mut phi, mut phi_d) = (0.0, 0.0);
    let n = (seconds / DT).round() as usize;
    let mut rows = Vec::with_capacity(n);
    for k in 0..n {
        let t = k as f64 * DT;
        let [theta, theta_d, _] = tilt(t);
        // The accelerometer reads the specific force (shake, g) in body axes.
        let (s, c) = theta.sin_cos();
        let f = (shake(t), g);
        rows.push(Row {
            t,
            phi,
            gyro: theta_d + GYRO_BIAS,
            ax: f.0 * c + f.1 * s,
            ay: -f.0 * s + f.1 * c,
            theta,
        });
        // RK4 over one sample interval, in 10 sub-steps (the 30 Hz shake needs them).
        let h = DT / 10.0;
        for j in 0..10 {
            let t0 = t + j as f64 * h;
            let f = |dt: f64, x: f64, v: f64| (v, phi_dd(&p, g, t0 + dt, x, v));
            let k1 = f(0.0, phi, phi_d);
            let k2 = f(h / 2.0, phi + h / 2.0 * k1.0, phi_d + h / 2.0 * k1.1);
            let k3 = f(h / 2.0, phi + h / 2.0 * k2.0, phi_d + h / 2.0 * k2.1);
            let k4 = f(h, phi + h * k3.0, phi_d + h * k3.1);
            phi += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
            phi_d += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
        }
    }
    rows
}

/// RMS of `estimate - truth` in degrees, over the rows from `skip` on (the estimators
/// start from rest and need a moment to settle).
pub fn rms_deg(rows: &[Row], estimates: &[f64], skip: usize) -> f64 {
    let sq: f64 = rows[skip..]
        .iter()
        .zip(&estimates[skip..])
        .map(|(r, e)| (e - r.theta).powi(2))
        .sum();
    (sq / (rows.len() - skip) as f64).sqrt().to_degrees()
}
