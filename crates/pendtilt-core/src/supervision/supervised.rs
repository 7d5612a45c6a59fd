//! Algorithm 3 (Eq 30) with live supervision of K, L, M, N against the gyro (Eq 29).
//!
//! Every sample, [`SupervisedAlg3`] runs [`Alg3`] and keeps the terms of Eq (30) in a ring
//! buffer of capacity `CAP` (no allocation). Then, by [`Method`]:
//! - [`Method::Newton`] (the paper): every [`SupervisorSettings::refit_interval`] samples,
//!   [`SupervisorSettings::newton_iterations`] iterations of Newton's method (Eqs 24-28) on
//!   the Eq (29) cost over the last [`SupervisorSettings::window`] samples. The paper's
//!   finite differences (Eqs 25-28) need the cost at 15 points; they are accumulated in one
//!   pass over the window, per sample, from the Taylor expansion of the asin about the
//!   current argument (exact to rounding for the small dp), then one pass per step tried.
//!   So an iteration costs about two passes instead of sixteen, and the amortised
//!   per-sample cost is about `2 * iterations * window / refit_interval` evaluations of
//!   Eq (30).
//! - [`Method::Rls`]: every sample, one recursive-least-squares update (see
//!   [`super::rls`]) of the derivative of Eq (30), linearised in K, L, M at the current
//!   gains: `G - (phi_k - phi_(k-1))/dt = K c dphi' + L c dphi'' + M c dG_d + N dG_k`, with
//!   `c = 1 / sqrt(1 - u^2)` the derivative of asin at the current argument `u` and the
//!   primes finite differences of consecutive samples. The gains are handed to the
//!   estimator every `refit_interval` samples.
//!
//! Internally the gains are scaled by their start values (K, N by |K0|, L by |L0|, M by
//! |M0|), so [`NewtonSettings::dp`] and [`RlsSettings::p0`] are relative.
//!
//! Why it works in f32: the second difference of the cost is about `dp^2` (1e-8) of the
//! cost, below f32's resolution, so taken from cost values (as the paper writes it) it is
//! rounding noise and the f32 refit wandered (0.66 deg RMS from f64 on a scooter ride).
//! Here every difference is accumulated per sample as a difference (`a (2 r + a)` for the
//! change of `r^2`, the asin's change from its derivatives, `asin(u1) - asin(u0)` by
//! `asin(d (u1 + u0) / (u1 w0 + u0 w1))`), and the RMS differences are formed from them without cancellation; the
//! f32 gains then follow the f64 ones to 1e-3 and the estimate to 1e-4 deg
//! (`tests/f32_vs_f64.rs`).
//!
//! The gains adapt when the rig changes: a change of friction moves K, a change of the
//! sample time (a clock that drifts against the time stamps) moves all four.
use super::newton::{check_settings, newton_step, CostDifferences, NewtonSettings};
use super::rls::{Rls, RlsSettings};
use super::Objective;
use crate::estimators::alg3::{Alg3, Alg3Settings};
use crate::estimators::equations::{clamped_asin, Alg3Gains};
use crate::estimators::theta_dd::DEFAULT_WINDOW_CAPACITY;
use crate::{Estimate, Estimator, Real, Sample};
use nalgebra::{SMatrix, SVector};

bitflags::bitflags! {
    /// What the supervisor did on a sample (beside the estimator's own [`crate::Flags`]).
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub struct SupervisionFlags: u8 {
        /// Not supervising yet: the warm-up is running or the window is still filling.
        const WARMING_UP = 1 << 0;
        /// New gains were computed on this sample and take effect from the next one.
        const REFIT = 1 << 1;
        /// A refit was due but made no progress (flat or non-finite cost, no descent):
        /// the gains were kept.
        const REFIT_REJECTED = 1 << 2;
        /// The sample could not be used for supervision (held, or gyro missing).
        const SKIPPED = 1 << 3;
    }
}

/// How the gains are re-fitted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Method {
    /// The paper's Newton's method (Eqs 24-28) on the Eq (29) cost over a window.
    #[default]
    Newton,
    /// Recursive least squares with forgetting, one update per sample.
    Rls,
}

