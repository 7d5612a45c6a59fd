//! Offline fits (Eqs 23-28, and Levenberg-Marquardt) on simulated logs.
use pendtilt::fit::{fit_log, Algorithm, Cost, FitError, FitSettings, Method, Target};
use pendtilt::sim::planar::motion::{Chirp, Motion};
use pendtilt::sim::planar::{simulate, Scenario};
use pendtilt_core::estimators::front_end::FrontEndSettings;
use pendtilt_core::{PendulumParams, Sample};

type Log = (Vec<Sample<f64>>, Vec<f64>);

fn log_of(s: &Scenario) -> Log {
    let rows = simulate(s, 3).unwrap();
    (
        rows.iter().map(|r| r.sample()).collect(),
        rows.iter().map(|r| r.theta).collect(),
    )
}

/// The paper's Fig. 5 sigmoid, 5 s, ideal sensors.
fn noise_free() -> Log {
    let mut s = Scenario::named("sigmoid").unwrap();
    s.sensors = s.sensors.ideal();
    log_of(&s)
}

/// An 8 s chirp 0.2 -> 3 Hz with the default (noisy, quantised, biased) sensors and the
/// scooter's engine vibration (40 Hz and 80 Hz harmonics on P1, 1 mrad angular at 40 Hz).
fn noisy_vibrating() -> Log {
    let motion = Motion::Chirp(Chirp {
        f0: 0.2,
        f1: 3.0,
        sweep_time: 8.0,
        ..Chirp::default()
    });
    let mut s = Scenario::with_motion(motion, 8.0);
    let mut v = Scenario::named("scooter").unwrap().vibration;
    v.broadband.rms = [0.0, 0.0];
    s.vibration = v;
    log_of(&s)
}

/// The paper's inverse cost (Eq 23 / 29) unless a test sets another.
fn settings(alg: Algorithm, target: Target, method: Method) -> FitSettings {
    let t = PendulumParams::<f64>::default();
    FitSettings {
        algorithm: alg,
        target,
        method,
        cost: Cost::Inverse,
        // 50 % off in both directions.
        front_end: FrontEndSettings::from_params(PendulumParams {
            a: 1.5 * t.a,
            b: 0.5 * t.b,
            c: 0.0,
        }),
        ..FitSettings::default()
    }
}

fn rel_err(report: &pendtilt::fit::FitReport) -> (f64, f64) {
    let t = PendulumParams::<f64>::default();
    let p = report.pendulum_params();
    ((p.a / t.a - 1.0).abs(), (p.b / t.b - 1.0).abs())
}

#[test]
fn noise_free_fit_recovers_a_and_b_within_1_percent() {
    let (s, th) = noise_free();
    for target in [Target::Truth, Target::Gyro] {
        for method in [Method::Newton, Method::Lm] {
            let set = settings(Algorithm::Alg2, target, method);
            let mut logged = 0;
            let r = fit_log(&s, Some(&th), &set, |_| logged += 1).unwrap();
            let (ea, eb) = rel_err(&r);
            assert!(ea < 0.01 && eb < 0.01, "{target:?} {method:?}: {r:?}");
            assert!(r.cost < 0.01 * r.start_cost, "{target:?} {method:?}");
            // Every iteration was logged (plus the start).
            assert_eq!(logged, r.iterations.len());
            assert!(r.iterations.len() >= 2);
        }
    }
}

#[test]
fn alg3_noise_free_fit_finds_the_eq21_gains() {
    let (s, th) = noise_free();
    let r = fit_log(
        &s,
        Some(&th),
        &settings(Algorithm::Alg3, Target::Truth, Method::Lm),
        |_| {},
    )
    .unwrap();
    let t = PendulumParams::<f64>::default();
    let g = r.gains();
    assert!((g.k / t.a - 1.0).abs() < 0.01, "{g:?}");
    assert!((g.l / t.b - 1.0).abs() < 0.01, "{g:?}");
    assert!((g.m / -t.b - 1.0).abs() < 0.01, "{g:?}");
    assert!(g.n.abs() < 1e-4, "{g:?}");
}

#[test]
fn noisy_vibrating_fit_recovers_a_and_b_within_5_percent() {
    let (s, th) = noisy_vibrating();
    for target in [Target::Truth, Target::Gyro] {
        for method in [Method::Newton, Method::Lm] {
            let r = fit_log(
                &s,
                Some(&th),
                &settings(Algorithm::Alg2, target, method),
                |_| {},
            )
            .unwrap();
            let (ea, eb) = rel_err(&r);
            assert!(
                ea < 0.05 && eb < 0.05,
                "{target:?} {method:?}: {ea} {eb} {r:?}"
            );
        }
    }
}

