//! Per-sample cost of every paper estimator and the Kalman filter, f64 and f32.
//!
//! `cargo bench -p pendtilt-core --bench estimators`; throughput is one element per sample,
//! so criterion reports the time per sample directly (`time / 4096`).
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use pendtilt_core::estimators::accel::{Accel, AccelSettings};
use pendtilt_core::estimators::alg1::{Alg1, Alg1Settings};
use pendtilt_core::estimators::alg2::{Alg2, Alg2Settings};
use pendtilt_core::estimators::alg3::{Alg3, Alg3Settings};
use pendtilt_core::estimators::pendulum::{Pendulum, PendulumSettings};
use pendtilt_core::estimators::theta_dd::ThetaDdSource;
use pendtilt_core::kalman::{KalmanSettings, TiltKalman};
use pendtilt_core::{PlanarEstimator, Real, Sample};
use std::hint::black_box;

const N: usize = 4096;

/// A 1 kHz log of slow tilt with a little vibration, in the sample type `T`.
fn samples<T: Real>() -> Vec<Sample<T>> {
    (0..N)
        .map(|k| {
            let t = k as f64 * 1e-3;
            let th = 0.2 * (1.3 * t).sin();
            let vib = 0.002 * (2.0 * std::f64::consts::PI * 37.0 * t).sin();
            Sample {
                // The batch repeats: every step, the first included, is 1 ms.
                dt: T::lit(1e-3),
                phi: T::lit(th * 0.97 + vib),
                gyro: T::lit(0.26 * (1.3 * t).cos()),
                ax: T::lit(9.81 * th.sin() + 3.0 * vib),
                ay: T::lit(9.81 * th.cos()),
            }
        })
        .collect()
}

fn run<T: Real, E: PlanarEstimator<T>>(e: &mut E, s: &[Sample<T>]) -> T {
    e.reset();
    let mut acc = T::zero();
    for x in s {
        acc += e.update(black_box(x)).theta;
    }
    acc
}

fn bench_type<T: Real>(c: &mut Criterion, name: &str) {
    let s = samples::<T>();
    let mut g = c.benchmark_group(format!("estimator_{name}"));
    g.throughput(Throughput::Elements(N as u64));
    let mut accel = Accel::<T>::new(AccelSettings::default());
    g.bench_function(BenchmarkId::from_parameter("accel"), |b| {
        b.iter(|| run(&mut accel, &s))
    });
    let mut pend = Pendulum::<T>::new(PendulumSettings {});
    g.bench_function(BenchmarkId::from_parameter("pendulum"), |b| {
        b.iter(|| run(&mut pend, &s))
    });
    let mut a1 = Alg1::<T>::new(Alg1Settings::default());
    g.bench_function(BenchmarkId::from_parameter("alg1"), |b| {
        b.iter(|| run(&mut a1, &s))
    });
    let mut a2 = Alg2::<T>::new(Alg2Settings::default());
    g.bench_function(BenchmarkId::from_parameter("alg2"), |b| {
        b.iter(|| run(&mut a2, &s))
    });
    let mut window = Alg2Settings::default();
    window.front_end.theta_dd = ThetaDdSource::Window { span: T::lit(0.02) };
    let mut a2w = Alg2::<T>::new(window);
    g.bench_function(BenchmarkId::from_parameter("alg2_eq22_window"), |b| {
        b.iter(|| run(&mut a2w, &s))
    });
    let mut a3 = Alg3::<T>::new(Alg3Settings::default());
    g.bench_function(BenchmarkId::from_parameter("alg3"), |b| {
        b.iter(|| run(&mut a3, &s))
    });
    let mut kf = TiltKalman::<T>::new(KalmanSettings::default());
    let r = KalmanSettings::<T>::default().r_accel;
    g.bench_function(BenchmarkId::from_parameter("kalman"), |b| {
        b.iter(|| {
            kf.reset();
            let mut acc = T::zero();
            for x in &s {
                acc += kf.step(x.dt, x.gyro, &[(black_box(x.phi), r)]).theta;
            }
            acc
        })
    });
    g.finish();
}

fn benches(c: &mut Criterion) {
    bench_type::<f64>(c, "f64");
    bench_type::<f32>(c, "f32");
}

criterion_group!(estimators, benches);
criterion_main!(estimators);
