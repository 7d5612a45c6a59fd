//! The ring buffer of the Eq (29) terms and the passes over its window that Newton's
//! refit takes: the cost, the finite differences in one pass, and the change for a step.
use super::asin::{asin_changes, asin_diff, cos_of_asin, PAIRS};
use super::compensated::Compensated;
use super::Objective;
use crate::estimators::equations::clamped_asin;
use crate::Real;

/// Sums of one pass for Newton: `S0 = sum r^2`, the first and second differences of the
/// sum (upper triangle), and the residual count, each summed with compensation. See
/// [`Ring::differences`].
pub(super) struct PassSums<T> {
    /// `S0`, the sum of squared residuals at the gains of the pass.
    pub s0: Compensated<T>,
    /// `S(g + dg_j) - S0`.
    pub first: [Compensated<T>; 4],
    /// `S(g + dg_j + dg_k) - S(g + dg_j) - S(g + dg_k) + S0`, upper triangle.
    pub second: [[Compensated<T>; 4]; 4],
    /// Residuals summed.
    pub count: usize,
}

impl<T: Real> PassSums<T> {
    /// Adds one residual `r`, with `a` the changes of its rate term for each step (K, L,
    /// M, N) and `b` the second changes for the asin's [`PAIRS`]: the perturbed residual
    /// is `r + a_j`, and `(r + a_j)^2 - r^2 = a_j (2 r + a_j)`.
    #[inline]
    #[allow(clippy::needless_range_loop)] // m indexes two arrays
    fn add(&mut self, r: T, a: &[T; 4], b: &[T; 6]) {
        let two = T::lit(2.0);
        let r2 = two * r;
        self.s0.add(r * r);
        for (f, &am) in self.first.iter_mut().zip(a) {
            f.add(am * (r2 + am));
        }
        for (p, &(ja, kb)) in PAIRS.iter().enumerate() {
            let b = b[p];
            self.second[ja][kb].add(r2 * b + two * a[ja] * a[kb] + b * (two * (a[ja] + a[kb]) + b));
        }
        // Pairs with N: s is additive in N, so its second change is 0.
        for m in 0..4 {
            self.second[m][3].add(two * a[m] * a[3]);
        }
        self.count += 1;
    }
}

/// Ring buffer of the Eq (29) terms: for each sample the Eq (30) inputs
/// `x = [phi', phi'', G_d, G_k]`, the parameter-free part `y` of the residual and `1/dt`;
/// and, from the last [`Ring::differences`] pass, the asin argument `u`, `sqrt(1 - u^2)` and
/// the residual, which the step evaluations of the same refit reuse.
#[derive(Debug, Clone)]
pub(super) struct Ring<T, const CAP: usize> {
    x: [[T; 4]; CAP],
    y: [T; CAP],
    inv_dt: [T; CAP],
    linked: [bool; CAP],
    u0: [T; CAP],
    w0: [T; CAP],
    r0: [T; CAP],
    head: usize,
    len: usize,
}

impl<T: Real, const CAP: usize> Ring<T, CAP> {
    pub(super) fn new() -> Self {
        Self {
            x: [[T::zero(); 4]; CAP],
            y: [T::zero(); CAP],
            inv_dt: [T::zero(); CAP],
            linked: [false; CAP],
            u0: [T::zero(); CAP],
            w0: [T::zero(); CAP],
            r0: [T::zero(); CAP],
            head: 0,
            len: 0,
        }
    }

    pub(super) fn clear(&mut self) {
        self.head = 0;
        self.len = 0;
    }

    #[inline]
    pub(super) fn push(&mut self, x: [T; 4], y: T, inv_dt: T, linked: bool) {
        if CAP == 0 {
            return;
        }
        self.x[self.head] = x;
        self.y[self.head] = y;
        self.inv_dt[self.head] = inv_dt;
        self.linked[self.head] = linked;
        self.head += 1;
        if self.head == CAP {
            self.head = 0;
        }
        if self.len < CAP {
            self.len += 1;
        }
    }

    /// Samples held (at most `CAP`).
    #[inline]
    pub(super) fn len(&self) -> usize {
        self.len
    }

