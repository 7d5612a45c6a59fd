//! Calibration: the fit of the pendulum's a, b (the paper's Newton, Eqs 24-28, on the
//! default cost, the output error, which vibration does not bias) and of Algorithm 3's
//! K, L, M, N (Newton on the paper's Eq 23), on a separate ride with a true angle.
use pendtilt_core::estimators::equations::Alg3Gains;
use pendtilt_core::estimators::front_end::FrontEndSettings;
use pendtilt_core::PendulumParams;

use crate::bank::planar::BankSettings;
use crate::fit::{self, Algorithm, FitReport, FitSettings, Method, Target};

use super::progress::Progress;
use super::rides::Ride;

/// What the calibration produced, and how.
#[derive(Debug, Clone, PartialEq)]
pub struct Calibration {
    /// The pendulum's true a, b (known because the ride is simulated).
    pub true_params: PendulumParams<f64>,
    /// a, b used by the estimators.
    pub params: PendulumParams<f64>,
    /// K, L, M, N used by Algorithm 3.
    pub gains: Alg3Gains<f64>,
    /// Whether a, b came from the fit (false: the true values, see `notes`).
    pub params_fitted: bool,
    /// Whether K, L, M, N came from the fit (false: the Eq (21)-equivalent gains).
    pub gains_fitted: bool,
    /// One sentence per step, with the numbers (for the report).
    pub notes: Vec<String>,
}

impl Calibration {
    /// The bank settings: defaults for the calibrated a, b, Algorithm 3 with the
    /// calibrated gains, Kalman settings as given.
    pub fn bank_settings(
        &self,
        kalman: pendtilt_core::kalman::KalmanSettings<f64>,
    ) -> BankSettings {
        let mut s = BankSettings::from_params(self.params);
        s.rig.alg3.gains = self.gains;
        s.rig.kalman = kalman;
        s
    }
}

fn describe(r: &FitReport) -> String {
    let vals: Vec<String> = r
        .names
        .iter()
        .zip(&r.params)
        .map(|(n, v)| format!("{n} = {v:.5}"))
        .collect();
    format!(
        "{} after {} iterations ({:?}, {} passes over the log); cost (RMS) {:.4} -> {:.4} deg",
        vals.join(", "),
        r.iterations.len().saturating_sub(1),
        r.stop,
        r.evaluations,
        r.start_cost.to_degrees(),
        r.cost.to_degrees()
    )
}

/// Where the a, b fit starts: 30 % off the true values (a high, b low).
pub fn ab_start(true_params: &PendulumParams<f64>) -> PendulumParams<f64> {
    PendulumParams {
        a: true_params.a * 1.3,
        b: true_params.b * 0.7,
        c: 0.0,
    }
}

/// The paper's Newton fit (Eqs 24-28) of a, b for Algorithm 2 on `ride` (with its true
/// angle), from [`ab_start`], on the default cost ([`fit::Cost::Auto`]: the output error,
/// driven by the accelerometer when the ride vibrates). The kinematics settings (the
/// estimators' default differentiator, target through the estimator's low-pass) apply
/// when the cost is the paper's Eq (23).
pub fn fit_ab(ride: &Ride, true_params: &PendulumParams<f64>) -> Result<FitReport, fit::FitError> {
    fit_ab_with_cost(ride, true_params, fit::Cost::Auto)
}

/// [`fit_ab`] with another cost (e.g. [`fit::Cost::Inverse`], the paper's Eq 23, to show
/// its bias under vibration).
pub fn fit_ab_with_cost(
    ride: &Ride,
    true_params: &PendulumParams<f64>,
    cost: fit::Cost,
) -> Result<FitReport, fit::FitError> {
    let start = ab_start(true_params);
    let defaults = BankSettings::from_params(*true_params);
    let mut ab = FitSettings {
        algorithm: Algorithm::Alg2,
        target: Target::Truth,
        method: Method::Newton,
        cost,
        // The estimator's front end, started from `start`.
        front_end: FrontEndSettings {
            params: start,
            ..defaults.rig.alg2_settings().front_end
        },
        ..FitSettings::default()
    };
    ab.kinematics.matched_target = true;
    fit::fit_log(&ride.samples, Some(&ride.theta), &ab, |_| {})
}

/// One sentence on an a, b fit against the true values.
pub fn describe_ab(r: &FitReport, true_params: &PendulumParams<f64>) -> String {
    let p = r.pendulum_params();
    format!(
        "{}; true a = {:.5} s, b = {:.5} s^2 (errors {:+.1} %, {:+.1} %)",
        describe(r),
        true_params.a,
        true_params.b,
        (p.a / true_params.a - 1.0) * 100.0,
        (p.b / true_params.b - 1.0) * 100.0
    )
}

