//! What an estimator needs of a Gaussian filter: predict through a [`ProcessModel`],
//! apply a [`Measurement`], correct or inflate. The EKF ([`super::ExtendedKalman`]) and
//! the UKF ([`super::UnscentedKalman`]) implement it.
use super::gate::{Gate, Rejected};
use super::measurement::Measurement;
use super::process::ProcessModel;
use super::state::ErrorState;
use super::{Cov, Error};
use crate::Real;
use nalgebra::SVector;

/// A Gaussian filter over a state `S` with an `N`-dimensional error.
pub trait GaussianFilter<T: Real, S: ErrorState<T, N>, const N: usize>: Sized {
    /// A filter at `x0` with error covariance `p0`.
    fn start(x0: S, p0: Cov<T, N>) -> Self;

    /// The state estimate.
    fn state(&self) -> &S;

    /// Its error covariance.
    fn covariance(&self) -> &Cov<T, N>;

    /// Moves the estimate by `dx` ([`ErrorState::retract`]); `P` is unchanged (used to
    /// keep angles within a turn).
    fn retract(&mut self, dx: &Error<T, N>);

    /// Predicts over `dt` seconds with input `u` and process noise `q` (`model.q(dt)`,
    /// passed in so that it is computed once per distinct step). `false` if the covariance
    /// could not be propagated (the state is then left as it was).
    fn predict<P: ProcessModel<T, N, State = S>>(
        &mut self,
        model: &P,
        u: &P::Input,
        dt: T,
        q: &Cov<T, N>,
    ) -> bool;

    /// Applies reading `z` of `meas`, each axis gated by `gate`; an axis the gate rejects
    /// rejects the reading ([`Rejected::Outlier`]; an EKF may have applied the axes
    /// before it).
    fn update<Z: Measurement<T, S, N, M>, const M: usize>(
        &mut self,
        meas: &Z,
        z: &SVector<T, M>,
        gate: Gate<T>,
    ) -> Result<(), Rejected>;

    /// Adds `v v^T` to the covariance (re-acquisition after a run of rejected
    /// measurements: the filter forgets what it was too sure of, along `v`).
    fn inflate(&mut self, v: &Error<T, N>);

    /// `P = T P T^T` (kept symmetric): a linear map of the error's uncertainty, e.g. to
    /// bound it along a direction no measurement observes (a heading that would otherwise
    /// grow without end and take the covariance beyond `f32`'s range).
    fn transform(&mut self, t: &Cov<T, N>);
}
