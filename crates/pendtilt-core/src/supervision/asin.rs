//! The asin arithmetic of the refit: differences of asin without cancellation, its
//! series for small arguments, and the per-sample changes of the Eq (30) asin term under
//! Newton's small steps (Taylor expansion).
//!
//! Why: the second difference of the cost is about `dp^2` (1e-8) of the cost, below
//! f32's resolution, so every change of `asin` the refit needs is formed here as a change,
//! never as the difference of two nearly equal asin values (see [`super::supervised`]).
use crate::estimators::equations::clamped_asin;
use crate::Real;

/// Largest asin argument and perturbation for which the third-order Taylor expansion of
/// asin is used for the finite differences: the fourth-order remainder is then below
/// 1e-9 of the first-order term (the fourth derivative of asin is below 400 for
/// |u| <= 0.8).
const TAYLOR_MAX_U: f64 = 0.8;
const TAYLOR_MAX_D: f64 = 5e-4;

/// The pairs (j, k), j <= k < 3, of the second changes of the asin.
pub(super) const PAIRS: [(usize, usize); 6] = [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)];

/// `asin(u1) - asin(u0)` without the cancellation of subtracting two nearly equal values:
/// for `u0`, `u1` of the same sign it is `asin(d (u1 + u0) / (u1 w0 + u0 w1))` with
/// `d = u1 - u0` (computed by the caller from differences, not from `u1` and `u0`) and
/// `w = sqrt(1 - u^2)` (0 marks an argument outside (-1, 1), clamped like the estimator).
#[inline]
pub(super) fn asin_diff<T: Real>(u0: T, w0: T, u1: T, w1: T, d: T) -> T {
    let zero = T::zero();
    if w0 > zero && w1 > zero && u0 * u1 > zero {
        small_asin(d * (u1 + u0) / (u1 * w0 + u0 * w1))
    } else {
        clamped_asin(u1).0 - clamped_asin(u0).0
    }
}

/// `asin(z)`, by its series for |z| <= 1/16 (to z^13: the first term left out is below
/// 2e-19 of the result, so this is asin to rounding) and by the library otherwise. The
/// differences of asin that the refit takes (between consecutive samples, and for small
/// steps) are nearly all that small; the series costs a fraction of the library's asin.
#[inline]
fn small_asin<T: Real>(z: T) -> T {
    if z.abs() <= T::lit(0.0625) {
        let z2 = z * z;
        // Coefficients (2k)! / (4^k (k!)^2 (2k + 1)), k = 1..6.
        let p = T::lit(231.0 / 13312.0);
        let p = p * z2 + T::lit(63.0 / 2816.0);
        let p = p * z2 + T::lit(35.0 / 1152.0);
        let p = p * z2 + T::lit(5.0 / 112.0);
        let p = p * z2 + T::lit(3.0 / 40.0);
        let p = p * z2 + T::lit(1.0 / 6.0);
        z + z * z2 * p
    } else {
        z.asin()
    }
}

/// `sqrt(1 - u^2)` for |u| < 1, else 0 (the asin is clamped there).
#[inline]
pub(super) fn cos_of_asin<T: Real>(u: T) -> T {
    let one = T::one();
    if u.abs() < one {
        ((one - u) * (one + u)).sqrt()
    } else {
        T::zero()
    }
}

