//! What a fit returns: its [`FitReport`], the logged [`Iteration`]s and why it
//! stopped ([`Stop`]).
use std::time::Duration;

use super::{lm, Algorithm, Cost, Method, Target};
use pendtilt_core::estimators::equations::Alg3Gains;
use pendtilt_core::PendulumParams;

/// One logged iteration.
#[derive(Debug, Clone, PartialEq)]
pub struct Iteration {
    /// 1-based iteration number (0 is the start).
    pub n: usize,
    /// The parameters after it (a, b or K, L, M, N).
    pub params: Vec<f64>,
    /// The RMS cost (Eq 23 or 29) after it.
    pub cost: f64,
    /// Norm of the gradient used (Newton: finite-difference F'; LM: J'r / n).
    pub gradient_norm: f64,
    /// Newton: the factor that multiplied the step (h, halved as needed). LM: the damping
    /// lambda.
    pub step: f64,
    /// Cost evaluations (passes over the log) in this iteration.
    pub evaluations: usize,
}

/// Why the iterations stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    /// The change of cost or of the parameters met the tolerances.
    Converged,
    /// No step lowered the cost: a minimum to within the finite differences.
    NoDescent,
    /// The iteration limit was reached first.
    IterationLimit,
}

/// The result of a fit.
#[derive(Debug, Clone, PartialEq)]
pub struct FitReport {
    /// Which parameters.
    pub algorithm: Algorithm,
    /// Against what.
    pub target: Target,
    /// Which optimiser.
    pub method: Method,
    /// The cost run ([`Cost::Inverse`] or [`Cost::Output`], never [`Cost::Auto`]).
    pub cost_kind: Cost,
    /// Output cost: whether the simulation was driven by the accelerometer
    /// ([`output::OutputSettings::accel`](super::output::OutputSettings::accel), or chosen automatically for a vibrating log).
    pub accel_drive: bool,
    /// Output cost: the high-frequency RMS of the accelerometer (m/s^2) that decided the
    /// automatic accelerometer drive, when the log has `ax`, `ay`.
    pub vibration_rms: Option<f64>,
    /// Parameter names.
    pub names: Vec<&'static str>,
    /// The start values.
    pub start: Vec<f64>,
    /// The fitted values.
    pub params: Vec<f64>,
    /// RMS cost at the start (rad or rad/s).
    pub start_cost: f64,
    /// RMS cost at the fitted values.
    pub cost: f64,
    /// Every iteration.
    pub iterations: Vec<Iteration>,
    /// Total cost evaluations (passes over the log), including the sensitivity check.
    pub evaluations: usize,
    /// Why it stopped.
    pub stop: Stop,
    /// Residuals in the cost.
    pub samples: usize,
    /// The sensitivity found by the identifiability check.
    pub sensitivity: f64,
    /// Differentiator cutoff used \[Hz\] (output cost: the cutoff of the zero-phase
    /// smoothing of the true angle).
    pub cutoff_hz: f64,
    /// Wall time of the iterations (without computing the kinematics).
    pub elapsed: Duration,
}

impl FitReport {
    /// The fitted pendulum (alg1, alg2: a, b; alg3: a = K, b = L), c = 0.
    pub fn pendulum_params(&self) -> PendulumParams<f64> {
        PendulumParams {
            a: self.params[0],
            b: self.params[1],
            c: 0.0,
        }
    }

    /// The fitted gains (alg3), or the Eq (21)-equivalent gains of a, b.
    pub fn gains(&self) -> Alg3Gains<f64> {
        match self.algorithm {
            Algorithm::Alg3 => Alg3Gains {
                k: self.params[0],
                l: self.params[1],
                m: self.params[2],
                n: self.params[3],
            },
            _ => Alg3Gains::from_params(&self.pendulum_params()),
        }
    }

    /// Unit of the cost: rad (truth) or rad/s (gyro).
    pub fn cost_unit(&self) -> &'static str {
        match self.target {
            Target::Truth => "rad",
            Target::Gyro => "rad/s",
        }
    }
}

impl Iteration {
    /// Iteration 0: the start `params`, their `cost`, and the `evaluations` that took.
    pub(super) fn start(params: Vec<f64>, cost: f64, evaluations: usize) -> Self {
        Self {
            n: 0,
            params,
            cost,
            gradient_norm: f64::NAN,
            step: f64::NAN,
            evaluations,
        }
    }

    /// The record of one Levenberg-Marquardt iteration (its step is the damping).
    pub(super) fn from_lm<const N: usize>(it: &lm::LmIteration<N>, params: Vec<f64>) -> Self {
        Self {
            n: it.n,
            params,
            cost: it.rms,
            gradient_norm: it.gradient_norm,
            step: it.lambda,
            evaluations: it.evaluations,
        }
    }
}
