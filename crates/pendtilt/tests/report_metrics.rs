//! Metrics against hand-computed cases.
use pendtilt::report::metrics::{
    compute_metrics, detect_step, lag_by_xcorr, overshoot_pct, rate_from_times, settling_band,
    settling_time_s, AngleUnit, ErrorSamples, MetricsConfig, StepConfig, DEG_PER_RAD,
};
use pendtilt::report::ReportError;

fn deg_cfg() -> MetricsConfig {
    MetricsConfig {
        input_unit: AngleUnit::Deg,
        ..MetricsConfig::default()
    }
}

/// A smooth, non-periodic-looking test motion [deg].
fn motion(t: f64) -> f64 {
    use std::f64::consts::PI;
    8.0 * (2.0 * PI * 0.7 * t).sin()
        + 3.0 * (2.0 * PI * 1.3 * t + 0.4).sin()
        + 1.5 * (2.0 * PI * 0.23 * t).cos()
}

fn sampled(rate: f64, seconds: f64, delay_s: f64) -> (Vec<f64>, Vec<f64>) {
    let n = (rate * seconds) as usize;
    let truth = (0..n).map(|k| motion(k as f64 / rate)).collect();
    let est = (0..n).map(|k| motion(k as f64 / rate - delay_s)).collect();
    (est, truth)
}

#[test]
fn rms_bias_std_max_of_a_known_sequence() {
    // errors 3, 4: rms = sqrt((9 + 16) / 2), bias 3.5, std 0.5, max 4
    let e = ErrorSamples::new(&[3.0, 4.0], &[0.0, 0.0]).unwrap();
    assert!((e.rms() - 12.5f64.sqrt()).abs() < 1e-12);
    assert!((e.bias() - 3.5).abs() < 1e-12);
    assert!((e.std_dev() - 0.5).abs() < 1e-12);
    assert_eq!(e.max_abs(), 4.0);
    // alternating +-1 about a truth of 5: rms 1, bias 0, std 1
    let m = compute_metrics("alt", &[6.0, 4.0, 6.0, 4.0], &[5.0; 4], 10.0, &deg_cfg()).unwrap();
    assert!((m.rms_deg - 1.0).abs() < 1e-12);
    assert!(m.bias_deg.abs() < 1e-12);
    assert!((m.std_deg - 1.0).abs() < 1e-12);
    assert_eq!(m.max_abs_deg, 1.0);
    assert_eq!(m.samples_used, 4);
}

#[test]
fn constant_offset_is_all_bias_and_no_lag() {
    let (truth, _) = sampled(200.0, 10.0, 0.0);
    let est: Vec<f64> = truth.iter().map(|v| v + 0.3).collect();
    let m = compute_metrics("offset", &est, &truth, 200.0, &deg_cfg()).unwrap();
    assert!((m.bias_deg - 0.3).abs() < 1e-9);
    assert!((m.rms_deg - 0.3).abs() < 1e-9);
    assert!(m.std_deg < 1e-9);
    assert!(m.lag_ms.unwrap().abs() < 1e-6);
    assert!((m.lag_correlation.unwrap() - 1.0).abs() < 1e-9);
    assert_eq!(m.within_tolerance_pct, 100.0);
}

#[test]
fn radians_are_reported_in_degrees() {
    let truth = vec![0.1; 50];
    let est = vec![0.11; 50];
    let m = compute_metrics("rad", &est, &truth, 50.0, &MetricsConfig::default()).unwrap();
    assert!((m.bias_deg - 0.01 * DEG_PER_RAD).abs() < 1e-9);
}

#[test]
fn share_within_tolerance_counts_the_band_edges() {
    // |errors| 0.1, 0.4, 0.5, 0.6, 0.7: three within +-0.5 deg
    let truth = [0.0; 5];
    let est = [0.1, 0.4, 0.5, 0.6, -0.7];
    let m = compute_metrics("tol", &est, &truth, 1.0, &deg_cfg()).unwrap();
    assert!((m.within_tolerance_pct - 60.0).abs() < 1e-12);
    assert_eq!(m.tolerance_deg, 0.5);
}

#[test]
fn known_integer_delay_gives_its_lag() {
    let (est, truth) = sampled(1000.0, 10.0, 0.020);
    let m = compute_metrics("late", &est, &truth, 1000.0, &deg_cfg()).unwrap();
    let lag = m.lag_ms.unwrap();
    assert!((lag - 20.0).abs() < 0.05, "lag {lag} ms");
}

