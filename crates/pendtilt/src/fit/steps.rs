//! The steps of a planar fit from a log file (`pendtilt fit`): the log read in SI units,
//! the settings from the command's options, the hint on a time column in ms, the check of
//! the output cost's smoothing, the check of a result, and the rig file of a fitted
//! pendulum.
use std::path::Path;

use super::{Algorithm, Cost, FitReport, FitSettings, Method, Problem, Target};
use crate::config::RigConfig;
use crate::io::{Column, LogReader, ReaderOptions};
use pendtilt_core::estimators::front_end::FrontEndSettings;
use pendtilt_core::filters::diff::Cutoff;
use pendtilt_core::supervision::Objective;
use pendtilt_core::PendulumParams;

/// A planar log's columns as the fit reads them, in SI units.
pub struct FitLog {
    /// The rows as samples.
    pub samples: Vec<pendtilt_core::Sample<f64>>,
    /// The rows' time stamps \[s\].
    pub stamps: Vec<f64>,
    /// The true angle (NaN where missing, or everywhere without a `theta` column).
    pub truth: Vec<f64>,
    /// Whether the log has a `theta` column.
    pub has_theta: bool,
}

impl FitLog {
    /// Reads the whole log at `path` with `options`; `say` is given each line to tell: the
    /// file and its columns, each warning (`warning: ...`), and the samples read.
    pub fn read(
        path: &Path,
        options: ReaderOptions,
        mut say: impl FnMut(&str),
    ) -> anyhow::Result<FitLog> {
        let mut log = LogReader::open(path, options)?;
        say(&format!("{}: {}", log.file(), log.columns()));
        let has_theta = log.columns().has(Column::Theta);
        let mut samples = Vec::new();
        let mut stamps = Vec::new();
        let mut truth = Vec::new();
        while let Some(rec) = log.next_record()? {
            for w in log.drain_warnings() {
                say(&format!("warning: {w}"));
            }
            samples.push(rec.sample);
            stamps.push(rec.t);
            truth.push(rec.theta.unwrap_or(f64::NAN));
        }
        // The end of the log's warnings: the unit check's.
        for w in log.drain_warnings() {
            say(&format!("warning: {w}"));
        }
        say(&format!("read {} samples", samples.len()));
        Ok(FitLog {
            samples,
            stamps,
            truth,
            has_theta,
        })
    }
}

/// The options of a planar fit, as `pendtilt fit` takes them (each field its option).
#[derive(Debug, Clone, Copy)]
pub struct FitOptions {
    /// Which parameters (`--algorithm`).
    pub algorithm: Algorithm,
    /// What the cost compares with (`--target`).
    pub target: Target,
    /// The optimiser (`--method`, Newton by default).
    pub method: Method,
    /// The cost (`--cost`).
    pub cost: Cost,
    /// Whether a start a or b was given (`--a`, `--b`): alg3 then starts from them, not
    /// from the rig's gains.
    pub start_given: bool,
    /// The mean square instead of the RMS (`--mean-square`).
    pub mean_square: bool,
    /// Seconds left out at the start (`--skip`).
    pub skip: f64,
    /// The raw target instead of the matched one (`--unmatched`).
    pub unmatched: bool,
    /// Newton's step factor (`--h`).
    pub h: f64,
    /// Newton's finite difference (`--dp`).
    pub dp: f64,
    /// The iteration limit (`--max-iterations`).
    pub max_iterations: usize,
    /// Newton's cost tolerance (`--ftol`).
    pub ftol: f64,
    /// Newton's parameter tolerance (`--xtol`).
    pub xtol: f64,
    /// The output cost's smoothing of the true angle, Hz (`--smoothing-hz`).
    pub smoothing_hz: f64,
    /// Always drive with the accelerometer (`--accel-drive`).
    pub accel_drive: bool,
    /// Never drive with the accelerometer (`--no-accel-drive`).
    pub no_accel_drive: bool,
}

