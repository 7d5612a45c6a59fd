//! `pendtilt estimate` throughput on a 1,000,000-row log (1 kHz, 1000 s of the scooter
//! scenario), read, estimated by every estimator and written, as the command does it.
//!
//! `cargo bench -p pendtilt --bench estimate`. The log is generated once per run into a
//! temporary directory. Peak memory is measured on the command itself (docs/performance.md, "Speed").
use criterion::{criterion_group, criterion_main, Criterion};
use pendtilt::bank::planar::{Bank, BankSettings};
use pendtilt::io::{EstimatesWriter, LogReader, ReaderOptions, WriterOptions};
use pendtilt::pipeline;
use pendtilt::sim::planar::{output::write_log, Scenario, Simulator};
use pendtilt_core::PendulumParams;

fn bench(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("temp dir");
    let log = dir.path().join("scooter_1m.csv");
    let mut sc = Scenario::named("scooter").expect("scenario");
    sc.duration = 1000.0;
    let sim = Simulator::new(&sc, 1).expect("simulator");
    let file = std::io::BufWriter::new(std::fs::File::create(&log).expect("log"));
    write_log(sim, file, |_, _| {}).expect("write log");
    let out = dir.path().join("est.csv");
    let settings = BankSettings::from_params(PendulumParams::default());
    let mut g = c.benchmark_group("estimate");
    g.sample_size(10);
    g.bench_function("1M rows, all estimators, CSV in and out", |b| {
        b.iter(|| {
            let mut reader = LogReader::open(&log, ReaderOptions::default()).expect("open");
            let mut bank = Bank::new(&settings, pipeline::inputs_of(&reader), None).expect("bank");
            let mut w = EstimatesWriter::create(&out, bank.names(), true, WriterOptions::default())
                .expect("out");
            let s = pipeline::run_parallel(
                &mut reader,
                &mut bank,
                Some(&mut w),
                Some(0.0),
                |_| {},
                |_, _, _| {},
            )
            .expect("run");
            assert_eq!(s.rows, 1_000_000);
        })
    });
    g.finish();
}

criterion_group!(estimate, bench);
criterion_main!(estimate);
