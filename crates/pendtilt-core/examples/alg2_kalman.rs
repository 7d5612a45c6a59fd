//! Step 2 of the examples: Algorithm 2 removes the pendulum's lag, and the paper's
//! angle+bias Kalman filter fuses its angle with the gyro.
//!
//! Algorithm 2 (the paper's Eq 21) inverts the pendulum's dynamics: it needs the rig's
//! normalised parameters a and b ([`PendulumParams`]), the encoder and the gyro. The
//! Kalman filter (Eqs 2-11) integrates the gyro and corrects it with that angle, and
//! estimates the gyro's bias on the way. When the encoder drops out, Algorithm 2 holds
//! its last angle (and flags the samples); the filter carries on with the gyro.
//!
//! Run: `cargo run -p pendtilt-core --release --example alg2_kalman`
mod common;

use pendtilt_core::prelude::*;

fn main() {
    let rows = common::ride(20.0);

    // The rig: here the default pendulum; `pendtilt fit` measures a and b on a real one.
    let params = PendulumParams::<f64>::default();
    let mut pendulum = Pendulum::new(PendulumSettings {});
    let mut alg2 = Alg2::<f64>::new(Alg2Settings::from_params(params));
    let kalman_settings = KalmanSettings::<f64>::default();
    let mut kalman = TiltKalman::new(kalman_settings);

    let mut gate = StepGate::<f64>::new();
    let (mut raw, mut inverted, mut fused) = (Vec::new(), Vec::new(), Vec::new());
    for r in &rows {
        // The encoder drops out for half a second: a missing reading is NaN.
        let dropout = (10.0..10.5).contains(&r.t);
        let s = Sample {
            dt: gate.step(r.t),
            phi: if dropout { f64::NAN } else { r.phi },
            gyro: r.gyro,
            ax: r.ax,
            ay: r.ay,
        };
        raw.push(pendulum.update(&s).theta);
        let a2 = alg2.update(&s);
        assert_eq!(dropout, a2.flags.contains(Flags::SAMPLE_MISSING));
        inverted.push(a2.theta);
        // The filter takes any number of (angle, variance) measurements per sample; an
        // angle its source flagged as unusable (missing input, clamped asin) is passed as
        // NaN so that the filter only predicts. (`KalmanOn` does this for one source.)
        let z = if a2
            .flags
            .intersects(Flags::SAMPLE_MISSING | Flags::ASIN_CLAMPED)
        {
            f64::NAN
        } else {
            a2.theta
        };
        fused.push(
            kalman
                .step(s.dt, s.gyro, &[(z, kalman_settings.r_pendulum)])
                .theta,
        );
    }

    // Skip the first second: the differentiator and the filter start from rest.
    let skip = 1000;
    let raw_err = common::rms_deg(&rows, &raw, skip);
    let alg2_err = common::rms_deg(&rows, &inverted, skip);
    let kf_err = common::rms_deg(&rows, &fused, skip);
    println!("RMS tilt error after the first second:");
    println!("  raw pendulum           : {raw_err:6.3} deg");
    println!("  Algorithm 2            : {alg2_err:6.3} deg");
    println!("  Kalman filter on Alg 2 : {kf_err:6.3} deg");
    println!(
        "gyro bias: estimated {:.4} rad/s, true {:.4} rad/s",
        kalman.bias(),
        common::GYRO_BIAS
    );
    // Algorithm 2 beats the raw pendulum; the filter beats both, by the dropout.
    assert!(kf_err < alg2_err && alg2_err < raw_err);
    assert!((kalman.bias() - common::GYRO_BIAS).abs() < 0.005);
}
