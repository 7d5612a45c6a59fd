//! The 3-D scenarios of MODEL.md 7.8 and the vehicle motion of 7.7: each scenario's truth has
//! the statistics the table asks for; the accelerometer's specific force integrates to the
//! vehicle's velocity and the `speed` column; a simulated log satisfies the joint equations of
//! 7.3 (computed here from the log's columns alone); at rest the encoders read roll and pitch.

use pendtilt::sim::spatial::motion::{attitude, BodyMotion};
use pendtilt::sim::spatial::{specific_force_at, LogRow3d, Pendulum3d, Scenario3d, VehicleMotion};
use std::f64::consts::TAU;

const G: f64 = 9.80665;

fn deg(x: f64) -> f64 {
    x.to_degrees()
}

/// The named scenario with its motion built.
fn scenario(name: &str, seed: u64) -> (Scenario3d, VehicleMotion) {
    let s = Scenario3d::named(name, seed).unwrap();
    let m = s.motion().unwrap();
    (s, m)
}

/// The motion's state at `rate` Hz over [0, secs).
fn sample_times(secs: f64, rate: f64) -> impl Iterator<Item = f64> {
    (0..(secs * rate) as usize).map(move |k| k as f64 / rate)
}

/// Largest |x| of `f` over [0, secs) at 100 Hz.
fn peak(secs: f64, f: impl Fn(f64) -> f64) -> f64 {
    sample_times(secs, 100.0)
        .map(|t| f(t).abs())
        .fold(0.0, f64::max)
}

#[test]
fn still3d_is_two_sigmoid_steps() {
    let (s, m) = scenario("still3d", 1);
    assert_eq!((s.duration, s.rate, s.score_from), (6.0, 1000.0, 0.5));
    let end = m.state(6.0, G).euler;
    assert!((deg(end[0][0]) - 10.0).abs() < 1e-3 && (deg(end[1][0]) - 10.0).abs() < 1e-3);
    assert_eq!(end[2][0], 0.0);
    // Peak rate of a 10 deg sigmoid with tau 0.2 s: 10 / (4 tau) = 12.5 deg/s, at 2 and 3.5 s.
    let at = |t: f64| m.state(t, G).euler;
    assert!((deg(at(2.0)[0][1]) - 12.5).abs() < 1e-9);
    assert!((deg(at(3.5)[1][1]) - 12.5).abs() < 1e-9);
    assert!(deg(at(0.0)[0][0]).abs() < 1e-3);
    assert!(!s.motion.has_vibration());
    assert_eq!(
        s.sensors,
        pendtilt::sim::spatial::Sensors3d::default(),
        "ideal sensors"
    );
}

/// RMS of the vibration alone, per body axis: the scenario minus the same without vibration.
fn vibration_rms(s: &Scenario3d, secs: f64) -> [f64; 3] {
    let m = s.motion().unwrap();
    let quiet = VehicleMotion::new(
        &s.motion.clone().without_vibration(),
        s.rig.mounting.speed_at,
    )
    .unwrap();
    let mut sum = [0.0; 3];
    let n = (secs * 2000.0) as usize;
    for k in 0..n {
        let t = k as f64 / 2000.0;
        let (a, b) = (m.kinematics(t, G).f_p1, quiet.kinematics(t, G).f_p1);
        for i in 0..3 {
            sum[i] += (a[i] - b[i]).powi(2);
        }
    }
    sum.map(|x| (x / n as f64).sqrt())
}

