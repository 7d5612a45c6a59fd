//! Settings of the model-based filters and how their defaults follow from the rig and the
//! sensors' data-sheet noise figures.
//!
//! # Where the defaults come from
//! Measurement noise (per sample, from the sensors):
//! - encoder: `r_phi = q^2 / 12 + sigma_enc^2 + j^2`, `q = 2 pi / 2^bits` (a uniform
//!   rounding error has variance q^2 / 12), `j` the pendulum's jitter from vibration above
//!   its band ([`ModelSettings::encoder_jitter`], default 0);
//! - gyro: `r_gyro = d_g^2 / dt` for a white-noise density `d_g` [rad/s/sqrt(Hz)]
//!   (MODEL.md section 6: per-sample standard deviation `d sqrt(rate)`), recomputed from
//!   each sample's actual step;
//! - accelerometer: `r_acc = d_a^2 / dt + sigma_vib^2` per axis: its own white noise plus
//!   the floor vibration, which the filter does not model and which dominates.
//!
//! Process noise (densities, see [`ProcessNoise`]):
//! - bias: the gyro's bias random-walk density squared;
//! - jerk: the body's tilt acceleration changes at the pace of its manoeuvres: a sinusoid
//!   of amplitude A at f has theta''' of amplitude `A (2 pi f)^3`, so with the tilt RMS
//!   `A` spread up to the bandwidth `f` the density is `A^2 (2 pi f)^6 / f` (7 deg up to
//!   0.8 Hz: 301 rad^2/s^5). Angular vibration far above the pendulum (the scooter's
//!   40 Hz) is left to the gyro measurement: a random-walk theta'' fast enough to follow
//!   it would follow the gyro's noise as well;
//! - pendulum: a specific force `a` across the pendulum forces phi'' by `a / (b g)`
//!   (MODEL.md section 2: `I beta'' = -m l f`). The pendulum responds to its forcing
//!   near and below its natural frequency f_n and filters out the rest, so the white-noise
//!   density that stands for the vibration is the vibration's density near f_n, `d`:
//!   `q = d^2 / (b g)^2`. It is not the vibration's total power: engine harmonics and
//!   broadband vibration above f_n barely move the pendulum.
//!
//! Checked against the tuner on the simulated scooter ride (l12 = 0.2 m, 60 s): these
//! defaults gave 0.043 deg RMS (fixed; 0.042 with the adaptation), the fitted densities
//! 0.038 deg.
//!
//! The tuner in the std crate (`pendtilt::peers::tune`) fits the three process noise
//! densities on a log with a true angle.
use super::model::{PendulumProcess, ProcessNoise};
use crate::adaptation::Adaptation;
use crate::params::STANDARD_GRAVITY;
use crate::{PendulumParams, PhysicalParams, Real};

/// Data-sheet noise figures of the sensors. Defaults: a 12-bit encoder and a common MEMS
/// IMU (the simulator's defaults).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SensorNoise<T> {
    /// Encoder resolution in bits per turn (0: not quantised). Default 12.
    pub encoder_bits: u32,
    /// Encoder noise, standard deviation \[rad\]. Default 0.
    pub encoder_noise: T,
    /// Gyro white-noise density [rad/s/sqrt(Hz)]. Default 0.005 deg/s/sqrt(Hz) = 8.73e-5.
    pub gyro_density: T,
    /// Gyro bias random-walk density [rad/s/sqrt(s)]. Default 1e-4.
    pub gyro_bias_walk: T,
    /// How large the gyro's initial bias may be, standard deviation [rad/s].
    /// Default 1 deg/s = 0.01745.
    pub gyro_bias: T,
    /// Accelerometer white-noise density per axis [m/s^2/sqrt(Hz)].
    /// Default 400 ug/sqrt(Hz) = 3.92e-3.
    pub accel_density: T,
}

impl<T: Real> Default for SensorNoise<T> {
    fn default() -> Self {
        let deg = core::f64::consts::PI / 180.0;
        Self {
            encoder_bits: 12,
            encoder_noise: T::zero(),
            gyro_density: T::lit(0.005 * deg),
            gyro_bias_walk: T::lit(1e-4),
            gyro_bias: T::lit(deg),
            accel_density: T::lit(400e-6 * STANDARD_GRAVITY),
        }
    }
}

impl<T: Real> SensorNoise<T> {
    /// Variance of one encoder reading [rad^2]: `q^2 / 12 + sigma^2`.
    pub fn encoder_variance(&self) -> T {
        let q = if self.encoder_bits == 0 || self.encoder_bits > 52 {
            T::zero()
        } else {
            T::two_pi() / T::lit((1u64 << self.encoder_bits) as f64)
        };
        q * q / T::lit(12.0) + self.encoder_noise * self.encoder_noise
    }
}

