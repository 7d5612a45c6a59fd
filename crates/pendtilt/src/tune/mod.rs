//! Self-tuning: every estimator's settings from the user's own log, with no true angle.
//! One concern per module:
//!
//! - [`spectrum`]: Welch power spectral densities (the other estimators read them).
//! - [`encoder`]: encoder quantisation step and noise.
//! - [`gyro`]: gyro noise density and bias (still stretches, else the high band).
//! - [`accel`]: accelerometer noise floor and the vibration level per band.
//! - [`forcing`]: the EKF's pendulum forcing density (the accelerometer's residual near
//!   the natural frequency) and the encoder's jitter (the encoder's power above the
//!   pendulum's band, scaled toward its density in the filter's band by the EKF's error
//!   against the gyro's integral above 0.2 Hz).
//! - [`cutoff`]: the differentiator cutoff of Algorithms 1-3: measured against the
//!   gyro's integral in the band above 0.2 Hz ([`mod@reference`]) when the log has a gyro,
//!   else from the encoder's spectrum (a noise/delay trade-off rule).
//! - [`kalman`]: q_angle, q_bias and R of the `kf_*` filters by maximum likelihood of
//!   their innovations (reported);
//! - [`surrogate`]: the same three against a surrogate of `kf_alg2`'s error built from
//!   the gyro, a grid over R and q/R before the coordinate search (adopted when the log
//!   has a gyro: the likelihood takes Algorithm 2's coloured errors as white and trusts
//!   it too much); and the accelerometer's R alone on its surrogate, anchored on
//!   Algorithm 2 below the corner ([`surrogate::Surrogate::against`]), twice: for
//!   `kf_accel` (`r_accel`) and beside Algorithm 2 for `kf_fused` (`r_accel_fused`)
//!   ([`surrogate::fit_r`]; without a gyro `r_accel` by likelihood, and `r_accel_fused`
//!   kept as it started).
//! - [`ekf`]: the EKF's process noise, the same way, from the measured forcing; with no
//!   true angle the fit is adopted only if it lowers the process noise
//!   ([`ekf::only_lowers`]: raising it made the EKF worse on 20 of 25 zoo rides); the
//!   EKF takes the measured sensor noise.
//! - [`search`]: the derivative-free search in log space, the time limit and progress.
//! - [`rig_file`]: the tuned settings as a rig file with a comment per value.
//! - [`zoo`]: the test bed: seeded simulated rides on random rigs, each scored at the
//!   defaults, self-tuned and against an oracle grid.
//! - [`spatial`]: the 3-D tune (ekf3d's `[ekf3d]` table from a 3-D log), built on the
//!   estimators above, with its own zoo.
//!
//! [`tune`] runs them all in that order on a log in memory and returns the plain settings
//! structs the estimators take, with a [`Note`] per value saying how it was found or
//! why the default was kept (a log too short or too still for a value keeps its default
//! and says so).
//!
//! ```
//! use pendtilt::tune::{tune, Options, Start};
//! use pendtilt::sim::planar::{simulate, Scenario};
//! let mut sc = Scenario::named("sine").unwrap();
//! sc.duration = 12.0;
//! let samples: Vec<_> = simulate(&sc, 1).unwrap().iter().map(|r| r.sample()).collect();
//! let t = tune(&samples, &Start::default(), &Options::default());
//! assert!(t.kalman_fit.is_some());
//! assert!(t.notes.iter().any(|n| n.key == "kalman.q_angle"));
//! ```
pub mod accel;
pub mod cutoff;
pub mod ekf;
pub mod encoder;
mod filters;
pub mod forcing;
pub mod gyro;
pub mod kalman;
pub mod log;
mod notes;
pub mod reference;
pub mod rig_file;
pub mod search;
pub mod spatial;
pub mod spectrum;
mod steps;
pub mod surrogate;
mod targets;
pub mod zoo;

use crate::config::RigConfig;
use crate::peers::{self, PeerSettings};
use pendtilt_core::ekf::ModelSettings;
use pendtilt_core::estimators::accel::AccelSettings;
use pendtilt_core::estimators::alg1::Alg1Settings;
use pendtilt_core::estimators::alg2::Alg2Settings;
use pendtilt_core::filters::diff::DiffSettings;
use pendtilt_core::kalman::tilt::UNUSABLE;
use pendtilt_core::kalman::KalmanSettings;
use pendtilt_core::params::STANDARD_GRAVITY;
use pendtilt_core::{PendulumParams, PlanarEstimator, Sample};
use search::Budget;
use std::time::{Duration, Instant};
use steps::{choose_cutoffs, fit_or_keep, measure, note_fits, scale_jitter, why_not_fit, Columns};

