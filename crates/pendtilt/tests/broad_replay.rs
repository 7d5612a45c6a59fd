//! Real motion: the BROAD excerpt (tests/data/broad, CC-BY 4.0; five trials, 8 s of rest
//! and 32 s of movement each) replayed through MODEL.md 7.6's pendulum (`replay` at its
//! defaults), and the 3-D estimators at their defaults scored against the optical truth
//! from the first movement on (MODEL.md 7.9, 7.10).
use std::path::PathBuf;

use pendtilt::bank::spatial::rig::Pendulum3dConfig;
use pendtilt::bank::spatial::Settings3d;
use pendtilt::replay::benchmark::{score, Score};
use pendtilt::replay::source::ImuOptions;
use pendtilt::replay::{replay, Recording, Replay, ReplaySettings};
use pendtilt::sim::spatial::Mounting;

const TRIALS: [&str; 5] = [
    "06_undisturbed_fast_rotation_A",
    "10_undisturbed_slow_translation_A",
    "16_undisturbed_fast_translation_B",
    "24_disturbed_tapping_A",
    "27_disturbed_phone_vibration_B",
];

fn excerpt(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/broad")
        .join(format!("{name}.mat"))
}

fn replayed(name: &str) -> (Recording, Replay) {
    let rec = Recording::open(excerpt(name), &ImuOptions::default()).unwrap();
    let r = replay(&rec, &ReplaySettings::default()).unwrap();
    (rec, r)
}

fn settings(r: &Replay) -> Settings3d {
    Settings3d::new(
        Pendulum3dConfig::Physical(r.pendulum).params(),
        Mounting::default(),
        None,
    )
}

fn scores(name: &str, s: &Settings3d) -> (Vec<Score>, Vec<Vec<f64>>, Recording, Replay) {
    let (rec, r) = replayed(name);
    let only = ["ekf3d", "ukf3d", "imu3d", "vqf"].map(String::from);
    let (sc, e) = score(&rec, &r, s, Some(&only)).unwrap();
    (sc, e, rec, r)
}

fn by<'a>(s: &'a [Score], name: &str) -> &'a Score {
    s.iter().find(|x| x.estimator == name).unwrap()
}

/// The excerpt reads as BROAD's trials: 286 Hz, 40 s, the movement marked 8 s in, the
/// truth from the quaternion, an initial rest with the gyro's bias and gravity.
#[test]
fn the_excerpt_reads_as_broad_trials() {
    for name in TRIALS {
        let (rec, r) = replayed(name);
        let n = rec.t.len();
        let fs = (n - 1) as f64 / rec.t[n - 1];
        assert!((fs - 285.714).abs() < 0.01, "{name}: {fs} Hz");
        assert!(
            (rec.t[n - 1] - 40.0).abs() < 0.01,
            "{name}: {} s",
            rec.t[n - 1]
        );
        let first = rec.movement.unwrap();
        assert!((rec.t[first] - 8.0).abs() < 0.01, "{name}");
        let rest = r.report.rest.unwrap();
        assert_eq!(rest.end, first, "{name}");
        assert!(
            (r.report.gravity - 9.81).abs() < 0.15,
            "{name}: {}",
            r.report.gravity
        );
        assert!(rest.gyro_bias.iter().all(|b| b.abs() < 0.01), "{name}");
        // One log row per recorded row; encoders within (-pi, pi].
        assert_eq!(r.rows.len(), n);
        assert!(r.rows.iter().all(|x| x
            .phi
            .iter()
            .all(|p| *p > -std::f64::consts::PI && *p <= std::f64::consts::PI)));
        // At rest the pendulum hangs at the truth's tilt (BROAD's optical frame is aligned
        // to the IMU within a fraction of a degree).
        let rest_rows: Vec<_> = r.rows[..first]
            .iter()
            .filter(|x| x.roll.is_finite() && x.pitch.is_finite())
            .collect();
        assert!(rest_rows.len() > first / 2, "{name}");
        for x in rest_rows {
            assert!(
                (x.phi[0] - x.roll).abs().to_degrees() < 1.0,
                "{name} at {} s",
                x.t
            );
            assert!(
                (x.phi[1] - x.pitch).abs().to_degrees() < 1.0,
                "{name} at {} s",
                x.t
            );
        }
    }
}

