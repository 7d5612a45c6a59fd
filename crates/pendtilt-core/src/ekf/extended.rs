//! The extended Kalman filter over the pendulum state: the state goes through the nonlinear
//! process model, the covariance through its analytic Jacobian; measurements are applied
//! one scalar at a time in Joseph form ([`super::update::scalar_update`]).
use super::filter::StateFilter;
use super::measurement::Accelerometer;
use super::model::{Cov, PendulumProcess, State};
use super::update::{scalar_update, symmetrise, Rejected};
use crate::Real;

/// EKF state and covariance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExtendedKalman<T: Real> {
    /// State estimate.
    pub x: State<T>,
    /// State covariance (kept exactly symmetric).
    pub p: Cov<T>,
}

impl<T: Real> StateFilter<T> for ExtendedKalman<T> {
    fn start(x0: State<T>, p0: Cov<T>) -> Self {
        Self { x: x0, p: p0 }
    }

    fn state(&self) -> &State<T> {
        &self.x
    }

    fn covariance(&self) -> &Cov<T> {
        &self.p
    }

    fn shift(&mut self, dx: &State<T>) {
        self.x += dx;
    }

    /// `x = f(x)`, `P = F P F^T + Q`, then `(P + P^T) / 2`.
    #[inline]
    fn predict(&mut self, model: &PendulumProcess<T>, dt: T) -> bool {
        let f = model.jacobian(&self.x, dt);
        self.x = model.step(&self.x, dt);
        self.p = f * self.p * f.transpose() + model.q(dt);
        symmetrise(&mut self.p);
        true
    }

    #[inline]
    fn update_linear(&mut self, h: &State<T>, z: T, r: T) -> Result<(), Rejected> {
        let y = z - h.dot(&self.x);
        scalar_update(&mut self.x, &mut self.p, h, y, r).map(|_| ())
    }

    /// The two axes in turn, each linearised at the current estimate.
    fn update_accel(&mut self, m: &Accelerometer<T>, z: [T; 2]) -> Result<(), Rejected> {
        for (axis, &za) in z.iter().enumerate() {
            let pred = m.predict(&self.x)[axis];
            let h = m.jacobian(&self.x)[axis];
            scalar_update(&mut self.x, &mut self.p, &h, za - pred, m.r)?;
        }
        Ok(())
    }
}