/// Calibrates on `ride` (which must carry the true angle): first a, b by Newton on the
/// output error ([`fit_ab`], unbiased under vibration, where Eq (23) shrinks b), starting
/// 30 % off the truth; then K, L, M, N by
/// Newton on Eq (23) exactly as printed (Algorithm 3's output as it runs against the raw
/// truth: the gains are free to take up the differentiator's delay, which is Algorithm 3's
/// purpose), starting from the Eq (21)-equivalent gains of the fitted a, b.
///
/// A fit that fails is not fatal: the true values (a, b) or the Eq (21)-equivalent gains
/// are used instead and the notes say so and why.
pub fn calibrate(
    ride: &Ride,
    true_params: PendulumParams<f64>,
    progress: &dyn Progress,
) -> Calibration {
    let mut notes = Vec::new();
    progress.stage(
        &format!("fitting a, b (Newton, output error) on {}", ride.label),
        2,
    );
    let (params, params_fitted, note) = calibrate_ab(ride, &true_params);
    notes.push(note);
    progress.advance(1);
    progress.message(notes.last().map(String::as_str).unwrap_or(""));

    let (gains, gains_fitted, note) = calibrate_gains(ride, params);
    notes.push(note);
    progress.advance(1);
    progress.message(notes.last().map(String::as_str).unwrap_or(""));
    Calibration {
        true_params,
        params,
        gains,
        params_fitted,
        gains_fitted,
        notes,
    }
}

/// a, b fitted on the calibration ride (Newton, output error) from 30 % off the truth:
/// the parameters, whether they were fitted (else the true ones), and the note saying how.
fn calibrate_ab(
    ride: &Ride,
    true_params: &PendulumParams<f64>,
) -> (PendulumParams<f64>, bool, String) {
    let true_params = *true_params;
    let start = ab_start(&true_params);
    match fit_ab(ride, &true_params) {
        Ok(r) if r.params.iter().all(|v| v.is_finite() && *v > 0.0) => {
            let p = r.pendulum_params();
            let note = format!(
                "a, b: the paper's Newton's method (Eqs 24-28) on {}{} for Algorithm 2 \
                     over {} ({:.0} s), started 30 % off (a = {:.5}, b = {:.5}): {}.",
                r.cost_kind.describe(),
                if r.accel_drive {
                    ", driven by the accelerometer"
                } else {
                    ""
                },
                ride.label,
                ride.duration(),
                start.a,
                start.b,
                describe_ab(&r, &true_params)
            );
            (p, true, note)
        }
        Ok(r) => {
            let note = format!(
                "a, b: the Newton fit returned unusable values ({:?}); the TRUE values \
                     a = {:.5}, b = {:.5} are used instead.",
                r.params, true_params.a, true_params.b
            );
            (true_params, false, note)
        }
        Err(e) => {
            let note = format!(
                "a, b: the Newton fit failed ({e}); the TRUE values a = {:.5}, b = {:.5} \
                     are used instead.",
                true_params.a, true_params.b
            );
            (true_params, false, note)
        }
    }
}

/// K, L, M, N fitted on the calibration ride (Newton on Eq 23 as printed) from the
/// Eq (21)-equivalent gains of `params`: the gains, whether they were fitted (else the
/// starting ones), and the note saying how.
fn calibrate_gains(ride: &Ride, params: PendulumParams<f64>) -> (Alg3Gains<f64>, bool, String) {
    let settings = BankSettings::from_params(params);
    let start_gains = Alg3Gains::from_params(&params);
    let mut g = FitSettings {
        algorithm: Algorithm::Alg3,
        target: Target::Truth,
        method: Method::Newton,
        front_end: settings.rig.alg3_settings().front_end,
        start_gains: Some(start_gains),
        ..FitSettings::default()
    };
    g.kinematics.matched_target = false;
    match fit::fit_log(&ride.samples, Some(&ride.theta), &g, |_| {}) {
        Ok(r) if r.params.iter().all(|v| v.is_finite()) => {
            let note = format!(
                "K, L, M, N (Algorithm 3, Eq 30): Newton on Eq (23) as printed (the estimate as \
                 it runs against the raw truth) over {}, started from the Eq (21)-equivalent \
                 gains K = a, L = b, M = -b, N = 0: {}. The gains are fixed for the test ride \
                 (a supervisor with the whole calibration ride as its window).",
                ride.label,
                describe(&r)
            );
            (r.gains(), true, note)
        }
        Ok(r) => {
            let note = format!(
                "K, L, M, N: the Newton fit returned unusable values ({:?}); Algorithm 3 runs \
                 with the Eq (21)-equivalent gains (it then equals Algorithm 2).",
                r.params
            );
            (start_gains, false, note)
        }
        Err(e) => {
            let note = format!(
                "K, L, M, N: the Newton fit failed ({e}); Algorithm 3 runs with the \
                 Eq (21)-equivalent gains (it then equals Algorithm 2)."
            );
            (start_gains, false, note)
        }
    }
}
