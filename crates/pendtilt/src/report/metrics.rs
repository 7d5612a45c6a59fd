//! Per-estimator accuracy metrics against the true angle.
//!
//! Everything here is a pure function over slices sampled at a uniform rate. The building
//! blocks ([`ErrorSamples`], [`lag_by_xcorr`], [`detect_step`], [`overshoot_pct`],
//! [`settling_time_s`]) work in whatever unit they are given; [`compute_metrics`] takes the
//! angles in the unit named by [`MetricsConfig::input_unit`] (radians by default, as in the
//! data contract) and reports everything in degrees, milliseconds and seconds.
//!
//! Non-finite samples (NaN or infinite) are never used silently: they are counted
//! ([`ErrorSamples::non_finite_estimate`], [`Metrics::non_finite_estimate`]) and the pair is left
//! out of every statistic.
use serde::Serialize;

use super::ReportError;

/// Degrees per radian.
pub const DEG_PER_RAD: f64 = 180.0 / core::f64::consts::PI;

/// Unit of the angles handed to [`compute_metrics`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum AngleUnit {
    /// Radians (the data contract's unit).
    Rad,
    /// Degrees.
    Deg,
}

impl AngleUnit {
    /// Factor that converts a value in this unit to degrees.
    pub fn to_deg_factor(self) -> f64 {
        match self {
            AngleUnit::Rad => DEG_PER_RAD,
            AngleUnit::Deg => 1.0,
        }
    }
}

/// How a step of the true angle is detected, and the band used for settling.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StepConfig {
    /// Length \[s\] of the windows at the start and at the end of the record whose means are
    /// the initial and final values of the step.
    pub plateau_s: f64,
    /// Smallest |final - initial| \[deg\] that counts as a step.
    pub min_step_deg: f64,
    /// The truth must stay within \[min(initial, final) - f |S|, max(initial, final) + f |S|\]
    /// for the record to count as one step (f is this fraction, S the step): this rejects
    /// oscillating and wandering motion, where overshoot means nothing.
    pub envelope_frac: f64,
    /// Settling band as a fraction of |S| (0.02 = 2%).
    pub band_frac: f64,
    /// Settling band floor \[deg\]: the band is the larger of `band_frac |S|` and this.
    pub band_deg: f64,
}

impl Default for StepConfig {
    fn default() -> Self {
        Self {
            plateau_s: 0.25,
            min_step_deg: 1.0,
            envelope_frac: 0.1,
            band_frac: 0.02,
            band_deg: 0.5,
        }
    }
}

/// Settings of [`compute_metrics`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MetricsConfig {
    /// Unit of the estimate and truth slices.
    pub input_unit: AngleUnit,
    /// Half-width \[deg\] of the band for [`Metrics::within_tolerance_pct`].
    pub tolerance_deg: f64,
    /// Largest lag \[s\] searched, in both directions, by the cross-correlation.
    pub max_lag_s: f64,
    /// Step detection and settling band.
    pub step: StepConfig,
    /// The error statistics and the lag are computed from this long after the first
    /// sample on \[s\] (from sample `ceil(score_from_s * rate)`); overshoot and settling
    /// time always from the whole record, since a step response is the start. Default 0.
    #[serde(skip_serializing_if = "is_zero")]
    pub score_from_s: f64,
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

impl MetricsConfig {
    /// The first sample scored at `rate_hz` ([`MetricsConfig::score_from_s`]).
    pub fn first_scored(&self, rate_hz: f64) -> usize {
        let k = (self.score_from_s * rate_hz - 1e-9).ceil();
        if k.is_finite() && k > 0.0 {
            k as usize
        } else {
            0
        }
    }
}

impl Default for MetricsConfig {
    fn default() -> Self {
        Self {
            input_unit: AngleUnit::Rad,
            tolerance_deg: 0.5,
            max_lag_s: 0.5,
            step: StepConfig::default(),
            score_from_s: 0.0,
        }
    }
}

