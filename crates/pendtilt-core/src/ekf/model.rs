//! The process model: the pendulum of MODEL.md section 2 (with the pivot offset l12) on a
//! body whose tilt acceleration is a random walk, plus a gyro bias that drifts.
//!
//! State `x = [theta, theta', theta'', phi, phi', bias]` (indices [`THETA`] .. [`BIAS`]).
//! Dividing the equation of motion by `m_p g l_p` gives, with a = C / (m g l),
//! b = I / (m g l), c = l12 / g,
//!
//! ```text
//! phi'' = theta'' - (a phi' + sin(phi - theta) + c (theta'' cos phi - theta'^2 sin phi)) / b
//! ```
//!
//! Translation and vibration of the rotation axis P1 are not known to the filter: they
//! force the pendulum as an unknown acceleration, modelled as white noise on phi''
//! ([`ProcessNoise::pendulum`]). theta''' is white noise ([`ProcessNoise::jerk`]), the
//! gyro bias a random walk ([`ProcessNoise::bias`]).
//!
//! One step of `dt` is a semi-implicit (symplectic) Euler step: theta, theta' are advanced
//! exactly for a constant theta''; phi' is advanced with the acceleration at the start of
//! the step and phi with the new phi'. It stays stable for `w_n dt < 2` (the filters split
//! longer steps) and keeps the undamped pendulum's energy bounded. The Jacobian is
//! analytic (its [`ProcessModel::jacobian`]).
use crate::engine::ProcessModel;
use crate::{PendulumParams, Real};
use nalgebra::{SMatrix, SVector};

/// Number of states.
pub const N: usize = 6;
/// Index of the body tilt theta \[rad\].
pub const THETA: usize = 0;
/// Index of the tilt rate theta' [rad/s].
pub const OMEGA: usize = 1;
/// Index of the tilt acceleration theta'' [rad/s^2].
pub const ALPHA: usize = 2;
/// Index of the pendulum angle relative to the body phi \[rad\].
pub const PHI: usize = 3;
/// Index of phi' [rad/s].
pub const DPHI: usize = 4;
/// Index of the gyro bias [rad/s].
pub const BIAS: usize = 5;

/// The filter state.
pub type State<T> = SVector<T, N>;
/// A state covariance (or Jacobian).
pub type Cov<T> = SMatrix<T, N, N>;

/// Continuous-time process noise densities.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProcessNoise<T> {
    /// Density of theta''' (white), [rad^2/s^5]: how fast the body's angular acceleration
    /// may change.
    pub jerk: T,
    /// Density of the unknown forcing of phi'' [rad^2/s^3]: translation and vibration of
    /// the rotation axis, `(a_perp / (b g))^2` per Hz of vibration.
    pub pendulum: T,
    /// Density of the gyro-bias random walk [(rad/s)^2/s].
    pub bias: T,
}

/// The pendulum process model with its parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PendulumProcess<T> {
    /// Normalised parameters a, b, c.
    pub params: PendulumParams<T>,
    /// Process noise densities.
    pub noise: ProcessNoise<T>,
}

impl<T: Real> PendulumProcess<T> {
    /// phi'' from the state (the equation in the module documentation).
    #[inline]
    pub fn phi_acceleration(&self, x: &State<T>) -> T {
        let p = &self.params;
        let (sp, cp) = x[PHI].sin_cos();
        let w = x[OMEGA];
        let offset = p.c * (x[ALPHA] * cp - w * w * sp);
        x[ALPHA] - (p.a * x[DPHI] + (x[PHI] - x[THETA]).sin() + offset) / p.b
    }

    /// phi'' and its partial derivatives with respect to theta, theta', theta'', phi, phi'.
    #[inline]
    fn acceleration_and_partials(&self, x: &State<T>) -> (T, [T; 5]) {
        let p = &self.params;
        let inv_b = T::one() / p.b;
        let (sp, cp) = x[PHI].sin_cos();
        let (sd, cd) = (x[PHI] - x[THETA]).sin_cos();
        let w = x[OMEGA];
        let al = x[ALPHA];
        let acc = al - (p.a * x[DPHI] + sd + p.c * (al * cp - w * w * sp)) * inv_b;
        let j = [
            cd * inv_b,
            T::lit(2.0) * p.c * w * sp * inv_b,
            T::one() - p.c * cp * inv_b,
            (p.c * (al * sp + w * w * cp) - cd) * inv_b,
            -p.a * inv_b,
        ];
        (acc, j)
    }

