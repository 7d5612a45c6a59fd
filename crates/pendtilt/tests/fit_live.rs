//! Live supervision (Eq 29) of Algorithm 3 (Eq 30) in the core: convergence from a start
//! 50 % off and tracking of a step change of the damping.
use pendtilt::sim::planar::motion::{Chirp, Motion};
use pendtilt::sim::planar::{simulate, Scenario};
use pendtilt_core::estimators::alg3::{Alg3, Alg3Settings};
use pendtilt_core::estimators::equations::Alg3Gains;
use pendtilt_core::filters::diff::Cutoff;
use pendtilt_core::supervision::{
    Method, Objective, SettingsError, SupervisedAlg3, SupervisedAlg3Settings, SupervisionFlags,
};
use pendtilt_core::{Estimator, PendulumParams, Sample};

/// A 10 s chirp 0.2 -> 3 Hz with the default noisy sensors; `damping_scale` multiplies C.
fn chirp(damping_scale: f64, t_offset: f64) -> Vec<Sample<f64>> {
    let motion = Motion::Chirp(Chirp {
        f0: 0.2,
        f1: 3.0,
        sweep_time: 10.0,
        ..Chirp::default()
    });
    let mut s = Scenario::with_motion(motion, 10.0);
    s.pendulum.damping *= damping_scale;
    simulate(&s, 7)
        .unwrap()
        .iter()
        .map(|r| {
            let mut x = r.sample();
            if t_offset > 0.0 && x.dt == 0.0 {
                // Continues a log that ended at t_offset - 1 ms.
                x.dt = 1e-3;
            }
            x
        })
        .collect()
}

fn supervised(method: Method) -> SupervisedAlg3<f64, 1024> {
    let t = PendulumParams::<f64>::default();
    // 50 % off: a and b (so K, L, M) all 1.5 times the truth.
    let start = PendulumParams {
        a: 1.5 * t.a,
        b: 1.5 * t.b,
        c: 0.0,
    };
    let mut set = SupervisedAlg3Settings::<f64> {
        alg3: Alg3Settings::from_params(start),
        ..SupervisedAlg3Settings::default()
    };
    set.alg3.front_end.differentiator.cutoff = Cutoff::Hz(1.7 * t.natural_frequency_hz());
    set.supervisor.method = method;
    set.supervisor.window = 1000;
    set.supervisor.refit_interval = 250;
    set.supervisor.objective = Objective::MeanSquare;
    SupervisedAlg3::new(set).unwrap()
}

/// Runs 10 s at the rig's damping then 10 s at twice it; returns the gains every 0.5 s.
/// Measured: K is within 10 % of 2a from 6.5 s (Newton, window 1 s, refit every 0.25 s,
/// trust region 0.1 per refit; 5.0 s without it) and 9.0 s (RLS, forgetting 0.9995)
/// after the step on.
fn run(method: Method) -> Vec<(f64, Alg3Gains<f64>)> {
    let mut log = chirp(1.0, 0.0);
    log.extend(chirp(2.0, 10.0));
    let mut e = supervised(method);
    let mut out = Vec::new();
    let mut refits = 0;
    for (k, s) in log.iter().enumerate() {
        let r = e.update_supervised(s);
        assert!(r.estimate.theta.is_finite() || k == 0);
        if r.supervision.contains(SupervisionFlags::REFIT) {
            refits += 1;
        }
        if k % 500 == 499 {
            out.push((k as f64 * 1e-3, e.gains()));
        }
    }
    assert!(refits > 20, "{refits}");
    out
}

fn check(method: Method, converge_tol: f64, track_tol: f64, track_within: f64) {
    let t = PendulumParams::<f64>::default();
    let trace = run(method);
    // Converged before the step (t = 9.5 s): K, L, M within converge_tol of a, b, -b.
    let (_, g) = trace
        .iter()
        .find(|(ts, _)| (*ts - 9.499).abs() < 0.01)
        .unwrap();
    assert!((g.k / t.a - 1.0).abs() < converge_tol, "{method:?} {g:?}");
    assert!((g.l / t.b - 1.0).abs() < converge_tol, "{method:?} {g:?}");
    assert!((g.m / -t.b - 1.0).abs() < converge_tol, "{method:?} {g:?}");
    // After the damping doubles at t = 10 s, K reaches 2a within track_tol and stays there
    // from t = 10 + track_within to the end.
    let settled = trace
        .iter()
        .rev()
        .take_while(|(_, g)| (g.k / (2.0 * t.a) - 1.0).abs() < track_tol)
        .last()
        .map(|(ts, _)| ts - 10.0);
    eprintln!("{method:?}: K within {track_tol} of 2a from {settled:?} s after the step");
    for (ts, g) in trace.iter().filter(|(ts, _)| *ts >= 10.0 + track_within) {
        assert!(
            (g.k / (2.0 * t.a) - 1.0).abs() < track_tol,
            "{method:?} t = {ts}: K / 2a = {}",
            g.k / (2.0 * t.a)
        );
    }
}

