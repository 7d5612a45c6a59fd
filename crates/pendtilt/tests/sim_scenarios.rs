//! The named scenarios run and look like what they stand for; bad settings are refused
//! with the key named.

use pendtilt::sim::planar::{simulate, Scenario, SimError, Simulator, SCENARIO_NAMES};

#[test]
fn every_named_scenario_runs_with_finite_values() {
    for name in SCENARIO_NAMES {
        let mut s = Scenario::named(name).unwrap();
        s.duration = s.duration.min(5.0);
        let rows = simulate(&s, 1).unwrap();
        assert_eq!(rows.len() as u64, s.rows(), "{name}");
        for r in &rows {
            assert!(
                [r.t, r.phi, r.gyro, r.ax, r.ay, r.theta]
                    .iter()
                    .all(|x| x.is_finite()),
                "{name} at {}",
                r.t
            );
        }
        // The MODEL.md section 6 start: the pendulum hangs still in the world.
        assert_eq!(rows[0].truth.beta, 0.0);
        assert_eq!(rows[0].truth.beta_dot, 0.0);
    }
}

#[test]
fn sigmoid_is_the_papers_figure_5_input() {
    let s = Scenario::named("sigmoid").unwrap();
    let rows = simulate(&s, 1).unwrap();
    assert_eq!(rows.len(), 5000);
    let at = |t: f64| rows[(t * 1000.0) as usize].truth.theta;
    assert!(at(0.0) < 1e-5);
    assert!((at(2.0) - 5f64.to_radians()).abs() < 1e-12);
    assert!((at(4.999) - 10f64.to_radians()).abs() < 1e-5);
}

#[test]
fn scooter_looks_like_the_papers_ride() {
    let s = Scenario::named("scooter").unwrap();
    let rows = simulate(&s, 1).unwrap();
    let n = rows.len() as f64;
    // Slow tilting within about +-15 deg.
    let peak = rows.iter().map(|r| r.truth.theta.abs()).fold(0.0, f64::max);
    assert!(
        peak < 15.5f64.to_radians() && peak > 5f64.to_radians(),
        "{}",
        peak.to_degrees()
    );
    // Vibration of a few m/s^2 at the accelerometer.
    let mean_ay = rows.iter().map(|r| r.ay).sum::<f64>() / n;
    let ay_rms = (rows.iter().map(|r| (r.ay - mean_ay).powi(2)).sum::<f64>() / n).sqrt();
    assert!((2.0..6.0).contains(&ay_rms), "ay rms {ay_rms}");
    // The paper's point: the raw pendulum beats the accelerometer angle under vibration.
    let rms = |f: &dyn Fn(&pendtilt::sim::planar::SimRow) -> f64| {
        (rows.iter().map(|r| f(r).powi(2)).sum::<f64>() / n).sqrt()
    };
    let accel_err = rms(&|r| r.ax.atan2(r.ay) - r.truth.theta);
    let pend_err = rms(&|r| r.phi - r.truth.theta);
    assert!(
        pend_err < accel_err / 3.0,
        "pendulum {pend_err} vs accel {accel_err}"
    );
    assert!(
        pend_err > 1e-3,
        "{pend_err}: the pendulum should still lag and overshoot"
    );
}

#[test]
fn bad_settings_name_the_key() {
    let mut s = Scenario::named("scooter").unwrap();
    s.pendulum.mass = -1.0;
    let e = Simulator::new(&s, 1).unwrap_err();
    assert!(
        matches!(e, SimError::Invalid { ref key, .. } if key == "pendulum.mass"),
        "{e}"
    );
    let mut s = Scenario::named("scooter").unwrap();
    // 100 Hz x 2 substeps: nodes at 200 Hz cannot carry a 200 Hz band.
    s.rate = 100.0;
    let e = Simulator::new(&s, 1).unwrap_err().to_string();
    assert!(e.contains("vibration.broadband.band"), "{e}");
    let mut s = Scenario::named("sine").unwrap();
    s.sensors.gyro.noise_density = f64::NAN;
    let e = Simulator::new(&s, 1).unwrap_err().to_string();
    assert!(e.contains("sensors.gyro.noise_density"), "{e}");
    let mut s = Scenario::named("sine").unwrap();
    s.substeps = 0;
    assert!(Simulator::new(&s, 1).is_err());
    let e = Scenario::named("tractor").unwrap_err().to_string();
    assert!(e.contains("scooter"), "{e}");
}
