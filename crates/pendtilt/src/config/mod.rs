//! The rig file: pendulum parameters and estimator settings in TOML (MODEL.md section 5).
//!
//! # Format
//!
//! ```toml
//! [pendulum]            # EITHER the physical values ...
//! mass = 0.05           # m_p [kg], > 0
//! length = 0.05         # l_p, pivot to centre of gravity [m], > 0
//! inertia = 1.3e-4      # I_p about the pivot [kg m^2], >= mass * length^2
//! damping = 1.07e-3     # C, viscous friction at the pivot [N m s/rad], >= 0
//! pivot_offset = 0.0    # l12, body axis P1 to pendulum pivot P2 [m], any sign
//! gravity = 9.80665     # g [m/s^2], > 0
//!
//! # ... OR the normalised values that `pendtilt fit` writes (never both in one file):
//! # a = 0.04364         # C / (m_p g l_p) [s], >= 0
//! # b = 5.302e-3        # I_p / (m_p g l_p) [s^2], > 0
//! # c = 0.0             # l12 / g [s^2]
//!
//! [kalman]              # the angle+bias filter of MODEL.md section 4
//! q_angle = 0.001       # angle process noise density [rad^2/s]; Q = q * dt
//! q_bias = 0.003        # gyro-bias process noise density [(rad/s)^2/s]; Q = q * dt
//! r_accel = 0.03        # variance of the accelerometer angle [rad^2]
//! r_pendulum = 0.001    # variance of a pendulum algorithm's angle [rad^2]
//! # r_accel_fused = 0.03 # the accelerometer's beside it in kf_fused (default r_accel)
//! p0_angle = 0.01       # initial angle variance [rad^2]
//! p0_bias = 0.01        # initial bias variance [(rad/s)^2]
//!
//! [differentiator]      # phi', phi'' for alg1, alg2, alg3 (filters::diff)
//! response = "butterworth"      # or "bessel", "critically_damped"
//! # cutoff_times_natural = 1.3  # cutoff / natural frequency (default 1.3) ...
//! # cutoff_hz = 3.0             # ... or a fixed cutoff [Hz]; never both
//!
//! [accel]               # Eq (1)
//! # prefilter_hz = 5.0  # low-pass on ax, ay before atan2 [Hz]; default off
//! # full_scale = 78.5   # accelerometer full scale [m/s^2]; default unknown
//!
//! [gyro]                # the rate gyro (alg2, alg3 and every kf_*)
//! # full_scale = 8.73   # gyro full scale [rad/s]; default unknown
//!
//! [alg1]                # Eq (20)
//! phi = "raw"           # or "filtered"
//! # cutoff_times_natural = 1.3  # alg1's own cutoff; default [differentiator]'s
//!
//! [alg2]                # Eqs (21)-(22)
//! phi = "raw"
//! theta_dd = "matched"  # or "window" (the paper's Eq 22)
//! window = 0.02         # Eq (22) window [s], with theta_dd = "window"
//! pivot_offset = false  # add the l12 term (MODEL.md section 3)
//!
//! [alg3]                # Eq (30); gains left out: K = a, L = b, M = -b, N = 0
//! # k = 0.0436          # [s]
//! # l = 0.0053          # [s^2]
//! # m = -0.0053         # [s^2]
//! # n = 0.0             # [s]
//! phi = "raw"
//! theta_dd = "matched"
//! window = 0.02
//!
//! [ekf]                 # the ekf and ukf filters, as `pendtilt tune` writes them
//! # encoder_bits = 12   # every key left out: derived from the default sensors
//! # encoder_noise = 0.0, gyro_density = 8.73e-5, gyro_bias = 0.01745,
//! # accel_density = 3.92e-3, accel_vibration = 3.0, process_jerk = 301.0,
//! # process_pendulum = ..., process_bias = 1e-8   (see config::EkfConfig)
//! # adapt = true             # the forcing adapts online (tune writes false)
//! ```
//!
//! The tables are the fields of [`RigConfig`], listed there once: reading, writing and the
//! list of valid names in an error all come from its serde form. Each key sets one field
//! of a core settings struct and is documented there.
//!
//! Every key is optional and has the default shown (the pendulum defaults are
//! [`PhysicalParams::default`]). A `[pendulum]` table is in one of two forms, decided by
//! its keys: the physical form (any of `mass`, `length`, `inertia`, `damping`,
//! `pivot_offset`, `gravity`; the ones left out take their defaults) or the normalised form
//! (any of `a`, `b`, `c`; left out: the defaults normalised). A table that mixes the two
//! forms is an error, because the two could contradict each other. An empty or absent
//! `[pendulum]` table means the default physical pendulum.
//!
//! # Errors
//!
//! Loading never panics. Every error is a [`ConfigError`] whose message starts with
//! `file:line:column: table.key:` (line and column are 1-based, and absent when the
//! value was not in the file, e.g. a defaulted inertia that is too small for the given
//! mass and length) followed by why: a TOML syntax error, an unknown key (with the keys
//! that are allowed), a value of the wrong type, a string that is not one of the
//! choices, or a physically impossible value.
use std::path::Path;