#[test]
fn rls_converges_from_50_percent_off_and_tracks_a_damping_step() {
    check(Method::Rls, 0.05, 0.10, 9.0);
}

#[test]
fn newton_converges_from_50_percent_off_and_tracks_a_damping_step() {
    check(Method::Newton, 0.10, 0.10, 6.0);
}

#[test]
fn bad_settings_are_refused() {
    let mut set = SupervisedAlg3Settings::<f64>::default();
    set.supervisor.window = 2000; // above the capacity 1024
    assert_eq!(
        SupervisedAlg3::<f64, 1024>::new(set).err(),
        Some(SettingsError::Window)
    );
    let mut set = SupervisedAlg3Settings::<f64>::default();
    set.supervisor.refit_interval = 0;
    assert_eq!(
        SupervisedAlg3::<f64, 1024>::new(set).err(),
        Some(SettingsError::RefitInterval)
    );
    let mut set = SupervisedAlg3Settings::<f64>::default();
    set.alg3.gains.k = f64::NAN;
    assert_eq!(
        SupervisedAlg3::<f64, 1024>::new(set).err(),
        Some(SettingsError::Gains)
    );
    let mut set = SupervisedAlg3Settings::<f64>::default();
    set.supervisor.max_step = f64::NAN;
    assert_eq!(
        SupervisedAlg3::<f64, 1024>::new(set).err(),
        Some(SettingsError::MaxStep)
    );
    let mut set = SupervisedAlg3Settings::<f64>::default();
    set.supervisor.rls.forgetting = 1.5;
    assert_eq!(
        SupervisedAlg3::<f64, 1024>::new(set).err(),
        Some(SettingsError::Rls)
    );
}

#[test]
fn f32_rls_supervisor_runs_and_converges_roughly() {
    let t = PendulumParams::<f32>::default();
    let start = PendulumParams {
        a: 1.5 * t.a,
        b: 1.5 * t.b,
        c: 0.0,
    };
    let mut set = SupervisedAlg3Settings::<f32> {
        alg3: Alg3Settings::from_params(start),
        ..SupervisedAlg3Settings::default()
    };
    set.alg3.front_end.differentiator.cutoff = Cutoff::Hz(1.7 * t.natural_frequency_hz());
    set.supervisor.method = Method::Rls;
    set.supervisor.refit_interval = 250;
    let mut e = SupervisedAlg3::<f32, 64>::new(SupervisedAlg3Settings {
        supervisor: pendtilt_core::supervision::SupervisorSettings {
            window: 64,
            ..set.supervisor
        },
        ..set
    })
    .unwrap();
    for s in chirp(1.0, 0.0) {
        e.update_supervised(&s.cast::<f32>());
    }
    let g = e.gains();
    assert!((g.k / t.a - 1.0).abs() < 0.25, "{g:?}");
    assert!((g.l / t.b - 1.0).abs() < 0.25, "{g:?}");
}

/// `reps` 10 s chirps back to back from `t_offset`, damping times `damping_scale`.
fn chirps(damping_scale: f64, t_offset: f64, reps: usize) -> Vec<Sample<f64>> {
    (0..reps)
        .flat_map(|k| chirp(damping_scale, t_offset + 10.0 * k as f64))
        .collect()
}

/// Quartiles of K / `k_ref` over the gains sampled in (t0, t1).
fn k_quartiles(trace: &[(f64, Alg3Gains<f64>)], t0: f64, t1: f64, k_ref: f64) -> [f64; 3] {
    let mut v: Vec<f64> = trace
        .iter()
        .filter(|(t, _)| *t > t0 && *t < t1)
        .map(|(_, g)| g.k / k_ref)
        .collect();
    v.sort_by(f64::total_cmp);
    [v[v.len() / 4], v[v.len() / 2], v[3 * v.len() / 4]]
}

