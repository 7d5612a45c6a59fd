//! Small fixed-size linear algebra: exact discretisation of linear continuous-time systems.
//!
//! The differentiators are continuous-time filters; to run them on samples whose spacing
//! may change (jitter, gaps), they are discretised at the actual step with the matrix
//! exponential, with a first-order hold on the input (exact for inputs that are linear
//! between samples, so no half-sample delay is added the way a zero-order hold would).

use crate::Real;
use nalgebra::{SMatrix, SVector};

/// The three integrals that discretise `x' = A x + B u` over one step `h` with the input
/// linear between samples: `E = e^{A h}`, `F = ∫_0^h e^{A s} ds`,
/// `G = ∫_0^h e^{A s} (h - s) ds`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Discretisation<T: Real, const N: usize> {
    /// e^{A h}.
    pub e: SMatrix<T, N, N>,
    /// ∫_0^h e^{A s} ds.
    pub f: SMatrix<T, N, N>,
    /// ∫_0^h e^{A s} (h - s) ds.
    pub g: SMatrix<T, N, N>,
}

/// Taylor terms used once the step is scaled down to `||A h|| <= 0.5`: the truncation
/// error is below 0.5^13 / 13! ≈ 2e-14, under f64 rounding.
const TAYLOR_TERMS: usize = 12;
/// Upper bound on the halvings, so a huge or absurd step cannot loop for long.
const MAX_SQUARINGS: u32 = 64;

/// Computes [`Discretisation`] of `a` over the step `h` by scaling and squaring.
///
/// Returns `None` if `a` or `h` is not finite or `h <= 0`.
pub fn discretise<T: Real, const N: usize>(
    a: &SMatrix<T, N, N>,
    h: T,
) -> Option<Discretisation<T, N>> {
    if !(h.is_finite() && h > T::zero()) || a.iter().any(|v| !v.is_finite()) {
        return None;
    }
    // 1-norm of A h decides how many times the step is halved.
    let norm = (0..N)
        .map(|j| a.column(j).iter().fold(T::zero(), |s, v| s + v.abs()))
        .fold(T::zero(), |m, v| if v > m { v } else { m })
        * h;
    let half = T::lit(0.5);
    let mut squarings = 0u32;
    let mut hs = h;
    let mut n = norm;
    while n > half && squarings < MAX_SQUARINGS {
        n *= half;
        hs *= half;
        squarings += 1;
    }
    // Taylor series at the scaled step: E = Σ (A hs)^k / k!, F = hs Σ (A hs)^k / (k+1)!,
    // G = hs^2 Σ (A hs)^k / (k+2)!.
    let ah = a * hs;
    let id = SMatrix::<T, N, N>::identity();
    let mut term = id; // (A hs)^k / k!
    let mut e = id;
    let mut f = id; // divided by hs until the end
    let mut g = id * half; // divided by hs^2 until the end
    for k in 1..=TAYLOR_TERMS {
        term = term * ah / T::lit(k as f64);
        e += term;
        f += term / T::lit((k + 1) as f64);
        g += term / T::lit(((k + 1) * (k + 2)) as f64);
    }
    f *= hs;
    g *= hs * hs;
    // Doubling: E(2h) = E^2, F(2h) = (I + E) F, G(2h) = h F + (I + E) G.
    for _ in 0..squarings {
        let ipe = id + e;
        g = f * hs + ipe * g;
        f = ipe * f;
        e = e * e;
        hs += hs;
    }
    Some(Discretisation { e, f, g })
}

/// One step of `x' = A x + B u` with `u` linear from `u0` (start) to `u1` (end of step):
/// `x1 = E x0 + (F - G / h) B u0 + (G / h) B u1`. Returns the two input vectors
/// `(b0, b1)` to multiply `u0` and `u1`.
pub fn first_order_hold_inputs<T: Real, const N: usize>(
    d: &Discretisation<T, N>,
    b: &SVector<T, N>,
    h: T,
) -> (SVector<T, N>, SVector<T, N>) {
    let gb = d.g * b / h;
    (d.f * b - gb, gb)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix2;

    #[test]
    fn scalar_matches_closed_form() {
        // x' = -2 x: E = e^{-2h}, F = (1 - e^{-2h}) / 2, G = (2h - 1 + e^{-2h}) / 4.
        for &h in &[1e-3, 0.1, 1.0, 30.0] {
            let a = SMatrix::<f64, 1, 1>::new(-2.0);
            let d = discretise(&a, h).unwrap();
            let ex = (-2.0 * h).exp();
            assert!((d.e[0] - ex).abs() < 1e-13, "h={h}");
            assert!((d.f[0] - (1.0 - ex) / 2.0).abs() < 1e-13, "h={h}");
            assert!((d.g[0] - (2.0 * h - 1.0 + ex) / 4.0).abs() < 1e-12, "h={h}");
        }
    }

    #[test]
    fn rotation_generator_gives_rotation() {
        // A = [[0, -w], [w, 0]] → e^{A h} is a rotation by w h.
        let w: f64 = 7.0;
        let h: f64 = 0.9;
        let a = Matrix2::new(0.0, -w, w, 0.0);
        let d = discretise(&a, h).unwrap();
        let (c, s) = ((w * h).cos(), (w * h).sin());
        assert!((d.e - Matrix2::new(c, -s, s, c)).abs().max() < 1e-12);
    }

    #[test]
    fn first_order_hold_is_exact_for_a_ramp() {
        // x' = u with u = t (ramp) over [0, h]: x(h) = h^2 / 2 from x(0) = 0.
        let a = SMatrix::<f64, 1, 1>::zeros();
        let b = SVector::<f64, 1>::new(1.0);
        let h = 0.3;
        let d = discretise(&a, h).unwrap();
        let (b0, b1) = first_order_hold_inputs(&d, &b, h);
        let x = b0[0] * 0.0 + b1[0] * h;
        assert!((x - h * h / 2.0).abs() < 1e-15);
    }

    #[test]
    fn rejects_bad_steps() {
        let a = Matrix2::<f64>::identity();
        assert!(discretise(&a, 0.0).is_none());
        assert!(discretise(&a, -1.0).is_none());
        assert!(discretise(&a, f64::NAN).is_none());
        assert!(discretise(&(a * f64::INFINITY), 1.0).is_none());
    }
}
