//! The estimator on short synthetic runs: imu3d, the gyro's clips and holds, the
//! heading's bound, the speed column.
use super::covariance::HEADING_VARIANCE;
use super::gyro_hold::BIAS_HOLD;
use super::*;
use crate::spatial::ekf::state::ROT;
use crate::spatial::ekf::Ekf;
use nalgebra::{Vector2, Vector4};

fn still(k: usize, gyro: [f64; 3]) -> SpatialSample<f64> {
    SpatialSample::new(
        if k == 0 { 0.0 } else { 1e-3 },
        [0.0, 0.0],
        gyro,
        [f64::NAN; 3],
    )
}

/// imu3d ([`Settings::imu_only`]) needs no encoders: on a body resting tilted, with no
/// encoder reading at all, it starts on the accelerometer and holds its tilt; ekf3d on
/// the same samples never starts. A body accelerating along x at 2 m/s^2 for a second
/// (12 deg of an accelerometer's tilt) moves it by far less: the adaptation and the
/// guard's reference keep to the gyro.
#[test]
fn imu3d_runs_on_the_accelerometer_alone() {
    let (roll, pitch) = (0.2f64, -0.1f64);
    let up = crate::spatial::attitude::up_from_roll_pitch(roll, pitch);
    let sample = |k: usize, push: f64| {
        let f = [9.81 * up[0] + push, 9.81 * up[1], 9.81 * up[2]];
        SpatialSample::new(if k == 0 { 0.0 } else { 1e-3 }, [f64::NAN; 2], [0.0; 3], f)
    };
    let mut imu = Ekf::<f64>::new(Settings::default().imu_only());
    let mut ekf = Ekf::<f64>::new(Settings::default());
    let mut worst = 0.0f64;
    for k in 0..20_000 {
        let push = if (10_000..11_000).contains(&k) {
            2.0
        } else {
            0.0
        };
        let a = imu.update(&sample(k, push));
        let e = ekf.update(&sample(k, push));
        assert!(e.flags.contains(Flags::INITIALISING), "{k}");
        if k > 3000 {
            let err = crate::spatial::attitude::inclination_between(
                crate::spatial::attitude::up_from_roll_pitch(a.roll, a.pitch),
                up,
            );
            worst = worst.max(err.to_degrees());
        }
        if k == 9_999 {
            assert!((a.roll - roll).abs() < 1e-3 && (a.pitch - pitch).abs() < 1e-3);
        }
    }
    assert!(worst < 3.0, "{worst} deg");
}

/// A gyro axis at its full scale is flagged saturated and loosens the attitude about
/// that axis against its joint angle (by the slope the rate had on entering the clip),
/// so the encoders carry it; below the full scale, or without one, nothing changes.
#[test]
fn a_reading_at_full_scale_is_flagged_and_loosens_the_attitude_about_its_axis() {
    let mut st = Settings::default();
    st.gyro.full_scale = Some(0.5);
    let mut e = Ekf::<f64>::new(st);
    let mut plain = Ekf::<f64>::new(Settings::default());
    // The x rate ramps up at 10 rad/s^2 and sticks at the full scale for 20 ms.
    let rate = |k: usize| (k.saturating_sub(100) as f64 * 1e-2).min(0.5);
    let mut flagged = 0;
    for k in 0..170 {
        let s = still(k, [rate(k), 0.0, 0.0]);
        let a = e.update(&s);
        plain.update(&s);
        assert_eq!(a.flags.contains(Flags::SATURATED), rate(k) >= 0.5, "{k}");
        flagged += usize::from(a.flags.contains(Flags::SATURATED));
    }
    assert_eq!(flagged, 20);
    let (p, q) = (e.covariance().unwrap(), plain.covariance().unwrap());
    // The prediction's variance about x before the last update is at least
    // (10 rad/s^2 (20 ms)^2 / 2)^2 = 4e-6 rad^2 more (the smoothed slope is a little
    // under the ramp's); the encoders then leave the extra mostly on the
    // joint-and-attitude direction they do not see.
    let dx = p[(ROT, ROT)] - q[(ROT, ROT)];
    let dy = p[(ROT + 1, ROT + 1)] - q[(ROT + 1, ROT + 1)];
    assert!(dx > 1e-7 && dx > 100.0 * dy.abs(), "{dx} {dy}");
    let mut none = Ekf::<f64>::new(Settings::default());
    let a = none.update(&still(0, [9.0; 3]));
    assert!(!a.flags.contains(Flags::SATURATED));
}

