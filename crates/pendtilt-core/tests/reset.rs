//! `reset` forgets the run and nothing else: after a run and a reset, every estimator (and
//! inv3d, its spatial counterpart) gives on a log what a new one built from the same
//! settings gives: the same flags and the
//! same angles to 1e-12 rad. Resets rebuild the state only (the settings and the
//! coefficients derived from them stay), so a state field a reset forgets shows up here.
//! (Not bit for bit: the differentiator keeps its discretisation for steps within 1e-9 of
//! the cached one, and which of two such steps was cached first moves the last bits.)
use pendtilt_core::ekf::{Ekf, ModelSettings};
use pendtilt_core::estimators::accel::{Accel, AccelSettings};
use pendtilt_core::estimators::alg1::{Alg1, Alg1Settings};
use pendtilt_core::estimators::alg2::{Alg2, Alg2Settings};
use pendtilt_core::estimators::alg3::{Alg3, Alg3Settings};
use pendtilt_core::estimators::complementary::{Complementary, ComplementarySettings};
use pendtilt_core::estimators::pendulum::{Pendulum, PendulumSettings};
use pendtilt_core::estimators::theta_dd::ThetaDdSource;
use pendtilt_core::kalman::{KalmanOn, KalmanSettings};
use pendtilt_core::params::GyroSettings;
use pendtilt_core::spatial::inv::{Inv3d, Inv3dSettings};
use pendtilt_core::spatial::{Attitude, SpatialSample};
use pendtilt_core::supervision::{SupervisedAlg3, SupervisedAlg3Settings};
use pendtilt_core::{Estimate, Estimator, PendulumParams, PlanarEstimator, Sample, StepGate};

/// A tilting, vibrating body with a jittered step, a missing phi, a gyro gap, a clipped
/// gyro and a repeated stamp: every path of the estimators' state is taken.
fn log(seconds: f64, phase: f64) -> Vec<Sample<f64>> {
    let mut gate = StepGate::new();
    let mut t = 0.0f64;
    let n = (seconds * 1000.0) as usize;
    (0..n)
        .map(|k| {
            t += if k % 5 == 0 { 1.4e-3 } else { 1e-3 };
            let stamp = if k == n / 2 { t - 2e-3 } else { t };
            let th = 0.3 * (1.3 * t + phase).sin() + 0.01 * (170.0 * t).sin();
            let rate = 0.39 * (1.3 * t + phase).cos() + 1.7 * (170.0 * t).cos();
            Sample {
                dt: gate.step(stamp),
                phi: if k == n / 3 { f64::NAN } else { 0.8 * th },
                gyro: if (n / 4..n / 4 + 30).contains(&k) {
                    f64::NAN
                } else {
                    rate.clamp(-1.5, 1.5)
                },
                ax: 9.81 * th.sin() + 0.5 * (90.0 * t).sin(),
                ay: 9.81 * th.cos(),
            }
        })
        .collect()
}

fn run(e: &mut dyn PlanarEstimator<f64>, log: &[Sample<f64>]) -> Vec<Estimate<f64>> {
    log.iter().map(|s| e.update(s)).collect()
}

fn check(
    name: &str,
    mut used: Box<dyn PlanarEstimator<f64>>,
    mut fresh: Box<dyn PlanarEstimator<f64>>,
) {
    let (first, second) = (log(3.0, 0.0), log(2.0, 0.7));
    let before = run(used.as_mut(), &first);
    assert!(before.iter().any(|e| e.theta.is_finite()), "{name} ran");
    used.reset();
    let again = run(used.as_mut(), &second);
    let want = run(fresh.as_mut(), &second);
    for (k, (a, w)) in again.iter().zip(&want).enumerate() {
        assert_eq!(a.flags, w.flags, "{name} sample {k}");
        assert!(
            (a.theta - w.theta).abs() <= 1e-12 || (a.theta.is_nan() && w.theta.is_nan()),
            "{name} sample {k}: {} after reset, {} new",
            a.theta,
            w.theta
        );
    }
}

