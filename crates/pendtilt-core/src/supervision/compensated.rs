//! Compensated (Kahan) summation for the refit's sums over the window.
//!
//! Why: on a window with little excitation in some direction (the gyro and phi' nearly
//! proportional), the Newton step of the refit amplifies the rounding of its sums by the
//! Hessian's condition number. Summed plainly in f32, 1000 terms carry about 1000 times
//! the type's resolution, and the f32 refit's gains moved up to 1e-2 (relative to their
//! scale) away from the f64 ones on the same window; compensated, 5e-4
//! (docs/reliability.md section 6).

use crate::Real;

/// A running sum with Kahan's compensation: the low-order part that each addition drops is
/// kept and subtracted from the next term, so the sum carries about the rounding of its
/// terms rather than one rounding per addition.
#[derive(Debug, Clone, Copy)]
pub(super) struct Compensated<T> {
    sum: T,
    lost: T,
}

impl<T: Real> Compensated<T> {
    /// The empty sum.
    #[inline]
    pub(super) fn zero() -> Self {
        Self {
            sum: T::zero(),
            lost: T::zero(),
        }
    }

    /// Adds `x`.
    #[inline]
    pub(super) fn add(&mut self, x: T) {
        let y = x - self.lost;
        let t = self.sum + y;
        // What the addition rounded off (exactly, in round-to-nearest arithmetic).
        self.lost = (t - self.sum) - y;
        self.sum = t;
    }

    /// The sum.
    #[inline]
    pub(super) fn value(&self) -> T {
        self.sum
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Terms of mixed size and sign like the refit's (a large mean, small alternating
    /// parts): the compensated f32 sum is within 2 ulp of the exact one, the plain f32 sum
    /// far off.
    #[test]
    fn compensated_f32_sum_is_exact_to_its_terms_rounding() {
        let terms: std::vec::Vec<f32> = (0..1000)
            .map(|i| {
                let t = i as f64 * 0.01;
                (0.3 + 1e-3 * (37.0 * t).sin() + 7e-3 * t.cos()) as f32
            })
            .collect();
        let exact: f64 = terms.iter().map(|&v| v as f64).sum();
        let mut c = Compensated::<f32>::zero();
        let mut plain = 0.0f32;
        for &v in &terms {
            c.add(v);
            plain += v;
        }
        let err_c = (c.value() as f64 - exact).abs();
        let err_plain = (plain as f64 - exact).abs();
        assert!(err_c <= 2.0 * f32::EPSILON as f64 * exact, "{err_c}");
        assert!(err_plain > 10.0 * err_c.max(1e-9), "{err_plain} {err_c}");
    }
}
