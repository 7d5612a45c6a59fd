//! What the vibration does to the pendulum, measured on the log: the EKF's pendulum
//! forcing density (in its band) and the encoder's jitter (above it).
//!
//! - Forcing density: the EKF forces the pendulum with white noise standing for the
//!   specific force across it that its model does not predict, of density `d` near the
//!   natural frequency f_n: `process.pendulum = d^2 / (b g)^2`
//!   ([`pendtilt_core::ekf::settings`]). The accelerometer at the pivot reads that force:
//!   `ax` minus what the model predicts from its own state (`g sin theta - d_acc theta''`,
//!   the EKF run with the log's sensor figures) is the unpredicted force, and the median
//!   of its one-sided spectrum within a third of an octave of f_n is `2 d^2` (as for the
//!   gyro: `d` is the density of the model's white noise, of variance `d^2 dt` over a
//!   step dt). The sensor's own noise is included: an upper bound, kept so that a log
//!   without vibration still leaves the model some slack. `ax` itself will not do: the
//!   body's tilt puts `g sin theta` into it, and a chirp through f_n made it 700 times
//!   the residual (zoo ride 11).
//! - Jitter: vibration far above f_n still moves the pendulum a little, and a fine
//!   encoder reads it ([`pendtilt_core::ekf::ModelSettings::encoder_jitter`]). The power
//!   of `phi` (from the spectrum of its first difference, over the difference's gain
//!   `4 sin^2(pi f / rate)`: no leakage of the slow swing) from [`JITTER_TIMES_NATURAL`] times f_n up to 0.3 of the sample rate, less
//!   the white floor there (the median density over 0.3-0.45 of the rate, as for the
//!   gyro), is the jitter's variance: the tilt and the pendulum's own swing lie below
//!   that band. (This takes the measured jitter as white, which it is not: an engine tone
//!   is predictable. The innovation likelihood, which assumes white readings, prefers no
//!   jitter at all on such logs and a filter that follows the tone as forcing: zoo ride
//!   11, -17.6 against -14.9 per innovation, with the RMS error 0.013 against 0.0045 deg.)
use super::spectrum::{segment_for, welch};
use pendtilt_core::ekf::model::{ALPHA, THETA};
use pendtilt_core::ekf::{Ekf, ModelSettings};
use pendtilt_core::{Estimator, Sample};

/// The jitter band starts at this multiple of the natural frequency: the pendulum's
/// response to forcing falls as `(f_n / f)^2` above f_n, 1/25 here.
pub const JITTER_TIMES_NATURAL: f64 = 5.0;

/// Spectral resolution of the forcing density, as a fraction of f_n (a third of an
/// octave is 0.23 f_n wide: a few bins in it).
const RESOLUTION_OF_NATURAL: f64 = 0.1;

/// The pendulum's forcing density in its band.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Forcing {
    /// Density of the unpredicted specific force across the pendulum near f_n
    /// \[m/s^2/sqrt(Hz)\].
    pub density: f64,
    /// The EKF's pendulum process noise it gives \[1/s^3\].
    pub process: f64,
}

/// The pendulum's forcing density on `samples` (sample rate `rate`), the EKF run with
/// `settings` (module documentation), the first `skip` rows left out; `Err` says why not.
pub fn forcing(
    settings: &ModelSettings<f64>,
    samples: &[Sample<f64>],
    rate: f64,
    skip: usize,
) -> Result<Forcing, String> {
    let p = &settings.params;
    let f_n = p.natural_frequency_hz();
    if !(f_n.is_finite() && f_n > 0.0) {
        return Err("the pendulum has no natural frequency".into());
    }
    if !samples.iter().any(|s| s.ax.is_finite()) {
        return Err("no accelerometer in the log".into());
    }
    let (g, d_acc) = (settings.gravity, settings.accel_distance);
    let mut ekf = Ekf::new(*settings);
    let residual: Vec<f64> = samples
        .iter()
        .map(|s| {
            ekf.update(s);
            ekf.state()
                .map_or(f64::NAN, |x| s.ax - (g * x[THETA].sin() - d_acc * x[ALPHA]))
        })
        .collect();
    let residual = &residual[skip.min(residual.len())..];
    let want = rate / (RESOLUTION_OF_NATURAL * f_n);
    let seg = (want.max(8.0) as usize)
        .next_power_of_two()
        .max(segment_for(rate));
    let psd = welch(residual, rate, seg).ok_or_else(|| {
        format!(
            "too short for the accelerometer's spectrum at {:.3} Hz resolution",
            rate / seg as f64
        )
    })?;
    let third = 2f64.powf(1.0 / 6.0);
    let density = psd
        .band_median(f_n / third, f_n * third)
        .ok_or_else(|| "no spectrum bin near the natural frequency".to_string())?;
    let density = (density / 2.0).sqrt();
    let bg = p.b * g;
    Ok(Forcing {
        density,
        process: (density / bg).powi(2),
    })
}

