//! The 3-D rig file (MODEL.md 7.6) as `estimate` reads it: `[pendulum3d]` in the physical
//! form ([`Pendulum3d`], what `simulate` writes) or the normalised one
//! ([`CardanParams`]: `a_x, a_y, b_x, b_y, b_z, b_ring, c, gravity`, every key given),
//! never both; `[mounting]` optional; `[ekf3d]` optional ([`Ekf3dConfig`]: the spatial
//! filter's settings a rig may change); `[gyro]` optional, the planar rig's table (its
//! `full_scale` \[rad/s\]). Errors name the file, and the line and column when the TOML
//! parser gives a position.
use std::path::Path;

use pendtilt_core::params::GyroSettings;
use pendtilt_core::spatial::cardan::CardanParams;
use pendtilt_core::spatial::ekf;
use serde::{Deserialize, Serialize};

use crate::config::{doubt_length, doubt_length_beyond, plain, LengthDoubt, DOUBTFUL_SPEED_POINT};
use crate::sim3d::scenario::check_mounting;
use crate::sim3d::{Mounting, Pendulum3d};

pub use crate::config::TABLES_3D;

/// The tables only a planar rig file has (MODEL.md 5).
const TABLES_PLANAR: [&str; 8] = [
    "pendulum",
    "kalman",
    "differentiator",
    "accel",
    "alg1",
    "alg2",
    "alg3",
    "ekf",
];

/// The keys of the normalised form.
const NORMALISED_KEYS: [&str; 8] = ["a_x", "a_y", "b_x", "b_y", "b_z", "b_ring", "c", "gravity"];

/// The units of [`NORMALISED_KEYS`], in their order.
const NORMALISED_UNITS: [&str; 8] = [
    "s",
    "s",
    "s^2",
    "s^2",
    "s^2",
    "s^2, 0 for a light ring",
    "s^2, an array [x, y, z]: the pivot P2 - P1 over g",
    "m/s^2",
];

