//! The 3-D fit (`pendtilt::fit::cardan`) against the simulator's truth: a rig that is not
//! MODEL.md 7.6's recovered with and without the true angles, a still log refused as
//! unidentifiable, an implausible rig named, and the fitted rig read back by the 3-D rig
//! reader.
use pendtilt::bank::spatial::rig::Rig3dConfig;
use pendtilt::core::spatial::cardan::CardanParams;
use pendtilt::fit::cardan::{
    check, fit_cardan, rig::rig_toml, Fit3dReport, Fit3dSettings, Implausible3d, Log3dColumns,
    NoiseDensities,
};
use pendtilt::fit::plausibility::LogSpan;
use pendtilt::fit::{FitError, Target};
use pendtilt::sim::spatial::{Pendulum3d, Scenario3d};

/// A pendulum of natural frequency `hz` and damping ratio `zeta` on both axes, MODEL.md
/// 7.6's mass and length.
fn rig(hz: f64, zeta: f64) -> Pendulum3d {
    let p = Pendulum3d::default();
    let mgl = p.mgl();
    let inertia = mgl / (std::f64::consts::TAU * hz).powi(2);
    Pendulum3d {
        inertia_xx: inertia,
        inertia_yy: inertia,
        damping_x: zeta * 2.0 * (inertia * mgl).sqrt(),
        damping_y: zeta * 2.0 * (inertia * mgl).sqrt(),
        ..p
    }
}

/// A scooter3d log of `seconds` with pendulum `p` and the gyro's noise and bias walk
/// times `gyro_scale`; the log and the sensors' noise densities.
fn scooter(
    p: Pendulum3d,
    seconds: f64,
    seed: u64,
    gyro_scale: f64,
) -> (Log3dColumns, NoiseDensities) {
    let mut s = Scenario3d::named("scooter3d", seed).unwrap();
    s.duration = seconds;
    s.rig.pendulum3d = p;
    s.sensors.gyro_noise_density *= gyro_scale;
    s.sensors.gyro_bias_walk *= gyro_scale;
    let rows: Vec<_> = s.run(seed).unwrap().map(|(_, r)| r).collect();
    let noise = NoiseDensities {
        accel: [s.sensors.accel_noise_density; 2],
        gyro: [s.sensors.gyro_noise_density; 2],
    };
    (Log3dColumns::from_rows(&rows), noise)
}

/// The largest relative error of a_x, a_y, b_x + b_ring, b_y against `truth`.
fn worst_error(r: &Fit3dReport, truth: &CardanParams<f64>) -> f64 {
    let want = [truth.a_x, truth.a_y, truth.b_x + truth.b_ring, truth.b_y];
    (0..4)
        .map(|j| (r.params[j] / want[j] - 1.0).abs())
        .fold(0.0, f64::max)
}

/// A 1.2 Hz pendulum at zeta 0.15, its pivot 5 mm above the IMU, a consumer gyro (ten
/// times the noise density and bias walk of MODEL.md 7.8's), from MODEL.md 7.6's rig as
/// the start (2.19 Hz, zeta 0.30, no offset: c_z is held there, the log does not show it):
/// within 3 % against the truth and 5 % from the gyro, and the fit says it is plausible.
#[test]
fn an_unseen_rig_is_recovered_with_and_without_truth() {
    let p = Pendulum3d {
        pivot_offset: [0.0, 0.0, 0.005],
        ..rig(1.2, 0.15)
    };
    let (log, noise) = scooter(p, 40.0, 1, 10.0);
    let span = LogSpan::of(log.t.iter().copied()).unwrap();
    for (target, bound) in [(Target::Truth, 0.03), (Target::Gyro, 0.05)] {
        let s = Fit3dSettings {
            target,
            noise: Some(noise),
            ..Fit3dSettings::default()
        };
        let r = fit_cardan(&log, &CardanParams::default(), [0.0; 3], &s, |_| {}).unwrap();
        let e = worst_error(&r, &p.normalised());
        println!("{target:?}: worst {:.2} % {:?}", 100.0 * e, r.params);
        assert!(
            e < bound,
            "{target:?}: {:.2} % off: {:?}",
            100.0 * e,
            r.params
        );
        assert!(!r.active[4], "c_z is not identifiable from a scooter ride");
        assert!(check(&r.fitted, &span).is_empty());
        let f = r.natural_frequencies_hz();
        assert!(
            (f[0] - 1.2).abs() < 0.05 && (f[1] - 1.2).abs() < 0.05,
            "{f:?}"
        );
    }
}

