//! The estimators beyond the paper, ready to run beside it: the model-based filters of
//! [`pendtilt_core::ekf`], Algorithm 2 with the pivot-offset term, and the peers users
//! would pick instead of a pendulum (Madgwick and Mahony from the `ahrs` crate, a
//! complementary filter), each built by name from the rig and the sensors' noise figures
//! through the bank's registry (`bank::REGISTRY`, the one table of names; `bank::build`
//! builds one alone).
//!
//! | column | estimator | inputs |
//! |---|---|---|
//! | `ekf` | [`pendtilt_core::ekf::Ekf`], pendulum dynamics with l12 | phi, gyro |
//! | `ukf` | [`pendtilt_core::ekf::Ukf`], the same model, unscented | phi, gyro |
//! | `alg2_offset` | [`pendtilt_core::estimators::alg2::Alg2`] with `pivot_offset` | phi, gyro |
//! | `madgwick` | [`ahrs_planar::madgwick`], beta = [`ahrs_planar::MADGWICK_BETA`] | gyro, ax, ay |
//! | `mahony` | [`ahrs_planar::mahony`], kp, ki = [`ahrs_planar::MAHONY_GAINS`] | gyro, ax, ay |
//! | `complementary` | [`pendtilt_core::estimators::complementary::Complementary`], tau = 0.75 s, 5 Hz accelerometer prefilter | gyro, ax, ay |
//!
//! The peers' gains are the best ones a small search found on the simulated scooter ride
//! ([`tune::search_peer_gains`]); [`tune::fit_process_noise`] fits the EKF's process noise
//! on any log with a true angle.
pub mod ahrs_planar;
pub mod fusion;
pub mod spatial;
pub mod steady;
pub mod tune;

use pendtilt_core::ekf::{Environment, ModelSettings, SensorNoise};
use pendtilt_core::estimators::complementary::ComplementarySettings;
use pendtilt_core::PendulumParams;

/// The columns this module provides, in report order.
pub const COLUMNS: [&str; 6] = [
    "ekf",
    "ukf",
    "alg2_offset",
    "madgwick",
    "mahony",
    "complementary",
];

/// Everything the estimators of this module are built from besides the rig.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PeerSettings {
    /// The sensors' noise figures (EKF/UKF measurement noise).
    pub sensors: SensorNoise<f64>,
    /// The environment the EKF/UKF process noise is derived from.
    pub environment: Environment<f64>,
    /// Madgwick's beta [rad/s]. Default [`ahrs_planar::MADGWICK_BETA`].
    pub madgwick_beta: f64,
    /// Mahony's kp [1/s] and ki [1/s^2]. Default [`ahrs_planar::MAHONY_GAINS`].
    pub mahony: [f64; 2],
    /// The complementary filter. Default [`ComplementarySettings::default`].
    pub complementary: ComplementarySettings<f64>,
}

impl Default for PeerSettings {
    fn default() -> Self {
        Self {
            sensors: SensorNoise::default(),
            environment: Environment::default(),
            madgwick_beta: ahrs_planar::MADGWICK_BETA,
            mahony: ahrs_planar::MAHONY_GAINS,
            complementary: ComplementarySettings::default(),
        }
    }
}

/// EKF/UKF settings for normalised parameters `params`, gravity `gravity` and `peer`.
pub fn model_settings(
    params: &PendulumParams<f64>,
    gravity: f64,
    peer: &PeerSettings,
) -> ModelSettings<f64> {
    ModelSettings::derived(*params, gravity, peer.sensors, &peer.environment)
}
