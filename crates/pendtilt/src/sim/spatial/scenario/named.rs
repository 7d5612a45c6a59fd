//! The named 3-D scenarios of MODEL.md 7.8 and the variants of `ride3d`, their random
//! parts drawn from the scenario's own stream.
use rand::Rng;
use std::f64::consts::TAU;

use super::{Rig3d, Scenario3d};
use crate::sim::spatial::sensors::{Sensors3d, SpeedFault};
use crate::sim::spatial::timefn::{Context, Shape};
use crate::sim::spatial::vehicle::{
    Axis, EngineMod, EngineSpec, MotionSpec, Term, Tones, Vibration,
};

fn base(duration: f64, score_from: f64, sensors: Sensors3d, motion: MotionSpec) -> Scenario3d {
    Scenario3d {
        duration,
        rate: 1000.0,
        substeps: 2,
        score_from,
        rig: Rig3d::default(),
        sensors,
        motion,
    }
}

fn sigmoid(amp: f64, t0: f64, tau: f64) -> Shape {
    Shape::Sigmoid { amp, t0, tau }
}

fn bump(amp: f64, t0: f64, tau: f64) -> Shape {
    Shape::Bump { amp, t0, tau }
}

fn sine(amp: f64, freq: f64, phase: f64) -> Shape {
    Shape::Sine { amp, freq, phase }
}

fn phase<R: Rng>(rng: &mut R) -> f64 {
    rng.random_range(0.0..TAU)
}

/// `still3d`: roll sigmoid 10 deg at 2 s, pitch sigmoid 10 deg at 3.5 s, tau 0.2 s, yaw 0;
/// 6 s, ideal sensors.
pub(super) fn still3d() -> Scenario3d {
    let motion = MotionSpec {
        roll: vec![Term::new(sigmoid(10.0, 2.0, 0.2))],
        pitch: vec![Term::new(sigmoid(10.0, 3.5, 0.2))],
        yaw: vec![Term::new(Shape::Const { value: 0.0 })],
        ..MotionSpec::default()
    };
    base(6.0, 0.5, Sensors3d::default(), motion)
}

/// `n` sines at log-uniform random frequencies in `band`, amplitude ~ f^-0.6, random phases,
/// scaled so that their sum's largest |value| over `duration` (sampled at 50 Hz) is `max`.
fn random_sines<R: Rng>(
    rng: &mut R,
    n: usize,
    band: [f64; 2],
    max: f64,
    duration: f64,
) -> Vec<Term> {
    let (l0, l1) = (band[0].ln(), band[1].ln());
    let mut shapes: Vec<Shape> = (0..n)
        .map(|_| {
            let f = rng.random_range(l0..l1).exp();
            sine(f.powf(-0.6), f, phase(rng))
        })
        .collect();
    let ctx = Context::default();
    let peak = (0..=(duration * 50.0) as usize)
        .map(|k| crate::sim::spatial::timefn::eval_sum(&shapes, k as f64 / 50.0, &ctx)[0].abs())
        .fold(0.0, f64::max);
    for s in &mut shapes {
        *s = s.scaled(max / peak);
    }
    shapes.into_iter().map(Term::new).collect()
}

/// Engine-locked linear vibration: `amps[k - 1]` (x, y, z) m/s^2 at harmonic k.
fn engine_vibration<R: Rng>(rng: &mut R, amps: &[[f64; 3]]) -> Vec<Vibration> {
    let mut out = Vec::new();
    for (k, a) in amps.iter().enumerate() {
        for (axis, amp) in [Axis::X, Axis::Y, Axis::Z].into_iter().zip(a) {
            out.push(Vibration {
                axis,
                shape: Shape::Engine {
                    amp: *amp,
                    harmonic: (k + 1) as f64,
                    phase: phase(rng),
                },
                speed_ref: None,
            });
        }
    }
    out
}

/// Broadband vibration per axis: `n` tones at uniform random frequencies in `band`, random
/// phases, each of amplitude rms sqrt(2 / n) (RMS `rms`, times v / speed_ref if given).
fn broadband<R: Rng>(
    rng: &mut R,
    n: usize,
    band: [f64; 2],
    rms: [f64; 3],
    speed_ref: Option<f64>,
) -> Vec<Tones> {
    [Axis::X, Axis::Y, Axis::Z]
        .into_iter()
        .zip(rms)
        .map(|(axis, rms)| Tones {
            axis,
            amp: rms * (2.0 / n as f64).sqrt(),
            speed_ref,
            freq: (0..n).map(|_| rng.random_range(band[0]..band[1])).collect(),
            phase: (0..n).map(|_| phase(rng)).collect(),
        })
        .collect()
}

/// An engine-locked angle term \[deg\].
fn engine_angle<R: Rng>(rng: &mut R, amp: f64, harmonic: f64) -> Term {
    Term::new(Shape::Engine {
        amp,
        harmonic,
        phase: phase(rng),
    })
}

