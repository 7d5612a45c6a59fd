//! The streaming interface: one [`Sample`] in, one [`Estimate`] out.

use crate::{Flags, Real};

/// One row of sensor data, SI units (MODEL.md section 5). A sensor that is absent or
/// failed on this sample is `NaN`; each estimator reads only the fields it needs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample<T> {
    /// Time [s]; strictly increasing from sample to sample.
    pub t: T,
    /// Encoder: pendulum angle relative to the body, clockwise positive [rad].
    pub phi: T,
    /// Gyro: body rate about the tilt axis, CCW positive [rad/s].
    pub gyro: T,
    /// Accelerometer specific force along the body x axis [m/s^2].
    pub ax: T,
    /// Accelerometer specific force along the body y (up) axis [m/s^2].
    pub ay: T,
}

impl<T: Real> Sample<T> {
    /// A sample at time `t` with every sensor missing; fill the fields you have.
    pub fn at(t: T) -> Self {
        Self {
            t,
            phi: T::nan(),
            gyro: T::nan(),
            ax: T::nan(),
            ay: T::nan(),
        }
    }
}

/// One tilt estimate with its diagnostics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate<T> {
    /// Estimated body tilt theta [rad], CCW positive. `NaN` only before the estimator has
    /// seen any usable input (then [`Flags::SAMPLE_MISSING`] is set).
    pub theta: T,
    /// What happened on this sample.
    pub flags: Flags,
}

/// The shape every estimator shares: feed samples in time order, get one estimate each.
pub trait Estimator<T: Real> {
    /// Processes one sample and returns the estimate for its time.
    fn update(&mut self, sample: &Sample<T>) -> Estimate<T>;
    /// Forgets all history, as if newly constructed with the same settings.
    fn reset(&mut self);
}
