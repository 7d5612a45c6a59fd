//! The innovation gate and why a measurement update was not applied.
use crate::Real;

/// Why an update was not applied.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rejected {
    /// The measurement, its variance or the innovation variance was not finite.
    NotFinite,
    /// The innovation variance was not positive.
    NotPositive,
    /// The normalised innovation squared `y^2 / s` was above the gate: an outlier.
    Outlier,
}

/// The innovation gate of one measurement axis: `y` is an outlier if
/// `y^2 > threshold (s + floor)`, `s` the innovation variance the filter predicts and
/// `floor` a variance the filter does not model but the measurement carries (the gyro's
/// angular vibration). For a consistent filter and `floor = 0`, `y^2 / s` is chi-square
/// with one degree of freedom.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gate<T> {
    /// Threshold on `y^2 / (s + floor)`; infinity turns the gate off.
    pub threshold: T,
    /// Variance added to `s` for the test only [measurement unit squared].
    pub floor: T,
}

impl<T: Real> Gate<T> {
    /// No gate: every finite innovation is applied.
    pub fn off() -> Self {
        Self {
            threshold: T::lit(f64::INFINITY),
            floor: T::zero(),
        }
    }

    /// Whether innovation `y` with predicted variance `s` is an outlier.
    #[inline]
    pub fn rejects(&self, y: T, s: T) -> bool {
        y * y > self.threshold * (s + self.floor)
    }
}
