//! `pendulum3d`: roll = phi_x, pitch = phi_y, the raw encoder angles. Exact for a pendulum
//! hanging still (MODEL.md 7.2: `phi_x = roll`, `phi_y = pitch` for any yaw); in motion it
//! lags and overshoots on both axes, as the planar pendulum does.
use super::{Attitude, SpatialSample};
use crate::estimators::encoder::{is_reading, wrap_angle};
use crate::{Estimator, Flags, Real, StepClock};

/// Settings of [`Pendulum`]: none; kept for the common estimator shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PendulumSettings {}

/// The raw encoder angles as roll and pitch, holding the last attitude when an encoder
/// reading is missing.
#[derive(Debug, Clone)]
pub struct Pendulum<T: Real> {
    last: Attitude<T>,
    clock: StepClock<T>,
}

impl<T: Real> Pendulum<T> {
    /// A new estimator.
    pub fn new(_settings: PendulumSettings) -> Self {
        Self {
            last: Attitude::unknown(),
            clock: StepClock::new(),
        }
    }

    fn hold(&self, flags: Flags) -> Attitude<T> {
        Attitude { flags, ..self.last }
    }
}

impl<T: Real> Estimator for Pendulum<T> {
    type Input = SpatialSample<T>;
    type Output = Attitude<T>;

    #[inline]
    fn update(&mut self, s: &SpatialSample<T>) -> Attitude<T> {
        if let Err(flags) = self.clock.offer(s.dt) {
            return self.hold(flags);
        }
        if !(is_reading(s.phi[0]) && is_reading(s.phi[1])) {
            return self.hold(Flags::SAMPLE_MISSING);
        }
        self.clock.accept();
        self.last = Attitude {
            roll: wrap_angle(s.phi[0]),
            pitch: wrap_angle(s.phi[1]),
            flags: Flags::empty(),
        };
        self.last
    }

    fn reset(&mut self) {
        *self = Self::new(PendulumSettings {});
    }
}
