//! Offline parameter fitting (paper section IV-B, C): the paper's Newton's method on the
//! Eq (23) / Eq (29) cost, and Levenberg-Marquardt with an analytic Jacobian.
//!
//! - Eq (23): `F(P) = RMS(theta_est(P) - theta_true)`, with a true angle
//!   ([`Target::Truth`]).
//! - Eq (29): `F(P) = RMS(d/dt theta_est(P) - G)`, against the gyro ([`Target::Gyro`]);
//!   `d/dt theta_est` is the difference of consecutive estimates over their time step,
//!   compared with the mean of the two gyro samples.
//! - Parameters: a, b for alg1 (Eq 20) and alg2 (Eq 21); K, L, M, N for alg3 (Eq 30).
//!
//! Methods:
//! - [`Method::Newton`]: Eqs (24)-(28) with the finite differences of MODEL.md section 3
//!   (step h, difference dp, tolerances and iteration limit in
//!   [`pendtilt_core::supervision::NewtonSettings`]), one logged [`Iteration`] per step; the
//!   iteration itself is [`pendtilt_core::supervision::newton::newton_iteration`], the same
//!   code the live supervisor runs.
//! - [`Method::Lm`]: Levenberg-Marquardt (beyond the paper) on the sum of squared
//!   residuals, with the analytic Jacobian of Eq (20)/(21)/(30), normal equations
//!   accumulated in one pass into nalgebra 4x4 fixed matrices ([`lm`]). The
//!   `levenberg-marquardt` crate was not used: its current release depends on nalgebra
//!   0.34 (we are on 0.35), and it wants the whole residual vector and Jacobian (100,000 x 4)
//!   materialised and QR-factorised every iteration.
//!
//! Costs ([`Cost`]): the output error of [`output`] (the pendulum simulated from the true
//! angle against the measured phi; the default, [`Cost::Auto`], for a, b against the true
//! angle), or the paper's inverse cost above (`--cost inverse`; the only one for the gyro
//! target and alg3). The output error is not biased by vibration: on a chirp with the full `scooter` vibration it recovers a
//! and b within 2 % where Eq (23) is 4-6 % off; on the 60 s `scooter` ride b within 8-13 %
//! where Eq (23) is 53-57 % low, and within 1 % when the simulation is driven by the
//! accelerometer ([`output::OutputSettings::accel`]) (README, parameter fitting).
//!
//! Fitting is fast because the kinematics are cached: see [`problem`]. The live
//! counterparts (sliding window Newton, RLS) are in [`pendtilt_core::supervision`].
//!
//! # Newton vs Levenberg-Marquardt vs RLS (measured)
//!
//! `cargo bench -p pendtilt --bench fit` on a 100,000-sample log (a 10 s chirp 0.2-3 Hz with
//! the default noisy sensors, repeated to 100 s), alg2, Eq (23), start a x 1.5, b x 0.5, on
//! the 2-core development machine (shared, so +-15 %):
//!
//! | method | iterations | passes over the log | time (fit / with the 14 ms kinematics pass) | final RMS | a error | b error |
//! |---|---|---|---|---|---|---|
//! | Newton (Eqs 24-28, RMS) | 7 | 87 | 171 ms / 188 ms | 3.797e-3 rad | +0.70 % | -1.07 % |
//! | Levenberg-Marquardt | 3 | 6 | 28 ms / 46 ms | 3.797e-3 rad | +0.72 % | -1.07 % |
//!
//! Both reach the same minimum (the 1 % is the log's, whose repeats restart the pendulum
//! every 10 s); LM needs 15 times fewer passes. Live ([`pendtilt_core::supervision`],
//! `SupervisedAlg3`, 1 kHz, bench group `live_supervisor`, thread CPU time on the shared
//! machine): RLS costs 123 ns per sample including the estimator (47 ns alone), the
//! windowed Newton with the defaults (RMS, window 1000, refit every 2000) 113 ns, with a
//! refit every 250 samples 424 ns. With the settings of test `fit_live` (mean square,
//! refit every 250) both converge from 50 % off to within 5 % (RLS) or 10 % (Newton) of a, b, -b in 9.5 s of a
//! chirp and follow a doubling of the damping to within 10 % (Newton in 6.5 s, RLS 9 s).
//!
//! Before fitting, the cost's sensitivity is checked ([`sensitivity`]): a log in which a
//! 100 % change of the parameters (along the least sensitive direction) changes the
//! estimate by less than [`FitSettings::min_sensitivity`] is reported as
//! [`FitError::Unidentifiable`] instead of returning a number.
pub mod lm;
pub mod output;
pub mod plausibility;
pub mod problem;

