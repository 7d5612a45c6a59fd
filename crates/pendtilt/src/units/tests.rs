//! The unit checks against logs with a known mistake, and against correct ones.
use super::*;
use crate::units::{AccelUnit, STANDARD_GRAVITY};

/// A vibrating body's specific force: gravity tilted by `tilt` plus a vibration of
/// `vib` m/s^2 (a deterministic spread of tones), in `unit`.
fn accel_log(n: usize, vib: f64, unit: AccelUnit) -> AccelMagnitude {
    let mut m = AccelMagnitude::default();
    for k in 0..n {
        let t = k as f64 * 1e-3;
        let tilt = 0.3 * (0.7 * t).sin();
        let v = vib * ((2.0 * std::f64::consts::PI * 37.0 * t).sin() + (91.0 * t).cos());
        let (ax, ay) = (
            STANDARD_GRAVITY * tilt.sin() + v,
            STANDARD_GRAVITY * tilt.cos() - 0.5 * v,
        );
        m.add(ax.hypot(ay) / unit.metres_per_second_squared());
    }
    m
}

/// The median magnitude to 1 %; a log in g or mg named with the unit that explains it
/// and the fix; a log in m/s^2 quiet, also with strong vibration; m/s^2 read with
/// `--accel-unit g` told to leave it out; one absurd reading moves nothing; too few
/// readings, no verdict.
#[test]
fn the_accelerometer_in_g_or_mg_is_found_from_gravity() {
    let right = accel_log(5000, 3.0, AccelUnit::MetresPerSecondSquared);
    let med = right.median().unwrap();
    assert!((med / STANDARD_GRAVITY - 1.0).abs() < 0.1, "{med}");
    assert!(right.finding("ax, ay", None).is_none());
    // A hard ride: 8 m/s^2 of vibration on 9.8 of gravity.
    assert!(accel_log(5000, 8.0, AccelUnit::MetresPerSecondSquared)
        .finding("ax, ay", None)
        .is_none());
    for (unit, ratio) in [(AccelUnit::G, 0.102), (AccelUnit::MilliG, 102.0)] {
        let f = accel_log(5000, 3.0, unit).finding("ax, ay", None).unwrap();
        assert_eq!(f.comparison, Comparison::AccelGravity);
        assert!(
            (f.fit.factor / ratio - 1.0).abs() < 0.1,
            "{unit}: {}",
            f.fit.factor
        );
        assert!(
            f.message
                .starts_with("ax, ay: the specific force's median magnitude is")
                && f.message.contains(&format!(
                    "is the accelerometer in {unit}? read it with --accel-unit {unit}"
                )),
            "{}",
            f.message
        );
        // Read with the right unit (the reader scales to m/s^2 before the check): quiet.
        assert!(accel_log(5000, 3.0, AccelUnit::MetresPerSecondSquared)
            .finding("ax, ay", Some(unit))
            .is_none());
    }
    // m/s^2 read as g: 9.8x too large.
    let mut twice = AccelMagnitude::default();
    for k in 0..500 {
        twice.add(STANDARD_GRAVITY * STANDARD_GRAVITY * (1.0 + 1e-3 * k as f64));
    }
    let f = twice.finding("ax, ay, az", Some(AccelUnit::G)).unwrap();
    assert!(
        f.message.contains("(read with --accel-unit g)")
            && f.message
                .contains("is it already in m/s^2? leave out --accel-unit g"),
        "{}",
        f.message
    );
    // Neither g nor mg explains ft/s^2 (3.28x): the question.
    let mut feet = AccelMagnitude::default();
    for _ in 0..500 {
        feet.add(STANDARD_GRAVITY / 0.3048);
    }
    let f = feet.finding("ax, ay", None).unwrap();
    assert!(
        f.message.contains("is the accelerometer in m/s^2"),
        "{}",
        f.message
    );
    // One absurd reading in a right log, zeros and NaN: no finding, the median kept.
    let mut one = accel_log(5000, 3.0, AccelUnit::MetresPerSecondSquared);
    one.add(1e300);
    one.add(1e5);
    one.add(0.0);
    one.add(f64::NAN);
    assert!(one.finding("ax, ay", None).is_none());
    assert_eq!(one.median(), right.median());
    // Too few readings to tell.
    assert!(accel_log(99, 3.0, AccelUnit::G)
        .finding("ax, ay", None)
        .is_none());
    assert!(accel_log(100, 3.0, AccelUnit::G)
        .finding("ax, ay", None)
        .is_some());
}

/// A sensor 5 m above the centre its body pitches about (two sines, 5 deg at 0.14 Hz
/// and 1 deg at 0.31 Hz, as ship3d's pitch): the pendulum reads `theta - (h / g)
/// theta''`. The plain pair takes the gyro for 0.57 of the encoder's rate; the lever
/// fit gives 1 (57.3 with the gyro in deg/s) and the height.
#[test]
fn the_lever_fit_takes_out_the_height_above_the_centre_of_rotation() {
    let (h, g, dt) = (5.0, 9.80665, 1e-3);
    let parts = [(5f64.to_radians(), 0.14), (1f64.to_radians(), 0.31)];
    for scale in [1.0, DEG] {
        let mut check = UnitCheck::with_natural_frequency(2.19, Inputs::PHI_GYRO).with_lever();
        for k in 0..60_000 {
            let t = k as f64 * dt;
            let (mut th, mut rate, mut acc) = (0.0, 0.0, 0.0);
            for (a, f) in parts {
                let w = std::f64::consts::TAU * f;
                th += a * (w * t).sin();
                rate += a * w * (w * t).cos();
                acc -= a * w * w * (w * t).sin();
            }
            let s = Sample {
                dt: if k == 0 { 0.0 } else { dt },
                phi: th - h / g * acc,
                gyro: scale * rate,
                ax: f64::NAN,
                ay: f64::NAN,
            };
            check.add(&s, None);
        }
        let plain = check.fit(Comparison::GyroEncoderRate).unwrap();
        assert!(plain.factor / scale < 0.7, "{plain:?}");
        let l = check.lever_fit(g).unwrap();
        assert!((l.fit.factor / scale - 1.0).abs() < 0.01, "{l:?}");
        assert!(l.fit.correlation > 0.999, "{l:?}");
        assert!((l.height - h).abs() < 0.1, "{l:?}");
    }
}
