//! The unscented Kalman filter over the same pendulum model: the covariance is propagated
//! through the nonlinear process (and the accelerometer) by `2 N` symmetric sigma points
//! `x ± sqrt(N) L_i`, `L L^T = P` (Cholesky), each of weight `1 / (2 N)` (the scaled
//! transform with alpha = 1, kappa = 0, beta = 0: all weights positive, so the propagated
//! covariance is a sum of positive terms). The encoder and the gyro are linear in the
//! state, where the unscented transform is exactly the Kalman update: they use
//! [`super::update::scalar_update`].
use super::filter::StateFilter;
use super::measurement::Accelerometer;
use super::model::{Cov, PendulumProcess, State, N};
use super::update::{add_outer, scalar_update, symmetrise, unit_update, Gate, Rejected};
use crate::Real;
use nalgebra::{Cholesky, Matrix2, SMatrix, Vector2};

/// UKF state and covariance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UnscentedKalman<T: Real> {
    /// State estimate.
    pub x: State<T>,
    /// State covariance (kept exactly symmetric).
    pub p: Cov<T>,
}

impl<T: Real> UnscentedKalman<T> {
    /// `sqrt(N) L` with `L L^T = P`; a `P` that fails Cholesky is retried once with a
    /// small diagonal load.
    fn spread(&self) -> Option<Cov<T>> {
        let scale = T::lit(N as f64).sqrt();
        if let Some(c) = Cholesky::new(self.p) {
            return Some(c.l() * scale);
        }
        let load = self.p.diagonal().max() * T::lit(1e-12) + T::lit(1e-300);
        let p = self.p + Cov::<T>::identity() * load;
        Cholesky::new(p).map(|c| c.l() * scale)
    }
}

impl<T: Real> StateFilter<T> for UnscentedKalman<T> {
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

    fn predict(&mut self, model: &PendulumProcess<T>, dt: T, q: &Cov<T>) -> bool {
        let Some(s) = self.spread() else {
            return false;
        };
        let w = T::one() / T::lit((2 * N) as f64);
        let mut pts = [State::<T>::zeros(); 2 * N];
        let mut mean = State::<T>::zeros();
        for i in 0..N {
            let c = s.column(i);
            pts[2 * i] = model.step(&(self.x + c), dt);
            pts[2 * i + 1] = model.step(&(self.x - c), dt);
            mean += (pts[2 * i] + pts[2 * i + 1]) * w;
        }
        let mut p = *q;
        for y in &pts {
            let d = y - mean;
            p += d * d.transpose() * w;
        }
        symmetrise(&mut p);
        self.x = mean;
        self.p = p;
        true
    }

    fn update_linear(&mut self, h: &State<T>, z: T, r: T, gate: Gate<T>) -> Result<(), Rejected> {
        let y = z - h.dot(&self.x);
        scalar_update(&mut self.x, &mut self.p, h, y, r, gate).map(|_| ())
    }

    fn update_unit(&mut self, idx: &[usize], z: T, r: T, gate: Gate<T>) -> Result<(), Rejected> {
        unit_update(&mut self.x, &mut self.p, idx, z, r, gate).map(|_| ())
    }

    fn inflate(&mut self, v: &State<T>) {
        add_outer(&mut self.p, v);
    }

    /// Both axes at once through the sigma points; each axis is gated on its own variance
    /// (as the EKF's sequential scalar updates are).
    fn update_accel(
        &mut self,
        m: &Accelerometer<T>,
        z: [T; 2],
        gate: Gate<T>,
    ) -> Result<(), Rejected> {
        if !(z[0].is_finite() && z[1].is_finite() && m.r.is_finite()) {
            return Err(Rejected::NotFinite);
        }
        let s = self.spread().ok_or(Rejected::NotPositive)?;
        let w = T::one() / T::lit((2 * N) as f64);
        let mut xs = [State::<T>::zeros(); 2 * N];
        let mut zs = [Vector2::<T>::zeros(); 2 * N];
        let mut zm = Vector2::<T>::zeros();
        for i in 0..N {
            let c = s.column(i);
            xs[2 * i] = self.x + c;
            xs[2 * i + 1] = self.x - c;
        }
        for (x, zp) in xs.iter().zip(zs.iter_mut()) {
            let f = m.predict(x);
            *zp = Vector2::new(f[0], f[1]);
            zm += *zp * w;
        }
        let mut pzz = Matrix2::<T>::identity() * m.r;
        let mut pxz = SMatrix::<T, N, 2>::zeros();
        for (x, zp) in xs.iter().zip(zs.iter()) {
            let dz = zp - zm;
            pzz += dz * dz.transpose() * w;
            pxz += (x - self.x) * dz.transpose() * w;
        }
        let innov = Vector2::new(z[0], z[1]) - zm;
        if (0..2).any(|i| gate.rejects(innov[i], pzz[(i, i)])) {
            return Err(Rejected::Outlier);
        }
        let inv = pzz.try_inverse().ok_or(Rejected::NotPositive)?;
        let k = pxz * inv;
        let x = self.x + k * innov;
        let mut p = self.p - k * pzz * k.transpose();
        symmetrise(&mut p);
        if x.iter().chain(p.iter()).any(|v| !v.is_finite()) {
            return Err(Rejected::NotFinite);
        }
        self.x = x;
        self.p = p;
        Ok(())
    }
}
