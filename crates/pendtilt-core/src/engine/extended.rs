//! The extended Kalman filter: the state goes through the nonlinear process model, the
//! covariance through its Jacobian; measurements are applied one scalar axis at a time,
//! each linearised at the current estimate, `P - v v^T / s` kept exactly symmetric
//! (`super::update::scalar_update`). With a linear model it is the ordinary Kalman
//! filter (the paper's Eqs 2-8).
use super::filter::GaussianFilter;
use super::gate::{Gate, Rejected};
use super::measurement::Measurement;
use super::process::ProcessModel;
use super::state::ErrorState;
use super::update::{add_outer, sequential_update};
use super::{Cov, Error};
use crate::Real;
use nalgebra::SVector;

/// EKF state and error covariance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExtendedKalman<T: Real, S, const N: usize> {
    /// State estimate.
    pub x: S,
    /// Error covariance (kept exactly symmetric by the updates).
    pub p: Cov<T, N>,
}

impl<T: Real, S: ErrorState<T, N>, const N: usize> GaussianFilter<T, S, N>
    for ExtendedKalman<T, S, N>
{
    fn start(x0: S, p0: Cov<T, N>) -> Self {
        Self { x: x0, p: p0 }
    }

    fn state(&self) -> &S {
        &self.x
    }

    fn covariance(&self) -> &Cov<T, N> {
        &self.p
    }

    fn retract(&mut self, dx: &Error<T, N>) {
        self.x = self.x.retract(dx);
    }

    /// `x = f(x, u)`, `P = F P F^T + Q` ([`ProcessModel::propagate`]).
    #[inline]
    fn predict<P: ProcessModel<T, N, State = S>>(
        &mut self,
        model: &P,
        u: &P::Input,
        dt: T,
        q: &Cov<T, N>,
    ) -> bool {
        let (x, f) = model.step_with_jacobian(&self.x, u, dt);
        self.x = x;
        self.p = model.propagate(&f, &self.p) + q;
        true
    }

    #[inline]
    fn update<Z: Measurement<T, S, N, M>, const M: usize>(
        &mut self,
        meas: &Z,
        z: &SVector<T, M>,
        gate: Gate<T>,
    ) -> Result<(), Rejected> {
        sequential_update(&mut self.x, &mut self.p, meas, z, gate)
    }

    fn inflate(&mut self, v: &Error<T, N>) {
        add_outer(&mut self.p, v);
    }

    fn transform(&mut self, t: &Cov<T, N>) {
        let p = t * self.p * t.transpose();
        self.p = (p + p.transpose()) * T::lit(0.5);
    }
}
