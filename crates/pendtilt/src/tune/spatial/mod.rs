//! The 3-D tune: ekf3d's settings (`[ekf3d]` of a 3-D rig file) from the user's own 3-D
//! log (MODEL.md 7.6), with no true attitude. The planar tune's estimators do the
//! measuring, axis by axis; one concern per module:
//!
//! - [`noise`]: the sensors' noise ([`crate::tune::encoder`], [`crate::tune::gyro`],
//!   [`crate::tune::accel`] on each axis, the speed's by its second differences);
//! - [`speed`]: the vehicle's jerk density, by the likelihood of the speed readings;
//! - [`forcing`]: the vibration density near the natural frequencies (the accelerometer
//!   less what ekf3d's model predicts of it) and the encoders' jitter
//!   ([`crate::tune::forcing::jitter`] per axis);
//! - [`rig_file`]: the start's rig file with the tuned `[ekf3d]` table, a comment per
//!   value;
//! - [`zoo`]: the test bed: seeded scooter3d, ship3d and ride3d logs on drawn rigs and
//!   sensors, each scored at the defaults, self-tuned and tuned against the truth.
//!
//! [`tune3d`] runs them in that order and returns the settings with a [`Note`] per value.
//! A value the log cannot tell (no speed column, a log too short for a spectrum) keeps the
//! start's and its note says so; so does the one the log never tells here, the gyro's bias
//! walk (a doubt, in the file).
//!
//! ```
//! use pendtilt::sim::spatial::Scenario3d;
//! use pendtilt::tune::spatial::{tune3d, Start3d};
//! let mut sc = Scenario3d::named("scooter3d", 1).unwrap();
//! sc.duration = 12.0;
//! let samples: Vec<_> = sc.run(1).unwrap().map(|(_, r)| r.sample(1e-3)).collect();
//! let t = tune3d(&samples, &Start3d::default());
//! assert!(t.notes.iter().any(|n| n.key == "ekf3d.gyro_density" && !n.kept_default));
//! ```
pub mod forcing;
pub mod noise;
pub mod reference;
pub mod rig_file;
pub mod speed;
pub mod zoo;

use super::Note;
use crate::bank::spatial::rig::{Ekf3dConfig, Rig3dConfig};
use crate::bank::spatial::Settings3d;
use pendtilt_core::spatial::ekf::Settings;
use pendtilt_core::spatial::SpatialSample;

/// Where tuning starts: the rig file's settings for ekf3d (its pendulum, mounting and
/// `[ekf3d]` table), and the table as given (the keys the tune does not set are kept).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Start3d {
    /// ekf3d's settings as `pendtilt estimate --params RIG` builds them.
    pub settings: Settings<f64>,
    /// The rig file's `[ekf3d]` table.
    pub config: Ekf3dConfig,
}

impl Default for Start3d {
    /// MODEL.md 7.6's rig and ekf3d's defaults.
    fn default() -> Self {
        Self::from_rig(&Rig3dConfig::default())
    }
}

impl Start3d {
    /// The settings of a 3-D rig file, as `estimate` builds them without `--scenario`.
    pub fn from_rig(rig: &Rig3dConfig) -> Self {
        let mut s = Settings3d::new(rig.pendulum3d.params(), rig.mounting, None);
        rig.ekf3d.apply(&mut s.ekf);
        s.ekf.gyro = rig.gyro;
        Self {
            settings: s.ekf,
            config: rig.ekf3d,
        }
    }
}

/// Everything the 3-D tune found.
#[derive(Debug, Clone)]
pub struct Tuned3d {
    /// The sensors' noise as measured.
    pub noise: noise::Noise3d,
    /// The vehicle's jerk density from the speed column; `None` without one.
    pub jerk: Option<Result<speed::Jerk, String>>,
    /// The vibration density near the natural frequencies.
    pub forcing: Result<forcing::Forcing3d, String>,
    /// The encoders' jitter \[rad\] as measured.
    pub jitter: Result<f64, String>,
    /// The scale ekf3d takes the jitter at, and the band errors that chose it.
    pub jitter_scale: Option<crate::tune::forcing::JitterScale>,
    /// ekf3d's settings, tuned.
    pub settings: Settings<f64>,
    /// The rig file's `[ekf3d]` table: the start's with every tuned key set.
    pub config: Ekf3dConfig,
    /// One note per value, in the table's order; `kept_default` marks a value the log
    /// did not tell (a doubt).
    pub notes: Vec<Note>,
}

/// Seconds at the start left out of the forcing's spectrum (the filter settles).
pub const SETTLE_SECONDS: f64 = 2.0;

/// Sample rate \[Hz\] from the median positive step; 1 kHz without one.
pub fn sample_rate(samples: &[SpatialSample<f64>]) -> f64 {
    let mut d: Vec<f64> = samples
        .iter()
        .map(|s| s.dt)
        .filter(|d| d.is_finite() && *d > 0.0)
        .collect();
    if d.is_empty() {
        return 1000.0;
    }
    d.sort_by(f64::total_cmp);
    1.0 / d[d.len() / 2]
}

