//! Measurement models: what a sensor sees of the state, and how noisily.
use super::Error;
use crate::Real;
use nalgebra::{SMatrix, SVector};

/// A reading of `M` values (1 for a scalar) of a state `S` with an `N`-dimensional error:
/// `z = h(x) + v`, `v ~ N(0, R)`, `R` diagonal (independent axes, which lets the EKF
/// apply the axes one scalar at a time, exactly).
pub trait Measurement<T: Real, S, const N: usize, const M: usize> {
    /// Whether `h` is linear in the state. The UKF applies a linear measurement by the
    /// Kalman update (where the unscented transform is exact), not through sigma points.
    const LINEAR: bool = false;

    /// The predicted reading `h(x)`.
    fn predict(&self, x: &S) -> SVector<T, M>;

    /// The Jacobian `H(x)`, `M x N` (error coordinates).
    fn jacobian(&self, x: &S) -> SMatrix<T, M, N>;

    /// The diagonal of `R`: each axis' noise variance.
    fn variance(&self) -> SVector<T, M>;

    /// If row `axis` of `H` is ones at these error indices and zeros elsewhere (the
    /// encoder reads phi, the gyro theta' + bias), the filter uses sums of covariance
    /// columns instead of products. `None` (the default): a general row.
    #[inline]
    fn unit_row(&self, _axis: usize) -> Option<&[usize]> {
        None
    }
}

/// Row `axis` of a measurement's Jacobian as an error vector.
#[inline]
pub(crate) fn row<T: Real, S, const N: usize, const M: usize, Z: Measurement<T, S, N, M>>(
    m: &Z,
    x: &S,
    axis: usize,
) -> Error<T, N> {
    m.jacobian(x).row(axis).transpose()
}