/// The metrics of one estimator against the true angle, in degrees unless the name says
/// otherwise.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Metrics {
    /// Estimator name (column name in the estimates CSV).
    pub name: String,
    /// Number of samples scored: the record's from [`MetricsConfig::score_from_s`] on.
    pub samples: usize,
    /// Number of (estimate, truth) pairs used: both finite.
    pub samples_used: usize,
    /// Number of non-finite (NaN or infinite) estimate samples, left out.
    pub non_finite_estimate: usize,
    /// Number of non-finite truth samples (estimate finite), left out.
    pub non_finite_truth: usize,
    /// Root-mean-square error \[deg\].
    pub rms_deg: f64,
    /// Largest absolute error \[deg\].
    pub max_abs_deg: f64,
    /// Mean error (estimate - truth) \[deg\].
    pub bias_deg: f64,
    /// Standard deviation of the error \[deg\] (population form, divided by n, so that
    /// rms^2 = bias^2 + std^2).
    pub std_deg: f64,
    /// Half-width \[deg\] of the tolerance band used for `within_tolerance_pct`.
    pub tolerance_deg: f64,
    /// Share of used samples with |error| <= `tolerance_deg` \[%\].
    pub within_tolerance_pct: f64,
    /// Delay of the estimate behind the truth \[ms\] (positive: the estimate lags), from the
    /// peak of the cross-correlation; `None` when it could not be measured (see `notes`).
    pub lag_ms: Option<f64>,
    /// Correlation coefficient at the lag peak (1 = the estimate is a shifted copy).
    pub lag_correlation: Option<f64>,
    /// Overshoot \[% of the step\] on a step-like truth, see [`overshoot_pct`]; `None` when the
    /// truth is not one step.
    pub overshoot_pct: Option<f64>,
    /// Settling time \[s\] after the step's 50% point, see [`settling_time_s`]; `None` when the
    /// truth is not one step or the estimate does not settle before the record ends.
    pub settling_time_s: Option<f64>,
    /// Why an optional metric is missing, in words.
    pub notes: Vec<String>,
}

/// The errors (estimate - truth) of the pairs where both are finite, with the count of
/// the pairs left out.
#[derive(Debug, Clone, PartialEq)]
pub struct ErrorSamples {
    /// Errors of the used pairs, in input order.
    pub errors: Vec<f64>,
    /// Sample index of each used pair.
    pub indices: Vec<usize>,
    /// Total number of samples.
    pub samples: usize,
    /// Pairs left out because the estimate is NaN or infinite.
    pub non_finite_estimate: usize,
    /// Pairs left out because the truth is NaN or infinite (the estimate being finite).
    pub non_finite_truth: usize,
}

impl ErrorSamples {
    /// Pairs `estimate` with `truth` sample by sample.
    ///
    /// Errors: empty or mismatched slices, or no pair with both values finite.
    pub fn new(estimate: &[f64], truth: &[f64]) -> Result<Self, ReportError> {
        check_lengths(estimate, truth)?;
        let mut errors = Vec::with_capacity(estimate.len());
        let mut indices = Vec::with_capacity(estimate.len());
        let (mut bad_est, mut bad_truth) = (0, 0);
        for (k, (&e, &x)) in estimate.iter().zip(truth).enumerate() {
            if !e.is_finite() {
                bad_est += 1;
            } else if !x.is_finite() {
                bad_truth += 1;
            } else {
                errors.push(e - x);
                indices.push(k);
            }
        }
        if errors.is_empty() {
            return Err(ReportError::NoValidSamples {
                non_finite_estimate: bad_est,
                non_finite_truth: bad_truth,
            });
        }
        Ok(Self {
            errors,
            indices,
            samples: estimate.len(),
            non_finite_estimate: bad_est,
            non_finite_truth: bad_truth,
        })
    }

    /// Number of pairs used.
    pub fn used(&self) -> usize {
        self.errors.len()
    }

    /// Root-mean-square error.
    pub fn rms(&self) -> f64 {
        (self.errors.iter().map(|e| e * e).sum::<f64>() / self.used() as f64).sqrt()
    }