#[test]
fn scooter3d_swings_engine_and_vibration() {
    let (s, m) = scenario("scooter3d", 1);
    assert_eq!(s.rig.mounting.speed_at, [0.0, 0.0, -0.25]);
    let e = |t: f64| m.state(t, G).euler;
    // Scaled so that the largest swing is 10 deg (roll, pitch) and 4 deg (yaw).
    assert!((deg(peak(120.0, |t| e(t)[0][0])) - 10.0).abs() < 0.02);
    assert!((deg(peak(120.0, |t| e(t)[1][0])) - 10.0).abs() < 0.02);
    assert!((deg(peak(120.0, |t| e(t)[2][0])) - 4.0).abs() < 0.02);
    // Slow: roll rate stays below that of a 10 deg sine at 0.9 Hz.
    assert!(peak(120.0, |t| e(t)[0][1]) < TAU * 0.9 * 10f64.to_radians());
    // Engine 31.5 + 3 sin(2 pi 0.05 t) + sin(2 pi 0.31 t + 1) Hz.
    let fe = |t: f64| m.state(t, G).engine[1] / TAU;
    for t in [0.0, 3.7, 5.0, 12.3, 80.0] {
        let want = 31.5 + 3.0 * (TAU * 0.05 * t).sin() + (TAU * 0.31 * t + 1.0).sin();
        assert!((fe(t) - want).abs() < 1e-9, "t {t}: {} {want}", fe(t));
    }
    // Standing: no speed.
    assert_eq!(peak(120.0, |t| m.speed(t, G)), 0.0);
    // Vibration RMS per axis: broadband 1.5 plus the three engine harmonics (amp / sqrt 2),
    // over 20 s (the random tones' cross terms average out to a few per cent).
    let rms = vibration_rms(&s, 20.0);
    let harm = [[2.5, 3.0, 0.8], [2.0, 1.5, 0.6], [4.0, 2.0, 1.0]];
    for i in 0..3 {
        let want = (1.5f64.powi(2) + harm[i].iter().map(|a| a * a / 2.0).sum::<f64>()).sqrt();
        assert!(
            (rms[i] / want - 1.0).abs() < 0.06,
            "axis {i}: {} vs {want}",
            rms[i]
        );
    }
    // Broadband tones inside 5-200 Hz, 200 per axis.
    assert_eq!(s.motion.broadband.len(), 3);
    for b in &s.motion.broadband {
        assert_eq!(b.freq.len(), 200);
        assert!(b.freq.iter().all(|f| (5.0..200.0).contains(f)));
    }
}

#[test]
fn ship3d_swell_surge_heave_and_lever_arm() {
    let (s, m) = scenario("ship3d", 2);
    assert_eq!(s.rig.mounting.speed_at, [8.0, 0.0, -5.0]);
    let e = |t: f64| m.state(t, G).euler;
    let roll = deg(peak(120.0, |t| e(t)[0][0]));
    let pitch = deg(peak(120.0, |t| e(t)[1][0]));
    assert!((13.5..=16.5).contains(&roll), "roll {roll}");
    assert!((4.0..=6.0).contains(&pitch), "pitch {pitch}");
    assert!(deg(peak(120.0, |t| e(t)[2][0])) <= 4.0);
    // Surge 6 + 0.3 sin(2 pi 0.1 t) m/s; the log's speed (body x) within the tilt's cosine
    // and the heave rate's share.
    for t in [0.0, 2.5, 7.5, 61.0] {
        let v = m.state(t, G).speed[0];
        assert!((v - 6.0 - 0.3 * (TAU * 0.1 * t).sin()).abs() < 1e-12);
        let sp = m.speed(t, G);
        assert!((sp - v).abs() < 0.1 * v, "t {t}: speed {sp} v {v}");
    }
    // Heave amplitude about 1.6 m.
    let z = peak(120.0, |t| m.state(t, G).heave[0]);
    assert!((1.2..=1.6).contains(&z), "heave {z}");
    // The IMU 8 m aft and 5 m up feels the swell as lever-arm acceleration of ~1 m/s^2:
    // compare with the same ship with O at the IMU.
    let here = VehicleMotion::new(&s.motion.clone().without_vibration(), [0.0; 3]).unwrap();
    let far = VehicleMotion::new(&s.motion.clone().without_vibration(), [8.0, 0.0, -5.0]).unwrap();
    let lever = peak(120.0, |t| {
        let (a, b) = (far.kinematics(t, G).f_p1, here.kinematics(t, G).f_p1);
        ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
    });
    assert!(
        (0.5..3.0).contains(&lever),
        "lever-arm acceleration {lever}"
    );
    let rms = vibration_rms(&s, 20.0);
    let want = [0.1f64, 0.1, 0.2]
        .iter()
        .zip([[0.2, 0.1], [0.2, 0.1], [0.4, 0.2]])
        .map(|(b, h)| (b * b + h.iter().map(|a| a * a / 2.0).sum::<f64>()).sqrt())
        .collect::<Vec<_>>();
    for i in 0..3 {
        assert!(
            (rms[i] / want[i] - 1.0).abs() < 0.1,
            "axis {i}: {} {}",
            rms[i],
            want[i]
        );
    }
}