/// The settings tuning starts from (and keeps where the log cannot tell).
#[derive(Debug, Clone, PartialEq)]
pub struct Start {
    /// The pendulum's a, b, c.
    pub params: PendulumParams<f64>,
    /// Gravity \[m/s^2\].
    pub gravity: f64,
    /// The `kf_*` filters.
    pub kalman: KalmanSettings<f64>,
    /// Algorithm 1.
    pub alg1: Alg1Settings<f64>,
    /// Algorithm 2 (its differentiator is the one of Algorithms 1-3).
    pub alg2: Alg2Settings<f64>,
    /// The accelerometer angle (`kf_accel`'s measurement).
    pub accel: AccelSettings<f64>,
    /// The EKF.
    pub ekf: ModelSettings<f64>,
}

impl Default for Start {
    fn default() -> Self {
        Self::from_rig(&RigConfig::default())
    }
}

impl Start {
    /// The settings a rig file gives (the EKF's from the default sensors and environment
    /// and the file's `[ekf]` table, as `pendtilt estimate` builds it).
    pub fn from_rig(cfg: &RigConfig) -> Self {
        let params = cfg.params();
        let gravity = cfg.physical().map_or(STANDARD_GRAVITY, |p| p.gravity);
        Self {
            params,
            gravity,
            kalman: cfg.kalman_settings(),
            alg1: cfg.alg1_settings(),
            alg2: cfg.alg2_settings(),
            accel: cfg.accel_settings(),
            ekf: cfg.ekf.apply(peers::model_settings(
                &params,
                gravity,
                &PeerSettings::default(),
            )),
        }
    }
}

/// What the Kalman filters and the EKF are tuned against.
#[derive(Debug, Clone, Copy, Default)]
pub enum Target<'a> {
    /// The likelihood of their own innovations: no true angle needed.
    #[default]
    Likelihood,
    /// The RMS error against a true angle per row \[rad\] (a calibration ride).
    Truth(&'a [f64]),
}

impl Target<'_> {
    /// `"likelihood"` or `"truth"`.
    pub fn name(&self) -> &'static str {
        match self {
            Target::Likelihood => "likelihood",
            Target::Truth(_) => "truth",
        }
    }
}

/// How tuning runs.
pub struct Options<'a> {
    /// What the filters are tuned against. Default [`Target::Likelihood`].
    pub target: Target<'a>,
    /// Stop the searches this long after [`tune`] starts (the best found so far is kept;
    /// the noise estimates, one pass each, always run). Default none.
    pub time_limit: Option<Duration>,
    /// Called with the evaluations done and [`planned_evaluations`].
    pub progress: Option<&'a dyn Fn(u64, u64)>,
    /// The likelihood fits use at most this much of the log \[s\]. Default 60 s.
    pub fit_seconds: f64,
}

impl Default for Options<'_> {
    fn default() -> Self {
        Self {
            target: Target::Likelihood,
            time_limit: None,
            progress: None,
            fit_seconds: 60.0,
        }
    }
}

/// A log shorter than this \[s\] keeps the filters' noise settings at their defaults.
pub const MIN_FIT_SECONDS: f64 = 10.0;
/// A log whose tilt (phi's one-second means) spans less than this \[rad\] (1 deg) is too
/// still to tell how the body moves: the process noises keep their defaults.
pub const MIN_TILT_RANGE: f64 = 0.017_453_292_519_943_295;
/// A log whose gyro integral moves less than this \[rad\] RMS (0.1 deg) above
/// [`reference::CORNER_HZ`] keeps the differentiator cutoffs: no delay to trade against
/// noise shows (a still log 0.004 deg, a scooter idling 0.04; rides 1.8-8 deg).
pub const MIN_BAND_MOTION: f64 = 0.001_745_329_251_994_329_5;