/// A 3-D rig file with every key at its default and what it means: MODEL.md 7.6's rig,
/// the sensors at P1, the filters' defaults. It reads back as [`Rig3dConfig::default`]
/// with every `[ekf3d]` key given at its default.
pub fn template() -> String {
    let p = Pendulum3d::default();
    let e = ekf::Settings::<f64>::default();
    let m = Mounting::default();
    let v = |x: [f64; 3]| format!("[{:?}, {:?}, {:?}]", x[0], x[1], x[2]);
    let f = |x: f64| format!("{x:?}");
    // Per table: its name and its (key, value, comment) lines.
    type Keys<'a> = Vec<(&'a str, String, &'a str)>;
    let tables: [(&str, Keys); 3] = [
        (
            "pendulum3d",
            vec![
                ("mass", f(p.mass), "m [kg]"),
                (
                    "length",
                    f(p.length),
                    "l, pivot P2 to the centre of mass [m]",
                ),
                (
                    "inertia_xx",
                    f(p.inertia_xx),
                    "Ixx about P2, pendulum axes, with m l^2 [kg m^2]",
                ),
                ("inertia_yy", f(p.inertia_yy), "Iyy [kg m^2]"),
                ("inertia_zz", f(p.inertia_zz), "Izz, small and > 0 [kg m^2]"),
                (
                    "ring_inertia",
                    f(p.ring_inertia),
                    "the outer ring about body x [kg m^2]",
                ),
                (
                    "damping_x",
                    f(p.damping_x),
                    "C_x, outer joint viscous damping [N m s/rad]",
                ),
                ("damping_y", f(p.damping_y), "C_y, inner joint [N m s/rad]"),
                (
                    "pivot_offset",
                    v(p.pivot_offset),
                    "P2 - P1, body axes (x fwd, y left, z up) [m]",
                ),
                ("gravity", f(p.gravity), "g [m/s^2]"),
            ],
        ),
        (
            "mounting",
            vec![
                (
                    "accel_at",
                    v(m.accel_at),
                    "the accelerometer - P1, body axes [m]",
                ),
                (
                    "speed_at",
                    v(m.speed_at),
                    "O - P1: the point `speed` is of; else the pivot of turns [m]",
                ),
            ],
        ),
        (
            "ekf3d",
            vec![
                (
                    "vibration_density",
                    f(e.environment.vibration_density),
                    "vibration near the pendulum [m/s^2/sqrt(Hz)]",
                ),
                (
                    "adapt",
                    e.adaptation.enabled.to_string(),
                    "adapt the forcing to the log (docs/adaptation.md)",
                ),
                (
                    "adapt_min_factor",
                    f(e.adaptation.min_factor),
                    "the adaptation's floor, times vibration_density^2",
                ),
                (
                    "adapt_max_factor",
                    f(e.adaptation.max_factor),
                    "the adaptation's ceiling, times vibration_density^2",
                ),
                (
                    "encoder_jitter",
                    f(e.encoder_jitter),
                    "encoder jitter from vibration above the band [rad]",
                ),
                (
                    "angular_accel_hz",
                    f(e.angular_accel_hz),
                    "cutoff of the gyro's derivative [Hz]",
                ),
                (
                    "angular_accel_lead",
                    e.angular_accel_lead.to_string(),
                    "take that filter's delay out",
                ),
                (
                    "speed_noise",
                    f(e.speed.noise),
                    "the speed column's noise [m/s]",
                ),
                (
                    "jerk_density",
                    f(e.speed.jerk_density),
                    "the vehicle's jerk [m/s^3/sqrt(Hz)]",
                ),
                (
                    "path_turn_hz",
                    f(e.path.path_turn_hz),
                    "low-pass of the path's turn rate [Hz], inf: as read",
                ),
                (
                    "path_pitch_hz",
                    f(e.path.path_pitch_hz),
                    "low-pass of the path's pitch rate [Hz]",
                ),
                (
                    "use_accel",
                    e.use_accel.to_string(),
                    "the accelerometer as a further up measurement",
                ),
                (
                    "guard_angle",
                    f(e.guard_angle),
                    "reset to the gyro+accel reference beyond this [rad]",
                ),
                (
                    "pendulum_range",
                    f(e.pendulum_range),
                    "the pendulum unused beyond this swing [rad]",
                ),
                (
                    "encoder_bits",
                    e.sensors.encoder_bits.to_string(),
                    "encoder resolution, bits per turn (0: none)",
                ),
                (
                    "encoder_noise",
                    f(e.sensors.encoder_noise),
                    "encoder white noise [rad]",
                ),
                (
                    "gyro_density",
                    f(e.sensors.gyro_density),
                    "gyro noise density [rad/s/sqrt(Hz)]",
                ),
                (
                    "gyro_bias_walk",
                    f(e.sensors.gyro_bias_walk),
                    "gyro bias random walk [rad/s/sqrt(s)]",
                ),
                (
                    "gyro_bias",
                    f(e.sensors.gyro_bias),
                    "spread of the gyro's initial bias [rad/s]",
                ),
                (
                    "accel_density",
                    f(e.sensors.accel_density),
                    "accelerometer noise density [m/s^2/sqrt(Hz)]",
                ),
            ],
        ),
    ];
    let mut out = String::from(
        "# pendtilt 3-D rig file (MODEL.md 7.6). SI units, angles in rad.\n\
         # [pendulum3d] is required, in this physical form or the normalised one (a_x, a_y,\n\
         # b_x, b_y, b_z, b_ring, c, gravity: MODEL.md 7.3, every key); the other tables and\n\
         # every key in them are optional, each shown here at its default.\n",
    );
    for (name, keys) in tables {
        out.push_str(&format!("\n[{name}]\n"));
        for (k, value, what) in keys {
            out.push_str(&format!("{:<36} # {what}\n", format!("{k} = {value}")));
        }
    }
    out.push_str(&format!(
        "\n[gyro]\n{:<36} # the gyro's full scale [rad/s]; default: unknown\n",
        "# full_scale = 8.73"
    ));
    out
}

/// The pendulum of a 3-D rig file, in the form the file gave it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Pendulum3dConfig {
    /// Physical values.
    Physical(Pendulum3d),
    /// Normalised values (MODEL.md 7.3).
    Normalised(CardanParams<f64>),
}

impl Pendulum3dConfig {
    /// The normalised parameters the estimators use.
    pub fn params(&self) -> CardanParams<f64> {
        match self {
            Self::Physical(p) => p.normalised(),
            Self::Normalised(c) => *c,
        }
    }

    /// Its gravity \[m/s^2\].
    pub fn gravity(&self) -> f64 {
        match self {
            Self::Physical(p) => p.gravity,
            Self::Normalised(c) => c.gravity,
        }
    }

