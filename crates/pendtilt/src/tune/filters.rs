//! The filters' noise fitted on the log ([`super::tune`]'s last step): the `kf_*`
//! filters' Q and R on Algorithm 2's angle ([`super::kalman`], [`super::surrogate`]), the
//! accelerometer's R alone and beside Algorithm 2, and the EKF's process noise
//! ([`super::ekf`]).
use super::search::Budget;
use super::{
    decimation, ekf, kalman, measurements, reference, surrogate, targets, AccelFit, Options, Start,
    Target,
};
use pendtilt_core::ekf::{Ekf, ModelSettings};
use pendtilt_core::estimators::accel::Accel;
use pendtilt_core::estimators::alg2::Alg2;
use pendtilt_core::filters::diff::DiffSettings;
use pendtilt_core::kalman::KalmanSettings;
use pendtilt_core::{Estimator, Sample};

/// The filters' settings after fitting (or as they started) and the fits made.
pub(super) struct FilterFits {
    pub(super) kalman: KalmanSettings<f64>,
    pub(super) ekf: ModelSettings<f64>,
    pub(super) kalman_fit: Option<kalman::Fitted>,
    pub(super) kalman_surrogate: Option<surrogate::Fitted>,
    pub(super) accel_fit: Option<AccelFit>,
    pub(super) fused_fit: Option<AccelFit>,
    pub(super) ekf_fit: Option<ekf::EkfFitted>,
    pub(super) ekf_band: Option<(f64, f64)>,
}

impl FilterFits {
    /// No fit made: the start's `kalman` and the measured `ekf`.
    pub(super) fn unfitted(kalman: KalmanSettings<f64>, ekf: ModelSettings<f64>) -> Self {
        Self {
            kalman,
            ekf,
            kalman_fit: None,
            kalman_surrogate: None,
            accel_fit: None,
            fused_fit: None,
            ekf_band: None,
            ekf_fit: None,
        }
    }
}

/// What [`fit_filters`] fits on.
pub(super) struct FitData<'a> {
    /// The rows fitted on.
    pub(super) samples: &'a [Sample<f64>],
    /// Their steps \[s\].
    pub(super) dt: Vec<f64>,
    /// Their gyro \[rad/s\].
    pub(super) gyro: &'a [f64],
    /// Rows left out of the costs at the start.
    pub(super) skip: usize,
    /// Sample rate \[Hz\].
    pub(super) rate: f64,
    /// True when the log has an accelerometer reading.
    pub(super) has_accel: bool,
    /// The gyro's error figures when estimated (then the surrogate fit runs).
    pub(super) gyro_errors: Option<surrogate::GyroErrors>,
}

/// Fits the `kf_*` filters' Q and R on Algorithm 2's angle (with `differentiator`),
/// `kf_accel`'s R when the log has an accelerometer, and the EKF from `ekf_start`,
/// within `budget`.
pub(super) fn fit_filters(
    start: &Start,
    ekf_start: ModelSettings<f64>,
    differentiator: DiffSettings<f64>,
    d: &FitData,
    opts: &Options,
    budget: &mut Budget,
) -> FilterFits {
    let kf = fit_kalman(start, differentiator, d, opts, budget);
    let mut kalman_s = kf.settings;
    let (accel_fit, fused_fit) = if d.has_accel {
        fit_accel(start, &kf, d, opts, budget)
    } else {
        (None, None)
    };
    if let Some(a) = &accel_fit {
        kalman_s.r_accel = a.r;
    }
    if let Some(a) = &fused_fit {
        kalman_s.r_accel_fused = Some(a.r);
    }
    let e = targets::ekf(&ekf_start, d.samples, d.skip, opts, budget);
    let ekf_band = ekf_band(&ekf_start, &e.settings, d, opts);
    // The likelihood fit is adopted only when it takes process noise out (see
    // `ekf::only_lowers`); the band error is reported.
    let ekf = match opts.target {
        Target::Truth(_) => e.settings,
        Target::Likelihood if ekf::only_lowers(&ekf_start, &e.settings) => e.settings,
        Target::Likelihood => ekf_start,
    };
    FilterFits {
        kalman: kalman_s,
        ekf,
        kalman_fit: Some(kf.fitted),
        kalman_surrogate: kf.surrogate_fit,
        accel_fit,
        fused_fit,
        ekf_band,
        ekf_fit: Some(e),
    }
}

