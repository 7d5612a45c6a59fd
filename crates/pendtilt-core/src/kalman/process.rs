//! The paper's process model (Eqs 9, 11) on the filter engine.
use crate::engine::ProcessModel;
use crate::Real;
use nalgebra::{Matrix2, Vector2};

/// The paper's model (Eqs 9, 11): state `[theta, bias]`, input the gyro rate,
/// `x- = A x + B u` with `A = [[1, -dt], [0, 1]]`, `B = [dt, 0]^T`,
/// `Q = diag(q_angle, q_bias) dt`. Linear, so the engine's EKF is the paper's Kalman
/// filter on it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AngleBias<T> {
    /// Angle process noise density [rad^2/s].
    pub q_angle: T,
    /// Gyro-bias process noise density [(rad/s)^2/s].
    pub q_bias: T,
}

impl<T: Real> AngleBias<T> {
    /// A (the paper's state transition) over `dt`.
    #[inline]
    fn a(dt: T) -> Matrix2<T> {
        Matrix2::new(T::one(), -dt, T::zero(), T::one())
    }
}

impl<T: Real> ProcessModel<T, 2> for AngleBias<T> {
    type State = Vector2<T>;
    type Input = T;

    #[inline]
    fn step(&self, x: &Vector2<T>, u: &T, dt: T) -> Vector2<T> {
        self.step_with_jacobian(x, u, dt).0
    }

    #[inline]
    fn jacobian(&self, _x: &Vector2<T>, _u: &T, dt: T) -> Matrix2<T> {
        Self::a(dt)
    }

    /// `A x + B u` and `A`.
    #[inline]
    fn step_with_jacobian(&self, x: &Vector2<T>, u: &T, dt: T) -> (Vector2<T>, Matrix2<T>) {
        let a = Self::a(dt);
        (a * x + Vector2::new(dt * *u, T::zero()), a)
    }

    #[inline]
    fn q(&self, dt: T) -> Matrix2<T> {
        Matrix2::new(self.q_angle * dt, T::zero(), T::zero(), self.q_bias * dt)
    }
}
