//! Model-based estimators (the paper's future work): an extended and an unscented Kalman
//! filter that carry the pendulum's own dynamics, so the pendulum angle need not be
//! differentiated twice the way Algorithms 1-3 do.
//!
//! They are models on the filter engine ([`crate::engine`]), one concern per module:
//! - [`model`]: the process model, MODEL.md section 2 with the pivot offset l12; state
//!   `[theta, theta', theta'', phi, phi', gyro bias]`, theta'' a random walk, analytic
//!   Jacobian with its zero pattern exploited, exact process-noise integrals.
//! - `measurement`: the encoder (phi), the gyro (theta' + bias) and the optional
//!   accelerometer (specific force at a point of the body) with its own noise.
//! - `sensor`: what the estimator does around each measurement (where its reading is in
//!   a sample, its gate, how it is re-acquired), so that the estimator applies them all
//!   by one loop: a new sensor is a new measurement type and one line there.
//! - [`settings`]: settings and their defaults derived from the rig parameters and the
//!   sensors' noise figures.
//! - [`estimator`]: the streaming [`crate::Estimator`] around either filter of the
//!   engine: [`Ekf`] (column `ekf`) and [`Ukf`] (column `ukf`), with the innovation gate
//!   that skips outliers and re-acquires after a run of them
//!   ([`ModelSettings::innovation_gate`], [`ModelSettings::reacquire_after`]; measured
//!   by `cargo test --release -p pendtilt --test ekf_gate -- --nocapture`: a 100 ms,
//!   2.5 rad encoder glitch leaves the EKF within 0.0088 deg of the clean run from 50 ms
//!   after it, 16.9 deg without the gate; a 0.2 rad encoder re-zero is followed to within
//!   0.15 deg from 0.5 s on; no sample of four clean 60 s rides is skipped).
//!
//! Everything is `no_std`, allocation-free and generic over `f32`/`f64`; `f64` is
//! recommended for the filters (the covariance spans many orders of magnitude).
//!
//! ## Measured
//! Simulated scooter ride (`Scenario::named("scooter")`: engine harmonics, broadband and
//! angular vibration; l12 = 0.2 m; 60 s at 1 kHz, seed 1; error after the first 2 s;
//! lag by cross-correlation), default settings everywhere, the peers at the gains their
//! search found (`pendtilt::peers::tune::search_peer_gains`):
//!
//! | estimator | RMS \[deg\] | bias \[deg\] | lag \[ms\] |
//! |---|---|---|---|
//! | alg1 | 2.371 | 0.028 | 5.5 |
//! | alg2 | 2.690 | 0.027 | 10.0 |
//! | alg3 (gains = alg2) | 2.690 | 0.027 | 10.0 |
//! | kf_alg2 | 2.699 | 0.025 | 18.2 |
//! | alg2_offset | 1.691 | 0.032 | -15.7 |
//! | **ekf** | **0.042** | 0.030 | 0.1 |
//! | ukf | 0.042 | 0.030 | 0.1 |
//! | madgwick (beta 1.18) | 1.162 | 0.675 | 5.7 |
//! | mahony (kp 0.45, ki 0) | 3.035 | -1.858 | -17.3 |
//! | complementary (tau 0.75 s) | 0.806 | 0.522 | 29.0 |
//!
//! Command: `cargo test --release -p pendtilt --test ekf_scooter -- --nocapture`
//! (the test asserts the targets: EKF at most half the best of alg1-3, below
//! kf_alg2, at most a fifth of the best peer, lag no worse than alg2's). Per-sample cost:
//! `cargo bench -p pendtilt --bench peers` (EKF beside Madgwick from `ahrs`).
pub mod estimator;
pub(crate) mod measurement;
pub mod model;
pub(crate) mod sensor;
pub mod settings;

pub use estimator::ModelBased;
pub use model::{PendulumProcess, ProcessNoise};
pub use settings::{Environment, ModelSettings, SensorNoise};

/// The engine's EKF over the pendulum state.
pub type ExtendedKalman<T> = crate::engine::ExtendedKalman<T, model::State<T>, { model::N }>;
/// The engine's UKF over the pendulum state.
pub type UnscentedKalman<T> = crate::engine::UnscentedKalman<T, model::State<T>, { model::N }>;

/// The extended Kalman filter estimator (column `ekf`).
pub type Ekf<T> = ModelBased<T, ExtendedKalman<T>>;
/// The unscented Kalman filter estimator (column `ukf`).
pub type Ukf<T> = ModelBased<T, UnscentedKalman<T>>;
