//! What forces the Cardan pendulum, measured on the log: ekf3d's vibration density (the
//! specific force across the pendulum that its model does not predict, near the natural
//! frequencies) and the encoders' jitter (the vibration above the pendulum's band).
//!
//! - Vibration density: ekf3d forces each joint with white noise of density `d / (g b)`
//!   ([`pendtilt_core::spatial::ekf::settings`]), `d` standing for the specific force its
//!   model does not predict. The accelerometer reads the specific force; what the model
//!   predicts of it is gravity along the filter's up direction, O's known acceleration
//!   (the speed's rate along body x and its centripetal part) and the lever arm from O to
//!   the accelerometer (`wd x r + w x (w x r)`, the gyro's derivative through a 10 Hz
//!   low-pass). The rest, on `ax` and `ay`, is the unpredicted force: the median of its
//!   one-sided spectrum within a third of an octave of each axis' natural frequency is
//!   `2 d^2`. The same force in the band of the body's slow motion ([`MOTION_BAND`],
//!   0.1-0.3 Hz: a ship's heave, a car's unpredicted accelerations) is what the pendulum
//!   would take for tilt there, where the filter's attitude follows it: its density (the
//!   band's mean power, its tones counted) counts too, and `d` is the largest of the
//!   four (two axes, two bands). Measured on the zoo (`zoo`, rides 1, 4, 7: ships), the
//!   motion band's 0.11-0.17 against 0.011-0.015 near f_n, and ekf3d tuned on the truth
//!   took 0.07-0.15. As in the planar tune, the sensor's own noise and the filter's
//!   attitude error (g times it) are included: an upper bound.
//! - Jitter: the planar tune's [`crate::tune::forcing::jitter`] on each encoder (its power
//!   from 5 times that axis' natural frequency to 0.3 of the rate, less the white floor),
//!   the root mean square of the two; then scaled as the planar tune scales it, by the
//!   filter's error against the gyro in the band the pendulum does not reach
//!   ([`jitter_scale3d`]).
use super::noise::column;
use super::SETTLE_SECONDS;
use crate::tune::forcing::{doubling_search, jitter, JitterScale, JITTER_TIMES_NATURAL};
use crate::tune::spectrum::{segment_for, welch};
use nalgebra::Vector3;
use pendtilt_core::filters::biquad::LowPass2;
use pendtilt_core::spatial::ekf::{Ekf, Settings};
use pendtilt_core::spatial::mounting::lever_arm;
use pendtilt_core::spatial::SpatialSample;
use pendtilt_core::Estimator;
use std::f64::consts::TAU;

/// Cutoff \[Hz\] of the low-pass before the gyro is differentiated (ekf3d's own default).
const DERIVATIVE_HZ: f64 = 10.0;

/// The band \[Hz\] of the body's slow motion in which the unpredicted force is measured
/// too (module documentation).
pub const MOTION_BAND: [f64; 2] = [0.1, 0.3];

/// The unpredicted specific force across the pendulum.
#[derive(Debug, Clone, PartialEq)]
pub struct Forcing3d {
    /// Its density on body x and y near the natural frequencies (of the outer and inner
    /// joint), the median's floor \[m/s^2/sqrt(Hz)\].
    pub near: [f64; 2],
    /// Its density on body x and y in [`MOTION_BAND`], the band's mean power (its tones
    /// count) \[m/s^2/sqrt(Hz)\].
    pub motion: [f64; 2],
    /// The largest of the four: ekf3d's `vibration_density`.
    pub density: f64,
    /// The runs of ekf3d it took ([`settle`]).
    pub rounds: usize,
    /// Why the motion band was not measured (a log too short for its resolution): the
    /// density is then the one near the natural frequencies alone.
    pub motion_short: Option<String>,
}

/// Runs of [`settle`] at most.
pub const MAX_ROUNDS: usize = 5;