#[test]
fn ride3d_speeds_braking_turns_and_engine() {
    let (s, m) = scenario("ride3d", 3);
    assert_eq!(s.sensors.speed_scale, 1.01);
    assert_eq!(s.rig.mounting.speed_at, [-0.5, 0.1, -0.6]);
    let st = |t: f64| m.state(t, G);
    // Plateaus: 6, 10, 15, 5, 12, 0 m/s.
    for (t, v) in [
        (12.5, 6.0),
        (20.0, 10.0),
        (50.0, 15.0),
        (72.0, 5.0),
        (96.0, 12.0),
        (119.0, 0.0),
    ] {
        assert!(
            (st(t).speed[0] - v).abs() < 0.4,
            "t {t}: {} not {v}",
            st(t).speed[0]
        );
    }
    // Braking at 62 s peaks at 4.2 m/s^2.
    let decel = (0..2000)
        .map(|k| -st(61.0 + k as f64 * 1e-3).speed[1])
        .fold(0.0, f64::max);
    assert!((decel - 4.2).abs() < 0.05, "braking {decel}");
    // Turn rates of the path heading at each turn's middle (rad/s), and the speed there.
    let path_rate = |t: f64| {
        let x = st(t);
        // The heading of travel: atan2 of d's world y, x.
        let (h0, h1) = (
            x.direction[1].atan2(x.direction[0]),
            (x.direction[1] + 1e-6 * x.direction_rate[1])
                .atan2(x.direction[0] + 1e-6 * x.direction_rate[0]),
        );
        (h1 - h0) / 1e-6
    };
    for (t, rate, v) in [
        (22.0, 0.44, 10.0),
        (28.0, -0.44, 10.0),
        (70.0, 0.50, 5.0),
        (76.0, -0.50, 5.0),
        (94.0, 0.28, 12.0),
        (100.0, -0.28, 12.0),
    ] {
        let r = path_rate(t);
        assert!((r - rate).abs() < 0.01, "t {t}: turn rate {r}, want {rate}");
        assert!((st(t).speed[0] - v).abs() < 0.5, "t {t}: speed");
    }
    // Net heading after the S-turns is back; the 30 deg curve stays.
    let heading = |t: f64| deg(st(t).direction[1].atan2(st(t).direction[0]));
    assert!(heading(40.0).abs() < 0.5 && (heading(60.0) - 30.0).abs() < 0.5);
    // Outward roll in the first turn: a left turn (positive yaw rate) at 4.4 m/s^2 rolls the
    // body right-side down by ~4 deg/g * 0.45 g = 1.8 deg relative to the straight road.
    let roll_turn = deg(st(22.0).euler[0][0]) - deg(st(18.0).euler[0][0]);
    assert!(roll_turn > 1.0, "outward roll {roll_turn}");
    // Pitch: grade 6 + undulation 2 + dive: together under 10 deg, over 6.
    let pitch = deg(peak(120.0, |t| st(t).euler[1][0]));
    assert!((6.0..10.0).contains(&pitch), "pitch {pitch}");
    let roll = deg(peak(120.0, |t| st(t).euler[0][0]));
    assert!((3.0..12.0).contains(&roll), "roll {roll}");
    // Engine 18 Hz + 2.4 Hz per m/s (to 54 Hz at 15 m/s) + 0.5 sin(2 pi 0.13 t).
    let fe = peak(120.0, |t| st(t).engine[1] / TAU);
    assert!((54.0..55.0).contains(&fe), "engine {fe}");
    // Road broadband follows the speed: (1, 1, 1.5) m/s^2 RMS at 10 m/s, 1.5 times that at
    // 15 m/s (50 s), almost none at 0.03 m/s (t = 0).
    let mut road = s.clone();
    road.motion.vibration.clear();
    let rms_at = |t0: f64| vibration_rms_window(&road, t0, 1.0);
    let (stopped, cruising) = (rms_at(0.0), rms_at(50.0));
    for (i, want) in [1.5, 1.5, 2.25].into_iter().enumerate() {
        assert!(
            (cruising[i] / want - 1.0).abs() < 0.1,
            "axis {i}: {cruising:?}"
        );
        assert!(stopped[i] < 0.01, "{stopped:?}");
    }
}

