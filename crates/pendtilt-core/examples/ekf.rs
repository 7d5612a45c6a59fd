//! Step 4 of the examples: the model-based extended Kalman filter (beyond the paper).
//!
//! Instead of differentiating the encoder, the EKF carries the pendulum's own dynamics
//! in its state (theta, theta', theta'', phi, phi', gyro bias) and takes the encoder and
//! the gyro as measurements. Its noise settings are derived from the rig, so the physical
//! parameters are all it needs. `Ukf` (the unscented filter) is used the same way.
//!
//! Run: `cargo run -p pendtilt-core --release --example ekf`
mod common;

use pendtilt_core::prelude::*;

fn main() {
    let rows = common::ride(20.0);

    let rig = PhysicalParams::<f64>::default();
    let mut ekf = Ekf::new(ModelSettings::from_physical(&rig));
    // For comparison, Algorithm 2 on the same rig (step 2).
    let mut alg2 = Alg2::<f64>::new(Alg2Settings::from_params(rig.normalised()));

    let mut gate = StepGate::<f64>::new();
    let (mut by_ekf, mut by_alg2) = (Vec::new(), Vec::new());
    for r in &rows {
        let s = Sample {
            dt: gate.step(r.t),
            phi: r.phi,
            gyro: r.gyro,
            ax: r.ax,
            ay: r.ay,
        };
        let e = ekf.update(&s);
        // The innovation gate skips (and flags) readings the model finds implausible;
        // on this clean ride there are none.
        assert!(!e.flags.contains(Flags::MEASUREMENT_SKIPPED));
        by_ekf.push(e.theta);
        by_alg2.push(alg2.update(&s).theta);
    }

    let skip = 1000;
    let ekf_err = common::rms_deg(&rows, &by_ekf, skip);
    let alg2_err = common::rms_deg(&rows, &by_alg2, skip);
    println!("RMS tilt error after the first second:");
    println!("  Algorithm 2 : {alg2_err:6.3} deg");
    println!("  EKF         : {ekf_err:6.3} deg");
    println!(
        "gyro bias: estimated {:.4} rad/s, true {:.4} rad/s",
        ekf.bias(),
        common::GYRO_BIAS
    );
    assert!(ekf_err < alg2_err);
}
