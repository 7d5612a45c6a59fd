//! What the estimator needs of a nonlinear filter over the pendulum state: predict through
//! the process model, apply a scalar linear measurement, apply the accelerometer. The EKF
//! ([`super::ExtendedKalman`]) and the UKF ([`super::UnscentedKalman`]) implement it.
use super::measurement::Accelerometer;
use super::model::{Cov, PendulumProcess, State};
use super::update::{Gate, Rejected};
use crate::Real;

/// A Gaussian filter over the pendulum state.
pub trait StateFilter<T: Real> {
    /// A filter at `x0` with covariance `p0`.
    fn start(x0: State<T>, p0: Cov<T>) -> Self;
    /// The state estimate.
    fn state(&self) -> &State<T>;
    /// Its covariance.
    fn covariance(&self) -> &Cov<T>;
    /// Shifts the estimate by `dx` (used to keep angles within a turn); `P` is unchanged.
    fn shift(&mut self, dx: &State<T>);
    /// Predicts over `dt` seconds with process noise `q` (`model.q(dt)`, passed in so that
    /// it is computed once per distinct step). `false` if the covariance could not be
    /// propagated (the state is then left as it was).
    fn predict(&mut self, model: &PendulumProcess<T>, dt: T, q: &Cov<T>) -> bool;
    /// Applies `z = h . x + v`, `v ~ N(0, r)`, unless its normalised innovation squared
    /// is rejected by `gate` ([`Rejected::Outlier`]; see [`super::update::scalar_update`]).
    fn update_linear(&mut self, h: &State<T>, z: T, r: T, gate: Gate<T>) -> Result<(), Rejected>;
    /// Applies `z = sum of x[i] for i in idx + v`, `v ~ N(0, r)` (the encoder, the gyro):
    /// the same as [`Self::update_linear`] with a row of ones at `idx`, without the
    /// multiplications.
    fn update_unit(&mut self, idx: &[usize], z: T, r: T, gate: Gate<T>) -> Result<(), Rejected>;
    /// Applies an accelerometer reading `[f_x, f_y]`; an axis that `gate` rejects
    /// rejects the reading.
    fn update_accel(
        &mut self,
        m: &Accelerometer<T>,
        z: [T; 2],
        gate: Gate<T>,
    ) -> Result<(), Rejected>;
    /// Adds `v v^T` to the covariance (re-acquisition after a run of rejected
    /// measurements: the filter forgets what it was too sure of, along `v`).
    fn inflate(&mut self, v: &State<T>);
}