use std::time::{Duration, Instant};

use nalgebra::{SMatrix, SVector, Vector4};
use pendtilt_core::estimators::equations::Alg3Gains;
use pendtilt_core::estimators::front_end::FrontEndSettings;
use pendtilt_core::supervision::newton::{converged, newton_iteration, NewtonError};
use pendtilt_core::supervision::{NewtonSettings, Objective};
use pendtilt_core::{PendulumParams, Sample};

pub use lm::LmSettings;
pub use problem::{fixed_cutoff, KinematicsSettings, Problem};

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
    fn active(self) -> [bool; 4] {
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
    fn threshold(&self, cost: Cost) -> f64 {
        self.min_sensitivity.unwrap_or(match (cost, self.target) {
            (Cost::Output, _) => 1e-4,
            (_, Target::Truth) => 1e-6,
            (_, Target::Gyro) => 1e-5,
        })
    }
}

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
    /// ([`output::OutputSettings::accel`], or chosen automatically for a vibrating log).
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

/// Computes the kinematics of a log once: see [`Problem::new`].
pub fn prepare(
    samples: &[Sample<f64>],
    truth: Option<&[f64]>,
    settings: &FitSettings,
) -> Result<Problem, FitError> {
    settings.start_vector()?;
    Problem::new(
        samples,
        truth,
        settings.algorithm,
        settings.target,
        &settings.front_end,
        &settings.kinematics,
    )
}

/// The identifiability check: the RMS change of the estimate (truth) or of its rate
/// (gyro) when the parameters change by 100 % of their start size along the least
/// sensitive direction: `sqrt(lambda_min(D J'J D / n))`, D = diag(|p0|) (N scaled like K).
/// Returns it with that direction.
pub fn sensitivity(problem: &Problem, p0: &Vector4<f64>, active: [bool; 4]) -> (f64, Vec<f64>) {
    let (jtj, _, _) = problem.normal_equations(p0);
    let scale = [p0[0].abs(), p0[1].abs(), p0[2].abs(), p0[0].abs()];
    let idx: Vec<usize> = (0..4).filter(|&j| active[j]).collect();
    let m = idx.len();
    let mut s = nalgebra::DMatrix::<f64>::zeros(m, m);
    for (a, &i) in idx.iter().enumerate() {
        for (b, &j) in idx.iter().enumerate() {
            s[(a, b)] = jtj[(i, j)] * scale[i] * scale[j] / problem.len() as f64;
        }
    }
    let eig = s.symmetric_eigen();
    let (k, &lmin) = eig
        .eigenvalues
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))
        .unwrap_or((0, &0.0));
    let dir = if m > 0 {
        eig.eigenvectors.column(k).iter().copied().collect()
    } else {
        Vec::new()
    };
    (lmin.max(0.0).sqrt(), dir)
}