/// The documented live defaults (`SupervisorSettings::default()`: Newton on the RMS of
/// Eq 29, window 1000, one iteration every 2000 samples, trust region 0.1; the
/// estimator's default differentiator at 1.3 f_n) from a start 50 % off, on 60 s of
/// repeated 0.2-3 Hz chirps at the rig's damping, then 60 s at twice it.
///
/// Measured: K / a quartiles 1.29 / 1.38 / 1.43 over 30-60 s, K / 2a 1.23 / 1.26 / 1.29
/// over 90-120 s. The defaults stay bounded and follow the doubling (median ratio 1.82)
/// but K settles 25-40 % high, so they do NOT meet the target "within 10 %"; the tuned
/// settings of the tests above (1.7 f_n, mean square, refit every 250) do. Without the
/// trust region (`max_step` = inf) the same run sent K to -5 and +14 times a.
#[test]
fn default_settings_stay_bounded_from_50_percent_off_and_follow_a_damping_step() {
    let t = PendulumParams::<f64>::default();
    let start = PendulumParams {
        a: 1.5 * t.a,
        b: 1.5 * t.b,
        c: 0.0,
    };
    let set = SupervisedAlg3Settings::<f64> {
        alg3: Alg3Settings::from_params(start),
        ..SupervisedAlg3Settings::default()
    };
    assert_eq!(set.supervisor.objective, Objective::Rms);
    assert_eq!(set.supervisor.refit_interval, 2000);
    let mut e = SupervisedAlg3::<f64, 1024>::new(set).unwrap();
    let mut log = chirps(1.0, 0.0, 6);
    log.extend(chirps(2.0, 60.0, 6));
    let mut trace = Vec::new();
    for (k, s) in log.iter().enumerate() {
        e.update_supervised(s);
        if k % 500 == 499 {
            trace.push((k as f64 * 1e-3, e.gains()));
        }
    }
    let before = k_quartiles(&trace, 30.0, 60.0, t.a);
    let after = k_quartiles(&trace, 90.0, 120.0, t.a);
    eprintln!("defaults: K / a quartiles {before:.3?} (30-60 s), {after:.3?} (90-120 s)");
    // Bounded: every sampled K from 30 s on within a factor 2 of the truth.
    for (ts, g) in trace.iter().filter(|(ts, _)| *ts > 30.0) {
        let truth = if *ts < 60.0 { t.a } else { 2.0 * t.a };
        assert!(
            (0.5..2.0).contains(&(g.k / truth)),
            "t = {ts}: K / K_true = {}",
            g.k / truth
        );
    }
    // Near the truth (within the measured bias, +-50 %), and the doubling is followed.
    assert!(before[0] > 0.5 && before[2] < 1.5, "{before:?}");
    assert!(after[0] > 1.0 && after[2] < 3.0, "{after:?}");
    let ratio = after[1] / before[1];
    assert!(
        (1.6..2.4).contains(&ratio),
        "K after / before the step: {ratio}"
    );
}

/// Eight 10 s chirps 0.2 -> 3 Hz end to end at 1 kHz: (sample, true angle) per row.
fn chirp_rows() -> Vec<(Sample<f64>, f64)> {
    let motion = Motion::Chirp(Chirp {
        f0: 0.2,
        f1: 3.0,
        sweep_time: 10.0,
        ..Chirp::default()
    });
    let mut rows = Vec::new();
    for _ in 0..8 {
        let s = Scenario::with_motion(motion.clone(), 10.0);
        for r in simulate(&s, 7).unwrap() {
            rows.push((r.sample(), r.theta));
        }
    }
    rows
}

/// `rows` read at true times whose interval is 1 ms for 10 s, then drifts linearly to
/// 1.25 ms at 70 s, while the stamps keep claiming 1 ms (64 s of log at most).
fn drifting_log(rows: &[(Sample<f64>, f64)]) -> Vec<(Sample<f64>, f64)> {
    let n = 64_000;
    let mut t_true: f64 = 0.0;
    let mut log = Vec::with_capacity(n);
    for k in 0..n {
        let stamp = k as f64 * 1e-3;
        let i = (t_true * 1000.0).floor() as usize;
        if i + 1 >= rows.len() {
            break;
        }
        let f = t_true * 1000.0 - i as f64;
        let (a, b) = (&rows[i], &rows[i + 1]);
        let lerp = |u: f64, v: f64| u + f * (v - u);
        let s = Sample {
            dt: if k == 0 { 0.0 } else { 1e-3 },
            phi: lerp(a.0.phi, b.0.phi),
            gyro: lerp(a.0.gyro, b.0.gyro),
            ax: lerp(a.0.ax, b.0.ax),
            ay: lerp(a.0.ay, b.0.ay),
        };
        log.push((s, lerp(a.1, b.1)));
        let drift = ((stamp - 10.0) / 50.0).clamp(0.0, 1.0);
        t_true += 1e-3 * (1.0 + 0.25 * drift);
    }
    log
}

