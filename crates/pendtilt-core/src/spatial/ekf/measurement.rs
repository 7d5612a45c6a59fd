//! Measurement models of the spatial filter (state layout in [`super::state`]).
//!
//! - [`Encoders`]: the joint angles `z = (a, b) = (-phi_x, -phi_y)`, linear; each row a
//!   single one, so the filter updates with a covariance column, not a product.
//! - [`Accelerometer`]: `z = g u + lever`, the specific force of a body turning about a
//!   point O that does not accelerate (`u` the world's up direction in body axes, `lever`
//!   the known rigid-body term from O to the accelerometer); the vibration it reads is its
//!   noise. Nonlinear in the attitude.
use super::state::{State, A, B, N, ROT};
use crate::engine::Measurement;
use crate::Real;
use nalgebra::{SMatrix, SVector, Vector2, Vector3};

/// The two encoders as the joint angles they read, `z = (a, b) = (-phi_x, -phi_y)`
/// (MODEL.md 7.2), variance `r` [rad^2] each.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Encoders<T> {
    /// Variance of one reading [rad^2].
    pub r: T,
}

impl<T: Real> Measurement<T, State<T>, N, 2> for Encoders<T> {
    const LINEAR: bool = true;

    #[inline]
    fn predict(&self, x: &State<T>) -> Vector2<T> {
        Vector2::new(x.joints[0], x.joints[1])
    }

    #[inline]
    fn jacobian(&self, _x: &State<T>) -> SMatrix<T, 2, N> {
        let mut h = SMatrix::<T, 2, N>::zeros();
        h[(0, A)] = T::one();
        h[(1, B)] = T::one();
        h
    }

    #[inline]
    fn unit_row(&self, axis: usize) -> Option<&[usize]> {
        match axis {
            0 => Some(&[A]),
            _ => Some(&[B]),
        }
    }

    #[inline]
    fn variance(&self) -> Vector2<T> {
        Vector2::new(self.r, self.r)
    }
}

/// The accelerometer as a measurement of the up direction: `z = g u + lever`, variance
/// `r` [(m/s^2)^2] per axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Accelerometer<T: Real> {
    /// g [m/s^2].
    pub gravity: T,
    /// The known specific force beyond gravity: O's acceleration from the speed and the
    /// lever arm from O to the accelerometer, `wd x r + w x (w x r)` [m/s^2] (see
    /// [`crate::spatial::mounting`]); it does not depend on the attitude.
    pub lever: Vector3<T>,
    /// Variance per axis: white noise over the sample plus the vibration.
    pub r: T,
}

impl<T: Real> Measurement<T, State<T>, N, 3> for Accelerometer<T> {
    #[inline]
    fn predict(&self, x: &State<T>) -> Vector3<T> {
        x.up() * self.gravity + self.lever
    }

    /// `u(q exp d) = u + u x d`: `H = g [u]x` on the rotation error.
    #[inline]
    fn jacobian(&self, x: &State<T>) -> SMatrix<T, 3, N> {
        let s = super::process::skew(&x.up()) * self.gravity;
        let mut h = SMatrix::<T, 3, N>::zeros();
        h.fixed_view_mut::<3, 3>(0, ROT).copy_from(&s);
        h
    }

    #[inline]
    fn variance(&self) -> SVector<T, 3> {
        Vector3::new(self.r, self.r, self.r)
    }
}