/// While the gyro is held (missing) and for BIAS_HOLD after, the encoders move the
/// attitude but not the gyro bias: a body rolling at 0.2 rad/s for 0.3 s with its gyro
/// missing leaves the bias where it was (to rounding); BIAS_HOLD later it is learnt
/// again.
#[test]
fn a_held_gyro_leaves_the_bias_where_it_was() {
    let mut e = Ekf::<f64>::new(Settings::default());
    let bias_walk = |e: &Ekf<f64>| e.state().unwrap().bias;
    // Still and level, a reading of 0.01 rad/s on x: the bias starts being learnt.
    for k in 0..2000 {
        e.update(&still(k, [0.01, 0.0, 0.0]));
    }
    let before = bias_walk(&e);
    assert!(before[0] > 1e-4, "{before}");
    // The body rolls at 0.2 rad/s (the pendulum hanging: phi_x follows the roll) with
    // the gyro missing, then still again with the gyro back.
    let mut roll = 0.0;
    for k in 2000..2300 {
        roll += 0.2e-3;
        let mut s = still(k, [f64::NAN; 3]);
        s.phi = [roll, 0.0];
        let a = e.update(&s);
        assert!(a.flags.contains(Flags::SAMPLE_MISSING));
        assert!((bias_walk(&e) - before).norm() < 1e-15, "{k}");
    }
    let mut s = still(2300, [0.01, 0.0, 0.0]);
    s.phi = [roll, 0.0];
    let a = e.update(&s);
    assert!((bias_walk(&e) - before).norm() < 1e-15);
    // The encoders turned the attitude meanwhile.
    assert!(a.roll > 0.1 * roll, "{} {roll}", a.roll);
    // BIAS_HOLD after the hold the bias is learnt again.
    for k in 2301..2400 + (BIAS_HOLD * 1e3) as usize {
        let mut s = still(k, [0.01, 0.0, 0.0]);
        s.phi = [roll, 0.0];
        e.update(&s);
    }
    assert!((bias_walk(&e) - before).norm() > 1e-9);
}

/// On a level body the heading and the z bias are unobserved: the heading variance
/// would grow as the z bias's variance times t^2; it is held at or below twice its
/// bound, and roll and pitch stay exact.
#[test]
fn the_unobserved_heading_variance_is_bounded() {
    let mut e = Ekf::<f64>::new(Settings::default());
    let mut worst = 0.0f64;
    for k in 0..300_000 {
        let s = SpatialSample::new(
            if k == 0 { 0.0 } else { 1e-3 },
            [0.0, 0.0],
            [0.0; 3],
            [f64::NAN; 3],
        );
        let a = e.update(&s);
        worst = worst.max(a.roll.abs()).max(a.pitch.abs());
    }
    let x = e.state().unwrap();
    let p = e
        .covariance()
        .unwrap()
        .fixed_view::<3, 3>(ROT, ROT)
        .into_owned();
    let u = x.up();
    let var = u.dot(&(p * u));
    assert!(var <= 2.0 * HEADING_VARIANCE + 1e-9, "{var}");
    // Without the bound it would be about 3e-4 (rad/s)^2 (300 s)^2 = 27 rad^2.
    assert!(var > 0.5 * HEADING_VARIANCE, "{var}");
    assert!(worst < 1e-9, "{worst}");
}