/// What the filter is told about the environment: how the body moves and shakes. Only
/// used to derive [`ProcessNoise`] and the accelerometer's noise. Defaults: the `scooter`
/// scenario of MODEL.md section 6.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Environment<T> {
    /// RMS of the slow tilt manoeuvres \[rad\]. Default 7 deg.
    pub tilt_rms: T,
    /// Their highest frequency \[Hz\]. Default 0.8 Hz.
    pub tilt_bandwidth_hz: T,
    /// Density of the translational acceleration across the pendulum near its natural
    /// frequency [m/s^2/sqrt(Hz)]. Default 0.02: the scooter's broadband vibration
    /// (1.5 m/s^2 RMS across the pendulum in 5-200 Hz, second-order band edges) at the
    /// default pendulum's 2.19 Hz: `1.5 / sqrt(195) (2.19 / 5)^2 = 0.020`.
    pub vibration_density: T,
    /// RMS of all the vibration an accelerometer reads, per axis [m/s^2]. Default
    /// 3 m/s^2 (the scooter's engine harmonics and broadband vibration together: 1.8 on
    /// x, 3.4 on y).
    pub vibration_rms: T,
    /// RMS of the body's angular vibration rate [rad/s]: vibration too fast for the
    /// model's tilt acceleration to follow, which the gyro reads and the filter leaves to
    /// it. Default 0.178 rad/s: the scooter's 1 mrad at 40 Hz, `2 pi 40 1e-3 / sqrt(2)`.
    pub angular_vibration_rms: T,
}

impl<T: Real> Default for Environment<T> {
    fn default() -> Self {
        let deg = core::f64::consts::PI / 180.0;
        Self {
            tilt_rms: T::lit(7.0 * deg),
            tilt_bandwidth_hz: T::lit(0.8),
            vibration_density: T::lit(0.02),
            vibration_rms: T::lit(3.0),
            angular_vibration_rms: T::lit(0.178),
        }
    }
}

impl<T: Real> ProcessNoise<T> {
    /// The densities derived from the rig, the sensors and the environment (see the module
    /// documentation).
    pub fn derive(
        params: &PendulumParams<T>,
        gravity: T,
        sensors: &SensorNoise<T>,
        env: &Environment<T>,
    ) -> Self {
        let jerk = if env.tilt_bandwidth_hz > T::zero() {
            let w = T::two_pi() * env.tilt_bandwidth_hz;
            let w3 = w * w * w;
            env.tilt_rms * env.tilt_rms * w3 * w3 / env.tilt_bandwidth_hz
        } else {
            T::zero()
        };
        let bg = params.b * gravity;
        let pendulum = env.vibration_density * env.vibration_density / (bg * bg);
        Self {
            jerk,
            pendulum,
            bias: sensors.gyro_bias_walk * sensors.gyro_bias_walk,
        }
    }
}