    /// F from the partials of phi'' (see the module documentation for the step).
    #[inline]
    fn assemble(j: &[T; 5], dt: T) -> Cov<T> {
        let z = T::zero();
        let o = T::one();
        let dt2 = dt * dt;
        #[rustfmt::skip]
        let f = Cov::<T>::from_row_slice(&[
            o, dt, T::lit(0.5) * dt2, z, z, z,
            z, o, dt, z, z, z,
            z, z, o, z, z, z,
            dt2 * j[0], dt2 * j[1], dt2 * j[2], o + dt2 * j[3], dt + dt2 * j[4], z,
            dt * j[0], dt * j[1], dt * j[2], dt * j[3], o + dt * j[4], z,
            z, z, z, z, z, o,
        ]);
        f
    }
}

/// The pendulum as a process model of the engine: no input (the gyro is a measurement),
/// a vector state (the correction is addition).
impl<T: Real> ProcessModel<T, N> for PendulumProcess<T> {
    type State = State<T>;
    type Input = ();

    /// The state after one step of `dt` seconds (see the module documentation).
    #[inline]
    fn step(&self, x: &State<T>, _u: &(), dt: T) -> State<T> {
        let half = T::lit(0.5);
        let acc = self.phi_acceleration(x);
        let dphi = x[DPHI] + dt * acc;
        State::<T>::from([
            x[THETA] + dt * x[OMEGA] + half * dt * dt * x[ALPHA],
            x[OMEGA] + dt * x[ALPHA],
            x[ALPHA],
            x[PHI] + dt * dphi,
            dphi,
            x[BIAS],
        ])
    }

    /// The state after one step and the Jacobian of [`Self::step`] at `x`, analytic,
    /// sharing the trigonometry.
    #[inline]
    fn step_with_jacobian(&self, x: &State<T>, _u: &(), dt: T) -> (State<T>, Cov<T>) {
        let (acc, j) = self.acceleration_and_partials(x);
        let half = T::lit(0.5);
        let dphi = x[DPHI] + dt * acc;
        let next = State::<T>::from([
            x[THETA] + dt * x[OMEGA] + half * dt * dt * x[ALPHA],
            x[OMEGA] + dt * x[ALPHA],
            x[ALPHA],
            x[PHI] + dt * dphi,
            dphi,
            x[BIAS],
        ]);
        (next, Self::assemble(&j, dt))
    }

    /// The Jacobian of [`Self::step`] with respect to the state at `x`.
    #[inline]
    fn jacobian(&self, x: &State<T>, _u: &(), dt: T) -> Cov<T> {
        Self::assemble(&self.acceleration_and_partials(x).1, dt)
    }

    /// The process noise covariance over a step of `dt`: the exact integrals for the
    /// theta chain driven by white theta''' and for the phi chain driven by white phi''
    /// forcing; the bias walk adds `bias dt`.
    #[inline]
    fn q(&self, dt: T) -> Cov<T> {
        let n = &self.noise;
        let dt2 = dt * dt;
        let dt3 = dt2 * dt;
        let mut q = Cov::<T>::zeros();
        let j = n.jerk;
        q[(THETA, THETA)] = j * dt3 * dt2 / T::lit(20.0);
        q[(THETA, OMEGA)] = j * dt2 * dt2 / T::lit(8.0);
        q[(THETA, ALPHA)] = j * dt3 / T::lit(6.0);
        q[(OMEGA, OMEGA)] = j * dt3 / T::lit(3.0);
        q[(OMEGA, ALPHA)] = j * dt2 / T::lit(2.0);
        q[(ALPHA, ALPHA)] = j * dt;
        q[(OMEGA, THETA)] = q[(THETA, OMEGA)];
        q[(ALPHA, THETA)] = q[(THETA, ALPHA)];
        q[(ALPHA, OMEGA)] = q[(OMEGA, ALPHA)];
        let v = n.pendulum;
        q[(PHI, PHI)] = v * dt3 / T::lit(3.0);
        q[(PHI, DPHI)] = v * dt2 / T::lit(2.0);
        q[(DPHI, PHI)] = q[(PHI, DPHI)];
        q[(DPHI, DPHI)] = v * dt;
        q[(BIAS, BIAS)] = n.bias * dt;
        q
    }

    /// The structured product (`propagate`).
    #[inline]
    fn propagate(&self, f: &Cov<T>, p: &Cov<T>) -> Cov<T> {
        propagate(f, p)
    }
}

