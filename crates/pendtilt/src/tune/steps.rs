//! The steps [`super::tune`] runs, in the order they depend on each other, and what each
//! needs: the log's columns, the one-pass measurements, the jitter's scale, the cutoffs,
//! the filters' fits and their notes.
use super::filters::{fit_filters, FilterFits, FitData};
use super::search::Budget;
use super::{
    accel, cutoff, encoder, forcing, gyro, kalman, notes, reference, sample_rate, surrogate, Note,
    Options, Start, Target, MIN_BAND_MOTION, MIN_FIT_SECONDS, MIN_TILT_RANGE,
};
use pendtilt_core::ekf::ModelSettings;
use pendtilt_core::filters::diff::DiffSettings;
use pendtilt_core::Sample;

/// The log as the steps read it: its columns, rate and length, and the rows the fits use.
pub(super) struct Columns<'a> {
    /// Sample rate \[Hz\] (1 kHz when the log does not tell).
    pub(super) rate: f64,
    pub(super) phi: Vec<f64>,
    pub(super) gyro: Vec<f64>,
    pub(super) ax: Vec<f64>,
    pub(super) ay: Vec<f64>,
    /// Length \[s\].
    pub(super) duration: f64,
    /// How far the body tilted ([`tilt_range`]) \[rad\].
    pub(super) tilt: f64,
    /// The first [`Options::fit_seconds`] of the log, which the fits use.
    pub(super) fit_samples: &'a [Sample<f64>],
    /// Rows the fits' costs leave out at the start (the filters' burn-in).
    pub(super) skip: usize,
}

impl<'a> Columns<'a> {
    /// Reads `samples` into columns once: each estimate takes one or two of them.
    pub(super) fn read(samples: &'a [Sample<f64>], fit_seconds: f64) -> Self {
        let rate = sample_rate(samples).unwrap_or(1000.0);
        let col = |f: fn(&Sample<f64>) -> f64| samples.iter().map(f).collect::<Vec<f64>>();
        let phi = col(|s| s.phi);
        let fit_rows = samples.len().min((fit_seconds * rate).round() as usize);
        Self {
            rate,
            gyro: col(|s| s.gyro),
            ax: col(|s| s.ax),
            ay: col(|s| s.ay),
            duration: samples.len() as f64 / rate,
            tilt: tilt_range(&phi, rate),
            phi,
            fit_samples: &samples[..fit_rows],
            skip: (kalman::BURN_IN * rate).round() as usize,
        }
    }
}

/// What one pass over the log measures (no search, so no time limit stops it).
pub(super) struct Measured {
    pub(super) enc: Result<encoder::EncoderNoise, String>,
    pub(super) gyr: Result<gyro::GyroNoise, String>,
    pub(super) acc: Result<accel::AccelNoise, String>,
    pub(super) jit: Result<f64, String>,
    pub(super) force: Result<forcing::Forcing, String>,
    /// The EKF's settings with the measured noise, jitter and forcing: the fits start here.
    pub(super) ekf_start: ModelSettings<f64>,
}

/// The sensors' noise, the encoder's jitter and the pendulum's forcing, each noted: the
/// figures every later step starts from.
pub(super) fn measure(log: &Columns, start: &Start, notes: &mut Vec<Note>) -> Measured {
    let (phi, rate) = (&log.phi, log.rate);
    let f_n = start.params.natural_frequency_hz();
    let enc = encoder::estimate(phi);
    let gyr = gyro::estimate(&log.gyro, phi, rate);
    let acc = accel::estimate(&log.ax, &log.ay, rate, f_n);
    let mut ekf_start = notes::sensor_settings(&start.ekf, &enc, &gyr, &acc, notes);
    let jit = forcing::jitter(phi, rate, f_n);
    notes::jitter(&mut ekf_start, &jit, notes);
    let force = match unforced(log.tilt, &acc) {
        Some(why) => Err(why),
        None => forcing::forcing(&ekf_start, log.fit_samples, rate, log.skip),
    };
    notes::forcing(&mut ekf_start, &force, notes);
    Measured {
        enc,
        gyr,
        acc,
        jit,
        force,
        ekf_start,
    }
}

/// Span of phi's one-second means \[rad\] (how far the body tilted, swing averaged out).
fn tilt_range(phi: &[f64], rate: f64) -> f64 {
    let w = (rate.round() as usize).max(1);
    let means: Vec<f64> = phi
        .chunks(w)
        .filter_map(|c| {
            let f: Vec<f64> = c.iter().copied().filter(|v| v.is_finite()).collect();
            (!f.is_empty()).then(|| f.iter().sum::<f64>() / f.len() as f64)
        })
        .collect();
    let lo = means.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = means.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if hi >= lo {
        hi - lo
    } else {
        0.0
    }
}

