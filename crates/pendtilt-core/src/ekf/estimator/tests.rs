//! The estimator on short synthetic runs: the gate, gaps, the kept bias.
use super::*;
use crate::ekf::ExtendedKalman;

/// Sample `k` of a 1 kHz log (`k` is kept for the tests' readability).
fn s(k: usize, phi: f64) -> Sample<f64> {
    Sample {
        dt: if k == 0 { 0.0 } else { 1e-3 },
        phi,
        gyro: 0.0,
        ax: f64::NAN,
        ay: f64::NAN,
    }
}

fn skipped(e: &mut ModelBased<f64, ExtendedKalman<f64>>, k: usize, phi: f64) -> bool {
    e.update(&s(k, phi))
        .flags
        .contains(Flags::MEASUREMENT_SKIPPED)
}

#[test]
fn a_step_is_skipped_reacquire_after_times_then_followed() {
    let st = ModelSettings {
        reacquire_after: 5,
        ..ModelSettings::<f64>::default()
    };
    let mut e = ModelBased::<f64, ExtendedKalman<f64>>::new(st);
    for k in 0..2000 {
        e.update(&s(k, 0.1));
    }
    // A glitch shorter than reacquire_after: skipped, the estimate untouched.
    let before = e.state().unwrap()[THETA];
    assert!((2000..2004).all(|k| skipped(&mut e, k, 0.4)));
    assert!((e.state().unwrap()[THETA] - before).abs() < 1e-6);
    assert!(!skipped(&mut e, 2004, 0.1));
    // A step that stays: five rejections, then re-acquired and never rejected again.
    let flags: [bool; 10] = core::array::from_fn(|i| skipped(&mut e, 2005 + i, 0.4));
    assert_eq!(
        flags,
        [true, true, true, true, true, false, false, false, false, false]
    );
    let mut theta = 0.0;
    for k in 2015..3000 {
        let o = e.update(&s(k, 0.4));
        assert!(!o.flags.contains(Flags::MEASUREMENT_SKIPPED), "sample {k}");
        theta = o.theta;
    }
    assert!((theta - 0.4).abs() < 1e-3, "{theta}");
}

#[test]
fn the_reading_after_a_gap_is_taken_ungated() {
    let mut e = ModelBased::<f64, ExtendedKalman<f64>>::new(ModelSettings::default());
    for k in 0..2000 {
        e.update(&s(k, 0.1));
    }
    assert!(skipped(&mut e, 2000, f64::NAN));
    // Far outside the gate, but the first reading after a gap.
    assert!(!skipped(&mut e, 2001, 0.2));
    // Without the gap it is an outlier.
    let mut f = ModelBased::<f64, ExtendedKalman<f64>>::new(ModelSettings::default());
    for k in 0..2001 {
        f.update(&s(k, 0.1));
    }
    assert!(skipped(&mut f, 2001, 0.2));
}

/// A still body on a gyro with a 0.01 rad/s bias: 20 s to learn the bias.
fn biased(phi: f64, gyro: f64, k: usize) -> Sample<f64> {
    Sample {
        gyro: if gyro.is_nan() { gyro } else { gyro + 0.01 },
        ..s(k, phi)
    }
}

#[test]
fn resume_keeps_the_bias_and_reset_forgets_it() {
    let mut e = ModelBased::<f64, ExtendedKalman<f64>>::new(ModelSettings::default());
    for k in 0..20_000 {
        e.update(&biased(0.1, 0.0, k));
    }
    let learnt = e.bias();
    assert!((learnt - 0.01).abs() < 1e-3, "{learnt}");
    let var = e.covariance().unwrap()[(BIAS, BIAS)];
    let mut f = e.clone();
    e.resume();
    // The next row comes 10 s later: the bias walked.
    let out = e.update(&Sample {
        dt: 10.0,
        ..biased(0.1, 0.0, 1)
    });
    assert!(out.flags.contains(Flags::INITIALISING));
    assert!((e.bias() - learnt).abs() < 1e-12);
    let walk = e.settings().process.bias * 10.0;
    let grown = e.covariance().unwrap()[(BIAS, BIAS)];
    assert!(
        (grown - (var + walk)).abs() <= 1e-9 * grown,
        "{grown} {var} {walk}"
    );
    f.reset();
    f.update(&biased(0.1, 0.0, 0));
    assert_eq!(f.bias(), 0.0);
}

#[test]
fn an_encoder_gap_is_bridged_with_the_gyro_and_restarts_without_it() {
    let mut e = ModelBased::<f64, ExtendedKalman<f64>>::new(ModelSettings::default());
    for k in 0..20_000 {
        e.update(&biased(0.1, 0.0, k));
    }
    let learnt = e.bias();
    // 100 ms without the encoder (twice max_gap), the gyro there: no restart.
    let mut f = e.clone();
    for k in 0..100 {
        f.update(&biased(f64::NAN, 0.0, k + 1));
    }
    let back = f.update(&biased(0.1, 0.0, 101));
    assert!(!back.flags.contains(Flags::INITIALISING), "{back:?}");
    assert!((back.theta - 0.1).abs() < 1e-3, "{back:?}");
    // Without the gyro too: a restart that keeps the bias.
    for k in 0..100 {
        e.update(&biased(f64::NAN, f64::NAN, k + 1));
    }
    let back = e.update(&biased(0.1, 0.0, 101));
    assert!(back.flags.contains(Flags::INITIALISING), "{back:?}");
    assert!((e.bias() - learnt).abs() < 1e-12);
}

#[test]
fn a_gyro_gap_leaves_theta_and_the_bias_where_they_were() {
    let mut e = ModelBased::<f64, ExtendedKalman<f64>>::new(ModelSettings::default());
    for k in 0..20_000 {
        e.update(&biased(0.1, 0.0, k));
    }
    let learnt = e.bias();
    for k in 0..100 {
        e.update(&biased(0.1, f64::NAN, k + 1));
    }
    // Back with a reading off by a vibration-sized 0.2 rad/s for one sample.
    e.update(&biased(0.1, 0.2, 101));
    let mut theta = 0.0;
    for k in 102..1000 {
        theta = e.update(&biased(0.1, 0.0, k)).theta;
    }
    assert!((theta - 0.1).abs() < 1e-3, "{theta}");
    assert!((e.bias() - learnt).abs() < 1e-3, "{} {learnt}", e.bias());
}