/// How one tuned (or kept) value was found.
#[derive(Debug, Clone, PartialEq)]
pub struct Note {
    /// The value's name, `table.key` as in the rig file where it has one.
    pub key: String,
    /// The value, formatted with its unit.
    pub value: String,
    /// True when the log could not tell and the value is the default.
    pub kept_default: bool,
    /// How it was found, or why it was not.
    pub how: String,
    /// True when the log gave a value no filter can use (a noise of 0: the filter would
    /// trust that sensor without bound) and the start's was kept instead; `pendtilt tune`
    /// says so on standard error.
    pub fell_back: bool,
}

/// Everything tuning found.
#[derive(Debug, Clone)]
pub struct Tuned {
    /// Encoder noise, if the log has enough encoder readings.
    pub encoder: Result<encoder::EncoderNoise, String>,
    /// Gyro noise and bias.
    pub gyro: Result<gyro::GyroNoise, String>,
    /// Accelerometer noise and vibration.
    pub accel: Result<accel::AccelNoise, String>,
    /// The encoder's jitter from vibration above the pendulum's band \[rad\].
    pub jitter: Result<f64, String>,
    /// The scale the EKF takes the jitter at (and how it was chosen), when the log has a
    /// gyro to choose it with.
    pub jitter_scale: Option<forcing::JitterScale>,
    /// The pendulum's forcing density near its natural frequency.
    pub forcing: Result<forcing::Forcing, String>,
    /// The spectral rule's choice.
    pub cutoff: Result<cutoff::CutoffChoice, String>,
    /// The cutoff measured against the gyro: (multiple of the natural frequency, RMS
    /// band error of Algorithm 2 there \[rad\]).
    pub cutoff_by_gyro: Option<(f64, f64)>,
    /// Algorithm 1's own cutoff measured against the gyro: (multiple of the natural
    /// frequency, RMS band error there \[rad\]); the rig file's `[alg1]
    /// cutoff_times_natural`.
    pub alg1_cutoff: Option<(f64, f64)>,
    /// The differentiator of Algorithms 1-3 (Algorithm 1's cutoff apart, when measured).
    pub differentiator: DiffSettings<f64>,
    /// The `kf_*` filters.
    pub kalman: KalmanSettings<f64>,
    /// The EKF.
    pub ekf: ModelSettings<f64>,
    /// The Kalman filters' fit on `kf_alg2` (likelihood or truth cost before and after).
    pub kalman_fit: Option<kalman::Fitted>,
    /// The surrogate fit of `kf_alg2` (adopted when present).
    pub kalman_surrogate: Option<surrogate::Fitted>,
    /// `kf_accel`'s R fit.
    pub accel_fit: Option<AccelFit>,
    /// `kf_fused`'s accelerometer R fit (`kalman.r_accel_fused`).
    pub fused_fit: Option<AccelFit>,
    /// The EKF's fit.
    pub ekf_fit: Option<ekf::EkfFitted>,
    /// The EKF's error against the gyro's integral above 0.2 Hz \[rad\] with the start's
    /// process noise and with the likelihood fit's (reported; [`ekf::only_lowers`]
    /// decides).
    pub ekf_band: Option<(f64, f64)>,
    /// One note per value.
    pub notes: Vec<Note>,
    /// `"likelihood"` or `"truth"`: what the filters were tuned against.
    pub target: &'static str,
    /// True if the time limit cut a fit short.
    pub stopped_by_time_limit: bool,
}

/// An accelerometer R fitted alone: `kf_accel`'s (`kalman.r_accel`) or `kf_fused`'s
/// (`kalman.r_accel_fused`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AccelFit {
    /// R \[rad^2\].
    pub r: f64,
    /// The cost at the start and at the fit: the surrogate's RMS error \[rad\], or the
    /// mean negative log-likelihood of kf_accel's innovations (or the filter's RMS error
    /// against the truth) when there is no surrogate.
    pub before: f64,
    /// See [`Self::before`].
    pub after: f64,
    /// True when fitted on the surrogate ([`surrogate::fit_r`]).
    pub surrogate: bool,
}