/// ekf3d, ukf3d and imu3d (the same filter on the accelerometer) never lose the attitude
/// on recorded motion: under 10 deg at every scored sample of every excerpt (the pendulum
/// tumbles on fast translation and tapping), within 4x the `vqf` column's RMS and 2.5 deg. Not the target (no worse than VQF): see
/// docs/real-motion.md for the figures.
#[test]
fn ekf3d_never_loses_the_attitude_on_recorded_motion() {
    for name in TRIALS {
        let (_, r) = replayed(name);
        let (sc, _, _, _) = scores(name, &settings(&r));
        let (e, u, v) = (by(&sc, "ekf3d"), by(&sc, "ukf3d"), by(&sc, "vqf"));
        let i = by(&sc, "imu3d");
        eprintln!(
            "{name}: ekf3d {:.3} ({:.2}), ukf3d {:.3} ({:.2}), imu3d {:.3} ({:.2}), \
             vqf {:.3} ({:.2}) deg RMS (max)",
            e.rms, e.max, u.rms, u.max, i.rms, i.max, v.rms, v.max
        );
        for s in [e, u, i] {
            assert!(
                s.max < 10.0,
                "{name}: {} max {:.2} deg at {} s",
                s.estimator,
                s.max,
                s.t_max
            );
            assert!(
                s.rms < 2.5 && s.rms < 4.0 * v.rms,
                "{name}: {} {:.3} deg, vqf {:.3}",
                s.estimator,
                s.rms,
                v.rms
            );
        }
        // ukf3d no worse than ekf3d by more than 20 % (the target, 10 %, is not reached:
        // 17 % worse on the tapping excerpt, 1.15 against 0.98 deg).
        assert!(
            u.rms < 1.2 * e.rms + 0.02,
            "{name}: ukf3d {:.3} ekf3d {:.3}",
            u.rms,
            e.rms
        );
    }
}

/// Without the guard and the adaptation (the filter as it was before recorded motion
/// was tried) ekf3d loses the attitude on the same excerpts: the test above could fail.
#[test]
fn without_guard_and_adaptation_ekf3d_loses_the_attitude() {
    let mut worst = 0.0f64;
    for name in TRIALS {
        let (_, r) = replayed(name);
        let mut s = settings(&r);
        s.ekf.guard_angle = f64::INFINITY;
        s.ekf.adaptation.enabled = false;
        let (sc, _, _, _) = scores(name, &s);
        worst = worst.max(by(&sc, "ekf3d").max);
    }
    assert!(worst > 20.0, "{worst}");
}

/// After the pendulum tumbles (a run of at least 0.2 s of rows flagged `pendulum_unused`:
/// its inner joint beyond the model's range, or a run of rejected readings), ekf3d takes
/// it back on the first reading in range, its attitude then within 1 deg of the `vqf`
/// column's error (the gyro and accelerometer carried it meanwhile), and it takes it back
/// within the tumble's own time: the joints restart at once, their rates unknown. On the
/// excerpt: the tumbles of fast translation. What follows the take-back is the pendulum's
/// ordinary use under hand-held acceleration (ekf3d up to 3.5 deg worse than vqf 1 s
/// later, not a recovery fault: see docs/real-motion.md).
#[test]
fn after_the_pendulum_tumbles_ekf3d_takes_it_back() {
    use pendtilt::bank::spatial::Bank3d;
    use pendtilt_core::spatial::attitude::inclination_between;
    use pendtilt_core::spatial::attitude::up_from_roll_pitch;
    use pendtilt_core::{Flags, StepGate};
    let mut tumbles = 0;
    for name in TRIALS {
        let (rec, r) = replayed(name);
        let first = rec.movement.unwrap_or(0);
        let only = ["ekf3d", "vqf"].map(String::from);
        let mut bank = Bank3d::new(&settings(&r), Some(&only)).unwrap();
        let mut gate = StepGate::<f64>::new();
        let (mut unused_since, mut back_at) = (None, None);
        // Worst excess of ekf3d's error over vqf's [deg]: on taking the pendulum back, 1 s on.
        let mut worst = [f64::NEG_INFINITY; 2];
        let mut longest = 0.0f64;
        for (k, row) in r.rows.iter().enumerate() {
            let out = bank.update(&row.sample(gate.step(row.t)));
            let truth = up_from_roll_pitch(row.roll, row.pitch);
            let err = |i: usize| {
                inclination_between(up_from_roll_pitch(out[i].roll, out[i].pitch), truth)
                    .to_degrees()
            };
            let excess = err(0) - err(1);
            match (out[0].flags.contains(Flags::PENDULUM_UNUSED), unused_since) {
                (true, None) => unused_since = Some(row.t),
                (false, Some(t0)) => {
                    if row.t - t0 >= 0.2 && k > first {
                        tumbles += 1;
                        longest = longest.max(row.t - t0);
                        worst[0] = worst[0].max(excess);
                        back_at = Some(row.t);
                    }
                    unused_since = None;
                }
                _ => {}
            }
            if back_at.is_some_and(|t| row.t >= t + 1.0) {
                worst[1] = worst[1].max(excess);
                back_at = None;
            }
        }
        eprintln!(
            "{name}: ekf3d's error less vqf's on taking the pendulum back {:.2} deg, 1 s later \
             {:.2} deg; longest tumble {longest:.2} s",
            worst[0], worst[1]
        );
        assert!(worst[0] < 1.0, "{name}: {worst:?}");
    }
    // The excerpt's fast translation and tapping make the pendulum tumble.
    assert!(tumbles >= 2, "{tumbles} tumbles");
}
