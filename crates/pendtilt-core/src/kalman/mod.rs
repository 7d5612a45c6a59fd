//! The paper's angle + gyro-bias Kalman filter (Eqs 2-11) as models on the filter engine
//! ([`crate::engine`]):
//!
//! - `process`: `process::AngleBias`, the paper's angle + gyro-bias model (Eqs 9, 11).
//! - `measurement`: `measurement::AngleMeasurement`, any sensor that reports the tilt
//!   angle (H = [1, 0]).
//! - [`tilt`]: the paper's filter assembled from those pieces on the engine's Kalman
//!   filter (MODEL.md section 4), with the conventions of the widely used Arduino filter,
//!   taking any number of angle measurements per sample (`kf_accel`, `kf_alg2`,
//!   `kf_fused`, ...).
pub(crate) mod measurement;
pub(crate) mod process;
pub mod tilt;

pub use tilt::{KalmanOn, KalmanSettings, TiltKalman};

/// The engine's Kalman filter over `[theta, bias]` (linear models: the EKF is the
/// ordinary Kalman filter, Eqs 2-8).
pub type KalmanFilter<T> = crate::engine::ExtendedKalman<T, nalgebra::Vector2<T>, 2>;

#[cfg(test)]
mod reference_tests;
