//! `pendtilt batch` scaling: the same 8 planar logs (60 s of the scooter ride at 1 kHz, every
//! estimator) with one job and with one job per core, in the same run. The ratio of the two
//! times is the speed-up the cores give (docs/performance.md).
//!
//! `cargo bench -p pendtilt --bench batch`.
use std::process::Command;

use criterion::{criterion_group, criterion_main, Criterion};

fn bench(c: &mut Criterion) {
    let exe = env!("CARGO_BIN_EXE_pendtilt");
    let dir = tempfile::tempdir().expect("temp dir");
    let logs = dir.path().join("logs");
    std::fs::create_dir_all(&logs).expect("logs folder");
    for seed in 1..=8 {
        let out = logs.join(format!("ride{seed}.csv"));
        let ok = Command::new(exe)
            .args([
                "simulate",
                "--scenario",
                "scooter",
                "--duration",
                "60",
                "-q",
            ])
            .args(["--seed", &seed.to_string(), "-o"])
            .arg(&out)
            .status()
            .expect("simulate");
        assert!(ok.success());
    }
    let pattern = format!("{}/*.csv", logs.display());
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut g = c.benchmark_group("batch, 8 logs of 60 000 rows");
    g.sample_size(10);
    for jobs in [1, cores] {
        let out = dir.path().join(format!("out{jobs}"));
        g.bench_function(format!("{jobs} job(s)"), |b| {
            b.iter(|| {
                let ok = Command::new(exe)
                    .args(["batch", &pattern, "-q", "-j", &jobs.to_string(), "-o"])
                    .arg(&out)
                    .status()
                    .expect("batch");
                assert!(ok.success());
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
