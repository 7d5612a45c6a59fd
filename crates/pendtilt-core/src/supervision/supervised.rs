//! Algorithm 3 (Eq 30) with live supervision of K, L, M, N against the gyro (Eq 29).
//!
//! Every sample, [`SupervisedAlg3`] runs [`Alg3`] and keeps the terms of Eq (30) in a ring
//! buffer of capacity `CAP` (no allocation). Then, by [`Method`]:
//! - [`Method::Newton`] (the paper): every [`SupervisorSettings::refit_interval`](super::SupervisorSettings::refit_interval) samples,
//!   [`SupervisorSettings::newton_iterations`](super::SupervisorSettings::newton_iterations) iterations of Newton's method (Eqs 24-28) on
//!   the Eq (29) cost over the last [`SupervisorSettings::window`](super::SupervisorSettings::window) samples. The paper's
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
//! |M0|), so [`NewtonSettings::dp`](super::NewtonSettings::dp) and [`RlsSettings::p0`](super::RlsSettings::p0) are relative.
//!
//! Why it works in f32: the second difference of the cost is about `dp^2` (1e-8) of the
//! cost, below f32's resolution, so taken from cost values (as the paper writes it) it is
//! rounding noise and the f32 refit wandered (0.66 deg RMS from f64 on a scooter ride).
//! Here every difference is accumulated per sample as a difference (`a (2 r + a)` for the
//! change of `r^2`, the asin's change from its derivatives, `asin(u1) - asin(u0)` by
//! `asin(d (u1 + u0) / (u1 w0 + u0 w1))`), and the RMS differences are formed from them
//! without cancellation; the f32 gains then follow the f64 ones to 1e-3 and the estimate
//! to 1e-4 deg (`tests/f32_vs_f64.rs`).
//!
//! Over hours it needs two more things, because on a window where phi' and the gyro are
//! nearly proportional the cost is nearly flat along one direction of (K, N) and the
//! Newton step amplifies small errors of its inputs by the Hessian's condition number:
//! the window's sums are compensated (Kahan), and the estimator's derivatives come from
//! the differentiator in delta form ([`crate::filters::diff`]), 3x closer to f64's. Either
//! alone left the f32 estimate 0.006-0.013 deg RMS from f64 after two hours (3600
//! refits); both, 0.0008 (docs/reliability.md section 6).
//!
//! The gains adapt when the rig changes: a change of friction moves K, a change of the
//! sample time (a clock that drifts against the time stamps) moves all four.
use super::newton::newton_step;
use super::objective::{objective_change, objective_differences};
use super::ring::Ring;
use super::rls::Rls;
use super::settings::{Method, SettingsError, SupervisedAlg3Settings};
use crate::estimators::alg3::{Alg3, Alg3Terms};
use crate::estimators::equations::Alg3Gains;
use crate::estimators::theta_dd::DEFAULT_WINDOW_CAPACITY;
use crate::{Estimate, Estimator, Real, Sample};
use nalgebra::SVector;

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

/// Algorithm 3 with live supervision; see the module docs. `CAP` is the window buffer
/// capacity in samples, `W` the Eq (22) window capacity of the estimator.
#[derive(Debug, Clone)]
pub struct SupervisedAlg3<
    T: Real,
    const CAP: usize = 1024,
    const W: usize = DEFAULT_WINDOW_CAPACITY,
> {
    settings: SupervisedAlg3Settings<T>,
    coeffs: Coefficients<T>,
    state: State<T, CAP, W>,
}

/// What the settings give once: the gains' scales and the start gains in them, to which
/// `reset` returns.
#[derive(Debug, Clone, Copy)]
struct Coefficients<T: Real> {
    /// K, L, M, N are fitted relative to these (|K0|, |L0|, |M0|, |K0|, a fallback for a
    /// zero one), so that `dp` and `p0` are relative.
    scale: [T; 4],
    /// The start gains, scaled.
    start: SVector<T, 4>,
}

/// Everything a run changes: what `reset` starts again.
#[derive(Debug, Clone)]
struct State<T: Real, const CAP: usize, const W: usize> {
    /// The estimator, its gains the supervisor's latest.
    alg3: Alg3<T, W>,
    /// The Eq (29) terms of the window (Newton).
    ring: Ring<T, CAP>,
    rls: Rls<T, 4>,
    prev: Option<Prev<T>>,
    /// Usable samples so far (the warm-up counts them).
    seen: usize,
    since_refit: usize,
    refits: usize,
    last_cost: T,
}

