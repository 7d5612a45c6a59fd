//! The 3-axis sensor models of MODEL.md 7.5 and the log row of 7.6 (the `speed` column reads
//! the vehicle's forward speed of 7.7, 0 for a body that does not travel).
//!
//! Wheel slip: [`SpeedFault`] stretches where the `speed` reading departs from
//! the true speed (a spinning wheel reads above it, a locked one drops towards 0), listed
//! in [`Sensors3d::speed_faults`] so that the scenario file records them.
//!
//! White-noise density d gives a per-sample sigma d sqrt(rate); random-walk density q gives
//! steps of sigma q sqrt(dt). Each noise source draws from its own ChaCha8 stream of the
//! seed, so a shorter run is the start of a longer one and switching one source off leaves
//! the others unchanged.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

use super::dynamics::specific_force_at;
use super::simulator::Truth3d;

/// A stretch of wheel slip: the `speed` reading departs from the true speed and comes
/// back. With `e(t)` the fault's envelope (0 before `t0`, a smoothstep to 1 over `rise`, 1
/// for `hold`, a smoothstep back to 0 over `fall`), the reading before its white noise is
///
/// ```text
/// speed = (1 - e + e gain) * scale * v + e * offset
/// ```
///
/// A wheel spinning when pulling away: `gain` 1, `offset` 3.5 m/s (the reading rises above
/// the truth); a wheel locking when braking: `gain` 0, `offset` 0 (it drops to 0 while the
/// vehicle still moves).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpeedFault {
    /// Start \[s\]: the reading begins to depart from the truth.
    pub t0: f64,
    /// Time to depart fully \[s\].
    pub rise: f64,
    /// Time fully departed \[s\].
    pub hold: f64,
    /// Time to return to the truth \[s\].
    pub fall: f64,
    /// Factor on the true reading at full departure (1 spin, 0 lock).
    pub gain: f64,
    /// Added at full departure \[m/s\].
    pub offset: f64,
}

/// `3 x^2 - 2 x^3` on [0, 1], 0 below, 1 above: a ramp with no step in its rate at its ends.
fn smoothstep(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

impl SpeedFault {
    /// The true slip interval `[t0, t0 + rise + hold + fall]` \[s\]: where the reading
    /// departs from the truth.
    pub fn interval(&self) -> [f64; 2] {
        [self.t0, self.t0 + self.rise + self.hold + self.fall]
    }

    /// The envelope `e(t)` in [0, 1] (see the type's documentation).
    pub fn envelope(&self, t: f64) -> f64 {
        let up = if self.rise > 0.0 {
            smoothstep((t - self.t0) / self.rise)
        } else {
            f64::from(t >= self.t0)
        };
        let end = self.t0 + self.rise + self.hold;
        let down = if self.fall > 0.0 {
            smoothstep((t - end) / self.fall)
        } else {
            f64::from(t >= end)
        };
        up * (1.0 - down)
    }

    /// The reading `speed` (without noise) becomes under this fault at `t`.
    pub fn apply(&self, t: f64, speed: f64) -> f64 {
        let e = self.envelope(t);
        (1.0 - e + e * self.gain) * speed + e * self.offset
    }

    fn validate(&self, k: usize) -> Result<(), crate::sim::planar::SimError> {
        let all = [
            self.t0,
            self.rise,
            self.hold,
            self.fall,
            self.gain,
            self.offset,
        ];
        let times = [self.rise, self.hold, self.fall];
        if all.iter().any(|v| !v.is_finite()) || times.iter().any(|&v| v < 0.0) {
            return Err(crate::sim::planar::SimError::invalid(
                format!("sensors.speed_faults[{k}]"),
                "values must be finite, rise, hold and fall >= 0 s",
            ));
        }
        Ok(())
    }
}

/// Sensor settings (MODEL.md 7.5), SI units. [`Default`] is ideal: no noise, no bias, no
/// quantisation, accelerometer at P1, speed scale 1, no speed faults.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Sensors3d {
    /// Encoder resolution: 2^bits steps per turn; 0 = none.
    pub encoder_bits: u32,
    /// Encoder white noise, per sample \[rad\], added before rounding.
    pub encoder_noise: f64,
    /// Gyro white-noise density \[rad/s/sqrt(Hz)\].
    pub gyro_noise_density: f64,
    /// Gyro constant bias, body axes \[rad/s\].
    pub gyro_bias: [f64; 3],
    /// Gyro bias random-walk density \[rad/s/sqrt(s)\].
    pub gyro_bias_walk: f64,
    /// Accelerometer white-noise density \[m/s^2/sqrt(Hz)\].
    pub accel_noise_density: f64,
    /// Accelerometer constant bias, body axes \[m/s^2\].
    pub accel_bias: [f64; 3],
    /// Accelerometer position - P1, body axes \[m\] (`[mounting] accel_at`, 7.6; not
    /// written with the sensors: the rig file's `[mounting]` holds it).
    #[serde(skip)]
    pub accel_at: [f64; 3],
    /// Speed sensor scale factor (a wheel's radius error): speed = scale * true speed.
    pub speed_scale: f64,
    /// Speed white noise, per sample \[m/s\].
    pub speed_noise: f64,
    /// Wheel-slip stretches of the speed reading, in any order (overlapping ones apply in
    /// turn). Not written when empty.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub speed_faults: Vec<SpeedFault>,
}