fn vibration_rms_window(s: &Scenario3d, t0: f64, secs: f64) -> [f64; 3] {
    let m = s.motion().unwrap();
    let quiet = VehicleMotion::new(
        &s.motion.clone().without_vibration(),
        s.rig.mounting.speed_at,
    )
    .unwrap();
    let n = (secs * 4000.0) as usize;
    let mut sum = [0.0; 3];
    for k in 0..n {
        let t = t0 + k as f64 / 4000.0;
        let (a, b) = (m.kinematics(t, G).f_p1, quiet.kinematics(t, G).f_p1);
        for i in 0..3 {
            sum[i] += (a[i] - b[i]).powi(2);
        }
    }
    sum.map(|x| (x / n as f64).sqrt())
}

/// The specific force at O (from the accelerometer's f_P1, moved by the rigid-body formula)
/// rotated to the world and with gravity added back integrates to the vehicle's velocity;
/// its body-x component is the `speed` truth. Checks that the travel accelerations (speed
/// changes, turns, grades, heave) are in f, with the right signs.
#[test]
fn specific_force_integrates_to_the_speed() {
    for name in ["ride3d", "ship3d"] {
        let (s, _) = scenario(name, 4);
        let at = s.rig.mounting.speed_at;
        let m = VehicleMotion::new(&s.motion.clone().without_vibration(), at).unwrap();
        let rate = 1000.0;
        let a_world = |t: f64| {
            let k = m.kinematics(t, G);
            let f_o = specific_force_at(k.f_p1, k.w, k.wd, at);
            let r = attitude(k.euler[0][0], k.euler[1][0], k.euler[2][0]);
            let a: [f64; 3] =
                core::array::from_fn(|i| (0..3).map(|j| r[i][j] * f_o[j]).sum::<f64>());
            [a[0], a[1], a[2] - G]
        };
        let mut v = m.state(0.0, G).velocity();
        let mut a0 = a_world(0.0);
        let mut worst: f64 = 0.0;
        for k in 1..(80.0 * rate) as usize {
            let t = k as f64 / rate;
            let a1 = a_world(t);
            for i in 0..3 {
                v[i] += 0.5 / rate * (a0[i] + a1[i]);
            }
            a0 = a1;
            let truth = m.state(t, G).velocity();
            let err = (0..3).map(|i| (v[i] - truth[i]).abs()).fold(0.0, f64::max);
            worst = worst.max(err);
            if k % 1000 == 0 {
                let k = m.kinematics(t, G);
                let r = attitude(k.euler[0][0], k.euler[1][0], k.euler[2][0]);
                let sp = r[0][0] * v[0] + r[1][0] * v[1] + r[2][0] * v[2];
                assert!((sp - m.speed(t, G)).abs() < 1e-3, "{name} t {t}: {sp}");
            }
        }
        assert!(
            worst < 1e-3,
            "{name}: integrated velocity off by {worst} m/s"
        );
    }
}

/// The analytic derivatives of ride3d's angles (turn roll, per-speed sines, engine terms)
/// agree with central differences.
#[test]
fn ride3d_angle_derivatives_are_exact() {
    let (_, m) = scenario("ride3d", 5);
    let h = 1e-6;
    for k in 0..400 {
        let t = 0.3 * k as f64 + 0.01;
        let (x, xp, xm) = (m.state(t, G), m.state(t + h, G), m.state(t - h, G));
        for a in 0..3 {
            for o in 0..2 {
                let fd = (xp.euler[a][o] - xm.euler[a][o]) / (2.0 * h);
                let tol = 2e-6 * (1.0 + x.euler[a][o + 1].abs());
                assert!(
                    (fd - x.euler[a][o + 1]).abs() < tol,
                    "t {t} angle {a} order {o}"
                );
            }
        }
        for i in 0..3 {
            let dd = (xp.direction[i] - xm.direction[i]) / (2.0 * h);
            assert!((dd - x.direction_rate[i]).abs() < 1e-7, "t {t}: d'");
        }
    }
}

