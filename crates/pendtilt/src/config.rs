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
//! p0_angle = 0.01       # initial angle variance [rad^2]
//! p0_bias = 0.01        # initial bias variance [(rad/s)^2]
//!
//! [differentiator]      # phi', phi'' for alg1, alg2, alg3 (filters::diff)
//! response = "butterworth"      # or "bessel", "critically_damped"
//! # cutoff_times_natural = 1.7  # cutoff / natural frequency (default 1.7) ...
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
//! ```
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

mod estimators;

pub use estimators::{
    Alg1Config, Alg2Config, Alg3Config, DifferentiatorConfig, ThetaDdChoice, DEFAULT_GD_WINDOW,
};

use pendtilt_core::estimators::accel::AccelSettings;
use pendtilt_core::estimators::alg1::Alg1Settings;
use pendtilt_core::estimators::alg2::Alg2Settings;
use pendtilt_core::estimators::alg3::Alg3Settings;
use pendtilt_core::estimators::equations::Alg3Gains;
use pendtilt_core::estimators::front_end::FrontEndSettings;
use pendtilt_core::estimators::theta_dd::ThetaDdSource;
use pendtilt_core::estimators::PhiSource;
use pendtilt_core::filters::diff::DiffSettings;
use pendtilt_core::kalman::KalmanSettings;
use pendtilt_core::params::GyroSettings;
use pendtilt_core::{PendulumParams, PhysicalParams};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use toml::de::{DeTable, DeValue};
use toml::Spanned;

use estimators::Issue;

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
    #[error("unknown key; allowed here: {allowed}")]
    UnknownKey {
        /// The keys allowed in this table, comma-separated.
        allowed: String,
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
    #[error("impossible value {value}: {why}")]
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
#[derive(Debug, Clone, Copy, PartialEq)]
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

/// A whole rig file: the pendulum and the estimator settings.
///
/// Build it with [`RigConfig::load`], [`RigConfig::from_toml_str`],
/// [`RigConfig::from_physical`] or [`RigConfig::from_params`]; write it with
/// [`RigConfig::to_toml_string`] or [`RigConfig::save`] (the text loads back to an equal
/// value). The public fields may be changed freely; [`RigConfig::validate`] checks them.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RigConfig {
    /// The `[pendulum]` table.
    pub pendulum: PendulumConfig,
    /// The `[kalman]` table: the core's [`KalmanSettings`], read and written by its serde
    /// derive (its `gyro` is not a key: [`RigConfig::kalman_settings`] takes `[gyro]`).
    pub kalman: KalmanSettings<f64>,
    /// The `[differentiator]` table (phi', phi'' for alg1, alg2, alg3).
    pub differentiator: DifferentiatorConfig,
    /// The `[accel]` table (Eq 1): the core's [`AccelSettings`].
    pub accel: AccelSettings<f64>,
    /// The `[gyro]` table (the rate gyro's full scale): the core's [`GyroSettings`].
    pub gyro: GyroSettings<f64>,
    /// The `[alg1]` table (Eq 20).
    pub alg1: Alg1Config,
    /// The `[alg2]` table (Eqs 21-22).
    pub alg2: Alg2Config,
    /// The `[alg3]` table (Eq 30: gains K, L, M, N).
    pub alg3: Alg3Config,
}

/// Name used in errors for configurations built in memory rather than read from a file.
pub const IN_MEMORY: &str = "<rig parameters>";