impl Default for Sensors3d {
    fn default() -> Self {
        Self {
            encoder_bits: 0,
            encoder_noise: 0.0,
            gyro_noise_density: 0.0,
            gyro_bias: [0.0; 3],
            gyro_bias_walk: 0.0,
            accel_noise_density: 0.0,
            accel_bias: [0.0; 3],
            accel_at: [0.0; 3],
            speed_scale: 1.0,
            speed_noise: 0.0,
            speed_faults: Vec::new(),
        }
    }
}

impl Sensors3d {
    /// The "noisy" grade of MODEL.md 7.8: encoders 14 bit + 0.01 deg white; gyro
    /// 0.01 deg/s/sqrt(Hz), bias (0.5, -0.3, 0.2) deg/s, random walk 0.005 deg/s/sqrt(s);
    /// accelerometer 200 ug/sqrt(Hz), bias (0.02, -0.015, 0.03) m/s^2; speed 0.05 m/s white,
    /// scale 1.
    pub fn noisy() -> Self {
        let d = 1f64.to_radians();
        Self {
            encoder_bits: 14,
            encoder_noise: 0.01 * d,
            gyro_noise_density: 0.01 * d,
            gyro_bias: [0.5 * d, -0.3 * d, 0.2 * d],
            gyro_bias_walk: 0.005 * d,
            accel_noise_density: 200e-6 * 9.80665,
            accel_bias: [0.02, -0.015, 0.03],
            accel_at: [0.0; 3],
            speed_scale: 1.0,
            speed_noise: 0.05,
            speed_faults: Vec::new(),
        }
    }

    /// The same without random errors (white noise, bias walk); biases, scale, speed
    /// faults and quantisation stay (`--no-noise`).
    pub fn without_noise(self) -> Self {
        Self {
            encoder_noise: 0.0,
            gyro_noise_density: 0.0,
            gyro_bias_walk: 0.0,
            accel_noise_density: 0.0,
            speed_noise: 0.0,
            ..self
        }
    }

    /// Ideal sensors at the same mounting (`--ideal-sensors`).
    pub fn ideal(self) -> Self {
        Self {
            accel_at: self.accel_at,
            ..Self::default()
        }
    }

    /// The true slip intervals of [`Sensors3d::speed_faults`] \[s\] (see
    /// [`SpeedFault::interval`]).
    pub fn slip_intervals(&self) -> Vec<[f64; 2]> {
        self.speed_faults.iter().map(SpeedFault::interval).collect()
    }