/// Why the log cannot tell the pendulum's forcing, if it cannot: the tilt spans under
/// [`MIN_TILT_RANGE`] and the accelerometer reads no more above the pendulum's band than
/// its white noise (1.5 times its RMS there at most). Then nothing forced the pendulum,
/// and the residual near f_n is the sensors' noise through the filter: on the 20 s still
/// scenario it gave 0.0037 1/s^3, 40 times below the default, and that rig took the EKF
/// on 30 s scooter rides (seeds 1-3) from 0.042, 0.055, 0.039 to 0.049, 0.046, 0.045 deg
/// RMS after 2 s.
fn unforced(tilt: f64, acc: &Result<accel::AccelNoise, String>) -> Option<String> {
    let a = acc.as_ref().ok()?;
    // One-sided density 2 d^2 over the band above the pendulum's, to the Nyquist frequency
    // (the top band's edge).
    let top = a.bands.last().map_or(0.0, |b| b.band[1]);
    let white = a.density * (2.0 * (top - a.pendulum_band).max(0.0)).sqrt();
    (tilt < MIN_TILT_RANGE && a.vibration_rms <= 1.5 * white).then(|| {
        format!(
            "nothing forced the pendulum (tilt spans {:.2} deg, the accelerometer above {:.1} Hz \
             {:.3} m/s^2 RMS, its white noise alone {:.3}): a still log cannot tell how a ride \
             forces it",
            tilt.to_degrees(),
            a.pendulum_band,
            a.vibration_rms,
            white
        )
    })
}

/// The measured jitter scaled toward the density it has in the filter's band, by the
/// EKF's error against the gyro's integral (`forcing::jitter_scale`); it needs the gyro's
/// `bias` and a log long enough to fit.
pub(super) fn scale_jitter(
    m: &mut Measured,
    bias: Option<f64>,
    log: &Columns,
    budget: &mut Budget,
    notes: &mut [Note],
) -> Option<forcing::JitterScale> {
    let js = match (bias, &m.jit) {
        (Some(b), Ok(j)) if *j > 0.0 && log.duration >= MIN_FIT_SECONDS => {
            let (rows, rate, skip) = (log.fit_samples, log.rate, log.skip);
            forcing::jitter_scale(&m.ekf_start, rows, b, rate, skip, budget)
        }
        _ => None,
    }?;
    m.ekf_start.encoder_jitter *= js.scale;
    notes::jitter_scale(m.ekf_start.encoder_jitter, &js, notes);
    Some(js)
}

/// The differentiator's cutoffs (the spectral rule's and [`cutoffs`] against the gyro),
/// noted, and the differentiator they give Algorithms 1-3.
pub(super) fn choose_cutoffs(
    start: &Start,
    log: &Columns,
    bias: Option<f64>,
    budget: &mut Budget,
    notes: &mut Vec<Note>,
) -> (Cutoffs, DiffSettings<f64>) {
    let start_diff = start.alg2.front_end.differentiator;
    let cut = cutoff::choose(&log.phi, log.rate, &start.params, &start_diff);
    let long_enough = log.duration >= MIN_FIT_SECONDS;
    let (rows, skip) = (log.fit_samples, log.skip);
    let cuts = cutoffs(start, rows, bias, long_enough, skip, cut, budget);
    let differentiator = adopted_differentiator(start, cuts.by_gyro, &cuts.cut);
    notes::cutoff(&cuts.cut, cuts.by_gyro, &start_diff, &start.params, notes);
    let too_still = cuts.too_still.as_deref();
    notes::alg1_cutoff(cuts.alg1, too_still, &start.params, notes);
    (cuts, differentiator)
}

/// The differentiator's cutoffs the log tells ([`cutoffs`]).
pub(super) struct Cutoffs {
    /// The spectral rule's choice, or why there is none.
    pub(super) cut: Result<cutoff::CutoffChoice, String>,
    /// Algorithm 2's cutoff against the gyro's reference and its band error.
    pub(super) by_gyro: Option<(f64, f64)>,
    /// Algorithm 1's, the same way.
    pub(super) alg1: Option<(f64, f64)>,
    /// Why the log is too still to choose any.
    pub(super) too_still: Option<String>,
}

/// The cutoffs against the gyro's reference (with the gyro's `bias`, on a log `long_enough`
/// to fit), and the spectral rule's `cut` unless the log is too still. Without tilt in the
/// reference's band there is no delay to trade against noise: any cutoff scores alike, and
/// the lowest was taken (a still log tuned to 0.61 f_n took alg1 on a scooter ride from
/// 0.61 to 1.00 deg RMS).
fn cutoffs(
    start: &Start,
    fit_samples: &[Sample<f64>],
    bias: Option<f64>,
    long_enough: bool,
    skip: usize,
    cut: Result<cutoff::CutoffChoice, String>,
    budget: &mut Budget,
) -> Cutoffs {
    let too_still = bias.and_then(|b| too_still(fit_samples, b, skip));
    let cut = match &too_still {
        Some(why) => Err(why.clone()),
        None => cut,
    };
    let by_gyro = bias
        .filter(|_| long_enough && too_still.is_none())
        .map(|b| cutoff::by_gyro_reference(fit_samples, &start.alg1, &start.alg2, b, skip, budget));
    Cutoffs {
        cut,
        by_gyro: by_gyro.map(|c| c.alg2).filter(|(_, e)| e.is_finite()),
        alg1: by_gyro.map(|c| c.alg1).filter(|(_, e)| e.is_finite()),
        too_still,
    }
}