    /// Mean error (bias).
    pub fn bias(&self) -> f64 {
        self.errors.iter().sum::<f64>() / self.used() as f64
    }

    /// Population standard deviation of the error (divided by n).
    pub fn std_dev(&self) -> f64 {
        let m = self.bias();
        let var = self.errors.iter().map(|e| (e - m) * (e - m)).sum::<f64>() / self.used() as f64;
        var.sqrt()
    }

    /// Largest absolute error.
    pub fn max_abs(&self) -> f64 {
        self.errors.iter().fold(0.0, |acc: f64, e| acc.max(e.abs()))
    }

    /// Share (0..=1) of used pairs with |error| <= `tol`.
    pub fn share_within(&self, tol: f64) -> f64 {
        let n = self.errors.iter().filter(|e| e.abs() <= tol).count();
        n as f64 / self.used() as f64
    }
}

fn check_lengths(estimate: &[f64], truth: &[f64]) -> Result<(), ReportError> {
    if truth.is_empty() {
        return Err(ReportError::Empty("truth".into()));
    }
    if estimate.len() != truth.len() {
        return Err(ReportError::LengthMismatch {
            name: "estimate".into(),
            expected: truth.len(),
            got: estimate.len(),
        });
    }
    Ok(())
}

fn check_rate(rate_hz: f64) -> Result<(), ReportError> {
    if rate_hz.is_finite() && rate_hz > 0.0 {
        Ok(())
    } else {
        Err(ReportError::InvalidRate(rate_hz))
    }
}

/// Mean sample rate \[Hz\] of a time column: (n - 1) / (t_last - t_first).
///
/// The metrics assume uniform sampling; this is the rate to hand them for a log whose
/// time column is close to uniform. Errors: fewer than two samples, or times not finite
/// and strictly increasing.
pub fn rate_from_times(t: &[f64]) -> Result<f64, ReportError> {
    if t.len() < 2 {
        return Err(ReportError::Empty("time column (needs two samples)".into()));
    }
    for (k, w) in t.windows(2).enumerate() {
        if !(w[0].is_finite() && w[1].is_finite() && w[1] > w[0]) {
            return Err(ReportError::TimeNotIncreasing { index: k + 1 });
        }
    }
    Ok((t.len() - 1) as f64 / (t[t.len() - 1] - t[0]))
}

/// Below this peak correlation [`compute_metrics`] notes that the lag is unreliable.
pub const WEAK_CORRELATION: f64 = 0.8;

/// Result of [`lag_by_xcorr`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LagEstimate {
    /// Delay of the estimate behind the truth \[samples\], sub-sample refined.
    pub lag_samples: f64,
    /// The same in seconds.
    pub lag_s: f64,
    /// Correlation coefficient at the integer peak.
    pub peak_correlation: f64,
}

/// `s` minus its mean over its finite values.
fn centred(s: &[f64]) -> Vec<f64> {
    let (sum, cnt) = s
        .iter()
        .filter(|v| v.is_finite())
        .fold((0.0, 0usize), |(a, c), v| (a + v, c + 1));
    let m = if cnt > 0 { sum / cnt as f64 } else { 0.0 };
    s.iter().map(|v| v - m).collect()
}

/// Pearson's correlation of the pairs (e\[k\], x\[k - lag\]) where both are finite; NaN
/// with fewer than two pairs or a constant side.
fn correlation_at(e: &[f64], x: &[f64], lag: isize) -> f64 {
    let n = x.len();
    let k0 = lag.max(0) as usize;
    let k1 = (n as isize + lag.min(0)) as usize;
    let (mut c, mut se, mut sx, mut see, mut sxx, mut sex) = (0.0f64, 0.0, 0.0, 0.0, 0.0, 0.0);
    for k in k0..k1 {
        let a = e[k];
        let b = x[(k as isize - lag) as usize];
        if a.is_finite() && b.is_finite() {
            c += 1.0;
            se += a;
            sx += b;
            see += a * a;
            sxx += b * b;
            sex += a * b;
        }
    }
    if c < 2.0 {
        return f64::NAN;
    }
    let cov = sex - se * sx / c;
    let ve = see - se * se / c;
    let vx = sxx - sx * sx / c;
    if ve > 0.0 && vx > 0.0 {
        cov / (ve * vx).sqrt()
    } else {
        f64::NAN
    }
}