impl<T: Real, const CAP: usize, const W: usize> State<T, CAP, W> {
    fn new(settings: &SupervisedAlg3Settings<T>, coeffs: &Coefficients<T>) -> Self {
        let sup = &settings.supervisor;
        Self {
            alg3: Alg3::new(settings.alg3),
            ring: Ring::new(),
            rls: Rls::new(coeffs.start, sup.adapt, sup.rls),
            prev: None,
            seen: 0,
            since_refit: 0,
            refits: 0,
            last_cost: T::nan(),
        }
    }

    /// Back to the state before the first sample, the start gains in the estimator.
    fn reset(&mut self, settings: &SupervisedAlg3Settings<T>, coeffs: &Coefficients<T>) {
        // The estimator's state restarts and its gains return to the start ones (checked
        // finite by `new`); its coefficients stay.
        self.alg3.reset();
        self.alg3.set_gains(settings.alg3.gains);
        self.ring.clear();
        let sup = &settings.supervisor;
        self.rls = Rls::new(coeffs.start, sup.adapt, sup.rls);
        self.prev = None;
        self.seen = 0;
        self.since_refit = 0;
        self.refits = 0;
        self.last_cost = T::nan();
    }
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
        settings.check(CAP)?;
        let g = settings.alg3.gains;
        let sk = nonzero(g.k, T::lit(1e-2));
        let sl = nonzero(g.l, T::lit(1e-3));
        let scale = [sk, sl, nonzero(g.m, sl), sk];
        let coeffs = Coefficients {
            start: Self::to_scaled(&g, &scale),
            scale,
        };
        Ok(Self {
            state: State::new(&settings, &coeffs),
            coeffs,
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
        self.state.alg3.gains()
    }

    /// The settings.
    pub fn settings(&self) -> &SupervisedAlg3Settings<T> {
        &self.settings
    }

    /// How many refits changed the gains so far.
    pub fn refits(&self) -> usize {
        self.state.refits
    }

    /// The Eq (29) cost over the window after the last Newton refit (NaN before the first
    /// one, and with RLS).
    pub fn last_cost(&self) -> T {
        self.state.last_cost
    }

    /// The Eq (29) cost over the current window for gains `g` (NaN while it is empty).
    pub fn window_cost(&self, g: &Alg3Gains<T>) -> T {
        self.state.ring.cost(
            &[g.k, g.l, g.m, g.n],
            self.settings.supervisor.window,
            self.settings.supervisor.objective,
        )
    }

    /// One sample: the Eq (30) estimate, then the supervisor's step.
    pub fn update_supervised(&mut self, s: &Sample<T>) -> SupervisedEstimate<T> {
        let (estimate, terms) = self.state.alg3.update_with_terms(s);
        let supervision = match terms {
            Some(t) if s.gyro.is_finite() => self.supervise(s.gyro, &t),
            _ => {
                self.state.prev = None;
                SupervisionFlags::SKIPPED
            }
        };
        SupervisedEstimate {
            estimate,
            supervision,
        }
    }

    /// The supervisor's step on a usable sample: the Eq (29) terms of the interval since
    /// the previous one go to the ring (Newton) or to RLS, then a refit when it is due.
    fn supervise(&mut self, raw_gyro: T, terms: &Alg3Terms<T>) -> SupervisionFlags {
        self.state.seen = self.state.seen.saturating_add(1);
        let sup = self.settings.supervisor;
        // Matched: the gyro through the estimator's own phi low-pass for G and for the N
        // term; "phi" carries phi' (the rate of the low-passed phi), see `matched`.
        let (gyro, phi_or_rate) = if sup.matched {
            (terms.gk_filtered, terms.dphi)
        } else {
            (raw_gyro, terms.phi)
        };
        let x = [
            terms.dphi,
            terms.ddphi,
            terms.gd,
            if sup.matched { gyro } else { terms.gk },
        ];
        let prev = self.state.prev.replace(Prev {
            phi: phi_or_rate,
            gyro,
            x,
        });
        if self.state.seen <= sup.warmup {
            return SupervisionFlags::WARMING_UP;
        }
        let Some(prev) = prev else {
            self.state.ring.push(x, T::zero(), T::zero(), false);
            return SupervisionFlags::WARMING_UP;
        };
        let inv_dt = T::one() / terms.dt;
        let half = T::lit(0.5);
        // Parameter-free part of the residual: G at mid-interval minus the raw phi rate.
        let y = if sup.matched {
            (gyro + prev.gyro - phi_or_rate - prev.phi) * half
        } else {
            (raw_gyro + prev.gyro) * half - (phi_or_rate - prev.phi) * inv_dt
        };
        self.state.since_refit += 1;
        // RLS needs no window: only Newton fills the ring.
        let filled = match sup.method {
            Method::Rls => {
                self.rls_step(&prev.x, &x, y, inv_dt);
                self.state.seen > sup.warmup + sup.window
            }
            Method::Newton => {
                self.state.ring.push(x, y, inv_dt, true);
                self.state.ring.len() >= sup.window
            }
        };
        if !filled {
            SupervisionFlags::WARMING_UP
        } else if self.state.since_refit >= sup.refit_interval {
            self.state.since_refit = 0;
            self.refit()
        } else {
            SupervisionFlags::empty()
        }
    }

    #[inline]
    fn rls_step(&mut self, x0: &[T; 4], x1: &[T; 4], y: T, inv_dt: T) {
        let g = self.state.alg3.gains();
        let u = g.k * x1[0] + g.l * x1[1] + g.m * x1[2];
        let one = T::one();
        let c = if u.abs() < T::lit(0.99) {
            one / (one - u * u).sqrt()
        } else {
            one
        };
        let sc = &self.coeffs.scale;
        let z = SVector::<T, 4>::new(
            c * (x1[0] - x0[0]) * inv_dt * sc[0],
            c * (x1[1] - x0[1]) * inv_dt * sc[1],
            c * (x1[2] - x0[2]) * inv_dt * sc[2],
            (x1[3] - x0[3]) * inv_dt * sc[3],
        );
        self.state.rls.update(&z, y);
    }

    /// [`SupervisorSettings::newton_iterations`](super::SupervisorSettings::newton_iterations) iterations of Newton's method from `old`:
    /// per iteration one pass for the finite differences ([`Ring::differences`]) and one
    /// per step tried ([`Ring::change`]). Returns the scaled gains, the objective there
    /// and whether they moved.
    fn newton_refit(&mut self, old: &Alg3Gains<T>) -> (SVector<T, 4>, T, bool) {
        let sup = self.settings.supervisor;
        let scale = self.coeffs.scale;
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
            let sums = self.state.ring.differences(&g, &dg, sup.window);
            if sums.count == 0 {
                break;
            }
            let inv_n = T::one() / T::lit(sums.count as f64);
            let m1 = sums.first.map(|v| v.value() * inv_n);
            let m2 = sums.second.map(|row| row.map(|v| v.value() * inv_n));
            let m0 = sums.s0.value() * inv_n;
            let (f0, d) = objective_differences(sup.objective, m0, &m1, &m2, 1);
            f = f0;
            let ring = &self.state.ring;
            let q0 = q;
            // Tries of the step halving that the quadratic model of the mean square (from
            // the same differences) predicts to raise it are skipped: `m(t) = t G + t^2 C`
            // descends for t < t* = -G / C; a try is skipped only when t > 2 t*, so the
            // model would have to be off by a factor of 2 for the skipped try to have been
            // taken. On the RMS, whose Newton step overshoots (see `newton`), this saves
            // most of the passes the halving costs.
            let inv_dp = T::one() / dp;
            let mut change = |qn: &SVector<T, 4>| {
                let too_long = (0..4).any(|j| (qn[j] - q0[j]).abs() > sup.max_step);
                if too_long || predicted_rise(&m1, &m2, &q0, qn, inv_dp) {
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
        let scale = self.coeffs.scale;
        let old = self.state.alg3.gains();
        let new = match sup.method {
            Method::Rls => Self::from_scaled(self.state.rls.params(), &scale),
            Method::Newton => {
                let (q, f, moved) = self.newton_refit(&old);
                self.state.last_cost = f;
                if !moved {
                    return SupervisionFlags::REFIT_REJECTED;
                }
                Self::from_scaled(&q, &scale)
            }
        };
        if new != old && self.state.alg3.set_gains(new) {
            self.state.refits += 1;
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
        self.state.reset(&self.settings, &self.coeffs);
    }
}

/// Whether the quadratic model of the mean square, from its first and second differences
/// `m1`, `m2` (upper triangle) at `q0` for steps of `dp = 1 / inv_dp`, predicts that
/// moving to `qn` raises it: `m(t) = t G + t^2 C` descends for `t < t* = -G / C`; true
/// only when `t > 2 t*`.
#[inline]
fn predicted_rise<T: Real>(
    m1: &[T; 4],
    m2: &[[T; 4]; 4],
    q0: &SVector<T, 4>,
    qn: &SVector<T, 4>,
    inv_dp: T,
) -> bool {
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
}