impl FitOptions {
    /// The fit's settings from these options and the rig, starting at `start`.
    pub fn settings(&self, rig: &RigConfig, start: PendulumParams<f64>) -> FitSettings {
        let mut settings = FitSettings {
            algorithm: self.algorithm,
            target: self.target,
            method: self.method,
            cost: self.cost,
            front_end: FrontEndSettings {
                differentiator: rig.diff_settings(),
                ..FrontEndSettings::from_params(start)
            },
            start_gains: (self.algorithm == Algorithm::Alg3 && !self.start_given)
                .then(|| rig.alg3_gains()),
            objective: if self.mean_square {
                Objective::MeanSquare
            } else {
                Objective::Rms
            },
            ..FitSettings::default()
        };
        settings.kinematics.skip = self.skip;
        settings.kinematics.matched_target = !self.unmatched;
        settings.newton.h = self.h;
        settings.newton.dp = self.dp;
        settings.newton.max_iterations = self.max_iterations;
        settings.newton.ftol = self.ftol;
        settings.newton.xtol = self.xtol;
        settings.lm.max_iterations = self.max_iterations;
        settings.output.smoothing_hz = self.smoothing_hz;
        settings.output.accel = self.accel_drive;
        settings.output.auto_accel = !self.no_accel_drive;
        settings.output.skip = self.skip.max(settings.output.skip);
        settings
    }
}

/// A slow median step is the usual sign of time in ms: said beside any failure.
pub fn time_hint(span: Option<super::plausibility::LogSpan>) -> String {
    match span {
        Some(s) if s.median_step >= 0.05 => format!(
            " (the log's median time step is {:.3} s, i.e. {:.2} Hz: if its time column is in \
             ms, divide it by 1000)",
            s.median_step,
            1.0 / s.median_step
        ),
        _ => String::new(),
    }
}

/// The output cost's smoothing (`smoothing_hz`, `--smoothing-hz`) must lie below the log's
/// Nyquist frequency.
pub fn check_smoothing(smoothing_hz: f64, s: &super::plausibility::LogSpan) -> anyhow::Result<()> {
    // Seven significant digits, written plainly (500, not 499.99999999999955).
    let tidy = |x: f64| format!("{x:.6e}").parse::<f64>().unwrap_or(x);
    let nyquist = tidy(0.5 / s.median_step);
    anyhow::ensure!(
        smoothing_hz < nyquist,
        "--smoothing-hz {} Hz is at or above the Nyquist frequency {nyquist} Hz of this log \
         (median time step {} s): valid above 0 up to below {nyquist} Hz",
        smoothing_hz,
        tidy(s.median_step)
    );
    Ok(())
}

/// Refuses a fit outside the physical region, and an implausible one unless
/// `accept_implausible` (`--accept-implausible`; then `warn` is given the warning);
/// `output` is the rig file not written.
pub fn check_result(
    accept_implausible: bool,
    output: &Path,
    report: &FitReport,
    fitted: &PendulumParams<f64>,
    implausible: &[super::plausibility::Implausible],
    warn: impl FnOnce(&str),
) -> anyhow::Result<()> {
    anyhow::ensure!(
        fitted.a >= 0.0 && fitted.b > 0.0,
        "the fit left the physical region ({} = {:.4e}, {} = {:.4e}): not written; check the \
         log's columns and units, or start closer",
        report.names[0],
        fitted.a,
        report.names[1],
        fitted.b
    );
    if !implausible.is_empty() {
        let why: Vec<String> = implausible.iter().map(|i| format!("  - {i}")).collect();
        // A non-zero exit, and no rig file: a wrong pendulum written quietly would spoil
        // every later `estimate`, and scripts read exit codes, not warnings.
        anyhow::ensure!(
            accept_implausible,
            "the fitted pendulum is implausible for this log:\n{}\n{} not written; check the \
             log's units (time in s, angles in rad or --deg) and that it moves the pendulum, \
             or pass --accept-implausible to write it anyway",
            why.join("\n"),
            output.display()
        );
        warn(&format!(
            "warning: the fitted pendulum is implausible for this log (written anyway, \
             --accept-implausible):\n{}",
            why.join("\n")
        ));
    }
    Ok(())
}

/// The rig file to write: the fitted pendulum, the differentiator the fit used, alg3's
/// gains when fitted (`algorithm`); `rig` is the start rig, `problem` the inverse cost's.
pub fn fitted_rig(
    algorithm: Algorithm,
    rig: RigConfig,
    report: &FitReport,
    fitted: PendulumParams<f64>,
    problem: Option<&Problem>,
) -> anyhow::Result<RigConfig> {
    let mut differentiator = rig.differentiator;
    let mut rig = RigConfig::from_params(fitted)?;
    // The differentiator the fit used, fixed in Hz as its kinematics were, so that
    // `pendtilt estimate` with this file computes exactly what was fitted.
    // (The output cost uses no differentiator: the rig's own settings are kept.)
    if let Some(problem) = problem {
        differentiator.cutoff = Cutoff::Hz(problem.cutoff_hz());
    }
    rig.differentiator = differentiator;
    if algorithm == Algorithm::Alg3 {
        rig.alg3.gains = report.gains();
    }
    rig.validate()?;
    Ok(rig)
}