    /// Its lengths beyond [`crate::config::DOUBTFUL_LENGTH`] (the check every planar rig
    /// gets, [`crate::config::doubt_length`]): the length l and the pivot offset r12 (or
    /// c g), each named by `table`'s key (`pendulum3d`, a scenario's `rig.pendulum3d`).
    pub fn length_doubts(&self, table: &str) -> Vec<LengthDoubt> {
        let norm = |v: [f64; 3]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        let milli = |v: [f64; 3]| format!("{:?}", v.map(|x| plain(x / 1000.0)));
        match self {
            Self::Physical(p) => [
                doubt_length(
                    &format!("{table}.length"),
                    format!("a pendulum length l of {} m", p.length),
                    p.length,
                    plain(p.length / 1000.0),
                ),
                doubt_length(
                    &format!("{table}.pivot_offset"),
                    format!(
                        "a pivot offset r12 = {:?} m ({:.3} m long)",
                        p.pivot_offset,
                        norm(p.pivot_offset)
                    ),
                    norm(p.pivot_offset),
                    milli(p.pivot_offset),
                ),
            ]
            .into_iter()
            .flatten()
            .collect(),
            Self::Normalised(c) => {
                let r12 = c.c.map(|x| x * c.gravity);
                doubt_length(
                    &format!("{table}.c"),
                    format!(
                        "c = r12 / g = {:?} s^2, a pivot offset {:.3} m long,",
                        c.c,
                        norm(r12)
                    ),
                    norm(r12),
                    milli(c.c),
                )
                .into_iter()
                .collect()
            }
        }
    }
}

/// The accelerometer's position beyond [`crate::config::DOUBTFUL_LENGTH`] from P1 (the
/// rig's length check: `accel_at = [0, 0, 250]` meant 250 mm, silently), and the speed
/// point O's (whose speed the log gives) beyond [`DOUBTFUL_SPEED_POINT`] (a ship's may be
/// metres away, ship3d's 9.4 m;
/// `speed_at = [1200, 0, -300]` meant mm), named by `table`'s key (`mounting`, a
/// scenario's `rig.mounting`).
pub fn mounting_doubts(m: &Mounting, table: &str) -> Vec<LengthDoubt> {
    let len = |v: [f64; 3]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let mm = |v: [f64; 3]| format!("{:?}", v.map(|x| plain(x / 1000.0)));
    let (a, s) = (m.accel_at, m.speed_at);
    let accel = doubt_length(
        &format!("{table}.accel_at"),
        format!("the accelerometer at {a:?} m ({:.3} m from P1)", len(a)),
        len(a),
        mm(a),
    );
    let speed = doubt_length_beyond(
        &format!("{table}.speed_at"),
        format!(
            "the point O whose forward speed the log gives, at {s:?} m ({:.3} m from P1)",
            len(s)
        ),
        len(s),
        (
            DOUBTFUL_SPEED_POINT,
            "farther from the pendulum than O can be on any vehicle (half the largest ships' 400 m)",
        ),
        mm(s),
    );
    accel.into_iter().chain(speed).collect()
}

/// A 3-D rig file: the pendulum, where the sensors sit and the spatial filter's settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rig3dConfig {
    /// `[pendulum3d]`.
    pub pendulum3d: Pendulum3dConfig,
    /// `[mounting]` (default: every sensor at P1).
    pub mounting: Mounting,
    /// `[ekf3d]` (default: every key absent, the filter's defaults).
    pub ekf3d: Ekf3dConfig,
    /// `[gyro]`: its full scale (default unknown). A reading at it is clipped and flagged
    /// `saturated`; beyond it, impossible and read as missing.
    pub gyro: GyroSettings<f64>,
    /// Whether the file has a `[mounting]` table (without one, a log's `speed` is taken as
    /// P1's, which `estimate` says).
    pub mounting_given: bool,
}

