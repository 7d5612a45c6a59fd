//! Algorithm 3 (Eq 30) with live supervision of K, L, M, N against the gyro (Eq 29).
//!
//! Every sample, [`SupervisedAlg3`] runs [`Alg3`] and keeps the terms of Eq (30) in a ring
//! buffer of capacity `CAP` (no allocation). Then, by [`Method`]:
//! - [`Method::Newton`] (the paper): every [`SupervisorSettings::refit_interval`] samples,
//!   [`SupervisorSettings::newton_iterations`] iterations of Newton's method (Eqs 24-28) on
//!   the Eq (29) cost over the last [`SupervisorSettings::window`] samples. Each iteration
//!   costs 15 passes over the window, so the amortised per-sample cost is about
//!   `15 * iterations * window / refit_interval` evaluations of Eq (30).
//! - [`Method::Rls`]: every sample, one recursive-least-squares update (see
//!   [`super::rls`]) of the derivative of Eq (30), linearised in K, L, M at the current
//!   gains: `G - (phi_k - phi_(k-1))/dt = K c dphi' + L c dphi'' + M c dG_d + N dG_k`, with
//!   `c = 1 / sqrt(1 - u^2)` the derivative of asin at the current argument `u` and the
//!   primes finite differences of consecutive samples. The gains are handed to the
//!   estimator every `refit_interval` samples.
//!
//! Internally the gains are scaled by their start values (K, N by |K0|, L by |L0|, M by
//! |M0|), so [`NewtonSettings::dp`] and [`RlsSettings::p0`] are relative. Newton's finite
//! differences need f64 (with f32 set dp to 1e-2 or more, or use RLS).
//!
//! The gains adapt when the rig changes: a change of friction moves K, a change of the
//! sample time (a clock that drifts against the time stamps) moves all four.
use super::newton::{check_settings, newton_iteration, NewtonSettings};
use super::rls::{Rls, RlsSettings};
use super::Objective;
use crate::estimators::alg3::{Alg3, Alg3Settings};
use crate::estimators::equations::{clamped_asin, Alg3Gains};
use crate::estimators::theta_dd::DEFAULT_WINDOW_CAPACITY;
use crate::filters::diff::SmoothingDifferentiator;
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
    t: T,
    phi: T,
    gyro: T,
    x: [T; 4],
}

/// Ring buffer of the Eq (29) terms: for each sample the Eq (30) inputs
/// `x = [phi', phi'', G_d, G_k]`, the parameter-free part `y` of the residual and `1/dt`.
#[derive(Debug, Clone)]
struct Ring<T, const CAP: usize> {
    x: [[T; 4]; CAP],
    y: [T; CAP],
    inv_dt: [T; CAP],
    linked: [bool; CAP],
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
        self.head = (self.head + 1) % CAP;
        if self.len < CAP {
            self.len += 1;
        }
    }

    /// Eq (29) over the last `window` samples for the real gains `g` (K, L, M, N).
    fn cost(&self, g: &[T; 4], window: usize, objective: Objective) -> T {
        let n = window.min(self.len);
        let start = (self.head + CAP - n) % CAP;
        let mut sum = T::zero();
        let mut count = 0usize;
        let mut s_prev = T::zero();
        for i in 0..n {
            let j = (start + i) % CAP;
            let x = &self.x[j];
            let (a, _) = clamped_asin(g[0] * x[0] + g[1] * x[1] + g[2] * x[2]);
            let s = a + g[3] * x[3];
            if i > 0 && self.linked[j] {
                let r = (s - s_prev) * self.inv_dt[j] - self.y[j];
                sum += r * r;
                count += 1;
            }
            s_prev = s;
        }
        objective.from_sum(sum, count)
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
    gyro_lp: SmoothingDifferentiator<T>,
    lp_t: Option<T>,
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
            gyro_lp: SmoothingDifferentiator::new(
                settings.alg3.differentiator.response,
                settings
                    .alg3
                    .differentiator
                    .cutoff_hz(&settings.alg3.params),
            ),
            lp_t: None,
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
        // Matched: the low-passed gyro for G and for the N term; "phi" carries phi' (the
        // rate of the low-passed phi), see `matched`.
        let (gyro, phi_or_rate) = if sup.matched {
            let dt = self.lp_t.map_or(T::one(), |tp| s.t - tp);
            self.lp_t = Some(s.t);
            (self.gyro_lp.update(s.gyro, dt).value, terms.dphi)
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
            t: s.t,
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
        let dt = s.t - prev.t;
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

    fn refit(&mut self) -> SupervisionFlags {
        let sup = self.settings.supervisor;
        let scale = self.scale;
        let old = self.alg3.gains();
        let new = match sup.method {
            Method::Rls => Self::from_scaled(self.rls.params(), &scale),
            Method::Newton => {
                let ring = &self.ring;
                let mut cost = |q: &SVector<T, 4>| {
                    let g = [
                        q[0] * scale[0],
                        q[1] * scale[1],
                        q[2] * scale[2],
                        q[3] * scale[3],
                    ];
                    ring.cost(&g, sup.window, sup.objective)
                };
                let mut q = Self::to_scaled(&old, &scale);
                let mut f = cost(&q);
                let mut moved = false;
                for _ in 0..sup.newton_iterations.max(1) {
                    match newton_iteration(&mut cost, &q, f, &sup.adapt, &sup.newton) {
                        Ok(it) if !it.stalled => {
                            q = it.params;
                            f = it.cost;
                            moved = true;
                        }
                        _ => break,
                    }
                }
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

impl<T: Real, const CAP: usize, const W: usize> Estimator<T> for SupervisedAlg3<T, CAP, W> {
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
        self.gyro_lp.reset();
        self.lp_t = None;
        self.prev = None;
        self.seen = 0;
        self.since_refit = 0;
        self.refits = 0;
        self.last_cost = T::nan();
    }
}
