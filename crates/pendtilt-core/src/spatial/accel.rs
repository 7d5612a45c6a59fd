//! `accel3d`: roll and pitch from the accelerometer, the baseline every IMU filter starts
//! from: at rest it reads `f = g u`, so `roll = atan2(f_y, f_z)` and
//! `pitch = atan2(-f_x, sqrt(f_y^2 + f_z^2))` (MODEL.md 7.1). Under vibration these
//! nonlinear functions of raw samples are biased (as the planar Eq 1);
//! [`AccelSettings::prefilter_hz`] low-passes each axis first (the planar Eq 1's settings:
//! one definition of the prefilter and the full scale).
use super::attitude::roll_pitch_from_up;
use super::{Attitude, SpatialSample};
pub use crate::estimators::accel::AccelSettings;
use crate::filters::biquad::LowPass2;
use crate::{Estimator, Flags, Real, StepClock};

/// Roll and pitch from the accelerometer as a streaming estimator.
#[derive(Debug, Clone)]
pub struct Accel<T: Real> {
    settings: AccelSettings<T>,
    low: [LowPass2<T>; 3],
    clock: StepClock<T>,
    last: Attitude<T>,
}

impl<T: Real> Accel<T> {
    /// A new estimator.
    pub fn new(settings: AccelSettings<T>) -> Self {
        let f = settings.prefilter_hz.unwrap_or(T::one());
        Self {
            settings,
            low: [LowPass2::new(f), LowPass2::new(f), LowPass2::new(f)],
            clock: StepClock::new(),
            last: Attitude::unknown(),
        }
    }

    /// The settings in use.
    pub fn settings(&self) -> &AccelSettings<T> {
        &self.settings
    }

    fn hold(&self, flags: Flags) -> Attitude<T> {
        Attitude { flags, ..self.last }
    }
}

impl<T: Real> Estimator for Accel<T> {
    type Input = SpatialSample<T>;
    type Output = Attitude<T>;

    #[inline]
    fn update(&mut self, s: &SpatialSample<T>) -> Attitude<T> {
        let step = match self.clock.offer(s.dt) {
            Ok(step) => step,
            Err(flags) => return self.hold(flags),
        };
        if !s.accel.iter().all(|v| v.is_finite()) {
            return self.hold(Flags::SAMPLE_MISSING);
        }
        let mut flags = Flags::empty();
        if let Some(fs) = self.settings.checked_full_scale() {
            if s.accel.iter().any(|v| v.abs() >= fs) {
                flags |= Flags::SATURATED;
            }
        }
        let f = match (self.settings.prefilter_hz, step) {
            (Some(_), Some(dt)) => core::array::from_fn(|i| self.low[i].update(s.accel[i], dt)),
            (Some(_), None) => {
                flags |= Flags::INITIALISING;
                core::array::from_fn(|i| self.low[i].update(s.accel[i], T::one()))
            }
            (None, _) => s.accel,
        };
        if !f.iter().all(|v: &T| v.is_finite()) {
            // An input near the type's largest value overflowed a low-pass: restart them.
            self.low.iter_mut().for_each(|l| l.reset());
            return self.hold(flags | Flags::SATURATED | Flags::SAMPLE_MISSING);
        }
        self.clock.accept();
        let (roll, pitch) = roll_pitch_from_up(f);
        self.last = Attitude { roll, pitch, flags };
        self.last
    }

    fn reset(&mut self) {
        self.low.iter_mut().for_each(|l| l.reset());
        self.clock.restart();
        self.last = Attitude::unknown();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spatial::attitude::up_from_roll_pitch;

    /// A full scale of 0 or below flags nothing; a positive one flags a reading at it.
    #[test]
    fn only_a_positive_full_scale_flags_saturation() {
        let s = SpatialSample::new(0.0, [f64::NAN; 2], [f64::NAN; 3], [0.0, 0.0, 9.8]);
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
    fn a_still_accelerometer_gives_its_roll_and_pitch_for_any_yaw() {
        let mut e = Accel::<f64>::new(AccelSettings::default());
        let (r, p) = (0.35, -0.6);
        let f = up_from_roll_pitch(r, p).map(|v| v * 9.81);
        let s = SpatialSample {
            accel: f,
            ..SpatialSample::after(1e-3)
        };
        let a = e.update(&s);
        assert!(
            (a.roll - r).abs() < 1e-14 && (a.pitch - p).abs() < 1e-14,
            "{a:?}"
        );
        assert!(!a.flags.contains(Flags::SAMPLE_MISSING));
        // A missing axis holds the last attitude, flagged.
        let mut m = s;
        m.accel[1] = f64::NAN;
        let h = e.update(&m);
        assert_eq!((h.roll, h.pitch), (a.roll, a.pitch));
        assert!(h.flags.contains(Flags::SAMPLE_MISSING));
    }
}
