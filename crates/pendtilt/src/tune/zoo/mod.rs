//! The zoo of unseen rigs: seeded simulated rides with randomly drawn rigs,
//! sensor grades, vibration and motions, on which self-tuning is measured against the
//! defaults and a brute-force grid tuned against the true angle ([`score`]).
//!
//! Ride `k` is drawn from a ChaCha generator seeded with `k` alone, so ride 7 is the same
//! ride whatever else is drawn:
//! - pendulum: natural frequency 0.5-5 Hz (log-uniform), damping ratio 0.1-0.8, pivot
//!   offset 0-0.1 m; 50 g, its centre of gravity at most 5 cm from the pivot;
//! - sensors, one grade of four (consumer, industrial, navigation, tactical): encoder
//!   10-16 bits with 0-0.03 deg of noise; gyro noise density 0.02 to 0.0005
//!   deg/s/sqrt(Hz) and bias walk; accelerometer 60-400 ug/sqrt(Hz);
//! - vibration, one of: none; an engine (fundamental 15-90 Hz, 0.5-4 m/s^2, a second
//!   harmonic, angular vibration up to 1.5 mrad); broadband (0.3-3 m/s^2 in 5-200 Hz);
//!   both;
//! - motion, one of: random manoeuvres (RMS 3-10 deg in 0.05-0.5..1.2 Hz), a sine
//!   (5-15 deg, 0.1-1.2 Hz), a chirp (3-8 deg, 0.05 -> 1-2 Hz).
pub mod score;

use crate::sim::planar::motion::{Chirp, Manoeuvres, Motion, Sine};
use crate::sim::planar::vibration::{AngularHarmonic, Broadband, Harmonic, Vibration};
use crate::sim::planar::{PendulumTable, Scenario};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::{PI, TAU};

const DEG: f64 = PI / 180.0;
/// Standard gravity \[m/s^2\].
const G: f64 = 9.80665;

/// One ride of the zoo: the scenario and the seed it is simulated with.
#[derive(Debug, Clone)]
pub struct Ride {
    /// Its number (the seed of the draw and of the simulation).
    pub index: u64,
    /// The drawn scenario.
    pub scenario: Scenario,
    /// One line: the rig, sensors, vibration and motion drawn.
    pub description: String,
}

/// A log-uniform draw in `[lo, hi]`.
fn log_uniform(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    (lo.ln() + rng.random::<f64>() * (hi.ln() - lo.ln())).exp()
}

/// A pendulum of natural frequency `f_n` \[Hz\], damping ratio `zeta` and pivot offset
/// `l12` \[m\]: 50 g, the centre of gravity at most 5 cm from the pivot and the inertia
/// that gives `f_n` (at least the point mass's).
pub fn pendulum(f_n: f64, zeta: f64, l12: f64) -> PendulumTable {
    let (mass, w2) = (0.05, (TAU * f_n).powi(2));
    // A point mass at l has w^2 = g / l: the centre of gravity is within 0.8 g / w^2.
    let length = (0.8 * G / w2).min(0.05);
    let inertia = mass * G * length / w2;
    let damping = 2.0 * zeta * (inertia * mass * G * length).sqrt();
    PendulumTable {
        mass,
        length,
        inertia,
        damping,
        pivot_offset: l12,
        gravity: G,
    }
}

/// The sensors of one of four grades (0 consumer .. 3 tactical), with some spread.
fn sensors(rng: &mut ChaCha8Rng, scenario: &mut Scenario) -> &'static str {
    let grade = rng.random_range(0..4usize);
    let spread = |rng: &mut ChaCha8Rng| log_uniform(rng, 0.7, 1.4);
    let s = &mut scenario.sensors;
    let (name, bits, enc, gyro, walk, acc) = [
        ("consumer", 10, 0.03, 0.02, 3e-4, 400e-6),
        ("industrial", 12, 0.01, 0.006, 1e-4, 200e-6),
        ("navigation", 14, 0.003, 0.002, 3e-5, 100e-6),
        ("tactical", 16, 0.0, 0.0005, 1e-5, 60e-6),
    ][grade];
    s.encoder.bits = bits;
    s.encoder.noise = enc * DEG * spread(rng);
    s.gyro.noise_density = gyro * DEG * spread(rng);
    s.gyro.bias_walk = walk * spread(rng);
    s.gyro.bias = rng.random_range(-1.0..1.0) * DEG;
    s.accel.noise_density = acc * G * spread(rng);
    name
}

