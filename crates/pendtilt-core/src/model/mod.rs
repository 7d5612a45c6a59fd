//! The model's types, apart from the estimators that read them: the planar pendulum's
//! parameters ([`PendulumParams`], [`PhysicalParams`]) and sample ([`Sample`]), the Cardan
//! pendulum's ([`cardan`], MODEL.md 7.3), where the sensors sit ([`mounting`]), the 3-D
//! sample ([`SpatialSample`]), the table of sensors a log carries ([`SENSORS`]) and the
//! encoder's range ([`PHI_LIMIT`]). The simulators and
//! the readers build on this module alone; the estimators' modules (`estimators`, `ekf`,
//! `kalman`, `spatial`) build on it too.
pub mod cardan;
pub mod mounting;
mod spatial_sample;

pub use crate::params::{PendulumParams, PhysicalParams};
pub use crate::sample::Sample;
pub use crate::sensor::{Sensor, SensorSpec, SENSORS, SENSOR_COUNT};
pub use mounting::Mounting;
pub use spatial_sample::SpatialSample;

/// Largest encoder reading taken as an angle \[rad\] (about 1600 turns): beyond it (or not
/// finite) the sample is missing. A reading near the type's largest value would otherwise
/// break the wrap-around unwrapping (found by fuzzing in f32 with 3e38).
pub const PHI_LIMIT: f64 = 1e4;
