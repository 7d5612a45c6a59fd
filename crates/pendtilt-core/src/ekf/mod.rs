//! Model-based estimators (the paper's future work): an extended and an unscented Kalman
//! filter that carry the pendulum's own dynamics, so the pendulum angle need not be
//! differentiated twice the way Algorithms 1-3 do.
//!
//! One concern per module:
//! - [`model`]: the process model, MODEL.md section 2 with the pivot offset l12; state
//!   `[theta, theta', theta'', phi, phi', gyro bias]`, theta'' a random walk, analytic
//!   Jacobian, exact process-noise integrals.
//! - [`measurement`]: the encoder (phi), the gyro (theta' + bias) and the optional
//!   accelerometer (specific force at a point of the body) with its own noise.
//! - [`update`]: the scalar measurement update in Joseph form (P stays symmetric positive
//!   definite).
//! - [`filter`]: the [`StateFilter`] interface; [`extended`] ([`ExtendedKalman`]) and [`unscented`]
//!   ([`UnscentedKalman`]) implement it on nalgebra fixed-size matrices.
//! - [`settings`]: settings and their defaults derived from the rig parameters and the
//!   sensors' noise figures.
//! - [`estimator`]: the streaming [`crate::Estimator`] around either filter:
//!   [`Ekf`] (column `ekf`) and [`Ukf`] (column `ukf`).
//!
//! Everything is `no_std`, allocation-free and generic over `f32`/`f64`; `f64` is
//! recommended for the filters (the covariance spans many orders of magnitude).
pub mod estimator;
pub mod extended;
pub mod filter;
pub mod measurement;
pub mod model;
pub mod settings;
pub mod unscented;
pub mod update;

pub use estimator::ModelBased;
pub use extended::ExtendedKalman;
pub use filter::StateFilter;
pub use model::{PendulumProcess, ProcessNoise};
pub use settings::{Environment, ModelSettings, SensorNoise};
pub use unscented::UnscentedKalman;

/// The extended Kalman filter estimator (column `ekf`).
pub type Ekf<T> = ModelBased<T, ExtendedKalman<T>>;
/// The unscented Kalman filter estimator (column `ukf`).
pub type Ukf<T> = ModelBased<T, UnscentedKalman<T>>;