/// `F P F^T` for the pendulum Jacobian's zero pattern (see
/// [`ProcessModel::jacobian`]): the theta chain (rows 0-2) depends only on
/// itself, the phi chain (rows 3-4) on everything but the bias, the bias (row 5) only on
/// itself. The upper triangle is mirrored, so the result is exactly symmetric. About 40 %
/// of the dense products' multiplications.
#[inline]
pub(crate) fn propagate<T: Real>(f: &Cov<T>, p: &Cov<T>) -> Cov<T> {
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

#[cfg(test)]
mod tests {
    use super::*;

    fn model(c: f64) -> PendulumProcess<f64> {
        PendulumProcess {
            params: PendulumParams {
                a: 0.04,
                b: 0.005,
                c,
            },
            noise: ProcessNoise {
                jerk: 1.0,
                pendulum: 1.0,
                bias: 1e-6,
            },
        }
    }

    #[test]
    fn phi_acceleration_matches_the_equation_of_motion_by_hand() {
        // b (phi'' - theta'') + a phi' + sin(phi - theta) + c (theta'' cos phi - theta'^2 sin phi) = 0
        let m = model(0.03);
        let x = State::<f64>::from([0.1, 0.5, 2.0, 0.3, -0.7, 0.01]);
        let acc = m.phi_acceleration(&x);
        let (a, b, c) = (0.04, 0.005, 0.03);
        let residual = b * (acc - 2.0)
            + a * -0.7
            + (0.3f64 - 0.1).sin()
            + c * (2.0 * 0.3f64.cos() - 0.25 * 0.3f64.sin());
        assert!(residual.abs() < 1e-14, "{residual}");
    }

    #[test]
    fn jacobian_matches_finite_differences() {
        let m = model(0.03);
        let x = State::<f64>::from([0.1, 0.5, 2.0, 0.3, -0.7, 0.01]);
        let dt = 2e-3;
        let f = m.jacobian(&x, &(), dt);
        for j in 0..N {
            let h = 1e-6;
            let mut xp = x;
            let mut xm = x;
            xp[j] += h;
            xm[j] -= h;
            let col = (m.step(&xp, &(), dt) - m.step(&xm, &(), dt)) / (2.0 * h);
            for i in 0..N {
                assert!(
                    (col[i] - f[(i, j)]).abs() < 1e-8,
                    "F[{i},{j}] = {} vs {}",
                    f[(i, j)],
                    col[i]
                );
            }
        }
    }

    #[test]
    fn step_with_jacobian_agrees_with_its_parts() {
        let m = model(0.03);
        let x = State::<f64>::from([0.1, 0.5, 2.0, 0.3, -0.7, 0.01]);
        let (y, f) = m.step_with_jacobian(&x, &(), 1e-3);
        assert!((y - m.step(&x, &(), 1e-3)).abs().max() < 1e-15);
        assert_eq!(f, m.jacobian(&x, &(), 1e-3));
    }

    #[test]
    fn small_oscillation_has_the_natural_frequency() {
        // Undamped, body still: phi oscillates at w_n = 1/sqrt(b); count zero crossings.
        let mut m = model(0.0);
        m.params.a = 0.0;
        let dt = 1e-3;
        let mut x = State::<f64>::from([0.0, 0.0, 0.0, 0.01, 0.0, 0.0]);
        let mut crossings = 0;
        let mut prev = x[PHI];
        let steps = 10_000; // 10 s
        for _ in 0..steps {
            x = m.step(&x, &(), dt);
            if prev > 0.0 && x[PHI] <= 0.0 || prev < 0.0 && x[PHI] >= 0.0 {
                crossings += 1;
            }
            prev = x[PHI];
        }
        let f_n = 1.0 / (2.0 * core::f64::consts::PI * 0.005f64.sqrt());
        let measured = crossings as f64 / 2.0 / 10.0;
        assert!((measured - f_n).abs() < 0.06, "{measured} vs {f_n}");
        // Energy stays bounded (symplectic): amplitude within 1 %.
        let e = 0.5 * 0.005 * x[DPHI] * x[DPHI] + (1.0 - x[PHI].cos());
        let e0 = 1.0 - 0.01f64.cos();
        assert!((e / e0 - 1.0).abs() < 0.01, "{}", e / e0);
    }

    #[test]
    fn q_is_symmetric_positive_semidefinite() {
        let q = model(0.0).q(1e-3);
        assert_eq!(q, q.transpose());
        let eig = q.symmetric_eigenvalues();
        assert!(eig.iter().all(|&e| e >= -1e-30), "{eig}");
        assert!(q[(ALPHA, ALPHA)] > 0.0 && q[(DPHI, DPHI)] > 0.0 && q[(BIAS, BIAS)] > 0.0);
    }

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
        let f = m.jacobian(&x, &(), 1e-3);
        let a = Cov::<f64>::from_fn(|i, j| ((i * 5 + j * 3) % 7) as f64 * 0.1 + 0.01 * j as f64);
        let p = a * a.transpose();
        let dense = f * p * f.transpose();
        let fast = propagate(&f, &p);
        assert!((dense - fast).abs().max() < 1e-13);
        assert_eq!(fast, fast.transpose());
    }
}