/// Without the noise correction the sensors' noise pulls the damping up: the correction
/// is what brings the fit within the target (the same log, truth target).
#[test]
fn the_noise_correction_takes_out_the_sensors_bias() {
    let p = rig(1.2, 0.15);
    let (log, noise) = scooter(p, 40.0, 1, 1.0);
    let run = |noise| {
        let s = Fit3dSettings {
            noise,
            ..Fit3dSettings::default()
        };
        let r = fit_cardan(&log, &CardanParams::default(), [0.0; 3], &s, |_| {}).unwrap();
        worst_error(&r, &p.normalised())
    };
    let (with, without) = (run(Some(noise)), run(None));
    println!("with {with:.4} without {without:.4}");
    assert!(with < 0.03 && without > with, "{with} {without}");
}

/// A log at rest moves no pendulum: refused as unidentifiable, with the sensitivity.
#[test]
fn a_still_log_is_unidentifiable() {
    let n = 10_000;
    let mut log = Log3dColumns::default();
    for k in 0..n {
        let wiggle = 1e-6 * ((k * 7919) % 13) as f64;
        log.t.push(k as f64 * 1e-3);
        log.phi.push([wiggle, -wiggle]);
        log.gyro.push([wiggle, 0.0, -wiggle]);
        log.accel.push([wiggle, 0.0, 9.80665]);
        log.truth.push([0.0, 0.0]);
    }
    for target in [Target::Truth, Target::Gyro] {
        let s = Fit3dSettings {
            target,
            ..Fit3dSettings::default()
        };
        match fit_cardan(&log, &CardanParams::default(), [0.0; 3], &s, |_| {}) {
            Err(e @ FitError::Unidentifiable { .. }) => {
                let text = e.to_string();
                assert!(
                    text.contains("not identifiable") && text.contains("more motion"),
                    "{text}"
                );
            }
            other => panic!("{target:?}: {other:?}"),
        }
    }
}

/// A ring eight times the pendulum's inertia makes the outer joint three times slower
/// than the inner: the fit finds it (it is what the log shows) and the check names it.
#[test]
fn a_ring_heavier_than_a_cardan_rig_allows_is_named() {
    let mut p = rig(2.0, 0.3);
    p.ring_inertia = 8.0 * p.inertia_xx;
    let (log, _) = scooter(p, 20.0, 2, 1.0);
    let r = fit_cardan(
        &log,
        &CardanParams::default(),
        [0.0; 3],
        &Fit3dSettings::default(),
        |_| {},
    )
    .unwrap();
    let span = LogSpan::of(log.t.iter().copied()).unwrap();
    let why = check(&r.fitted, &span);
    assert!(
        matches!(&why[..], [Implausible3d::FrequencyRatio { f_outer, f_inner, .. }] if f_inner / f_outer > 2.5),
        "{why:?}"
    );
}

/// The written rig reads back as the fitted pendulum, with the start rig's held values.
#[test]
fn the_fitted_rig_reads_back() {
    let (log, _) = scooter(rig(1.8, 0.25), 15.0, 3, 1.0);
    let start = CardanParams {
        b_ring: 1e-4,
        c: [0.001, 0.0, 0.0],
        ..CardanParams::default()
    };
    let r = fit_cardan(&log, &start, [0.0; 3], &Fit3dSettings::default(), |_| {}).unwrap();
    let text = rig_toml(&r.fitted, None, &Rig3dConfig::default(), &[]).unwrap();
    let back = Rig3dConfig::from_toml_str(&text, "fitted.toml")
        .unwrap()
        .pendulum3d
        .params();
    assert_eq!(back, r.fitted);
    assert_eq!((back.b_ring, back.c[0]), (1e-4, 0.001));
    assert!((back.b_x + back.b_ring - r.params[2]).abs() < 1e-15);
}
