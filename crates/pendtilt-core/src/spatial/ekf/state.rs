//! The state of the spatial filter and its error coordinates.
//!
//! Stored: the attitude `q` (a unit quaternion, world <- body), the gyro bias, and the
//! Cardan joint's angles `a`, `b` with the pendulum's absolute rates `p`, `r` about the
//! joint axes (see [`super::process`] for why absolute rates), and the forward speed `v`
//! of the point O with its rate `v'` (a vehicle's, from the `speed` column; held at zero
//! without one). The error has 12 dimensions: a rotation vector in body axes
//! (`q ⊞ d = q exp(d)`, the multiplicative error of an error-state filter), then the
//! bias, `a`, `b`, `p`, `r`, `v`, `v'` by addition.
use crate::engine::ErrorState;
use crate::Real;
use nalgebra::{SVector, UnitQuaternion, Vector2, Vector3, Vector4};

/// Error dimension.
pub const N: usize = 12;
/// Error index of the attitude's rotation vector (3 entries, body axes).
pub const ROT: usize = 0;
/// Error index of the gyro bias (3 entries).
pub const BIAS: usize = 3;
/// Error index of the outer joint angle a.
pub const A: usize = 6;
/// Error index of the inner joint angle b.
pub const B: usize = 7;
/// Error index of the ring's absolute rate about body x, `p = w_x + a'`.
pub const P: usize = 8;
/// Error index of the pendulum's absolute rate about the inner axis, `r = u2 + b'`.
pub const R: usize = 9;
/// Error index of O's forward speed `v` along body x.
pub const V: usize = 10;
/// Error index of O's forward acceleration `v'`.
pub const ACC: usize = 11;

/// An error vector.
pub type Error<T> = SVector<T, N>;

/// The spatial filter's state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct State<T: Real> {
    /// Attitude, world <- body.
    pub q: UnitQuaternion<T>,
    /// Gyro bias, body axes [rad/s].
    pub bias: Vector3<T>,
    /// `(a, b, p, r)`: joint angles \[rad\] and the absolute rates [rad/s].
    pub joints: Vector4<T>,
    /// `(v, v')`: O's forward speed along body x \[m/s\] and its rate \[m/s^2\].
    pub travel: Vector2<T>,
}

impl<T: Real> State<T> {
    /// The world's up direction in body axes, `u = R^T e_z`.
    #[inline]
    pub fn up(&self) -> Vector3<T> {
        self.q.inverse_transform_vector(&Vector3::z())
    }
}

impl<T: Real> ErrorState<T, N> for State<T> {
    #[inline]
    fn retract(&self, dx: &Error<T>) -> Self {
        let d = Vector3::new(dx[ROT], dx[ROT + 1], dx[ROT + 2]);
        // Renormalised: a product of unit quaternions drifts from unit length by rounding
        // (in f32 enough to scale the modelled gravity within minutes).
        let mut q = self.q * UnitQuaternion::from_scaled_axis(d);
        q.renormalize_fast();
        Self {
            q,
            bias: self.bias + Vector3::new(dx[BIAS], dx[BIAS + 1], dx[BIAS + 2]),
            joints: self.joints + Vector4::new(dx[A], dx[B], dx[P], dx[R]),
            travel: self.travel + Vector2::new(dx[V], dx[ACC]),
        }
    }

    #[inline]
    fn local(&self, y: &Self) -> Error<T> {
        let d = (self.q.inverse() * y.q).scaled_axis();
        let b = y.bias - self.bias;
        let j = y.joints - self.joints;
        let t = y.travel - self.travel;
        Error::<T>::from_column_slice(&[
            d[0], d[1], d[2], b[0], b[1], b[2], j[0], j[1], j[2], j[3], t[0], t[1],
        ])
    }

    #[inline]
    fn is_finite(&self) -> bool {
        self.q.coords.iter().all(|v| v.is_finite())
            && self.bias.iter().all(|v| v.is_finite())
            && self.joints.iter().all(|v| v.is_finite())
            && self.travel.iter().all(|v| v.is_finite())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn retract_and_local_are_inverse() {
        let x = State {
            q: UnitQuaternion::from_euler_angles(0.3, -0.2, 1.0),
            bias: Vector3::new(0.01, -0.02, 0.003),
            joints: Vector4::new(-0.3, 0.2, 0.1, -0.05),
            travel: Vector2::new(7.0, -1.5),
        };
        let dx = Error::<f64>::from_column_slice(&[
            0.02, -0.01, 0.3, 1e-3, 2e-3, -1e-3, 0.01, -0.02, 0.5, 0.25, 0.1, -0.3,
        ]);
        let y = x.retract(&dx);
        let back = x.local(&y);
        assert!((back - dx).norm() < 1e-14, "{back}");
        // The rotation error is in body axes: q exp(d).
        let e = y.q
            * (x.q * UnitQuaternion::from_scaled_axis(Vector3::new(0.02, -0.01, 0.3))).inverse();
        assert!(e.angle() < 1e-14);
    }
}