/// Settings of the supervisor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SupervisorSettings<T> {
    /// Newton or RLS. Default [`Method::Newton`].
    pub method: Method,
    /// Samples in the Eq (29) window (at most the buffer capacity). Default 1000.
    pub window: usize,
    /// Samples between refits (Newton) or between handing new gains to the estimator
    /// (RLS). Default 2000.
    pub refit_interval: usize,
    /// Samples ignored at the start while the differentiators settle. Default 500.
    pub warmup: usize,
    /// Newton iterations per refit. Default 1.
    pub newton_iterations: usize,
    /// Newton's h, dp (relative to the start gains), tolerances. Default h = 1, dp = 1e-4.
    pub newton: NewtonSettings<T>,
    /// What Newton minimises. Default [`Objective::Rms`] (Eq 29 as printed).
    pub objective: Objective,
    /// RLS forgetting, initial covariance (relative), wind-up guard.
    pub rls: RlsSettings<T>,
    /// Which of K, L, M, N are supervised. Default all four (the paper).
    pub adapt: [bool; 4],
    /// Trust region of a Newton refit: the largest change of any gain per refit, relative
    /// to its start value (K, N in units of K's). A longer Newton step is halved until it
    /// fits. A window with little excitation (slow motion: phi'' and G_d small) leaves
    /// the cost nearly flat along some direction, where the finite-difference Newton step
    /// is long and, fitting the noise, still lowers the window's cost: measured on
    /// repeated 0.2-3 Hz chirps with no limit, K wandered to -5 and +14 times a. Default
    /// 0.1 (`f64::INFINITY` for none).
    pub max_step: T,
    /// Evaluate Eq (29) on the estimator's low-passed twin: phi and the gyro through the
    /// same low-pass as phi', phi'' (phi rate = the differentiator's phi', G and the N term
    /// from the low-passed gyro). Both sides then carry the same delay, so the fitted gains
    /// are the pendulum's (K = a, L = b, M = -b, N = 0 on a clean rig) and the residual is
    /// not dominated by encoder steps turned into rate. Measured on a noisy chirp, with
    /// `false` (the raw cost as printed) the gains wandered by +-500 % and the estimate
    /// got worse, with `true` they converged. Default true.
    pub matched: bool,
}

impl<T: Real> Default for SupervisorSettings<T> {
    fn default() -> Self {
        Self {
            method: Method::Newton,
            window: 1000,
            refit_interval: 2000,
            warmup: 500,
            newton_iterations: 1,
            newton: NewtonSettings {
                dp: T::lit(1e-4),
                ..NewtonSettings::default()
            },
            objective: Objective::Rms,
            rls: RlsSettings::default(),
            adapt: [true; 4],
            max_step: T::lit(0.1),
            matched: true,
        }
    }
}

/// Settings of [`SupervisedAlg3`]: the estimator's and the supervisor's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SupervisedAlg3Settings<T> {
    /// Algorithm 3 (its gains are the start values).
    pub alg3: Alg3Settings<T>,
    /// The supervisor.
    pub supervisor: SupervisorSettings<T>,
}

impl<T: Real> Default for SupervisedAlg3Settings<T> {
    fn default() -> Self {
        Self {
            alg3: Alg3Settings::default(),
            supervisor: SupervisorSettings::default(),
        }
    }
}

/// A setting that [`SupervisedAlg3::new`] refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SettingsError {
    /// `window` is below 3 or above the buffer capacity `CAP`.
    Window,
    /// `refit_interval` is 0.
    RefitInterval,
    /// The Newton settings are not usable (h, dp must be finite and > 0).
    Newton,
    /// The RLS settings are not usable (forgetting in (0, 1], p0 and max_trace > 0).
    Rls,
    /// A start gain is not finite.
    Gains,
    /// `max_step` is not positive (or is NaN).
    MaxStep,
}