/// Tunes ekf3d on `samples` (one 3-D log, rows in order) from `start`: see the module
/// documentation.
pub fn tune3d(samples: &[SpatialSample<f64>], start: &Start3d) -> Tuned3d {
    let rate = sample_rate(samples);
    let f_n = forcing::natural_hz(&start.settings);
    // The figures are measured with the filter's forcing fixed (what each run measures
    // is then the density it was given); the adaptation is set last ([`adaptation`]).
    let start = &Start3d {
        settings: Settings {
            adaptation: pendtilt_core::spatial::ekf::Adaptation {
                enabled: false,
                ..start.settings.adaptation
            },
            ..start.settings
        },
        ..*start
    };
    let noise = noise::estimate(samples, rate, f_n[0].min(f_n[1]));
    let mut notes = Vec::new();
    let mut s = start.settings;
    notes::sensors(&mut s, &noise, &mut notes);
    let jitter = forcing::jitter3d(samples, rate, f_n);
    notes::jitter(&mut s, &jitter, &mut notes);
    let skip = (SETTLE_SECONDS * rate).round() as usize;
    let force = forcing::settle(&s, samples, rate, skip);
    notes::forcing(&mut s, &force, &mut notes);
    let scale = match &jitter {
        Ok(j) if *j > 0.0 => Some(forcing::jitter_scale3d(&s, samples, rate, skip)),
        _ => None,
    };
    if let Some(js) = &scale {
        s.encoder_jitter *= js.scale;
        notes::jitter_scale(s.encoder_jitter, js, &mut notes);
    }
    // The jerk last: the forcing and the jitter are measured with the start's, as they
    // were chosen (measured with the jerk found, scooter ride 3 of the zoo went from
    // 0.019 to 0.061 deg).
    let jerk = matches!(noise.speed, Some(Ok(v)) if v > 0.0)
        .then(|| speed::jerk(samples, s.speed.noise, s.speed.initial_rate));
    notes::jerk(&mut s, &jerk, &mut notes);
    notes::kept(&s, &noise, &mut notes);
    let standing = matches!(&jerk, Some(Ok(j)) if j.at_bound && j.density < 1.0);
    s.adaptation = adaptation(&s, standing);
    notes::adaptation(&s, standing, &mut notes);
    let config = config_of(&start.config, &s, noise.speed.is_some());
    Tuned3d {
        noise,
        jerk,
        forcing: force,
        jitter,
        jitter_scale: scale,
        settings: s,
        config,
        notes,
    }
}

/// The forcing's density \[m/s^2/sqrt(Hz)\] the adaptation may reach at most, whatever
/// the tune measured: ekf3d's default density times the square root of its default
/// largest factor (0.02 x 316 = 6.3), beyond any body the pendulum still follows
/// ([`pendtilt_core::adaptation::defaults::MAX_FACTOR`]).
pub fn forcing_ceiling() -> f64 {
    let d = Settings::<f64>::default();
    d.environment.vibration_density * d.adaptation.max_factor.sqrt()
}

/// The adaptation's floor on a standing vehicle (a factor on the tuned density's
/// variance): see [`adaptation`].
pub const STANDING_FLOOR: f64 = 0.1;

/// The online adaptation of `s` once its vibration density is tuned: on, starting from
/// the tuned density, up to [`forcing_ceiling`], and down to the tuned density itself,
/// or to [`STANDING_FLOOR`] times its variance when `standing` (the speed column never
/// changed: [`speed::Jerk::at_bound`] at the range's floor).
///
/// The floor: the tuned density is an upper bound (the residual it is measured on holds
/// the filter's own attitude error). On a standing vehicle nothing but vibration forces
/// the pendulum, and the filter's innovations may bring the density down; on a moving
/// one the unpredicted accelerations are real and show as tilt, not in the innovations.
/// Measured on the zoo (60 s; the rule chosen on rides 0-8, rides 9-17 held out), deg
/// RMS at floors 1 and 0.1: standing scooters 0, 3, 6: 0.056 -> 0.038, 0.018 -> 0.016,
/// 0.035 -> 0.029; held out 9, 12, 15: 0.0080 -> 0.0087, 0.016 -> 0.014, 0.044 -> 0.034;
/// ships 1, 4 (their speed changes): 0.173 -> 0.273, 0.145 -> 0.193. With the floor at
/// one the adaptation changed one ride of 18 by more than 1 % (ship ride 10, 0.363 ->
/// 0.376 deg); it is there for the motion the log did not show: a hand-held stretch, a
/// tumble (docs/real-motion.md).
pub fn adaptation(
    s: &Settings<f64>,
    standing: bool,
) -> pendtilt_core::spatial::ekf::Adaptation<f64> {
    let d = s.environment.vibration_density;
    let max = if d > 0.0 && d.is_finite() {
        (forcing_ceiling() / d).powi(2).max(1.0)
    } else {
        s.adaptation.max_factor
    };
    pendtilt_core::spatial::ekf::Adaptation {
        enabled: true,
        min_factor: if standing { STANDING_FLOOR } else { 1.0 },
        max_factor: max,
        ..s.adaptation
    }
}

/// The `[ekf3d]` table: `start` with every value the tune sets taken from `s` (the speed's
/// only when the log has one).
fn config_of(start: &Ekf3dConfig, s: &Settings<f64>, speed: bool) -> Ekf3dConfig {
    let n = &s.sensors;
    Ekf3dConfig {
        vibration_density: Some(s.environment.vibration_density),
        encoder_jitter: Some(s.encoder_jitter),
        encoder_bits: Some(n.encoder_bits),
        encoder_noise: Some(n.encoder_noise),
        gyro_density: Some(n.gyro_density),
        gyro_bias_walk: Some(n.gyro_bias_walk),
        gyro_bias: Some(n.gyro_bias),
        accel_density: Some(n.accel_density),
        speed_noise: if speed {
            Some(s.speed.noise)
        } else {
            start.speed_noise
        },
        jerk_density: if speed {
            Some(s.speed.jerk_density)
        } else {
            start.jerk_density
        },
        adapt: Some(s.adaptation.enabled),
        adapt_min_factor: Some(s.adaptation.min_factor),
        adapt_max_factor: Some(s.adaptation.max_factor),
        ..*start
    }
}

mod notes;
