//! Hold-and-flag input gating for the gyro + accelerometer estimators (the complementary
//! filter here, the planar `ahrs` wrappers of the std crate's `peers`), which shared the
//! same preamble: a sample whose time is not finite or does not advance is refused
//! ([`Flags::BAD_TIME_STEP`], the caller holds its output); a missing gyro reading is
//! replaced by the last good one ([`Flags::SAMPLE_MISSING`]); the time step runs from the
//! last accepted sample.
use crate::{Flags, Real, Sample, StepClock};

/// What [`InputHold::begin`] makes of a sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Step<T> {
    /// The time is not finite or not after the last accepted sample: do nothing with it,
    /// return the previous estimate flagged [`Flags::BAD_TIME_STEP`].
    BadTime,
    /// No sample accepted yet: start on this one if its other inputs allow, and then call
    /// [`InputHold::started`].
    First {
        /// The gyro reading, or the last good one.
        gyro: T,
        /// [`Flags::SAMPLE_MISSING`] if the gyro was held.
        flags: Flags,
    },
    /// A later sample, already accepted.
    Next {
        /// Time since the last accepted sample \[s\], positive.
        dt: T,
        /// The gyro reading, or the last good one.
        gyro: T,
        /// [`Flags::SAMPLE_MISSING`] if the gyro was held.
        flags: Flags,
    },
}

/// The time and gyro state behind [`Step`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InputHold<T> {
    clock: StepClock<T>,
    last_gyro: T,
}

impl<T: Real> Default for InputHold<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Real> InputHold<T> {
    /// Nothing accepted yet; a gyro missing before any good reading is taken as zero.
    pub fn new() -> Self {
        Self {
            clock: StepClock::new(),
            last_gyro: T::zero(),
        }
    }

    /// Gates sample `s` (see [`Step`]).
    #[inline]
    pub fn begin(&mut self, s: &Sample<T>) -> Step<T> {
        let Ok(step) = self.clock.offer(s.dt) else {
            return Step::BadTime;
        };
        let mut flags = Flags::empty();
        let gyro = if s.gyro.is_finite() {
            self.last_gyro = s.gyro;
            s.gyro
        } else {
            flags |= Flags::SAMPLE_MISSING;
            self.last_gyro
        };
        match step {
            None => Step::First { gyro, flags },
            Some(dt) => {
                self.clock.accept();
                Step::Next { dt, gyro, flags }
            }
        }
    }

    /// The estimator started on the sample just gated: later steps run from it.
    pub fn started(&mut self) {
        self.clock.accept();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn s(dt: f64, gyro: f64) -> Sample<f64> {
        Sample {
            dt,
            phi: f64::NAN,
            gyro,
            ax: 0.0,
            ay: 9.8,
        }
    }

    #[test]
    fn first_then_steps_with_the_gyro_held_and_bad_times_refused() {
        let mut h = InputHold::<f64>::new();
        // Not started: the time is not taken, so the next sample is First again.
        assert_eq!(
            h.begin(&s(0.0, f64::NAN)),
            Step::First {
                gyro: 0.0,
                flags: Flags::SAMPLE_MISSING
            }
        );
        assert_eq!(
            h.begin(&s(0.5, 0.3)),
            Step::First {
                gyro: 0.3,
                flags: Flags::empty()
            }
        );
        h.started();
        assert_eq!(h.begin(&s(0.0, 0.0)), Step::BadTime);
        assert_eq!(h.begin(&s(-0.1, 0.0)), Step::BadTime);
        assert_eq!(h.begin(&s(f64::NAN, 0.0)), Step::BadTime);
        assert_eq!(
            h.begin(&s(0.25, f64::NAN)),
            Step::Next {
                dt: 0.25,
                gyro: 0.3,
                flags: Flags::SAMPLE_MISSING
            }
        );
        assert_eq!(
            h.begin(&s(0.25, -0.1)),
            Step::Next {
                dt: 0.25,
                gyro: -0.1,
                flags: Flags::empty()
            }
        );
    }
}
