//! Sensor models: encoder, gyroscope, accelerometer and the potentiometer that gives the
//! true angle. Conventions of MODEL.md section 6: a white-noise density `d` gives a
//! per-sample standard deviation `d * sqrt(rate)`; a random-walk density `q` gives steps of
//! standard deviation `q * sqrt(dt)`; the encoder rounds to the nearest of `2^bits` steps
//! per turn. Each sensor draws from its own random stream, so switching one off or changing
//! its settings leaves the others' noise sequences unchanged.

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

use super::SimError;

/// Degrees to radians, for the defaults below.
const DEG: f64 = std::f64::consts::PI / 180.0;
/// Standard gravity, for defaults quoted in g.
const G0: f64 = 9.80665;

/// Rotary encoder at P2, reading phi.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Encoder {
    /// Resolution: 2^bits steps per turn; 0 = no quantisation. Default 12 (0.088 deg).
    pub bits: u32,
    /// Standard deviation of Gaussian noise added before quantisation \[rad\]. Default 0.
    pub noise: f64,
}

impl Default for Encoder {
    fn default() -> Self {
        Self {
            bits: 12,
            noise: 0.0,
        }
    }
}

/// Gyroscope on the body, reading theta'.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Gyro {
    /// White-noise density \[rad/s/sqrt(Hz)\]. Default 0.005 deg/s/sqrt(Hz) = 8.73e-5
    /// (a common MEMS gyro).
    pub noise_density: f64,
    /// Constant bias \[rad/s\]. Default 0.5 deg/s = 8.73e-3 rad/s.
    pub bias: f64,
    /// Bias random-walk density \[rad/s/sqrt(s)\]. Default 1e-4.
    pub bias_walk: f64,
    /// Full scale: readings clamp to +-full_scale \[rad/s\]; 0 = no saturation.
    /// Default 500 deg/s = 8.73 rad/s.
    pub full_scale: f64,
}

impl Default for Gyro {
    fn default() -> Self {
        Self {
            noise_density: 0.005 * DEG,
            bias: 0.5 * DEG,
            bias_walk: 1e-4,
            full_scale: 500.0 * DEG,
        }
    }
}

/// Accelerometer on the body, reading the specific force in body axes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Accel {
    /// White-noise density per axis \[m/s^2/sqrt(Hz)\]. Default 400 ug/sqrt(Hz) = 3.92e-3.
    pub noise_density: f64,
    /// Constant bias \[x, y\] \[m/s^2\]. Default \[0.02, -0.03\].
    pub bias: [f64; 2],
    /// Full scale: each axis clamps to +-full_scale \[m/s^2\]; 0 = no saturation.
    /// Default 8 g = 78.45 m/s^2.
    pub full_scale: f64,
    /// Mount position relative to the pendulum pivot P2, body axes \[x, y\] \[m\].
    /// Default \[0, 0\]: at P2, where the pendulum feels the same specific force.
    pub mount: [f64; 2],
}

impl Default for Accel {
    fn default() -> Self {
        Self {
            noise_density: 400e-6 * G0,
            bias: [0.02, -0.03],
            full_scale: 8.0 * G0,
            mount: [0.0, 0.0],
        }
    }
}

/// The potentiometer at P1 that measures the true tilt.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Potentiometer {
    /// Standard deviation of its Gaussian noise \[rad\]. Default 0.02 deg = 3.49e-4 rad.
    pub noise: f64,
}

impl Default for Potentiometer {
    fn default() -> Self {
        Self { noise: 0.02 * DEG }
    }
}

/// All sensors of the rig.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Sensors {
    /// The encoder (column `phi`).
    pub encoder: Encoder,
    /// The gyroscope (column `gyro`).
    pub gyro: Gyro,
    /// The accelerometer (columns `ax`, `ay`).
    pub accel: Accel,
    /// The potentiometer (column `theta`).
    pub potentiometer: Potentiometer,
}

impl Sensors {
    /// Switches off every random error: white noise, bias random walk, potentiometer noise.
    /// Constant biases, quantisation and saturation stay (they are deterministic).
    pub fn without_noise(mut self) -> Self {
        self.encoder.noise = 0.0;
        self.gyro.noise_density = 0.0;
        self.gyro.bias_walk = 0.0;
        self.accel.noise_density = 0.0;
        self.potentiometer.noise = 0.0;
        self
    }

