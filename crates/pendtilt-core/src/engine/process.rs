//! Process models: how the state moves over one step, driven by an input.
use super::state::ErrorState;
use super::Cov;
use crate::Real;

/// A process model with an `N`-dimensional error state.
///
/// The Jacobian and `Q` are in error coordinates: for a vector state the ordinary
/// `d f / d x`; for a rotation, how an error `dx` before the step maps to the error after
/// it.
pub trait ProcessModel<T: Real, const N: usize> {
    /// The stored state (a vector, or a rotation with a vector beside it).
    type State: ErrorState<T, N>;
    /// What drives the step (the gyro rate for the paper's filter; `()` for none).
    type Input;

    /// The state after `dt` seconds with input `u`.
    fn step(&self, x: &Self::State, u: &Self::Input, dt: T) -> Self::State;

    /// The Jacobian `F` of [`Self::step`] at `x` (error coordinates).
    fn jacobian(&self, x: &Self::State, u: &Self::Input, dt: T) -> Cov<T, N>;

    /// [`Self::step`] and [`Self::jacobian`] together (a model overrides it to share the
    /// work, as the trigonometry of the pendulum).
    #[inline]
    fn step_with_jacobian(
        &self,
        x: &Self::State,
        u: &Self::Input,
        dt: T,
    ) -> (Self::State, Cov<T, N>) {
        (self.step(x, u, dt), self.jacobian(x, u, dt))
    }

    /// The process noise covariance `Q` over a step of `dt` seconds.
    fn q(&self, dt: T) -> Cov<T, N>;

    /// `F P F^T` for this model's `F`. The default is the dense product; a model whose
    /// Jacobian has structural zeros overrides it to skip them.
    #[inline]
    fn propagate(&self, f: &Cov<T, N>, p: &Cov<T, N>) -> Cov<T, N> {
        f * p * f.transpose()
    }
}
