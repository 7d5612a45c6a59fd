//! What a fit is asked to do ([`FitSettings`]): the algorithm, target, cost and method,
//! and the errors a fit can end in ([`FitError`]).

use super::{output, KinematicsSettings, LmSettings};
use nalgebra::Vector4;
use pendtilt_core::estimators::equations::Alg3Gains;
use pendtilt_core::estimators::front_end::FrontEndSettings;
use pendtilt_core::supervision::{NewtonSettings, Objective};

/// Which estimator's parameters are fitted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Algorithm {
    /// Eq (20): a, b.
    Alg1,
    /// Eq (21): a, b.
    Alg2,
    /// Eq (30): K, L, M, N.
    Alg3,
}

impl Algorithm {
    /// The names of the fitted parameters.
    pub fn names(self) -> &'static [&'static str] {
        match self {
            Algorithm::Alg1 | Algorithm::Alg2 => &["a", "b"],
            Algorithm::Alg3 => &["K", "L", "M", "N"],
        }
    }

    /// Which of the four internal parameters move.
    pub(super) fn active(self) -> [bool; 4] {
        match self {
            Algorithm::Alg1 | Algorithm::Alg2 => [true, true, false, false],
            Algorithm::Alg3 => [true; 4],
        }
    }
}

/// What the estimate is compared with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Target {
    /// The true angle (`theta` column), Eq (23).
    Truth,
    /// The gyro, Eq (29).
    Gyro,
}

/// Which cost is minimised.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum Cost {
    /// The default: the output error wherever it applies (truth target, alg1/alg2), else
    /// the paper's inverse cost (gyro target, alg3), the only one there.
    #[default]
    Auto,
    /// The paper's Eq (23) (or Eq 29 for the gyro target): the inverted estimate against
    /// the target. Biased on a vibrating body (b comes out low, 29 % on the 60 s scooter
    /// ride).
    Inverse,
    /// Output error (module fit::output): the pendulum simulated from the true angle
    /// against the measured phi. Unbiased under vibration; alg1/alg2 (a, b) and the truth
    /// target only.
    Output,
}

impl Cost {
    /// The cost actually run: [`Cost::Auto`] becomes [`Cost::Output`] for a, b against
    /// the true angle and [`Cost::Inverse`] otherwise; the others stay.
    pub fn resolve(self, target: Target, algorithm: Algorithm) -> Cost {
        match self {
            Cost::Auto if target == Target::Truth && algorithm != Algorithm::Alg3 => Cost::Output,
            Cost::Auto => Cost::Inverse,
            c => c,
        }
    }

    /// A short description for messages.
    pub fn describe(self) -> &'static str {
        match self {
            Cost::Auto => "auto",
            Cost::Inverse => "the paper's inverse cost (Eq 23/29; biased under vibration)",
            Cost::Output => "output error (phi measured - phi simulated from the true angle)",
        }
    }
}

/// Which optimiser.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Method {
    /// The paper's Newton's method, Eqs (24)-(28).
    Newton,
    /// Levenberg-Marquardt with the analytic Jacobian.
    Lm,
}

/// Why a fit failed.
#[derive(Debug, thiserror::Error)]
pub enum FitError {
    /// A start value that the model cannot take.
    #[error("invalid start value {name} = {value}: {why}")]
    InvalidStart {
        /// The parameter.
        name: &'static str,
        /// Its value.
        value: f64,
        /// The rule it breaks.
        why: &'static str,
    },
    /// The log lacks a column the fit needs.
    #[error("the log has no usable `{0}` column, which this fit needs")]
    MissingColumn(&'static str),
    /// Not enough usable samples.
    #[error("only {have} usable samples after the settling time; a fit needs at least {need}")]
    TooFewSamples {
        /// Usable residuals.
        have: usize,
        /// Needed.
        need: usize,
    },
    /// The cost is flat: the log does not determine the parameters.
    #[error(
        "the parameters are not identifiable from this log: changing them by 100 % along \
         the least sensitive direction ({direction}) changes the estimate by only \
         {sensitivity:.3e} {unit} RMS (threshold {threshold:.1e}); the log needs more \
         motion"
    )]
    Unidentifiable {
        /// RMS change of the estimate (or of its rate) per 100 % parameter change.
        sensitivity: f64,
        /// The threshold.
        threshold: f64,
        /// rad or rad/s.
        unit: &'static str,
        /// The least sensitive direction, as relative parameter changes.
        direction: String,
    },
    /// The cost is not finite at the start.
    #[error("the cost is not finite at the start values")]
    NonFiniteCost,
    /// A setting that cannot be used.
    #[error("bad setting: {0}")]
    BadSettings(String),
}