/// The explicit joint equations of MODEL.md 7.3 (written out here from the contract):
/// residuals (J + Ia) a'' - rhs_a and Iyy b'' - rhs_b \[N m\].
#[allow(clippy::too_many_arguments)]
fn joint_residual(
    p: &Pendulum3d,
    [a, b]: [f64; 2],
    [ad, bd]: [f64; 2],
    [add, bdd]: [f64; 2],
    w: [f64; 3],
    wd: [f64; 3],
    f: [f64; 3],
) -> [f64; 2] {
    let (sa, ca) = a.sin_cos();
    let (sb, cb) = b.sin_cos();
    let (ixx, iyy, izz, j) = (p.inertia_xx, p.inertia_yy, p.inertia_zz, p.ring_inertia);
    let ml = p.mass * p.length;
    let (u2, u3) = (ca * w[1] + sa * w[2], -sa * w[1] + ca * w[2]);
    let (v2, v3) = (ca * wd[1] + sa * wd[2], -sa * wd[1] + ca * wd[2]);
    let (h1, h2, h3) = (f[0], ca * f[1] + sa * f[2], -sa * f[1] + ca * f[2]);
    let pr = w[0] + ad;
    let (w1, w2, w3) = (cb * pr - sb * u3, u2 + bd, sb * pr + cb * u3);
    let ia = ixx * cb * cb + izz * sb * sb;
    let rhs_a = -p.damping_x * ad
        - (j + ia) * wd[0]
        - ml * cb * h2
        - (izz - ixx) * sb * cb * (bd * pr + v3 - ad * u2)
        + ia * bd * u3
        - w2 * (cb * (izz - iyy) * w3 + sb * (iyy - ixx) * w1);
    let rhs_b =
        -p.damping_y * bd - iyy * (v2 + ad * u3) - (ixx - izz) * w1 * w3 + ml * (cb * h1 - sb * h3);
    [(j + ia) * add - rhs_a, iyy * bdd - rhs_b]
}

/// The largest joint-equation residual of a log (relative to m g l), from its columns only:
/// a = -phi_x, b = -phi_y and gyro differentiated by central differences, the pivot's
/// specific force moved from the accelerometer's (at P1) by the rigid-body formula.
fn log_residual(p: &Pendulum3d, rows: &[LogRow3d]) -> f64 {
    let h = rows[1].t - rows[0].t;
    let mut worst: f64 = 0.0;
    for k in 1..rows.len() - 1 {
        let (r0, r, r1) = (&rows[k - 1], &rows[k], &rows[k + 1]);
        let ang = |r: &LogRow3d| [-r.phi[0], -r.phi[1]];
        let (x0, x, x1) = (ang(r0), ang(r), ang(r1));
        let d1 = [0, 1].map(|i| (x1[i] - x0[i]) / (2.0 * h));
        let d2 = [0, 1].map(|i| (x1[i] - 2.0 * x[i] + x0[i]) / (h * h));
        let wd = [0, 1, 2].map(|i| (r1.gyro[i] - r0.gyro[i]) / (2.0 * h));
        let f = specific_force_at(r.accel, r.gyro, wd, p.pivot_offset);
        let res = joint_residual(p, x, d1, d2, r.gyro, wd, f);
        worst = worst.max(res[0].abs()).max(res[1].abs());
    }
    worst / p.mgl()
}