/// Delay of `estimate` behind `truth` by cross-correlation.
///
/// For every integer lag L in \[-W, W\] (W = `max_lag_s * rate_hz` rounded, at most n/2 so that
/// at least half the record overlaps) it computes the Pearson correlation coefficient of the
/// pairs (estimate\[k\], truth\[k - L\]) where both are finite, over the overlap. The lag with the
/// highest coefficient is refined by fitting a parabola through it and its two neighbours:
/// delta = (r\[L-1\] - r\[L+1\]) / (2 (r\[L-1\] - 2 r\[L\] + r\[L+1\])), clamped to +-0.5 sample.
/// Positive lag: the estimate is late (estimate(t) ~ truth(t - lag)). Means are removed, so a
/// constant bias does not move the lag.
///
/// Errors: bad lengths or rate, a window under one sample, a constant signal or too few
/// usable samples (no correlation defined at or next to the peak), or a peak on the edge of
/// the window (the true lag is probably outside it: widen `max_lag_s`).
pub fn lag_by_xcorr(
    estimate: &[f64],
    truth: &[f64],
    rate_hz: f64,
    max_lag_s: f64,
) -> Result<LagEstimate, ReportError> {
    check_lengths(estimate, truth)?;
    check_rate(rate_hz)?;
    if !(max_lag_s.is_finite() && max_lag_s > 0.0) {
        return Err(ReportError::Lag(format!(
            "search window {max_lag_s} s is not positive"
        )));
    }
    let n = truth.len();
    let w = ((max_lag_s * rate_hz).round() as usize).min(n / 2);
    if w < 1 {
        return Err(ReportError::Lag(
            "search window is under one sample (record too short or window too small)".into(),
        ));
    }
    // Centre both signals on their means over finite samples: keeps the sums well
    // conditioned for slow signals far from zero.
    let e = centred(estimate);
    let x = centred(truth);
    let wi = w as isize;
    let r: Vec<f64> = (-wi..=wi).map(|lag| correlation_at(&e, &x, lag)).collect();
    let (best, &peak) = r
        .iter()
        .enumerate()
        .filter(|(_, v)| v.is_finite())
        .max_by(|a, b| a.1.total_cmp(b.1))
        .ok_or_else(|| {
            ReportError::Lag("no correlation defined (constant or missing signal)".into())
        })?;
    if best == 0 || best == 2 * w {
        return Err(ReportError::Lag(format!(
            "correlation peak on the edge of the +-{:.0} ms window",
            w as f64 / rate_hz * 1e3
        )));
    }
    let (ym, y0, yp) = (r[best - 1], peak, r[best + 1]);
    if !(ym.is_finite() && yp.is_finite()) {
        return Err(ReportError::Lag(
            "correlation undefined next to its peak (too few usable samples)".into(),
        ));
    }
    let mut delta = 0.0;
    let denom = ym - 2.0 * y0 + yp;
    if denom < 0.0 {
        delta = (0.5 * (ym - yp) / denom).clamp(-0.5, 0.5);
    }
    let lag_samples = best as f64 - w as f64 + delta;
    Ok(LagEstimate {
        lag_samples,
        lag_s: lag_samples / rate_hz,
        peak_correlation: peak,
    })
}

/// A step of the true angle, found by [`detect_step`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Step {
    /// Mean of the truth over the first `plateau_s`.
    pub initial: f64,
    /// Mean of the truth over the last `plateau_s`.
    pub final_value: f64,
    /// `final_value - initial`.
    pub size: f64,
    /// First sample at which the truth has covered half the step.
    pub index: usize,
    /// `index / rate` \[s\] from the first sample.
    pub time_s: f64,
}

