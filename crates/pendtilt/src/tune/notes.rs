//! How each value was found, in words: the [`Note`]s of [`super::Tuned`], and the EKF's
//! measurement noise set from the noise estimators.
use super::accel::AccelNoise;
use super::cutoff::CutoffChoice;
use super::ekf::EkfFitted;
use super::encoder::EncoderNoise;
use super::gyro::GyroNoise;
use super::kalman::Fitted;
use super::Note;
use pendtilt_core::ekf::ModelSettings;
use pendtilt_core::filters::diff::DiffSettings;
use pendtilt_core::kalman::KalmanSettings;
use pendtilt_core::PendulumParams;

fn note(notes: &mut Vec<Note>, key: &str, value: String, kept: bool, how: String) {
    notes.push(Note {
        key: key.to_string(),
        value,
        kept_default: kept,
        how,
        fell_back: false,
    });
}

/// A note for a value the log gave as `got` (0: no noise) that no filter can use, so the
/// start's value (`kept`, formatted) stays: `why` says what the log showed.
fn fallback(notes: &mut Vec<Note>, key: &str, kept: String, got: String, why: &str) {
    notes.push(Note {
        key: key.to_string(),
        value: kept,
        kept_default: true,
        how: format!(
            "the log gave {got}, which would make the filters trust this sensor without \
             bound ({why}): kept the start's value"
        ),
        fell_back: true,
    });
}

/// The EKF's sensor settings from the noise estimates (defaults of `base` where an
/// estimate failed), with a note per value.
pub(super) fn sensor_settings(
    base: &ModelSettings<f64>,
    enc: &Result<EncoderNoise, String>,
    gyro: &Result<GyroNoise, String>,
    acc: &Result<AccelNoise, String>,
    notes: &mut Vec<Note>,
) -> ModelSettings<f64> {
    let mut s = *base;
    encoder_noise(&mut s, enc, notes);
    gyro_noise(&mut s, gyro, notes);
    accel_noise(&mut s, acc, notes);
    s
}

/// The encoder's resolution and noise into `s`, from its estimate.
fn encoder_noise(
    s: &mut ModelSettings<f64>,
    enc: &Result<EncoderNoise, String>,
    notes: &mut Vec<Note>,
) {
    match enc {
        // Readings that never change (a still pendulum within one step of a quantised
        // encoder) show neither the step nor a noise: an encoder variance of 0, which took
        // the EKF on a scooter ride from 0.131 to 0.222 deg RMS.
        Ok(e) if e.white == 0.0 && e.step.is_none() => {
            let base = *s;
            fallback(
                notes,
                "sensors.encoder_noise",
                format!(
                    "{:.3e} rad, {} bits",
                    base.sensors.encoder_noise, base.sensors.encoder_bits
                ),
                "an encoder noise of 0 and no quantisation step".into(),
                &format!(
                    "phi never changed over {} samples: a still pendulum within one step of its \
                     encoder shows neither the step nor the noise",
                    e.samples + 2
                ),
            );
        }
        Ok(e) => {
            match (e.step, e.bits) {
                (_, Some(bits)) => s.sensors.encoder_bits = bits,
                (Some(_), None) | (None, None) => s.sensors.encoder_bits = 0,
            }
            // A step that is not 2 pi / 2^bits: its rounding goes into the noise.
            s.sensors.encoder_noise = if e.bits.is_some() { e.noise } else { e.white };
            let step = e.step.map_or("not quantised".to_string(), |q| {
                format!(
                    "step {q:.4e} rad ({})",
                    e.bits
                        .map_or("not a power of two".into(), |b| format!("{b} bits"))
                )
            });
            note(
                notes,
                "sensors.encoder_bits",
                format!("{}", s.sensors.encoder_bits),
                false,
                format!("{step}: gaps between the distinct readings"),
            );
            note(notes, "sensors.encoder_noise", format!("{:.3e} rad", s.sensors.encoder_noise), false,
                format!("second differences of phi over {} samples: residual {:.3e} rad RMS, minus the rounding's q^2/12", e.samples, e.white));
        }
        Err(why) => note(
            notes,
            "sensors.encoder_noise",
            format!("{:.3e} rad", s.sensors.encoder_noise),
            true,
            format!("{why}: kept the default"),
        ),
    }
}

