//! The raw pendulum: theta = phi. At rest the pendulum hangs vertical, so its angle to the
//! body is the tilt; in motion it lags and overshoots (the paper's Figs 7-8).
use crate::{Estimate, Estimator, Flags, Real, Sample};

/// Largest encoder reading taken as an angle \[rad\] (about 1600 turns): beyond it (or not
/// finite) the sample is missing. A reading near the type's largest value would otherwise
/// break the wrap-around unwrapping (found by fuzzing in f32 with 3e38).
pub const PHI_LIMIT: f64 = 1e4;

/// Settings of [`Pendulum`]: none yet; kept for the common estimator shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PendulumSettings {}

/// The raw pendulum reading as a tilt estimate, with encoder unwrapping and hold-on-missing.
#[derive(Debug, Clone)]
pub struct Pendulum<T: Real> {
    last: T,
    unwrap: T,
    prev: Option<T>,
    t_prev: Option<T>,
}

impl<T: Real> Pendulum<T> {
    /// A new estimator.
    pub fn new(_settings: PendulumSettings) -> Self {
        Self {
            last: T::nan(),
            unwrap: T::zero(),
            prev: None,
            t_prev: None,
        }
    }
}

impl<T: Real> Estimator<T> for Pendulum<T> {
    #[inline]
    fn update(&mut self, s: &Sample<T>) -> Estimate<T> {
        if !s.t.is_finite()
            || self
                .t_prev
                .is_some_and(|tp| !crate::real::is_positive(s.t - tp))
        {
            return Estimate {
                theta: self.last,
                flags: Flags::BAD_TIME_STEP,
            };
        }
        if !s.phi.is_finite() || s.phi.abs() >= T::lit(PHI_LIMIT) {
            return Estimate {
                theta: self.last,
                flags: Flags::SAMPLE_MISSING,
            };
        }
        self.t_prev = Some(s.t);
        let mut flags = Flags::empty();
        let mut phi = s.phi + self.unwrap;
        if let Some(p) = self.prev {
            let jump = phi - p;
            if jump.abs() > T::pi() {
                let turns = (jump / T::two_pi()).round() * T::two_pi();
                self.unwrap -= turns;
                phi -= turns;
                flags |= Flags::ENCODER_WRAPPED;
            }
        }
        self.prev = Some(phi);
        let theta = if phi.abs() > T::pi() {
            phi.sin().atan2(phi.cos())
        } else {
            phi
        };
        self.last = theta;
        Estimate { theta, flags }
    }

    fn reset(&mut self) {
        *self = Self::new(PendulumSettings {});
    }
}