#[test]
fn known_sub_sample_delay_is_refined_by_the_parabola() {
    // 12.3 ms at 100 Hz = 1.23 samples: the integer peak alone would say 10 ms
    let (est, truth) = sampled(100.0, 20.0, 0.0123);
    let l = lag_by_xcorr(&est, &truth, 100.0, 0.2).unwrap();
    assert!(
        (l.lag_samples - 1.23).abs() < 0.05,
        "lag {} samples",
        l.lag_samples
    );
    assert!((l.lag_s - 0.0123).abs() < 0.0005);
    // an estimate ahead of the truth has a negative lag
    let (early, truth) = sampled(100.0, 20.0, -0.0377);
    let l = lag_by_xcorr(&early, &truth, 100.0, 0.2).unwrap();
    assert!(
        (l.lag_samples + 3.77).abs() < 0.05,
        "lag {} samples",
        l.lag_samples
    );
}

#[test]
fn lag_ignores_bias_and_skips_nan() {
    let (mut est, truth) = sampled(500.0, 8.0, 0.05);
    for v in est.iter_mut() {
        *v += 2.0;
    }
    est[100] = f64::NAN;
    est[2000] = f64::NAN;
    let l = lag_by_xcorr(&est, &truth, 500.0, 0.3).unwrap();
    assert!((l.lag_s - 0.05).abs() < 1e-4, "lag {} s", l.lag_s);
}

#[test]
fn lag_outside_the_window_is_an_error_not_a_wrong_number() {
    let (est, truth) = sampled(100.0, 20.0, 0.3);
    let r = lag_by_xcorr(&est, &truth, 100.0, 0.1);
    assert!(matches!(r, Err(ReportError::Lag(_))), "{r:?}");
    let m = compute_metrics(
        "far",
        &est,
        &truth,
        100.0,
        &MetricsConfig {
            max_lag_s: 0.1,
            ..deg_cfg()
        },
    )
    .unwrap();
    assert_eq!(m.lag_ms, None);
    assert!(m.notes.iter().any(|n| n.contains("edge")), "{:?}", m.notes);
    // a delayed copy buried in noise: the lag comes out, flagged as unreliable
    let (late, truth) = sampled(100.0, 20.0, 0.05);
    let noisy: Vec<f64> = late
        .iter()
        .enumerate()
        .map(|(k, v)| v + ((k * 7919 % 1009) as f64 / 1009.0 - 0.5) * 36.0)
        .collect();
    let m = compute_metrics("noisy", &noisy, &truth, 100.0, &deg_cfg()).unwrap();
    let r = m.lag_correlation.unwrap();
    assert!(r < 0.8 && r > 0.2, "r {r}");
    assert!(
        m.notes.iter().any(|n| n.contains("unreliable")),
        "{:?}",
        m.notes
    );
    // a constant estimate has no correlation at all
    let flat = vec![1.0; truth.len()];
    assert!(lag_by_xcorr(&flat, &truth, 100.0, 0.1).is_err());
}

#[test]
fn nan_samples_are_counted_and_excluded() {
    let truth = [1.0, 2.0, 3.0, 4.0, 5.0, f64::NAN];
    let est = [1.5, f64::NAN, 3.5, f64::INFINITY, 5.5, 6.0];
    let m = compute_metrics("holes", &est, &truth, 10.0, &deg_cfg()).unwrap();
    assert_eq!(m.samples, 6);
    assert_eq!(m.non_finite_estimate, 2);
    assert_eq!(m.non_finite_truth, 1);
    assert_eq!(m.samples_used, 3);
    assert!((m.bias_deg - 0.5).abs() < 1e-12);
    assert!((m.rms_deg - 0.5).abs() < 1e-12);
    assert!(m.rms_deg.is_finite() && m.max_abs_deg.is_finite());
}

#[test]
fn bad_input_is_an_error() {
    let all_nan = [f64::NAN; 4];
    assert!(matches!(
        compute_metrics("x", &all_nan, &[0.0; 4], 10.0, &deg_cfg()),
        Err(ReportError::NoValidSamples {
            non_finite_estimate: 4,
            ..
        })
    ));
    assert!(matches!(
        compute_metrics("x", &[0.0; 3], &[0.0; 4], 10.0, &deg_cfg()),
        Err(ReportError::LengthMismatch {
            expected: 4,
            got: 3,
            ..
        })
    ));
    assert!(matches!(
        compute_metrics("x", &[], &[], 10.0, &deg_cfg()),
        Err(ReportError::Empty(_))
    ));
    for bad_rate in [0.0, -5.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            compute_metrics("x", &[0.0; 4], &[0.0; 4], bad_rate, &deg_cfg()),
            Err(ReportError::InvalidRate(_))
        ));
    }
}

