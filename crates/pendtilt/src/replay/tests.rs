use super::*;
use crate::sim::spatial::motion::Component;
use crate::sim::spatial::{Simulator3d, SineMotion};

/// A body that rests 1.5 s, then rolls, pitches and yaws in steps, simulated exactly at
/// `rate`: the recording an ideal IMU at P1 would give, and the simulator's own encoders.
fn simulated(rate: f64, secs: f64, pend: Pendulum3d) -> (Recording, Vec<[f64; 2]>) {
    let bump = |amp: f64, t0: f64| Component::Sigmoid { amp, t0, tau: 0.15 };
    let m = SineMotion {
        roll: vec![Component::Const(0.1), bump(0.4, 1.8), bump(-0.6, 3.6)],
        pitch: vec![Component::Const(-0.05), bump(-0.3, 2.5)],
        yaw: vec![bump(1.0, 3.0)],
        ..SineMotion::default()
    };
    let sim = Simulator3d::new(pend, m, rate, 4, secs).unwrap();
    let mut rec = Recording {
        origin: "simulated".into(),
        truth: Some(Vec::new()),
        ..Recording::default()
    };
    let mut enc = Vec::new();
    for x in sim {
        rec.t.push(x.t);
        rec.gyro.push(x.body.w);
        rec.accel.push(x.body.f_p1);
        rec.truth
            .as_mut()
            .unwrap()
            .push([x.body.euler[0][0], x.body.euler[1][0]]);
        enc.push(x.encoders());
    }
    (rec, enc)
}

fn exact() -> ReplaySettings {
    ReplaySettings {
        encoder_bits: 0,
        encoder_noise: 0.0,
        ..ReplaySettings::default()
    }
}

/// Driven by the recorded gyro and specific force alone, the replayed pendulum reads what
/// the simulator's pendulum read under the prescribed motion (MODEL.md 7.3 twice, once
/// from body kinematics and once from what an IMU records): within 0.03 deg (0.02
/// measured) at 1 kHz and from a 286 Hz recording (BROAD's rate), whose spline drive cannot
/// know the motion between samples.
#[test]
fn a_replay_of_a_simulated_imu_reads_the_simulators_encoders() {
    for (rate, tol_deg) in [(1000.0, 0.03), (285.714, 0.03)] {
        let (rec, enc) = simulated(rate, 5.0, Pendulum3d::default());
        let r = replay(&rec, &exact()).unwrap();
        let worst = r
            .rows
            .iter()
            .zip(&enc)
            .map(|(row, e)| (row.phi[0] - e[0]).abs().max((row.phi[1] - e[1]).abs()))
            .fold(0.0, f64::max);
        assert!(
            worst.to_degrees() < tol_deg,
            "{rate} Hz: {:.4} deg",
            worst.to_degrees()
        );
        assert!(
            r.report.substep_change < SUBSTEP_TOLERANCE,
            "{:?}",
            r.report
        );
        // The truth and the IMU columns pass through as recorded.
        assert_eq!(r.rows[100].gyro, rec.gyro[100]);
        assert_eq!(r.rows[100].roll, rec.truth.as_ref().unwrap()[100][0]);
    }
}

/// A body at rest, tilted: the pendulum hangs still and the encoders read roll and pitch
/// (MODEL.md 7.2), quantised to 14 bits; gravity is the recording's mean |a|, and the
/// gyro's bias over the rest is removed.
#[test]
fn a_tilted_body_at_rest_reads_its_roll_and_pitch() {
    let (r, p) = (0.2f64, -0.35f64);
    let g = 9.79;
    let f = [-g * p.sin(), g * p.cos() * r.sin(), g * p.cos() * r.cos()];
    let n = 600;
    let rec = Recording {
        origin: "rest".into(),
        t: (0..n).map(|k| k as f64 * 0.005).collect(),
        gyro: vec![[0.01, -0.02, 0.003]; n],
        accel: vec![f; n],
        ..Recording::default()
    };
    let out = replay(
        &rec,
        &ReplaySettings {
            encoder_noise: 0.0,
            ..ReplaySettings::default()
        },
    )
    .unwrap();
    let q = std::f64::consts::TAU / 16384.0;
    for row in &out.rows {
        assert!((row.phi[0] - r).abs() <= 0.5 * q + 1e-12, "{:?}", row.phi);
        assert!((row.phi[1] - p).abs() <= 0.5 * q + 1e-12, "{:?}", row.phi);
        assert!(row.roll.is_nan() && row.speed.is_nan());
    }
    let rest = out.report.rest.unwrap();
    assert_eq!(rest.end, n);
    assert!((out.report.gravity - g).abs() < 1e-12);
    assert!((rest.gyro_bias[1] + 0.02).abs() < 1e-15);
}