#[test]
fn bad_starts_are_clear_errors() {
    let (s, th) = noise_free();
    for (a, b) in [
        (-0.01, 5e-3),
        (0.0, 5e-3),
        (f64::NAN, 5e-3),
        (0.04, -1e-3),
        (0.04, 0.0),
        (0.04, f64::NAN),
    ] {
        let mut set = settings(Algorithm::Alg2, Target::Truth, Method::Newton);
        set.front_end.params = PendulumParams { a, b, c: 0.0 };
        let e = fit_log(&s, Some(&th), &set, |_| {}).unwrap_err();
        assert!(matches!(e, FitError::InvalidStart { .. }), "{a} {b}: {e}");
        let msg = e.to_string();
        assert!(msg.contains("invalid start value"), "{msg}");
        assert!(
            msg.contains(if a.is_nan() || a <= 0.0 { "a =" } else { "b =" }),
            "{msg}"
        );
    }
}

#[test]
fn a_log_without_motion_is_unidentifiable() {
    let mut sc = Scenario::named("still").unwrap();
    sc.duration = 2.0;
    let (s, th) = log_of(&sc);
    for target in [Target::Truth, Target::Gyro] {
        for method in [Method::Newton, Method::Lm] {
            let e = fit_log(
                &s,
                Some(&th),
                &settings(Algorithm::Alg2, target, method),
                |_| {},
            )
            .unwrap_err();
            assert!(matches!(e, FitError::Unidentifiable { .. }), "{e}");
            assert!(e.to_string().contains("not identifiable"), "{e}");
        }
    }
}

#[test]
fn missing_truth_or_gyro_is_named() {
    let (s, _) = noise_free();
    let set = settings(Algorithm::Alg2, Target::Truth, Method::Lm);
    let e = fit_log(&s, None, &set, |_| {}).unwrap_err();
    assert!(e.to_string().contains("`theta`"), "{e}");
    let no_gyro: Vec<Sample<f64>> = s
        .iter()
        .map(|x| Sample {
            gyro: f64::NAN,
            ..*x
        })
        .collect();
    let set = settings(Algorithm::Alg1, Target::Gyro, Method::Lm);
    let e = fit_log(&no_gyro, None, &set, |_| {}).unwrap_err();
    assert!(e.to_string().contains("`gyro`"), "{e}");
}

/// The output-error cost ([`pendtilt::fit::output`]) on a realistic log: an 8 s chirp
/// 0.2 -> 3 Hz with the default noisy sensors and the full `scooter` vibration (engine
/// harmonics, angular vibration and the broadband 5-200 Hz floor vibration). Measured:
/// within 2 % for a and b on seeds 1, 3, 7.
#[test]
fn output_error_fit_on_a_fully_vibrating_log_recovers_a_and_b_within_5_percent() {
    use pendtilt::fit::output::{fit_output, OutputProblem, OutputSettings};
    use pendtilt::fit::{LmSettings, Stop};
    let t = PendulumParams::<f64>::default();
    let motion = Motion::Chirp(Chirp {
        f0: 0.2,
        f1: 3.0,
        sweep_time: 8.0,
        ..Chirp::default()
    });
    let mut sc = Scenario::with_motion(motion, 8.0);
    sc.vibration = Scenario::named("scooter").unwrap().vibration;
    assert!(sc.vibration.broadband.rms[1] > 0.0);
    for seed in [1, 3, 7] {
        let rows = simulate(&sc, seed).unwrap();
        let s: Vec<Sample<f64>> = rows.iter().map(|r| r.sample()).collect();
        let th: Vec<f64> = rows.iter().map(|r| r.theta).collect();
        let p = OutputProblem::new(&s, Some(&th), &OutputSettings::default()).unwrap();
        let start_cost = p.cost(1.5 * t.a, 0.5 * t.b);
        let mut logged = 0;
        let o = fit_output(&p, 1.5 * t.a, 0.5 * t.b, &LmSettings::default(), |_| {
            logged += 1
        })
        .unwrap();
        let (ea, eb) = (o.params[0] / t.a - 1.0, o.params[1] / t.b - 1.0);
        assert!(
            ea.abs() < 0.05 && eb.abs() < 0.05,
            "seed {seed}: {ea} {eb} {o:?}"
        );
        assert_eq!(o.stop, Stop::Converged, "seed {seed}");
        assert!(logged >= 2);
        assert!(p.cost(o.params[0], o.params[1]) < 0.5 * start_cost);
    }
}