    /// Ideal sensors: no noise, no bias, no quantisation, no saturation (the mount position
    /// is kept: it is geometry, not an error).
    pub fn ideal(self) -> Self {
        let mut s = self.without_noise();
        s.encoder.bits = 0;
        s.gyro.bias = 0.0;
        s.gyro.full_scale = 0.0;
        s.accel.bias = [0.0, 0.0];
        s.accel.full_scale = 0.0;
        s
    }

    /// Checks every value; errors name the key (`sensors.<sensor>.<field>`) and why.
    pub fn validate(&self) -> Result<(), SimError> {
        let nonneg = |x: f64, key: &str| {
            if x.is_finite() && x >= 0.0 {
                Ok(())
            } else {
                Err(SimError::invalid(key, format!("must be >= 0, got {x:?}")))
            }
        };
        let finite = |x: f64, key: &str| {
            if x.is_finite() {
                Ok(())
            } else {
                Err(SimError::invalid(key, format!("must be finite, got {x:?}")))
            }
        };
        if self.encoder.bits > 52 {
            return Err(SimError::invalid(
                "sensors.encoder.bits",
                format!("must be 0 ..= 52, got {}", self.encoder.bits),
            ));
        }
        nonneg(self.encoder.noise, "sensors.encoder.noise")?;
        nonneg(self.gyro.noise_density, "sensors.gyro.noise_density")?;
        finite(self.gyro.bias, "sensors.gyro.bias")?;
        nonneg(self.gyro.bias_walk, "sensors.gyro.bias_walk")?;
        nonneg(self.gyro.full_scale, "sensors.gyro.full_scale")?;
        nonneg(self.accel.noise_density, "sensors.accel.noise_density")?;
        finite(self.accel.bias[0], "sensors.accel.bias")?;
        finite(self.accel.bias[1], "sensors.accel.bias")?;
        nonneg(self.accel.full_scale, "sensors.accel.full_scale")?;
        finite(self.accel.mount[0], "sensors.accel.mount")?;
        finite(self.accel.mount[1], "sensors.accel.mount")?;
        nonneg(self.potentiometer.noise, "sensors.potentiometer.noise")
    }
}

/// What the sensors see at one sample, before their errors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrueSignals {
    /// Pendulum angle relative to the body \[rad\].
    pub phi: f64,
    /// Body rate \[rad/s\].
    pub omega: f64,
    /// Specific force at the accelerometer, body axes \[m/s^2\].
    pub accel: [f64; 2],
    /// Body tilt \[rad\].
    pub theta: f64,
}

/// The readings of one sample: `phi`, `gyro`, `ax`, `ay`, `theta` of the log.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Readings {
    /// Encoder \[rad\].
    pub phi: f64,
    /// Gyro \[rad/s\].
    pub gyro: f64,
    /// Accelerometer x \[m/s^2\].
    pub ax: f64,
    /// Accelerometer y \[m/s^2\].
    pub ay: f64,
    /// Potentiometer \[rad\].
    pub theta: f64,
}

/// The sensors of a run: settings turned into per-sample standard deviations, with their
/// random streams and the gyro's wandering bias.
#[derive(Debug, Clone)]
pub struct SensorBank {
    quantum: f64,
    enc_sd: f64,
    gyro_sd: f64,
    gyro_bias: f64,
    walk_sd: f64,
    gyro_fs: f64,
    acc_sd: f64,
    acc_bias: [f64; 2],
    acc_fs: f64,
    pot_sd: f64,
    walk: f64,
    started: bool,
    rng: [ChaCha8Rng; 4],
}

fn gauss(rng: &mut ChaCha8Rng, sd: f64) -> f64 {
    if sd > 0.0 {
        sd * rng.sample::<f64, _>(StandardNormal)
    } else {
        0.0
    }
}

fn clamp(x: f64, fs: f64) -> f64 {
    if fs > 0.0 {
        x.clamp(-fs, fs)
    } else {
        x
    }
}

