//! Step 1 of the examples: the raw pendulum as a tilt sensor.
//!
//! A pendulum hanging on the body reads the tilt directly (theta = phi at rest), and its
//! mechanical low-pass keeps out the vibration that ruins an accelerometer. This runs
//! both on a simulated ride with a shaking floor and prints their errors.
//!
//! Run: `cargo run -p pendtilt-core --release --example minimal`
mod common;

use pendtilt_core::prelude::*;

fn main() {
    // 20 s of simulated sensor rows at 1 kHz (see common/mod.rs).
    let rows = common::ride(20.0);

    // Every estimator has a settings struct with documented defaults and `new(settings)`.
    let mut pendulum = Pendulum::<f64>::new(PendulumSettings {});
    let mut accel = Accel::<f64>::new(AccelSettings::default());

    // Estimators take the time since the previous sample, `dt`, not a time stamp:
    // a `StepGate` turns the logger's stamps into steps once, for every estimator.
    let mut gate = StepGate::<f64>::new();
    let (mut by_pendulum, mut by_accel) = (Vec::new(), Vec::new());
    for r in &rows {
        let sample = Sample {
            dt: gate.step(r.t),
            phi: r.phi,
            gyro: r.gyro,
            ax: r.ax,
            ay: r.ay,
        };
        // One sample in, one estimate out: the angle and flags saying how it was made.
        let e = pendulum.update(&sample);
        assert!(e.flags.is_empty(), "clean data raises no flag");
        by_pendulum.push(e.theta);
        by_accel.push(accel.update(&sample).theta);
    }

    let pendulum_err = common::rms_deg(&rows, &by_pendulum, 0);
    let accel_err = common::rms_deg(&rows, &by_accel, 0);
    println!("RMS tilt error over {} samples:", rows.len());
    println!("  accelerometer, Eq (1) : {accel_err:6.3} deg");
    println!("  raw pendulum          : {pendulum_err:6.3} deg");
    // The pendulum is not disturbed by the shaking, but it lags the motion; the
    // next example removes most of that lag.
    assert!(pendulum_err < accel_err);
}