/// One estimate with what the supervisor did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SupervisedEstimate<T> {
    /// The Eq (30) estimate and the estimator's flags.
    pub estimate: Estimate<T>,
    /// The supervisor's flags.
    pub supervision: SupervisionFlags,
}

/// The previous usable sample, for the finite differences of Eq (29).
#[derive(Debug, Clone, Copy)]
struct Prev<T> {
    phi: T,
    gyro: T,
    x: [T; 4],
}

/// `asin(u1) - asin(u0)` without the cancellation of subtracting two nearly equal values:
/// for `u0`, `u1` of the same sign it is `asin(d (u1 + u0) / (u1 w0 + u0 w1))` with
/// `d = u1 - u0` (computed by the caller from differences, not from `u1` and `u0`) and
/// `w = sqrt(1 - u^2)` (0 marks an argument outside (-1, 1), clamped like the estimator).
#[inline]
fn asin_diff<T: Real>(u0: T, w0: T, u1: T, w1: T, d: T) -> T {
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
fn cos_of_asin<T: Real>(u: T) -> T {
    let one = T::one();
    if u.abs() < one {
        ((one - u) * (one + u)).sqrt()
    } else {
        T::zero()
    }
}

/// Largest asin argument and perturbation for which the third-order Taylor expansion of
/// asin is used for the finite differences: the fourth-order remainder is then below
/// 1e-9 of the first-order term (the fourth derivative of asin is below 400 for
/// |u| <= 0.8).
const TAYLOR_MAX_U: f64 = 0.8;
const TAYLOR_MAX_D: f64 = 5e-4;

/// The pairs (j, k), j <= k < 3, of the second changes of the asin.
const PAIRS: [(usize, usize); 6] = [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)];

/// Sums of one pass for Newton: `S0 = sum r^2`, the first and second differences of the
/// sum (upper triangle), and the residual count. See [`Ring::differences`].
struct PassSums<T> {
    s0: T,
    first: [T; 4],
    second: [[T; 4]; 4],
    count: usize,
}