mod checks;
mod doubts;
mod ekf;
mod error;
mod parse;
mod tables;
mod write;

pub use doubts::{
    doubt_accel_full_scale, doubt_gravity, doubt_gyro_full_scale, doubt_length,
    doubt_length_beyond, plain, shown, LengthDoubt, DOUBTFUL_ACCEL_FULL_SCALE_HIGH,
    DOUBTFUL_ACCEL_FULL_SCALE_LOW, DOUBTFUL_GYRO_FULL_SCALE, DOUBTFUL_LENGTH, DOUBTFUL_SPEED_POINT,
    PLAUSIBLE_GRAVITY,
};
pub use ekf::EkfConfig;
pub use error::{ConfigError, ConfigErrorKind, Location};
use parse::{Parser, RawPendulum};

use pendtilt_core::estimators::accel::AccelSettings;
use pendtilt_core::estimators::alg1::Alg1Settings;
use pendtilt_core::estimators::alg2::Alg2Settings;
use pendtilt_core::estimators::alg3::Alg3Settings;
use pendtilt_core::estimators::equations::Alg3Gains;
use pendtilt_core::estimators::front_end::FrontEndSettings;
use pendtilt_core::filters::diff::DiffSettings;
use pendtilt_core::kalman::KalmanSettings;
use pendtilt_core::params::GyroSettings;
use pendtilt_core::{PendulumParams, PhysicalParams};
use serde::{Deserialize, Serialize};

/// The pendulum of a rig file, in the form the file gave it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "RawPendulum", into = "RawPendulum")]
pub enum PendulumConfig {
    /// Physical values (m_p, l_p, I_p, C, l12, g).
    Physical(PhysicalParams<f64>),
    /// Normalised a, b, c (for example as fitted by `pendtilt fit`).
    Normalised(PendulumParams<f64>),
}

impl Default for PendulumConfig {
    fn default() -> Self {
        Self::Physical(PhysicalParams::default())
    }
}

impl PendulumConfig {
    /// The normalised parameters the estimators use.
    pub fn params(&self) -> PendulumParams<f64> {
        match self {
            Self::Physical(p) => p.normalised(),
            Self::Normalised(p) => *p,
        }
    }

    /// The physical values, when the file gave them.
    pub fn physical(&self) -> Option<PhysicalParams<f64>> {
        match self {
            Self::Physical(p) => Some(*p),
            Self::Normalised(_) => None,
        }
    }
}