/// Why the log is too still for a cutoff: the gyro's integral (less `bias`) above the
/// reference's corner moves less than [`MIN_BAND_MOTION`]; `None` when it moves enough.
fn too_still(samples: &[Sample<f64>], bias: f64, skip: usize) -> Option<String> {
    let motion = reference::band_motion(samples, bias, skip);
    (motion < MIN_BAND_MOTION).then(|| {
        format!(
            "log too still for a cutoff (the gyro's integral above {} Hz moves {:.4} deg \
             RMS, at least {:.1} deg needed to see the delay)",
            reference::CORNER_HZ,
            motion.to_degrees(),
            MIN_BAND_MOTION.to_degrees()
        )
    })
}

/// The differentiator adopted: the gyro-referenced cutoff when there is one, else the
/// spectral rule's, else the start's.
fn adopted_differentiator(
    start: &Start,
    cutoff_by_gyro: Option<(f64, f64)>,
    cut: &Result<cutoff::CutoffChoice, String>,
) -> DiffSettings<f64> {
    let current = start.alg2.front_end.differentiator;
    match cutoff_by_gyro {
        Some((x, _)) => DiffSettings {
            response: current.response,
            cutoff: pendtilt_core::filters::diff::Cutoff::TimesNatural(x),
        },
        None => cut.as_ref().map_or(current, |c| c.settings),
    }
}

/// Why the filters cannot be fitted on a log of `duration` \[s\] whose tilt spans
/// `range` \[rad\] (`None`: they can).
pub(super) fn why_not_fit(duration: f64, range: f64) -> Option<String> {
    if duration < MIN_FIT_SECONDS {
        Some(format!(
            "log too short ({duration:.1} s, at least {MIN_FIT_SECONDS} s needed): kept the default"
        ))
    } else if range < MIN_TILT_RANGE {
        Some(format!(
            "log too still (tilt spans {:.2} deg, at least 1 deg needed): kept the default",
            range.to_degrees()
        ))
    } else {
        None
    }
}

/// The filters fitted on the log from the measured `m`, or as they start when the log is
/// too short or too still to fit (`why_not`).
pub(super) fn fit_or_keep(
    start: &Start,
    m: &Measured,
    differentiator: DiffSettings<f64>,
    log: &Columns,
    why_not: Option<&str>,
    opts: &Options,
    budget: &mut Budget,
) -> FilterFits {
    if why_not.is_some() {
        return FilterFits::unfitted(start.kalman, m.ekf_start);
    }
    let data = FitData {
        samples: log.fit_samples,
        dt: log.fit_samples.iter().map(|s| s.dt).collect(),
        gyro: &log.gyro[..log.fit_samples.len()],
        skip: log.skip,
        rate: log.rate,
        has_accel: log.ax.iter().any(|v| v.is_finite()),
        gyro_errors: gyro_errors(&m.gyr, start),
    };
    fit_filters(start, m.ekf_start, differentiator, &data, opts, budget)
}

/// The gyro's errors the surrogate fits draw, when its bias was measured.
fn gyro_errors(
    gyr: &Result<gyro::GyroNoise, String>,
    start: &Start,
) -> Option<surrogate::GyroErrors> {
    gyr.as_ref().ok().and_then(|g| {
        g.bias.map(|bias| surrogate::GyroErrors {
            bias,
            density: g.density,
            bias_walk: start.ekf.sensors.gyro_bias_walk,
        })
    })
}

/// The filters' notes, one per fitted (or kept) value; the forcing's process noise, when
/// measured, is not a default.
pub(super) fn note_fits(
    start: &Start,
    fits: &FilterFits,
    m: &Measured,
    opts: &Options,
    why_not: Option<&str>,
    notes: &mut Vec<Note>,
) {
    notes::filters(
        &start.kalman,
        &fits.kalman,
        fits.kalman_fit.as_ref(),
        fits.kalman_surrogate.as_ref(),
        fits.accel_fit.as_ref(),
        fits.fused_fit.as_ref(),
        &m.ekf_start,
        fits.ekf_fit.as_ref(),
        fits.ekf_band,
        matches!(opts.target, Target::Truth(_)),
        why_not,
        notes,
    );
    if m.force.is_ok() {
        forcing_measured(notes);
    }
}

/// The process noise "kept" by the filters' notes is the start's, whose pendulum forcing
/// was measured: not a default.
fn forcing_measured(notes: &mut [Note]) {
    for n in notes.iter_mut().filter(|n| n.key == "ekf.process.pendulum") {
        if n.kept_default {
            n.kept_default = false;
            n.how += " (the start's value is the accelerometer's measured forcing)";
        }
    }
}
