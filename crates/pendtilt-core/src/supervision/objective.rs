//! What Newton's method minimises ([`Objective`]) and the objective's finite differences
//! and changes formed from those of the mean square, without cancellation.
use super::newton::CostDifferences;
use crate::Real;
use nalgebra::{SMatrix, SVector};

/// What Newton's method minimises: the paper's RMS (Eqs 23 and 29) or its square.
///
/// Both have the same minimiser. The RMS is the paper's; far from its minimum it is
/// nearly a cone, where Newton's step overshoots and must be halved (see
/// [`super::newton`]). The mean square is close to a quadratic in the parameters (the
/// asin argument is linear in them), so Newton converges on it in very few iterations.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Objective {
    /// `sqrt(mean(r^2))`, Eqs (23), (29) as printed (default).
    #[default]
    Rms,
    /// `mean(r^2)`.
    MeanSquare,
}

impl Objective {
    /// The objective from a sum of squared residuals over `n` samples (NaN when `n` = 0).
    #[inline]
    pub fn from_sum<T: Real>(self, sum_sq: T, n: usize) -> T {
        if n == 0 {
            return T::nan();
        }
        let ms = sum_sq / T::lit(n as f64);
        match self {
            Objective::Rms => ms.sqrt(),
            Objective::MeanSquare => ms,
        }
    }
}

/// `sqrt(max(m, 0))`.
#[inline]
fn root<T: Real>(m: T) -> T {
    m.max(T::zero()).sqrt()
}

/// `num / den`, 0 when `den` is not positive (a zero cost has no slope to speak of).
#[inline]
fn ratio<T: Real>(num: T, den: T) -> T {
    if den > T::zero() {
        num / den
    } else {
        T::zero()
    }
}

/// The objective's value and finite differences from those of the mean square (`m0` the
/// mean square, `m1[j]`, `m2[j][k]` its first and second differences, upper triangle).
/// For the RMS, with `R(x) = sqrt(m0 + x)`, the first difference is
/// `a / (R(a) + R(0))` and the second `R(a + b + e) - R(a + b) + (R(a + b) - R(a) - R(b) + R(0))`
/// is written as `e / (R(a+b+e) + R(a+b)) - a b (1/(R(b) + R(a+b)) + 1/(R(0) + R(a))) /
/// ((R(a+b) + R(a)) (R(b) + R(0)))`: terms without cancellation.
#[allow(clippy::needless_range_loop)] // j, k index several arrays at once
pub(super) fn objective_differences<T: Real>(
    objective: Objective,
    m0: T,
    m1: &[T; 4],
    m2: &[[T; 4]; 4],
    evaluations: usize,
) -> (T, CostDifferences<T, 4>) {
    let mut d = CostDifferences {
        first: SVector::<T, 4>::zeros(),
        second: SMatrix::<T, 4, 4>::zeros(),
        evaluations,
    };
    match objective {
        Objective::MeanSquare => {
            for j in 0..4 {
                d.first[j] = m1[j];
                for k in j..4 {
                    d.second[(j, k)] = m2[j][k];
                    d.second[(k, j)] = m2[j][k];
                }
            }
            (m0, d)
        }
        Objective::Rms => {
            let f0 = root(m0);
            let r = |x: T| root(m0 + x);
            for j in 0..4 {
                d.first[j] = ratio(m1[j], r(m1[j]) + f0);
            }
            for j in 0..4 {
                for k in j..4 {
                    let (a, b, e) = (m1[j], m1[k], m2[j][k]);
                    let rab = r(a + b);
                    let ra = r(a);
                    let rb = r(b);
                    let inner = ratio(T::one(), rb + rab) + ratio(T::one(), f0 + ra);
                    let v =
                        ratio(e, r(a + b + e) + rab) - ratio(a * b * inner, (rab + ra) * (rb + f0));
                    d.second[(j, k)] = v;
                    d.second[(k, j)] = v;
                }
            }
            (f0, d)
        }
    }
}

/// The objective's change from that of the sum of squares (`s0` the mean square at the
/// start, `dm` the change of the mean square): `(F(q) - F(p), F(q))`.
#[inline]
pub(super) fn objective_change<T: Real>(objective: Objective, m0: T, dm: T) -> (T, T) {
    match objective {
        Objective::MeanSquare => (dm, m0 + dm),
        Objective::Rms => {
            let f1 = root(m0 + dm);
            let f0 = root(m0);
            (ratio(dm, f1 + f0), f1)
        }
    }
}