/// A whole rig file: the pendulum and the estimator settings, one field per table.
///
/// This struct is the one list of the file's tables: its serde form is the file (unknown
/// tables and keys are refused, every key left out takes the core's default). Each table
/// is a core settings struct; the keys that set a field are documented on that field.
/// Build it with [`RigConfig::load`], [`RigConfig::from_toml_str`],
/// [`RigConfig::from_physical`] or [`RigConfig::from_params`]; write it with
/// [`RigConfig::to_toml_string`] or [`RigConfig::save`] (the text loads back to an equal
/// value). The public fields may be changed freely; [`RigConfig::validate`] checks them.
///
/// The settings one table shares with others are not keys of it, and are not read from
/// it: [`KalmanSettings::gyro`] and the `params`, `differentiator` and `gyro` of an
/// algorithm's `front_end` come from `[gyro]`, `[pendulum]` and `[differentiator]`
/// ([`RigConfig::kalman_settings`], [`RigConfig::alg2_settings`], ...).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RigConfig {
    /// `[pendulum]`: physical values or the normalised a, b, c (never both).
    pub pendulum: PendulumConfig,
    /// `[kalman]`: the angle+bias filter of every `kf_*` output.
    pub kalman: KalmanSettings<f64>,
    /// `[differentiator]`: phi' and phi'' for alg1, alg2, alg3; the cutoff is the key
    /// `cutoff_hz` ([`Cutoff::Hz`]) or `cutoff_times_natural` ([`Cutoff::TimesNatural`]).
    ///
    /// [`Cutoff::Hz`]: pendtilt_core::filters::diff::Cutoff::Hz
    /// [`Cutoff::TimesNatural`]: pendtilt_core::filters::diff::Cutoff::TimesNatural
    #[serde(with = "tables::differentiator")]
    pub differentiator: DiffSettings<f64>,
    /// `[accel]`: Eq (1).
    pub accel: AccelSettings<f64>,
    /// `[gyro]`: the rate gyro, for alg2, alg3 and every `kf_*`.
    pub gyro: GyroSettings<f64>,
    /// `[alg1]`, Eq (20): the key `phi` ([`FrontEndSettings::phi`]) and Algorithm 1's own
    /// cutoff `cutoff_times_natural` ([`Alg1Table`]).
    #[serde(with = "tables::alg1")]
    pub alg1: Alg1Table,
    /// `[alg2]`, Eqs (21)-(22): `phi`, `theta_dd = "matched" | "window"` with `window`
    /// \[s\] ([`FrontEndSettings::theta_dd`]), `pivot_offset`, `delay_compensation`.
    #[serde(with = "tables::alg2")]
    pub alg2: Alg2Settings<f64>,
    /// `[alg3]`, Eq (30): the gains `k`, `l`, `m`, `n` (those left out of a file are
    /// K = a, L = b, M = -b, N = 0 of its `[pendulum]`), `phi`, `theta_dd`, `window`.
    #[serde(with = "tables::alg3")]
    pub alg3: Alg3Settings<f64>,
    /// `[ekf]`: the `ekf` and `ukf` filters' noise figures ([`EkfConfig`]); written empty
    /// when no key is set (every figure then derived from the default sensors).
    pub ekf: EkfConfig,
}

/// The `[alg1]` table: Algorithm 1's settings and, if it has one, its own differentiator
/// cutoff.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Alg1Table {
    /// Eq (20): its front end's `phi` (the rest of the front end from the shared tables).
    pub settings: Alg1Settings<f64>,
    /// Algorithm 1's differentiator cutoff as a multiple of the natural frequency, in
    /// place of `[differentiator]`'s (the response stays that table's). Default none: the
    /// shared cutoff. `pendtilt tune` sets it: measured on the zoo of unseen rigs, Algorithm 1
    /// (phi and phi'' only) and Algorithm 2 (with the gyro) want cutoffs far apart on a
    /// slow pendulum (ride 12, f_n 0.5 Hz: alg1 best at 1.34 f_n, alg2 at 10 f_n), and
    /// one cutoff for both, chosen for both together, was worse than either's default.
    pub cutoff_times_natural: Option<f64>,
}

/// Name used in errors for configurations built in memory rather than read from a file.
pub const IN_MEMORY: &str = "<rig parameters>";

/// The tables of a 3-D rig file (MODEL.md 7.6; read by [`crate::bank::spatial::rig`]): named
/// here so that a planar file holding one is told it is the wrong kind of file.
pub const TABLES_3D: [&str; 4] = ["pendulum3d", "mounting", "ekf3d", "gyro"];

