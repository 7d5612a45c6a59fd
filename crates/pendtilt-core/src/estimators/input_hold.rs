//! Hold-and-flag input gating for the gyro + accelerometer estimators (the complementary
//! filter here, the planar `ahrs` wrappers of the std crate's `peers`), which shared the
//! same preamble: a sample whose time is not finite or does not advance is refused
//! ([`Flags::BAD_TIME_STEP`], the caller holds its output); a missing gyro reading is
//! replaced by the recent mean of the good ones ([`MISSING_RATE_TAU`],
//! [`Flags::SAMPLE_MISSING`]); the time step runs from the last accepted sample.
use crate::{Flags, Real, Sample, StepClock};

/// Time constant \[s\] of the gyro mean that stands in for a missing reading. The last
/// reading would carry one sample of the body's angular vibration through the gap (the
/// scooter's 40 Hz, 0.25 rad/s): integrated over 100 missing samples of the simulated
/// scooter rides (seeds 1, 3, 6, 200 gaps), the angle was off by 1.06-1.09 deg RMS with the
/// last reading, 0.43-0.59 deg with a 25 ms mean and 0.52-0.74 deg with a 50 ms one (a
/// longer mean lags the manoeuvres).
pub const MISSING_RATE_TAU: f64 = 0.025;

/// What [`InputHold::begin`] makes of a sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Step<T> {
    /// The time is not finite or not after the last accepted sample: do nothing with it,
    /// return the previous estimate flagged [`Flags::BAD_TIME_STEP`].
    BadTime,
    /// No sample accepted yet: start on this one if its other inputs allow, and then call
    /// [`InputHold::started`].
    First {
        /// The gyro reading, or the recent mean of the good ones.
        gyro: T,
        /// [`Flags::SAMPLE_MISSING`] if the gyro was missing.
        flags: Flags,
    },
    /// A later sample, already accepted.
    Next {
        /// Time since the last accepted sample \[s\], positive.
        dt: T,
        /// The gyro reading, or the recent mean of the good ones.
        gyro: T,
        /// [`Flags::SAMPLE_MISSING`] if the gyro was missing.
        flags: Flags,
    },
}

/// The time and gyro state behind [`Step`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InputHold<T> {
    clock: StepClock<T>,
    /// The gyro's recent mean [rad/s] ([`MISSING_RATE_TAU`]); zero before any reading.
    mean_gyro: T,
    seen_gyro: bool,
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
            mean_gyro: T::zero(),
            seen_gyro: false,
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
            let a = match step {
                Some(dt) if self.seen_gyro => (dt / T::lit(MISSING_RATE_TAU)).min(T::one()),
                _ => T::one(),
            };
            self.mean_gyro = self.mean_gyro + a * (s.gyro - self.mean_gyro);
            self.seen_gyro = true;
            s.gyro
        } else {
            flags |= Flags::SAMPLE_MISSING;
            self.mean_gyro
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

    #[test]
    fn a_missing_gyro_is_the_recent_mean_not_the_last_vibrating_reading() {
        let mut h = InputHold::<f64>::new();
        h.begin(&s(0.0, 1.0));
        h.started();
        // A 250 Hz square wave around 0.2 rad/s at 1 kHz: the last reading is 1.2 or -0.8.
        for k in 1..200 {
            let g = if (k / 2) % 2 == 0 { 1.2 } else { -0.8 };
            h.begin(&s(1e-3, g));
        }
        let Step::Next { gyro, flags, .. } = h.begin(&s(1e-3, f64::NAN)) else {
            panic!("a step");
        };
        assert!(flags.contains(Flags::SAMPLE_MISSING));
        // The 25 ms mean leaves about 1 / (2 pi 250 Hz 25 ms) = 2.5 % of the square wave.
        assert!((gyro - 0.2).abs() < 0.05, "{gyro}");
    }
}