/// The changes of `s = asin(u) + N G_k` at one sample under Newton's steps: `d[m]` the
/// change of `u` for a step of gain m (K, L, M), `dn` the change of the N term. Returns
/// the first changes (K, L, M, N) and the second changes of the asin for the [`PAIRS`].
///
/// The third-order Taylor expansion `c d + s2 d^2 / 2 + s3 d^3 / 6` (c, s2, s3 the first
/// three derivatives of asin at `u`; exact to rounding for the small steps dp makes), or,
/// for large arguments or steps, [`asin_diff`]. `w` is [`cos_of_asin`] of `u`.
#[inline]
pub(super) fn asin_changes<T: Real>(u: T, w: T, d: [T; 3], dn: T) -> ([T; 4], [T; 6]) {
    let zero = T::zero();
    let one = T::one();
    let half = T::lit(0.5);
    let sixth = T::lit(1.0 / 6.0);
    let mut ds = [zero, zero, zero, dn];
    let mut d2 = [zero; 6];
    let dmax = d[0].abs().max(d[1].abs()).max(d[2].abs());
    if w > zero && u.abs() <= T::lit(TAYLOR_MAX_U) && dmax <= T::lit(TAYLOR_MAX_D) {
        let c = one / w;
        let c2 = c * c;
        let s2 = u * c * c2;
        let s3 = (one + T::lit(2.0) * u * u) * c2 * c2 * c;
        for m in 0..3 {
            ds[m] = d[m] * (c + d[m] * (half * s2 + sixth * s3 * d[m]));
        }
        for (p, &(a, b)) in PAIRS.iter().enumerate() {
            d2[p] = d[a] * d[b] * (s2 + half * s3 * (d[a] + d[b]));
        }
    } else {
        // Rare (near the ends of the asin, or a large dp): exact differences.
        let ch = |dd: T| {
            let u1 = u + dd;
            asin_diff(u, w, u1, cos_of_asin(u1), dd)
        };
        for m in 0..3 {
            ds[m] = ch(d[m]);
        }
        for (p, &(a, b)) in PAIRS.iter().enumerate() {
            d2[p] = ch(d[a] + d[b]) - ds[a] - ds[b];
        }
    }
    (ds, d2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn series_asin_equals_the_library_asin() {
        for i in 0..=1000 {
            let z = -0.0625 + 0.125 * i as f64 / 1000.0;
            let (a, b) = (small_asin(z), z.asin());
            assert!(
                (a - b).abs() <= 2.0 * f64::EPSILON * b.abs(),
                "{z}: {a} {b}"
            );
        }
        assert_eq!(small_asin(0.5f64), 0.5f64.asin());
    }

    #[test]
    fn asin_difference_is_exact_near_equal_arguments() {
        let (u0, d) = (0.3f32, 1e-6f32);
        let u1 = u0 + d;
        let got = asin_diff(u0, cos_of_asin(u0), u1, cos_of_asin(u1), u1 - u0);
        let exact = (u1 as f64).asin() - (u0 as f64).asin();
        assert!(((got as f64) - exact).abs() < 1e-6 * exact, "{got} {exact}");
        // Clamped ends and a sign change.
        assert_eq!(
            asin_diff(0.5, cos_of_asin(0.5), 1.5, 0.0, 1.0),
            0.5f64.asin().mul_add(-1.0, core::f64::consts::FRAC_PI_2)
        );
        let v = asin_diff(-0.2, cos_of_asin(-0.2), 0.1, cos_of_asin(0.1), 0.3f64);
        assert!((v - (0.1f64.asin() + 0.2f64.asin())).abs() < 1e-15);
    }

    /// The Taylor changes equal the exact asin differences (f64) within the Lagrange bound
    /// of the fourth-order remainder (the fourth derivative of asin is below 400 for
    /// |u| <= 0.8), and the exact branch (u = 0.95) to rounding.
    #[test]
    fn taylor_changes_equal_exact_differences() {
        let remainder = |d: f64| 400.0 / 24.0 * d.powi(4) + 1e-15;
        for &u in &[-0.7f64, -0.1, 0.0, 0.35, 0.79, 0.95] {
            let w = cos_of_asin(u);
            let d = [1e-4, -3e-4, 2e-4];
            let (ds, d2) = asin_changes(u, w, d, 0.25);
            assert_eq!(ds[3], 0.25);
            for m in 0..3 {
                let exact = (u + d[m]).asin() - u.asin();
                assert!((ds[m] - exact).abs() < remainder(d[m]), "{u} {m}");
            }
            for (p, &(a, b)) in PAIRS.iter().enumerate() {
                let da = (u + d[a]).asin() - u.asin();
                let db = (u + d[b]).asin() - u.asin();
                let exact = (u + d[a] + d[b]).asin() - u.asin() - da - db;
                let tol = remainder(d[a].abs() + d[b].abs());
                assert!((d2[p] - exact).abs() < tol, "{u} {p}: {} vs {exact}", d2[p]);
            }
        }
    }
}
