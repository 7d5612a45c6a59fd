//! Settings of the live supervision: the supervisor's ([`SupervisorSettings`]), the
//! supervised estimator's ([`SupervisedAlg3Settings`]) and what [`super::SupervisedAlg3`]
//! refuses ([`SettingsError`]).
use super::newton::{check_settings, NewtonSettings};
use super::rls::RlsSettings;
use super::Objective;
use crate::estimators::alg3::Alg3Settings;
use crate::Real;

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
    /// RLS forgetting, initial covariance (relative), wind-up guard. Default:
    /// [`RlsSettings::default`].
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

/// Settings of [`SupervisedAlg3`](super::SupervisedAlg3): the estimator's and the supervisor's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SupervisedAlg3Settings<T> {
    /// Algorithm 3 (its gains are the start values). Default: [`Alg3Settings::default`].
    pub alg3: Alg3Settings<T>,
    /// The supervisor. Default: [`SupervisorSettings::default`].
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

/// A setting that [`super::SupervisedAlg3::new`] refused.
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

impl<T: Real> SupervisedAlg3Settings<T> {
    /// Checks the settings for a window buffer of `capacity` samples.
    pub(super) fn check(&self, capacity: usize) -> Result<(), SettingsError> {
        let sup = &self.supervisor;
        if sup.window < 3 || sup.window > capacity {
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
        if !self.alg3.gains.is_finite() {
            return Err(SettingsError::Gains);
        }
        Ok(())
    }
}
