//! Fitting speed on a 100,000-sample log (100 s at 1 kHz): the paper's Newton (Eqs 24-28)
//! and Levenberg-Marquardt, from a start 50 % off, on the cached kinematics; the kinematics
//! pass itself; and the live supervisor's per-sample cost (RLS and windowed Newton).
//!
//! `cargo bench -p pendtilt --bench fit`
//!
//! The live group times the thread's CPU time (Linux `CLOCK_THREAD_CPUTIME_ID`; wall time
//! elsewhere), so that other processes on a shared machine do not count; the supervisor is
//! built outside the timed part.
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use pendtilt::fit::{fit, prepare, Algorithm, FitSettings, Method, Target};
use pendtilt::sim::planar::motion::{Chirp, Motion};
use pendtilt::sim::planar::{simulate, Scenario};
use pendtilt_core::estimators::alg3::Alg3Settings;
use pendtilt_core::estimators::front_end::FrontEndSettings;
use pendtilt_core::filters::diff::Cutoff;
use pendtilt_core::supervision::{
    Method as LiveMethod, Objective, SupervisedAlg3, SupervisedAlg3Settings,
};
use pendtilt_core::{PendulumParams, Sample};
use std::hint::black_box;
use std::time::{Duration, Instant};

const N: usize = 100_000;

fn log() -> (Vec<Sample<f64>>, Vec<f64>) {
    // A 10 s chirp 0.2 -> 3 Hz with the default noisy sensors, repeated to 100 s.
    let motion = Motion::Chirp(Chirp {
        f0: 0.2,
        f1: 3.0,
        sweep_time: 10.0,
        ..Chirp::default()
    });
    let s = Scenario::with_motion(motion, 10.0);
    let rows = simulate(&s, 11).unwrap();
    let mut samples = Vec::with_capacity(N);
    let mut truth = Vec::with_capacity(N);
    for k in 0..N / rows.len() {
        for r in &rows {
            let mut x = r.sample();
            if k > 0 && x.dt == 0.0 {
                // Repeats continue the log: 1 ms after the previous one's last row.
                x.dt = 1e-3;
            }
            samples.push(x);
            truth.push(r.theta);
        }
    }
    (samples, truth)
}

fn settings(method: Method) -> FitSettings {
    let t = PendulumParams::<f64>::default();
    FitSettings {
        algorithm: Algorithm::Alg2,
        target: Target::Truth,
        method,
        front_end: FrontEndSettings::from_params(PendulumParams {
            a: 1.5 * t.a,
            b: 0.5 * t.b,
            c: 0.0,
        }),
        ..FitSettings::default()
    }
}

fn offline(c: &mut Criterion) {
    let (samples, truth) = log();
    let mut g = c.benchmark_group("fit_100k");
    g.sample_size(10);
    let newton = settings(Method::Newton);
    g.bench_function("kinematics_pass", |b| {
        b.iter(|| prepare(black_box(&samples), Some(&truth), &newton).unwrap())
    });
    for method in [Method::Newton, Method::Lm] {
        let s = settings(method);
        let problem = prepare(&samples, Some(&truth), &s).unwrap();
        let r = fit(&problem, &s, |_| {}).unwrap();
        eprintln!(
            "{method:?}: {} iterations, {} passes, cost {:.4e} -> {:.4e} rad, a {:.6e} b {:.6e} ({:?})",
            r.iterations.len() - 1,
            r.evaluations,
            r.start_cost,
            r.cost,
            r.params[0],
            r.params[1],
            r.stop
        );
        g.bench_function(format!("{method:?}_iterations").to_lowercase(), |b| {
            b.iter(|| fit(black_box(&problem), &s, |_| {}).unwrap())
        });
        g.bench_function(format!("{method:?}_total").to_lowercase(), |b| {
            b.iter(|| {
                let p = prepare(black_box(&samples), Some(&truth), &s).unwrap();
                fit(&p, &s, |_| {}).unwrap()
            })
        });
    }
    g.finish();
}

/// CPU time of this thread (Linux), else wall time since an arbitrary origin.
fn thread_time() -> Duration {
    #[cfg(target_os = "linux")]
    {
        #[repr(C)]
        struct Timespec {
            sec: i64,
            nsec: i64,
        }
        extern "C" {
            fn clock_gettime(clock: i32, ts: *mut Timespec) -> i32;
        }
        const CLOCK_THREAD_CPUTIME_ID: i32 = 3;
        let mut ts = Timespec { sec: 0, nsec: 0 };
        // SAFETY: clock_gettime writes one timespec (two longs on 64-bit Linux) to ts.
        if unsafe { clock_gettime(CLOCK_THREAD_CPUTIME_ID, &mut ts) } == 0 {
            return Duration::new(ts.sec as u64, ts.nsec as u32);
        }
    }
    static ORIGIN: std::sync::OnceLock<Instant> = std::sync::OnceLock::new();
    ORIGIN.get_or_init(Instant::now).elapsed()
}

/// Runs `run` on a fresh `make()` `iters` times, timing only `run` in thread CPU time.
fn cpu_timed<E>(b: &mut criterion::Bencher, make: impl Fn() -> E, mut run: impl FnMut(&mut E)) {
    b.iter_custom(|iters| {
        let mut total = Duration::ZERO;
        for _ in 0..iters {
            let mut e = make();
            let t0 = thread_time();
            run(&mut e);
            total += thread_time() - t0;
            black_box(&e);
        }
        total
    })
}

fn live(c: &mut Criterion) {
    let (samples, _) = log();
    let t = PendulumParams::<f64>::default();
    let mut g = c.benchmark_group("live_supervisor");
    g.sample_size(10);
    g.throughput(Throughput::Elements(N as u64));
    // The defaults are Newton on the RMS (Eq 29) every 2000 samples; the live tests also
    // run the mean square every 250.
    for (name, method, interval, objective) in [
        ("rls", LiveMethod::Rls, 250, Objective::MeanSquare),
        (
            "newton_window1000_every2000_rms",
            LiveMethod::Newton,
            2000,
            Objective::Rms,
        ),
        (
            "newton_window1000_every2000",
            LiveMethod::Newton,
            2000,
            Objective::MeanSquare,
        ),
        (
            "newton_window1000_every250",
            LiveMethod::Newton,
            250,
            Objective::MeanSquare,
        ),
    ] {
        let mut set = SupervisedAlg3Settings::<f64> {
            alg3: Alg3Settings::from_params(PendulumParams {
                a: 1.5 * t.a,
                b: 1.5 * t.b,
                c: 0.0,
            }),
            ..SupervisedAlg3Settings::default()
        };
        set.alg3.front_end.differentiator.cutoff = Cutoff::Hz(1.7 * t.natural_frequency_hz());
        set.supervisor.method = method;
        set.supervisor.refit_interval = interval;
        set.supervisor.objective = objective;
        g.bench_function(name, |b| {
            cpu_timed(
                b,
                || SupervisedAlg3::<f64, 1024>::new(set).unwrap(),
                |e| {
                    for s in &samples {
                        black_box(e.update_supervised(s));
                    }
                },
            )
        });
    }
    // The estimator alone, for the supervisor's share.
    g.bench_function("alg3_alone", |b| {
        cpu_timed(
            b,
            || pendtilt_core::estimators::alg3::Alg3::<f64>::new(Alg3Settings::default()),
            |e| {
                for s in &samples {
                    black_box(e.update_with_terms(s));
                }
            },
        )
    });
    g.finish();
}

criterion_group!(benches, offline, live);
criterion_main!(benches);