/// Settings of [`super::Ekf`] and [`super::Ukf`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModelSettings<T> {
    /// The pendulum's normalised parameters a, b and c = l12 / g. Default: the MODEL.md
    /// rig ([`PendulumParams::default`]).
    pub params: PendulumParams<T>,
    /// Gravity g [m/s^2]. Default 9.80665.
    pub gravity: T,
    /// Sensor noise figures (measurement noise). Default: [`SensorNoise::default`].
    pub sensors: SensorNoise<T>,
    /// Process noise densities. Default [`ProcessNoise::derive`] with the default
    /// [`Environment`].
    pub process: ProcessNoise<T>,
    /// Use the accelerometer as a further measurement. Default false: the pendulum and
    /// the gyro alone. On a simulated scooter ride (20 s, seed 4, l12 = 0.2 m) it changed
    /// the RMS error from 0.049 to 0.050 deg: the accelerometer reads the vibration
    /// unfiltered, and what it knows of gravity the pendulum already tells.
    pub use_accel: bool,
    /// Distance of the accelerometer from the rotation axis P1 along the body's up-axis
    /// \[m\]. Default `c g` = l12 (mounted at the pendulum pivot).
    pub accel_distance: T,
    /// Standard deviation of the vibration the accelerometer reads, per axis [m/s^2],
    /// added to its white noise. Default [`Environment::vibration_rms`], 3 m/s^2.
    pub accel_vibration: T,
    /// RMS of the angular vibration rate the gyro reads and the model does not follow
    /// [rad/s]. Only the gyro's innovation gate uses it, as a floor under the innovation
    /// variance (the gyro's own noise alone would make the ride's vibration look like
    /// outliers). Default [`Environment::angular_vibration_rms`], 0.178 rad/s.
    pub gyro_vibration: T,
    /// Standard deviation \[rad\] of the pendulum's jitter from the vibration above its
    /// band, added to the encoder's variance (as the spatial filter's
    /// `spatial::ekf::Settings::encoder_jitter`): the process model forces the pendulum
    /// with white noise of the vibration's density near its natural frequency, but an
    /// engine's tone far above it still moves the pendulum by a few hundredths of a degree,
    /// which a fine encoder reads and the filter, trusting it, takes for tilt. Measured on
    /// the zoo of unseen rigs (ride 11: 16-bit encoder, 26 Hz engine at 2.4 m/s^2, sensor figures
    /// and process noise as self-tuned): 0 -> 0.03 deg took the EKF from 0.0131 to
    /// 0.0045 deg RMS. Default 0: the default 12-bit encoder's rounding (0.025 deg RMS)
    /// already stands for it, and `pendtilt tune` measures it from the encoder's spectrum.
    pub encoder_jitter: T,
    /// Longest single integration step \[s\]; longer sample intervals are split.
    /// Default 5 ms (w_n dt = 0.07 for the default pendulum).
    pub max_step: T,
    /// Longest gap \[s\] bridged by prediction, between rows or between encoder readings
    /// (rows whose phi is missing) while the gyro is missing too; after a longer one the
    /// filter restarts on the next reading, keeping its gyro bias (an encoder gap with the
    /// gyro present is bridged whatever its length). Default 50 ms: on the scooter ride, bridging a gap of every sensor left
    /// 0.5 deg (50 ms), 0.9 deg (100 ms) and 181 deg (900 ms) of error 3 s later, because
    /// the prediction extrapolates the last estimated tilt acceleration, vibration
    /// included; restarting left 0.07-0.11 deg for gaps from 50 to 900 ms.
    pub max_gap: T,
    /// Initial standard deviation of theta around the first phi \[rad\]. Default 2 deg
    /// (the pendulum is assumed at rest on the first sample, MODEL.md section 6).
    pub initial_angle: T,
    /// Innovation gate: a measurement (the encoder, the gyro, an accelerometer axis) whose
    /// normalised innovation squared `y^2 / s` is above this is skipped and the sample
    /// flagged [`crate::Flags::MEASUREMENT_SKIPPED`] (the gyro's `s` gets the floor
    /// [`Self::gyro_vibration`] squared). Default 50: for a consistent filter `y^2 / s` is
    /// chi-square with one degree of freedom, whose quantile for a false-alarm
    /// probability of 1e-6 per measurement is 23.9; on the simulated scooter ride the
    /// encoder's `y^2 / s` averages 2.2 instead of 1 (the vibration that forces the
    /// pendulum is not white), so the quantile is scaled by 2.2 (52.6) and rounded down.
    /// Measured on four 60 s scooter rides (seeds 1-4): 0 samples skipped at 50 (and at
    /// 36); 4 to 152 at 25. An encoder step of 0.01 rad (0.57 deg) on that ride was
    /// still rejected. Infinity turns the gate off. See
    /// [`Self::reacquire_after`] for a change that is genuine.
    pub innovation_gate: T,
    /// Consecutive rejections of one measurement after which the filter re-acquires it:
    /// the covariance is inflated by the size of the innovation (see
    /// [`super::ModelBased`]) and the measurement is applied without the gate, so that a
    /// genuine step (the pendulum knocked, the encoder re-zeroed, a gyro offset) is
    /// followed instead of locking the filter out. Default 200 samples, 0.2 s at 1 kHz:
    /// longer than a glitch worth riding through (a 100 ms encoder fault is ignored
    /// entirely), short next to the time a body tilt takes. Scale it with the sample
    /// rate. Values below 1 count as 1.
    pub reacquire_after: u32,
    /// The pendulum's forcing ([`ProcessNoise::pendulum`]) adapted online to the
    /// encoder's innovations, and the encoder's variance floored by its measured noise
    /// (see [`super::ModelBased`]): one set of defaults for a standing scooter, a ride, a
    /// ship and a hand-held device. Default on, [`Adaptation::planar`]
    /// (docs/adaptation.md); `pendtilt tune` turns it off, its figures being the log's.
    pub adaptation: Adaptation<T>,
}

impl<T: Real> Default for ModelSettings<T> {
    fn default() -> Self {
        Self::from_params(PendulumParams::default(), T::lit(STANDARD_GRAVITY))
    }
}

impl<T: Real> ModelSettings<T> {
    /// Defaults for a pendulum with normalised parameters `params` under gravity `gravity`,
    /// default sensors and environment.
    pub fn from_params(params: PendulumParams<T>, gravity: T) -> Self {
        Self::derived(
            params,
            gravity,
            SensorNoise::default(),
            &Environment::default(),
        )
    }