/// Finds the one step of a step-like true angle (the paper's sigmoid, Fig. 5), values in
/// degrees.
///
/// Definition: the initial and final values are the means of the finite truth samples over
/// the first and the last `plateau_s`; the step S = final - initial must be at least
/// `min_step_deg` in size, and every finite truth sample must lie within
/// \[min(initial, final) - envelope_frac |S|, max(initial, final) + envelope_frac |S|\]. The
/// step's time is the first sample at which the truth has covered half of S.
///
/// Errors (`ReportError::NotStepLike`, with the reason) when the record is not one step.
pub fn detect_step(truth_deg: &[f64], rate_hz: f64, cfg: &StepConfig) -> Result<Step, ReportError> {
    check_rate(rate_hz)?;
    let n = truth_deg.len();
    let plateau = ((cfg.plateau_s * rate_hz).round() as usize).max(1);
    if 2 * plateau >= n {
        return Err(ReportError::NotStepLike(format!(
            "record of {n} samples is too short for two {}-sample plateaus",
            plateau
        )));
    }
    let finite_mean = |s: &[f64]| {
        let (sum, cnt) = s
            .iter()
            .filter(|v| v.is_finite())
            .fold((0.0, 0usize), |(a, c), v| (a + v, c + 1));
        (cnt > 0).then(|| sum / cnt as f64)
    };
    let (Some(initial), Some(final_value)) = (
        finite_mean(&truth_deg[..plateau]),
        finite_mean(&truth_deg[n - plateau..]),
    ) else {
        return Err(ReportError::NotStepLike(
            "no finite truth at the start or the end".into(),
        ));
    };
    let size = final_value - initial;
    if size.abs() < cfg.min_step_deg {
        return Err(ReportError::NotStepLike(format!(
            "start and end differ by {:.3} deg, under the {} deg minimum",
            size.abs(),
            cfg.min_step_deg
        )));
    }
    let margin = cfg.envelope_frac * size.abs();
    let lo = initial.min(final_value) - margin;
    let hi = initial.max(final_value) + margin;
    if let Some(k) = truth_deg
        .iter()
        .position(|v| v.is_finite() && (*v < lo || *v > hi))
    {
        return Err(ReportError::NotStepLike(format!(
            "truth leaves the step's envelope [{lo:.2}, {hi:.2}] deg at sample {k}"
        )));
    }
    let sign = size.signum();
    let index = truth_deg
        .iter()
        .position(|v| v.is_finite() && (v - initial) * sign >= 0.5 * size.abs())
        .ok_or_else(|| ReportError::NotStepLike("truth never reaches half the step".into()))?;
    Ok(Step {
        initial,
        final_value,
        size,
        index,
        time_s: index as f64 / rate_hz,
    })
}

/// Overshoot \[% of |S|\] of an estimate on a step (values in the step's unit).
///
/// Definition: over the finite estimate samples from the step's 50% point to the end, the
/// largest excursion beyond the truth's final value in the direction of the step,
/// max((estimate - final) sign(S)), as a percentage of |S|; 0 when the estimate never goes
/// beyond. Being measured against the truth, a bias or noise in the estimate counts as
/// overshoot. `None` when no finite estimate sample follows the 50% point.
pub fn overshoot_pct(estimate: &[f64], step: &Step) -> Option<f64> {
    let sign = step.size.signum();
    let worst = estimate
        .iter()
        .skip(step.index)
        .filter(|v| v.is_finite())
        .map(|v| (v - step.final_value) * sign)
        .reduce(f64::max)?;
    Some(worst.max(0.0) / step.size.abs() * 100.0)
}

/// The settling band of a step: the larger of `band_frac |S|` and `band_deg` (values in
/// degrees).
pub fn settling_band(step: &Step, cfg: &StepConfig) -> f64 {
    (cfg.band_frac * step.size.abs()).max(cfg.band_deg)
}