/// O accelerates along body x on a level body (a smooth 2 m/s^2 pulse from 2 to 6 s),
/// the joints following the filter's own equations of motion under that force. The
/// pendulum alone reads 11 deg of apparent pitch at the peak; with the speed column
/// (0.05 m/s of noise) ekf3d and ukf3d put it into O's acceleration, which the speed
/// alone gives only through its derivative, and stay level; so does ekf3d with the
/// speed on one row in 20 (a 50 Hz wheel-speed signal in a 1 kHz log).
#[test]
fn the_speed_column_tells_acceleration_from_tilt() {
    let st = Settings::<f64>::default();
    let model = st.process_model();
    let accel = |t: f64| {
        if (2.0..6.0).contains(&t) {
            2.0 * (core::f64::consts::PI * (t - 2.0) / 4.0).sin().powi(2)
        } else {
            0.0
        }
    };
    // The speed (1 m/s at the start), the integral of `accel`, and a deterministic
    // noise of sd 0.05 m/s.
    let speed = |t: f64| {
        let tau = (t - 2.0).clamp(0.0, 4.0);
        1.0 + tau - 2.0 / core::f64::consts::PI * (core::f64::consts::PI * tau / 2.0).sin()
    };
    let noise = |k: usize| (((k * 7919 + 13) % 1000) as f64 / 1000.0 - 0.5) * 0.173;
    let drive = Drive {
        gyro: Vector3::zeros(),
        angular_accel: Vector3::zeros(),
        path_gyro: Vector3::zeros(),
        slow_gyro: Vector3::zeros(),
        z_bias: 0.0,
    };
    let up = Vector3::z();
    let mut joints = Vector4::<f64>::zeros();
    let mut with = Ekf::<f64>::new(st);
    let mut with_ukf = crate::spatial::ekf::Ukf::<f64>::new(st);
    let mut without = Ekf::<f64>::new(st);
    let mut sparse = Ekf::<f64>::new(st);
    let (mut worst, mut worst_ukf, mut apparent, mut rate_err) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let mut worst_sparse = 0.0f64;
    for k in 0..8000 {
        let t = k as f64 * 1e-3;
        if k > 0 {
            let travel = Vector2::new(speed(t), accel(t));
            joints = model.joint_step(&joints, &Vector3::zeros(), &drive, (&up, &travel), 1e-3);
        }
        let mut s = SpatialSample {
            speed: speed(t) + noise(k),
            ..SpatialSample::new(
                if k == 0 { 0.0 } else { 1e-3 },
                [-joints[0], -joints[1]],
                [0.0; 3],
                [f64::NAN; 3],
            )
        };
        let a = with.update(&s);
        let u = with_ukf.update(&s);
        let reading = s.speed;
        s.speed = f64::NAN;
        let b = without.update(&s);
        s.speed = if k % 20 == 0 { reading } else { f64::NAN };
        let c = sparse.update(&s);
        let incl = |a: &Attitude<f64>| a.roll.hypot(a.pitch).to_degrees();
        if t > 1.0 {
            worst = worst.max(incl(&a));
            worst_ukf = worst_ukf.max(incl(&u));
            apparent = apparent.max(incl(&b));
            worst_sparse = worst_sparse.max(incl(&c));
            rate_err = rate_err.max((with.state().unwrap().travel[1] - accel(t)).abs());
        }
    }
    // Measured: 11.3 deg without the speed; 0.083 deg (ekf3d and ukf3d) with it, the
    // rate within 0.12 m/s^2 (at the pulse's onset, where the jerk is largest).
    assert!(apparent > 10.0, "{apparent}");
    assert!(worst < 0.15, "{worst}");
    assert!(worst_ukf < 0.15, "{worst_ukf}");
    // One row in 20: 0.19 deg (20 times fewer readings); with the speed held at zero
    // on every row without one, as before SpeedSettings::timeout, 11.3 (none at all).
    assert!(worst_sparse < 0.3, "{worst_sparse}");
    assert!(rate_err < 0.2, "{rate_err}");
}