/// `scooter3d`: a standing scooter with its engine running, slow roll/pitch/yaw swings,
/// engine and broadband vibration (MODEL.md 7.8).
pub(super) fn scooter3d<R: Rng>(rng: &mut R) -> Scenario3d {
    let duration = 120.0;
    let mut roll = random_sines(rng, 8, [0.05, 0.9], 10.0, duration);
    let mut pitch = random_sines(rng, 8, [0.05, 0.9], 10.0, duration);
    let mut yaw = random_sines(rng, 5, [0.03, 0.5], 4.0, duration);
    roll.push(engine_angle(rng, 0.012, 1.0));
    roll.push(engine_angle(rng, 0.006, 2.0));
    pitch.push(engine_angle(rng, 0.008, 1.0));
    pitch.push(engine_angle(rng, 0.005, 2.0));
    yaw.push(engine_angle(rng, 0.005, 1.0));
    let motion = MotionSpec {
        roll,
        pitch,
        yaw,
        engine: EngineSpec {
            f0: 31.5,
            k_speed: 0.0,
            mods: vec![
                EngineMod {
                    df: 3.0,
                    fm: 0.05,
                    phase: 0.0,
                },
                EngineMod {
                    df: 1.0,
                    fm: 0.31,
                    phase: 1.0,
                },
            ],
        },
        vibration: engine_vibration(rng, &[[2.5, 2.0, 4.0], [3.0, 1.5, 2.0], [0.8, 0.6, 1.0]]),
        broadband: broadband(rng, 200, [5.0, 200.0], [1.5; 3], None),
        ..MotionSpec::default()
    };
    let mut s = base(duration, 5.0, Sensors3d::noisy(), motion);
    s.rig.mounting.speed_at = [0.0, 0.0, -0.25];
    s
}

/// `ship3d`: roll, pitch and yaw swells, surge, heave, the IMU 8 m aft of and 5 m above O,
/// a slow engine and light broadband vibration (MODEL.md 7.8).
pub(super) fn ship3d<R: Rng>(rng: &mut R) -> Scenario3d {
    let motion = MotionSpec {
        roll: vec![
            Term::new(sine(15.0, 0.10, phase(rng))),
            Term::new(sine(1.5, 0.23, phase(rng))),
        ],
        pitch: vec![
            Term::new(sine(5.0, 0.14, phase(rng))),
            Term::new(sine(1.0, 0.31, phase(rng))),
        ],
        yaw: vec![
            Term::path(sine(3.0, 0.02, phase(rng))),
            Term::new(sine(1.0, 0.10, phase(rng))),
        ],
        speed: vec![Shape::Const { value: 6.0 }, sine(0.3, 0.1, 0.0)],
        heave: vec![
            Term::new(sine(1.2, 0.09, phase(rng))),
            Term::new(sine(0.4, 0.16, phase(rng))),
        ],
        engine: EngineSpec {
            f0: 12.0,
            k_speed: 0.0,
            mods: vec![EngineMod {
                df: 0.3,
                fm: 0.1,
                phase: 0.0,
            }],
        },
        vibration: engine_vibration(rng, &[[0.2, 0.2, 0.4], [0.1, 0.1, 0.2]]),
        broadband: broadband(rng, 60, [5.0, 100.0], [0.1, 0.1, 0.2], None),
    };
    let mut s = base(120.0, 5.0, Sensors3d::noisy(), motion);
    s.rig.mounting.speed_at = [8.0, 0.0, -5.0];
    s
}

/// A speed change of `dv` m/s centred at `t0` with peak acceleration `dv / (4 tau)`.
struct SpeedStep {
    dv: f64,
    t0: f64,
    tau: f64,
}

/// The speed profile of `ride3d`: 0 -> 6 (8 s) -> 10 (15 s) -> 15 (40 s) -> 5 (braking at
/// 62 s, 4.2 m/s^2) -> 12 (84 s) -> 0 (108 s).
const RIDE_SPEED: [SpeedStep; 6] = [
    SpeedStep {
        dv: 6.0,
        t0: 8.0,
        tau: 1.5,
    },
    SpeedStep {
        dv: 4.0,
        t0: 15.0,
        tau: 1.0,
    },
    SpeedStep {
        dv: 5.0,
        t0: 40.0,
        tau: 1.2,
    },
    SpeedStep {
        dv: -10.0,
        t0: 62.0,
        tau: 10.0 / (4.0 * 4.2),
    },
    SpeedStep {
        dv: 7.0,
        t0: 84.0,
        tau: 1.5,
    },
    SpeedStep {
        dv: -12.0,
        t0: 108.0,
        tau: 1.2,
    },
];

/// Heading sigmoids of `ride3d` (deg, t0, peak rate rad/s): the S-turns and the curve.
const RIDE_TURNS: [(f64, f64, f64); 7] = [
    (60.0, 22.0, 0.44),
    (-60.0, 28.0, 0.44),
    (30.0, 50.0, 0.13),
    (90.0, 70.0, 0.50),
    (-90.0, 76.0, 0.50),
    (45.0, 94.0, 0.28),
    (-45.0, 100.0, 0.28),
];

