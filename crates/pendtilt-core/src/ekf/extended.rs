//! The extended Kalman filter over the pendulum state: the state goes through the nonlinear
//! process model, the covariance through its analytic Jacobian; measurements are applied
//! one scalar at a time, `P - v v^T / s` kept exactly symmetric
//! ([`super::update::scalar_update`]).
use super::filter::StateFilter;
use super::measurement::Accelerometer;
use super::model::N;
use super::model::{Cov, PendulumProcess, State};
use super::update::{add_outer, scalar_update, unit_update, Gate, Rejected};
use crate::Real;

/// `F P F^T` for the pendulum Jacobian's zero pattern (see
/// [`super::model::PendulumProcess::jacobian`]): the theta chain (rows 0-2) depends only on
/// itself, the phi chain (rows 3-4) on everything but the bias, the bias (row 5) only on
/// itself. The upper triangle is mirrored, so the result is exactly symmetric. About 40 %
/// of the dense products' multiplications.
#[inline]
pub fn propagate<T: Real>(f: &Cov<T>, p: &Cov<T>) -> Cov<T> {
    let mut fa = [[T::zero(); N]; N];
    let mut pa = [[T::zero(); N]; N];
    for i in 0..N {
        for j in 0..N {
            fa[i][j] = f[(i, j)];
            pa[i][j] = p[(i, j)];
        }
    }
    // m = F P, row by row.
    let mut m = [[T::zero(); N]; N];
    for j in 0..N {
        m[0][j] = fa[0][0] * pa[0][j] + fa[0][1] * pa[1][j] + fa[0][2] * pa[2][j];
        m[1][j] = fa[1][1] * pa[1][j] + fa[1][2] * pa[2][j];
        m[2][j] = fa[2][2] * pa[2][j];
        for i in 3..5 {
            m[i][j] = fa[i][0] * pa[0][j]
                + fa[i][1] * pa[1][j]
                + fa[i][2] * pa[2][j]
                + fa[i][3] * pa[3][j]
                + fa[i][4] * pa[4][j];
        }
        m[5][j] = fa[5][5] * pa[5][j];
    }
    // out = m F^T, upper triangle, mirrored.
    let mut out = Cov::<T>::zeros();
    for i in 0..N {
        let r = &m[i];
        let row = [
            r[0] * fa[0][0] + r[1] * fa[0][1] + r[2] * fa[0][2],
            r[1] * fa[1][1] + r[2] * fa[1][2],
            r[2] * fa[2][2],
            r[0] * fa[3][0] + r[1] * fa[3][1] + r[2] * fa[3][2] + r[3] * fa[3][3] + r[4] * fa[3][4],
            r[0] * fa[4][0] + r[1] * fa[4][1] + r[2] * fa[4][2] + r[3] * fa[4][3] + r[4] * fa[4][4],
            r[5] * fa[5][5],
        ];
        for j in i..N {
            out[(i, j)] = row[j];
            out[(j, i)] = row[j];
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
    fn predict(&mut self, model: &PendulumProcess<T>, dt: T, q: &Cov<T>) -> bool {
        let (x, f) = model.step_with_jacobian(&self.x, dt);
        self.x = x;
        self.p = propagate(&f, &self.p) + q;
        true
    }

    #[inline]
    fn update_unit(&mut self, idx: &[usize], z: T, r: T, gate: Gate<T>) -> Result<(), Rejected> {
        unit_update(&mut self.x, &mut self.p, idx, z, r, gate).map(|_| ())
    }

    #[inline]
    fn update_linear(&mut self, h: &State<T>, z: T, r: T, gate: Gate<T>) -> Result<(), Rejected> {
        let y = z - h.dot(&self.x);
        scalar_update(&mut self.x, &mut self.p, h, y, r, gate).map(|_| ())
    }

    /// The two axes in turn, each linearised at the current estimate and gated on its
    /// own; a rejected axis stops there (the first may have been applied).
    fn update_accel(
        &mut self,
        m: &Accelerometer<T>,
        z: [T; 2],
        gate: Gate<T>,
    ) -> Result<(), Rejected> {
        for (axis, &za) in z.iter().enumerate() {
            let pred = m.predict(&self.x)[axis];
            let h = m.jacobian(&self.x)[axis];
            scalar_update(&mut self.x, &mut self.p, &h, za - pred, m.r, gate)?;
        }
        Ok(())
    }

    fn inflate(&mut self, v: &State<T>) {
        add_outer(&mut self.p, v);
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