    /// Checks every value; errors name the `sensors.<key>`.
    pub fn validate(&self) -> Result<(), crate::sim::planar::SimError> {
        let non_negative = [
            ("encoder_noise", self.encoder_noise),
            ("gyro_noise_density", self.gyro_noise_density),
            ("gyro_bias_walk", self.gyro_bias_walk),
            ("accel_noise_density", self.accel_noise_density),
            ("speed_noise", self.speed_noise),
        ];
        for (key, v) in non_negative {
            if !(v.is_finite() && v >= 0.0) {
                return Err(crate::sim::planar::SimError::invalid(
                    format!("sensors.{key}"),
                    format!("must be finite and >= 0, got {v:?}"),
                ));
            }
        }
        let finite = self
            .gyro_bias
            .iter()
            .chain(&self.accel_bias)
            .chain(&self.accel_at)
            .chain([&self.speed_scale]);
        if finite.into_iter().any(|x| !x.is_finite()) {
            return Err(crate::sim::planar::SimError::invalid(
                "sensors",
                "biases, accel_at and speed_scale must be finite",
            ));
        }
        for (k, f) in self.speed_faults.iter().enumerate() {
            f.validate(k)?;
        }
        if self.encoder_bits > 32 {
            return Err(crate::sim::planar::SimError::invalid(
                "sensors.encoder_bits",
                format!("must be 0 (none) to 32, got {}", self.encoder_bits),
            ));
        }
        Ok(())
    }
}

/// One row of the 3-D sensor log (MODEL.md 7.6, columns [`LogRow3d::COLUMNS`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LogRow3d {
    /// t \[s\].
    pub t: f64,
    /// Encoders (phi_x, phi_y) = (-a, -b) with noise and rounding \[rad\].
    pub phi: [f64; 2],
    /// Gyro, body axes \[rad/s\].
    pub gyro: [f64; 3],
    /// Accelerometer, body axes \[m/s^2\].
    pub accel: [f64; 3],
    /// Forward speed \[m/s\] (MODEL.md 7.5).
    pub speed: f64,
    /// True ZYX roll \[rad\].
    pub roll: f64,
    /// True ZYX pitch \[rad\].
    pub pitch: f64,
}

impl LogRow3d {
    /// The CSV header of MODEL.md 7.6.
    pub const COLUMNS: [&'static str; 12] = [
        "t", "phi_x", "phi_y", "gyro_x", "gyro_y", "gyro_z", "ax", "ay", "az", "speed", "roll",
        "pitch",
    ];

    /// The sensor readings as the 3-D estimators take them, `dt` after the previous row.
    pub fn sample(&self, dt: f64) -> pendtilt_core::model::SpatialSample<f64> {
        pendtilt_core::model::SpatialSample {
            speed: self.speed,
            ..pendtilt_core::model::SpatialSample::new(dt, self.phi, self.gyro, self.accel)
        }
    }

    /// The values in [`LogRow3d::COLUMNS`] order.
    pub fn values(&self) -> [f64; 12] {
        [
            self.t,
            self.phi[0],
            self.phi[1],
            self.gyro[0],
            self.gyro[1],
            self.gyro[2],
            self.accel[0],
            self.accel[1],
            self.accel[2],
            self.speed,
            self.roll,
            self.pitch,
        ]
    }
}

/// Random stream numbers, one per noise source.
mod stream {
    pub const ENCODER: u64 = 11;
    pub const GYRO: u64 = 12;
    pub const GYRO_WALK: u64 = 13;
    pub const ACCEL: u64 = 14;
    pub const SPEED: u64 = 15;
}

/// The sensors of one run: settings, their random streams and the gyro's walking bias.
#[derive(Debug, Clone)]
pub struct SensorBank3d {
    s: Sensors3d,
    /// Per-sample white-noise sigmas: gyro, accelerometer.
    sigma: [f64; 2],
    /// Random-walk step sigma.
    walk_step: f64,
    walk: [f64; 3],
    rng: [ChaCha8Rng; 5],
}

fn rng(seed: u64, stream: u64) -> ChaCha8Rng {
    let mut r = ChaCha8Rng::seed_from_u64(seed);
    r.set_stream(stream);
    r
}

fn gauss(r: &mut ChaCha8Rng) -> f64 {
    r.sample(StandardNormal)
}

impl SensorBank3d {
    /// Sensors `s` sampled at `rate` Hz, noise drawn from `seed`.
    pub fn new(s: Sensors3d, rate: f64, seed: u64) -> Self {
        Self {
            sigma: [
                s.gyro_noise_density * rate.sqrt(),
                s.accel_noise_density * rate.sqrt(),
            ],
            walk_step: s.gyro_bias_walk / rate.sqrt(),
            walk: [0.0; 3],
            rng: [
                stream::ENCODER,
                stream::GYRO,
                stream::GYRO_WALK,
                stream::ACCEL,
                stream::SPEED,
            ]
            .map(|k| rng(seed, k)),
            s,
        }
    }