/// `[ekf3d]`: the settings of `ekf3d` and `ukf3d` a rig may set, each optional and each
/// the field of [`ekf::Settings`] of the same name (documented there, with its default).
/// A travelling vehicle may want a larger `vibration_density` than the standing
/// scooter's default: see docs/spatial.md, "The 3-D estimators (library)".
#[derive(Debug, Clone, Copy, PartialEq, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Ekf3dConfig {
    /// [`pendtilt_core::ekf::Environment::vibration_density`] \[m/s^2/sqrt(Hz)\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub vibration_density: Option<f64>,
    /// [`ekf::Settings::angular_accel_hz`] \[Hz\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub angular_accel_hz: Option<f64>,
    /// [`ekf::Settings::angular_accel_lead`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub angular_accel_lead: Option<bool>,
    /// [`ekf::SpeedSettings::noise`] \[m/s\] of [`ekf::Settings::speed`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub speed_noise: Option<f64>,
    /// [`ekf::SpeedSettings::jerk_density`] \[m/s^3/sqrt(Hz)\] of [`ekf::Settings::speed`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jerk_density: Option<f64>,
    /// [`pendtilt_core::spatial::travel::PathSettings::path_turn_hz`] \[Hz\] (`inf`: the gyro as read).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub path_turn_hz: Option<f64>,
    /// [`pendtilt_core::spatial::travel::PathSettings::path_pitch_hz`] \[Hz\] (`inf`: the gyro as read).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub path_pitch_hz: Option<f64>,
    /// [`ekf::Settings::encoder_jitter`] \[rad\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub encoder_jitter: Option<f64>,
    /// [`ekf::Settings::use_accel`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub use_accel: Option<bool>,
    /// [`pendtilt_core::spatial::ekf::Adaptation::enabled`] of
    /// [`ekf::Settings::adaptation`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub adapt: Option<bool>,
    /// [`pendtilt_core::spatial::ekf::Adaptation::min_factor`]: the lowest factor on
    /// `vibration_density`'s variance the adaptation may reach.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub adapt_min_factor: Option<f64>,
    /// [`pendtilt_core::spatial::ekf::Adaptation::max_factor`]: the highest factor on
    /// `vibration_density`'s variance the adaptation may reach.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub adapt_max_factor: Option<f64>,
    /// [`ekf::Settings::guard_angle`] \[rad\] (`inf`: no guard).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub guard_angle: Option<f64>,
    /// [`ekf::Settings::pendulum_range`] \[rad\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pendulum_range: Option<f64>,
    /// [`pendtilt_core::ekf::SensorNoise::encoder_bits`] of [`ekf::Settings::sensors`]
    /// (0: not quantised).
    pub encoder_bits: Option<u32>,
    /// [`pendtilt_core::ekf::SensorNoise::encoder_noise`] \[rad\].
    pub encoder_noise: Option<f64>,
    /// [`pendtilt_core::ekf::SensorNoise::gyro_density`] \[rad/s/sqrt(Hz)\].
    pub gyro_density: Option<f64>,
    /// [`pendtilt_core::ekf::SensorNoise::gyro_bias_walk`] \[rad/s/sqrt(s)\].
    pub gyro_bias_walk: Option<f64>,
    /// [`pendtilt_core::ekf::SensorNoise::gyro_bias`] \[rad/s\]: the initial bias' spread.
    pub gyro_bias: Option<f64>,
    /// [`pendtilt_core::ekf::SensorNoise::accel_density`] \[m/s^2/sqrt(Hz)\].
    pub accel_density: Option<f64>,
}

impl Ekf3dConfig {
    /// `key: why` for a value no filter can use.
    fn check(&self) -> Result<(), String> {
        for (key, v) in [
            ("vibration_density", self.vibration_density),
            ("angular_accel_hz", self.angular_accel_hz),
            ("jerk_density", self.jerk_density),
            ("gyro_density", self.gyro_density),
            ("gyro_bias_walk", self.gyro_bias_walk),
            ("gyro_bias", self.gyro_bias),
            ("accel_density", self.accel_density),
            ("adapt_min_factor", self.adapt_min_factor),
            ("adapt_max_factor", self.adapt_max_factor),
        ] {
            if let Some(v) = v.filter(|v| !(v.is_finite() && *v > 0.0)) {
                return Err(format!("ekf3d.{key}: {v} must be finite and > 0"));
            }
        }
        if let (Some(lo), Some(hi)) = (self.adapt_min_factor, self.adapt_max_factor) {
            if lo > hi {
                return Err(format!(
                    "ekf3d.adapt_min_factor {lo} is above adapt_max_factor {hi}"
                ));
            }
        }
        for (key, v) in [
            ("path_turn_hz", self.path_turn_hz),
            ("path_pitch_hz", self.path_pitch_hz),
        ] {
            if let Some(v) = v.filter(|v| v.is_nan() || *v <= 0.0) {
                return Err(format!(
                    "ekf3d.{key}: {v} must be > 0 (inf takes the gyro as read)"
                ));
            }
        }
        if let Some(v) = self.guard_angle.filter(|v| v.is_nan() || *v <= 0.0) {
            return Err(format!(
                "ekf3d.guard_angle: {v} must be > 0 rad (inf: no guard)"
            ));
        }
        if let Some(v) = self
            .pendulum_range
            .filter(|v| !(v.is_finite() && *v > 0.0 && *v <= std::f64::consts::FRAC_PI_2))
        {
            return Err(format!(
                "ekf3d.pendulum_range: {v} must be between 0 and pi/2 rad (the Cardan joint locks at pi/2)"
            ));
        }
        // An exact sensor may say 0 (a speed from a simulation, a jitter-free encoder).
        for (key, v) in [
            ("encoder_jitter", self.encoder_jitter),
            ("speed_noise", self.speed_noise),
            ("encoder_noise", self.encoder_noise),
        ] {
            if let Some(v) = v.filter(|v| !(v.is_finite() && *v >= 0.0)) {
                return Err(format!("ekf3d.{key}: {v} must be finite and >= 0"));
            }
        }
        if let Some(b) = self.encoder_bits.filter(|b| *b > 52) {
            return Err(format!(
                "ekf3d.encoder_bits: {b} must be 0 (not quantised) to 52"
            ));
        }
        Ok(())
    }