/// A body spun about x at 3 turns a second: the pendulum spins with respect to the body;
/// the encoders stay in (-pi, pi]; with stops at 40 deg it never passes them and the hits
/// are counted.
#[test]
fn a_spinning_pendulum_wraps_and_stops_hold_it() {
    let n = 2000;
    let dt = 0.002;
    let w = std::f64::consts::TAU * 3.0;
    let g = 9.81;
    let rec = Recording {
        origin: "spin".into(),
        t: (0..n).map(|k| k as f64 * dt).collect(),
        gyro: (0..n)
            .map(|k| [if k < 300 { 0.0 } else { w }, 0.0, 0.0])
            .collect(),
        accel: (0..n)
            .map(|k| {
                let a = if k < 300 {
                    0.0
                } else {
                    w * (k - 300) as f64 * dt
                };
                [0.0, g * a.sin(), g * a.cos()]
            })
            .collect(),
        ..Recording::default()
    };
    let free = replay(&rec, &exact()).unwrap();
    assert!(
        free.report.largest_swing[0] > std::f64::consts::PI,
        "{:?}",
        free.report
    );
    assert!(free
        .rows
        .iter()
        .all(|r| r.phi[0] > -std::f64::consts::PI && r.phi[0] <= std::f64::consts::PI));
    let travel = 40f64.to_radians();
    let held = replay(
        &rec,
        &ReplaySettings {
            travel: Some([travel, travel]),
            ..exact()
        },
    )
    .unwrap();
    assert!(held.report.stop_hits[0] > 0);
    assert!(
        held.report.largest_swing[0] <= travel + 1e-12,
        "{:?}",
        held.report
    );
    assert!(held.rows.iter().all(|r| r.phi[0].abs() <= travel + 1e-12));
}

#[test]
fn bad_settings_and_recordings_are_refused() {
    let rec = Recording {
        origin: "r.csv".into(),
        t: vec![0.0],
        gyro: vec![[0.0; 3]],
        accel: vec![[0.0, 0.0, 9.8]],
        ..Recording::default()
    };
    let e = replay(&rec, &ReplaySettings::default()).unwrap_err();
    assert_eq!(e.to_string(), "r.csv: fewer than 2 rows: nothing to replay");
    let rec = Recording {
        t: vec![0.0, 0.01],
        gyro: vec![[f64::NAN; 3]; 2],
        accel: vec![[0.0, 0.0, 9.8]; 2],
        ..rec
    };
    let e = replay(&rec, &ReplaySettings::default()).unwrap_err();
    assert_eq!(
        e.to_string(),
        "r.csv: no finite gyro value in the whole recording"
    );
    let e = replay(
        &rec,
        &ReplaySettings {
            substeps: 2,
            ..ReplaySettings::default()
        },
    )
    .unwrap_err();
    assert!(
        e.to_string().contains("at least") || e.to_string().contains("4 to 10000"),
        "{e}"
    );
}

#[test]
fn wrap_keeps_angles_in_the_half_open_interval() {
    use std::f64::consts::PI;
    assert_eq!(wrap_pi(PI), PI);
    assert_eq!(wrap_pi(-PI), PI);
    assert!((wrap_pi(3.0 * PI / 2.0) + PI / 2.0).abs() < 1e-15);
    assert_eq!(wrap_pi(0.25), 0.25);
}
