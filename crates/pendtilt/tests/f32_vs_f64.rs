//! f32 against f64 (issue 6, item 6): on a simulated scooter ride, every estimator run in
//! `f32` stays within 0.01 deg RMS of the same estimator in `f64`.
//!
//! The estimators take `dt = t - t_prev` in their own type. In `f32` a time stamp near t
//! has a spacing of about t * 1.2e-7 s, so dt from large absolute times is coarse: the
//! second test measures that, and shows the remedy a firmware uses (time since start,
//! from an integer tick counter, as `examples/firmware` does).
use pendtilt::core::ekf::{Ekf, ModelSettings};
use pendtilt::core::estimators::accel::{Accel, AccelSettings};
use pendtilt::core::estimators::alg1::{Alg1, Alg1Settings};
use pendtilt::core::estimators::alg2::{Alg2, Alg2Settings};
use pendtilt::core::estimators::alg3::{Alg3, Alg3Settings};
use pendtilt::core::estimators::complementary::{Complementary, ComplementarySettings};
use pendtilt::core::estimators::pendulum::{Pendulum, PendulumSettings};
use pendtilt::core::kalman::tilt::KalmanOn;
use pendtilt::core::kalman::KalmanSettings;
use pendtilt::core::supervision::supervised::{SupervisedAlg3, SupervisedAlg3Settings};
use pendtilt::core::{Estimator, PendulumParams, Real, Sample};
use pendtilt::sim::{simulate, Scenario};