/// The gyro's noise density and bias spread into `s`, from its estimate.
fn gyro_noise(s: &mut ModelSettings<f64>, gyro: &Result<GyroNoise, String>, notes: &mut Vec<Note>) {
    match gyro {
        Ok(g) if !(g.density > 0.0 && g.density.is_finite()) => fallback(
            notes,
            "sensors.gyro_density",
            format!("{:.3e} rad/s/sqrt(Hz)", s.sensors.gyro_density),
            format!("a gyro noise density of {:.3e} rad/s/sqrt(Hz)", g.density),
            "the gyro read the same value throughout its still stretches or its top band",
        ),
        Ok(g) => {
            s.sensors.gyro_density = g.density;
            note(
                notes,
                "sensors.gyro_density",
                format!("{:.3e} rad/s/sqrt(Hz)", g.density),
                false,
                g.method.clone(),
            );
            match g.bias {
                Some(b) => {
                    // The filter starts its bias at 0 with this spread: it must cover the
                    // bias seen (twice it), and is never narrowed below the start's (a
                    // spread of |b| alone slowed the start: zoo ride 1, 0.063 -> 0.30 deg).
                    let spread = s.sensors.gyro_bias.max(2.0 * b.abs());
                    let widened = spread > s.sensors.gyro_bias;
                    s.sensors.gyro_bias = spread;
                    note(notes, "sensors.gyro_bias", format!("{spread:.3e} rad/s"), !widened,
                        format!("mean bias over the log {b:.3e} rad/s ({:.3} deg/s); the filter's initial bias spread (it starts at 0) is the start's or twice the bias seen, whichever is larger", b.to_degrees()));
                }
                None => note(notes, "sensors.gyro_bias", format!("{:.3e} rad/s", s.sensors.gyro_bias), true,
                    "no still stretch and too short for the pendulum's tilt change: kept the default".into()),
            }
        }
        Err(why) => note(
            notes,
            "sensors.gyro_density",
            format!("{:.3e} rad/s/sqrt(Hz)", s.sensors.gyro_density),
            true,
            format!("{why}: kept the default"),
        ),
    }
}

/// The accelerometer's noise density and vibration into `s`, from its estimate.
fn accel_noise(
    s: &mut ModelSettings<f64>,
    acc: &Result<AccelNoise, String>,
    notes: &mut Vec<Note>,
) {
    match acc {
        Ok(a) if !(a.density > 0.0 && a.density.is_finite()) => fallback(
            notes,
            "sensors.accel_density",
            format!("{:.3e} m/s^2/sqrt(Hz)", s.sensors.accel_density),
            format!(
                "an accelerometer noise density of {:.3e} m/s^2/sqrt(Hz)",
                a.density
            ),
            "the accelerometer's top band holds no power",
        ),
        Ok(a) => {
            s.sensors.accel_density = a.density;
            s.accel_vibration = a.vibration_rms;
            let bands: Vec<String> = a
                .bands
                .iter()
                .map(|b| {
                    format!(
                        "{:.0}-{:.0} Hz: {:.3}/{:.3}",
                        b.band[0], b.band[1], b.rms[0], b.rms[1]
                    )
                })
                .collect();
            note(notes, "sensors.accel_density", format!("{:.3e} m/s^2/sqrt(Hz)", a.density), false,
                "median of the spectrum in the top band (0.3-0.45 x rate); an upper bound while vibration reaches it".into());
            note(
                notes,
                "accel_vibration",
                format!("{:.3} m/s^2", a.vibration_rms),
                false,
                format!(
                    "RMS above the pendulum's band ({:.1} Hz), larger axis; per band x/y m/s^2: {}",
                    a.pendulum_band,
                    bands.join(", ")
                ),
            );
        }
        Err(why) => note(
            notes,
            "sensors.accel_density",
            format!("{:.3e} m/s^2/sqrt(Hz)", s.sensors.accel_density),
            true,
            format!("{why}: kept the default"),
        ),
    }
}

/// The encoder's jitter into `s`, from its estimate.
pub(super) fn jitter(s: &mut ModelSettings<f64>, j: &Result<f64, String>, notes: &mut Vec<Note>) {
    match j {
        Ok(j) => {
            s.encoder_jitter = *j;
            note(notes, "ekf.encoder_jitter", format!("{j:.3e} rad"), false, format!(
                "power of phi from {} x f_n to 0.3 x the rate less its white floor ({:.4} deg RMS): the pendulum's jitter from vibration above its band",
                super::forcing::JITTER_TIMES_NATURAL, j.to_degrees()));
        }
        Err(why) => note(
            notes,
            "ekf.encoder_jitter",
            format!("{:.3e} rad", s.encoder_jitter),
            true,
            format!("{why}: kept the default"),
        ),
    }
}