    /// Writes the keys given into `s`.
    pub fn apply(&self, s: &mut ekf::Settings<f64>) {
        if let Some(v) = self.vibration_density {
            s.environment.vibration_density = v;
        }
        if let Some(v) = self.angular_accel_hz {
            s.angular_accel_hz = v;
        }
        if let Some(v) = self.angular_accel_lead {
            s.angular_accel_lead = v;
        }
        if let Some(v) = self.speed_noise {
            s.speed.noise = v;
        }
        if let Some(v) = self.jerk_density {
            s.speed.jerk_density = v;
        }
        if let Some(v) = self.path_turn_hz {
            s.path.path_turn_hz = v;
        }
        if let Some(v) = self.path_pitch_hz {
            s.path.path_pitch_hz = v;
        }
        if let Some(v) = self.encoder_jitter {
            s.encoder_jitter = v;
        }
        if let Some(v) = self.use_accel {
            s.use_accel = v;
        }
        if let Some(v) = self.adapt {
            s.adaptation.enabled = v;
        }
        if let Some(v) = self.adapt_min_factor {
            s.adaptation.min_factor = v;
        }
        if let Some(v) = self.adapt_max_factor {
            s.adaptation.max_factor = v;
        }
        if let Some(v) = self.guard_angle {
            s.guard_angle = v;
        }
        if let Some(v) = self.pendulum_range {
            s.pendulum_range = v;
        }
        let n = &mut s.sensors;
        if let Some(v) = self.encoder_bits {
            n.encoder_bits = v;
        }
        if let Some(v) = self.encoder_noise {
            n.encoder_noise = v;
        }
        if let Some(v) = self.gyro_density {
            n.gyro_density = v;
        }
        if let Some(v) = self.gyro_bias_walk {
            n.gyro_bias_walk = v;
        }
        if let Some(v) = self.gyro_bias {
            n.gyro_bias = v;
        }
        if let Some(v) = self.accel_density {
            n.accel_density = v;
        }
    }

    /// True when the table gives every sensor noise figure (then a log's filter needs no
    /// `--scenario` for them).
    pub fn gives_sensor_noise(&self) -> bool {
        self.encoder_bits.is_some()
            && self.encoder_noise.is_some()
            && self.gyro_density.is_some()
            && self.gyro_bias_walk.is_some()
            && self.accel_density.is_some()
    }
}