/// [`forcing`] run again with ekf3d at the density found until it changes by less than
/// 10 % (at most [`MAX_ROUNDS`] runs): the residual holds the filter's own attitude error
/// (g times it), which the density it runs with sets. A filter that follows its pendulum
/// too far reads a large residual and loosens; one that trusts its model where nothing
/// unpredicted forces it reads less and tightens.
pub fn settle(
    settings: &Settings<f64>,
    samples: &[SpatialSample<f64>],
    rate: f64,
    skip: usize,
) -> Result<Forcing3d, String> {
    let mut s = *settings;
    let mut f = forcing(&s, samples, rate, skip)?;
    for k in 2..=MAX_ROUNDS {
        if !(f.density > 0.0 && f.density.is_finite()) {
            break;
        }
        let was = s.environment.vibration_density;
        s.environment.vibration_density = f.density;
        if (f.density / was - 1.0).abs() < 0.1 {
            break;
        }
        f = Forcing3d {
            rounds: k,
            ..forcing(&s, samples, rate, skip)?
        };
    }
    Ok(f)
}

/// The natural frequencies \[Hz\] of the outer and inner joint.
pub fn natural_hz(s: &Settings<f64>) -> [f64; 2] {
    s.params.natural_frequencies().map(|w| w / TAU)
}

/// The unpredicted specific force on x and y per row (module documentation), ekf3d run
/// with `settings`; NaN before the filter starts.
fn residual(settings: &Settings<f64>, samples: &[SpatialSample<f64>]) -> [Vec<f64>; 2] {
    let g = settings.params.gravity;
    let r = settings.mounting.from_centre(settings.mounting.accel_at);
    let mut ekf = Ekf::new(*settings);
    let mut lp = [0, 1, 2].map(|_| LowPass2::new(DERIVATIVE_HZ));
    let mut prev_w = None::<Vector3<f64>>;
    let mut out = [
        Vec::with_capacity(samples.len()),
        Vec::with_capacity(samples.len()),
    ];
    for (k, s) in samples.iter().enumerate() {
        let a = ekf.update(s);
        let dt = if k == 0 { 0.0 } else { s.dt };
        let bias = ekf.state().map_or(Vector3::zeros(), |x| x.bias);
        let raw = Vector3::new(s.gyro[0], s.gyro[1], s.gyro[2]) - bias;
        let w = Vector3::new(
            lp[0].update(raw[0], dt),
            lp[1].update(raw[1], dt),
            lp[2].update(raw[2], dt),
        );
        let wd = match prev_w {
            Some(p) if dt > 0.0 => (w - p) / dt,
            _ => Vector3::zeros(),
        };
        prev_w = Some(w);
        // O's acceleration as the filter holds it (its speed and the speed's rate are
        // states): the rate along x, and the turn's centripetal part w x (v x_b). A
        // differenced reading would not do: 0.05 m/s of white noise differenced at 1 kHz
        // is 0.03 m/s^2/sqrt(Hz) at 2 Hz, the size of the density sought.
        let travel = ekf
            .state()
            .map_or([0.0, 0.0], |x| [x.travel[0], x.travel[1]]);
        let vel = Vector3::new(travel[0], 0.0, 0.0);
        let a_o = Vector3::new(travel[1], 0.0, 0.0) + w.cross(&vel);
        let up = a.up();
        let predicted = Vector3::new(up[0], up[1], up[2]) * g + a_o + lever_arm(&w, &wd, &r);
        for (i, o) in out.iter_mut().enumerate() {
            o.push(s.accel[i] - predicted[i]);
        }
    }
    out
}