impl RigConfig {
    /// The bounds of plausible readings the log reader applies: the sensors' full scales
    /// (`[gyro]`, `[accel]`), or the default physical bounds where they are unset.
    pub fn limits(&self) -> crate::io::SensorLimits {
        crate::io::SensorLimits {
            gyro_full_scale: self.gyro.full_scale,
            accel_full_scale: self.accel.full_scale,
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

    /// A rig with these physical pendulum values and default estimator settings.
    /// Errors if a value is impossible (see [`RigConfig::validate`]).
    pub fn from_physical(p: PhysicalParams<f64>) -> Result<Self, ConfigError> {
        let cfg = Self {
            pendulum: PendulumConfig::Physical(p),
            ..Self::default()
        };
        cfg.validate()?;
        Ok(cfg)
    }

    /// A rig with these normalised a, b, c (a fit result) and default estimator settings.
    /// Errors if a value is impossible (a < 0, b <= 0, or not finite).
    pub fn from_params(p: PendulumParams<f64>) -> Result<Self, ConfigError> {
        let cfg = Self {
            pendulum: PendulumConfig::Normalised(p),
            ..Self::default()
        };
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

    /// Algorithm 3's gains: those of `[alg3]`, the ones left out K = a, L = b, M = -b, N = 0.
    pub fn alg3_gains(&self) -> Alg3Gains<f64> {
        self.alg3.gains(&self.params())
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
        self.differentiator.settings()
    }

    /// Settings of `accel`, from `[accel]`.
    pub fn accel_settings(&self) -> AccelSettings<f64> {
        self.accel
    }

    /// The front end of Algorithms 1-3 from `[pendulum]`, `[differentiator]` and `[gyro]`,
    /// with `phi` and `theta_dd` from an algorithm's table.
    fn front_end(&self, phi: PhiSource, theta_dd: ThetaDdSource<f64>) -> FrontEndSettings<f64> {
        FrontEndSettings {
            params: self.params(),
            differentiator: self.diff_settings(),
            phi,
            theta_dd,
            gyro: self.gyro_settings(),
        }
    }

    /// Settings of `alg1`, from `[pendulum]`, `[differentiator]` and `[alg1]`.
    pub fn alg1_settings(&self) -> Alg1Settings<f64> {
        Alg1Settings {
            // Algorithm 1 reads neither theta'' nor the gyro.
            front_end: self.front_end(self.alg1.phi, ThetaDdSource::default()),
        }
    }

    /// Settings of `alg2`, from `[pendulum]`, `[differentiator]`, `[gyro]` and `[alg2]`.
    pub fn alg2_settings(&self) -> Alg2Settings<f64> {
        let a = &self.alg2;
        Alg2Settings {
            front_end: self.front_end(a.phi, estimators::theta_dd(a.theta_dd, a.window)),
            pivot_offset: a.pivot_offset,
            delay_compensation: a.delay_compensation,
        }
    }

    /// Settings of `alg3`, from `[pendulum]`, `[differentiator]`, `[gyro]` and `[alg3]`
    /// (gains left out of `[alg3]` are K = a, L = b, M = -b, N = 0).
    pub fn alg3_settings(&self) -> Alg3Settings<f64> {
        let a = &self.alg3;
        Alg3Settings {
            front_end: self.front_end(a.phi, estimators::theta_dd(a.theta_dd, a.window)),
            gains: a.gains(&self.params()),
        }
    }

    /// Checks every value as [`RigConfig::load`] does; errors name [`IN_MEMORY`] as the file.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let mut issues = Vec::new();
        check_pendulum(&self.pendulum, &mut issues);
        check_kalman(&self.kalman, &mut issues);
        estimators::check_estimators(self, &mut issues);
        match issues.into_iter().next() {
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
        let file = RawFile {
            pendulum: RawPendulum::from(&self.pendulum),
            kalman: self.kalman,
            differentiator: self.differentiator,
            accel: self.accel,
            gyro: self.gyro,
            alg1: self.alg1,
            alg2: self.alg2,
            alg3: self.alg3,
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

/// The unit and meaning of each key, for the comments of [`RigConfig::to_toml_string`].
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
        ("kalman", "p0_angle") => "initial angle variance [rad^2]",
        ("kalman", "p0_bias") => "initial bias variance [(rad/s)^2]",
        _ => return estimators::key_comment(table, key),
    })
}

const TABLES: [&str; 8] = [
    "pendulum",
    "kalman",
    "differentiator",
    "accel",
    "gyro",
    "alg1",
    "alg2",
    "alg3",
];

/// The `[pendulum]` table as written: every key optional.
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

impl From<&PendulumConfig> for RawPendulum {
    fn from(p: &PendulumConfig) -> Self {
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

/// The whole file for writing.
#[derive(Serialize)]
struct RawFile {
    pendulum: RawPendulum,
    kalman: KalmanSettings<f64>,
    differentiator: DifferentiatorConfig,
    accel: AccelSettings<f64>,
    gyro: GyroSettings<f64>,
    alg1: Alg1Config,
    alg2: Alg2Config,
    alg3: Alg3Config,
}

fn require(issues: &mut Vec<Issue>, key: &str, value: f64, ok: bool, why: &str) {
    if !value.is_finite() {
        issues.push((
            key.to_string(),
            value,
            "must be a finite number".to_string(),
        ));
    } else if !ok {
        issues.push((key.to_string(), value, why.to_string()));
    }
}

fn check_pendulum(p: &PendulumConfig, issues: &mut Vec<Issue>) {
    match p {
        PendulumConfig::Physical(p) => {
            require(
                issues,
                "pendulum.mass",
                p.mass,
                p.mass > 0.0,
                "mass must be > 0 [kg]",
            );
            require(
                issues,
                "pendulum.length",
                p.length,
                p.length > 0.0,
                "length (pivot to centre of gravity) must be > 0 [m]",
            );
            require(
                issues,
                "pendulum.inertia",
                p.inertia,
                p.inertia > 0.0,
                "inertia about the pivot must be > 0 [kg m^2]",
            );
            require(
                issues,
                "pendulum.damping",
                p.damping,
                p.damping >= 0.0,
                "damping (viscous friction) must be >= 0 [N m s/rad]",
            );
            require(issues, "pendulum.pivot_offset", p.pivot_offset, true, "");
            require(
                issues,
                "pendulum.gravity",
                p.gravity,
                p.gravity > 0.0,
                "gravity must be > 0 [m/s^2]",
            );
            let point = p.mass * p.length * p.length;
            if issues.is_empty() && p.inertia < point * (1.0 - 1e-12) {
                // Six significant digits, written plainly (0.00015, not 0.00015000000000000001).
                let shown: f64 = format!("{point:.5e}").parse().unwrap_or(point);
                issues.push((
                    "pendulum.inertia".to_string(),
                    p.inertia,
                    format!(
                        "inertia about the pivot must be >= mass * length^2 = {shown} kg m^2 \
                         (a point mass at the centre of gravity)"
                    ),
                ));
            }
        }
        PendulumConfig::Normalised(p) => {
            require(
                issues,
                "pendulum.a",
                p.a,
                p.a >= 0.0,
                "a = C / (m_p g l_p) must be >= 0 [s]",
            );
            require(
                issues,
                "pendulum.b",
                p.b,
                p.b > 0.0,
                "b = I_p / (m_p g l_p) must be > 0 [s^2]",
            );
            require(issues, "pendulum.c", p.c, true, "");
        }
    }
}

fn check_kalman(k: &KalmanSettings<f64>, issues: &mut Vec<Issue>) {
    let nonneg = "a noise density must be >= 0";
    require(
        issues,
        "kalman.q_angle",
        k.q_angle,
        k.q_angle >= 0.0,
        nonneg,
    );
    require(issues, "kalman.q_bias", k.q_bias, k.q_bias >= 0.0, nonneg);
    let pos = "a measurement variance must be > 0";
    require(issues, "kalman.r_accel", k.r_accel, k.r_accel > 0.0, pos);
    require(
        issues,
        "kalman.r_pendulum",
        k.r_pendulum,
        k.r_pendulum > 0.0,
        pos,
    );
    let var = "an initial variance must be >= 0";
    require(
        issues,
        "kalman.p0_angle",
        k.p0_angle,
        k.p0_angle >= 0.0,
        var,
    );
    require(issues, "kalman.p0_bias", k.p0_bias, k.p0_bias >= 0.0, var);
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

    fn at(&self, span: Option<std::ops::Range<usize>>, key: Option<String>) -> Location {
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

    /// The key and value spans of `table.key` (or of the top-level `table` when `key` is
    /// `None`).
    fn spans_of(
        &self,
        table: &str,
        key: Option<&str>,
    ) -> Option<(std::ops::Range<usize>, std::ops::Range<usize>)> {
        let top = self.spans.get_ref();
        let (tk, tv) = top.iter().find(|(k, _)| k.get_ref().as_ref() == table)?;
        match key {
            None => Some((tk.span(), tv.span())),
            Some(key) => match tv.get_ref() {
                DeValue::Table(t) => t
                    .iter()
                    .find(|(k, _)| k.get_ref().as_ref() == key)
                    .map(|(k, v)| (k.span(), v.span())),
                _ => None,
            },
        }
    }

    fn key_span(&self, table: &str, key: &str) -> Option<std::ops::Range<usize>> {
        self.spans_of(table, Some(key)).map(|(k, _)| k)
    }

    fn value_span(&self, table: &str, key: &str) -> Option<std::ops::Range<usize>> {
        self.spans_of(table, Some(key)).map(|(_, v)| v)
    }

    /// Reads one table into its serde struct, checking each key on its own so that the
    /// error names the key and its position.
    fn section<T: DeserializeOwned + Default>(&self, name: &str) -> Result<T, ConfigError> {
        let Some(value) = self.values.get(name) else {
            return Ok(T::default());
        };
        let toml::Value::Table(table) = value else {
            return Err(ConfigError::new(
                self.at(
                    self.spans_of(name, None).map(|(_, v)| v),
                    Some(name.to_string()),
                ),
                ConfigErrorKind::WrongType(format!(
                    "`{name}` must be a table ([{name}]), found a {}",
                    value.type_str()
                )),
            ));
        };
        for (key, v) in table {
            let mut one = toml::Table::new();
            one.insert(key.clone(), v.clone());
            if let Err(e) = T::deserialize(toml::Value::Table(one)) {
                let message = e.message().trim().to_string();
                let dotted = format!("{name}.{key}");
                return Err(if message.starts_with("unknown field") {
                    let allowed = message
                        .split_once("expected ")
                        .map(|(_, rest)| rest.trim_start_matches("one of ").to_string())
                        .unwrap_or_default();
                    ConfigError::new(
                        self.at(self.key_span(name, key), Some(dotted)),
                        ConfigErrorKind::UnknownKey { allowed },
                    )
                } else if message.starts_with("unknown variant") {
                    ConfigError::new(
                        self.at(self.value_span(name, key), Some(dotted)),
                        ConfigErrorKind::BadChoice(message),
                    )
                } else {
                    ConfigError::new(
                        self.at(self.value_span(name, key), Some(dotted)),
                        ConfigErrorKind::WrongType(message),
                    )
                });
            }
        }
        T::deserialize(value.clone()).map_err(|e| {
            ConfigError::new(
                self.at(
                    self.spans_of(name, None).map(|(k, _)| k),
                    Some(name.to_string()),
                ),
                ConfigErrorKind::WrongType(e.message().trim().to_string()),
            )
        })
    }

    fn parse(self) -> Result<RigConfig, ConfigError> {
        for (key, _) in self.spans.get_ref().iter() {
            let key_name = key.get_ref().as_ref();
            if !TABLES.contains(&key_name) {
                return Err(ConfigError::new(
                    self.at(Some(key.span()), Some(key_name.to_string())),
                    ConfigErrorKind::UnknownKey {
                        allowed: TABLES
                            .iter()
                            .map(|t| format!("[{t}]"))
                            .collect::<Vec<_>>()
                            .join(", "),
                    },
                ));
            }
        }
        let raw: RawPendulum = self.section("pendulum")?;
        let physical_given = [
            ("mass", raw.mass),
            ("length", raw.length),
            ("inertia", raw.inertia),
            ("damping", raw.damping),
            ("pivot_offset", raw.pivot_offset),
            ("gravity", raw.gravity),
        ];
        let normalised_given = [("a", raw.a), ("b", raw.b), ("c", raw.c)];
        let present = |list: &[(&'static str, Option<f64>)]| -> Vec<&'static str> {
            list.iter()
                .filter(|(_, v)| v.is_some())
                .map(|(k, _)| *k)
                .collect()
        };
        let phys = present(&physical_given);
        let norm = present(&normalised_given);
        if !phys.is_empty() && !norm.is_empty() {
            return Err(ConfigError::new(
                self.at(self.key_span("pendulum", norm[0]), Some("pendulum".into())),
                ConfigErrorKind::MixedPendulumForms {
                    physical: phys.join(", "),
                    normalised: norm.join(", "),
                },
            ));
        }
        let pendulum = if norm.is_empty() {
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
        };
        let cfg = RigConfig {
            pendulum,
            kalman: self.section("kalman")?,
            differentiator: self.section("differentiator")?,
            accel: self.section("accel")?,
            gyro: self.section("gyro")?,
            alg1: self.section("alg1")?,
            alg2: self.section("alg2")?,
            alg3: self.section("alg3")?,
        };
        let mut issues = Vec::new();
        check_pendulum(&cfg.pendulum, &mut issues);
        check_kalman(&cfg.kalman, &mut issues);
        estimators::check_estimators(&cfg, &mut issues);
        if let Some((key, value, why)) = issues.into_iter().next() {
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
