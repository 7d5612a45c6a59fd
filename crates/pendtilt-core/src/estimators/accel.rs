//! The accelerometer tilt, Eq (1): `theta = atan2(ax, ay)`.
//!
//! Under vibration atan2 of raw samples is biased: the nonlinearity rectifies the vibration
//! (about 2.7 deg on a simulated ride, MODEL.md section 4). [`AccelSettings::prefilter_hz`]
//! low-passes ax and ay before atan2; it is off by default so that Eq (1) stays the paper's.
use super::equations::accel_angle;
use crate::filters::biquad::LowPass2;
use crate::{Estimate, Estimator, Flags, Real, Sample, StepClock};

/// Settings of [`Accel`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields, default)
)]
pub struct AccelSettings<T> {
    /// Cutoff \[Hz\] of a 2nd-order Butterworth low-pass on ax and ay before atan2.
    /// Default `None` (the paper's Eq 1 on raw samples).
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "Option::is_none"))]
    pub prefilter_hz: Option<T>,
    /// Accelerometer full scale [m/s^2]: samples at or beyond it are flagged
    /// [`Flags::SATURATED`]. Default `None` (unknown).
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "Option::is_none"))]
    pub full_scale: Option<T>,
}

impl<T> Default for AccelSettings<T> {
    fn default() -> Self {
        Self {
            prefilter_hz: None,
            full_scale: None,
        }
    }
}

impl<T: Real> AccelSettings<T> {
    /// The full scale if it is a usable bound (positive), for the per-sample check.
    pub fn checked_full_scale(&self) -> Option<T> {
        self.full_scale.filter(|f| crate::real::is_positive(*f))
    }
}

/// Eq (1) as a streaming estimator. [`Estimator::reset`] restarts the low-passes and
/// the clock; the settings and the low-passes' design stay.
#[derive(Debug, Clone)]
pub struct Accel<T: Real> {
    settings: AccelSettings<T>,
    lx: LowPass2<T>,
    ly: LowPass2<T>,
    clock: StepClock<T>,
    last: T,
}

impl<T: Real> Accel<T> {
    /// A new estimator.
    pub fn new(settings: AccelSettings<T>) -> Self {
        let f = settings.prefilter_hz.unwrap_or(T::one());
        Self {
            settings,
            lx: LowPass2::new(f),
            ly: LowPass2::new(f),
            clock: StepClock::new(),
            last: T::nan(),
        }
    }

    /// The settings in use.
    pub fn settings(&self) -> &AccelSettings<T> {
        &self.settings
    }
}

impl<T: Real> Estimator for Accel<T> {
    type Input = Sample<T>;
    type Output = Estimate<T>;

    #[inline]
    fn update(&mut self, s: &Sample<T>) -> Estimate<T> {
        let step = match self.clock.offer(s.dt) {
            Ok(step) => step,
            Err(flags) => {
                return Estimate {
                    theta: self.last,
                    flags,
                }
            }
        };
        if !(s.ax.is_finite() && s.ay.is_finite()) {
            return Estimate {
                theta: self.last,
                flags: Flags::SAMPLE_MISSING,
            };
        }
        let mut flags = Flags::empty();
        // A full scale that is not positive is no full scale (as every estimator takes it).
        if let Some(fs) = self.settings.checked_full_scale() {
            if s.ax.abs() >= fs || s.ay.abs() >= fs {
                flags |= Flags::SATURATED;
            }
        }
        let (ax, ay) = match (self.settings.prefilter_hz, step) {
            (Some(_), Some(dt)) => (self.lx.update(s.ax, dt), self.ly.update(s.ay, dt)),
            (Some(_), None) => {
                flags |= Flags::INITIALISING;
                (
                    self.lx.update(s.ax, T::one()),
                    self.ly.update(s.ay, T::one()),
                )
            }
            (None, _) => (s.ax, s.ay),
        };
        if !(ax.is_finite() && ay.is_finite()) {
            // An input near the type's largest value overflowed the low-pass (found by
            // fuzzing in f32 with 3e38): restart it on the next sample, hold the angle.
            self.lx.reset();
            self.ly.reset();
            return Estimate {
                theta: self.last,
                flags: flags | Flags::SATURATED | Flags::SAMPLE_MISSING,
            };
        }
        self.clock.accept();
        self.last = accel_angle(ax, ay);
        Estimate {
            theta: self.last,
            flags,
        }
    }

    fn reset(&mut self) {
        self.lx.reset();
        self.ly.reset();
        self.clock.restart();
        self.last = T::nan();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A full scale of 0 or below (a library user's placeholder) flags nothing, as
    /// [`AccelSettings::checked_full_scale`] says; a positive one flags a reading at it.
    #[test]
    fn only_a_positive_full_scale_flags_saturation() {
        let s = Sample {
            dt: 0.0,
            phi: f64::NAN,
            gyro: f64::NAN,
            ax: 0.0,
            ay: 9.8,
        };
        for (fs, saturated) in [(Some(0.0), false), (Some(-1.0), false), (Some(9.8), true)] {
            let mut a = Accel::<f64>::new(AccelSettings {
                prefilter_hz: None,
                full_scale: fs,
            });
            let e = a.update(&s);
            assert_eq!(e.flags.contains(Flags::SATURATED), saturated, "{fs:?}");
        }
    }

    #[test]
    fn prefilter_overflow_holds_flags_and_recovers() {
        let mut a = Accel::<f32>::new(AccelSettings {
            prefilter_hz: Some(5.0),
            full_scale: None,
        });
        let s = |dt: f32, ax: f32, ay: f32| Sample {
            dt,
            phi: f32::NAN,
            gyro: f32::NAN,
            ax,
            ay,
        };
        // The filter starts at rest on 3e38; the next step's 1.95 y overflows.
        let first = a.update(&s(0.0, 3e38, 9.8)).theta;
        assert!(first.is_finite());
        let e = a.update(&s(0.001, 0.0, 9.8));
        assert_eq!(e.theta, first);
        assert!(e.flags.contains(Flags::SATURATED | Flags::SAMPLE_MISSING));
        // The next ordinary samples give ordinary angles again.
        for k in 3..50 {
            let e = a.update(&s(1e-3, 0.0, 9.8));
            assert!(e.theta.abs() < 1e-6, "{k}: {e:?}");
        }
    }
}
