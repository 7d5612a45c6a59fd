//! Kalman filtering, split the way a new sensor or a 3-D state needs it:
//!
//! - [`process`]: process models (how the state moves between samples, driven by an input):
//!   [`process::AngleBias`], the paper's angle + gyro-bias model (Eqs 9, 11).
//! - [`measurement`]: measurement models (what a sensor sees of the state):
//!   [`measurement::AngleMeasurement`], any sensor that reports the tilt angle (H = [1, 0]).
//! - [`filter`]: the linear Kalman filter itself (Eqs 2-8), generic in state and measurement
//!   size, knowing nothing of tilt.
//! - [`tilt`]: the paper's filter assembled from those pieces (MODEL.md section 4), with
//!   the conventions of the widely used Arduino filter, taking any number of angle
//!   measurements per sample (`kf_accel`, `kf_alg2`, `kf_fused`, ...).
pub mod filter;
pub mod measurement;
pub mod process;
pub mod tilt;

pub use filter::KalmanFilter;
pub use tilt::{KalmanOn, KalmanSettings, TiltKalman};