/// Everything a fit is told.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitSettings {
    /// Which parameters. Default alg2.
    pub algorithm: Algorithm,
    /// Against what. Default the true angle.
    pub target: Target,
    /// Which optimiser. Default Newton.
    pub method: Method,
    /// Which cost. Default [`Cost::Auto`]: the output error for a, b against the true
    /// angle (unbiased under vibration), the paper's Eq (23) / (29) otherwise.
    pub cost: Cost,
    /// Settings of the output-error cost ([`Cost::Output`]).
    pub output: output::OutputSettings,
    /// The estimator's front end the kinematics are computed with (the phi
    /// differentiator, whose cutoff relative to f_n is fixed in Hz from the start; which
    /// phi; theta''), and in its `params` the start a, b (alg1, alg2). Default:
    /// [`FrontEndSettings::default`] (the MODEL.md rig).
    pub front_end: FrontEndSettings<f64>,
    /// Start K, L, M, N for alg3. Default (None): K = a, L = b, M = -b, N = 0.
    pub start_gains: Option<Alg3Gains<f64>>,
    /// What the kinematics' cost reads of them.
    pub kinematics: KinematicsSettings,
    /// Newton's h, dp (absolute), tolerances, iteration limit. Default h = 1, dp = 1e-6,
    /// ftol 1e-10, xtol 1e-8, 100 iterations.
    pub newton: NewtonSettings<f64>,
    /// What Newton minimises. Default the paper's RMS.
    pub objective: Objective,
    /// Levenberg-Marquardt settings.
    pub lm: LmSettings,
    /// Smallest RMS change of the estimate for a 100 % parameter change below which the
    /// log is reported as unidentifiable: rad for the truth target, rad/s for the gyro.
    /// Default None: 1e-6 rad, 1e-5 rad/s; 1e-4 rad for [`Cost::Output`]. (Measured: a still
    /// log gives exactly 0, since the encoder reading does not move; the paper's sigmoid
    /// gives 8.6e-5 rad for alg2's b. Output cost: a still log 1.1e-5 rad, the potentiometer's
    /// noise driving the simulated pendulum; the 8 s chirp of `fit_offline` 1.4e-2 rad.)
    pub min_sensitivity: Option<f64>,
}

impl Default for FitSettings {
    fn default() -> Self {
        Self {
            algorithm: Algorithm::Alg2,
            target: Target::Truth,
            method: Method::Newton,
            cost: Cost::Auto,
            output: output::OutputSettings::default(),
            front_end: FrontEndSettings::default(),
            start_gains: None,
            kinematics: KinematicsSettings::default(),
            newton: NewtonSettings::default(),
            objective: Objective::Rms,
            lm: LmSettings::default(),
            min_sensitivity: None,
        }
    }
}

impl FitSettings {
    /// The start as the four internal parameters, checked: a and b (K and L) must be
    /// finite and > 0, M and N finite.
    pub fn start_vector(&self) -> Result<Vector4<f64>, FitError> {
        let pos = "must be a finite number > 0";
        let check = |name, value: f64, positive: bool| {
            if !value.is_finite() || (positive && value <= 0.0) {
                Err(FitError::InvalidStart {
                    name,
                    value,
                    why: if positive { pos } else { "must be finite" },
                })
            } else {
                Ok(())
            }
        };
        match self.algorithm {
            Algorithm::Alg1 | Algorithm::Alg2 => {
                let start = &self.front_end.params;
                check("a", start.a, true)?;
                check("b", start.b, true)?;
                Ok(Vector4::new(start.a, start.b, 0.0, 0.0))
            }
            Algorithm::Alg3 => {
                check("b", self.front_end.params.b, true)?;
                let g = self
                    .start_gains
                    .unwrap_or_else(|| Alg3Gains::from_params(&self.front_end.params));
                check("K", g.k, true)?;
                check("L", g.l, true)?;
                check("M", g.m, false)?;
                check("N", g.n, false)?;
                Ok(Vector4::new(g.k, g.l, g.m, g.n))
            }
        }
    }

    /// The identifiability threshold of `cost` (the one actually run).
    pub(super) fn threshold(&self, cost: Cost) -> f64 {
        self.min_sensitivity.unwrap_or(match (cost, self.target) {
            (Cost::Output, _) => 1e-4,
            (_, Target::Truth) => 1e-6,
            (_, Target::Gyro) => 1e-5,
        })
    }
}
