//! The spatial model's input ([`SpatialSample`]) and output ([`Attitude`]).
use super::attitude::up_from_roll_pitch;
use crate::{Estimator, Flags, Output, Real};

/// One row of spatial sensor data, SI units, body axes (MODEL.md 7.6). A sensor that is
/// absent or failed on this sample is `NaN` (per axis); each estimator reads only the
/// fields it needs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpatialSample<T> {
    /// Time since the previous sample \[s\], from a [`crate::StepGate`] (as
    /// [`crate::Sample::dt`]).
    pub dt: T,
    /// Encoders `[phi_x, phi_y] = [-a, -b]` of the Cardan joint \[rad\] (MODEL.md 7.2).
    pub phi: [T; 2],
    /// Gyro: body rate, body axes [rad/s].
    pub gyro: [T; 3],
    /// Accelerometer: specific force, body axes [m/s^2] (+g on z when level).
    pub accel: [T; 3],
    /// Forward speed along body x [m/s] (a wheel-speed sensor), `NaN` when absent.
    pub speed: T,
}

impl<T: Real> SpatialSample<T> {
    /// A sample `dt` seconds after the previous one with every sensor missing.
    pub fn after(dt: T) -> Self {
        let n = T::nan();
        Self {
            dt,
            phi: [n; 2],
            gyro: [n; 3],
            accel: [n; 3],
            speed: n,
        }
    }

    /// The same readings in another scalar type.
    pub fn cast<U: Real>(&self) -> SpatialSample<U> {
        let c = |x: T| U::lit(x.to_f64());
        SpatialSample {
            dt: c(self.dt),
            phi: self.phi.map(c),
            gyro: self.gyro.map(c),
            accel: self.accel.map(c),
            speed: c(self.speed),
        }
    }
}

/// Roll and pitch of the body \[rad\] (ZYX, MODEL.md 7.1) with the sample's flags.
/// `NaN` only before the estimator has seen a usable input.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Attitude<T> {
    /// Roll \[rad\]: positive lowers the right side.
    pub roll: T,
    /// Pitch \[rad\]: positive lowers the nose.
    pub pitch: T,
    /// What happened on this sample.
    pub flags: Flags,
}

impl<T: Real> Attitude<T> {
    /// Before any usable input: roll and pitch `NaN`, no flags.
    pub fn unknown() -> Self {
        Self {
            roll: T::nan(),
            pitch: T::nan(),
            flags: Flags::empty(),
        }
    }

    /// The world's up direction in body axes, `u = R^T e_z` (MODEL.md 7.1).
    pub fn up(&self) -> [T; 3] {
        up_from_roll_pitch(self.roll, self.pitch)
    }
}

impl<T> Output for Attitude<T> {
    #[inline]
    fn flags(&self) -> Flags {
        self.flags
    }
}

/// An [`Estimator`] of the spatial model: [`SpatialSample`] in, [`Attitude`] out
/// (implemented for every such estimator; usable as `dyn SpatialEstimator<f64>`).
pub trait SpatialEstimator<T>: Estimator<Input = SpatialSample<T>, Output = Attitude<T>> {}

impl<T, E: Estimator<Input = SpatialSample<T>, Output = Attitude<T>> + ?Sized> SpatialEstimator<T>
    for E
{
}
