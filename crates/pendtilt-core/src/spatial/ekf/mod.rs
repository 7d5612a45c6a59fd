//! `ekf3d` and `ukf3d`: a multiplicative (error-state) quaternion filter whose state
//! carries the attitude, the gyro bias and the Cardan pendulum's two angles and rates.
//! The gyro (and, when the log has it, the speed) drives the process, the encoders (and,
//! optionally, the accelerometer) are measurements; the encoders are never differentiated
//! (MODEL.md section 7).
//!
//! - [`state`]: the state, its 10-dimensional error and `retract` (composition for the
//!   attitude);
//! - [`process`]: the gyro and the pendulum's equations of motion as a process model of
//!   the engine;
//! - [`measurement`]: the encoders and the accelerometer as measurement models;
//! - [`slip`]: wheel-slip detection on the speed (the speed against the accelerometer);
//! - [`settings`]: settings and how the noise follows from the sensors;
//! - [`estimator`]: the streaming estimator around the engine's EKF or UKF.
pub mod estimator;
pub mod measurement;
pub mod process;
pub mod settings;
pub mod slip;
pub mod state;

pub use estimator::ModelBased;
pub use settings::{Adaptation, Settings, SpeedSettings};

/// The engine's EKF over the spatial state.
pub type ExtendedKalman<T> = crate::engine::ExtendedKalman<T, state::State<T>, { state::N }>;
/// The engine's UKF over the spatial state.
pub type UnscentedKalman<T> = crate::engine::UnscentedKalman<T, state::State<T>, { state::N }>;
/// `ekf3d`: the spatial model-based estimator over the EKF.
pub type Ekf<T> = ModelBased<T, ExtendedKalman<T>>;
/// `ukf3d`: the same over the UKF.
pub type Ukf<T> = ModelBased<T, UnscentedKalman<T>>;
