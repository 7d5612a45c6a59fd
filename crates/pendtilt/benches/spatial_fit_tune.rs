//! The 3-D fit's and the 3-D tune's speed (the targets: `fit` under 5 s, `tune` on a
//! 120 s, 1 kHz 3-D log under 10 s): [`pendtilt::fit::cardan::fit_cardan`] on a 60 s
//! scooter3d log from MODEL.md 7.6's rig, against the truth and against the gyro, and
//! [`pendtilt::tune::spatial::tune3d`] on 120 s of scooter3d and of ride3d.
//!
//! `cargo bench -p pendtilt --bench spatial_fit_tune`
//!
//! Each run takes seconds: ten samples per case, the fewest criterion takes. The planar
//! fit and tune (`benches/fit.rs`, `benches/tune.rs`) are their peers.
use criterion::{criterion_group, criterion_main, Criterion};
use pendtilt::fit::cardan::{fit_cardan, Fit3dSettings, Log3dColumns};
use pendtilt::fit::Target;
use pendtilt::sim::spatial::{LogRow3d, Scenario3d};
use pendtilt::tune::spatial::{tune3d, Start3d};
use pendtilt_core::spatial::cardan::CardanParams;
use std::hint::black_box;
use std::time::Duration;

fn rows(scenario: &str, seconds: f64) -> (Scenario3d, Vec<LogRow3d>) {
    let mut s = Scenario3d::named(scenario, 1).expect("a named scenario");
    s.duration = seconds;
    let rows = s
        .run(1)
        .expect("a valid scenario")
        .map(|(_, r)| r)
        .collect();
    (s, rows)
}

fn bench_fit3d(c: &mut Criterion) {
    let mut g = c.benchmark_group("fit3d");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(40));
    let (s, rows) = rows("scooter3d", 60.0);
    let log = Log3dColumns::from_rows(&rows);
    let start = CardanParams::default();
    let accel_at = s.rig.mounting.accel_at;
    for target in [Target::Truth, Target::Gyro] {
        let settings = Fit3dSettings {
            target,
            ..Fit3dSettings::default()
        };
        g.bench_function(format!("scooter3d 60 s at 1 kHz, {target:?}"), |b| {
            b.iter(|| {
                black_box(fit_cardan(black_box(&log), &start, accel_at, &settings, |_| {}).ok())
            })
        });
    }
    g.finish();
}

fn bench_tune3d(c: &mut Criterion) {
    let mut g = c.benchmark_group("tune3d");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(40));
    let start = Start3d::default();
    for scenario in ["scooter3d", "ride3d"] {
        let (_, rows) = rows(scenario, 120.0);
        let samples: Vec<_> = rows.iter().map(|r| r.sample(1e-3)).collect();
        g.bench_function(format!("{scenario} 120 s at 1 kHz"), |b| {
            b.iter(|| black_box(tune3d(black_box(&samples), &start)))
        });
    }
    g.finish();
}

criterion_group!(benches, bench_fit3d, bench_tune3d);
criterion_main!(benches);
