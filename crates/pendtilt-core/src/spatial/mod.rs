//! The spatial model (MODEL.md section 7): roll and pitch of a body from a two-axis
//! pendulum on a Cardan joint, a 3-axis gyro and a 3-axis accelerometer.
//!
//! The same streaming shape as the planar estimators ([`crate::Estimator`]), with its own
//! input and output: a [`SpatialSample`] in, an [`Attitude`] out
//! ([`SpatialEstimator`]). Conventions (MODEL.md 7.1): body axes FLU, attitude
//! `R = Rz(yaw) Ry(pitch) Rx(roll)` (world <- body), positive roll lowers the right side,
//! positive pitch lowers the nose; the encoders read `phi_x = -a`, `phi_y = -b` of the
//! Cardan joint, so a pendulum hanging still reads `phi_x = roll`, `phi_y = pitch`.
//!
//! - [`sample`]: the input and output types;
//! - [`attitude`]: the world's up direction in body axes, roll and pitch from it, the
//!   inclination error (MODEL.md 7.9);
//! - [`cardan`]: the pendulum's normalised parameters and its equations of motion
//!   (MODEL.md 7.3), for the model-based filter;
//! - [`mounting`]: where the sensors sit, and the lever arm between body points;
//! - [`travel`]: a travelling vehicle's known acceleration from its speed and the gyro;
//! - [`pendulum`]: `pendulum3d`, the raw encoder angles;
//! - [`accel`]: `accel3d`, roll and pitch from the accelerometer;
//! - [`inv`]: `inv3d`, Algorithm 2 in three dimensions (the joint equations solved for
//!   the tilt);
//! - [`imu`]: an inclination reference from the gyro and accelerometer alone (after
//!   VQF), ekf3d's guard;
//! - [`ekf`]: `ekf3d`/`ukf3d`, the quaternion filter on the engine.
pub mod accel;
pub mod attitude;
pub use crate::model::cardan;
pub mod ekf;
pub mod imu;
pub mod inv;
pub use crate::model::mounting;
pub mod pendulum;
pub mod sample;
pub mod travel;

pub use mounting::Mounting;
pub use sample::{Attitude, SpatialEstimator, SpatialSample};