impl Default for Rig3dConfig {
    /// MODEL.md 7.6's rig.
    fn default() -> Self {
        Self {
            pendulum3d: Pendulum3dConfig::Physical(Pendulum3d::default()),
            mounting: Mounting::default(),
            ekf3d: Ekf3dConfig::default(),
            gyro: GyroSettings::default(),
            mounting_given: false,
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File<P> {
    pendulum3d: P,
    #[serde(default)]
    mounting: Mounting,
    #[serde(default)]
    ekf3d: Ekf3dConfig,
    #[serde(default)]
    gyro: GyroSettings<f64>,
}

/// `file:line:column: message` from a TOML error (the position when it has a span).
fn toml_error(origin: &str, text: &str, e: &toml::de::Error) -> String {
    let message = e.message().trim_end();
    match e.span() {
        Some(span) => {
            let before = &text[..span.start.min(text.len())];
            let line = before.matches('\n').count() + 1;
            let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
            format!("{origin}:{line}:{column}: {message}")
        }
        None => format!("{origin}: {message}"),
    }
}

impl Rig3dConfig {
    /// Reads a rig file.
    pub fn load(path: &Path) -> Result<Self, String> {
        let origin = path.display().to_string();
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("{origin}: cannot read the rig file: {e}"))?;
        Self::from_toml_str(&text, &origin)
    }

    /// Reads a rig from TOML text; `origin` names it in errors.
    pub fn from_toml_str(text: &str, origin: &str) -> Result<Self, String> {
        let table: toml::Table = toml::from_str(text).map_err(|e| toml_error(origin, text, &e))?;
        // A planar rig file given for a 3-D log: say so, not "unknown field `accel`".
        if !table.contains_key("pendulum3d") {
            if let Some(name) = TABLES_PLANAR.iter().find(|n| table.contains_key(**n)) {
                let line = text
                    .lines()
                    .position(|l| l.trim_start().starts_with(&format!("[{name}]")))
                    .map_or(String::new(), |i| format!("{}:1:", i + 1));
                return Err(format!(
                    "{origin}:{line} [{name}]: a planar rig file (MODEL.md 5), and this log is \
                     3-D: give a 3-D rig file ([pendulum3d], MODEL.md 7.6), as `pendtilt \
                     simulate --scenario scooter3d` writes beside its log"
                ));
            }
        }
        let keys: Vec<String> = match table.get("pendulum3d") {
            Some(toml::Value::Table(t)) => t.keys().cloned().collect(),
            _ => Vec::new(),
        };
        let normalised: Vec<&String> = keys
            .iter()
            .filter(|k| NORMALISED_KEYS.contains(&k.as_str()) && *k != "gravity")
            .collect();
        let physical: Vec<&String> = keys
            .iter()
            .filter(|k| !NORMALISED_KEYS.contains(&k.as_str()))
            .collect();
        if !normalised.is_empty() && !physical.is_empty() {
            return Err(format!(
                "{origin}: pendulum3d: mixes the physical form ({}) with the normalised form \
                 ({}); give one",
                physical
                    .iter()
                    .map(|s| s.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
                normalised
                    .iter()
                    .map(|s| s.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
        if normalised.is_empty() {
            let f: File<Pendulum3d> =
                toml::from_str(text).map_err(|e| toml_error(origin, text, &e))?;
            f.pendulum3d
                .validate()
                .map_err(|e| format!("{origin}: {e}"))?;
            check_mounting(&f.mounting, "mounting").map_err(|e| format!("{origin}: {e}"))?;
            f.ekf3d.check().map_err(|e| format!("{origin}: {e}"))?;
            check_gyro(&f.gyro).map_err(|e| format!("{origin}: {e}"))?;
            return Ok(Self {
                pendulum3d: Pendulum3dConfig::Physical(f.pendulum3d),
                mounting: f.mounting,
                ekf3d: f.ekf3d,
                gyro: f.gyro,
                mounting_given: table.contains_key("mounting"),
            });
        }
        // Every key of the normalised form is needed: all the missing ones in one message.
        let missing: Vec<String> = NORMALISED_KEYS
            .iter()
            .zip(NORMALISED_UNITS)
            .filter(|(k, _)| !keys.iter().any(|g| g == *k))
            .map(|(k, u)| format!("{k} [{u}]"))
            .collect();
        if !missing.is_empty() {
            return Err(format!(
                "{origin}: [pendulum3d] in the normalised form (MODEL.md 7.3) needs every key; \
                 missing: {}. Or give the physical form (mass, length, inertia_xx, ...); \
                 `pendtilt rig --template 3d` prints a rig file with every key",
                missing.join(", ")
            ));
        }
        let f: File<CardanParams<f64>> =
            toml::from_str(text).map_err(|e| toml_error(origin, text, &e))?;
        check_normalised(&f.pendulum3d).map_err(|e| format!("{origin}: pendulum3d.{e}"))?;
        check_mounting(&f.mounting, "mounting").map_err(|e| format!("{origin}: {e}"))?;
        f.ekf3d.check().map_err(|e| format!("{origin}: {e}"))?;
        check_gyro(&f.gyro).map_err(|e| format!("{origin}: {e}"))?;
        Ok(Self {
            pendulum3d: Pendulum3dConfig::Normalised(f.pendulum3d),
            mounting: f.mounting,
            ekf3d: f.ekf3d,
            gyro: f.gyro,
            mounting_given: table.contains_key("mounting"),
        })
    }
}

/// `key: why` for a gyro full scale no gyro has (the planar rig's rule).
fn check_gyro(g: &GyroSettings<f64>) -> Result<(), String> {
    match g.full_scale {
        Some(v) if !(v.is_finite() && v > 0.0) => Err(format!(
            "gyro.full_scale: the full scale must be > 0 [rad/s] (leave it out when unknown), \
             got {:?}",
            v
        )),
        _ => Ok(()),
    }
}

/// `key: why` for a normalised value no pendulum has.
fn check_normalised(c: &CardanParams<f64>) -> Result<(), String> {
    let positive = [
        ("b_x", c.b_x),
        ("b_y", c.b_y),
        ("b_z", c.b_z),
        ("gravity", c.gravity),
    ];
    for (k, v) in positive {
        if !(v.is_finite() && v > 0.0) {
            return Err(format!("{k}: must be finite and > 0, got {v:?}"));
        }
    }
    for (k, v) in [("a_x", c.a_x), ("a_y", c.a_y), ("b_ring", c.b_ring)] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(format!("{k}: must be finite and >= 0, got {v:?}"));
        }
    }
    if c.c.iter().any(|v| !v.is_finite()) {
        return Err(format!("c: must be finite, got {:?}", c.c));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `[ekf3d]` sets the filter's fields of the same name and nothing else; a misspelt key
    /// or an impossible value is an error naming the file, the key and (for a key) the line.
    #[test]
    fn the_ekf3d_table_sets_the_filter_settings() {
        let rig = crate::sim3d::Rig3d::default().to_toml_string().unwrap();
        let text = format!("{rig}\n[ekf3d]\nvibration_density = 0.15\njerk_density = 5.0\n");
        let c = Rig3dConfig::from_toml_str(&text, "r.toml").unwrap();
        let mut s = ekf::Settings::<f64>::default();
        let before = s;
        c.ekf3d.apply(&mut s);
        assert_eq!(s.environment.vibration_density, 0.15);
        assert_eq!(s.speed.jerk_density, 5.0);
        s.environment.vibration_density = before.environment.vibration_density;
        s.speed.jerk_density = before.speed.jerk_density;
        assert_eq!(s, before);
        let bad = text.replace("jerk_density", "jerk");
        let e = Rig3dConfig::from_toml_str(&bad, "r.toml").unwrap_err();
        let line = bad.lines().position(|l| l.starts_with("jerk")).unwrap() + 1;
        assert!(e.starts_with(&format!("r.toml:{line}:")), "{e}");
        assert!(e.contains("jerk"), "{e}");
        let bad = text.replace("= 0.15", "= -1.0");
        let e = Rig3dConfig::from_toml_str(&bad, "r.toml").unwrap_err();
        assert_eq!(
            e,
            "r.toml: ekf3d.vibration_density: -1 must be finite and > 0"
        );
        // A speed without noise is allowed, a negative one is not.
        let exact = format!("{text}speed_noise = 0.0\n");
        let c = Rig3dConfig::from_toml_str(&exact, "r.toml").unwrap();
        let mut z = ekf::Settings::<f64>::default();
        c.ekf3d.apply(&mut z);
        assert_eq!(z.speed.noise, 0.0);
        let e = Rig3dConfig::from_toml_str(
            &exact.replace("speed_noise = 0.0", "speed_noise = -0.1"),
            "r.toml",
        )
        .unwrap_err();
        assert_eq!(e, "r.toml: ekf3d.speed_noise: -0.1 must be finite and >= 0");
        // The path's rates may be taken as read (inf), not cut off entirely.
        let inf = format!("{text}path_pitch_hz = inf\npath_turn_hz = 3.0\n");
        let c = Rig3dConfig::from_toml_str(&inf, "r.toml").unwrap();
        c.ekf3d.apply(&mut s);
        assert_eq!(s.path.path_pitch_hz, f64::INFINITY);
        assert_eq!(s.path.path_turn_hz, 3.0);
        let zero = inf.replace("path_turn_hz = 3.0", "path_turn_hz = 0.0");
        let e = Rig3dConfig::from_toml_str(&zero, "r.toml").unwrap_err();
        assert!(
            e.contains("ekf3d.path_turn_hz: 0 must be > 0 (inf takes"),
            "{e}"
        );
    }

    /// The physical and the normalised form of one pendulum give the same parameters.
    #[test]
    fn both_forms_give_the_same_parameters() {
        let p = Pendulum3d {
            ring_inertia: 2e-5,
            pivot_offset: [0.01, 0.0, 0.1],
            ..Pendulum3d::default()
        };
        let phys = crate::sim3d::Rig3d {
            pendulum3d: p,
            mounting: Mounting::default(),
        }
        .to_toml_string()
        .unwrap();
        let a = Rig3dConfig::from_toml_str(&phys, "p.toml").unwrap();
        let n = p.normalised();
        let norm = format!(
            "[pendulum3d]\na_x = {}\na_y = {}\nb_x = {}\nb_y = {}\nb_z = {}\nb_ring = {}\n\
             c = [{}, {}, {}]\ngravity = {}\n",
            n.a_x, n.a_y, n.b_x, n.b_y, n.b_z, n.b_ring, n.c[0], n.c[1], n.c[2], n.gravity
        );
        let b = Rig3dConfig::from_toml_str(&norm, "n.toml").unwrap();
        assert!(matches!(b.pendulum3d, Pendulum3dConfig::Normalised(_)));
        assert_eq!(a.pendulum3d.params(), b.pendulum3d.params());
        // 1 / sqrt(b_x + b_ring) is the outer axis' natural frequency (MODEL.md 7.2).
        let w = p.natural_frequencies(0.0)[0];
        let c = b.pendulum3d.params();
        assert!((w - 1.0 / (c.b_x + c.b_ring).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn errors_name_file_line_and_column() {
        let e =
            Rig3dConfig::from_toml_str("[pendulum3d]\nmass = \"heavy\"\n", "r.toml").unwrap_err();
        assert!(e.starts_with("r.toml:2:8: "), "{e}");
        let e = Rig3dConfig::from_toml_str("[pendulum3d]\nmas = 0.05\n", "r.toml").unwrap_err();
        assert!(e.starts_with("r.toml:2:1: ") && e.contains("mass"), "{e}");
        let e = Rig3dConfig::from_toml_str("[pendulum3d]\nmass = 0.05\nb_x = 1\n", "r.toml")
            .unwrap_err();
        assert!(e.contains("mixes the physical form (mass)"), "{e}");
        let e = Rig3dConfig::from_toml_str("[pendulum3d]\nmass = -1\n", "r.toml").unwrap_err();
        assert!(e.contains("pendulum3d.mass"), "{e}");
    }

    /// `[gyro]` is the planar rig's table: its full scale is read, and one no gyro has is
    /// refused with the key.
    #[test]
    fn the_gyro_full_scale_is_read_and_checked() {
        let r = Rig3dConfig::from_toml_str("[pendulum3d]\n[gyro]\nfull_scale = 0.35\n", "r.toml")
            .unwrap();
        assert_eq!(r.gyro.full_scale, Some(0.35));
        assert_eq!(
            Rig3dConfig::from_toml_str("[pendulum3d]\n", "r.toml")
                .unwrap()
                .gyro
                .full_scale,
            None
        );
        let e = Rig3dConfig::from_toml_str("[pendulum3d]\n[gyro]\nfull_scale = -2\n", "r.toml")
            .unwrap_err();
        assert!(
            e.starts_with("r.toml: gyro.full_scale") && e.contains("-2"),
            "{e}"
        );
        let e =
            Rig3dConfig::from_toml_str("[pendulum3d]\n[gyro]\nrange = 2\n", "r.toml").unwrap_err();
        assert!(
            e.starts_with("r.toml:3:1: ") && e.contains("full_scale"),
            "{e}"
        );
    }

    /// The template reads back as the defaults: MODEL.md 7.6's rig, the sensors at P1,
    /// and every `[ekf3d]` key at the filter's default.
    #[test]
    fn the_template_reads_back_as_the_defaults() {
        let r = Rig3dConfig::from_toml_str(&template(), "t.toml").unwrap();
        assert_eq!(
            r.pendulum3d,
            Pendulum3dConfig::Physical(Pendulum3d::default())
        );
        assert_eq!(r.mounting, Mounting::default());
        assert_eq!(r.gyro.full_scale, None);
        let mut s = ekf::Settings::<f64>::default();
        r.ekf3d.apply(&mut s);
        assert_eq!(s, ekf::Settings::<f64>::default());
        // Every key of Ekf3dConfig is in it (a key added later must be added there too).
        let given = format!("{:?}", r.ekf3d);
        assert!(!given.contains("None"), "{given}");
    }

    /// A normalised [pendulum3d] short of keys names them all at once, with their units.
    #[test]
    fn every_missing_normalised_key_is_named_in_one_message() {
        let e = Rig3dConfig::from_toml_str("[pendulum3d]\na_x = 0.87\nb_x = 0.1\n", "r.toml")
            .unwrap_err();
        assert!(
            e.starts_with("r.toml: [pendulum3d] in the normalised form (MODEL.md 7.3) needs every key; missing: a_y [s], b_y [s^2], b_z [s^2], b_ring [s^2, 0 for a light ring], c [s^2, an array [x, y, z]"),
            "{e}"
        );
        assert!(
            e.contains("gravity [m/s^2]") && e.contains("rig --template 3d"),
            "{e}"
        );
    }
}
