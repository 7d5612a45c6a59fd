//! Measurement models of the pendulum state (see [`super::model`] for the state layout):
//! what each sensor sees, and how noisily.
//!
//! - [`Encoder`]: `z = phi`, linear.
//! - [`Gyro`]: `z = theta' + bias`, linear.
//! - [`Accelerometer`]: the specific force at a point of the body at distance `d` from the
//!   rotation axis P1 along the body's up-axis, in body axes:
//!   `f_x = g sin theta - d theta''`, `f_y = g cos theta - d theta'^2` (MODEL.md
//!   sections 1-2; `d = l12` when it sits at the pendulum pivot P2). Nonlinear.
use super::model::{State, ALPHA, BIAS, OMEGA, PHI, THETA};
use crate::Real;

/// A scalar linear measurement `z = h . x + v`, `v ~ N(0, r)`.
pub trait ScalarMeasurement<T: Real> {
    /// The row `h`.
    fn h(&self) -> State<T>;
    /// The noise variance `r` for this sample.
    fn r(&self) -> T;
}

/// The encoder: `z = phi`, variance `r` [rad^2].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Encoder<T> {
    /// Variance [rad^2]: quantisation `step^2 / 12` plus the encoder's own noise.
    pub r: T,
}

impl<T> Encoder<T> {
    /// The state it reads: `h` is one at these indices, zero elsewhere.
    pub const INDICES: [usize; 1] = [PHI];
}

impl<T: Real> ScalarMeasurement<T> for Encoder<T> {
    #[inline]
    fn h(&self) -> State<T> {
        let mut h = State::<T>::zeros();
        h[PHI] = T::one();
        h
    }
    #[inline]
    fn r(&self) -> T {
        self.r
    }
}

/// The gyro: `z = theta' + bias`, variance `r` [(rad/s)^2].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gyro<T> {
    /// Variance of one sample [(rad/s)^2]: `density^2 / dt` for a white-noise density.
    pub r: T,
}

impl<T> Gyro<T> {
    /// The states it reads: `h` is one at these indices, zero elsewhere.
    pub const INDICES: [usize; 2] = [OMEGA, BIAS];
}

impl<T: Real> ScalarMeasurement<T> for Gyro<T> {
    #[inline]
    fn h(&self) -> State<T> {
        let mut h = State::<T>::zeros();
        h[OMEGA] = T::one();
        h[BIAS] = T::one();
        h
    }
    #[inline]
    fn r(&self) -> T {
        self.r
    }
}

/// The accelerometer (two axes, independent noise of variance `r` each).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Accelerometer<T> {
    /// Gravity g [m/s^2].
    pub gravity: T,
    /// Distance d from the rotation axis P1 along the body's up-axis [m].
    pub distance: T,
    /// Variance of each axis [(m/s^2)^2]: sensor noise plus the vibration the filter
    /// does not model.
    pub r: T,
}

impl<T: Real> Accelerometer<T> {
    /// The predicted reading `[f_x, f_y]` for state `x`.
    #[inline]
    pub fn predict(&self, x: &State<T>) -> [T; 2] {
        let (s, c) = x[THETA].sin_cos();
        let w = x[OMEGA];
        [
            self.gravity * s - self.distance * x[ALPHA],
            self.gravity * c - self.distance * w * w,
        ]
    }

    /// The Jacobian rows `[d f_x / dx, d f_y / dx]` at `x`.
    #[inline]
    pub fn jacobian(&self, x: &State<T>) -> [State<T>; 2] {
        let (s, c) = x[THETA].sin_cos();
        let mut hx = State::<T>::zeros();
        hx[THETA] = self.gravity * c;
        hx[ALPHA] = -self.distance;
        let mut hy = State::<T>::zeros();
        hy[THETA] = -self.gravity * s;
        hy[OMEGA] = -T::lit(2.0) * self.distance * x[OMEGA];
        [hx, hy]
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
            for (axis, row) in jac.iter().enumerate() {
                let d = (fp[axis] - fm[axis]) / (2.0 * h);
                assert!((d - row[j]).abs() < 1e-7, "axis {axis} state {j}");
            }
        }
    }

    #[test]
    fn linear_rows() {
        assert_eq!(
            Encoder { r: 1.0 }.h(),
            State::<f64>::from([0., 0., 0., 1., 0., 0.])
        );
        assert_eq!(
            Gyro { r: 1.0 }.h(),
            State::<f64>::from([0., 1., 0., 0., 0., 1.])
        );
    }
}
