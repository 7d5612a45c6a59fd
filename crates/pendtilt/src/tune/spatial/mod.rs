//! The 3-D tune: ekf3d's settings (`[ekf3d]` of a 3-D rig file) from the user's own 3-D
//! log (MODEL.md 7.6), with no true attitude. The planar tune's estimators do the
//! measuring, axis by axis; one concern per module:
//!
//! - [`noise`]: the sensors' noise ([`crate::tune::encoder`], [`crate::tune::gyro`],
//!   [`crate::tune::accel`] on each axis, the speed's by its second differences);
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
//! start's and its note says so; so do the two the log never tells here, the gyro's bias
//! walk and the vehicle's jerk density (doubts, in the file).
//!
//! ```
//! use pendtilt::sim3d::Scenario3d;
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
pub mod zoo;

use super::Note;
use crate::bank3d::rig::{Ekf3dConfig, Rig3dConfig};
use crate::bank3d::Settings3d;
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
    // The tuned figures are the log's: the filter runs with them fixed, here and after
    // (as the planar tune; on the zoo's rides 0-8 the adaptation on top of them took
    // scooter ride 3 from 0.033 to 0.043 deg and changed no other ride by 1 %).
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
    notes::kept(&s, &noise, &mut notes);
    notes.push(Note {
        key: "ekf3d.adapt".into(),
        value: "false".into(),
        kept_default: false,
        how: "the figures above are this log's: ekf3d runs with them fixed rather than adapting \
            its forcing from its default (on the zoo's rides the adaptation on top of them \
            changed nothing by 1 % but one scooter ride, 0.033 -> 0.043 deg)"
            .into(),
        fell_back: false,
    });
    let config = config_of(&start.config, &s, noise.speed.is_some());
    Tuned3d {
        noise,
        forcing: force,
        jitter,
        jitter_scale: scale,
        settings: s,
        config,
        notes,
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
        ..*start
    }
}

mod notes;