/// The jitter's scale into the `ekf.encoder_jitter` note (`jitter`: the value taken).
pub(super) fn jitter_scale(jitter: f64, js: &super::forcing::JitterScale, notes: &mut [Note]) {
    let Some(n) = notes.iter_mut().find(|n| n.key == "ekf.encoder_jitter") else {
        return;
    };
    let tried: Vec<String> = js
        .tried
        .iter()
        .map(|(m, e)| format!("x{m:.2}: {:.4} deg", e.to_degrees()))
        .collect();
    n.value = format!("{jitter:.3e} rad");
    n.how += &format!(
        "; taken at {:.2} times that (doubled while each doubling lowered the EKF's error against the gyro's integral above {} Hz by more than {:.0} %, at most {:.2} times: the jitter's density just above its band over the whole band's; {})",
        js.scale,
        super::reference::CORNER_HZ,
        100.0 * super::forcing::JITTER_STEP_GAIN,
        js.cap,
        tried.join(", ")
    );
}

/// The EKF's pendulum forcing density into `s`, from its estimate.
pub(super) fn forcing(
    s: &mut ModelSettings<f64>,
    f: &Result<super::forcing::Forcing, String>,
    notes: &mut Vec<Note>,
) {
    match f {
        Ok(f) => {
            let before = s.process.pendulum;
            s.process.pendulum = f.process;
            note(notes, "ekf.process.pendulum", format!("{:.4e} 1/s^3", f.process), false, format!(
                "the accelerometer's residual (ax less the EKF's g sin theta - d theta'') near f_n: {:.3e} m/s^2/sqrt(Hz), squared over (b g)^2 (was {before:.4e}); the likelihood fit below starts here",
                f.density));
        }
        Err(why) => note(
            notes,
            "ekf.process.pendulum",
            format!("{:.4e} 1/s^3", s.process.pendulum),
            true,
            format!("{why}: kept the default"),
        ),
    }
}

/// Algorithm 1's own cutoff's note.
pub(super) fn alg1_cutoff(
    c: Option<(f64, f64)>,
    why_not: Option<&str>,
    params: &PendulumParams<f64>,
    notes: &mut Vec<Note>,
) {
    match c {
        Some((x, e)) => note(notes, "alg1.cutoff_times_natural", format!("{x:.3}"), false, format!(
            "{:.3} Hz: least error of Algorithm 1 against the gyro's integral above {} Hz ({:.4} deg RMS); apart from Algorithm 2's, which suits it poorly on a slow pendulum",
            x * params.natural_frequency_hz(), super::reference::CORNER_HZ, e.to_degrees())),
        None => note(notes, "alg1.cutoff_times_natural", "none".into(), true, format!(
            "{}: alg1 takes [differentiator]'s cutoff",
            why_not.unwrap_or("no gyro bias estimate to measure it against (or too short)"))),
    }
}

/// The cutoff's note.
pub(super) fn cutoff(
    c: &Result<CutoffChoice, String>,
    by_gyro: Option<(f64, f64)>,
    start: &DiffSettings<f64>,
    params: &PendulumParams<f64>,
    notes: &mut Vec<Note>,
) {
    let rule = match c {
        Ok(c) => format!(
            "the spectral rule (valley {:.2} Hz) gave {:.3} Hz",
            c.valley_hz, c.hz
        ),
        Err(why) => format!("no spectral rule: {why}"),
    };
    if let Some((x, e)) = by_gyro {
        let f_n = params.natural_frequency_hz();
        note(notes, "differentiator.cutoff_hz", format!("{:.3} Hz", x * f_n), false, format!(
            "{x:.3} x f_n: least error of Algorithm 2 against the gyro's integral above {} Hz ({:.4} deg RMS); {rule}",
            super::reference::CORNER_HZ, e.to_degrees()));
        return;
    }
    match c {
        Ok(c) => note(notes, "differentiator.cutoff_hz", format!("{:.3} Hz", c.hz), false, format!(
            "noise/delay rule on the encoder's spectrum: valley between tilt and vibration at {:.2} Hz; predicted error {:.4} deg RMS (the previous {:.3} Hz: {:.4} deg)",
            c.valley_hz, c.predicted_rms.to_degrees(), start.cutoff_hz(params), c.reference_rms.to_degrees())),
        Err(why) => note(notes, "differentiator.cutoff_hz", format!("{:.3} Hz", start.cutoff_hz(params)), true, format!("{why}: kept the default")),
    }
}

