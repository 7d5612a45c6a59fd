//! Measurement models of the pendulum state (see [`super::model`] for the state layout):
//! what each sensor sees, and how noisily, as models of the engine
//! ([`crate::engine::Measurement`]).
//!
//! - [`Encoder`]: `z = phi`, linear.
//! - [`Gyro`]: `z = theta' + bias`, linear.
//! - [`Accelerometer`]: the specific force at a point of the body at distance `d` from the
//!   rotation axis P1 along the body's up-axis, in body axes:
//!   `f_x = g sin theta - d theta''`, `f_y = g cos theta - d theta'^2` (MODEL.md
//!   sections 1-2; `d = l12` when it sits at the pendulum pivot P2). Nonlinear.
use super::model::{State, ALPHA, BIAS, N, OMEGA, PHI, THETA};
use crate::engine::Measurement;
use crate::Real;
use nalgebra::{SMatrix, SVector, Vector1, Vector2};

/// The encoder: `z = phi`, variance `r` [rad^2].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Encoder<T> {
    /// Variance [rad^2]: quantisation `step^2 / 12` plus the encoder's own noise.
    pub r: T,
}

impl<T> Encoder<T> {
    /// The state it reads: `H` is one at these indices, zero elsewhere.
    pub const INDICES: [usize; 1] = [PHI];
}

impl<T: Real> Measurement<T, State<T>, N, 1> for Encoder<T> {
    const LINEAR: bool = true;

    #[inline]
    fn predict(&self, x: &State<T>) -> Vector1<T> {
        Vector1::new(x[PHI])
    }

    #[inline]
    fn jacobian(&self, _x: &State<T>) -> SMatrix<T, 1, N> {
        let mut h = SMatrix::<T, 1, N>::zeros();
        h[PHI] = T::one();
        h
    }

    #[inline]
    fn variance(&self) -> Vector1<T> {
        Vector1::new(self.r)
    }

    #[inline]
    fn unit_row(&self, _axis: usize) -> Option<&[usize]> {
        Some(&Self::INDICES)
    }
}

/// The gyro: `z = theta' + bias`, variance `r` [(rad/s)^2].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gyro<T> {
    /// Variance of one sample [(rad/s)^2]: `density^2 / dt` for a white-noise density.
    pub r: T,
    /// Variance the reading carries that the filter does not model (angular vibration)
    /// [(rad/s)^2]: added to the innovation variance by the gate only
    /// ([`crate::engine::Gate::floor`]).
    pub gate_floor: T,
}

impl<T> Gyro<T> {
    /// The states it reads: `H` is one at these indices, zero elsewhere.
    pub const INDICES: [usize; 2] = [OMEGA, BIAS];
}

impl<T: Real> Measurement<T, State<T>, N, 1> for Gyro<T> {
    const LINEAR: bool = true;

    #[inline]
    fn predict(&self, x: &State<T>) -> Vector1<T> {
        Vector1::new(x[OMEGA] + x[BIAS])
    }

    #[inline]
    fn jacobian(&self, _x: &State<T>) -> SMatrix<T, 1, N> {
        let mut h = SMatrix::<T, 1, N>::zeros();
        h[OMEGA] = T::one();
        h[BIAS] = T::one();
        h
    }

    #[inline]
    fn variance(&self) -> Vector1<T> {
        Vector1::new(self.r)
    }

    #[inline]
    fn unit_row(&self, _axis: usize) -> Option<&[usize]> {
        Some(&Self::INDICES)
    }
}

/// The accelerometer (two axes, independent noise of variance `r` each).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Accelerometer<T> {
    /// Gravity g [m/s^2].
    pub gravity: T,
    /// Distance d from the rotation axis P1 along the body's up-axis \[m\].
    pub distance: T,
    /// Variance of each axis [(m/s^2)^2]: sensor noise plus the vibration the filter
    /// does not model.
    pub r: T,
}