impl RigConfig {
    /// Reads and checks a rig file. Errors name `path`.
    pub fn load(path: impl AsRef<Path>) -> Result<Self, ConfigError> {
        let path = path.as_ref();
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| {
            ConfigError::new(
                Location {
                    file: file.clone(),
                    line: None,
                    column: None,
                    key: None,
                },
                ConfigErrorKind::Io(e),
            )
        })?;
        Self::from_toml_str(&text, &file)
    }

    /// Parses and checks rig TOML; `origin` names the source in errors (a file name).
    pub fn from_toml_str(text: &str, origin: &str) -> Result<Self, ConfigError> {
        Parser::new(text, origin)?.parse()
    }

    /// Default settings for `pendulum`, unchecked (Algorithm 3's gains its Eq (21)
    /// equivalent).
    pub fn with_pendulum(pendulum: PendulumConfig) -> Self {
        let mut cfg = Self {
            pendulum,
            ..Self::default()
        };
        cfg.alg3.gains = Alg3Gains::from_params(&cfg.params());
        cfg
    }

    /// A rig with these physical pendulum values and default estimator settings.
    /// Errors if a value is impossible (see [`RigConfig::validate`]).
    pub fn from_physical(p: PhysicalParams<f64>) -> Result<Self, ConfigError> {
        let cfg = Self::with_pendulum(PendulumConfig::Physical(p));
        cfg.validate()?;
        Ok(cfg)
    }

    /// A rig with these normalised a, b, c (a fit result) and default estimator settings.
    /// Errors if a value is impossible (a < 0, b <= 0, or not finite).
    pub fn from_params(p: PendulumParams<f64>) -> Result<Self, ConfigError> {
        let cfg = Self::with_pendulum(PendulumConfig::Normalised(p));
        cfg.validate()?;
        Ok(cfg)
    }

    /// The normalised parameters a, b, c the estimators use.
    pub fn params(&self) -> PendulumParams<f64> {
        self.pendulum.params()
    }

    /// The physical pendulum, when the file gave the physical form.
    pub fn physical(&self) -> Option<PhysicalParams<f64>> {
        self.pendulum.physical()
    }

    /// Gravity \[m/s^2\]: the physical pendulum's, else standard gravity (the normalised
    /// form has none).
    pub fn gravity(&self) -> f64 {
        self.physical()
            .map_or(pendtilt_core::params::STANDARD_GRAVITY, |p| p.gravity)
    }

    /// Algorithm 3's gains (`[alg3]`).
    pub fn alg3_gains(&self) -> Alg3Gains<f64> {
        self.alg3.gains
    }

    /// True when Algorithm 3's gains are those under which Eq (30) is Eq (21) for this
    /// pendulum (K = a, L = b, M = -b, N = 0), as when `[alg3]` gives none.
    pub fn alg3_gains_are_eq21(&self) -> bool {
        self.alg3.gains == Alg3Gains::from_params(&self.params())
    }

    /// Settings of the Kalman filters (`kf_*`), from `[kalman]` and `[gyro]`.
    pub fn kalman_settings(&self) -> KalmanSettings<f64> {
        KalmanSettings {
            gyro: self.gyro,
            ..self.kalman
        }
    }

    /// The gyro's settings, from `[gyro]`.
    pub fn gyro_settings(&self) -> GyroSettings<f64> {
        self.gyro
    }

    /// Settings of the phi differentiator, from `[differentiator]`.
    pub fn diff_settings(&self) -> DiffSettings<f64> {
        self.differentiator
    }

    /// Settings of `accel`, from `[accel]`.
    pub fn accel_settings(&self) -> AccelSettings<f64> {
        self.accel
    }

    /// An algorithm's front end: `phi` and `theta_dd` from its table, the rest from
    /// `[pendulum]`, `[differentiator]` and `[gyro]`.
    fn front_end(&self, table: &FrontEndSettings<f64>) -> FrontEndSettings<f64> {
        FrontEndSettings {
            params: self.params(),
            differentiator: self.differentiator,
            gyro: self.gyro,
            ..*table
        }
    }

    /// Settings of `alg1`, from `[pendulum]`, `[differentiator]`, `[gyro]` and `[alg1]`
    /// (its own cutoff, if it has one).
    pub fn alg1_settings(&self) -> Alg1Settings<f64> {
        let mut front_end = self.front_end(&self.alg1.settings.front_end);
        if let Some(x) = self.alg1.cutoff_times_natural {
            front_end.differentiator.cutoff = pendtilt_core::filters::diff::Cutoff::TimesNatural(x);
        }
        Alg1Settings { front_end }
    }

    /// Settings of `alg2`, from `[pendulum]`, `[differentiator]`, `[gyro]` and `[alg2]`.
    pub fn alg2_settings(&self) -> Alg2Settings<f64> {
        Alg2Settings {
            front_end: self.front_end(&self.alg2.front_end),
            ..self.alg2
        }
    }

    /// Settings of `alg3`, from `[pendulum]`, `[differentiator]`, `[gyro]` and `[alg3]`.
    pub fn alg3_settings(&self) -> Alg3Settings<f64> {
        Alg3Settings {
            front_end: self.front_end(&self.alg3.front_end),
            ..self.alg3
        }
    }

    /// Checks every value as [`RigConfig::load`] does; errors name [`IN_MEMORY`] as the file.
    pub fn validate(&self) -> Result<(), ConfigError> {
        match checks::issues(self).into_iter().next() {
            None => Ok(()),
            Some((key, value, why)) => Err(ConfigError::new(
                Location {
                    file: IN_MEMORY.to_string(),
                    line: None,
                    column: None,
                    key: Some(key),
                },
                ConfigErrorKind::Impossible { value, why },
            )),
        }
    }
}