/// Identifiability of the inverse fit ([`sensitivity`] at `p0`): the sensitivity, its
/// threshold and unit, or [`FitError::Unidentifiable`] with the flat direction.
fn inverse_identifiability(
    problem: &Problem,
    settings: &FitSettings,
    p0: &Vector4<f64>,
) -> Result<(f64, f64, &'static str), FitError> {
    let (sens, dir) = sensitivity(problem, p0, settings.algorithm.active());
    let threshold = settings.threshold(Cost::Inverse);
    let unit = match settings.target {
        Target::Truth => "rad",
        Target::Gyro => "rad/s",
    };
    if sens.is_nan() || sens < threshold {
        let names = settings.algorithm.names();
        let direction = names
            .iter()
            .zip(&dir)
            .map(|(n, d)| format!("{n} {d:+.2}"))
            .collect::<Vec<_>>()
            .join(", ");
        return Err(FitError::Unidentifiable {
            sensitivity: sens,
            threshold,
            unit,
            direction,
        });
    }
    Ok((sens, threshold, unit))
}

impl Iteration {
    /// Iteration 0: the start `params`, their `cost`, and the `evaluations` that took.
    fn start(params: Vec<f64>, cost: f64, evaluations: usize) -> Self {
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
    fn from_lm<const N: usize>(it: &lm::LmIteration<N>, params: Vec<f64>) -> Self {
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

/// Fits the parameters of `problem` as `settings` say; `on_iteration` sees every
/// iteration as it is made (iteration 0 is the start).
pub fn fit(
    problem: &Problem,
    settings: &FitSettings,
    mut on_iteration: impl FnMut(&Iteration),
) -> Result<FitReport, FitError> {
    if problem.algorithm() != settings.algorithm || problem.target() != settings.target {
        return Err(FitError::BadSettings(
            "the problem was prepared for another algorithm or target".into(),
        ));
    }
    let p0 = settings.start_vector()?;
    let active = settings.algorithm.active();
    let n_active = settings.algorithm.names().len();
    let started = Instant::now();
    let (sens, threshold, unit) = inverse_identifiability(problem, settings, &p0)?;
    let start_cost = problem.cost(&p0, Objective::Rms);
    if !start_cost.is_finite() {
        return Err(FitError::NonFiniteCost);
    }
    let take = |p: &Vector4<f64>| p.iter().take(n_active).copied().collect::<Vec<f64>>();
    let it0 = Iteration::start(take(&p0), start_cost, 2);
    on_iteration(&it0);
    let mut iterations = vec![it0];
    let mut evaluations = 2usize;
    let (p, stop) = match settings.method {
        Method::Newton => {
            let objective = settings.objective;
            newton_fit(
                &mut |p: &Vector4<f64>| problem.cost(p, objective),
                p0,
                &active,
                &settings.newton,
                (sens, threshold, unit),
                |p| (take(p), problem.cost(p, Objective::Rms)),
                &mut on_iteration,
                &mut iterations,
                &mut evaluations,
            )?
        }
        Method::Lm => {
            let out = lm::levenberg_marquardt(problem, &p0, &active, &settings.lm, |it| {
                let rec = Iteration::from_lm(it, take(&it.params));
                on_iteration(&rec);
                iterations.push(rec);
            })?;
            evaluations += out.evaluations;
            (out.params, out.stop)
        }
    };
    let elapsed = started.elapsed();
    Ok(FitReport {
        algorithm: settings.algorithm,
        target: settings.target,
        method: settings.method,
        cost_kind: Cost::Inverse,
        accel_drive: false,
        vibration_rms: None,
        names: settings.algorithm.names().to_vec(),
        start: take(&p0),
        params: take(&p),
        start_cost,
        cost: problem.cost(&p, Objective::Rms),
        iterations,
        evaluations,
        stop,
        samples: problem.len(),
        sensitivity: sens,
        cutoff_hz: problem.cutoff_hz(),
        elapsed,
    })
}

/// [`prepare`] then [`fit`]; with [`Cost::Output`] (also [`Cost::Auto`] for a, b against
/// the true angle), [`fit_output_log`].
pub fn fit_log(
    samples: &[Sample<f64>],
    truth: Option<&[f64]>,
    settings: &FitSettings,
    on_iteration: impl FnMut(&Iteration),
) -> Result<FitReport, FitError> {
    if settings.cost.resolve(settings.target, settings.algorithm) == Cost::Output {
        return fit_output_log(samples, truth, settings, on_iteration);
    }
    let problem = prepare(samples, truth, settings)?;
    fit(&problem, settings, on_iteration)
}

/// The output-error fit ([`output`]) of a, b: Levenberg-Marquardt ([`Method::Lm`]) or the
/// paper's Newton, Eqs (24)-(28), on the RMS output error ([`Method::Newton`]). Needs the
/// truth target and alg1 or alg2; reports [`FitError::Unidentifiable`] like [`fit`].
pub fn fit_output_log(
    samples: &[Sample<f64>],
    truth: Option<&[f64]>,
    settings: &FitSettings,
    mut on_iteration: impl FnMut(&Iteration),
) -> Result<FitReport, FitError> {
    if settings.target != Target::Truth || settings.algorithm == Algorithm::Alg3 {
        return Err(FitError::BadSettings(
            "the output-error cost fits a, b (alg1, alg2) against the true angle only".into(),
        ));
    }
    let p0 = settings.start_vector()?;
    let problem = output::OutputProblem::new(samples, truth, &settings.output)?;
    let started = Instant::now();
    let threshold = settings.threshold(Cost::Output);
    let (sens, sum0) = output_identifiability(&problem, &p0, threshold)?;
    let n = problem.len() as f64;
    let start_cost = (sum0 / n).sqrt();
    if !start_cost.is_finite() {
        return Err(FitError::NonFiniteCost);
    }
    let it0 = Iteration::start(vec![p0[0], p0[1]], start_cost, 5);
    on_iteration(&it0);
    let mut iterations = vec![it0];
    let mut evaluations = 5usize;
    let (p, stop) = match settings.method {
        Method::Lm => {
            let out = output::fit_output(&problem, p0[0], p0[1], &settings.lm, |it| {
                let rec = Iteration::from_lm(it, vec![it.params[0], it.params[1]]);
                on_iteration(&rec);
                iterations.push(rec);
            })?;
            evaluations += out.evaluations;
            (
                Vector4::new(out.params[0], out.params[1], 0.0, 0.0),
                out.stop,
            )
        }
        Method::Newton => {
            let objective = settings.objective;
            let mut scratch = Vec::with_capacity(problem.len());
            newton_fit(
                &mut |p: &Vector4<f64>| {
                    objective.from_sum(problem.residuals(p[0], p[1], &mut scratch), problem.len())
                },
                p0,
                &[true, true, false, false],
                &settings.newton,
                (sens, threshold, "rad"),
                |p| (vec![p[0], p[1]], problem.cost(p[0], p[1])),
                &mut on_iteration,
                &mut iterations,
                &mut evaluations,
            )?
        }
    };
    let elapsed = started.elapsed();
    Ok(FitReport {
        algorithm: settings.algorithm,
        target: settings.target,
        method: settings.method,
        cost_kind: Cost::Output,
        accel_drive: problem.accel_driven(),
        vibration_rms: problem.vibration_rms(),
        names: settings.algorithm.names().to_vec(),
        start: vec![p0[0], p0[1]],
        params: vec![p[0], p[1]],
        start_cost,
        cost: problem.cost(p[0], p[1]),
        iterations,
        evaluations,
        stop,
        samples: problem.len(),
        sensitivity: sens,
        cutoff_hz: settings.output.smoothing_hz,
        elapsed,
    })
}

/// Identifiability of the output-error fit, as [`sensitivity`] on the output error's
/// Jacobian at `p0`: the sensitivity and the sum of squares there, or
/// [`FitError::Unidentifiable`] below `threshold`.
fn output_identifiability(
    problem: &output::OutputProblem,
    p0: &Vector4<f64>,
    threshold: f64,
) -> Result<(f64, f64), FitError> {
    let (jtj, _, sum0) = problem.normal_equations(p0[0], p0[1]);
    let n = problem.len() as f64;
    let d = nalgebra::Matrix2::new(p0[0], 0.0, 0.0, p0[1]);
    let eig = (d * jtj * d / n).symmetric_eigen();
    let k = if eig.eigenvalues[0] <= eig.eigenvalues[1] {
        0
    } else {
        1
    };
    let sens = eig.eigenvalues[k].max(0.0).sqrt();
    if sens.is_nan() || sens < threshold {
        let v = eig.eigenvectors.column(k);
        return Err(FitError::Unidentifiable {
            sensitivity: sens,
            threshold,
            unit: "rad",
            direction: format!("a {:+.2}, b {:+.2}", v[0], v[1]),
        });
    }
    Ok((sens, sum0))
}

/// Solves `(A + shift) x = b` on the active block with Cholesky (inactive: x = 0).
pub(crate) fn solve_active<const N: usize>(
    a: &SMatrix<f64, N, N>,
    b: &SVector<f64, N>,
    active: &[bool; N],
) -> Option<SVector<f64, N>> {
    let mut m = *a;
    let mut r = *b;
    for j in 0..N {
        if !active[j] {
            for k in 0..N {
                m[(j, k)] = 0.0;
                m[(k, j)] = 0.0;
            }
            m[(j, j)] = 1.0;
            r[j] = 0.0;
        }
    }
    let x = m.cholesky()?.solve(&r);
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// The paper's Newton loop (Eqs 24-28) on `cost` from `p0` over the `active` parameters,
/// shared by the Eq (23) and the output-error fits: one logged [`Iteration`] per step
/// (its parameters and RMS cost from `record`), evaluations counted, stopping on
/// convergence, on no descent or at the iteration limit. A singular Hessian is reported
/// as unidentifiable with `flat` = (sensitivity, threshold, unit).
#[allow(clippy::too_many_arguments)]
fn newton_fit(
    cost: &mut impl FnMut(&Vector4<f64>) -> f64,
    p0: Vector4<f64>,
    active: &[bool; 4],
    s: &NewtonSettings<f64>,
    flat: (f64, f64, &'static str),
    mut record: impl FnMut(&Vector4<f64>) -> (Vec<f64>, f64),
    on_iteration: &mut impl FnMut(&Iteration),
    iterations: &mut Vec<Iteration>,
    evaluations: &mut usize,
) -> Result<(Vector4<f64>, Stop), FitError> {
    pendtilt_core::supervision::newton::check_settings(s)
        .map_err(|_| FitError::BadSettings("Newton h and dp must be finite and > 0".into()))?;
    let mut p = p0;
    let mut f = cost(&p);
    *evaluations += 1;
    for n in 1..=s.max_iterations {
        let it = match newton_iteration(cost, &p, f, active, s) {
            Ok(it) => it,
            Err(NewtonError::FlatCost) => {
                return Err(FitError::Unidentifiable {
                    sensitivity: flat.0,
                    threshold: flat.1,
                    unit: flat.2,
                    direction: "Newton's finite-difference Hessian is singular".into(),
                })
            }
            Err(NewtonError::NonFiniteCost) => return Err(FitError::NonFiniteCost),
            Err(NewtonError::BadSettings) => {
                return Err(FitError::BadSettings("Newton settings".into()))
            }
        };
        *evaluations += it.evaluations;
        let (params, rms) = record(&it.params);
        let rec = Iteration {
            n,
            params,
            cost: rms,
            gradient_norm: it.gradient.norm(),
            step: it.step_scale,
            evaluations: it.evaluations,
        };
        on_iteration(&rec);
        iterations.push(rec);
        if it.stalled {
            return Ok((p, Stop::NoDescent));
        }
        let done = converged(&p, &it.params, f, it.cost, s);
        p = it.params;
        f = it.cost;
        if done {
            return Ok((p, Stop::Converged));
        }
    }
    Ok((p, Stop::IterationLimit))
}
