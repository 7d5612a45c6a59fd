//! The raw pendulum: theta = phi. At rest the pendulum hangs vertical, so its angle to the
//! body is the tilt; in motion it lags and overshoots (the paper's Figs 7-8).
use super::encoder::{is_reading, wrap_angle, Unwrapper};
use crate::{Estimate, Estimator, Flags, Real, Sample, StepClock};

/// Settings of [`Pendulum`]: none yet; kept for the common estimator shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PendulumSettings {}

/// The raw pendulum reading as a tilt estimate, with encoder unwrapping and hold-on-missing.
#[derive(Debug, Clone)]
pub struct Pendulum<T: Real> {
    last: T,
    encoder: Unwrapper<T>,
    clock: StepClock<T>,
}

impl<T: Real> Pendulum<T> {
    /// A new estimator.
    pub fn new(_settings: PendulumSettings) -> Self {
        Self {
            last: T::nan(),
            encoder: Unwrapper::new(),
            clock: StepClock::new(),
        }
    }
}

impl<T: Real> Estimator for Pendulum<T> {
    type Input = Sample<T>;
    type Output = Estimate<T>;

    #[inline]
    fn update(&mut self, s: &Sample<T>) -> Estimate<T> {
        if let Err(flags) = self.clock.offer(s.dt) {
            return Estimate {
                theta: self.last,
                flags,
            };
        }
        if !is_reading(s.phi) {
            return Estimate {
                theta: self.last,
                flags: Flags::SAMPLE_MISSING,
            };
        }
        self.clock.accept();
        let (phi, wrapped) = self.encoder.unwrap(s.phi);
        let flags = if wrapped {
            Flags::ENCODER_WRAPPED
        } else {
            Flags::empty()
        };
        let theta = wrap_angle(phi);
        self.last = theta;
        Estimate { theta, flags }
    }

    fn reset(&mut self) {
        self.last = T::nan();
        self.encoder = Unwrapper::new();
        self.clock.restart();
    }
}
