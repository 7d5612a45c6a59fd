//! Recursive least squares with exponential forgetting: the cheap live alternative to
//! re-running Newton's method on a window (not in the paper).
//!
//! Model `y_k = z_k . p + e_k`; each update costs O(N^2) (about 40 multiply-adds for
//! N = 4), no matter how long the effective window is. With forgetting factor `lambda`
//! the estimate minimises `sum_i lambda^(k-i) (y_i - z_i . p)^2`, an exponential window of
//! about `1 / (1 - lambda)` samples:
//!
//! ```text
//! g = P z / (lambda + z' P z),   p += g (y - z' p),   P = (P - g z' P) / lambda
//! ```
//!
//! When the data stop exciting some direction (the body at rest), dividing by `lambda`
//! makes P grow without bound ("wind-up") and the next excitation gives a jump; the
//! division is skipped while trace(P) exceeds [`RlsSettings::max_trace`].
use crate::Real;
use nalgebra::{SMatrix, SVector};

/// Settings of [`Rls`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RlsSettings<T> {
    /// Forgetting factor lambda in (0, 1]. Default 0.9995 (about 2000 samples, 2 s at
    /// 1 kHz).
    pub forgetting: T,
    /// Initial covariance diagonal, in the (scaled) parameters' units squared. Default 1.
    pub p0: T,
    /// Wind-up guard: no forgetting while trace(P) exceeds this. Default 1e3.
    pub max_trace: T,
}

impl<T: Real> Default for RlsSettings<T> {
    fn default() -> Self {
        Self {
            forgetting: T::lit(0.9995),
            p0: T::one(),
            max_trace: T::lit(1e3),
        }
    }
}

impl<T: Real> RlsSettings<T> {
    /// True when lambda is in (0, 1] and p0, max_trace are finite and positive.
    pub fn is_valid(&self) -> bool {
        let pos = |v: T| v.is_finite() && v > T::zero();
        pos(self.forgetting) && self.forgetting <= T::one() && pos(self.p0) && pos(self.max_trace)
    }
}

/// Recursive least squares over N parameters with forgetting; see the module docs.
#[derive(Debug, Clone)]
pub struct Rls<T: Real, const N: usize> {
    settings: RlsSettings<T>,
    active: [bool; N],
    params: SVector<T, N>,
    p: SMatrix<T, N, N>,
    inv_forgetting: T,
}

impl<T: Real, const N: usize> Rls<T, N> {
    /// Starts from `params`; only the entries with `active[j]` are estimated.
    pub fn new(params: SVector<T, N>, active: [bool; N], settings: RlsSettings<T>) -> Self {
        let mut r = Self {
            settings,
            active,
            params,
            p: SMatrix::zeros(),
            inv_forgetting: T::one() / settings.forgetting,
        };
        r.reset_covariance();
        r
    }

    /// Sets P back to `p0` I on the active parameters (keeps the estimate).
    pub fn reset_covariance(&mut self) {
        self.p = SMatrix::zeros();
        for j in 0..N {
            if self.active[j] {
                self.p[(j, j)] = self.settings.p0;
            }
        }
    }

    /// The current estimate.
    pub fn params(&self) -> &SVector<T, N> {
        &self.params
    }

    /// The current covariance P (scaled by the noise variance).
    pub fn covariance(&self) -> &SMatrix<T, N, N> {
        &self.p
    }

    /// Replaces the estimate (for example after the caller clipped it).
    pub fn set_params(&mut self, params: SVector<T, N>) {
        self.params = params;
    }

    /// One update with regressor `z` and observation `y`; returns the a-priori error
    /// `y - z . p`. A non-finite input is ignored (returns `None`).
    #[inline]
    pub fn update(&mut self, z: &SVector<T, N>, y: T) -> Option<T> {
        if !y.is_finite() || z.iter().any(|v| !v.is_finite()) {
            return None;
        }
        let mut za = *z;
        for j in 0..N {
            if !self.active[j] {
                za[j] = T::zero();
            }
        }
        let err = y - z.dot(&self.params);
        let pz = self.p * za;
        let denom = self.settings.forgetting + za.dot(&pz);
        if denom.partial_cmp(&T::zero()) != Some(core::cmp::Ordering::Greater) || !denom.is_finite()
        {
            return Some(err);
        }
        let inv = T::one() / denom;
        self.params += pz * (err * inv);
        // P = (P - (P z)(P z)' / denom) / lambda. P stays symmetric: update the upper
        // triangle and mirror it (half the work, and no drift to re-symmetrise). No
        // forgetting while trace(P) exceeds max_trace (wind-up guard).
        let mut trace = T::zero();
        for j in 0..N {
            trace += self.p[(j, j)] - pz[j] * pz[j] * inv;
        }
        let f = if trace < self.settings.max_trace {
            self.inv_forgetting
        } else {
            T::one()
        };
        for k in 0..N {
            let c = pz[k] * inv;
            for j in 0..=k {
                let v = (self.p[(j, k)] - pz[j] * c) * f;
                self.p[(j, k)] = v;
                self.p[(k, j)] = v;
            }
        }
        Some(err)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector2;

    #[test]
    fn recovers_a_line_and_tracks_a_change() {
        let s = RlsSettings {
            forgetting: 0.99,
            p0: 100.0,
            max_trace: 1e6,
        };
        let mut r = Rls::<f64, 2>::new(Vector2::zeros(), [true, true], s);
        for k in 0..500 {
            let x = (k as f64 * 0.37).sin();
            r.update(&Vector2::new(x, 1.0), 2.0 * x - 0.5);
        }
        assert!((r.params()[0] - 2.0).abs() < 1e-4, "{:?}", r.params());
        assert!((r.params()[1] + 0.5).abs() < 1e-4);
        for k in 0..1000 {
            let x = (k as f64 * 0.37).sin();
            r.update(&Vector2::new(x, 1.0), 3.0 * x - 0.5);
        }
        assert!((r.params()[0] - 3.0).abs() < 1e-4);
    }

    #[test]
    fn inactive_parameter_is_held_and_nan_ignored() {
        let mut r = Rls::<f64, 2>::new(
            Vector2::new(0.0, 7.0),
            [true, false],
            RlsSettings {
                p0: 100.0,
                ..RlsSettings::default()
            },
        );
        for k in 0..200 {
            let x = (k as f64 * 0.5).cos();
            // y includes the held parameter's contribution: 7 * 1.
            r.update(&Vector2::new(x, 1.0), 1.5 * x + 7.0);
        }
        assert_eq!(r.params()[1], 7.0);
        assert!((r.params()[0] - 1.5).abs() < 1e-3, "{:?}", r.params());
        assert_eq!(r.update(&Vector2::new(f64::NAN, 1.0), 1.0), None);
    }
}