/// Cost evaluations [`tune`] plans (for a progress bar): the cutoff against the gyro, the
/// jitter's scale (at most), the Kalman filters' three parameters (likelihood, and surrogate with its grid), `kf_accel`'s
/// and `kf_fused`'s accelerometer R and the EKF's two, each fit's passes.
pub fn planned_evaluations() -> u64 {
    let per = search::EVALS_PER_PARAMETER;
    let (k, e) = (kalman::ROUNDS as u64, ekf::ROUNDS as u64);
    let jitter = 1 + (forcing::JITTER_MAX_DOUBLINGS as u64);
    cutoff::EVALUATIONS
        + jitter
        + (1 + k * 3 * per)
        + surrogate::EVALUATIONS
        + 2 * surrogate::EVALUATIONS_R
        + (1 + e * 2 * per)
}

/// Sample rate \[Hz\] from the median positive step; `None` without one.
pub fn sample_rate(samples: &[Sample<f64>]) -> Option<f64> {
    let mut d: Vec<f64> = samples
        .iter()
        .map(|s| s.dt)
        .filter(|d| d.is_finite() && *d > 0.0)
        .collect();
    if d.is_empty() {
        return None;
    }
    d.sort_by(f64::total_cmp);
    Some(1.0 / d[d.len() / 2])
}

/// Every how many rows Algorithm 2's angle is used in the likelihood fit: a Nyquist
/// interval of the differentiator's cutoff `fc` \[Hz\] at `rate`, at least 1.
pub fn decimation(rate: f64, fc: f64) -> usize {
    let m = (rate / (2.0 * fc)).round();
    if m.is_finite() && m >= 1.0 {
        m as usize
    } else {
        1
    }
}

/// Runs `e` over `samples`: the angles, NaN where its flags make it unusable as a
/// Kalman measurement.
fn measurements(e: &mut dyn PlanarEstimator<f64>, samples: &[Sample<f64>]) -> Vec<f64> {
    samples
        .iter()
        .map(|s| {
            let m = e.update(s);
            if m.flags.intersects(UNUSABLE) {
                f64::NAN
            } else {
                m.theta
            }
        })
        .collect()
}

/// Tunes every estimator's settings on `samples` (one log, rows in order), starting from
/// `start`. See the module documentation: the steps run in the order they depend on
/// each other.
pub fn tune(samples: &[Sample<f64>], start: &Start, opts: &Options) -> Tuned {
    // The tuned figures are the log's: the filter runs with them fixed, here and after
    // (the rig file gets `adapt = false`).
    let fixed = Start {
        ekf: start.ekf.fixed(),
        ..start.clone()
    };
    let start = &fixed;
    let planned = planned_evaluations();
    let tell = |n: u64| {
        if let Some(p) = opts.progress {
            p(n, planned);
        }
    };
    // The time limit counts from here: the searches stop at it, keeping their best.
    let mut budget = Budget {
        deadline: opts.time_limit.map(|d| Instant::now() + d),
        evaluations: 0,
        stopped: false,
        progress: Some(&tell),
    };
    let mut notes = Vec::new();
    let log = Columns::read(samples, opts.fit_seconds);
    let mut m = measure(&log, start, &mut notes);
    let bias = m.gyr.as_ref().ok().and_then(|g| g.bias);
    let jitter_scale = scale_jitter(&mut m, bias, &log, &mut budget, &mut notes);
    let (cuts, differentiator) = choose_cutoffs(start, &log, bias, &mut budget, &mut notes);
    let why_not = why_not_fit(log.duration, log.tilt);
    let why_not = why_not.as_deref();
    let fits = fit_or_keep(start, &m, differentiator, &log, why_not, opts, &mut budget);
    note_fits(start, &fits, &m, opts, why_not, &mut notes);
    Tuned {
        encoder: m.enc,
        gyro: m.gyr,
        accel: m.acc,
        jitter: m.jit,
        jitter_scale,
        forcing: m.force,
        cutoff: cuts.cut,
        cutoff_by_gyro: cuts.by_gyro,
        alg1_cutoff: cuts.alg1,
        differentiator,
        kalman: fits.kalman,
        ekf: fits.ekf,
        kalman_fit: fits.kalman_fit,
        kalman_surrogate: fits.kalman_surrogate,
        accel_fit: fits.accel_fit,
        fused_fit: fits.fused_fit,
        ekf_fit: fits.ekf_fit,
        ekf_band: fits.ekf_band,
        notes,
        target: opts.target.name(),
        stopped_by_time_limit: budget.stopped,
    }
}
