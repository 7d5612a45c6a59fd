//! The unscented Kalman filter on the same models: the covariance is propagated through
//! the nonlinear process (and a nonlinear measurement) by `2 N` symmetric sigma points
//! `x ⊞ ±sqrt(N) L_i`, `L L^T = P` (Cholesky), each of weight `1 / (2 N)` (the scaled
//! transform with alpha = 1, kappa = 0, beta = 0: all weights positive, so the propagated
//! covariance is a sum of positive terms). A linear measurement
//! ([`Measurement::LINEAR`]), where the unscented transform is exactly the Kalman update,
//! uses `super::update::scalar_update` as the EKF does.
use super::filter::GaussianFilter;
use super::gate::{Gate, Rejected};
use super::measurement::Measurement;
use super::process::ProcessModel;
use super::state::ErrorState;
use super::update::{add_outer, sequential_update, symmetrise};
use super::{Cov, Error};
use crate::Real;
use nalgebra::{Cholesky, SMatrix, SVector};

/// UKF state and error covariance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UnscentedKalman<T: Real, S, const N: usize> {
    /// State estimate.
    pub x: S,
    /// Error covariance (kept exactly symmetric).
    pub p: Cov<T, N>,
}

impl<T: Real, S: ErrorState<T, N>, const N: usize> UnscentedKalman<T, S, N> {
    /// `sqrt(N) L` with `L L^T = P`; a `P` that fails Cholesky is retried once with a
    /// small diagonal load.
    fn spread(&self) -> Option<Cov<T, N>> {
        let scale = T::lit(N as f64).sqrt();
        if let Some(c) = Cholesky::new(self.p) {
            return Some(c.l() * scale);
        }
        let load = self.p.diagonal().max() * T::lit(1e-12) + T::lit(1e-300);
        let p = self.p + Cov::<T, N>::identity() * load;
        Cholesky::new(p).map(|c| c.l() * scale)
    }

    /// The sigma points `x ⊞ c_i`, `x ⊞ -c_i` for the columns `c_i` of `s`, each mapped
    /// by `f` (a loop, not `array::map`: the latter copied the arrays and cost the UKF
    /// a fifth of its time).
    #[inline(always)]
    fn sigma_points(&self, s: &Cov<T, N>, mut f: impl FnMut(S) -> S) -> [[S; 2]; N] {
        let mut pts = [[self.x; 2]; N];
        for (i, pair) in pts.iter_mut().enumerate() {
            let c: Error<T, N> = s.column(i).into_owned();
            pair[0] = f(self.x.retract(&c));
            pair[1] = f(self.x.retract(&-c));
        }
        pts
    }

    /// A nonlinear reading through the sigma points, all axes at once; each axis is gated
    /// on its own variance (as the EKF's sequential scalar updates are).
    fn unscented_update<Z: Measurement<T, S, N, M>, const M: usize>(
        &mut self,
        meas: &Z,
        z: &SVector<T, M>,
        gate: Gate<T>,
    ) -> Result<(), Rejected> {
        let r = meas.variance();
        if z.iter().chain(r.iter()).any(|v| !v.is_finite()) {
            return Err(Rejected::NotFinite);
        }
        let s = self.spread().ok_or(Rejected::NotPositive)?;
        let w = T::one() / T::lit((2 * N) as f64);
        let xs = self.sigma_points(&s, |x| x);
        let mut zs = [[SVector::<T, M>::zeros(); 2]; N];
        let mut zm = SVector::<T, M>::zeros();
        for (pair, zpair) in xs.iter().zip(zs.iter_mut()) {
            for (x, zp) in pair.iter().zip(zpair.iter_mut()) {
                *zp = meas.predict(x);
                zm += *zp * w;
            }
        }
        let mut pzz = SMatrix::<T, M, M>::from_diagonal(&r);
        let mut pxz = SMatrix::<T, N, M>::zeros();
        for (pair, zpair) in xs.iter().zip(zs.iter()) {
            for (x, zp) in pair.iter().zip(zpair.iter()) {
                let dz = zp - zm;
                pzz += dz * dz.transpose() * w;
                pxz += self.x.local(x) * dz.transpose() * w;
            }
        }
        let innov = z - zm;
        if (0..M).any(|i| gate.rejects(innov[i], pzz[(i, i)])) {
            return Err(Rejected::Outlier);
        }
        let inv = pzz.try_inverse().ok_or(Rejected::NotPositive)?;
        let k = pxz * inv;
        let x = self.x.retract(&(k * innov));
        let mut p = self.p - k * pzz * k.transpose();
        symmetrise(&mut p);
        if !x.is_finite() || p.iter().any(|v| !v.is_finite()) {
            return Err(Rejected::NotFinite);
        }
        self.x = x;
        self.p = p;
        Ok(())
    }
}

impl<T: Real, S: ErrorState<T, N>, const N: usize> GaussianFilter<T, S, N>
    for UnscentedKalman<T, S, N>
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

    fn predict<P: ProcessModel<T, N, State = S>>(
        &mut self,
        model: &P,
        u: &P::Input,
        dt: T,
        q: &Cov<T, N>,
    ) -> bool {
        let Some(s) = self.spread() else {
            return false;
        };
        let w = T::one() / T::lit((2 * N) as f64);
        let pts = self.sigma_points(&s, |x| model.step(&x, u, dt));
        let centre = pts.first().map_or(self.x, |pair| pair[0]);
        let mean = S::mean_of_pairs(&centre, &pts, w);
        let mut p = *q;
        for pair in &pts {
            for y in pair {
                p += S::weighted_outer(&mean.local(y), w);
            }
        }
        symmetrise(&mut p);
        self.x = mean;
        self.p = p;
        true
    }

    fn update<Z: Measurement<T, S, N, M>, const M: usize>(
        &mut self,
        meas: &Z,
        z: &SVector<T, M>,
        gate: Gate<T>,
    ) -> Result<(), Rejected> {
        if Z::LINEAR {
            sequential_update(&mut self.x, &mut self.p, meas, z, gate)
        } else {
            self.unscented_update(meas, z, gate)
        }
    }

    fn inflate(&mut self, v: &Error<T, N>) {
        add_outer(&mut self.p, v);
    }

    fn transform(&mut self, t: &Cov<T, N>) {
        let p = t * self.p * t.transpose();
        self.p = (p + p.transpose()) * T::lit(0.5);
    }
}