/// Settling time \[s\] of an estimate on a step (values in the step's unit).
///
/// Definition: the time from the step's 50% point to the first finite sample after which the
/// estimate stays within `band` of the truth's final value until the end of the record
/// (non-finite samples skipped). 0 when it never leaves the band after the 50% point; `None`
/// when the last finite sample is outside the band (it has not settled) or no finite sample
/// follows the 50% point.
pub fn settling_time_s(estimate: &[f64], step: &Step, rate_hz: f64, band: f64) -> Option<f64> {
    let valid: Vec<usize> = (step.index..estimate.len())
        .filter(|&k| estimate[k].is_finite())
        .collect();
    let outside = |k: usize| (estimate[k] - step.final_value).abs() > band;
    let &last = valid.last()?;
    if outside(last) {
        return None;
    }
    // the last excursion, then the next finite sample is where it has settled
    let settled_at = match valid.iter().rposition(|&k| outside(k)) {
        None => step.index,
        Some(p) => valid[p + 1],
    };
    Some((settled_at - step.index) as f64 / rate_hz)
}

/// All the metrics of one estimator against the truth, sampled at `rate_hz`.
///
/// The angles are in `cfg.input_unit`; the result is in degrees. The errors and the lag
/// are those of the samples from [`MetricsConfig::score_from_s`] on. Step metrics are filled
/// only when the truth is one step ([`detect_step`]); the lag only when the correlation
/// peak lies inside the window ([`lag_by_xcorr`]); otherwise `notes` says why.
///
/// Errors: empty or mismatched slices, a bad rate, or no pair with both values finite.
pub fn compute_metrics(
    name: &str,
    estimate: &[f64],
    truth: &[f64],
    rate_hz: f64,
    cfg: &MetricsConfig,
) -> Result<Metrics, ReportError> {
    check_rate(rate_hz)?;
    let f = cfg.input_unit.to_deg_factor();
    let est: Vec<f64> = estimate.iter().map(|v| v * f).collect();
    let tru: Vec<f64> = truth.iter().map(|v| v * f).collect();
    let from = cfg.first_scored(rate_hz).min(est.len());
    let errs = ErrorSamples::new(&est[from..], &tru[from..])?;
    let mut notes = Vec::new();
    let lag = lag_by_xcorr(&est[from..], &tru[from..], rate_hz, cfg.max_lag_s);
    let (lag_ms, lag_correlation) = match lag {
        Ok(l) => {
            // a weak peak (noise-dominated estimate) gives a number that means little
            if l.peak_correlation < WEAK_CORRELATION {
                notes.push(format!(
                    "lag: weak correlation peak (r = {:.2}), the lag is unreliable",
                    l.peak_correlation
                ));
            }
            (Some(l.lag_s * 1e3), Some(l.peak_correlation))
        }
        Err(e) => {
            notes.push(format!("lag: {e}"));
            (None, None)
        }
    };
    let (overshoot, settling) = match detect_step(&tru, rate_hz, &cfg.step) {
        Ok(step) => {
            let o = overshoot_pct(&est, &step);
            let s = settling_time_s(&est, &step, rate_hz, settling_band(&step, &cfg.step));
            if s.is_none() {
                notes.push("settling: not within the band at the end of the record".into());
            }
            (o, s)
        }
        // Not a step: overshoot and settling do not apply; the report says so once.
        Err(_) => (None, None),
    };
    Ok(Metrics {
        name: name.to_string(),
        samples: errs.samples,
        samples_used: errs.used(),
        non_finite_estimate: errs.non_finite_estimate,
        non_finite_truth: errs.non_finite_truth,
        rms_deg: errs.rms(),
        max_abs_deg: errs.max_abs(),
        bias_deg: errs.bias(),
        std_deg: errs.std_dev(),
        tolerance_deg: cfg.tolerance_deg,
        within_tolerance_pct: 100.0 * errs.share_within(cfg.tolerance_deg),
        lag_ms,
        lag_correlation,
        overshoot_pct: overshoot,
        settling_time_s: settling,
        notes,
    })
}
