//! Process models: the state transition over one time step.
use crate::Real;
use nalgebra::{SMatrix, SVector};

/// The linearised motion of an `N`-state system over one step: `x- = F x + B u`,
/// `P- = F P F^T + Q`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transition<T: Real, const N: usize> {
    /// State transition F (the paper's A).
    pub f: SMatrix<T, N, N>,
    /// The input's contribution B u.
    pub bu: SVector<T, N>,
    /// Process noise covariance over the step.
    pub q: SMatrix<T, N, N>,
}

/// A process model: the transition for a step `dt` under input `u`.
pub trait ProcessModel<T: Real, const N: usize> {
    /// The input (a gyro rate for [`AngleBias`]).
    type Input;
    /// The transition over `dt` seconds with input `u`.
    fn transition(&self, dt: T, u: &Self::Input) -> Transition<T, N>;
}

/// The paper's model (Eqs 9, 11): state `[theta, bias]`, input the gyro rate,
/// `A = [[1, -dt], [0, 1]]`, `B = [dt, 0]^T`, `Q = diag(q_angle, q_bias) dt`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AngleBias<T> {
    /// Angle process noise density [rad^2/s].
    pub q_angle: T,
    /// Gyro-bias process noise density [(rad/s)^2/s].
    pub q_bias: T,
}

impl<T: Real> ProcessModel<T, 2> for AngleBias<T> {
    type Input = T;

    #[inline]
    fn transition(&self, dt: T, u: &T) -> Transition<T, 2> {
        Transition {
            f: SMatrix::<T, 2, 2>::new(T::one(), -dt, T::zero(), T::one()),
            bu: SVector::<T, 2>::new(dt * *u, T::zero()),
            q: SMatrix::<T, 2, 2>::new(self.q_angle * dt, T::zero(), T::zero(), self.q_bias * dt),
        }
    }
}
