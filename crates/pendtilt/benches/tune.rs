//! Self-tuning speed (the target: `tune` on a 120 s, 1 kHz log in under 10 s): the
//! whole of [`pendtilt::tune::tune`] on the simulated scooter ride of 120 s (the likelihood
//! fits use its first 60 s, [`pendtilt::tune::Options::fit_seconds`]) and of 20 s.
//!
//! `cargo bench -p pendtilt --bench tune`
//!
//! Each run takes seconds: ten samples per log, the fewest criterion takes.
use criterion::{criterion_group, criterion_main, Criterion};
use pendtilt::sim::planar::{simulate, Scenario};
use pendtilt::tune::{tune, Options, Start};
use pendtilt_core::Sample;
use std::hint::black_box;
use std::time::Duration;

fn scooter(seconds: f64) -> Vec<Sample<f64>> {
    let mut s = Scenario::named("scooter").unwrap();
    s.duration = seconds;
    simulate(&s, 5)
        .unwrap()
        .iter()
        .map(|r| r.sample())
        .collect()
}

fn bench_tune(c: &mut Criterion) {
    let mut g = c.benchmark_group("tune");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(60));
    let start = Start::default();
    for seconds in [20.0, 120.0] {
        let samples = scooter(seconds);
        g.bench_function(format!("scooter {seconds} s at 1 kHz"), |b| {
            b.iter(|| black_box(tune(black_box(&samples), &start, &Options::default())))
        });
    }
    g.finish();
}

criterion_group!(benches, bench_tune);
criterion_main!(benches);
