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
use std::fmt;
use std::path::Path;

mod checks;
mod ekf;
mod tables;

pub use ekf::EkfConfig;

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
use toml::de::{DeTable, DeValue};
use toml::Spanned;

/// Where a configuration error is: the file, the position in it, and the dotted key.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Location {
    /// The file name (or the origin name given to [`RigConfig::from_toml_str`]).
    pub file: String,
    /// 1-based line of the offending key or value, when it was in the file.
    pub line: Option<usize>,
    /// 1-based column (in characters) of the offending key or value, when it was in the file.
    pub column: Option<usize>,
    /// Dotted path of the key, e.g. `pendulum.mass`; `None` for file-level errors.
    pub key: Option<String>,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.file)?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
            if let Some(column) = self.column {
                write!(f, ":{column}")?;
            }
        }
        if let Some(key) = &self.key {
            write!(f, ": {key}")?;
        }
        Ok(())
    }
}

/// Why a rig file was rejected.
#[derive(Debug, thiserror::Error)]
pub enum ConfigErrorKind {
    /// The file could not be read.
    #[error("cannot read the file: {0}")]
    Io(#[from] std::io::Error),
    /// The text is not valid TOML.
    #[error("TOML syntax error: {0}")]
    Syntax(String),
    /// A key (or table) that the rig file does not have.
    #[error("unknown key; allowed here: {allowed}{hint}")]
    UnknownKey {
        /// The keys allowed in this table, comma-separated.
        allowed: String,
        /// What the key says about the file (`; a 3-D rig file's table ...`), or empty.
        hint: String,
    },
    /// A string that is not one of the allowed choices (e.g. `response = "chebyshev"`).
    #[error("not one of the choices: {0}")]
    BadChoice(String),
    /// A value of the wrong TOML type (e.g. a string where a number is expected).
    #[error("wrong type: {0}")]
    WrongType(String),
    /// The `[pendulum]` table mixes physical and normalised keys.
    #[error(
        "mixes the physical form ({physical}) with the normalised form ({normalised}); \
         give either mass/length/inertia/damping/pivot_offset/gravity or a/b/c"
    )]
    MixedPendulumForms {
        /// The physical keys present.
        physical: String,
        /// The normalised keys present.
        normalised: String,
    },
    /// A value that no real rig can have.
    #[error("impossible value {}: {why}", shown(*.value))]
    Impossible {
        /// The value as given (or defaulted).
        value: f64,
        /// The rule it breaks.
        why: String,
    },
}

/// An error in a rig file: where it is ([`Location`]) and why ([`ConfigErrorKind`]).
///
/// Displays as `rig.toml:3:8: pendulum.mass: impossible value -1: mass must be > 0 [kg]`.
#[derive(Debug, thiserror::Error)]
#[error("{location}: {kind}")]
pub struct ConfigError {
    /// File, line, column and key.
    pub location: Location,
    /// What is wrong (boxed to keep `Result<_, ConfigError>` small).
    pub kind: Box<ConfigErrorKind>,
}

impl ConfigError {
    fn new(location: Location, kind: ConfigErrorKind) -> Self {
        Self {
            location,
            kind: Box::new(kind),
        }
    }
}

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

/// The tables of a 3-D rig file (MODEL.md 7.6; read by [`crate::bank3d::rig`]): named
/// here so that a planar file holding one is told it is the wrong kind of file.
pub const TABLES_3D: [&str; 4] = ["pendulum3d", "mounting", "ekf3d", "gyro"];

/// A pendulum length or pivot offset beyond this \[m\] is doubted ([`RigConfig::doubts`]).
pub const DOUBTFUL_LENGTH: f64 = 2.0;

/// g \[m/s^2\] for telling l12 from a normalised `c` (only for [`RigConfig::doubts`]).
const DEFAULT_GRAVITY: f64 = 9.80665;