/// Ring buffer of the Eq (29) terms: for each sample the Eq (30) inputs
/// `x = [phi', phi'', G_d, G_k]`, the parameter-free part `y` of the residual and `1/dt`;
/// and, from the last [`Ring::differences`] pass, the asin argument `u`, `sqrt(1 - u^2)` and
/// the residual, which the step evaluations of the same refit reuse.
#[derive(Debug, Clone)]
struct Ring<T, const CAP: usize> {
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
    fn new() -> Self {
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

    fn clear(&mut self) {
        self.head = 0;
        self.len = 0;
    }

    #[inline]
    fn push(&mut self, x: [T; 4], y: T, inv_dt: T, linked: bool) {
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

    /// The window's first slot and length.
    #[inline]
    fn span(&self, window: usize) -> (usize, usize) {
        let n = window.min(self.len);
        ((self.head + CAP - n) % CAP.max(1), n)
    }

    /// Eq (29) over the last `window` samples for the real gains `g` (K, L, M, N).
    fn cost(&self, g: &[T; 4], window: usize, objective: Objective) -> T {
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
    #[allow(clippy::needless_range_loop)] // j, k index several arrays at once
    fn differences(&mut self, g: &[T; 4], dg: &[T; 4], window: usize) -> PassSums<T> {
        let (mut j, n) = self.span(window);
        let zero = T::zero();
        let one = T::one();
        let two = T::lit(2.0);
        let half = T::lit(0.5);
        let sixth = T::lit(1.0 / 6.0);
        let max_u = T::lit(TAYLOR_MAX_U);
        let max_d = T::lit(TAYLOR_MAX_D);
        let mut out = PassSums {
            s0: zero,
            first: [zero; 4],
            second: [[zero; 4]; 4],
            count: 0,
        };
        // Previous sample: x, u, w, the changes of s for each step and the second changes.
        let mut px = [zero; 4];
        let mut pu = zero;
        let mut pw = one;
        let mut pds = [zero; 4];
        let mut pd2 = [zero; 6];
        for i in 0..n {
            let x = self.x[j];
            let u = g[0] * x[0] + g[1] * x[1] + g[2] * x[2];
            let w = cos_of_asin(u);
            self.u0[j] = u;
            self.w0[j] = w;
            let d = [dg[0] * x[0], dg[1] * x[1], dg[2] * x[2]];
            let mut ds = [zero, zero, zero, dg[3] * x[3]];
            let mut d2 = [zero; 6];
            let dmax = d[0].abs().max(d[1].abs()).max(d[2].abs());
            if w > zero && u.abs() <= max_u && dmax <= max_d {
                let c = one / w;
                let c2 = c * c;
                let s2 = u * c * c2;
                let s3 = (one + two * u * u) * c2 * c2 * c;
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
            if i > 0 && self.linked[j] {
                let inv = self.inv_dt[j];
                // The change of u since the previous sample, from the differences of x.
                let du = g[0] * (x[0] - px[0]) + g[1] * (x[1] - px[1]) + g[2] * (x[2] - px[2]);
                let r = (asin_diff(pu, pw, u, w, du) + g[3] * (x[3] - px[3])) * inv - self.y[j];
                self.r0[j] = r;
                let mut a = [zero; 4];
                for m in 0..4 {
                    a[m] = (ds[m] - pds[m]) * inv;
                }
                let r2 = two * r;
                out.s0 += r * r;
                for m in 0..4 {
                    out.first[m] += a[m] * (r2 + a[m]);
                }
                for (p, &(ja, kb)) in PAIRS.iter().enumerate() {
                    let b = (d2[p] - pd2[p]) * inv;
                    out.second[ja][kb] +=
                        r2 * b + two * a[ja] * a[kb] + b * (two * (a[ja] + a[kb]) + b);
                }
                // Pairs with N: s is additive in N, so its second change is 0.
                for m in 0..4 {
                    out.second[m][3] += two * a[m] * a[3];
                }
                out.count += 1;
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
    fn change(&self, dg: &[T; 4], window: usize) -> T {
        let (mut j, n) = self.span(window);
        let zero = T::zero();
        let two = T::lit(2.0);
        let mut sum = zero;
        let mut pds = zero;
        for i in 0..n {
            let x = &self.x[j];
            let u = self.u0[j];
            let d = dg[0] * x[0] + dg[1] * x[1] + dg[2] * x[2];
            let u1 = u + d;
            let ds = asin_diff(u, self.w0[j], u1, cos_of_asin(u1), d) + dg[3] * x[3];
            if i > 0 && self.linked[j] {
                let a = (ds - pds) * self.inv_dt[j];
                sum += a * (two * self.r0[j] + a);
            }
            pds = ds;
            j += 1;
            if j == CAP {
                j = 0;
            }
        }
        sum
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
fn objective_differences<T: Real>(
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
fn objective_change<T: Real>(objective: Objective, m0: T, dm: T) -> (T, T) {
    match objective {
        Objective::MeanSquare => (dm, m0 + dm),
        Objective::Rms => {
            let f1 = root(m0 + dm);
            let f0 = root(m0);
            (ratio(dm, f1 + f0), f1)
        }
    }
}

/// Algorithm 3 with live supervision; see the module docs. `CAP` is the window buffer
/// capacity in samples, `W` the Eq (22) window capacity of the estimator.
#[derive(Debug, Clone)]
pub struct SupervisedAlg3<
    T: Real,
    const CAP: usize = 1024,
    const W: usize = DEFAULT_WINDOW_CAPACITY,
> {
    settings: SupervisedAlg3Settings<T>,
    alg3: Alg3<T, W>,
    ring: Ring<T, CAP>,
    rls: Rls<T, 4>,
    scale: [T; 4],
    prev: Option<Prev<T>>,
    seen: usize,
    since_refit: usize,
    refits: usize,
    last_cost: T,
}

fn nonzero<T: Real>(v: T, fallback: T) -> T {
    if v.abs() > T::zero() && v.is_finite() {
        v.abs()
    } else {
        fallback
    }
}

impl<T: Real, const CAP: usize, const W: usize> SupervisedAlg3<T, CAP, W> {
    /// A new supervised estimator; refuses unusable settings.
    pub fn new(settings: SupervisedAlg3Settings<T>) -> Result<Self, SettingsError> {
        let sup = &settings.supervisor;
        if sup.window < 3 || sup.window > CAP {
            return Err(SettingsError::Window);
        }
        if sup.refit_interval == 0 {
            return Err(SettingsError::RefitInterval);
        }
        if check_settings(&sup.newton).is_err() {
            return Err(SettingsError::Newton);
        }
        if !sup.rls.is_valid() {
            return Err(SettingsError::Rls);
        }
        if sup.max_step.partial_cmp(&T::zero()) != Some(core::cmp::Ordering::Greater) {
            return Err(SettingsError::MaxStep);
        }
        let g = settings.alg3.gains;
        if !g.is_finite() {
            return Err(SettingsError::Gains);
        }
        let sk = nonzero(g.k, T::lit(1e-2));
        let sl = nonzero(g.l, T::lit(1e-3));
        let scale = [sk, sl, nonzero(g.m, sl), sk];
        let q0 = Self::to_scaled(&g, &scale);
        Ok(Self {
            alg3: Alg3::new(settings.alg3),
            ring: Ring::new(),
            rls: Rls::new(q0, sup.adapt, sup.rls),
            scale,
            prev: None,
            seen: 0,
            since_refit: 0,
            refits: 0,
            last_cost: T::nan(),
            settings,
        })
    }

    fn to_scaled(g: &Alg3Gains<T>, s: &[T; 4]) -> SVector<T, 4> {
        SVector::<T, 4>::new(g.k / s[0], g.l / s[1], g.m / s[2], g.n / s[3])
    }

    fn from_scaled(q: &SVector<T, 4>, s: &[T; 4]) -> Alg3Gains<T> {
        Alg3Gains {
            k: q[0] * s[0],
            l: q[1] * s[1],
            m: q[2] * s[2],
            n: q[3] * s[3],
        }
    }

    /// The gains K, L, M, N in use.
    pub fn gains(&self) -> Alg3Gains<T> {
        self.alg3.gains()
    }

    /// The settings.
    pub fn settings(&self) -> &SupervisedAlg3Settings<T> {
        &self.settings
    }

    /// How many refits changed the gains so far.
    pub fn refits(&self) -> usize {
        self.refits
    }

    /// The Eq (29) cost over the window after the last Newton refit (NaN before the first
    /// one, and with RLS).
    pub fn last_cost(&self) -> T {
        self.last_cost
    }

    /// The Eq (29) cost over the current window for gains `g` (NaN while it is empty).
    pub fn window_cost(&self, g: &Alg3Gains<T>) -> T {
        self.ring.cost(
            &[g.k, g.l, g.m, g.n],
            self.settings.supervisor.window,
            self.settings.supervisor.objective,
        )
    }

    /// One sample: the Eq (30) estimate, then the supervisor's step.
    pub fn update_supervised(&mut self, s: &Sample<T>) -> SupervisedEstimate<T> {
        let (estimate, terms) = self.alg3.update_with_terms(s);
        let mut flags = SupervisionFlags::empty();
        let terms = match terms {
            Some(t) if s.gyro.is_finite() => t,
            _ => {
                self.prev = None;
                return SupervisedEstimate {
                    estimate,
                    supervision: SupervisionFlags::SKIPPED,
                };
            }
        };
        self.seen = self.seen.saturating_add(1);
        let sup = self.settings.supervisor;
        // Matched: the gyro through the estimator's own phi low-pass for G and for the N
        // term; "phi" carries phi' (the rate of the low-passed phi), see `matched`.
        let (gyro, phi_or_rate) = if sup.matched {
            (terms.gk_filtered, terms.dphi)
        } else {
            (s.gyro, terms.phi)
        };
        let x = [
            terms.dphi,
            terms.ddphi,
            terms.gd,
            if sup.matched { gyro } else { terms.gk },
        ];
        let prev = self.prev.replace(Prev {
            phi: phi_or_rate,
            gyro,
            x,
        });
        if self.seen <= sup.warmup {
            return SupervisedEstimate {
                estimate,
                supervision: SupervisionFlags::WARMING_UP,
            };
        }
        let Some(prev) = prev else {
            self.ring.push(x, T::zero(), T::zero(), false);
            return SupervisedEstimate {
                estimate,
                supervision: SupervisionFlags::WARMING_UP,
            };
        };
        let dt = terms.dt;
        let inv_dt = T::one() / dt;
        let half = T::lit(0.5);
        // Parameter-free part of the residual: G at mid-interval minus the raw phi rate.
        let y = if sup.matched {
            (gyro + prev.gyro - phi_or_rate - prev.phi) * half
        } else {
            (s.gyro + prev.gyro) * half - (phi_or_rate - prev.phi) * inv_dt
        };
        self.since_refit += 1;
        // RLS needs no window: only Newton fills the ring.
        let filled = match sup.method {
            Method::Rls => {
                self.rls_step(&prev.x, &x, y, inv_dt);
                self.seen > sup.warmup + sup.window
            }
            Method::Newton => {
                self.ring.push(x, y, inv_dt, true);
                self.ring.len >= sup.window
            }
        };
        if !filled {
            flags |= SupervisionFlags::WARMING_UP;
        } else if self.since_refit >= sup.refit_interval {
            self.since_refit = 0;
            flags |= self.refit();
        }
        SupervisedEstimate {
            estimate,
            supervision: flags,
        }
    }

    #[inline]
    fn rls_step(&mut self, x0: &[T; 4], x1: &[T; 4], y: T, inv_dt: T) {
        let g = self.alg3.gains();
        let u = g.k * x1[0] + g.l * x1[1] + g.m * x1[2];
        let one = T::one();
        let c = if u.abs() < T::lit(0.99) {
            one / (one - u * u).sqrt()
        } else {
            one
        };
        let sc = &self.scale;
        let z = SVector::<T, 4>::new(
            c * (x1[0] - x0[0]) * inv_dt * sc[0],
            c * (x1[1] - x0[1]) * inv_dt * sc[1],
            c * (x1[2] - x0[2]) * inv_dt * sc[2],
            (x1[3] - x0[3]) * inv_dt * sc[3],
        );
        self.rls.update(&z, y);
    }

    /// [`SupervisorSettings::newton_iterations`] iterations of Newton's method from `old`:
    /// per iteration one pass for the finite differences ([`Ring::differences`]) and one
    /// per step tried ([`Ring::change`]). Returns the scaled gains, the objective there
    /// and whether they moved.
    fn newton_refit(&mut self, old: &Alg3Gains<T>) -> (SVector<T, 4>, T, bool) {
        let sup = self.settings.supervisor;
        let scale = self.scale;
        let dp = sup.newton.dp;
        let mut dg = [T::zero(); 4];
        for j in 0..4 {
            if sup.adapt[j] {
                dg[j] = dp * scale[j];
            }
        }
        let mut q = Self::to_scaled(old, &scale);
        let mut f = T::nan();
        let mut moved = false;
        for _ in 0..sup.newton_iterations.max(1) {
            let g = [
                q[0] * scale[0],
                q[1] * scale[1],
                q[2] * scale[2],
                q[3] * scale[3],
            ];
            let sums = self.ring.differences(&g, &dg, sup.window);
            if sums.count == 0 {
                break;
            }
            let inv_n = T::one() / T::lit(sums.count as f64);
            let m1 = sums.first.map(|v| v * inv_n);
            let m2 = sums.second.map(|row| row.map(|v| v * inv_n));
            let m0 = sums.s0 * inv_n;
            let (f0, d) = objective_differences(sup.objective, m0, &m1, &m2, 1);
            f = f0;
            let ring = &self.ring;
            let q0 = q;
            // Tries of the step halving that the quadratic model of the mean square (from
            // the same differences) predicts to raise it are skipped: `m(t) = t G + t^2 C`
            // descends for t < t* = -G / C; a try is skipped only when t > 2 t*, so the
            // model would have to be off by a factor of 2 for the skipped try to have been
            // taken. On the RMS, whose Newton step overshoots (see `newton`), this saves
            // most of the passes the halving costs.
            let inv_dp = T::one() / dp;
            let predicted_rise = |qn: &SVector<T, 4>| {
                let mut lin = T::zero();
                let mut quad = T::zero();
                for j in 0..4 {
                    let a = (qn[j] - q0[j]) * inv_dp;
                    lin += m1[j] * a;
                    for k in 0..4 {
                        let mk = if j <= k { m2[j][k] } else { m2[k][j] };
                        quad += mk * a * (qn[k] - q0[k]) * inv_dp;
                    }
                }
                quad > T::zero() && lin + T::lit(0.5) * quad > lin.abs()
            };
            let mut change = |qn: &SVector<T, 4>| {
                let too_long = (0..4).any(|j| (qn[j] - q0[j]).abs() > sup.max_step);
                if too_long || predicted_rise(qn) {
                    return (T::one(), T::nan());
                }
                let step = [
                    (qn[0] - q0[0]) * scale[0],
                    (qn[1] - q0[1]) * scale[1],
                    (qn[2] - q0[2]) * scale[2],
                    (qn[3] - q0[3]) * scale[3],
                ];
                objective_change(sup.objective, m0, ring.change(&step, sup.window) * inv_n)
            };
            match newton_step(&d, &mut change, &q, f0, &sup.adapt, &sup.newton) {
                Ok(it) if !it.stalled => {
                    q = it.params;
                    f = it.cost;
                    moved = true;
                }
                _ => break,
            }
        }
        (q, f, moved)
    }

    fn refit(&mut self) -> SupervisionFlags {
        let sup = self.settings.supervisor;
        let scale = self.scale;
        let old = self.alg3.gains();
        let new = match sup.method {
            Method::Rls => Self::from_scaled(self.rls.params(), &scale),
            Method::Newton => {
                let (q, f, moved) = self.newton_refit(&old);
                self.last_cost = f;
                if !moved {
                    return SupervisionFlags::REFIT_REJECTED;
                }
                Self::from_scaled(&q, &scale)
            }
        };
        if new != old && self.alg3.set_gains(new) {
            self.refits += 1;
            SupervisionFlags::REFIT
        } else {
            SupervisionFlags::REFIT_REJECTED
        }
    }
}

impl<T: Real, const CAP: usize, const W: usize> Estimator for SupervisedAlg3<T, CAP, W> {
    type Input = Sample<T>;
    type Output = Estimate<T>;

    #[inline]
    fn update(&mut self, s: &Sample<T>) -> Estimate<T> {
        self.update_supervised(s).estimate
    }

    /// Forgets all history and returns to the start gains.
    fn reset(&mut self) {
        self.alg3 = Alg3::new(self.settings.alg3);
        self.ring.clear();
        let q0 = Self::to_scaled(&self.settings.alg3.gains, &self.scale);
        self.rls = Rls::new(
            q0,
            self.settings.supervisor.adapt,
            self.settings.supervisor.rls,
        );
        self.prev = None;
        self.seen = 0;
        self.since_refit = 0;
        self.refits = 0;
        self.last_cost = T::nan();
    }
}

#[cfg(test)]
mod tests {
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
            let m1 = sums.first.map(|v| v / n);
            let m2 = sums.second.map(|row| row.map(|v| v / n));
            for objective in [Objective::MeanSquare, Objective::Rms] {
                let (f0, d) = objective_differences(objective, sums.s0 / n, &m1, &m2, 1);
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
                let (dq, fq) = objective_change(objective, sums.s0 / n, r.change(&step, 50) / n);
                assert!((fq - cost(q)).abs() < 1e-12, "{fq} vs {}", cost(q));
                assert!((dq - (cost(q) - f0)).abs() < 1e-12);
            }
        }
    }

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
}
