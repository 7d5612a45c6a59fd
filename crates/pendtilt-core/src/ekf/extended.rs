//! The extended Kalman filter over the pendulum state: the state goes through the nonlinear
//! process model, the covariance through its analytic Jacobian; measurements are applied
//! one scalar at a time in Joseph form ([`super::update::scalar_update`]).
use super::filter::StateFilter;
use super::measurement::Accelerometer;
use super::model::N;
use super::model::{Cov, PendulumProcess, State};
use super::update::{scalar_update, Rejected};
use crate::Real;

/// The columns `k` where row `i` of the pendulum Jacobian may be non-zero: the theta
/// chain is upper triangular, the phi chain depends on everything but the bias, the bias
/// only on itself (see [`super::model::PendulumProcess::jacobian`]).
#[inline(always)]
fn support(i: usize) -> core::ops::Range<usize> {
    match i {
        0..=2 => i..3,
        3 | 4 => 0..5,
        _ => 5..6,
    }
}

/// `F P F^T` for a Jacobian `F` with the zero pattern of [`support`], computed on the
/// upper triangle and mirrored: about 40 % of the dense products' multiplications, and
/// an exactly symmetric result.
#[inline]
pub fn propagate<T: Real>(f: &Cov<T>, p: &Cov<T>) -> Cov<T> {
    let mut m = Cov::<T>::zeros(); // F P
    for i in 0..N {
        for j in 0..N {
            let mut acc = T::zero();
            for k in support(i) {
                acc += f[(i, k)] * p[(k, j)];
            }
            m[(i, j)] = acc;
        }
    }
    let mut out = Cov::<T>::zeros();
    for i in 0..N {
        for j in i..N {
            let mut acc = T::zero();
            for k in support(j) {
                acc += m[(i, k)] * f[(j, k)];
            }
            out[(i, j)] = acc;
            out[(j, i)] = acc;
        }
    }
    out
}

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

    /// `x = f(x)`, `P = F P F^T + Q` on the upper triangle, mirrored (exactly symmetric).
    /// The products skip the Jacobian's structural zeros ([`propagate`]).
    #[inline]
    fn predict(&mut self, model: &PendulumProcess<T>, dt: T) -> bool {
        let (x, f) = model.step_with_jacobian(&self.x, dt);
        self.x = x;
        self.p = propagate(&f, &self.p) + model.q(dt);
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ekf::model::{ProcessNoise, State};
    use crate::PendulumParams;

    #[test]
    fn structured_propagation_equals_the_dense_product() {
        let m = PendulumProcess {
            params: PendulumParams {
                a: 0.04,
                b: 0.005,
                c: 0.02,
            },
            noise: ProcessNoise {
                jerk: 1.0,
                pendulum: 1.0,
                bias: 1e-6,
            },
        };
        let x = State::<f64>::from([0.1, 0.5, 2.0, 0.3, -0.7, 0.01]);
        let f = m.jacobian(&x, 1e-3);
        let a = Cov::<f64>::from_fn(|i, j| ((i * 5 + j * 3) % 7) as f64 * 0.1 + 0.01 * j as f64);
        let p = a * a.transpose();
        let dense = f * p * f.transpose();
        let fast = propagate(&f, &p);
        assert!((dense - fast).abs().max() < 1e-13);
        assert_eq!(fast, fast.transpose());
    }
}
