//! Per-sample cost of the 3-D estimators beside the 3-D peers, in one run:
//! `cargo bench -p pendtilt --bench spatial`. Each iteration feeds the same 1000 samples
//! (one second at 1 kHz of a body rolling, pitching and yawing with 40 Hz vibration, in
//! closed form) to an estimator warmed up on the second before; criterion reports the time
//! per sample (elements); `ekf3d_speed` is ekf3d on the same samples with a `speed`
//! column (O's speed a measurement, its speed and rate live states); `imu3d` is ekf3d's
//! filter on the accelerometer. Targets: ekf3d under 1 us and inv3d under 150 ns in f64,
//! read beside VQF and Madgwick from the same run.
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use pendtilt::peers::spatial::peers;
use pendtilt_core::spatial::accel::{Accel, AccelSettings};
use pendtilt_core::spatial::attitude::up_from_roll_pitch;
use pendtilt_core::spatial::ekf::{Ekf, Settings, Ukf};
use pendtilt_core::spatial::inv::{Inv3d, Inv3dSettings};
use pendtilt_core::spatial::pendulum::{Pendulum, PendulumSettings};
use pendtilt_core::spatial::{SpatialEstimator, SpatialSample};
use std::f64::consts::TAU;
use std::hint::black_box;

const BATCH: usize = 1000;

fn samples(t0: f64) -> Vec<SpatialSample<f64>> {
    (0..BATCH)
        .map(|k| {
            let t = t0 + k as f64 * 1e-3;
            let (roll, pitch) = (0.15 * (TAU * 0.3 * t).sin(), 0.1 * (TAU * 0.45 * t).cos());
            let vib = (TAU * 40.0 * t).sin();
            let f = up_from_roll_pitch(roll, pitch).map(|v| 9.81 * v + 2.0 * vib);
            SpatialSample::new(
                1e-3,
                [
                    0.15 * (TAU * 0.3 * (t - 0.05)).sin() + 1e-3 * vib,
                    0.1 * (TAU * 0.45 * (t - 0.05)).cos(),
                ],
                [
                    0.15 * TAU * 0.3 * (TAU * 0.3 * t).cos() + 0.01,
                    -0.1 * TAU * 0.45 * (TAU * 0.45 * t).sin() - 0.005,
                    0.05 + 0.2 * vib,
                ],
                f,
            )
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let warm = samples(0.0);
    let data = samples(1.0);
    // A vehicle at 8 m/s gaining 0.5 m/s^2.
    let moving = |v: &[SpatialSample<f64>], t0: f64| -> Vec<SpatialSample<f64>> {
        v.iter()
            .enumerate()
            .map(|(k, s)| SpatialSample {
                speed: 8.0 + 0.5 * (t0 + k as f64 * 1e-3),
                ..*s
            })
            .collect()
    };
    let (warm_moving, data_moving) = (moving(&warm, 0.0), moving(&data, 1.0));
    let mut g = c.benchmark_group("spatial_per_sample_f64");
    g.throughput(Throughput::Elements(BATCH as u64));
    let mut all: Vec<(&str, Box<dyn SpatialEstimator<f64>>)> = vec![
        ("pendulum3d", Box::new(Pendulum::new(PendulumSettings {}))),
        ("accel3d", Box::new(Accel::new(AccelSettings::default()))),
        (
            "inv3d",
            Box::new(Inv3d::<f64>::new(Inv3dSettings::default())),
        ),
        ("ekf3d", Box::new(Ekf::new(Settings::default()))),
        ("ekf3d_speed", Box::new(Ekf::new(Settings::default()))),
        ("ukf3d", Box::new(Ukf::new(Settings::default()))),
        ("imu3d", Box::new(Ekf::new(Settings::default().imu_only()))),
    ];
    all.extend(peers());
    for (name, mut e) in all {
        let (warm, data) = if name.ends_with("_speed") {
            (&warm_moving, &data_moving)
        } else {
            (&warm, &data)
        };
        for s in warm {
            e.update(s);
        }
        g.bench_function(name, |b| {
            b.iter(|| {
                let mut acc = 0.0;
                for s in data {
                    acc += e.update(black_box(s)).roll;
                }
                black_box(acc)
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
