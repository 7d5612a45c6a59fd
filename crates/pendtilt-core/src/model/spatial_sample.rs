//! One row of the 3-D log (MODEL.md 7.6) as the estimators read it.
use super::Sensor;
use crate::Real;

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
    /// A sample `dt` seconds after the previous one with the encoders, the gyro and the
    /// accelerometer read, and every other sensor (the speed) missing.
    pub fn new(dt: T, phi: [T; 2], gyro: [T; 3], accel: [T; 3]) -> Self {
        Self {
            phi,
            gyro,
            accel,
            ..Self::after(dt)
        }
    }

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

    /// The readings of `sensor`, one per axis (MODEL.md 7.6's column order).
    pub fn reading(&self, sensor: Sensor) -> &[T] {
        match sensor {
            Sensor::Encoder => &self.phi,
            Sensor::Gyro => &self.gyro,
            Sensor::Accel => &self.accel,
        }
    }

    /// The readings of `sensor`, to fill or to mark missing.
    pub fn reading_mut(&mut self, sensor: Sensor) -> &mut [T] {
        match sensor {
            Sensor::Encoder => &mut self.phi,
            Sensor::Gyro => &mut self.gyro,
            Sensor::Accel => &mut self.accel,
        }
    }

    /// True when every axis of `sensor` is finite.
    pub fn complete(&self, sensor: Sensor) -> bool {
        self.reading(sensor).iter().all(|v| v.is_finite())
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
