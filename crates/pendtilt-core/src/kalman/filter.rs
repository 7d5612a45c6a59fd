//! The linear Kalman filter (Eqs 2-8), generic in state size `N` and measurement size `M`.
use super::measurement::LinearMeasurement;
use super::process::Transition;
use crate::Real;
use nalgebra::{SMatrix, SVector};

/// Why an update was not applied.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UpdateError {
    /// The measurement or its covariance was not finite.
    NotFinite,
    /// The innovation covariance `H P H^T + R` could not be inverted.
    Singular,
}

/// State estimate `x` with covariance `P`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KalmanFilter<T: Real, const N: usize> {
    /// State estimate.
    pub x: SVector<T, N>,
    /// State covariance.
    pub p: SMatrix<T, N, N>,
}

impl<T: Real, const N: usize> KalmanFilter<T, N> {
    /// A filter starting at `x0` with covariance `p0`.
    pub fn new(x0: SVector<T, N>, p0: SMatrix<T, N, N>) -> Self {
        Self { x: x0, p: p0 }
    }

    /// Predict (Eqs 2, 4, 9): `x- = F x + B u`, `P- = F P F^T + Q`.
    #[inline]
    pub fn predict(&mut self, tr: &Transition<T, N>) {
        self.x = tr.f * self.x + tr.bu;
        self.p = tr.f * self.p * tr.f.transpose() + tr.q;
    }

    /// Update (Eqs 6-8): `K = P- H^T (H P- H^T + R)^-1`, `x = x- + K (z - H x-)`,
    /// `P = (I - K H) P-`. Returns the gain.
    #[inline]
    pub fn update<const M: usize, Meas: LinearMeasurement<T, N, M>>(
        &mut self,
        meas: &Meas,
        z: &SVector<T, M>,
    ) -> Result<SMatrix<T, N, M>, UpdateError> {
        let h = meas.h();
        let r = meas.r();
        if z.iter().chain(r.iter()).any(|v| !v.is_finite()) {
            return Err(UpdateError::NotFinite);
        }
        let s = h * self.p * h.transpose() + r;
        let s_inv = s.try_inverse().ok_or(UpdateError::Singular)?;
        let k = self.p * h.transpose() * s_inv;
        self.x += k * (z - h * self.x);
        self.p = (SMatrix::<T, N, N>::identity() - k * h) * self.p;
        Ok(k)
    }
}