/// The encoder's jitter \[rad\] from `phi` at `rate` for a pendulum of natural frequency
/// `f_n` \[Hz\] (module documentation); `Err` says why not.
pub fn jitter(phi: &[f64], rate: f64, f_n: f64) -> Result<f64, String> {
    let lo = JITTER_TIMES_NATURAL * f_n;
    let hi = 0.3 * rate;
    if lo >= hi || !lo.is_finite() {
        return Err(format!(
            "no band above {JITTER_TIMES_NATURAL} x f_n ({lo:.1} Hz) below 0.3 x the rate"
        ));
    }
    // The spectrum of phi's first difference over the difference's gain: phi's own,
    // without the leakage of the slow swing through the window (a 0.1 rad swing at 0.3 Hz
    // leaked 1.4e-4 rad into the band at 1 Hz bins).
    let dphi: Vec<f64> = phi.windows(2).map(|w| w[1] - w[0]).collect();
    let mut psd = welch(&dphi, rate, segment_for(rate))
        .ok_or_else(|| "too short for the encoder's spectrum (2 s needed)".to_string())?;
    let df = psd.df;
    for (i, p) in psd.density.iter_mut().enumerate().skip(1) {
        *p /= (2.0 * (std::f64::consts::PI * i as f64 * df / rate).sin()).powi(2);
    }
    let floor = psd
        .band_median(hi, 0.45 * rate)
        .ok_or_else(|| "no high band in the encoder's spectrum".to_string())?;
    Ok((psd.band_power(lo, hi) - floor * (hi - lo)).max(0.0).sqrt())
}

/// Doublings [`jitter_scale`] tries at most (a cap of 2^5 = 32 is a pendulum of
/// 0.1 Hz at 1 kHz).
pub const JITTER_MAX_DOUBLINGS: usize = 5;

/// A doubling of the jitter is kept only if it lowers the EKF's band error by more
/// than this fraction.
pub const JITTER_STEP_GAIN: f64 = 0.05;

/// The measured jitter's scale for the EKF, and the band errors that chose it.
#[derive(Debug, Clone, PartialEq)]
pub struct JitterScale {
    /// The factor the measured jitter is multiplied by (1: kept).
    pub scale: f64,
    /// Its upper bound, `sqrt(rate / 2 / (JITTER_TIMES_NATURAL f_n))`.
    pub cap: f64,
    /// (scale, the EKF's RMS error against the gyro's integral above
    /// [`super::reference::CORNER_HZ`] \[rad\]) for each scale tried, in order.
    pub tried: Vec<(f64, f64)>,
}

/// Scales the measured jitter of `settings` (the EKF as tuning starts it) by powers of
/// two up to the cap while each doubling lowers the EKF's error against the gyro's
/// integral (bias `bias`) above [`super::reference::CORNER_HZ`] by more than
/// [`JITTER_STEP_GAIN`]; rows before `skip` are not scored. `None` when the budget ran out
/// before the first run.
///
/// Why: the EKF takes the jitter for white noise of that variance, spread over the whole
/// band up to half the sample rate, but the pendulum's response to vibration falls as
/// `(f_n / f)^2`, so broadband vibration piles the jitter up just above 5 f_n, where the
/// filter does not average it away. White noise with the same density there has a
/// variance larger by up to the ratio of the bands, `rate / 2 / (5 f_n)`: the cap. An
/// error at those frequencies is what the gyro's integral measures well (its drift lies
/// below the corner), so the band error decides how far toward the cap to go. Zoo ride
/// 13 (broadband vibration, a 1.1 Hz pendulum): the EKF at 0.0201 deg RMS with the
/// jitter as measured, 0.0079 with it 8 times; an engine's tone far above the band or a
/// coarse encoder's rounding leaves the band error flat and the jitter as measured (ride
/// 14, 10-bit: 8 times would take 0.043 to 0.045 deg).
pub fn jitter_scale(
    settings: &ModelSettings<f64>,
    samples: &[Sample<f64>],
    bias: f64,
    rate: f64,
    skip: usize,
    budget: &mut super::search::Budget,
) -> Option<JitterScale> {
    let f_n = settings.params.natural_frequency_hz();
    let cap = (0.5 * rate / (JITTER_TIMES_NATURAL * f_n)).sqrt().max(1.0);
    let reference = super::reference::integral(samples, bias);
    let band = |m: f64| {
        let mut s = *settings;
        s.encoder_jitter *= m;
        let mut f = Ekf::new(s);
        let est: Vec<f64> = samples.iter().map(|x| f.update(x).theta).collect();
        super::reference::band_error(&est, &reference, samples, skip)
    };
    if !budget.tick() {
        return None;
    }
    Some(doubling_search(cap, band, || budget.tick()))
}