#[test]
fn reset_equals_a_new_estimator() {
    let p = PendulumParams {
        c: 0.01,
        ..PendulumParams::default()
    };
    let gyro = GyroSettings {
        full_scale: Some(1.5),
    };
    let accel = AccelSettings {
        prefilter_hz: Some(5.0),
        full_scale: Some(60.0),
    };
    let mut a2 = Alg2Settings::from_params(p);
    a2.front_end.gyro = gyro;
    a2.front_end.theta_dd = ThetaDdSource::Window { span: 0.01 };
    let mut a3 = Alg3Settings::from_params(p);
    a3.front_end.gyro = gyro;
    let kalman = KalmanSettings {
        gyro,
        ..KalmanSettings::default()
    };
    let complementary = ComplementarySettings::default();
    let supervised = SupervisedAlg3Settings {
        alg3: a3,
        ..SupervisedAlg3Settings::default()
    };
    type Make = Box<dyn Fn() -> Box<dyn PlanarEstimator<f64>>>;
    let all: Vec<(&str, Make)> = vec![
        ("accel", Box::new(move || Box::new(Accel::new(accel)))),
        (
            "pendulum",
            Box::new(|| Box::new(Pendulum::new(PendulumSettings {}))),
        ),
        (
            "alg1",
            Box::new(move || Box::new(Alg1::new(Alg1Settings::from_params(p)))),
        ),
        ("alg2", Box::new(move || Box::new(Alg2::<f64>::new(a2)))),
        ("alg3", Box::new(move || Box::new(Alg3::<f64>::new(a3)))),
        (
            "complementary",
            Box::new(move || Box::new(Complementary::new(complementary))),
        ),
        (
            "kf_alg2",
            Box::new(move || {
                Box::new(KalmanOn::new(
                    Alg2::<f64>::new(a2),
                    kalman.r_pendulum,
                    kalman,
                ))
            }),
        ),
        (
            "kf_accel",
            Box::new(move || Box::new(KalmanOn::new(Accel::new(accel), kalman.r_accel, kalman))),
        ),
        (
            "supervised_alg3",
            Box::new(move || {
                Box::new(SupervisedAlg3::<f64>::new(supervised).expect("valid settings"))
            }),
        ),
        (
            "ekf",
            Box::new(|| Box::new(Ekf::<f64>::new(ModelSettings::default()))),
        ),
    ];
    for (name, make) in &all {
        check(name, make(), make());
    }
}

/// The planar log on two axes, with a speed that comes and goes: every path of inv3d's
/// front ends and of its travel filters is taken.
fn spatial_log(seconds: f64, phase: f64) -> Vec<SpatialSample<f64>> {
    log(seconds, phase)
        .iter()
        .enumerate()
        .map(|(k, s)| SpatialSample {
            speed: if k % 700 < 40 {
                f64::NAN
            } else {
                6.0 + (k as f64 * 1e-3 + phase).sin()
            },
            ..SpatialSample::new(
                s.dt,
                [s.phi, 0.5 * s.phi - 0.02],
                [s.gyro, 0.5 * s.gyro, 0.1 * s.gyro],
                [s.ax, 0.3, s.ay],
            )
        })
        .collect()
}

#[test]
fn inv3d_reset_equals_a_new_estimator() {
    let mut settings = Inv3dSettings::<f64>::default();
    settings.params.c = [0.002, -0.001, 0.01];
    settings.mounting.speed_at = [0.4, 0.1, -0.3];
    settings.front_end.gyro = GyroSettings {
        full_scale: Some(1.5),
    };
    let run = |e: &mut Inv3d<f64>, log: &[SpatialSample<f64>]| -> Vec<Attitude<f64>> {
        log.iter().map(|s| e.update(s)).collect()
    };
    let (mut used, mut fresh) = (Inv3d::new(settings), Inv3d::new(settings));
    let before = run(&mut used, &spatial_log(3.0, 0.0));
    assert!(before.iter().any(|a| a.roll.is_finite()), "inv3d ran");
    used.reset();
    let second = spatial_log(2.0, 0.7);
    let (again, want) = (run(&mut used, &second), run(&mut fresh, &second));
    for (k, (a, w)) in again.iter().zip(&want).enumerate() {
        assert_eq!(a.flags, w.flags, "inv3d sample {k}");
        for (x, y) in [(a.roll, w.roll), (a.pitch, w.pitch)] {
            assert!(
                (x - y).abs() <= 1e-12 || (x.is_nan() && y.is_nan()),
                "inv3d sample {k}: {a:?} after reset, {w:?} new"
            );
        }
    }
}