/// `ride3d`: a car-like ride: speed changes, braking, S-turns with outward roll, a bank,
/// grades, dive and squat, suspension and heave per speed, an engine that follows the
/// speed, road broadband per speed (MODEL.md 7.8). Long function: it is the table of 7.8.
pub(super) fn ride3d<R: Rng>(rng: &mut R) -> Scenario3d {
    let speed = RIDE_SPEED
        .iter()
        .map(|s| sigmoid(s.dv, s.t0, s.tau))
        .collect();
    let per10 = |shape| Term::per_speed(shape, 10.0);
    let mut yaw: Vec<Term> = RIDE_TURNS
        .iter()
        .map(|&(deg, t0, rate)| Term::path(sigmoid(deg, t0, deg.to_radians().abs() / (4.0 * rate))))
        .collect();
    yaw.push(per10(sine(0.3, 1.5, phase(rng))));
    yaw.push(engine_angle(rng, 0.004, 1.0));
    let roll = vec![
        Term::new(Shape::Lateral { per_g: 4.0 }),
        Term::new(sigmoid(5.0, 45.0, 1.5)),
        Term::new(sigmoid(-5.0, 58.0, 1.5)),
        Term::new(sine(3.0, 0.021, phase(rng))),
        per10(sine(0.35, 1.3, phase(rng))),
        per10(sine(0.15, 2.1, phase(rng))),
        engine_angle(rng, 0.010, 1.0),
        engine_angle(rng, 0.006, 2.0),
    ];
    let mut pitch = vec![
        // Grades: nose up (negative pitch) climbing, nose down descending.
        Term::path(sigmoid(-6.0, 30.0, 2.0)),
        Term::path(sigmoid(6.0, 46.0, 2.0)),
        Term::path(sigmoid(6.0, 88.0, 2.0)),
        Term::path(sigmoid(-6.0, 104.0, 2.0)),
        Term::path(sine(2.0, 0.03, phase(rng))),
    ];
    // Dive (nose down) when braking, squat (nose up) when accelerating, timed with the speed.
    for s in &RIDE_SPEED {
        let amp = match (s.dv < 0.0, s.t0 > 100.0) {
            (true, false) => 1.5,
            (true, true) => 1.2,
            (false, _) => -(0.4 + 0.1 * (s.dv / 7.0).min(1.0)),
        };
        pitch.push(Term::new(bump(amp, s.t0, s.tau)));
    }
    pitch.push(per10(sine(0.4, 1.6, phase(rng))));
    pitch.push(per10(sine(0.15, 2.7, phase(rng))));
    pitch.push(engine_angle(rng, 0.008, 1.0));
    pitch.push(engine_angle(rng, 0.005, 2.0));
    let motion = MotionSpec {
        roll,
        pitch,
        yaw,
        speed,
        heave: vec![
            per10(sine(0.015, 1.2, phase(rng))),
            per10(sine(0.005, 2.7, phase(rng))),
        ],
        engine: EngineSpec {
            f0: 18.0,
            k_speed: 2.4,
            mods: vec![EngineMod {
                df: 0.5,
                fm: 0.13,
                phase: 0.0,
            }],
        },
        vibration: engine_vibration(rng, &[[1.5, 1.0, 2.5], [2.0, 1.5, 1.5], [0.6, 0.5, 0.8]]),
        broadband: broadband(rng, 200, [5.0, 150.0], [1.0, 1.0, 1.5], Some(10.0)),
    };
    let sensors = Sensors3d {
        speed_scale: 1.01,
        ..Sensors3d::noisy()
    };
    let mut s = base(120.0, 5.0, sensors, motion);
    s.rig.mounting.speed_at = [-0.5, 0.1, -0.6];
    s
}

/// `ride3d_yawbias`: `ride3d` with +0.5 deg/s more gyro z bias (module documentation).
pub(super) fn ride3d_yawbias<R: Rng>(rng: &mut R) -> Scenario3d {
    let mut s = ride3d(rng);
    s.sensors.gyro_bias[2] += 0.5f64.to_radians();
    s
}

/// `ride3d_slip`: `ride3d` with a locked wheel when braking at 62 s and a spinning one when
/// pulling away at 84 s (module documentation).
pub(super) fn ride3d_slip<R: Rng>(rng: &mut R) -> Scenario3d {
    let mut s = ride3d(rng);
    s.sensors.speed_faults = vec![
        SpeedFault {
            t0: 61.8,
            rise: 0.15,
            hold: 0.8,
            fall: 0.2,
            gain: 0.0,
            offset: 0.0,
        },
        SpeedFault {
            t0: 83.5,
            rise: 0.3,
            hold: 1.5,
            fall: 0.4,
            gain: 1.0,
            offset: 3.5,
        },
    ];
    s
}