type Bank<T> = Vec<(&'static str, Box<dyn Estimator<T>>)>;

fn bank<T: Real>(p64: PendulumParams<f64>) -> Bank<T> {
    let p = PendulumParams {
        a: T::lit(p64.a),
        b: T::lit(p64.b),
        c: T::lit(p64.c),
    };
    let k = KalmanSettings::<T>::default();
    let alg2 = || Alg2::<T>::new(Alg2Settings::from_params(p));
    vec![
        ("accel", Box::new(Accel::new(AccelSettings::default()))),
        (
            "accel_prefiltered",
            Box::new(Accel::new(AccelSettings {
                prefilter_hz: Some(T::lit(5.0)),
                full_scale: None,
            })),
        ),
        ("pendulum", Box::new(Pendulum::new(PendulumSettings {}))),
        ("alg1", Box::new(Alg1::new(Alg1Settings::from_params(p)))),
        ("alg2", Box::new(alg2())),
        (
            "alg2_offset",
            Box::new(Alg2::<T>::new(Alg2Settings {
                pivot_offset: true,
                ..Alg2Settings::from_params(p)
            })),
        ),
        (
            "alg3",
            Box::new(Alg3::<T>::new(Alg3Settings::from_params(p))),
        ),
        (
            "complementary",
            Box::new(Complementary::new(ComplementarySettings::default())),
        ),
        (
            "kf_accel",
            Box::new(KalmanOn::new(
                Accel::new(AccelSettings::default()),
                k.r_accel,
                k,
            )),
        ),
        (
            "kf_alg1",
            Box::new(KalmanOn::new(
                Alg1::new(Alg1Settings::from_params(p)),
                k.r_pendulum,
                k,
            )),
        ),
        ("kf_alg2", Box::new(KalmanOn::new(alg2(), k.r_pendulum, k))),
        (
            "alg3_supervised",
            Box::new(
                SupervisedAlg3::<T>::new(SupervisedAlg3Settings {
                    alg3: Alg3Settings::from_params(p),
                    ..SupervisedAlg3Settings::default()
                })
                .unwrap(),
            ),
        ),
        (
            "ekf",
            Box::new(Ekf::<T>::new(ModelSettings::from_params(
                p,
                T::lit(9.80665),
            ))),
        ),
    ]
}

fn run<T: Real>(p: PendulumParams<f64>, samples: &[Sample<f64>], t0: f64) -> Vec<Vec<f64>> {
    let mut b = bank::<T>(p);
    let mut out = vec![Vec::with_capacity(samples.len()); b.len()];
    for s in samples {
        let x = Sample {
            t: T::lit(s.t + t0),
            phi: T::lit(s.phi),
            gyro: T::lit(s.gyro),
            ax: T::lit(s.ax),
            ay: T::lit(s.ay),
        };
        for (j, (_, e)) in b.iter_mut().enumerate() {
            out[j].push(e.update(&x).theta.to_f64());
        }
    }
    out
}

fn ride(secs: f64) -> (PendulumParams<f64>, Vec<Sample<f64>>) {
    let mut s = Scenario::named("scooter").unwrap();
    s.duration = secs;
    let p = s.physical().normalised();
    (
        p,
        simulate(&s, 11)
            .unwrap()
            .iter()
            .map(|r| r.sample())
            .collect(),
    )
}

/// RMS of f32 - f64 per estimator [deg], skipping the first `skip` samples.
fn rms_diff(
    p: PendulumParams<f64>,
    s: &[Sample<f64>],
    t0: f64,
    skip: usize,
) -> Vec<(&'static str, f64)> {
    let a = run::<f64>(p, s, t0);
    let b = run::<f32>(p, s, t0);
    let names: Vec<_> = bank::<f64>(p).into_iter().map(|(n, _)| n).collect();
    names
        .into_iter()
        .zip(a.iter().zip(&b))
        .map(|(n, (x, y))| {
            let d: Vec<f64> = x[skip..]
                .iter()
                .zip(&y[skip..])
                .map(|(u, v)| u - v)
                .collect();
            assert!(d.iter().all(|v| v.is_finite()), "{n}: non-finite output");
            let ms = d.iter().map(|v| v * v).sum::<f64>() / d.len() as f64;
            (n, ms.sqrt().to_degrees())
        })
        .collect()
}

/// Includes the live-supervised Algorithm 3, which refits its gains (Newton, Eq 29) in the
/// estimator's own type: until its refit accumulated the finite differences per sample
/// (`supervision::supervised`), the f32 refit drifted 0.66 deg RMS from f64 on this ride.
#[test]
fn every_f32_estimator_within_a_hundredth_of_a_degree_of_f64() {
    let (p, s) = ride(30.0);
    let r = rms_diff(p, &s, 0.0, 0);
    for (n, d) in &r {
        println!("{n:<16} RMS |f32 - f64| = {d:.6} deg");
    }
    assert_eq!(r.len(), 13);
    for (n, d) in &r {
        assert!(*d < 0.01, "{n}: f32 differs from f64 by {d:.5} deg RMS");
    }
}

/// The supervised comparison above is not trivial: on the ride the supervisor refits its
/// gains many times and moves them, in both types, and the f32 gains follow the f64 ones.
#[test]
fn supervised_alg3_refits_on_the_ride_and_its_f32_gains_follow_f64() {
    fn gains<T: Real>(p: PendulumParams<f64>, s: &[Sample<f64>]) -> ([f64; 4], usize) {
        let pt = PendulumParams {
            a: T::lit(p.a),
            b: T::lit(p.b),
            c: T::lit(p.c),
        };
        let mut e = SupervisedAlg3::<T>::new(SupervisedAlg3Settings {
            alg3: Alg3Settings::from_params(pt),
            ..SupervisedAlg3Settings::default()
        })
        .unwrap();
        for x in s {
            e.update_supervised(&Sample {
                t: T::lit(x.t),
                phi: T::lit(x.phi),
                gyro: T::lit(x.gyro),
                ax: T::lit(x.ax),
                ay: T::lit(x.ay),
            });
        }
        let g = e.gains();
        (
            [g.k.to_f64(), g.l.to_f64(), g.m.to_f64(), g.n.to_f64()],
            e.refits(),
        )
    }
    let (p, s) = ride(30.0);
    let (g64, n64) = gains::<f64>(p, &s);
    let (g32, n32) = gains::<f32>(p, &s);
    println!("start a {} b {}; refits f64 {n64} f32 {n32}", p.a, p.b);
    println!("f64 gains {g64:?}\nf32 gains {g32:?}");
    assert!(n64 >= 10 && n32 == n64, "{n64} {n32}");
    // The gains moved from the start (K = a, L = b, M = -b) by more than 1 %...
    assert!((g64[0] / p.a - 1.0).abs() > 0.01 || (g64[1] / p.b - 1.0).abs() > 0.01);
    // ...and f32 agrees with f64 to 1e-3 of each gain's size (N at least K's).
    for j in 0..4 {
        let size = if j == 3 {
            g64[3].abs().max(g64[0].abs())
        } else {
            g64[j].abs()
        };
        assert!(
            (g32[j] - g64[j]).abs() < 1e-3 * size,
            "gain {j}: f32 {} f64 {}",
            g32[j],
            g64[j]
        );
    }
}

#[test]
fn large_absolute_time_stamps_cost_f32_accuracy_time_since_start_does_not() {
    // The same 10 s ride with the clock started t0 before; worst estimator.
    let (p, s) = ride(10.0);
    let at = |t0: f64| {
        let r = rms_diff(p, &s, t0, 0);
        let worst = r
            .iter()
            .cloned()
            .fold(("", 0.0), |m, x| if x.1 > m.1 { x } else { m });
        println!("t0 = {t0:>6} s: worst {} {:.5} deg RMS", worst.0, worst.1);
        for (n, d) in &r {
            println!("    {n:<16} {d:.6}");
        }
        worst.1
    };
    let w: Vec<f64> = [0.0, 60.0, 300.0, 900.0, 3600.0, 86400.0]
        .iter()
        .map(|&t0| at(t0))
        .collect();
    assert!(w[0] < 0.01, "{w:?}");
    // Measured (docs/reliability.md): within 0.01 deg up to about a minute of clock;
    // an hour-old f32 clock (spacing 0.24 ms against a 1 ms step) costs about 0.85 deg,
    // a day-old one (7.8 ms) holds most samples as bad time steps.
    assert!(w[1] < 0.01, "{w:?}");
    assert!(w[4] > 0.1, "{w:?}");
    assert!(w[5] > w[0], "{w:?}");
}