/// The jitter's scale from 1, doubled (at most [`JITTER_MAX_DOUBLINGS`] times, never past
/// `cap`) while each doubling lowers `band` (the error it gives) by more than
/// [`JITTER_STEP_GAIN`]; `more` is asked before each doubling's evaluation (a budget).
/// The planar and the 3-D tune's search.
pub(crate) fn doubling_search(
    cap: f64,
    mut band: impl FnMut(f64) -> f64,
    mut more: impl FnMut() -> bool,
) -> JitterScale {
    let mut at: (f64, f64) = (1.0, band(1.0));
    let mut tried = vec![at];
    for _ in 0..JITTER_MAX_DOUBLINGS {
        let next = (2.0 * at.0).min(cap);
        if next <= at.0 || !more() {
            break;
        }
        let e = band(next);
        tried.push((next, e));
        if e < (1.0 - JITTER_STEP_GAIN) * at.1 {
            at = (next, e);
        } else {
            break;
        }
    }
    JitterScale {
        scale: at.0,
        cap,
        tried,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::planar::vibration::Vibration;
    use crate::tune::zoo::score::RideLog;

    #[test]
    fn without_vibration_the_forcing_is_the_accelerometers_noise() {
        // Zoo ride 17 (industrial sensors, a chirp) with the pivot at the accelerometer
        // and no vibration: the specific force the model does not predict is the
        // accelerometer's white noise, whose density the simulator knows.
        let mut ride = crate::tune::zoo::ride(17, 30.0);
        ride.scenario.vibration = Vibration::default();
        ride.scenario.pendulum.pivot_offset = 0.0;
        let log = RideLog::simulate(&ride.scenario, 17);
        let rig = ride.scenario.rig().unwrap();
        let st = crate::tune::Start::from_rig(&rig).ekf;
        let f = forcing(&st, &log.samples, 1000.0, 1000).unwrap();
        let truth = ride.scenario.sensors.accel.noise_density;
        assert!(
            (f.density / truth - 1.0).abs() < 0.2,
            "{} vs {truth}",
            f.density
        );
        let bg = st.params.b * st.gravity;
        assert!((f.process - (f.density / bg).powi(2)).abs() < 1e-12 * f.process);
        // No accelerometer: said, not guessed.
        let none: Vec<_> = log
            .samples
            .iter()
            .map(|s| Sample { ax: f64::NAN, ..*s })
            .collect();
        let e = forcing(&st, &none, 1000.0, 1000).unwrap_err();
        assert!(e.contains("no accelerometer"), "{e}");
    }
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn a_tone_above_the_band_is_the_jitter_and_white_noise_is_not() {
        // phi: a slow swing, white noise of 1e-4 rad and a 40 Hz tone of amplitude 1e-3
        // rad (RMS 7.07e-4) for a 1 Hz pendulum.
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let rate = 1000.0;
        let phi: Vec<f64> = (0..20_000)
            .map(|k| {
                let t = k as f64 / rate;
                let white = 1e-4 * (rng.random::<f64>() - 0.5) * 12f64.sqrt();
                0.1 * (std::f64::consts::TAU * 0.3 * t).sin()
                    + 1e-3 * (std::f64::consts::TAU * 40.0 * t).sin()
                    + white
            })
            .collect();
        let j = jitter(&phi, rate, 1.0).unwrap();
        assert!((j / 7.07e-4 - 1.0).abs() < 0.05, "{j}");
        let quiet: Vec<f64> = phi
            .iter()
            .enumerate()
            .map(|(k, v)| v - 1e-3 * (std::f64::consts::TAU * 40.0 * k as f64 / rate).sin())
            .collect();
        // White noise alone: what is left is its estimate's scatter, well under the tone.
        let q = jitter(&quiet, rate, 1.0).unwrap();
        assert!(q < 1e-4, "{q}");
        assert!(jitter(&phi, rate, 70.0).is_err());
    }
}