/// The filters' notes.
#[allow(clippy::too_many_arguments)] // one note per fitted value, all from one run
pub(super) fn filters(
    start: &KalmanSettings<f64>,
    k: &KalmanSettings<f64>,
    kf: Option<&Fitted>,
    sur: Option<&super::surrogate::Fitted>,
    accel: Option<&super::AccelFit>,
    fused: Option<&super::AccelFit>,
    ekf_start: &ModelSettings<f64>,
    ekf: Option<&EkfFitted>,
    ekf_band: Option<(f64, f64)>,
    truth: bool,
    why_not: Option<&str>,
    notes: &mut Vec<Note>,
) {
    let cost = |b: f64, a: f64| {
        format!("mean -log-likelihood (ln S + y^2/S per innovation, or RMS error against the truth) {b:.4} -> {a:.4}")
    };
    let why = why_not
        .unwrap_or("not fitted: kept the default")
        .to_string();
    kalman_notes(start, k, kf, sur, &cost, &why, notes);
    match accel {
        Some(a) if a.surrogate => note(
            notes,
            "kalman.r_accel",
            format!("{:.4e} rad^2", a.r),
            false,
            format!(
                "fitted on a surrogate of kf_accel's error (the accelerometer angle's error from \
                 the gyro's integral above {} Hz and from Algorithm 2 below, the gyro's errors \
                 drawn as for kf_alg2), q_angle and q_bias as above; RMS {:.4} -> {:.4} deg",
                super::reference::CORNER_HZ,
                a.before.to_degrees(),
                a.after.to_degrees()
            ),
        ),
        Some(a) => note(
            notes,
            "kalman.r_accel",
            format!("{:.4e} rad^2", a.r),
            false,
            format!(
                "fitted on kf_accel's innovations, q_angle and q_bias as above; {}",
                cost(a.before, a.after)
            ),
        ),
        None => note(
            notes,
            "kalman.r_accel",
            format!("{:.4e} rad^2", start.r_accel),
            true,
            if why_not.is_some() {
                why.clone()
            } else {
                "no accelerometer in the log: kept the default".into()
            },
        ),
    }
    if let Some(a) = fused {
        fused_note(a, notes);
    }
    ekf_notes(ekf_start, ekf, ekf_band, truth, &why, notes);
}

/// The notes of the Kalman filters' Q and R: fitted (`kf`) or kept for `why`.
fn kalman_notes(
    start: &KalmanSettings<f64>,
    k: &KalmanSettings<f64>,
    kf: Option<&Fitted>,
    sur: Option<&super::surrogate::Fitted>,
    cost: &dyn Fn(f64, f64) -> String,
    why: &str,
    notes: &mut Vec<Note>,
) {
    let (set, kept, how) = match (kf, sur) {
        (Some(f), Some(s)) => (
            k,
            false,
            format!(
                "fitted on a surrogate of kf_alg2's error (alg2 minus the gyro's integral above \
                 0.2 Hz, and the gyro's estimated noise and bias, its bias walk {:.2e} rad/s/sqrt(s): \
                 the start's or the log's upper bound, the larger): predicted RMS {:.4} -> {:.4} \
                 deg; innovation likelihood (mean -log L) {:.4} at the start, {:.4} here; its \
                 own optimum ({:.4}: q_angle {:.2e}, q_bias {:.2e}, R {:.2e}) not adopted, as it \
                 takes alg2's coloured errors for white noise",
                s.bias_walk,
                s.rms_before.to_degrees(),
                s.rms_after.to_degrees(),
                f.nll_before,
                s.nll_at,
                f.nll_after,
                f.q_angle,
                f.q_bias,
                f.r
            ),
        ),
        (Some(f), None) => (
            k,
            false,
            format!(
                "fitted on kf_alg2's innovations; {}",
                cost(f.nll_before, f.nll_after)
            ),
        ),
        (None, _) => (start, true, why.to_string()),
    };
    let q_angle = format!("{:.4e} rad^2/s", set.q_angle);
    note(notes, "kalman.q_angle", q_angle, kept, how.clone());
    let q_bias = format!("{:.4e} (rad/s)^2/s", set.q_bias);
    note(notes, "kalman.q_bias", q_bias, kept, how.clone());
    let r = format!("{:.4e} rad^2", set.r_pendulum);
    note(notes, "kalman.r_pendulum", r, kept, how);
}