impl SensorBank {
    /// The sensors sampled at `rate` \[Hz\], with one random stream each (encoder, gyro,
    /// accelerometer, potentiometer).
    pub fn new(s: &Sensors, rate: f64, rng: [ChaCha8Rng; 4]) -> Self {
        let dt = 1.0 / rate;
        Self {
            quantum: if s.encoder.bits == 0 {
                0.0
            } else {
                TAU / 2f64.powi(s.encoder.bits as i32)
            },
            enc_sd: s.encoder.noise,
            gyro_sd: s.gyro.noise_density * rate.sqrt(),
            gyro_bias: s.gyro.bias,
            walk_sd: s.gyro.bias_walk * dt.sqrt(),
            gyro_fs: s.gyro.full_scale,
            acc_sd: s.accel.noise_density * rate.sqrt(),
            acc_bias: s.accel.bias,
            acc_fs: s.accel.full_scale,
            pot_sd: s.potentiometer.noise,
            walk: 0.0,
            started: false,
            rng,
        }
    }

    /// The readings of the next sample. The bias random walk is 0 at the first sample and
    /// takes one step per sample after it.
    pub fn read(&mut self, truth: &TrueSignals) -> Readings {
        let [enc, gyr, acc, pot] = &mut self.rng;
        let mut phi = truth.phi + gauss(enc, self.enc_sd);
        if self.quantum > 0.0 {
            phi = (phi / self.quantum).round() * self.quantum;
        }
        if self.started {
            self.walk += gauss(gyr, self.walk_sd);
        }
        self.started = true;
        let gyro = clamp(
            truth.omega + self.gyro_bias + self.walk + gauss(gyr, self.gyro_sd),
            self.gyro_fs,
        );
        let ax = clamp(
            truth.accel[0] + self.acc_bias[0] + gauss(acc, self.acc_sd),
            self.acc_fs,
        );
        let ay = clamp(
            truth.accel[1] + self.acc_bias[1] + gauss(acc, self.acc_sd),
            self.acc_fs,
        );
        let theta = truth.theta + gauss(pot, self.pot_sd);
        Readings {
            phi,
            gyro,
            ax,
            ay,
            theta,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    fn streams() -> [ChaCha8Rng; 4] {
        core::array::from_fn(|i| {
            let mut r = ChaCha8Rng::seed_from_u64(7);
            r.set_stream(i as u64 + 1);
            r
        })
    }

    #[test]
    fn noise_density_gives_per_sample_sd() {
        let s = Sensors {
            gyro: Gyro {
                noise_density: 0.01,
                bias: 0.0,
                bias_walk: 0.0,
                full_scale: 0.0,
            },
            ..Sensors::default()
        };
        let mut b = SensorBank::new(&s, 400.0, streams());
        let t = TrueSignals {
            phi: 0.0,
            omega: 0.0,
            accel: [0.0, 9.8],
            theta: 0.0,
        };
        let n = 100_000;
        let var = (0..n).map(|_| b.read(&t).gyro.powi(2)).sum::<f64>() / n as f64;
        // Expected sd 0.01 * sqrt(400) = 0.2.
        assert!((var.sqrt() / 0.2 - 1.0).abs() < 0.02, "{}", var.sqrt());
    }

    #[test]
    fn encoder_rounds_to_nearest_step() {
        let s = Sensors {
            encoder: Encoder {
                bits: 8,
                noise: 0.0,
            },
            ..Sensors::default()
        };
        let mut b = SensorBank::new(&s, 1000.0, streams());
        let q = TAU / 256.0;
        let t = TrueSignals {
            phi: 2.4 * q,
            omega: 0.0,
            accel: [0.0, 9.8],
            theta: 0.0,
        };
        assert!((b.read(&t).phi - 2.0 * q).abs() < 1e-15);
        let t = TrueSignals { phi: -2.6 * q, ..t };
        assert!((b.read(&t).phi + 3.0 * q).abs() < 1e-15);
    }

    #[test]
    fn saturation_clamps() {
        let s = Sensors::default();
        let mut b = SensorBank::new(&s.clone().without_noise(), 1000.0, streams());
        let t = TrueSignals {
            phi: 0.0,
            omega: 100.0,
            accel: [-500.0, 500.0],
            theta: 0.0,
        };
        let r = b.read(&t);
        assert_eq!(r.gyro, s.gyro.full_scale);
        assert_eq!(r.ax, -s.accel.full_scale);
        assert_eq!(r.ay, s.accel.full_scale);
    }
}
