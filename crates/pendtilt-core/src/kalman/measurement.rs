//! Measurement models: what a sensor sees of the state, and how noisily.
use crate::Real;
use nalgebra::SMatrix;

/// A linear measurement of `M` values of an `N`-state: `z = H x + v`, `v ~ N(0, R)`.
pub trait LinearMeasurement<T: Real, const N: usize, const M: usize> {
    /// H.
    fn h(&self) -> SMatrix<T, M, N>;
    /// R, the measurement noise covariance.
    fn r(&self) -> SMatrix<T, M, M>;
}

/// A sensor that reports the tilt angle (accelerometer via Eq 1, or a pendulum algorithm)
/// of the `[theta, bias]` state: `H = [1, 0]` (Eq 11), variance `r` [rad^2].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AngleMeasurement<T> {
    /// Measurement variance R [rad^2].
    pub r: T,
}

impl<T: Real> LinearMeasurement<T, 2, 1> for AngleMeasurement<T> {
    #[inline]
    fn h(&self) -> SMatrix<T, 1, 2> {
        SMatrix::<T, 1, 2>::new(T::one(), T::zero())
    }
    #[inline]
    fn r(&self) -> SMatrix<T, 1, 1> {
        SMatrix::<T, 1, 1>::new(self.r)
    }
}
