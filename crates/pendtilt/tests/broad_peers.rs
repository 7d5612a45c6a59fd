//! The 3-D peers against the reference filters they port, on the BROAD excerpt
//! (tests/data/broad): VQF (`vqf-rs` in [`Imu6`]) against the `vqf` Python package's
//! real-time VQF at its defaults, Madgwick and Mahony (`ahrs` crate in [`Imu6`]) against the
//! `ahrs` Python package's at its default gains. The reference figures are
//! `tests/data/broad/peers_reference_*.csv`, made by
//! `python3 tools/broad_peers_reference.py crates/pendtilt/tests/data/broad`.
//!
//! Each peer is fed the replay's rows as the BROAD benchmark feeds them, from the excerpt's
//! first row, and scored as it scores them.
//!
//! [`Imu6`]: pendtilt::peers::spatial::Imu6
use std::collections::BTreeMap;
use std::path::PathBuf;

use pendtilt::core::spatial::attitude::up_from_roll_pitch;
use pendtilt::core::spatial::SpatialEstimator;
use pendtilt::core::StepGate;
use pendtilt::peers::spatial::{
    madgwick3d, mahony3d, vqf, AHRS_PY_MADGWICK_BETA, AHRS_PY_MAHONY_GAINS, VQF_TAU_ACC,
};
use pendtilt::replay::benchmark::score_one;
use pendtilt::replay::source::ImuOptions;
use pendtilt::replay::{replay, Recording, ReplaySettings};

/// Per trial and filter: the rows stored and the reference's up direction there.
type Ups = BTreeMap<(String, String), Vec<(usize, [f64; 3])>>;

const TRIALS: [&str; 5] = [
    "06_undisturbed_fast_rotation_A",
    "10_undisturbed_slow_translation_A",
    "16_undisturbed_fast_translation_B",
    "24_disturbed_tapping_A",
    "27_disturbed_phone_vibration_B",
];

fn data(file: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/broad")
        .join(file)
}

/// The rows of a reference CSV after its header, split at commas.
fn rows(file: &str) -> Vec<Vec<String>> {
    std::fs::read_to_string(data(file))
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(String::from).collect())
        .collect()
}

fn peer(name: &str) -> Box<dyn SpatialEstimator<f64>> {
    match name {
        "vqf" => Box::new(vqf(VQF_TAU_ACC)),
        "madgwick" => Box::new(madgwick3d(AHRS_PY_MADGWICK_BETA)),
        "mahony" => Box::new(mahony3d(AHRS_PY_MAHONY_GAINS[0], AHRS_PY_MAHONY_GAINS[1])),
        _ => unreachable!("{name}"),
    }
}

fn angle_deg(a: [f64; 3], b: [f64; 3]) -> f64 {
    let c = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    let s = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
    s.atan2(a[0] * b[0] + a[1] * b[1] + a[2] * b[2])
        .to_degrees()
}

/// Each peer's up direction follows the reference filter's at every row stored (every
/// 286th), and its RMS and largest error from the truth over the scored rows, as the
/// benchmark scores them, are the reference's: within 1e-9 deg (measured: 8e-12 deg on the
/// direction, 5e-11 deg on the scores; VQF built for 1 ms instead of the log's 3.5 ms step
/// was 0.6 deg off on trial 10). The one exception is the `ahrs` package skipping the whole
/// update of a sample whose gyro reads exactly 0, which the crate does not: on the trials
/// with such samples (10: 34, 16: 1, all at rest) Madgwick and Mahony are within 0.02 deg
/// (measured: 0.011 and 0.0073 deg, at rest) and their scores within 1e-4 deg (1.1e-5).
#[test]
fn the_peers_follow_the_reference_filters() {
    let mut up = Ups::new();
    for r in rows("peers_reference_up.csv") {
        let v = |i: usize| r[i].parse::<f64>().unwrap();
        up.entry((r[0].clone(), r[1].clone()))
            .or_default()
            .push((r[2].parse().unwrap(), [v(3), v(4), v(5)]));
    }
    let scores: BTreeMap<(String, String), [f64; 2]> = rows("peers_reference_scores.csv")
        .into_iter()
        .map(|r| {
            let v = |i: usize| r[i].parse::<f64>().unwrap();
            ((r[0].clone(), r[1].clone()), [v(2), v(3)])
        })
        .collect();
    assert_eq!(scores.len(), 15);
    let mut checked = 0;
    for name in TRIALS {
        let rec = Recording::open(data(&format!("{name}.mat")), &ImuOptions::default()).unwrap();
        let r = replay(&rec, &ReplaySettings::default()).unwrap();
        let still = rec.gyro.iter().any(|g| g.iter().all(|x| *x == 0.0));
        for filter in ["vqf", "madgwick", "mahony"] {
            let key = (name[..2].to_string(), filter.to_string());
            let (tol_up, tol_score) = if still && filter != "vqf" {
                (0.02, 1e-4)
            } else {
                (1e-9, 1e-9)
            };
            // The up direction, row by row.
            let mut e = peer(filter);
            let mut gate = StepGate::<f64>::new();
            let ours: Vec<[f64; 3]> = r
                .rows
                .iter()
                .map(|row| {
                    let a = e.update(&row.sample(gate.step(row.t)));
                    up_from_roll_pitch(a.roll, a.pitch)
                })
                .collect();
            let reference = &up[&key];
            assert!(reference.len() > 40, "{key:?}");
            let worst = reference
                .iter()
                .map(|(k, u)| angle_deg(ours[*k], *u))
                .fold(0.0, f64::max);
            println!("{key:?}: up direction within {worst:.2e} deg of the reference");
            assert!(worst < tol_up, "{key:?}: {worst} deg");
            // The benchmark's scores.
            let (s, _) = score_one(&rec, &r, filter, peer(filter).as_mut());
            let [rms, max] = scores[&key];
            assert!(s.rows[0] > 9000, "{key:?}: {} rows", s.rows[0]);
            assert!(
                (s.rms - rms).abs() < tol_score && (s.max - max).abs() < tol_score,
                "{key:?}: {} ({}) deg RMS (max), reference {rms} ({max})",
                s.rms,
                s.max
            );
            checked += 1;
        }
    }
    assert_eq!(checked, 15);
}