impl<T: Real> Measurement<T, State<T>, N, 2> for Accelerometer<T> {
    /// The predicted reading `[f_x, f_y]` for state `x`.
    #[inline]
    fn predict(&self, x: &State<T>) -> Vector2<T> {
        let (s, c) = x[THETA].sin_cos();
        let w = x[OMEGA];
        Vector2::new(
            self.gravity * s - self.distance * x[ALPHA],
            self.gravity * c - self.distance * w * w,
        )
    }

    /// The Jacobian rows `[d f_x / dx, d f_y / dx]` at `x`.
    #[inline]
    fn jacobian(&self, x: &State<T>) -> SMatrix<T, 2, N> {
        let (s, c) = x[THETA].sin_cos();
        let mut h = SMatrix::<T, 2, N>::zeros();
        h[(0, THETA)] = self.gravity * c;
        h[(0, ALPHA)] = -self.distance;
        h[(1, THETA)] = -self.gravity * s;
        h[(1, OMEGA)] = -T::lit(2.0) * self.distance * x[OMEGA];
        h
    }

    #[inline]
    fn variance(&self) -> Vector2<T> {
        SVector::<T, 2>::repeat(self.r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn accelerometer_at_rest_reads_gravity_and_its_jacobian_is_right() {
        let a = Accelerometer {
            gravity: 9.81,
            distance: 0.3,
            r: 1.0,
        };
        let x = State::<f64>::from([0.2, 0.0, 0.0, 0.2, 0.0, 0.0]);
        let f = a.predict(&x);
        assert!((f[1].atan2(0.0) - core::f64::consts::FRAC_PI_2).abs() < 1e-15);
        assert!((f[0].atan2(f[1]) - 0.2).abs() < 1e-15, "Eq (1) at rest");
        // Rotating: tangential and centripetal terms.
        let x = State::<f64>::from([0.2, 2.0, 3.0, 0.2, 0.0, 0.0]);
        let f = a.predict(&x);
        assert!((f[0] - (9.81 * 0.2f64.sin() - 0.9)).abs() < 1e-14);
        assert!((f[1] - (9.81 * 0.2f64.cos() - 1.2)).abs() < 1e-14);
        let jac = a.jacobian(&x);
        for j in 0..6 {
            let h = 1e-6;
            let mut xp = x;
            let mut xm = x;
            xp[j] += h;
            xm[j] -= h;
            let (fp, fm) = (a.predict(&xp), a.predict(&xm));
            for axis in 0..2 {
                let d = (fp[axis] - fm[axis]) / (2.0 * h);
                assert!((d - jac[(axis, j)]).abs() < 1e-7, "axis {axis} state {j}");
            }
        }
    }

    #[test]
    fn linear_rows_and_their_unit_form_agree() {
        let x = State::<f64>::from([0.1, 0.2, 0.3, 0.4, 0.5, 0.6]);
        let e = Encoder { r: 1.0 };
        assert_eq!(
            e.jacobian(&x),
            SMatrix::<f64, 1, 6>::from_row_slice(&[0., 0., 0., 1., 0., 0.])
        );
        assert_eq!(e.predict(&x)[0], 0.4);
        let g = Gyro {
            r: 1.0,
            gate_floor: 0.0,
        };
        assert_eq!(
            g.jacobian(&x),
            SMatrix::<f64, 1, 6>::from_row_slice(&[0., 1., 0., 0., 0., 1.])
        );
        assert!((g.predict(&x)[0] - 0.8).abs() < 1e-15);
        // The unit rows name exactly the ones of H.
        for (idx, h) in [
            (e.unit_row(0).unwrap(), e.jacobian(&x)),
            (g.unit_row(0).unwrap(), g.jacobian(&x)),
        ] {
            for j in 0..6 {
                assert_eq!(h[j] == 1.0, idx.contains(&j));
            }
        }
    }
}