/// RMS error \[deg\] against the true angle of the three angles `update` gives per row of
/// `log`: [estimator][2-10 s (1 kHz), the last 8 s (800 Hz)].
fn rms_at_both_rates(
    log: &[(Sample<f64>, f64)],
    mut update: impl FnMut(&Sample<f64>) -> [f64; 3],
) -> [[f64; 2]; 3] {
    let mut err = [[0.0f64; 2]; 3]; // [estimator][first 10 s after warm-up, last 10 s] sum sq
    let mut cnt = [0usize; 2];
    for (k, (s, th)) in log.iter().enumerate() {
        let t = k as f64 * 1e-3;
        let e = update(s);
        let seg = if (2.0..10.0).contains(&t) {
            0
        } else if t >= log.len() as f64 * 1e-3 - 8.0 {
            1
        } else {
            continue;
        };
        cnt[seg] += 1;
        for j in 0..3 {
            err[j][seg] += (e[j] - th).powi(2);
        }
    }
    let rms = |j: usize, seg: usize| (err[j][seg] / cnt[seg] as f64).sqrt().to_degrees();
    [0, 1, 2].map(|j| [rms(j, 0), rms(j, 1)])
}

/// Sample-time drift: the rig's true sample interval drifts from 1 ms
/// (1 kHz) to 1.25 ms (800 Hz) over 60 s while the log's time stamps keep claiming 1 ms
/// (a clock that drifts against the stamps). The estimator's derivatives are then scaled
/// by the interval ratio r = 1.25 (phi', G_d by r, phi'' by r^2); the supervisor can absorb
/// that into K, L, M. Built by interpolating a 1 kHz simulated run of chirps at the
/// drifting true times; all three estimators start at the rig's true gains.
///
/// Measured (RMS error against the true angle, 2-10 s at 1 kHz / the last 8 s at 800 Hz):
/// fixed gains 3.72 / 4.24 deg, supervised Newton 3.70 / 3.67 deg, supervised RLS
/// 3.71 / 3.38 deg (the error at 1 kHz is mostly the 1.7 f_n differentiator's delay on
/// the 3 Hz end of the chirp). Newton's gains end at K/a 0.53, L/b 0.44, M/-b 0.53: down,
/// and L further than K as r^2 against r predicts, but by more than the 1/r = 0.8 and
/// 1/r^2 = 0.64 that would undo the scaling.
#[test]
fn supervised_alg3_follows_a_drifting_sample_time() {
    let t = PendulumParams::<f64>::default();
    let log = drifting_log(&chirp_rows());
    // All three start at the rig's true gains, with the same differentiator.
    let mut set = *supervised(Method::Newton).settings();
    set.alg3.gains = Alg3Gains::from_params(&t);
    let mut fixed = Alg3::<f64>::new(set.alg3);
    let mut sup = SupervisedAlg3::<f64, 1024>::new(set).unwrap();
    set.supervisor.method = Method::Rls;
    let mut rls = SupervisedAlg3::<f64, 1024>::new(set).unwrap();
    let rms = rms_at_both_rates(&log, |s| {
        [
            fixed.update(s).theta,
            sup.update_supervised(s).estimate.theta,
            rls.update_supervised(s).estimate.theta,
        ]
    });
    for (j, name) in ["alg3 fixed gains", "supervised Newton", "supervised RLS"]
        .iter()
        .enumerate()
    {
        eprintln!(
            "{name:<18} RMS error {:.3} deg at 1 kHz, {:.3} deg at 800 Hz",
            rms[j][0], rms[j][1]
        );
    }
    let g = sup.gains();
    let (k, l, m) = (g.k / t.a, g.l / t.b, -g.m / t.b);
    eprintln!("Newton gains at the end: K/a {k:.3} L/b {l:.3} M/-b {m:.3}");
    // At 1 kHz (the gains right) supervision costs nothing; at 800 Hz (the stamps wrong by
    // 25 %) both supervisors beat the fixed gains, RLS the more.
    let [fixed, newton, rls] = rms;
    assert!(
        newton[0] <= fixed[0] + 0.05 && rls[0] <= fixed[0] + 0.05,
        "{rms:?}"
    );
    assert!(newton[1] < fixed[1] - 0.3, "Newton at 800 Hz: {rms:?}");
    assert!(rls[1] < fixed[1] - 0.5, "RLS at 800 Hz: {rms:?}");
    // The gains go down with the drift, L (on phi'', r^2) further than K (on phi', r).
    assert!(k < 0.8 && l < k, "K/a {k}, L/b {l}");
}
