//! Values that are possible but far more likely a unit mistake: lengths in millimetres
//! read as metres, full scales and gravity in other units; one check each, shared by the
//! planar and 3-D rig files, the scenario files and the command line.
use super::{PendulumConfig, RigConfig};

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
}
