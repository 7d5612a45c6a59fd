//! Measurement models of the spatial filter (state layout in [`super::state`]).
//!
//! - [`Encoders`]: the joint angles `z = (a, b) = (-phi_x, -phi_y)`, linear; each row a
//!   single one, so the filter updates with a covariance column, not a product.
//! - [`Speed`]: O's forward speed `v`, the `speed` column, linear (one state).
//! - [`Accelerometer`]: `z = g u + a_O + lever`, the specific force of a body turning
//!   about a point O that moves with the forward speed `v` (`u` the world's up direction in
//!   body axes, `a_O = v' x_b + w_p x (v x_b)` from the state, `lever` the known rigid-body
//!   term from O to the accelerometer); the vibration it reads is its noise. Nonlinear in
//!   the attitude.
//! - [`RestBias`]: the gyro's bias as a body at rest reads it (the guard's rest detection),
//!   linear in the bias states.
//! - [`UpDirection`]: the world's up direction in body axes as an inclination reference
//!   gives it (the guard's, [`crate::spatial::imu`]), a unit vector; nonlinear in the
//!   attitude and in nothing else.
use super::state::{State, A, ACC, B, BIAS, N, ROT, V};
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

/// O's forward speed as the `speed` column reads it, `z = v`, variance `r` [(m/s)^2].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Speed<T> {
    /// Variance of one reading [(m/s)^2].
    pub r: T,
}

impl<T: Real> Measurement<T, State<T>, N, 1> for Speed<T> {
    const LINEAR: bool = true;

    #[inline]
    fn predict(&self, x: &State<T>) -> SVector<T, 1> {
        SVector::<T, 1>::new(x.travel[0])
    }

    #[inline]
    fn jacobian(&self, _x: &State<T>) -> SMatrix<T, 1, N> {
        let mut h = SMatrix::<T, 1, N>::zeros();
        h[(0, V)] = T::one();
        h
    }

    #[inline]
    fn unit_row(&self, _axis: usize) -> Option<&[usize]> {
        Some(&[V])
    }

    #[inline]
    fn variance(&self) -> SVector<T, 1> {
        SVector::<T, 1>::new(self.r)
    }
}

/// The accelerometer as a measurement of the up direction and O's acceleration:
/// `z = g u + v' x_b + v per_speed + lever`, variance `r` [(m/s^2)^2] per axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Accelerometer<T: Real> {
    /// g [m/s^2].
    pub gravity: T,
    /// O's centripetal acceleration per unit forward speed, `w_p x x_b` [1/s] (see
    /// [`super::process::Drive::centre_accel_per_speed`]).
    pub per_speed: Vector3<T>,
    /// The known specific force of the lever arm from O to the accelerometer,
    /// `wd x r + w x (w x r)` [m/s^2] (see [`crate::spatial::mounting`]); it does not
    /// depend on the state.
    pub lever: Vector3<T>,
    /// Variance per axis: white noise over the sample plus the vibration.
    pub r: T,
}

impl<T: Real> Measurement<T, State<T>, N, 3> for Accelerometer<T> {
    #[inline]
    fn predict(&self, x: &State<T>) -> Vector3<T> {
        x.up() * self.gravity
            + self.per_speed * x.travel[0]
            + Vector3::new(x.travel[1], T::zero(), T::zero())
            + self.lever
    }

    /// `u(q exp d) = u + u x d`: `H = g [u]x` on the rotation error; `per_speed` and
    /// `x_b` on the speed and its rate.
    #[inline]
    fn jacobian(&self, x: &State<T>) -> SMatrix<T, 3, N> {
        let s = super::process::skew(&x.up()) * self.gravity;
        let mut h = SMatrix::<T, 3, N>::zeros();
        h.fixed_view_mut::<3, 3>(0, ROT).copy_from(&s);
        h.fixed_view_mut::<3, 1>(0, V).copy_from(&self.per_speed);
        h[(0, ACC)] = T::one();
        h
    }

    #[inline]
    fn variance(&self) -> SVector<T, 3> {
        Vector3::new(self.r, self.r, self.r)
    }
}

/// The world's up direction in body axes as an inclination reference reads it, `z = u`
/// (a unit vector), variance `r` [rad^2] per axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UpDirection<T> {
    /// Variance per axis [rad^2].
    pub r: T,
}

impl<T: Real> Measurement<T, State<T>, N, 3> for UpDirection<T> {
    #[inline]
    fn predict(&self, x: &State<T>) -> Vector3<T> {
        x.up()
    }

    /// `u(q exp d) = u + u x d`: `H = [u]x` on the rotation error, nothing else.
    #[inline]
    fn jacobian(&self, x: &State<T>) -> SMatrix<T, 3, N> {
        let mut h = SMatrix::<T, 3, N>::zeros();
        h.fixed_view_mut::<3, 3>(0, ROT)
            .copy_from(&super::process::skew(&x.up()));
        h
    }

    #[inline]
    fn variance(&self) -> SVector<T, 3> {
        Vector3::new(self.r, self.r, self.r)
    }
}

/// The gyro's bias as a body at rest reads it, `z = b` \[rad/s\], variance `r`
/// \[(rad/s)^2\] per axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RestBias<T> {
    /// Variance per axis \[(rad/s)^2\].
    pub r: T,
}

impl<T: Real> Measurement<T, State<T>, N, 3> for RestBias<T> {
    const LINEAR: bool = true;

    #[inline]
    fn predict(&self, x: &State<T>) -> Vector3<T> {
        x.bias
    }

    #[inline]
    fn jacobian(&self, _x: &State<T>) -> SMatrix<T, 3, N> {
        let mut h = SMatrix::<T, 3, N>::zeros();
        for k in 0..3 {
            h[(k, BIAS + k)] = T::one();
        }
        h
    }

    #[inline]
    fn unit_row(&self, axis: usize) -> Option<&[usize]> {
        match axis {
            0 => Some(&[BIAS]),
            1 => Some(&[BIAS + 1]),
            _ => Some(&[BIAS + 2]),
        }
    }

    #[inline]
    fn variance(&self) -> SVector<T, 3> {
        Vector3::new(self.r, self.r, self.r)
    }
}
