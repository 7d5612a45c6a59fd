//! Simulator throughput: the scooter scenario (everything on) with and without writing CSV,
//! and the 3-D scenarios of MODEL.md 7.8 (truth and sensor rows).
//! `cargo bench -p pendtilt --bench sim`

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use pendtilt::sim::planar::output::write_log;
use pendtilt::sim::planar::{Scenario, Simulator};

fn bench(c: &mut Criterion) {
    let mut s = Scenario::named("scooter").unwrap();
    s.duration = 10.0;
    let rows = s.rows();
    let mut g = c.benchmark_group("sim");
    g.throughput(Throughput::Elements(rows));
    g.sample_size(10);
    g.bench_function("scooter_10s_rows", |b| {
        b.iter(|| {
            let sim = Simulator::new(&s, 1).unwrap();
            black_box(sim.fold(0.0, |acc, r| acc + r.phi))
        })
    });
    g.bench_function("scooter_10s_csv", |b| {
        let mut buf = Vec::with_capacity(80 * rows as usize);
        b.iter(|| {
            buf.clear();
            write_log(Simulator::new(&s, 1).unwrap(), &mut buf, |_, _| {}).unwrap();
            black_box(buf.len())
        })
    });
    s.vibration = Default::default();
    s.motion = pendtilt::sim::planar::motion::Motion::Sigmoid(Default::default());
    g.bench_function("sigmoid_10s_rows", |b| {
        b.iter(|| {
            let sim = Simulator::new(&s, 1).unwrap();
            black_box(sim.fold(0.0, |acc, r| acc + r.phi))
        })
    });
    g.finish();
    let mut g = c.benchmark_group("sim3d");
    g.sample_size(10);
    for name in ["scooter3d", "ride3d"] {
        let mut s = pendtilt::sim::spatial::Scenario3d::named(name, 1).unwrap();
        s.duration = 2.0;
        g.throughput(Throughput::Elements(s.rows()));
        g.bench_function(format!("{name}_2s_rows"), |b| {
            b.iter(|| black_box(s.run(1).unwrap().fold(0.0, |acc, (_, r)| acc + r.phi[0])))
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
