//! How a state is corrected: the error-state composition the filters use instead of
//! `x += K y`.
use super::{Cov, Error};
use crate::Real;
use nalgebra::SVector;

/// A state with an `N`-dimensional error: `x ⊞ dx` and `y ⊟ x`.
///
/// The covariance the filters carry is that of the error `dx`, not of the stored state, so
/// a state may store more numbers than its error has: a unit quaternion (4 numbers, a
/// 3-dimensional rotation error) with a vector beside it. For a vector state, `⊞` is
/// addition and `⊟` subtraction (the implementation for [`SVector`]).
pub trait ErrorState<T: Real, const N: usize>: Copy {
    /// `x ⊞ dx`: the state moved by the error `dx` (addition for a vector; composition with
    /// `exp(dx)` for a rotation).
    fn retract(&self, dx: &Error<T, N>) -> Self;

    /// `y ⊟ x`: the error `dx` with `x ⊞ dx = y` (the inverse of [`Self::retract`]).
    fn local(&self, y: &Self) -> Error<T, N>;

    /// Whether every stored number is finite.
    fn is_finite(&self) -> bool;

    /// The mean of sigma points given in symmetric pairs of equal weight `w` (the unscented
    /// transform of [`super::UnscentedKalman`]). The default is one Gauss-Newton step on
    /// the manifold about `centre` (one of the points): `centre ⊞ sum w (p_i ⊟ centre)`,
    /// exact for a vector state and to second order in the spread for a rotation.
    #[inline]
    fn mean_of_pairs(centre: &Self, pairs: &[[Self; 2]], w: T) -> Self {
        let mut acc = Error::<T, N>::zeros();
        for pair in pairs {
            acc += (centre.local(&pair[0]) + centre.local(&pair[1])) * w;
        }
        centre.retract(&acc)
    }

    /// The outer product of the error `dx` weighted by `w`, `w dx dx^T` (the unscented
    /// covariance term). Provided so an implementation can exploit structure; the default
    /// is the dense product.
    #[inline(always)]
    fn weighted_outer(dx: &Error<T, N>, w: T) -> Cov<T, N> {
        dx * dx.transpose() * w
    }
}

impl<T: Real, const N: usize> ErrorState<T, N> for SVector<T, N> {
    #[inline(always)]
    fn retract(&self, dx: &Error<T, N>) -> Self {
        self + dx
    }

    #[inline(always)]
    fn local(&self, y: &Self) -> Error<T, N> {
        y - self
    }

    #[inline(always)]
    fn is_finite(&self) -> bool {
        self.iter().all(|v| v.is_finite())
    }

    /// `sum over pairs of (a + b) w`, the plain mean (`centre` is not needed).
    #[inline]
    fn mean_of_pairs(_centre: &Self, pairs: &[[Self; 2]], w: T) -> Self {
        let mut mean = Self::zeros();
        for pair in pairs {
            mean += (pair[0] + pair[1]) * w;
        }
        mean
    }
}
