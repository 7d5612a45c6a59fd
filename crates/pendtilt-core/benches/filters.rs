//! Per-sample cost of the streaming FIR low-pass (the paper's 51 taps, 20 Hz at 1 kHz),
//! f64 and f32, over buffers in the struct (`PaperFir<T>`) and over lent buffers
//! (`FirSlice`, the `pendtilt filter` path).
//!
//! `cargo bench -p pendtilt-core --bench filters`; throughput is one element per sample, so
//! criterion's time divided by 4096 is the time per sample (it prints elements/s too).
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use pendtilt_core::filters::fir::{FirSlice, PaperFir, PAPER_TAPS};
use pendtilt_core::Real;
use std::hint::black_box;

const N: usize = 4096;

/// A 1 kHz tilt-like signal: slow swing plus 80 Hz vibration, in the sample type `T`.
fn signal<T: Real>() -> Vec<T> {
    (0..N)
        .map(|k| {
            let t = k as f64 * 1e-3;
            T::lit(0.2 * (1.3 * t).sin() + 0.01 * (2.0 * std::f64::consts::PI * 80.0 * t).sin())
        })
        .collect()
}

fn bench_type<T: Real>(c: &mut Criterion, name: &str) {
    let x = signal::<T>();
    let mut g = c.benchmark_group(format!("fir51_{name}"));
    g.throughput(Throughput::Elements(N as u64));

    let mut fir = PaperFir::<T>::paper(1000.0).expect("valid design");
    g.bench_function(BenchmarkId::from_parameter("Fir"), |b| {
        b.iter(|| {
            fir.reset();
            let mut acc = T::zero();
            for &v in &x {
                acc += fir.update(black_box(v));
            }
            acc
        })
    });

    let taps: [T; PAPER_TAPS] = PaperFir::<T>::paper(1000.0)
        .expect("valid design")
        .taps()
        .try_into()
        .expect("51 taps");
    let mut hist = [T::zero(); PAPER_TAPS];
    let mut slice = FirSlice::new(&taps, &mut hist).expect("same length");
    g.bench_function(BenchmarkId::from_parameter("FirSlice"), |b| {
        b.iter(|| {
            slice.reset();
            let mut acc = T::zero();
            for &v in &x {
                acc += slice.update(black_box(v));
            }
            acc
        })
    });
    g.finish();
}

fn fir(c: &mut Criterion) {
    bench_type::<f64>(c, "f64");
    bench_type::<f32>(c, "f32");
}

criterion_group!(benches, fir);
criterion_main!(benches);
