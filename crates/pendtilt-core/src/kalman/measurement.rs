//! The paper's measurement model (Eq 11) on the filter engine.
use crate::engine::Measurement;
use crate::Real;
use nalgebra::{Matrix1x2, Vector1, Vector2};

/// A sensor that reports the tilt angle (accelerometer via Eq 1, or a pendulum algorithm)
/// of the `[theta, bias]` state: `H = [1, 0]` (Eq 11), variance `r` [rad^2].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AngleMeasurement<T> {
    /// Measurement variance R [rad^2].
    pub r: T,
}

impl<T: Real> Measurement<T, Vector2<T>, 2, 1> for AngleMeasurement<T> {
    const LINEAR: bool = true;

    #[inline]
    fn predict(&self, x: &Vector2<T>) -> Vector1<T> {
        Vector1::new(x[0])
    }

    #[inline]
    fn jacobian(&self, _x: &Vector2<T>) -> Matrix1x2<T> {
        Matrix1x2::new(T::one(), T::zero())
    }

    #[inline]
    fn variance(&self) -> Vector1<T> {
        Vector1::new(self.r)
    }

    #[inline]
    fn unit_row(&self, _axis: usize) -> Option<&[usize]> {
        Some(&[0])
    }
}