    /// The log row for the true state `x` (call once per sample, in order).
    pub fn read(&mut self, x: &Truth3d) -> LogRow3d {
        let s = &self.s;
        let q = (s.encoder_bits > 0).then(|| TAU / 2f64.powi(s.encoder_bits as i32));
        let [er, gr, wr, ar, sr] = &mut self.rng;
        let phi = x.encoders().map(|v| {
            let v = v + s.encoder_noise * gauss(er);
            q.map_or(v, |q| (v / q).round() * q)
        });
        let w = x.body.w;
        let gyro: [f64; 3] = core::array::from_fn(|i| {
            w[i] + s.gyro_bias[i] + self.walk[i] + self.sigma[0] * gauss(gr)
        });
        for b in &mut self.walk {
            *b += self.walk_step * gauss(wr);
        }
        let f = specific_force_at(x.body.f_p1, w, x.body.wd, s.accel_at);
        let accel: [f64; 3] =
            core::array::from_fn(|i| f[i] + s.accel_bias[i] + self.sigma[1] * gauss(ar));
        LogRow3d {
            t: x.t,
            phi,
            gyro,
            accel,
            speed: s
                .speed_faults
                .iter()
                .fold(s.speed_scale * x.speed, |v, f| f.apply(x.t, v))
                + s.speed_noise * gauss(sr),
            roll: x.body.euler[0][0],
            pitch: x.body.euler[1][0],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::spatial::motion::Component;
    use crate::sim::spatial::{Pendulum3d, Simulator3d, SineMotion};

    fn truth(secs: f64) -> Vec<Truth3d> {
        let m = SineMotion {
            roll: vec![Component::Sine {
                amp: 0.3,
                freq: 0.5,
                phase: 0.0,
            }],
            pitch: vec![Component::Sine {
                amp: 0.2,
                freq: 0.7,
                phase: 1.0,
            }],
            yaw: vec![Component::Ramp(0.5)],
            ..SineMotion::default()
        };
        Simulator3d::new(Pendulum3d::default(), m, 1000.0, 2, secs)
            .unwrap()
            .collect()
    }

    /// Ideal sensors read the truth exactly; the accelerometer at P1 reads f_P1.
    #[test]
    fn ideal_sensors_read_the_truth() {
        let mut bank = SensorBank3d::new(Sensors3d::default(), 1000.0, 1);
        for x in truth(1.0) {
            let r = bank.read(&x);
            assert_eq!(r.phi, x.encoders());
            assert_eq!(r.gyro, x.body.w);
            assert_eq!(r.accel, x.body.f_p1);
            assert_eq!((r.roll, r.pitch), (x.body.euler[0][0], x.body.euler[1][0]));
        }
    }

    /// Noise sigmas follow d sqrt(rate), biases are means, encoders sit on the 14-bit grid,
    /// and a shorter run is the start of a longer one.
    #[test]
    fn noise_levels_bias_and_quantisation() {
        let s = Sensors3d {
            encoder_bits: 14,
            encoder_noise: 1e-4,
            gyro_noise_density: 1e-3,
            gyro_bias: [0.01, -0.02, 0.03],
            accel_noise_density: 2e-3,
            accel_bias: [0.2, -0.15, 0.3],
            ..Sensors3d::default()
        };
        let xs = truth(20.0);
        let mut bank = SensorBank3d::new(s.clone(), 1000.0, 7);
        let rows: Vec<_> = xs.iter().map(|x| bank.read(x)).collect();
        let q = TAU / 16384.0;
        let n = rows.len() as f64;
        for i in 0..3 {
            let e: Vec<f64> = xs
                .iter()
                .zip(&rows)
                .map(|(x, r)| r.gyro[i] - x.body.w[i])
                .collect();
            let mean = e.iter().sum::<f64>() / n;
            let sd = (e.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n).sqrt();
            assert!((mean - s.gyro_bias[i]).abs() < 5e-4, "gyro mean {mean}");
            assert!(
                (sd / (1e-3 * 1000f64.sqrt()) - 1.0).abs() < 0.03,
                "gyro sd {sd}"
            );
            let e: Vec<f64> = xs
                .iter()
                .zip(&rows)
                .map(|(x, r)| r.accel[i] - x.body.f_p1[i])
                .collect();
            let mean = e.iter().sum::<f64>() / n;
            let sd = (e.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n).sqrt();
            assert!((mean - s.accel_bias[i]).abs() < 1e-3, "accel mean {mean}");
            assert!(
                (sd / (2e-3 * 1000f64.sqrt()) - 1.0).abs() < 0.03,
                "accel sd {sd}"
            );
        }
        for (x, r) in xs.iter().zip(&rows) {
            for (p, t) in r.phi.iter().zip(x.encoders()) {
                assert!(((p / q) - (p / q).round()).abs() < 1e-9);
                assert!((p - t).abs() < 0.5 * q + 6e-4, "{p} {t}");
            }
        }
        let mut short = SensorBank3d::new(s, 1000.0, 7);
        for (x, r) in xs.iter().zip(&rows).take(500) {
            assert_eq!(short.read(x), *r);
        }
    }

    /// The gyro bias walk: after T s its spread across seeds is q sqrt(T).
    #[test]
    fn gyro_bias_walk_spreads_as_sqrt_t() {
        let s = Sensors3d {
            gyro_bias_walk: 2e-3,
            ..Sensors3d::default()
        };
        let xs = truth(4.0);
        let mut ends = Vec::new();
        for seed in 0..200 {
            let mut bank = SensorBank3d::new(s.clone(), 1000.0, seed);
            let last = xs.iter().map(|x| bank.read(x)).last().unwrap();
            ends.push(last.gyro[1] - xs.last().unwrap().body.w[1]);
        }
        let sd = (ends.iter().map(|v| v * v).sum::<f64>() / ends.len() as f64).sqrt();
        let expect = 2e-3 * (3.999f64).sqrt();
        assert!((sd / expect - 1.0).abs() < 0.15, "{sd} vs {expect}");
    }

    /// The fault's envelope by hand: smoothstep up over `rise`, hold, down over `fall`; a
    /// spin adds the offset, a lock scales the reading to 0.
    #[test]
    fn speed_fault_envelope_and_reading() {
        let spin = SpeedFault {
            t0: 10.0,
            rise: 0.4,
            hold: 1.0,
            fall: 0.2,
            gain: 1.0,
            offset: 3.0,
        };
        assert_eq!(spin.interval(), [10.0, 11.6]);
        // x = 0.25: 3 x^2 - 2 x^3 = 0.15625.
        let cases = [
            (9.9, 0.0),
            (10.1, 0.15625),
            (10.2, 0.5),
            (10.9, 1.0),
            (11.5, 0.5),
        ];
        for (t, e) in cases {
            assert!((spin.envelope(t) - e).abs() < 1e-12, "{t}");
            assert!((spin.apply(t, 8.0) - (8.0 + 3.0 * e)).abs() < 1e-12, "{t}");
        }
        assert_eq!(spin.envelope(11.7), 0.0);
        let lock = SpeedFault {
            gain: 0.0,
            offset: 0.0,
            ..spin
        };
        assert!((lock.apply(10.2, 8.0) - 4.0).abs() < 1e-12);
        assert_eq!(lock.apply(10.5, 8.0), 0.0);
    }

    /// An accelerometer away from P1 reads the rigid-body transfer of f_P1 (7.1).
    #[test]
    fn accelerometer_offset_adds_the_lever_arm() {
        let at = [0.1, -0.05, 0.2];
        let s = Sensors3d {
            accel_at: at,
            ..Sensors3d::default()
        };
        let mut bank = SensorBank3d::new(s, 1000.0, 1);
        for x in truth(0.5) {
            let r = bank.read(&x);
            assert_eq!(
                r.accel,
                specific_force_at(x.body.f_p1, x.body.w, x.body.wd, at)
            );
            assert_ne!(r.accel, x.body.f_p1);
        }
    }
}