/// Every scenario's simulated log (ideal sensors, an asymmetric rig with a pivot offset and a
/// ring) satisfies 7.3: the residual is the differences' O(h^2) error, 4x smaller at twice
/// the rate; a wrong or missing term would leave a residual that does not fall with h.
#[test]
fn simulated_logs_satisfy_the_joint_equations() {
    for name in ["still3d", "scooter3d", "ship3d", "ride3d"] {
        let mut s = Scenario3d::named(name, 6).unwrap();
        s.sensors = s.sensors.ideal();
        s.rig.pendulum3d = Pendulum3d {
            inertia_yy: 1.0e-4,
            inertia_zz: 3.0e-5,
            ring_inertia: 2.0e-5,
            pivot_offset: [0.03, -0.02, 0.1],
            ..Pendulum3d::default()
        };
        s.duration = 0.4;
        let mut res = Vec::new();
        for rate in [4000.0, 8000.0] {
            s.rate = rate;
            let rows: Vec<LogRow3d> = s.run(6).unwrap().map(|(_, r)| r).collect();
            res.push(log_residual(&s.rig.pendulum3d, &rows));
        }
        let ratio = res[0] / res[1];
        eprintln!(
            "{name}: residual {:e} (4 kHz), {:e} (8 kHz) of m g l",
            res[0], res[1]
        );
        assert!(res[1] < 2e-3, "{name}: residual {:e} of m g l", res[1]);
        assert!(
            (3.3..4.7).contains(&ratio),
            "{name}: residual ratio {ratio}, not O(h^2)"
        );
    }
}

/// At rest the log's encoders read roll and pitch: exactly at the start (the pendulum starts
/// hanging still), and to 1e-9 rad once still3d's steps have settled.
#[test]
fn encoders_at_rest_equal_roll_and_pitch() {
    let mut s = Scenario3d::named("still3d", 1).unwrap();
    s.duration = 12.0;
    s.motion.yaw[0].shape = pendtilt::sim::spatial::timefn::Shape::Const { value: 40.0 };
    let rows: Vec<LogRow3d> = s.run(1).unwrap().map(|(_, r)| r).collect();
    let (first, last) = (rows[0], rows[rows.len() - 1]);
    assert_eq!(first.phi, [first.roll, first.pitch]);
    assert!((last.roll - 10f64.to_radians()).abs() < 1e-12);
    assert!(
        (last.phi[0] - last.roll).abs() < 1e-9,
        "{:e}",
        last.phi[0] - last.roll
    );
    assert!(
        (last.phi[1] - last.pitch).abs() < 1e-9,
        "{:e}",
        last.phi[1] - last.pitch
    );
    // In between they do not: the pendulum swings after each step.
    let swing = rows
        .iter()
        .map(|r| (r.phi[0] - r.roll).abs())
        .fold(0.0, f64::max);
    assert!(swing > 0.1f64.to_radians(), "{swing}");
}

/// The speed column is scale * truth + white noise of the set sigma (ride3d: 1.01, 0.05).
#[test]
fn speed_column_scale_and_noise() {
    let mut s = Scenario3d::named("ride3d", 7).unwrap();
    s.duration = 12.0;
    s.rate = 500.0;
    s.motion = s.motion.without_vibration();
    let (mut sum, mut sq, mut n) = (0.0, 0.0, 0.0);
    for (x, r) in s.run(7).unwrap() {
        let e = r.speed - 1.01 * x.speed;
        sum += e;
        sq += e * e;
        n += 1.0;
    }
    let (mean, sd) = (sum / n, (sq / n - (sum / n).powi(2)).sqrt());
    assert!(
        mean.abs() < 0.005 && (sd / 0.05 - 1.0).abs() < 0.05,
        "{mean} {sd}"
    );
}

/// Same seed, same rows; another seed, other random parts.
#[test]
fn scenarios_are_seeded() {
    let a = Scenario3d::named("scooter3d", 9).unwrap();
    assert_eq!(a, Scenario3d::named("scooter3d", 9).unwrap());
    assert_ne!(a.motion, Scenario3d::named("scooter3d", 10).unwrap().motion);
    let e = Scenario3d::named("bus3d", 1).unwrap_err().to_string();
    assert!(e.contains("still3d, scooter3d, ship3d, ride3d"), "{e}");
}