/// The notes of the EKF's process noise: searched against the truth (adopted), fitted
/// on the likelihood (reported, kept) or not fitted for `why`.
fn ekf_notes(
    ekf_start: &ModelSettings<f64>,
    ekf: Option<&EkfFitted>,
    band: Option<(f64, f64)>,
    truth: bool,
    why: &str,
    notes: &mut Vec<Note>,
) {
    let lik = |e: &EkfFitted| {
        format!(
            "the encoder-innovation likelihood fit (mean -log-likelihood {:.4} -> {:.4}) found \
             jerk {:.3e}, pendulum {:.3e}",
            e.nll_before, e.nll_after, e.settings.process.jerk, e.settings.process.pendulum
        )
    };
    let (p, kept, how) = match (ekf, band) {
        (Some(e), Some((k, f))) if !truth && super::ekf::only_lowers(ekf_start, &e.settings) => (
            e.settings.process,
            false,
            format!(
                "{}; adopted: it lowers the process noise (a fit that raises it absorbs \
                 coloured encoder errors: see tune::ekf::only_lowers); the EKF's error \
                 against the gyro's integral above 0.2 Hz {:.4} -> {:.4} deg",
                lik(e),
                k.to_degrees(),
                f.to_degrees()
            ),
        ),
        (Some(e), Some((k, f))) if !truth => (
            ekf_start.process,
            true,
            format!(
                "{}; kept the start's: the fit raises a density, which the likelihood does \
                 to absorb coloured encoder errors (see tune::ekf::only_lowers); the EKF's \
                 error against the gyro's integral above 0.2 Hz {:.4} deg with it, {:.4} without",
                lik(e),
                f.to_degrees(),
                k.to_degrees()
            ),
        ),
        (ekf, _) => match ekf {
        Some(e) if truth => (
            e.settings.process,
            false,
            format!(
                "searched against the true angle; RMS error {:.4} -> {:.4} deg",
                e.nll_before.to_degrees(),
                e.nll_after.to_degrees()
            ),
        ),
        Some(e) if super::ekf::only_lowers(ekf_start, &e.settings) => (
            e.settings.process,
            false,
            format!("{}; adopted: it lowers the process noise (see tune::ekf::only_lowers)", lik(e)),
        ),
        Some(e) => (ekf_start.process, true, format!("kept: the encoder-innovation likelihood fit (mean -log-likelihood {:.4} -> {:.4}) found jerk {:.3e}, pendulum {:.3e}, raising a density, which the likelihood does to absorb coloured encoder errors (see tune::ekf::only_lowers)", e.nll_before, e.nll_after, e.settings.process.jerk, e.settings.process.pendulum)),
        None => (ekf_start.process, true, why.to_string()),
        },
    };
    let jerk = format!("{:.4e} rad^2/s^5", p.jerk);
    note(notes, "ekf.process.jerk", jerk, kept, how.clone());
    let pendulum = format!("{:.4e} 1/s^3", p.pendulum);
    note(notes, "ekf.process.pendulum", pendulum, kept, how);
}

/// `kf_fused`'s accelerometer R as fitted.
fn fused_note(a: &super::AccelFit, notes: &mut Vec<Note>) {
    let how = if a.surrogate {
        format!(
            "kf_fused's accelerometer R, fitted on the surrogates of the accelerometer's and \
             Algorithm 2's errors together, q_angle, q_bias and r_pendulum as above; RMS \
             {:.4} -> {:.4} deg",
            a.before.to_degrees(),
            a.after.to_degrees()
        )
    } else {
        format!(
            "kf_fused's accelerometer R, fitted on its error against the truth, q_angle, \
             q_bias and r_pendulum as above; RMS {:.4} -> {:.4} deg",
            a.before.to_degrees(),
            a.after.to_degrees()
        )
    };
    note(
        notes,
        "kalman.r_accel_fused",
        format!("{:.4e} rad^2", a.r),
        false,
        how,
    );
}