/// The floor's vibration: none, an engine, broadband, or both; and its description.
fn vibration(rng: &mut ChaCha8Rng) -> (Vibration, String) {
    let kind = rng.random_range(0..4usize);
    let mut v = Vibration::default();
    let mut what = Vec::new();
    if kind == 1 || kind == 3 {
        let f = log_uniform(rng, 15.0, 90.0);
        let a = log_uniform(rng, 0.5, 4.0);
        v.harmonics = vec![
            Harmonic {
                frequency: f,
                amplitude: a,
                axis: [rng.random_range(-1.0..1.0), 1.0],
                phase: rng.random_range(0.0..TAU),
            },
            Harmonic {
                frequency: 2.0 * f,
                amplitude: 0.5 * a,
                axis: [1.0, rng.random_range(-1.0..1.0)],
                phase: rng.random_range(0.0..TAU),
            },
        ];
        let ang = rng.random_range(0.0..1.5e-3);
        v.angular = vec![AngularHarmonic {
            frequency: f,
            amplitude: ang,
            phase: rng.random_range(0.0..TAU),
        }];
        what.push(format!(
            "engine {f:.0} Hz {a:.1} m/s^2, {:.2} mrad",
            ang * 1e3
        ));
    }
    if kind >= 2 {
        let r = [log_uniform(rng, 0.3, 3.0), log_uniform(rng, 0.3, 3.0)];
        v.broadband = Broadband {
            rms: r,
            band: [5.0, 200.0],
        };
        what.push(format!("broadband {:.1}/{:.1} m/s^2", r[0], r[1]));
    }
    if what.is_empty() {
        what.push("no vibration".into());
    }
    (v, what.join(" + "))
}

/// The body's motion and its description.
fn motion(rng: &mut ChaCha8Rng) -> (Motion, String) {
    match rng.random_range(0..3usize) {
        0 => {
            let rms = rng.random_range(3.0..10.0) * DEG;
            let top = rng.random_range(0.5..1.2);
            let m = Manoeuvres {
                amplitude: 2.2 * rms,
                rms,
                band: [0.05, top],
                ..Manoeuvres::default()
            };
            let d = format!("manoeuvres {:.1} deg RMS to {top:.2} Hz", rms / DEG);
            (Motion::Manoeuvres(m), d)
        }
        1 => {
            let (a, f) = (
                rng.random_range(5.0..15.0) * DEG,
                log_uniform(rng, 0.1, 1.2),
            );
            let s = Sine {
                amplitude: a,
                frequency: f,
                ..Sine::default()
            };
            (
                Motion::Sine(s),
                format!("sine {:.1} deg at {f:.2} Hz", a / DEG),
            )
        }
        _ => {
            let (a, f1) = (rng.random_range(3.0..8.0) * DEG, rng.random_range(1.0..2.0));
            let c = Chirp {
                amplitude: a,
                f0: 0.05,
                f1,
                sweep_time: 40.0,
                ..Chirp::default()
            };
            (
                Motion::Chirp(c),
                format!("chirp {:.1} deg, 0.05 -> {f1:.2} Hz", a / DEG),
            )
        }
    }
}

/// Ride `index` of the zoo, `duration` seconds at 1 kHz (module documentation).
pub fn ride(index: u64, duration: f64) -> Ride {
    let mut rng = ChaCha8Rng::seed_from_u64(index);
    let f_n = log_uniform(&mut rng, 0.5, 5.0);
    let zeta = rng.random_range(0.1..0.8);
    let l12 = rng.random_range(0.0..0.1);
    let (m, motion_d) = motion(&mut rng);
    let mut scenario = Scenario::with_motion(m, duration);
    scenario.pendulum = pendulum(f_n, zeta, l12);
    let grade = sensors(&mut rng, &mut scenario);
    let (v, vib_d) = vibration(&mut rng);
    scenario.vibration = v;
    let description = format!(
        "f_n {f_n:.2} Hz, zeta {zeta:.2}, l12 {:.0} mm; {grade}; {vib_d}; {motion_d}",
        l12 * 1e3
    );
    Ride {
        index,
        scenario,
        description,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_drawn_pendulum_has_the_drawn_frequency_and_damping() {
        for (f, z) in [(0.5, 0.1), (2.0, 0.4), (5.0, 0.8)] {
            let p = pendulum(f, z, 0.05);
            let phys: pendtilt_core::PhysicalParams<f64> = p.into();
            let n = phys.normalised();
            assert!((n.natural_frequency_hz() / f - 1.0).abs() < 1e-9, "{f}");
            assert!((n.damping_ratio() / z - 1.0).abs() < 1e-9, "{z}");
            assert!(p.inertia >= p.mass * p.length * p.length);
        }
    }

    #[test]
    fn rides_are_reproducible_and_valid() {
        for k in 0..30 {
            let a = ride(k, 40.0);
            assert_eq!(a.description, ride(k, 40.0).description);
            a.scenario.validate().unwrap();
            let p = a.scenario.physical().normalised();
            let f = p.natural_frequency_hz();
            assert!((0.5..=5.0).contains(&f), "{k}: {f}");
        }
    }
}