    /// Defaults for a rig given by its physical parameters.
    pub fn from_physical(p: &PhysicalParams<T>) -> Self {
        Self::from_params(p.normalised(), p.gravity)
    }

    /// Settings derived from the rig, the sensors and the environment.
    pub fn derived(
        params: PendulumParams<T>,
        gravity: T,
        sensors: SensorNoise<T>,
        env: &Environment<T>,
    ) -> Self {
        Self {
            process: ProcessNoise::derive(&params, gravity, &sensors, env),
            params,
            gravity,
            sensors,
            use_accel: false,
            accel_distance: params.c * gravity,
            accel_vibration: env.vibration_rms,
            gyro_vibration: env.angular_vibration_rms,
            encoder_jitter: T::zero(),
            max_step: T::lit(0.005),
            max_gap: T::lit(0.05),
            initial_angle: T::lit(2.0 * core::f64::consts::PI / 180.0),
            innovation_gate: T::lit(50.0),
            reacquire_after: 200,
            adaptation: Adaptation::planar(),
        }
    }

    /// Variance of one encoder reading as the filter takes it \[rad^2\]: the sensor's
    /// ([`SensorNoise::encoder_variance`]) plus the jitter's square
    /// ([`Self::encoder_jitter`]).
    pub fn encoder_variance(&self) -> T {
        self.sensors.encoder_variance() + self.encoder_jitter * self.encoder_jitter
    }

    /// These settings with the adaptation off: fixed noise figures, as before it.
    pub fn fixed(self) -> Self {
        Self {
            adaptation: Adaptation {
                enabled: false,
                ..self.adaptation
            },
            ..self
        }
    }

    /// The process model these settings describe.
    pub fn process_model(&self) -> PendulumProcess<T> {
        PendulumProcess {
            params: self.params,
            noise: self.process,
        }
    }
}

impl<T: Real> SensorNoise<T> {
    /// The same figures in another scalar type.
    pub fn cast<U: Real>(&self) -> SensorNoise<U> {
        let c = |x: T| U::lit(x.to_f64());
        SensorNoise {
            encoder_bits: self.encoder_bits,
            encoder_noise: c(self.encoder_noise),
            gyro_density: c(self.gyro_density),
            gyro_bias_walk: c(self.gyro_bias_walk),
            gyro_bias: c(self.gyro_bias),
            accel_density: c(self.accel_density),
        }
    }
}

impl<T: Real> Environment<T> {
    /// The same figures in another scalar type.
    pub fn cast<U: Real>(&self) -> Environment<U> {
        let c = |x: T| U::lit(x.to_f64());
        Environment {
            tilt_rms: c(self.tilt_rms),
            tilt_bandwidth_hz: c(self.tilt_bandwidth_hz),
            vibration_density: c(self.vibration_density),
            vibration_rms: c(self.vibration_rms),
            angular_vibration_rms: c(self.angular_vibration_rms),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encoder_variance_is_quantisation_over_twelve() {
        let s = SensorNoise::<f64>::default();
        let q = core::f64::consts::TAU / 4096.0;
        assert!((s.encoder_variance() - q * q / 12.0).abs() < 1e-18);
        let s0 = SensorNoise::<f64> {
            encoder_bits: 0,
            encoder_noise: 0.01,
            ..s
        };
        assert!((s0.encoder_variance() - 1e-4).abs() < 1e-18);
    }

    #[test]
    fn derived_process_noise_by_hand() {
        let p = PendulumParams::<f64> {
            a: 0.04,
            b: 0.005,
            c: 0.0,
        };
        let env = Environment::<f64> {
            tilt_rms: 0.1,
            tilt_bandwidth_hz: 1.0,
            vibration_density: 0.02,
            vibration_rms: 3.0,
            angular_vibration_rms: 0.0,
        };
        let q = ProcessNoise::derive(&p, 10.0, &SensorNoise::default(), &env);
        let w = core::f64::consts::TAU;
        assert!((q.jerk - 0.01 * w.powi(6)).abs() < 1e-9);
        assert!((q.pendulum - 4e-4 / (0.05 * 0.05)).abs() < 1e-12);
        // The default environment: 301 rad^2/s^5 for 7 deg up to 0.8 Hz.
        let d = ProcessNoise::derive(&p, 10.0, &SensorNoise::default(), &Environment::default());
        assert!((d.jerk - 300.94).abs() < 0.01, "{}", d.jerk);
        assert!((q.bias - 1e-8).abs() < 1e-20);
    }
}