/// The node filler (broadband tones by rotation) gives the same kinematics as one call per
/// node: bit for bit at the first node (the sample's row), to rounding at the others.
#[test]
fn node_fill_matches_one_call_per_node() {
    let (_, m) = scenario("scooter3d", 8);
    let mut out = vec![m.kinematics(0.0, G); 5];
    for k in [0u32, 1, 777, 119_999] {
        let t0 = f64::from(k) / 1000.0;
        m.fill(t0, 2.5e-4, G, &mut out);
        assert_eq!(out[0], m.kinematics(t0, G));
        for (j, o) in out.iter().enumerate() {
            let direct = m.kinematics(t0 + j as f64 * 2.5e-4, G);
            for i in 0..3 {
                // Tone phases up to 2 pi 200 Hz 120 s: rounding of 1e-11 rad in either form.
                assert!(
                    (o.f_p1[i] - direct.f_p1[i]).abs() < 1e-8,
                    "t0 {t0} node {j}"
                );
                assert_eq!(o.w[i], direct.w[i]);
            }
        }
    }
}

/// `ride3d` and a variant, both made with `seed`, the vibration off and at 200 Hz to keep
/// the run short, to `secs`: (truth speed, ride3d's row, the variant's row) per sample.
fn ride3d_and(variant: &str, seed: u64, secs: f64) -> Vec<(f64, LogRow3d, LogRow3d)> {
    let quick = |name| {
        let mut s = Scenario3d::named(name, seed).unwrap();
        s.duration = secs;
        s.rate = 200.0;
        s.motion = s.motion.without_vibration();
        s
    };
    let (base, var) = (quick("ride3d"), quick(variant));
    base.run(seed)
        .unwrap()
        .zip(var.run(seed).unwrap())
        .map(|((x, a), (_, b))| (x.speed, a, b))
        .collect()
}

/// `ride3d_yawbias` is `ride3d` with 0.5 deg/s more on the gyro's z reading, nothing else.
#[test]
fn ride3d_yawbias_adds_half_a_degree_per_second_to_gyro_z() {
    for (_, a, b) in ride3d_and("ride3d_yawbias", 2, 20.0) {
        assert!(
            (b.gyro[2] - a.gyro[2] - 0.5f64.to_radians()).abs() < 1e-12,
            "{b:?}"
        );
        let same = LogRow3d { gyro: a.gyro, ..b };
        assert_eq!(same, a);
    }
}

/// `ride3d_slip`'s speed column is ride3d's outside its two slip intervals; inside them a
/// locked wheel reads 0 (plus noise) while the vehicle still moves at 7-11 m/s, and a
/// spinning one 3.5 m/s above 1.01 x the truth; every other column is ride3d's.
#[test]
fn ride3d_slip_locks_when_braking_and_spins_when_pulling_away() {
    let s = Scenario3d::named("ride3d_slip", 1).unwrap();
    let slips = s.slip_intervals();
    assert_eq!(slips.len(), 2);
    let lock = slips[0];
    let spin = slips[1];
    assert!((lock[0] - 61.8).abs() < 1e-9 && (lock[1] - 62.95).abs() < 1e-9);
    assert!((spin[0] - 83.5).abs() < 1e-9 && (spin[1] - 85.7).abs() < 1e-9);
    let (mut locked, mut spun) = (0, 0);
    for (v, a, b) in ride3d_and("ride3d_slip", 1, 86.5) {
        let t = a.t;
        assert_eq!(
            LogRow3d {
                speed: a.speed,
                ..b
            },
            a
        );
        if slips.iter().all(|i| t < i[0] || t > i[1]) {
            assert_eq!(a.speed, b.speed, "t = {t}");
        } else if (61.95..=62.75).contains(&t) {
            // The hold of the lock: noise alone (0.05 m/s sigma) on 0.
            assert!(
                b.speed.abs() < 0.25 && v > 7.0,
                "t = {t}: {} at {v}",
                b.speed
            );
            locked += 1;
        } else if (83.8..=85.3).contains(&t) {
            assert!((b.speed - 1.01 * v - 3.5).abs() < 0.25, "t = {t}");
            spun += 1;
        }
    }
    assert_eq!((locked, spun), (161, 301));
}
