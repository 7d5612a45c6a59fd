//! Per-sample cost of the model-based filters beside the peers, in one run:
//! `cargo bench -p pendtilt --bench peers`. Each iteration feeds the same 1000 samples (one
//! second at 1 kHz of a tilting, vibrating rig, made in closed form) to the estimator,
//! restarted at the batch's start (the per-sample work of these filters does not depend on
//! how far they have converged); criterion reports time per sample (elements).
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use pendtilt::bank::planar::build;
use pendtilt::peers::PeerSettings;
use pendtilt_core::{PendulumParams, Sample};
use std::hint::black_box;

const BATCH: usize = 1000;

/// One second of readings: a 0.5 Hz tilt, the pendulum lagging it with a 40 Hz ripple, a
/// gyro with a bias, an accelerometer with engine vibration.
fn samples(t0: f64) -> Vec<Sample<f64>> {
    (0..BATCH)
        .map(|k| {
            let t = t0 + k as f64 * 1e-3;
            let w = std::f64::consts::TAU * 0.5;
            let th = 0.2 * (w * t).sin();
            let vib = (std::f64::consts::TAU * 40.0 * t).sin();
            Sample {
                // Batches follow each other: every step, the first included, is 1 ms.
                dt: 1e-3,
                phi: 0.2 * (w * t - 0.05).sin() + 1e-3 * vib,
                gyro: 0.2 * w * (w * t).cos() + 0.01,
                ax: 9.81 * th.sin() + 2.0 * vib,
                ay: 9.81 * th.cos() + 3.0 * vib,
            }
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let p = PendulumParams::<f64> {
        c: 0.2 / 9.80665,
        ..PendulumParams::default()
    };
    let warm = samples(0.0);
    let data = samples(1.0);
    let mut g = c.benchmark_group("per_sample_f64");
    g.throughput(Throughput::Elements(BATCH as u64));
    for name in [
        "ekf",
        "ukf",
        "madgwick",
        "mahony",
        "complementary",
        "alg2_offset",
    ] {
        let mut e = build(name, &p, 9.80665, &PeerSettings::default()).expect("known column");
        for s in &warm {
            e.update(s);
        }
        g.bench_function(name, |b| {
            b.iter(|| {
                let mut acc = 0.0;
                for s in &data {
                    acc += e.update(black_box(s)).theta;
                }
                // Rewind time so that the next batch is accepted (the state stays settled).
                e.reset();
                e.update(&warm[BATCH - 1]);
                acc
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