/// A length that is possible but far more likely millimetres read as metres: one of the
/// rig's lengths beyond [`DOUBTFUL_LENGTH`], wherever it was given (a rig or scenario file,
/// a command-line option; planar or 3-D). Made by [`doubt_length`], the one check.
#[derive(Debug, Clone, PartialEq)]
pub struct LengthDoubt {
    /// The key that holds it (`pendulum.pivot_offset`, `rig.pendulum3d.length`).
    pub key: String,
    /// What it is, with its value (`a pivot offset l12 of 50 m`).
    pub what: String,
    /// The value written in metres, if it was meant in millimetres (`0.05`).
    pub fix: String,
    /// Why so long a length is doubted: the limit \[m\] and what is no longer.
    pub beyond: (f64, &'static str),
}

/// The one check of a length \[m\]: a doubt when `|metres|` is beyond
/// [`DOUBTFUL_LENGTH`]. `key`, `what` and `fix` as in [`LengthDoubt`].
pub fn doubt_length(
    key: &str,
    what: String,
    metres: f64,
    fix: impl std::fmt::Display,
) -> Option<LengthDoubt> {
    const WHY: &str = "larger than any vehicle a pendulum sensor rides on but a ship";
    doubt_length_beyond(key, what, metres, (DOUBTFUL_LENGTH, WHY), fix)
}

/// [`doubt_length`] with its own limit \[m\] and reason, for a length a ship may take
/// beyond [`DOUBTFUL_LENGTH`] (3-D `speed_at`: [`DOUBTFUL_SPEED_POINT`]).
pub fn doubt_length_beyond(
    key: &str,
    what: String,
    metres: f64,
    beyond: (f64, &'static str),
    fix: impl std::fmt::Display,
) -> Option<LengthDoubt> {
    (metres.abs() > beyond.0).then(|| LengthDoubt {
        key: key.into(),
        what,
        fix: fix.to_string(),
        beyond,
    })
}

/// A point O (`speed_at`, whose forward speed the log gives) farther than this from the
/// pendulum \[m\] is doubted: half the length of the largest ships (400 m). ship3d's is
/// 9.4 m; a car's written in millimetres (say 1200 mm) reads as 1200 m.
pub const DOUBTFUL_SPEED_POINT: f64 = 200.0;

/// `x` to six significant digits, written plainly (0.0051, not 0.0050999999999999995).
pub fn plain(x: f64) -> f64 {
    format!("{x:.5e}").parse().unwrap_or(x)
}

/// `x` as a refusal quotes it: plainly (`0.5`, `-3`, `250`) between 1e-4 and 1e15, else
/// in exponent form (`1e300`, `2.5e-9`). `{}` writes an f64 in full: `1e300` as 301 digits.
pub fn shown(x: f64) -> String {
    let a = x.abs();
    if a == 0.0 || !a.is_finite() || (1e-4..1e15).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// A gyro full scale above this \[rad/s\] is doubted ([`doubt_gyro_full_scale`]):
/// 4000 deg/s, the largest range of MEMS gyros (ICM-42686-P, LSM6DSV); the common ones
/// stop at 2000 deg/s (34.9 rad/s). Every range written in deg/s (125, 250, 500, 1000,
/// 2000, 4000) is above it when read as rad/s, so a range in deg/s is always caught.
pub const DOUBTFUL_GYRO_FULL_SCALE: f64 = 4000.0 * std::f64::consts::PI / 180.0;

/// An accelerometer full scale below this \[m/s^2\] is doubted
/// ([`doubt_accel_full_scale`]): 2 g, the smallest range of MEMS accelerometers (a
/// smaller one clips gravity itself on a tilted or shaken body). The ranges written in g
/// (2, 4, 8, 16) are all below it.
pub const DOUBTFUL_ACCEL_FULL_SCALE_LOW: f64 = 2.0 * DEFAULT_GRAVITY;

/// An accelerometer full scale above this \[m/s^2\] is doubted
/// ([`doubt_accel_full_scale`]): 200 g, the largest range of IMU-class MEMS
/// accelerometers (ADXL375; the 400 g parts are crash recorders, not tilt sensors). The
/// ranges written in mg (2000 to 16000) are all above it.
pub const DOUBTFUL_ACCEL_FULL_SCALE_HIGH: f64 = 200.0 * DEFAULT_GRAVITY;

/// The one check of a gyro full scale \[rad/s\] under `key` (`gyro.full_scale`): above
/// [`DOUBTFUL_GYRO_FULL_SCALE`] it is far more likely deg/s read as rad/s (500 for
/// 500 deg/s: the clip finder and the plausibility bound then never act). The sentence
/// names the key, the value and the fix (`write gyro.full_scale = 8.73`); `source` the
/// file it is written in (`rig file`, `scenario file`).
pub fn doubt_gyro_full_scale(key: &str, full_scale: f64, source: &str) -> Option<String> {
    (full_scale > DOUBTFUL_GYRO_FULL_SCALE).then(|| {
        format!(
            "{key}: {full_scale} rad/s is above {:.1} rad/s (4000 deg/s), more than any MEMS \
             gyro has: if it was written in deg/s, write {key} = {} (the {source} is in \
             rad/s)",
            DOUBTFUL_GYRO_FULL_SCALE,
            plain(full_scale.to_radians())
        )
    })
}

/// The one check of an accelerometer full scale \[m/s^2\] under `key`
/// (`accel.full_scale`): below [`DOUBTFUL_ACCEL_FULL_SCALE_LOW`] it is far more likely
/// written in g (16 for 16 g), above [`DOUBTFUL_ACCEL_FULL_SCALE_HIGH`] in mg. The
/// sentence names the key, the value and the fix in m/s^2; `source` the file it is
/// written in.
pub fn doubt_accel_full_scale(key: &str, full_scale: f64, source: &str) -> Option<String> {
    if full_scale > 0.0 && full_scale < DOUBTFUL_ACCEL_FULL_SCALE_LOW {
        Some(format!(
            "{key}: {full_scale} m/s^2 is below {:.1} m/s^2 (2 g), less than any MEMS \
             accelerometer has: written in g? {full_scale} g is {:.1} m/s^2: write {key} = {} \
             (the {source} is in m/s^2)",
            DOUBTFUL_ACCEL_FULL_SCALE_LOW,
            full_scale * DEFAULT_GRAVITY,
            plain(full_scale * DEFAULT_GRAVITY)
        ))
    } else if full_scale > DOUBTFUL_ACCEL_FULL_SCALE_HIGH {
        let g = full_scale / 1000.0;
        Some(format!(
            "{key}: {full_scale} m/s^2 is above {:.0} m/s^2 (200 g), more than any IMU \
             accelerometer has: written in mg? {full_scale} mg is {:.1} m/s^2: write {key} = \
             {} (the {source} is in m/s^2)",
            DOUBTFUL_ACCEL_FULL_SCALE_HIGH,
            g * DEFAULT_GRAVITY,
            plain(g * DEFAULT_GRAVITY)
        ))
    } else {
        None
    }
}

/// Gravity \[m/s^2\] outside this band is doubted ([`doubt_gravity`]): the Earth's
/// surface gravity is 9.78 to 9.83 m/s^2 (equator to poles), a little less on a mountain.
pub const PLAUSIBLE_GRAVITY: [f64; 2] = [9.7, 9.9];

/// The one check of a rig's gravity \[m/s^2\] under `key` (`pendulum.gravity`): outside
/// [`PLAUSIBLE_GRAVITY`] it is far more likely another unit (1 for 1 g left alg2 7.8
/// deg RMS off instead of 0.86 on a scooter ride, without a word). The sentence names
/// the key, the value and the fix.
pub fn doubt_gravity(key: &str, g: f64) -> Option<String> {
    let [lo, hi] = PLAUSIBLE_GRAVITY;
    if (lo..=hi).contains(&g) {
        return None;
    }
    let fix = if (0.97..=1.01).contains(&g) {
        format!("written in g? write {key} = {DEFAULT_GRAVITY}")
    } else if (970.0..=990.0).contains(&g) {
        format!("written in cm/s^2? write {key} = {}", plain(g / 100.0))
    } else if (31.8..=32.3).contains(&g) {
        format!("written in ft/s^2? write {key} = {}", plain(g * 0.3048))
    } else {
        format!("write {key} = {DEFAULT_GRAVITY} (or the local g)")
    };
    Some(format!(
        "{key}: {g} m/s^2 is not the Earth's gravity (9.78 to 9.83 m/s^2), and the estimators \
         take the pendulum's stiffness and the accelerometer's gravity from it: {fix} (the \
         file is in m/s^2)"
    ))
}

impl LengthDoubt {
    /// Why it is doubted.
    fn why(&self) -> String {
        format!(
            "{} is beyond {} m, {}",
            self.what, self.beyond.0, self.beyond.1
        )
    }

    /// The sentence for a file of kind `kind` (`rig file`, `scenario file`): the key, the
    /// value, and `write KEY = FIX (the KIND is in metres)`.
    pub fn in_file(&self, kind: &str) -> String {
        format!(
            "{}: {}: if it was written in millimetres, write {} = {} (the {kind} is in metres)",
            self.key,
            self.why(),
            self.key,
            self.fix
        )
    }

    /// The sentence for a command-line option: `given` as typed (`--pivot-offset 50`),
    /// and the fix `fixed` would give (`--pivot-offset 0.05`).
    pub fn on_command_line(&self, given: &str, fixed: &str) -> String {
        format!(
            "{given}: {}: if it was meant in millimetres, give {fixed} (the options are in \
             metres)",
            self.why()
        )
    }
}

impl RigConfig {
    /// The bounds of plausible readings the log reader applies: the sensors' full scales
    /// (`[gyro]`, `[accel]`), or the default physical bounds where they are unset.
    pub fn limits(&self) -> crate::io::SensorLimits {
        crate::io::SensorLimits {
            gyro_full_scale: self.gyro.full_scale,
            accel_full_scale: self.accel.full_scale,
        }
    }

    /// Values that are possible but far more likely a unit mistake, each as one sentence
    /// naming the key, the value and the fix: a pendulum length or pivot offset l12
    /// beyond [`DOUBTFUL_LENGTH`] (a value in millimetres read as metres: l12 = 50 for
    /// 50 mm left alg2_offset 87 deg RMS off, the EKF 2.3 and the UKF 5.4 deg instead of
    /// 0.5, on a scooter ride, without a word). The commands print them as warnings.
    /// A full scale in other units is doubted too: `[gyro]` above
    /// [`DOUBTFUL_GYRO_FULL_SCALE`] (deg/s read as rad/s: `full_scale = 500` silently
    /// switched off the clip finder's "below the full scale" check and the plausibility
    /// bound), `[accel]` outside 2 g to 200 g (written in g or mg); a gravity off the
    /// Earth's ([`doubt_gravity`]).
    pub fn doubts(&self) -> Vec<String> {
        let mut d: Vec<String> = self
            .length_doubts()
            .iter()
            .map(|d| d.in_file("rig file"))
            .collect();
        if let PendulumConfig::Physical(p) = &self.pendulum {
            d.extend(doubt_gravity("pendulum.gravity", p.gravity));
        }
        d.extend(
            self.gyro
                .full_scale
                .and_then(|f| doubt_gyro_full_scale("gyro.full_scale", f, "rig file")),
        );
        d.extend(
            self.accel
                .full_scale
                .and_then(|f| doubt_accel_full_scale("accel.full_scale", f, "rig file")),
        );
        d
    }

    /// The lengths [`RigConfig::doubts`] words for a rig file, for callers that name
    /// another source (a command-line option, a scenario file).
    pub fn length_doubts(&self) -> Vec<LengthDoubt> {
        match &self.pendulum {
            PendulumConfig::Physical(p) => [
                ("pendulum.length", "a pendulum length l_p", p.length),
                (
                    "pendulum.pivot_offset",
                    "a pivot offset l12",
                    p.pivot_offset,
                ),
            ]
            .into_iter()
            .filter_map(|(key, what, v)| {
                doubt_length(key, format!("{what} of {v} m"), v, plain(v / 1000.0))
            })
            .collect(),
            PendulumConfig::Normalised(p) => {
                let l12 = p.c * DEFAULT_GRAVITY;
                doubt_length(
                    "pendulum.c",
                    format!(
                        "c = l12 / g = {} s^2, a pivot offset l12 of {l12:.3} m,",
                        p.c
                    ),
                    l12,
                    plain(p.c / 1000.0),
                )
                .into_iter()
                .collect()
            }
        }
    }

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

    /// The rig as TOML text, every value written out with a comment giving its unit.
    /// [`RigConfig::from_toml_str`] reads it back to an equal value.
    pub fn to_toml_string(&self) -> String {
        // alg3 with its pendulum, so that gains that are its Eq (21) equivalent are left
        // out, as in a file that gives none.
        let file = Self {
            alg3: self.alg3_settings(),
            ..self.clone()
        };
        // Serialising plain structs of finite floats cannot fail; fall back to an empty
        // body rather than panic if it ever did.
        let body = toml::to_string(&file).unwrap_or_default();
        let mut out = String::from(
            "# pendtilt rig file (MODEL.md section 5). SI units; every key is optional.\n",
        );
        let mut table = String::new();
        for line in body.lines() {
            let trimmed = line.trim();
            if let Some(name) = trimmed.strip_prefix('[').and_then(|s| s.strip_suffix(']')) {
                table = name.to_string();
                out.push_str(line);
                out.push('\n');
                if table == "ekf" && self.ekf.is_empty() {
                    out.push_str(
                        "# no key: every figure derived from the default sensors; \
                         `pendtilt tune` writes them\n",
                    );
                }
                continue;
            }
            let key = trimmed.split('=').next().unwrap_or("").trim();
            match key_comment(&table, key) {
                Some(comment) if !key.is_empty() => {
                    out.push_str(&format!("{line:<28} # {comment}\n"));
                }
                _ => {
                    out.push_str(line);
                    out.push('\n');
                }
            }
        }
        out
    }

    /// Writes [`RigConfig::to_toml_string`] to `path`; an error message names the path.
    pub fn save(&self, path: impl AsRef<Path>) -> std::io::Result<()> {
        let path = path.as_ref();
        std::fs::write(path, self.to_toml_string()).map_err(|e| {
            std::io::Error::new(e.kind(), format!("cannot write {}: {e}", path.display()))
        })
    }
}

/// The unit and meaning of each key, for the comments of [`RigConfig::to_toml_string`]
/// (test `every_written_key_has_a_comment`).
fn key_comment(table: &str, key: &str) -> Option<&'static str> {
    Some(match (table, key) {
        ("pendulum", "mass") => "m_p [kg]",
        ("pendulum", "length") => "l_p, pivot to centre of gravity [m]",
        ("pendulum", "inertia") => "I_p about the pivot [kg m^2]",
        ("pendulum", "damping") => "C, viscous friction [N m s/rad]",
        ("pendulum", "pivot_offset") => "l12, body axis to pendulum pivot [m]",
        ("pendulum", "gravity") => "g [m/s^2]",
        ("pendulum", "a") => "C / (m_p g l_p) [s]",
        ("pendulum", "b") => "I_p / (m_p g l_p) [s^2]",
        ("pendulum", "c") => "l12 / g [s^2]",
        ("kalman", "q_angle") => "angle noise density [rad^2/s], Q = q dt",
        ("kalman", "q_bias") => "bias noise density [(rad/s)^2/s], Q = q dt",
        ("kalman", "r_accel") => "accelerometer angle variance [rad^2]",
        ("kalman", "r_pendulum") => "pendulum angle variance [rad^2]",
        ("kalman", "r_accel_fused") => "kf_fused's accelerometer angle variance [rad^2]",
        ("kalman", "p0_angle") => "initial angle variance [rad^2]",
        ("kalman", "p0_bias") => "initial bias variance [(rad/s)^2]",
        ("differentiator", "response") => "butterworth | bessel | critically_damped",
        ("differentiator", "cutoff_hz") => "fixed cutoff [Hz]",
        ("differentiator", "cutoff_times_natural") => "cutoff / natural frequency",
        ("accel", "prefilter_hz") => "low-pass on ax, ay before atan2 [Hz]",
        ("accel", "full_scale") => "accelerometer full scale [m/s^2]",
        ("gyro", "full_scale") => "gyro full scale [rad/s]",
        ("alg1" | "alg2" | "alg3", "phi") => "raw | filtered",
        ("alg1", "cutoff_times_natural") => "alg1's own cutoff / natural frequency",
        ("alg2" | "alg3", "theta_dd") => "matched | window (Eq 22)",
        ("alg2" | "alg3", "window") => "Eq (22) window [s]",
        ("alg2", "pivot_offset") => "add the l12 term to alg2",
        ("alg2", "delay_compensation") => "remove the differentiator delay with the gyro",
        ("alg3", "k") => "K, times phi' [s]",
        ("alg3", "l") => "L, times phi'' [s^2]",
        ("alg3", "m") => "M, times G_d [s^2]",
        ("alg3", "n") => "N, times G_k [s]",
        ("ekf", "encoder_bits") => "encoder resolution [bits per turn], 0: not quantised",
        ("ekf", "encoder_noise") => "encoder noise, standard deviation [rad]",
        ("ekf", "gyro_density") => "gyro white-noise density [rad/s/sqrt(Hz)]",
        ("ekf", "gyro_bias") => "initial gyro bias spread [rad/s]",
        ("ekf", "accel_density") => "accelerometer noise density [m/s^2/sqrt(Hz)]",
        ("ekf", "accel_vibration") => "vibration RMS the accelerometer reads [m/s^2]",
        ("ekf", "process_jerk") => "tilt jerk process noise density [rad^2/s^5]",
        ("ekf", "process_pendulum") => "pendulum forcing process noise density [1/s^3]",
        ("ekf", "process_bias") => "gyro bias walk process noise density [(rad/s)^2/s]",
        ("ekf", "adapt") => "adapt the forcing and encoder noise to the log (docs/adaptation.md)",
        _ => return None,
    })
}

/// The `[pendulum]` table as written: every key optional, the form decided by the keys.
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
struct RawPendulum {
    #[serde(skip_serializing_if = "Option::is_none")]
    mass: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    length: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    inertia: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    damping: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pivot_offset: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    gravity: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    a: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    b: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    c: Option<f64>,
}

impl RawPendulum {
    /// The physical keys given and the normalised keys given.
    fn forms(&self) -> (Vec<&'static str>, Vec<&'static str>) {
        let present = |list: &[(&'static str, Option<f64>)]| -> Vec<&'static str> {
            list.iter()
                .filter(|(_, v)| v.is_some())
                .map(|(k, _)| *k)
                .collect()
        };
        let physical = present(&[
            ("mass", self.mass),
            ("length", self.length),
            ("inertia", self.inertia),
            ("damping", self.damping),
            ("pivot_offset", self.pivot_offset),
            ("gravity", self.gravity),
        ]);
        let normalised = present(&[("a", self.a), ("b", self.b), ("c", self.c)]);
        (physical, normalised)
    }

    /// The error of a table that mixes the two forms, if it does.
    fn mixed(&self) -> Option<ConfigErrorKind> {
        let (physical, normalised) = self.forms();
        (!physical.is_empty() && !normalised.is_empty()).then(|| {
            ConfigErrorKind::MixedPendulumForms {
                physical: physical.join(", "),
                normalised: normalised.join(", "),
            }
        })
    }
}

impl TryFrom<RawPendulum> for PendulumConfig {
    type Error = ConfigErrorKind;

    fn try_from(raw: RawPendulum) -> Result<Self, ConfigErrorKind> {
        if let Some(mixed) = raw.mixed() {
            return Err(mixed);
        }
        Ok(if raw.a.or(raw.b).or(raw.c).is_none() {
            let d = PhysicalParams::<f64>::default();
            PendulumConfig::Physical(PhysicalParams {
                mass: raw.mass.unwrap_or(d.mass),
                length: raw.length.unwrap_or(d.length),
                inertia: raw.inertia.unwrap_or(d.inertia),
                damping: raw.damping.unwrap_or(d.damping),
                pivot_offset: raw.pivot_offset.unwrap_or(d.pivot_offset),
                gravity: raw.gravity.unwrap_or(d.gravity),
            })
        } else {
            let d = PendulumParams::<f64>::default();
            PendulumConfig::Normalised(PendulumParams {
                a: raw.a.unwrap_or(d.a),
                b: raw.b.unwrap_or(d.b),
                c: raw.c.unwrap_or(d.c),
            })
        })
    }
}

impl From<PendulumConfig> for RawPendulum {
    fn from(p: PendulumConfig) -> Self {
        match p {
            PendulumConfig::Physical(p) => Self {
                mass: Some(p.mass),
                length: Some(p.length),
                inertia: Some(p.inertia),
                damping: Some(p.damping),
                pivot_offset: Some(p.pivot_offset),
                gravity: Some(p.gravity),
                ..Self::default()
            },
            PendulumConfig::Normalised(p) => Self {
                a: Some(p.a),
                b: Some(p.b),
                c: Some(p.c),
                ..Self::default()
            },
        }
    }
}

/// 1-based (line, column in characters) of a byte offset.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let offset = offset.min(text.len());
    let mut start = offset;
    while !text.is_char_boundary(start) {
        start -= 1;
    }
    let before = &text[..start];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let column = before[line_start..].chars().count() + 1;
    (line, column)
}

/// One parse of a rig text: the values (`toml::Table`) and their positions (`DeTable`).
struct Parser<'a> {
    text: &'a str,
    origin: &'a str,
    spans: Spanned<DeTable<'a>>,
    values: toml::Table,
}

type Span = std::ops::Range<usize>;

impl<'a> Parser<'a> {
    fn new(text: &'a str, origin: &'a str) -> Result<Self, ConfigError> {
        let syntax = |e: toml::de::Error| {
            let (line, column) = match e.span() {
                Some(span) => {
                    let (l, c) = line_column(text, span.start);
                    (Some(l), Some(c))
                }
                None => (None, None),
            };
            ConfigError::new(
                Location {
                    file: origin.to_string(),
                    line,
                    column,
                    key: None,
                },
                ConfigErrorKind::Syntax(e.message().trim().to_string()),
            )
        };
        let spans = DeTable::parse(text).map_err(syntax)?;
        let values: toml::Table = text.parse().map_err(syntax)?;
        Ok(Self {
            text,
            origin,
            spans,
            values,
        })
    }

    fn at(&self, span: Option<Span>, key: Option<String>) -> Location {
        let (line, column) = match span {
            Some(s) => {
                let (l, c) = line_column(self.text, s.start);
                (Some(l), Some(c))
            }
            None => (None, None),
        };
        Location {
            file: self.origin.to_string(),
            line,
            column,
            key,
        }
    }

    /// The (key span, value span) of each key of `table` (or of the top level when
    /// `table` is `None`), in file order.
    fn entries(&self, table: Option<&str>) -> Vec<(String, Span, Span)> {
        let top = self.spans.get_ref();
        let map = match table {
            None => Some(top),
            Some(name) => top
                .iter()
                .find(|(k, _)| k.get_ref().as_ref() == name)
                .and_then(|(_, v)| match v.get_ref() {
                    DeValue::Table(t) => Some(t),
                    _ => None,
                }),
        };
        let mut out: Vec<_> = map
            .into_iter()
            .flat_map(|m| m.iter())
            .map(|(k, v)| (k.get_ref().to_string(), k.span(), v.span()))
            .collect();
        out.sort_by_key(|(_, k, _)| k.start);
        out
    }

    fn key_span(&self, table: &str, key: &str) -> Option<Span> {
        let entries = self.entries(Some(table));
        entries.into_iter().find(|e| e.0 == key).map(|e| e.1)
    }

    fn value_span(&self, table: &str, key: &str) -> Option<Span> {
        let entries = self.entries(Some(table));
        entries.into_iter().find(|e| e.0 == key).map(|e| e.2)
    }

    /// The file's values for `name` alone read as a whole rig file (the serde form of
    /// [`RigConfig`]).
    fn read_alone(name: &str, table: toml::Table) -> Result<RigConfig, toml::de::Error> {
        let mut file = toml::Table::new();
        file.insert(name.to_string(), toml::Value::Table(table));
        RigConfig::deserialize(toml::Value::Table(file))
    }

    /// Checks one top-level entry: a known table name, a table, and then its keys one more
    /// at a time in file order, so that an error names the key that made the table
    /// unreadable and its position.
    fn check_table(
        &self,
        name: &str,
        name_span: Span,
        value_span: Span,
    ) -> Result<(), ConfigError> {
        if let Err(e) = Self::read_alone(name, toml::Table::new()) {
            // The only error an empty table can give: a name that is not a table's.
            // A 3-D rig's table: the file, not the key, is the mistake.
            let hint = if TABLES_3D.contains(&name) {
                format!(
                    "; [{name}] is a table of a 3-D rig file (MODEL.md 7.6), and a planar rig is \
                     read here: give a planar rig file ([pendulum], MODEL.md 5), or \
                     check that the log is the one meant"
                )
            } else {
                String::new()
            };
            return Err(ConfigError::new(
                self.at(Some(name_span), Some(name.to_string())),
                ConfigErrorKind::UnknownKey {
                    allowed: allowed(e.message(), true),
                    hint,
                },
            ));
        }
        let Some(value) = self.values.get(name) else {
            return Ok(());
        };
        let toml::Value::Table(table) = value else {
            return Err(ConfigError::new(
                self.at(Some(value_span), Some(name.to_string())),
                ConfigErrorKind::WrongType(format!(
                    "`{name}` must be a table ([{name}]), found a {}",
                    value.type_str()
                )),
            ));
        };
        let mut read = toml::Table::new();
        for (key, _, _) in self.entries(Some(name)) {
            let Some(v) = table.get(&key) else { continue };
            read.insert(key.clone(), v.clone());
            if let Err(e) = Self::read_alone(name, read.clone()) {
                return Err(self.key_error(name, &key, &read, e.message().trim()));
            }
        }
        Ok(())
    }

    /// The error of `table.key`, the key whose addition to `read` gave `message`.
    fn key_error(&self, table: &str, key: &str, read: &toml::Table, message: &str) -> ConfigError {
        let dotted = format!("{table}.{key}");
        let at_value = self.at(self.value_span(table, key), Some(dotted.clone()));
        let kind = if message.starts_with("unknown field") {
            return ConfigError::new(
                self.at(self.key_span(table, key), Some(dotted)),
                ConfigErrorKind::UnknownKey {
                    allowed: allowed(message, false),
                    hint: String::new(),
                },
            );
        } else if message.starts_with("unknown variant") {
            ConfigErrorKind::BadChoice(message.to_string())
        } else if ["invalid ", "missing ", "duplicate "]
            .iter()
            .any(|p| message.starts_with(p))
        {
            ConfigErrorKind::WrongType(message.to_string())
        } else if let Some(mixed) = (table == "pendulum")
            .then(|| RawPendulum::deserialize(toml::Value::Table(read.clone())).ok())
            .flatten()
            .and_then(|raw| raw.mixed())
        {
            let location = self.at(self.key_span(table, key), Some(table.to_string()));
            return ConfigError::new(location, mixed);
        } else {
            // A rule of the table's file form (tables.rs): an impossible value.
            let v = read.get(key);
            match v.and_then(|v| v.as_float().or(v.as_integer().map(|i| i as f64))) {
                Some(value) => ConfigErrorKind::Impossible {
                    value,
                    why: message.to_string(),
                },
                None => ConfigErrorKind::WrongType(message.to_string()),
            }
        };
        ConfigError::new(at_value, kind)
    }

    fn parse(self) -> Result<RigConfig, ConfigError> {
        for (name, name_span, value_span) in self.entries(None) {
            self.check_table(&name, name_span, value_span)?;
        }
        let mut cfg =
            RigConfig::deserialize(toml::Value::Table(self.values.clone())).map_err(|e| {
                ConfigError::new(
                    self.at(None, None),
                    ConfigErrorKind::WrongType(e.message().trim().to_string()),
                )
            })?;
        // Gains left out are the Eq (21) equivalent of this file's pendulum (tables::alg3).
        let eq21 = Alg3Gains::from_params(&cfg.params());
        let given = |key: &str| self.values.get("alg3").and_then(|t| t.get(key)).is_some();
        let g = &mut cfg.alg3.gains;
        for ((gain, key), value) in [&mut g.k, &mut g.l, &mut g.m, &mut g.n]
            .into_iter()
            .zip(tables::alg3::GAINS)
            .zip([eq21.k, eq21.l, eq21.m, eq21.n])
        {
            if !given(key) {
                *gain = value;
            }
        }
        if let Some((key, value, why)) = checks::issues(&cfg).into_iter().next() {
            let (table, k) = key.split_once('.').unwrap_or((key.as_str(), ""));
            let span = self.value_span(table, k);
            let why = if span.is_none() {
                format!("{why} (the value is the default: set it in [{table}])")
            } else {
                why
            };
            return Err(ConfigError::new(
                self.at(span, Some(key.clone())),
                ConfigErrorKind::Impossible { value, why },
            ));
        }
        Ok(cfg)
    }
}

/// The names serde's "unknown field `x`, expected one of `a`, `b`" allows, as `a, b`
/// (`[a], [b]` for the tables of the top level).
fn allowed(message: &str, tables: bool) -> String {
    let list = message
        .split_once("expected ")
        .map_or("", |(_, rest)| rest.trim_start_matches("one of "));
    let names = list
        .split(", ")
        .map(|n| n.trim().trim_matches('`'))
        .filter(|n| !n.is_empty());
    if tables {
        names
            .map(|n| format!("[{n}]"))
            .collect::<Vec<_>>()
            .join(", ")
    } else {
        names
            .map(|n| format!("`{n}`"))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_column_counts_characters() {
        let text = "ab\n\u{e9}x = 1\n";
        assert_eq!(line_column(text, 0), (1, 1));
        assert_eq!(line_column(text, 3), (2, 1));
        // 'x' is after a 2-byte character: byte 5, column 2.
        assert_eq!(line_column(text, 5), (2, 2));
    }

    #[test]
    fn every_written_key_has_a_comment() {
        let phys = RigConfig::default().to_toml_string();
        let norm = RigConfig::from_params(PendulumParams::default())
            .unwrap()
            .to_toml_string();
        for text in [phys, norm] {
            for line in text.lines() {
                if line.contains('=') {
                    assert!(line.contains('#'), "no comment on `{line}`");
                }
            }
        }
    }
}