/// The same through [`fit_log`] with [`Cost::Output`], both optimisers, against the
/// paper's Eq (23) on the same log; and the settings it refuses.
#[test]
fn output_cost_through_fit_log_beats_eq23_on_b_under_broadband_vibration() {
    let motion = Motion::Chirp(Chirp {
        f0: 0.2,
        f1: 3.0,
        sweep_time: 8.0,
        ..Chirp::default()
    });
    let mut sc = Scenario::with_motion(motion, 8.0);
    sc.vibration = Scenario::named("scooter").unwrap().vibration;
    let (s, th) = log_of(&sc);
    let mut eb_out = 0.0f64;
    for method in [Method::Lm, Method::Newton] {
        let mut set = settings(Algorithm::Alg2, Target::Truth, method);
        set.cost = Cost::Output;
        let r = fit_log(&s, Some(&th), &set, |_| {}).unwrap();
        let (ea, eb) = rel_err(&r);
        println!(
            "output {method:?}: a {ea:.4} b {eb:.4} {:?} {} iterations sens {:.3e}",
            r.stop,
            r.iterations.len() - 1,
            r.sensitivity
        );
        assert!(ea < 0.05 && eb < 0.05, "{method:?}: {ea} {eb} {r:?}");
        assert!(r.cost < r.start_cost);
        eb_out = eb_out.max(eb);
    }
    let r = fit_log(
        &s,
        Some(&th),
        &settings(Algorithm::Alg2, Target::Truth, Method::Lm),
        |_| {},
    )
    .unwrap();
    let (ea, eb) = rel_err(&r);
    println!("inverse Eq 23 LM: a {ea:.4} b {eb:.4}");
    // Measured (seed 3): Eq (23) a +6.1 %, b -4.3 %; output error a +1.8 %, b +0.7 %.
    assert!(eb_out < eb, "output b error {eb_out} vs Eq (23) {eb}");
    for (alg, target) in [
        (Algorithm::Alg3, Target::Truth),
        (Algorithm::Alg2, Target::Gyro),
    ] {
        let mut set = settings(alg, target, Method::Lm);
        set.cost = Cost::Output;
        let e = fit_log(&s, Some(&th), &set, |_| {}).unwrap_err();
        assert!(matches!(e, FitError::BadSettings(_)), "{e}");
    }
    let mut still = Scenario::named("still").unwrap();
    still.duration = 3.0;
    let (s, th) = log_of(&still);
    let mut set = settings(Algorithm::Alg2, Target::Truth, Method::Lm);
    set.cost = Cost::Output;
    let e = fit_log(&s, Some(&th), &set, |_| {}).unwrap_err();
    assert!(matches!(e, FitError::Unidentifiable { .. }), "{e}");
}

/// The full 60 s `scooter` ride (slow leaning, default noisy sensors, engine, angular and
/// broadband floor vibration): the output cost driven by the accelerometer recovers a and b
/// within 5 % (measured: within 1 % on seeds 1, 3, 7); without the accelerometer the
/// translational vibration leaves b 8-13 % low, and Eq (23) 53-57 % low.
#[test]
fn output_cost_with_accel_drive_fits_the_full_scooter_ride_within_5_percent() {
    let sc = Scenario::named("scooter").unwrap();
    assert!(sc.vibration.broadband.rms[0] > 0.0 && sc.duration >= 60.0);
    for seed in [1, 7] {
        let rows = simulate(&sc, seed).unwrap();
        let s: Vec<Sample<f64>> = rows.iter().map(|r| r.sample()).collect();
        let th: Vec<f64> = rows.iter().map(|r| r.theta).collect();
        let mut set = settings(Algorithm::Alg2, Target::Truth, Method::Lm);
        set.cost = Cost::Output;
        set.output.accel = true;
        let r = fit_log(&s, Some(&th), &set, |_| {}).unwrap();
        let (ea, eb) = rel_err(&r);
        assert!(ea < 0.05 && eb < 0.05, "seed {seed}: {ea} {eb} {r:?}");
        set.output.accel = false;
        set.output.auto_accel = false;
        let plain = fit_log(&s, Some(&th), &set, |_| {}).unwrap();
        let (_, eb_plain) = rel_err(&plain);
        let inverse = fit_log(
            &s,
            Some(&th),
            &settings(Algorithm::Alg2, Target::Truth, Method::Lm),
            |_| {},
        )
        .unwrap();
        let (_, eb_inverse) = rel_err(&inverse);
        assert!(
            eb < eb_plain && eb_plain < eb_inverse && eb_inverse > 0.2,
            "seed {seed}: b errors {eb} (accel) {eb_plain} (output) {eb_inverse} (Eq 23)"
        );
    }
}