    /// The window's first slot and length.
    #[inline]
    fn span(&self, window: usize) -> (usize, usize) {
        let n = window.min(self.len);
        ((self.head + CAP - n) % CAP.max(1), n)
    }

    /// Eq (29) over the last `window` samples for the real gains `g` (K, L, M, N).
    pub(super) fn cost(&self, g: &[T; 4], window: usize, objective: Objective) -> T {
        let (mut j, n) = self.span(window);
        let mut sum = T::zero();
        let mut count = 0usize;
        let mut s_prev = T::zero();
        for i in 0..n {
            let x = &self.x[j];
            let (a, _) = clamped_asin(g[0] * x[0] + g[1] * x[1] + g[2] * x[2]);
            let s = a + g[3] * x[3];
            if i > 0 && self.linked[j] {
                let r = (s - s_prev) * self.inv_dt[j] - self.y[j];
                sum += r * r;
                count += 1;
            }
            s_prev = s;
            j += 1;
            if j == CAP {
                j = 0;
            }
        }
        objective.from_sum(sum, count)
    }

    /// One pass over the window at the real gains `g` for Newton's finite differences
    /// with the real-gain steps `dg` (dp times each parameter's scale): the sum of squared
    /// residuals `S0`, and, accumulated per sample so that nothing is a difference of two
    /// nearly equal sums, `S(g + dg_j) - S0` and
    /// `S(g + dg_j + dg_k) - S(g + dg_j) - S(g + dg_k) + S0`.
    ///
    /// Per sample the change of `s = asin(u) + N G_k` under a step `d` of `u` is the
    /// third-order Taylor expansion `c d + s2 d^2 / 2 + s3 d^3 / 6` (c, s2, s3 the first
    /// three derivatives of asin at u; exact to rounding for the small steps dp makes), or,
    /// for large arguments or steps, [`asin_diff`]. The perturbed residual is `r + a_j`,
    /// with `a_j` the change of the rate term, and `(r + a_j)^2 - r^2 = a_j (2 r + a_j)`.
    /// One asin per sample instead of fifteen. Keeps u, sqrt(1 - u^2) and r per sample
    /// for [`Ring::change`].
    pub(super) fn differences(&mut self, g: &[T; 4], dg: &[T; 4], window: usize) -> PassSums<T> {
        let (mut j, n) = self.span(window);
        let zero = T::zero();
        let nil = Compensated::zero();
        let mut out = PassSums {
            s0: nil,
            first: [nil; 4],
            second: [[nil; 4]; 4],
            count: 0,
        };
        // Previous sample: x, u, w, the changes of s for each step and the second changes.
        let mut px = [zero; 4];
        let mut pu = zero;
        let mut pw = T::one();
        let mut pds = [zero; 4];
        let mut pd2 = [zero; 6];
        for i in 0..n {
            let x = self.x[j];
            let u = g[0] * x[0] + g[1] * x[1] + g[2] * x[2];
            let w = cos_of_asin(u);
            self.u0[j] = u;
            self.w0[j] = w;
            let d = [dg[0] * x[0], dg[1] * x[1], dg[2] * x[2]];
            let (ds, d2) = asin_changes(u, w, d, dg[3] * x[3]);
            if i > 0 && self.linked[j] {
                let inv = self.inv_dt[j];
                // The change of u since the previous sample, from the differences of x.
                let du = g[0] * (x[0] - px[0]) + g[1] * (x[1] - px[1]) + g[2] * (x[2] - px[2]);
                let r = (asin_diff(pu, pw, u, w, du) + g[3] * (x[3] - px[3])) * inv - self.y[j];
                self.r0[j] = r;
                let a = core::array::from_fn(|m| (ds[m] - pds[m]) * inv);
                let b = core::array::from_fn(|p| (d2[p] - pd2[p]) * inv);
                out.add(r, &a, &b);
            }
            px = x;
            pu = u;
            pw = w;
            pds = ds;
            pd2 = d2;
            j += 1;
            if j == CAP {
                j = 0;
            }
        }
        out
    }

