//! The 3-D rig file (MODEL.md 7.6) as `estimate` reads it: `[pendulum3d]` in the physical
//! form ([`Pendulum3d`], what `simulate` writes) or the normalised one
//! ([`CardanParams`]: `a_x, a_y, b_x, b_y, b_z, b_ring, c, gravity`, every key given),
//! never both; `[mounting]` optional; `[ekf3d]` optional ([`Ekf3dConfig`]: the spatial
//! filter's settings a rig may change); `[gyro]` optional, the planar rig's table (its
//! `full_scale` \[rad/s\]). Errors name the file, and the line and column when the TOML
//! parser gives a position.
use pendtilt_core::params::GyroSettings;
use pendtilt_core::spatial::cardan::CardanParams;

use crate::config::{doubt_length, doubt_length_beyond, plain, LengthDoubt, DOUBTFUL_SPEED_POINT};
use crate::sim::spatial::{Mounting, Pendulum3d};

pub use crate::config::TABLES_3D;

mod ekf3d;
mod read;
mod template;

pub use ekf3d::Ekf3dConfig;
pub use template::template;

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

#[cfg(test)]
mod tests {
    use super::*;
    use pendtilt_core::spatial::ekf;

    /// `[ekf3d]` sets the filter's fields of the same name and nothing else; a misspelt key
    /// or an impossible value is an error naming the file, the key and (for a key) the line.
    #[test]
    fn the_ekf3d_table_sets_the_filter_settings() {
        let rig = crate::sim::spatial::Rig3d::default()
            .to_toml_string()
            .unwrap();
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
        let phys = crate::sim::spatial::Rig3d {
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