/// The vibration density on `samples` at `rate` \[Hz\], ekf3d run with `settings` (its
/// measured sensor figures); rows before `skip` left out. `Err` says why not.
pub fn forcing(
    settings: &Settings<f64>,
    samples: &[SpatialSample<f64>],
    rate: f64,
    skip: usize,
) -> Result<Forcing3d, String> {
    let floor = settings.sensors.accel_density;
    if !samples.iter().any(|s| s.accel[0].is_finite()) {
        return Err("no accelerometer in the log".into());
    }
    let f_n = natural_hz(settings);
    let res = residual(settings, samples);
    let lo = f_n[0].min(f_n[1]);
    let rows = samples.len().saturating_sub(skip);
    // A tenth of the lower natural frequency per bin near it (a few bins in a third of an
    // octave); the motion band's resolution at most a sixth of its width.
    let near_seg = ((rate / (0.1 * lo)).max(8.0) as usize)
        .next_power_of_two()
        .max(segment_for(rate));
    let motion_seg =
        ((rate * 3.0 / (MOTION_BAND[1] - MOTION_BAND[0])) as usize).next_power_of_two();
    let third = 2f64.powf(1.0 / 6.0);
    let (mut near, mut motion) = ([0.0; 2], [0.0; 2]);
    let short = |seg: usize| {
        format!(
            "too short for the accelerometer's spectrum at {:.3} Hz resolution ({:.0} s \
             after the first {SETTLE_SECONDS} s needed, {:.0} s given)",
            rate / seg as f64,
            1.5 * seg as f64 / rate,
            rows as f64 / rate
        )
    };
    for i in 0..2 {
        let r = &res[i][skip.min(res[i].len())..];
        let psd = welch(r, rate, near_seg).ok_or_else(|| short(near_seg))?;
        let p = psd
            .band_median(f_n[i] / third, f_n[i] * third)
            .ok_or_else(|| "no spectrum bin near the natural frequency".to_string())?;
        near[i] = (p / 2.0 - floor * floor).max(0.0).sqrt();
        // Too short for the motion band: the density near f_n alone, and said.
        let [a, b] = MOTION_BAND;
        motion[i] = welch(r, rate, motion_seg).map_or(f64::NAN, |psd| {
            (psd.band_power(a, b) / (b - a) / 2.0 - floor * floor)
                .max(0.0)
                .sqrt()
        });
    }
    let m = |v: [f64; 2]| v[0].max(v[1]);
    let motion_short = motion.iter().any(|v| v.is_nan()).then(|| short(motion_seg));
    Ok(Forcing3d {
        rounds: 1,
        near,
        motion,
        density: if motion_short.is_some() {
            m(near)
        } else {
            m(near).max(m(motion))
        },
        motion_short,
    })
}

/// The encoders' jitter \[rad\]: the root mean square of the two axes' (module
/// documentation); `Err` when neither can be measured.
pub fn jitter3d(samples: &[SpatialSample<f64>], rate: f64, f_n: [f64; 2]) -> Result<f64, String> {
    let j: Vec<Result<f64, String>> = (0..2)
        .map(|i| jitter(&column(samples, |s| s.phi[i]), rate, f_n[i]))
        .collect();
    let ok: Vec<f64> = j.iter().filter_map(|r| r.as_ref().ok().copied()).collect();
    if ok.is_empty() {
        return Err(j.into_iter().find_map(Result::err).unwrap_or_default());
    }
    Ok((ok.iter().map(|v| v * v).sum::<f64>() / ok.len() as f64).sqrt())
}

/// Scales the measured jitter of `settings` by powers of two up to the cap while each
/// doubling lowers ekf3d's error against the gyro's up direction
/// ([`super::reference::band_error`]) by more than [`crate::tune::forcing::JITTER_STEP_GAIN`], as the planar
/// tune's [`crate::tune::forcing::jitter_scale`] does (and for its reason: the jitter
/// piles up just above the pendulum's band, where the filter does not average it away,
/// and the cap is the ratio of the bands, `rate / 2 / (5 f_n)`). Measured on the zoo
/// (rides 0-8, 30 s): ten times the jitter lowered the band error on the scooter rides
/// (0.046 -> 0.028, 0.033 -> 0.023, 0.033 -> 0.019 deg) and the true error with it (0.064
/// -> 0.062, 0.042 -> 0.038, 0.058 -> 0.020); on the ships and cars it raised both or left
/// the band error within 5 %.
pub fn jitter_scale3d(
    settings: &Settings<f64>,
    samples: &[SpatialSample<f64>],
    rate: f64,
    skip: usize,
) -> JitterScale {
    let f_n = natural_hz(settings);
    let cap = (0.5 * rate / (JITTER_TIMES_NATURAL * f_n[0].min(f_n[1])))
        .sqrt()
        .max(1.0);
    let band = |m: f64| {
        let mut s = *settings;
        s.encoder_jitter *= m;
        super::reference::band_error(&super::reference::run(&s, samples), samples, rate, skip)
    };
    doubling_search(cap, band, || true)
}