    /// `S(g + dg) - S(g)` for the gains `g` of the last [`Ring::differences`] pass and a
    /// step `dg` of any size, accumulated per sample as `a (2 r + a)`.
    pub(super) fn change(&self, dg: &[T; 4], window: usize) -> T {
        let (mut j, n) = self.span(window);
        let zero = T::zero();
        let two = T::lit(2.0);
        let mut sum = Compensated::zero();
        let mut pds = zero;
        for i in 0..n {
            let x = &self.x[j];
            let u = self.u0[j];
            let d = dg[0] * x[0] + dg[1] * x[1] + dg[2] * x[2];
            let u1 = u + d;
            let ds = asin_diff(u, self.w0[j], u1, cos_of_asin(u1), d) + dg[3] * x[3];
            if i > 0 && self.linked[j] {
                let a = (ds - pds) * self.inv_dt[j];
                sum.add(a * (two * self.r0[j] + a));
            }
            pds = ds;
            j += 1;
            if j == CAP {
                j = 0;
            }
        }
        sum.value()
    }
}

#[cfg(test)]
mod tests {
    use super::super::objective::{objective_change, objective_differences};
    use super::*;

    /// A ring of `n` made-up samples whose asin argument sweeps up to `u_max` for gains 1.
    fn ring(n: usize, u_max: f64) -> Ring<f64, 64> {
        let mut r = Ring::<f64, 64>::new();
        for i in 0..n {
            let t = i as f64 * 0.1;
            let x = [
                0.5 * u_max * t.sin(),
                0.3 * u_max * (1.3 * t).cos(),
                0.2 * u_max * (0.7 * t).sin(),
                0.4 * t.cos(),
            ];
            r.push(x, 0.3 * (0.9 * t).sin(), 10.0, i % 17 != 5);
        }
        r
    }

    /// The differences of one pass equal those of the paper's formulas on cost values
    /// (Eqs 25-28), for both objectives, with and without the Taylor expansion.
    #[test]
    fn one_pass_differences_equal_those_of_cost_values() {
        for (u_max, dp) in [(0.5, 1e-4), (0.97, 1e-4), (0.5, 2e-2)] {
            let mut r = ring(60, u_max);
            let g = [1.0, 1.0, 1.0, 0.3];
            let dg = [dp, dp, dp, dp];
            let sums = r.differences(&g, &dg, 50);
            let n = sums.count as f64;
            let m1 = sums.first.map(|v| v.value() / n);
            let m2 = sums.second.map(|row| row.map(|v| v.value() / n));
            for objective in [Objective::MeanSquare, Objective::Rms] {
                let (f0, d) = objective_differences(objective, sums.s0.value() / n, &m1, &m2, 1);
                let cost = |q: [f64; 4]| r.cost(&q, 50, objective);
                let plus = |j: usize, k: Option<usize>| {
                    let mut q = g;
                    q[j] += dg[j];
                    if let Some(k) = k {
                        q[k] += dg[k];
                    }
                    cost(q)
                };
                assert!((f0 - cost(g)).abs() < 1e-12 * f0, "{f0}");
                for j in 0..4 {
                    let fd = plus(j, None) - f0;
                    assert!(
                        (d.first[j] - fd).abs() < 1e-9 * fd.abs() + 1e-14,
                        "{u_max} {objective:?} first {j}: {} vs {fd}",
                        d.first[j]
                    );
                    for k in j..4 {
                        let fd2 = plus(j, Some(k)) - plus(j, None) - plus(k, None) + f0;
                        let tol = 1e-6 * fd2.abs() + 1e-13 * f0;
                        assert!(
                            (d.second[(j, k)] - fd2).abs() < tol,
                            "{u_max} {dp} {objective:?} second {j}{k}: {} vs {fd2}",
                            d.second[(j, k)]
                        );
                    }
                }
                // A large step: the change equals the difference of the costs.
                let step = [0.2, -0.1, 0.05, 0.1];
                let q = [
                    g[0] + step[0],
                    g[1] + step[1],
                    g[2] + step[2],
                    g[3] + step[3],
                ];
                let (dq, fq) =
                    objective_change(objective, sums.s0.value() / n, r.change(&step, 50) / n);
                assert!((fq - cost(q)).abs() < 1e-12, "{fq} vs {}", cost(q));
                assert!((dq - (cost(q) - f0)).abs() < 1e-12);
            }
        }
    }
}