#[test]
fn rate_from_a_time_column() {
    let t: Vec<f64> = (0..11).map(|k| 0.5 + k as f64 * 0.01).collect();
    assert!((rate_from_times(&t).unwrap() - 100.0).abs() < 1e-9);
    assert!(rate_from_times(&[0.0]).is_err());
    assert!(matches!(
        rate_from_times(&[0.0, 0.1, 0.1, 0.2]),
        Err(ReportError::TimeNotIncreasing { index: 2 })
    ));
}

/// Ideal step 0 -> 10 deg at sample 200 of 500 (100 Hz).
fn ideal_step() -> Vec<f64> {
    (0..500).map(|k| if k < 200 { 0.0 } else { 10.0 }).collect()
}

#[test]
fn known_overshoot_and_settling_time() {
    let truth = ideal_step();
    // 11.5 deg for 0.5 s after the step (15% overshoot), then 10.3 (inside the 0.5 deg band)
    let est: Vec<f64> = (0..500)
        .map(|k| match k {
            0..=199 => 0.0,
            200..=249 => 11.5,
            250..=299 => 10.3,
            _ => 10.0,
        })
        .collect();
    let cfg = StepConfig::default();
    let step = detect_step(&truth, 100.0, &cfg).unwrap();
    assert_eq!(step.index, 200);
    assert!((step.time_s - 2.0).abs() < 1e-12);
    assert_eq!(step.size, 10.0);
    assert!((overshoot_pct(&est, &step).unwrap() - 15.0).abs() < 1e-9);
    // band: max(2% of 10, 0.5) = 0.5 deg; last sample outside is 249, settled from 250
    assert_eq!(settling_band(&step, &cfg), 0.5);
    assert!((settling_time_s(&est, &step, 100.0, 0.5).unwrap() - 0.5).abs() < 1e-12);

    let m = compute_metrics("bump", &est, &truth, 100.0, &deg_cfg()).unwrap();
    assert!((m.overshoot_pct.unwrap() - 15.0).abs() < 1e-9);
    assert!((m.settling_time_s.unwrap() - 0.5).abs() < 1e-12);
    // the truth itself: no overshoot, settled at once
    let m = compute_metrics("truth", &truth, &truth, 100.0, &deg_cfg()).unwrap();
    assert_eq!(m.overshoot_pct, Some(0.0));
    assert_eq!(m.settling_time_s, Some(0.0));
}

#[test]
fn downward_step_overshoot_counts_downwards() {
    let truth: Vec<f64> = ideal_step().iter().map(|v| 10.0 - v).collect();
    let est: Vec<f64> = (0..500)
        .map(|k| match k {
            0..=199 => 10.0,
            200..=219 => -2.0,
            _ => 0.0,
        })
        .collect();
    let m = compute_metrics("down", &est, &truth, 100.0, &deg_cfg()).unwrap();
    assert!((m.overshoot_pct.unwrap() - 20.0).abs() < 1e-9);
    assert!((m.settling_time_s.unwrap() - 0.2).abs() < 1e-12);
}

#[test]
fn estimate_that_does_not_settle_has_no_settling_time() {
    let truth = ideal_step();
    let mut est = truth.clone();
    *est.last_mut().unwrap() = 11.0;
    let m = compute_metrics("late", &est, &truth, 100.0, &deg_cfg()).unwrap();
    assert_eq!(m.settling_time_s, None);
    assert!(m.notes.iter().any(|n| n.contains("settling")));
}

#[test]
fn sigmoid_is_a_step_and_sine_is_not() {
    let rate = 1000.0;
    let sig: Vec<f64> = (0..5000)
        .map(|k| 10.0 / (1.0 + (-((k as f64 / rate) - 2.0) / 0.2).exp()))
        .collect();
    let step = detect_step(&sig, rate, &StepConfig::default()).unwrap();
    assert!((step.time_s - 2.0).abs() < 0.002, "{}", step.time_s);
    assert!((step.size - 10.0).abs() < 0.01);

    let (sine, _) = sampled(rate, 10.0, 0.0);
    assert!(matches!(
        detect_step(&sine, rate, &StepConfig::default()),
        Err(ReportError::NotStepLike(_))
    ));
    let m = compute_metrics("sine", &sine, &sine, rate, &deg_cfg()).unwrap();
    assert_eq!(m.overshoot_pct, None);
    assert_eq!(m.settling_time_s, None);
}

#[test]
fn metrics_serialise_to_json() {
    let m = compute_metrics("alg1", &[1.0, 2.0], &[1.0, 2.5], 10.0, &deg_cfg()).unwrap();
    let v: serde_json::Value = serde_json::to_value(&m).unwrap();
    assert_eq!(v["name"], "alg1");
    assert_eq!(v["bias_deg"], -0.25);
    assert!(v["lag_ms"].is_null());
}