/// The Kalman filters' Q and R fitted on Algorithm 2's angle: the settings adopted, the
/// likelihood (or truth) fit, and the surrogate fit (adopted when made: likelihood target
/// and a gyro).
fn fit_kalman(
    start: &Start,
    differentiator: DiffSettings<f64>,
    d: &FitData,
    opts: &Options,
    budget: &mut Budget,
) -> KalmanFit {
    let mut alg2_s = start.alg2;
    alg2_s.front_end.differentiator = differentiator;
    let z_all = measurements(&mut Alg2::<f64>::new(alg2_s), d.samples);
    // Alg 2's errors are coloured (band-limited by the differentiator): the
    // likelihood sees them as independent only a Nyquist interval of the cutoff
    // apart, so it is fitted on every m-th angle and R scaled back by m.
    let m = match opts.target {
        Target::Likelihood => decimation(d.rate, differentiator.cutoff_hz(&start.params)),
        Target::Truth(_) => 1,
    };
    let z: Vec<f64> = z_all
        .iter()
        .enumerate()
        .map(|(k, v)| if k % m == 0 { *v } else { f64::NAN })
        .collect();
    let data = kalman::KalmanData {
        dt: &d.dt,
        gyro: d.gyro,
        z: &z,
    };
    let r0 = start.kalman.r_pendulum / m as f64;
    let mut f = targets::kalman(&start.kalman, r0, &data, d.skip, opts, budget);
    f.r *= m as f64;
    let mut kalman_s = start.kalman;
    kalman_s.q_angle = f.q_angle;
    kalman_s.q_bias = f.q_bias;
    kalman_s.r_pendulum = f.r;
    let sur = match (opts.target, d.gyro_errors) {
        (Target::Likelihood, Some(g)) => {
            // The bias walk: the start's, or the log's upper bound if larger.
            let bound = surrogate::walk_bound(d.samples, &z_all, g.bias, d.skip);
            let g = surrogate::GyroErrors {
                bias_walk: bound.map_or(g.bias_walk, |w| w.max(g.bias_walk)),
                ..g
            };
            let s = surrogate::Surrogate::new(d.samples, &z_all, &g);
            let r0 = start.kalman.r_pendulum;
            let mut fit = surrogate::fit(&start.kalman, r0, &s, d.skip, budget);
            let [q_angle, q_bias, r] = fit.x;
            kalman_s.q_angle = q_angle;
            kalman_s.q_bias = q_bias;
            kalman_s.r_pendulum = r;
            fit.nll_at = kalman::nll(&kalman_s, r / m as f64, &data, d.skip);
            fit.bias_walk = g.bias_walk;
            Some((fit, s))
        }
        _ => None,
    };
    let (surrogate_fit, surrogate) = sur.unzip();
    KalmanFit {
        settings: kalman_s,
        fitted: f,
        surrogate_fit,
        surrogate,
        z: z_all,
    }
}

/// What [`fit_kalman`] found, with what the accelerometer's fits reuse.
struct KalmanFit {
    /// The `kf_*` settings with kf_alg2's Q and R fitted.
    settings: KalmanSettings<f64>,
    /// The likelihood (or truth) fit.
    fitted: kalman::Fitted,
    /// The surrogate fit (adopted when present).
    surrogate_fit: Option<surrogate::Fitted>,
    /// Its surrogate of Algorithm 2's error.
    surrogate: Option<surrogate::Surrogate>,
    /// Algorithm 2's angle per row.
    z: Vec<f64>,
}

/// `kf_accel`'s and `kf_fused`'s accelerometer R: on the surrogates when the Kalman fit
/// made one (likelihood target, a gyro), against the truth, or by likelihood.
fn fit_accel(
    start: &Start,
    kf: &KalmanFit,
    d: &FitData,
    opts: &Options,
    budget: &mut Budget,
) -> (Option<AccelFit>, Option<AccelFit>) {
    let za = measurements(&mut Accel::new(start.accel), d.samples);
    let data = kalman::KalmanData {
        dt: &d.dt,
        gyro: d.gyro,
        z: &za,
    };
    let r0 = start.kalman.r_accel;
    let r0_fused = start.kalman.r_accel_fused.unwrap_or(r0);
    let q = kf.settings;
    let fit = |(r, before, after), surrogate| AccelFit {
        r,
        before,
        after,
        surrogate,
    };
    // Each in the order the budget was spent before: kf_accel's, then kf_fused's.
    match (opts.target, d.gyro_errors, &kf.surrogate_fit, &kf.surrogate) {
        // On the surrogate as kf_alg2's R, with the gyro's errors it drew, the
        // accelerometer's error below the corner its difference from Algorithm 2;
        // kf_fused's on both surrogates together, Algorithm 2's R as fitted.
        (Target::Likelihood, Some(g), Some(k), Some(sp)) => {
            let g = surrogate::GyroErrors {
                bias_walk: k.bias_walk,
                ..g
            };
            let sa = surrogate::Surrogate::against(d.samples, &za, &kf.z, &g);
            let alone = |r| surrogate::rms_of(&q, &[(&sa, r)], d.skip);
            let accel_fit = Some(fit(surrogate::fit_r(r0, alone, budget), true));
            let fused = |r| surrogate::rms_of(&q, &[(&sa, r), (sp, q.r_pendulum)], d.skip);
            (
                accel_fit,
                Some(fit(surrogate::fit_r(r0_fused, fused, budget), true)),
            )
        }
        (Target::Truth(truth), ..) => {
            let accel_fit = Some(fit(
                targets::kalman_r(&q, r0, &data, d.skip, opts, budget),
                false,
            ));
            let both = [(za.as_slice(), r0_fused), (kf.z.as_slice(), q.r_pendulum)];
            let fused = targets::kalman_fused_r(&q, &both, &data, truth, d.skip, budget);
            (accel_fit, Some(fit(fused, false)))
        }
        _ => (
            Some(fit(
                targets::kalman_r(&q, r0, &data, d.skip, opts, budget),
                false,
            )),
            None,
        ),
    }
}

/// The EKF's error against the gyro's integral above 0.2 Hz with the start and the fit,
/// reported in the notes (likelihood target, a gyro, and a fit that moved).
fn ekf_band(
    ekf_start: &ModelSettings<f64>,
    fitted: &ModelSettings<f64>,
    d: &FitData,
    opts: &Options,
) -> Option<(f64, f64)> {
    match (opts.target, d.gyro_errors) {
        (Target::Likelihood, Some(g)) if fitted != ekf_start => {
            let reference = reference::integral(d.samples, g.bias);
            let band = |s: ModelSettings<f64>| {
                let mut f = Ekf::new(s);
                let est: Vec<f64> = d.samples.iter().map(|x| f.update(x).theta).collect();
                reference::band_error(&est, &reference, d.samples, d.skip)
            };
            Some((band(*ekf_start), band(*fitted)))
        }
        _ => None,
    }
}
